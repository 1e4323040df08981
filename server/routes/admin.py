"""The admin's API under /api/v1/admin/…: learning platforms (LTI 1.3) registered by hand, dynamic registration
URLs, our tool keys. The same operations as `paltrainer admin lti-…` (server/lti/cli.py): both call
server/lti/registration.py and server/lti/keys.py. Users and API keys have their own routes (/api/v1/users,
/api/v1/api-keys); the browser's admin page (/admin, web/src/page-admin.js) uses all of them."""

from __future__ import annotations

from typing import Annotated, Literal

from fastapi import APIRouter, Depends, Request
from pydantic import BaseModel, ConfigDict, Field

from server.deps import AppSettings, DbSession, Principal, require_admin
from server.errors import ApiError, responses
from server.lti import keys, registration
from server.schemas import CLEAN, length

router = APIRouter(prefix="/api/v1/admin", tags=["admin"])
AdminPrincipal = Annotated[Principal, Depends(require_admin)]
_Kid = Annotated[str, length(64, min_length=1), CLEAN]
_Loose = Annotated[
    str, length(10_000), CLEAN
]  # bounded here; the limits that matter are registration.platform_problems's (German)


class PlatformIn(BaseModel):
    model_config = ConfigDict(extra="forbid")

    issuer: _Loose = Field(description="The platform's issuer (iss), e.g. Moodle's URL; https")
    client_id: _Loose = Field(description="The client id the platform gave the tool")
    auth_login_url: _Loose = Field(description="OIDC authorization endpoint of the platform; https")
    token_url: _Loose = Field(description="OAuth 2 access token URL of the platform; https")
    jwks_url: _Loose = Field(description="Public keyset URL of the platform; https")
    deployment_ids: list[_Loose] = Field(
        default=[], max_length=1000, description="At most 50, each 1–255 characters"
    )
    name: _Loose = Field(default="", description="Display name (default: the issuer)")


class PlatformOut(BaseModel):
    id: int
    name: str
    issuer: str
    client_id: str
    auth_login_url: str
    token_url: str
    jwks_url: str
    deployment_ids: list[str]
    created_at: str


class RegistrationUrl(BaseModel):
    url: str = Field(description='For the platform\'s dynamic registration (Moodle: "Tool-URL")')
    valid_days: int = Field(description="The URL is good for one registration within this many days")


class ToolKey(BaseModel):
    kid: str
    created_at: str
    retired_at: str | None
    current: bool
    state: Literal["current", "published", "retired"] = Field(
        description="current: signs; published: in /lti/jwks, no longer signs; retired: neither"
    )


class KeyId(BaseModel):
    kid: str


def _base(request: Request) -> str:
    return str(request.base_url).rstrip("/")


@router.post(
    "/lti/platforms", status_code=201, response_model=PlatformOut, responses=responses(401, 403, 422)
)
def add_platform(body: PlatformIn, db: DbSession, _: AdminPrincipal) -> PlatformOut:
    """Register a platform (or update the one with this issuer and client id; deployment ids are added). Every
    field is checked at once; what is wrong comes back per field, in German."""
    fields = body.model_dump()
    problems = registration.platform_problems(**fields)
    if problems:
        raise ApiError(
            "VALIDATION",
            detail="; ".join(f"{field}: {de}" for field, (de, _en) in problems.items()),
            errors=[
                {"field": field, "type": "value_error", "message": de, "message_en": en}
                for field, (de, en) in problems.items()
            ],
        )
    return PlatformOut(**registration.platform_out(db, registration.register(db, **fields)))


@router.get("/lti/platforms", response_model=list[PlatformOut], responses=responses(401, 403))
def list_platforms(db: DbSession, _: AdminPrincipal) -> list[PlatformOut]:
    """The registered platforms, oldest first (by hand and by dynamic registration)."""
    return [PlatformOut(**registration.platform_out(db, p)) for p in registration.platforms(db)]


@router.post("/lti/registration-url", response_model=RegistrationUrl, responses=responses(401, 403))
def new_registration_url(request: Request, settings: AppSettings, _: AdminPrincipal) -> RegistrationUrl:
    """A dynamic registration URL (valid 7 days, for one registration) for a platform's admin (Moodle: "Tool
    URL")."""
    return RegistrationUrl(
        url=registration.registration_url(_base(request), settings), valid_days=registration.REGISTRATION_DAYS
    )


@router.get("/lti/keys", response_model=list[ToolKey], responses=responses(401, 403))
def list_keys(db: DbSession, _: AdminPrincipal) -> list[ToolKey]:
    """Our signing keys, oldest first (one is made if there is none, as /lti/jwks does)."""
    keys.jwks(db)
    db.commit()
    return [ToolKey(**k) for k in keys.listing(db)]


@router.post("/lti/keys/rotate", status_code=201, response_model=KeyId, responses=responses(401, 403))
def rotate_key(db: DbSession, _: AdminPrincipal) -> KeyId:
    """A new signing key; the old ones stay published until retired."""
    row = keys.rotate(db)
    db.commit()
    return KeyId(kid=row.kid)


@router.post("/lti/keys/{kid}/retire", response_model=KeyId, responses=responses(401, 403, 404))
def retire_key(kid: _Kid, db: DbSession, _: AdminPrincipal) -> KeyId:
    """Take a key out of /lti/jwks (after platforms have fetched the newer one)."""
    if not keys.retire(db, kid):
        raise ApiError("NOT_FOUND")
    db.commit()
    return KeyId(kid=kid)
