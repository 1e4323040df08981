"""Passwords (argon2), bearer tokens (JWT, also carried in the browser's session cookie) and API keys."""

from __future__ import annotations

import hashlib
import hmac
import secrets
from datetime import UTC, datetime, timedelta
from typing import Any

import jwt
from pwdlib import PasswordHash
from pwdlib.exceptions import UnknownHashError
from pwdlib.hashers.argon2 import Argon2Hasher

_passwords = PasswordHash((Argon2Hasher(),))
_DUMMY_HASH = _passwords.hash("not a password")
API_KEY_PREFIX = "pal_"


def hash_password(password: str) -> str:
    return _passwords.hash(password)


def verify_password(password: str, hashed: str | None) -> bool:
    """True if `password` matches; with no hash it still spends the time of one check."""
    if hashed is None:
        _passwords.verify(password, _DUMMY_HASH)
        return False
    try:
        return _passwords.verify(password, hashed)
    except (UnknownHashError, ValueError):
        return False


def make_token(secret: str, user_id: int, role: str, minutes: int) -> str:
    now = datetime.now(UTC)
    claims = {"sub": str(user_id), "role": role, "iat": now, "exp": now + timedelta(minutes=minutes)}
    return jwt.encode(claims, secret, algorithm="HS256")


def read_token(secret: str, token: str) -> dict[str, Any] | None:
    try:
        claims: dict[str, Any] = jwt.decode(token, secret, algorithms=["HS256"], options={"require": ["exp", "sub"]})
    except jwt.PyJWTError:
        return None
    return claims


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
    parts = key[len(API_KEY_PREFIX):].split("_", 1)
    return parts[0] if len(parts) == 2 and parts[0] else None


def same_hash(a: str, b: str) -> bool:
    return hmac.compare_digest(a, b)
