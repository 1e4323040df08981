"""Accounts: token (OAuth2 password flow), browser session login/logout, who am I, users and API keys."""

from __future__ import annotations

from typing import Annotated, Any

from fastapi import APIRouter, Depends, Response
from fastapi.security import OAuth2PasswordRequestForm

from server import repository as repo
from server import services
from server.deps import (
    SESSION_COOKIE,
    AppSettings,
    CurrentPrincipal,
    DbSession,
    Principal,
    rate_limit,
    require_admin,
)
from server.errors import ApiError, responses
from server.schemas import (
    ApiKeyCreate,
    ApiKeyCreated,
    ApiKeyOut,
    LoginRequest,
    Me,
    Token,
    UserCreate,
    UserOut,
)
from server.security import make_token

router = APIRouter(tags=["accounts"])
LOGIN_LIMIT = [Depends(rate_limit("login", "rate_login_per_minute"))]


@router.post("/auth/token", response_model=Token, responses=responses(401, 422, 429), dependencies=LOGIN_LIMIT)
def token(form: Annotated[OAuth2PasswordRequestForm, Depends()], db: DbSession, settings: AppSettings) -> Token:
    """OAuth2 password flow (form fields username, password): a bearer token for scripts."""
    user = services.login(db, form.username, form.password)
    return Token(access_token=make_token(settings.jwt_secret(), user.id, user.role, settings.token_minutes))


@router.post("/auth/login", response_model=UserOut, responses=responses(401, 422, 429), dependencies=LOGIN_LIMIT)
def login(body: LoginRequest, response: Response, db: DbSession, settings: AppSettings) -> UserOut:
    """Browser login: sets the session cookie (HttpOnly, SameSite=Lax)."""
    user = services.login(db, body.username, body.password)
    response.set_cookie(SESSION_COOKIE, make_token(settings.jwt_secret(), user.id, user.role, settings.token_minutes),
                        max_age=settings.token_minutes * 60, httponly=True, samesite="lax",
                        secure=settings.cookie_secure, path="/")
    return services.user_out(user)


@router.post("/auth/logout", status_code=204)
def logout(response: Response) -> Response:
    response.delete_cookie(SESSION_COOKIE, path="/", httponly=True, samesite="lax")
    response.status_code = 204
    return response


@router.get("/me", response_model=Me, responses=responses(401))
def me(principal: CurrentPrincipal) -> Me:
    if principal.api_key is not None:
        return Me(kind="api_key", username=principal.user.username if principal.user else None, role=None,
                  scopes=principal.api_key.scopes)  # type: ignore[arg-type]
    assert principal.user is not None
    return Me(kind="user", username=principal.user.username, role=principal.user.role,  # type: ignore[arg-type]
              scopes=None)


@router.get("/users", response_model=list[UserOut], responses=responses(401, 403))
def list_users(db: DbSession, _: Annotated[Principal, Depends(require_admin)]) -> list[UserOut]:
    return [services.user_out(u) for u in repo.list_users(db)]


@router.post("/users", response_model=UserOut, status_code=201, responses=responses(401, 403, 409, 422))
def create_user(body: UserCreate, db: DbSession, _: Annotated[Principal, Depends(require_admin)]) -> UserOut:
    return services.user_out(services.create_user(db, body.username, body.password, body.role))


@router.get("/api-keys", response_model=list[ApiKeyOut], responses=responses(401, 403))
def list_api_keys(db: DbSession, principal: CurrentPrincipal) -> list[ApiKeyOut]:
    """Admins see every key, instructors their own."""
    if principal.api_key is not None or not principal.is_instructor():
        raise ApiError("FORBIDDEN")
    return services.visible_api_keys(db, principal)


@router.post("/api-keys", response_model=ApiKeyCreated, status_code=201, responses=responses(401, 403, 422))
def create_api_key(body: ApiKeyCreate, db: DbSession, principal: CurrentPrincipal) -> Any:
    """A new key acting for the calling instructor or admin, within `scopes`; the key is shown only here."""
    if principal.api_key is not None or not principal.is_instructor():
        raise ApiError("FORBIDDEN")
    record, secret = services.create_api_key(db, body.name, list(body.scopes), principal.user)
    return services.api_key_created(db, record, secret)


@router.delete("/api-keys/{key_id}", response_model=ApiKeyOut, responses=responses(401, 403, 404))
def revoke_api_key(key_id: int, db: DbSession, principal: CurrentPrincipal) -> ApiKeyOut:
    if principal.api_key is not None or not principal.is_instructor():
        raise ApiError("FORBIDDEN")
    return services.revoke_api_key(db, principal, key_id)
