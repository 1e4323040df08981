"""Accounts: token (OAuth2 password flow), browser session login/logout, who am I, API keys (users: users.py)."""

from __future__ import annotations

from typing import Annotated, Any

from fastapi import APIRouter, Depends, Request, Response
from fastapi.security import OAuth2PasswordRequestForm
from sqlalchemy import update
from sqlalchemy.orm import Session

from server import services
from server.config import Settings
from server.deps import (
    SESSION_COOKIE,
    AppSettings,
    CurrentPrincipal,
    DbSession,
    client_address,
    token_user,
)
from server.errors import ApiError, responses
from server.models import User
from server.ratelimit import RateLimiter, login_name
from server.schemas import (
    ApiKeyCreate,
    ApiKeyCreated,
    ApiKeyOut,
    LoginRequest,
    Me,
    Token,
    UserOut,
)
from server.security import make_token

router = APIRouter(tags=["accounts"])
LOGIN_FAILURES = "login-failures"


def checked_login(request: Request, db: Session, settings: Settings, username: str, password: str) -> User:
    """The user, if the password is right and neither the user name nor the address has used up its budget
    of failed logins (one budget for /auth/token and /auth/login); a wrong password uses up one of each."""
    limiter: RateLimiter = request.app.state.limiter
    budgets = (
        (login_name(username), settings.rate_login_per_minute),
        (f"ip:{client_address(request)}", settings.rate_login_address_per_minute),
    )
    wait = max(limiter.wait(LOGIN_FAILURES, who, limit) for who, limit in budgets)
    if wait:
        raise ApiError("RATE_LIMITED", headers={"Retry-After": str(wait)}, retry_after=wait)
    try:
        user = services.login(db, username, password)
    except ApiError:
        for who, limit in budgets:
            limiter.record(LOGIN_FAILURES, who, limit)
        raise
    if user.deactivated_at is not None:  # told only to whom knows the password
        raise ApiError("ACCOUNT_DEACTIVATED")
    return user


def _new_token(settings: Settings, user: User) -> str:
    return make_token(settings.jwt_secret(), user.id, user.role, settings.token_minutes, user.token_version)


@router.post("/auth/token", response_model=Token, responses=responses(401, 403, 422, 429))
def token(
    form: Annotated[OAuth2PasswordRequestForm, Depends()],
    request: Request,
    db: DbSession,
    settings: AppSettings,
) -> Token:
    """OAuth2 password flow (form fields username, password): a bearer token for scripts."""
    user = checked_login(request, db, settings, form.username, form.password)
    return Token(access_token=_new_token(settings, user))


@router.post("/auth/login", response_model=UserOut, responses=responses(401, 403, 422, 429))
def login(
    body: LoginRequest, request: Request, response: Response, db: DbSession, settings: AppSettings
) -> UserOut:
    """Browser login: sets the session cookie (HttpOnly, SameSite=Lax)."""
    user = checked_login(request, db, settings, body.username, body.password)
    set_session(response, settings, user)
    return services.user_out(user)


def set_session(response: Response, settings: Settings, user: User) -> None:
    """The browser's session cookie for `user` (login, sign-up, after changing the password)."""
    response.set_cookie(
        SESSION_COOKIE,
        _new_token(settings, user),
        max_age=settings.token_minutes * 60,
        httponly=True,
        samesite="lax",
        secure=settings.cookie_secure,
        path="/",
    )


@router.post("/auth/logout", status_code=204)
def logout(request: Request, response: Response, db: DbSession, settings: AppSettings) -> Response:
    """Ends the session: the token of the request (cookie or bearer) and every other token of the same user
    stop working (the user's token version goes up); the cookie is deleted. Without a valid token: only that."""
    header = request.headers.get("authorization", "")
    bearer = header[7:].strip() if header[:7].lower() == "bearer " else None
    for text in (bearer, request.cookies.get(SESSION_COOKIE)):
        user = token_user(db, settings, text) if text else None
        if user is not None:
            db.execute(update(User).where(User.id == user.id).values(token_version=User.token_version + 1))
            db.commit()
            break
    response.delete_cookie(
        SESSION_COOKIE, path="/", httponly=True, samesite="lax", secure=settings.cookie_secure
    )
    response.status_code = 204
    return response


@router.get("/me", response_model=Me, responses=responses(401))
def me(principal: CurrentPrincipal) -> Me:
    if principal.api_key is not None:
        return Me(
            kind="api_key",
            username=principal.user.username if principal.user else None,
            role=None,
            scopes=principal.api_key.scopes,  # type: ignore[arg-type]
        )
    assert principal.user is not None
    return Me(
        kind="user",
        username=principal.user.username,
        role=principal.user.role,  # type: ignore[arg-type]
        scopes=None,
    )


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
