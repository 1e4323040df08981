"""Our RSA keys for LTI: generated here, published at /lti/jwks, rotated, private keys encrypted at rest.

The encryption key is derived from the server's secret key with HKDF-SHA256 and used as a Fernet key
(AES-128-CBC + HMAC-SHA256, from `cryptography`): a database dump alone does not reveal our signing keys.
Rotation: `rotate()` makes a new key the current one (the newest unretired key signs); the older keys stay in
the JWKS so that tokens already signed with them still verify, until `retire()` takes them out.
"""

from __future__ import annotations

import base64
import json
import secrets
from datetime import UTC, datetime
from typing import Any

from cryptography.fernet import Fernet, InvalidToken
from cryptography.hazmat.primitives import hashes, serialization
from cryptography.hazmat.primitives.asymmetric import rsa
from cryptography.hazmat.primitives.kdf.hkdf import HKDF
from jwt.algorithms import RSAAlgorithm
from sqlalchemy import select
from sqlalchemy.orm import Session

from server.config import Settings
from server.models import LtiToolKey

_HKDF_INFO = b"paltrainer lti tool key encryption v1"
# the server's secret per database URL (several apps in one process, as in tests, each keep their own), and
# the last one configured for a session whose URL was not configured
_secrets: dict[str, str] = {}
_last: list[str] = []


def configure(settings: Settings) -> None:
    """Remember the server's secret key for its database (the app calls this on start, the CLI before it
    touches keys)."""
    secret = settings.jwt_secret()
    _secrets[settings.url] = secret
    _last[:] = [secret]


def _fernet(db: Session) -> Fernet:
    url = db.get_bind().engine.url.render_as_string(hide_password=False)
    secret = _secrets.get(url) or (_last[0] if _last else None)
    if secret is None:
        configure(Settings())
        secret = _last[0]
    derived = HKDF(algorithm=hashes.SHA256(), length=32, salt=None, info=_HKDF_INFO).derive(
        secret.encode("utf-8")
    )
    return Fernet(base64.urlsafe_b64encode(derived))


def new_key(db: Session) -> LtiToolKey:
    """A new RSA-2048 key; it becomes the current signing key."""
    private = rsa.generate_private_key(public_exponent=65537, key_size=2048)
    pem = private.private_bytes(
        serialization.Encoding.PEM, serialization.PrivateFormat.PKCS8, serialization.NoEncryption()
    )
    kid = secrets.token_urlsafe(12)
    jwk: dict[str, Any] = json.loads(RSAAlgorithm.to_jwk(private.public_key()))
    jwk.pop("key_ops", None)  # "use" says it; some platforms refuse keys with both
    jwk.update({"kid": kid, "alg": "RS256", "use": "sig"})
    row = LtiToolKey(
        kid=kid,
        private_pem_encrypted=_fernet(db).encrypt(pem).decode("ascii"),
        public_jwk=jwk,
        created_at=datetime.now(UTC),
    )
    db.add(row)
    db.flush()
    return row


def _current(db: Session) -> LtiToolKey | None:
    return db.scalars(
        select(LtiToolKey)
        .where(LtiToolKey.retired_at.is_(None))
        .order_by(LtiToolKey.created_at.desc(), LtiToolKey.id.desc())
        .limit(1)
    ).first()


def signing_key(db: Session) -> tuple[str, rsa.RSAPrivateKey]:
    """(kid, private key) of the current key; the first call makes one."""
    row = _current(db) or new_key(db)
    try:
        pem = _fernet(db).decrypt(row.private_pem_encrypted.encode("ascii"))
    except InvalidToken as exc:  # the secret key changed since the key was stored: rotate (see docs/lti.md)
        raise RuntimeError(
            "LTI tool key cannot be decrypted with this secret key; run `paltrainer admin lti-keys --rotate`"
        ) from exc
    private = serialization.load_pem_private_key(pem, password=None)
    assert isinstance(private, rsa.RSAPrivateKey)
    return row.kid, private


def jwks(db: Session) -> dict[str, Any]:
    """The public keys platforms verify our messages with (every key not retired; one is made if none)."""
    rows = list(db.scalars(select(LtiToolKey).where(LtiToolKey.retired_at.is_(None)).order_by(LtiToolKey.id)))
    if not rows:
        rows = [new_key(db)]
    return {"keys": [dict(r.public_jwk) for r in rows]}


def rotate(db: Session) -> LtiToolKey:
    """A new current key; the older ones stay published until retired."""
    return new_key(db)


def retire(db: Session, kid: str) -> bool:
    """Take a key out of the JWKS (and out of signing); False if there is no such unretired key."""
    row = db.scalars(select(LtiToolKey).where(LtiToolKey.kid == kid, LtiToolKey.retired_at.is_(None))).first()
    if row is None:
        return False
    row.retired_at = datetime.now(UTC)
    db.flush()
    return True


def _state(row: LtiToolKey, current: LtiToolKey | None) -> str:
    if row.retired_at is not None:
        return "retired"
    return "current" if current is not None and row.id == current.id else "published"


def listing(db: Session) -> list[dict[str, Any]]:
    """Every key, oldest first, with its state: "current" (signs), "published" (in /lti/jwks, no longer signs),
    "retired" (neither)."""
    current = _current(db)
    return [
        {
            "kid": r.kid,
            "created_at": r.created_at.isoformat(),
            "retired_at": r.retired_at.isoformat() if r.retired_at else None,
            "current": current is not None and r.id == current.id,
            "state": _state(r, current),
        }
        for r in db.scalars(select(LtiToolKey).order_by(LtiToolKey.id))
    ]
