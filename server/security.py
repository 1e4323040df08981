"""Passwords (argon2), bearer tokens (JWT, also carried in the browser's session cookie), API keys, and the
one rule for where the browser may be sent after logging in."""

from __future__ import annotations

import functools
import hashlib
import hmac
import re
import secrets
from datetime import UTC, datetime, timedelta
from typing import Any

import jwt
from pwdlib import PasswordHash
from pwdlib.exceptions import UnknownHashError
from pwdlib.hashers.argon2 import Argon2Hasher

_passwords = PasswordHash((Argon2Hasher(),))
API_KEY_PREFIX = "pal_"


def hash_password(password: str) -> str:
    return _passwords.hash(password)


@functools.cache
def _dummy_hash() -> str:
    """A hash to check a password against when there is no user: made at the first such login, not at import
    (an argon2 hash costs a tenth of a second in every process that imports this module: the server, each
    command, each worker)."""
    return _passwords.hash("not a password")


PASSWORD_MIN, PASSWORD_MAX = 8, 1000


def password_problem(password: str) -> tuple[str, str] | None:
    """The one rule for a new password (class lists, new users, changes, resets, sign-up): 8 to 1000 characters,
    no NUL; None if it holds, else what is wrong (German, English)."""
    if len(password) < PASSWORD_MIN:
        return (
            f"das Passwort braucht mindestens {PASSWORD_MIN} Zeichen",
            f"the password needs at least {PASSWORD_MIN} characters",
        )
    if len(password) > PASSWORD_MAX:
        return (
            f"das Passwort darf höchstens {PASSWORD_MAX} Zeichen lang sein",
            f"the password may be at most {PASSWORD_MAX} characters long",
        )
    if "\x00" in password:
        return "das Passwort enthält das Zeichen NUL", "the password contains the NUL character"
    return None


def verify_password(password: str, hashed: str | None) -> bool:
    """True if `password` matches; with no hash it still spends the time of one check."""
    if hashed is None:
        _passwords.verify(password, _dummy_hash())
        return False
    try:
        return _passwords.verify(password, hashed)
    except (UnknownHashError, ValueError):
        return False


def make_token(secret: str, user_id: int, role: str, minutes: int, version: int = 0) -> str:
    """A signed token for the user; `ver` is the user's token version then (logging out raises it)."""
    now = datetime.now(UTC)
    claims = {
        "sub": str(user_id),
        "role": role,
        "ver": version,
        "iat": now,
        "exp": now + timedelta(minutes=minutes),
    }
    return jwt.encode(claims, secret, algorithm="HS256")


def read_token(secret: str, token: str) -> dict[str, Any] | None:
    try:
        claims: dict[str, Any] = jwt.decode(
            token, secret, algorithms=["HS256"], options={"require": ["exp", "sub"]}
        )
    except jwt.PyJWTError:
        return None
    return claims


_USER_ID = re.compile(r"[1-9][0-9]{0,9}")  # ASCII digits only ("²".isdigit() is True, int("²") fails)
_MAX_ID = 2**31 - 1  # users.id is a 32-bit INTEGER on PostgreSQL; a larger number would be a database error


def token_user_id(claims: dict[str, Any]) -> int | None:
    """The user id a token names, or None when `sub` is anything but a plain positive number in range."""
    sub = claims.get("sub")
    if not isinstance(sub, str) or not _USER_ID.fullmatch(sub):
        return None
    return int(sub) if int(sub) <= _MAX_ID else None


def token_version(claims: dict[str, Any]) -> int | None:
    """The token version a token carries (tokens from before versions: 0), None if it is malformed."""
    ver = claims.get("ver", 0)
    return ver if isinstance(ver, int) and not isinstance(ver, bool) else None


# Where the browser may go after logging in: a path on this site, nothing else. A scheme (javascript:,
# https:), a second slash or a backslash at the start (//host, /\host: another host to the browser),
# control characters (browsers drop tab and newline inside URLs: "/\t/host" is "//host") and very long
# values all mean the start page. web/src/redirect.js is the same rule for the page; tests hold them equal.
_SAFE_PATH = re.compile(r"/(?![/\\])[^\\\x00-\x1f\x7f]{0,2047}")


def safe_redirect(target: str | None) -> str:
    """`target` if it is a same-site path (`/…`, not `//…`, not `/\\…`), else `/`."""
    return target if target is not None and _SAFE_PATH.fullmatch(target) else "/"


def new_api_key() -> tuple[str, str, str]:
    """A fresh key: (the full key shown once, its public prefix, the stored hash)."""
    prefix = secrets.token_hex(4)
    key = f"{API_KEY_PREFIX}{prefix}_{secrets.token_urlsafe(32)}"
    return key, prefix, hash_api_key(key)


def hash_api_key(key: str) -> str:
    """SHA-256 is enough here: the key is 256 random bits, not a password a person chose."""
    return hashlib.sha256(key.encode("utf-8")).hexdigest()


def split_api_key(key: str) -> str | None:
    """The prefix of a well-formed key, else None."""
    if not key.startswith(API_KEY_PREFIX):
        return None
    parts = key[len(API_KEY_PREFIX) :].split("_", 1)
    return parts[0] if len(parts) == 2 and parts[0] else None


def same_hash(a: str, b: str) -> bool:
    return hmac.compare_digest(a, b)
