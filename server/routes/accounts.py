"""Accounts without the command line (issue 31): change one's password, one-time passwords, deactivate and
activate users, self-registration with a course's join code. The rules are in server/accounts.py."""

from __future__ import annotations

from typing import Annotated

from fastapi import APIRouter, Depends, Request, Response
from starlette.concurrency import run_in_threadpool

from server import accounts
from server.deps import AppSettings, CurrentPrincipal, DbSession, Principal, client_address, require_admin
from server.errors import ApiError, responses
from server.ratelimit import RateLimiter
from server.routes.auth import checked_login, set_session
from server.schemas import PasswordChange, PasswordReset, SignupRequest, Username, UserOut

router = APIRouter(tags=["accounts"])
Admin = Annotated[Principal, Depends(require_admin)]


@router.post("/me/password", status_code=204, responses=responses(401, 403, 422, 429))
def change_password(
    body: PasswordChange,
    request: Request,
    response: Response,
    db: DbSession,
    settings: AppSettings,
    principal: CurrentPrincipal,
) -> Response:
    """The caller's own password: the current one (403 WRONG_PASSWORD if wrong; wrong tries use up the login
    budget of the name), the new one by the password rule (422 PASSWORD_RULE naming it). Other sessions end;
    this browser's session goes on (a new cookie)."""
    if principal.api_key is not None or principal.user is None:
        raise ApiError("FORBIDDEN")
    try:  # the failed-login budget of /auth/login: a taken-over session cannot guess the password freely
        user = checked_login(request, db, settings, principal.user.username, body.current_password)
    except ApiError as err:
        raise ApiError("WRONG_PASSWORD") if err.code == "BAD_CREDENTIALS" else err from None
    accounts.change_password(db, user, body.current_password, body.new_password)
    set_session(response, settings, user)
    response.status_code = 204
    return response


@router.post(
    "/users/{username}/password-reset", response_model=PasswordReset, responses=responses(401, 403, 404)
)
def reset_password(username: Username, db: DbSession, principal: CurrentPrincipal) -> PasswordReset:
    """A one-time password, shown only in this answer; the user must change it at the next login (until then the
    API answers 403 PASSWORD_CHANGE_REQUIRED). Instructors: students they manage or teach; admins: anyone."""
    user, password = accounts.reset_password(db, principal, username)
    return PasswordReset(username=user.username, password=password)


@router.post("/users/{username}/deactivate", response_model=UserOut, responses=responses(401, 403, 404, 409))
def deactivate(username: Username, db: DbSession, principal: Admin) -> UserOut:
    """Admins: the user cannot log in any more; their sessions, tokens and API keys stop working."""
    return accounts.set_active(db, principal, username, active=False)


@router.post("/users/{username}/activate", response_model=UserOut, responses=responses(401, 403, 404, 409))
def activate(username: Username, db: DbSession, principal: Admin) -> UserOut:
    return accounts.set_active(db, principal, username, active=True)


@router.post("/auth/signup", response_model=UserOut, status_code=201, responses=responses(404, 409, 422, 429))
async def signup(
    body: SignupRequest, request: Request, response: Response, db: DbSession, settings: AppSettings
) -> UserOut:
    """Self-registration (only with PALTRAINER_SELF_SIGNUP=course-code, else 404): a student account in the
    course with this join code, logged in at once (the session cookie of /auth/login). A wrong code is 404
    JOIN_CODE_INVALID; tries are limited per address."""
    if settings.self_signup != "course-code":
        raise ApiError("NOT_FOUND")
    limiter: RateLimiter = request.app.state.limiter
    wait = limiter.hit("signup", f"ip:{client_address(request)}", settings.rate_signup_per_minute)
    if wait:
        raise ApiError("RATE_LIMITED", headers={"Retry-After": str(wait)}, retry_after=wait)
    # hashing the password takes a while (argon2): off the event loop
    user = await run_in_threadpool(accounts.signup, db, body.join_code, body.username, body.password)
    set_session(response, settings, user)
    return accounts.user_out(db, user)
