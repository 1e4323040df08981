"""Request dependencies: the database session, who is asking (user or API key), role/scope rules, rate limits,
the cap on heavy requests."""

from __future__ import annotations

from collections.abc import AsyncIterator, Awaitable, Callable, Iterator
from dataclasses import dataclass
from typing import Annotated

from fastapi import Depends, Request
from fastapi.security import APIKeyHeader, HTTPAuthorizationCredentials, HTTPBearer
from sqlalchemy.orm import Session

from server import repository as repo
from server.config import Settings
from server.db import Database
from server.errors import ApiError
from server.models import ApiKey, User
from server.ratelimit import RateLimiter
from server.security import hash_api_key, read_token, same_hash, split_api_key, token_user_id, token_version
from server.workers import Workers

SESSION_COOKIE = "paltrainer_session"

_bearer = HTTPBearer(auto_error=False, description="A token from POST /api/v1/auth/token, or an API key")
_api_key_header = APIKeyHeader(name="X-API-Key", auto_error=False, description="An API key")


# the dependencies that do no I/O are coroutines: FastAPI runs a plain function in a thread of the pool, a hop that
# costs more than the function
async def get_settings(request: Request) -> Settings:
    settings: Settings = request.app.state.settings
    return settings


async def get_workers(request: Request) -> Workers:
    workers: Workers = request.app.state.workers
    return workers


def get_db(request: Request) -> Iterator[Session]:
    database: Database = request.app.state.db
    with database.session() as session:
        yield session


DbSession = Annotated[Session, Depends(get_db)]
AppSettings = Annotated[Settings, Depends(get_settings)]
AppWorkers = Annotated[Workers, Depends(get_workers)]


@dataclass(frozen=True)
class Principal:
    """Who a request is: a user, or an API key (acting for its owner, if it has one, within its scopes)."""

    user: User | None = None
    api_key: ApiKey | None = None

    @property
    def user_id(self) -> int | None:
        return self.user.id if self.user is not None else None

    @property
    def identity(self) -> str:
        if self.api_key is not None:
            return f"key:{self.api_key.prefix}"
        return f"user:{self.user.id}" if self.user is not None else "anonymous"

    def has_scope(self, scope: str) -> bool:
        return self.api_key is None or scope in self.api_key.scopes

    def is_instructor(self) -> bool:
        """Users with role instructor or admin; keys acting for such a user count when the scope allows."""
        return self.user is not None and self.user.role in ("instructor", "admin")

    def is_admin(self) -> bool:
        return self.user is not None and self.user.role == "admin" and self.api_key is None


ANONYMOUS = Principal()


def resolve(
    db: Session, settings: Settings, token: str | None, api_key: str | None, cookie: str | None
) -> Principal:
    """The principal of a request's credentials; ApiError 401 on bad ones, ANONYMOUS with none."""
    key = api_key or (token if token and split_api_key(token) else None)
    if key is not None:
        prefix = split_api_key(key)
        record = repo.api_key_by_prefix(db, prefix) if prefix else None
        if (
            record is None
            or record.revoked_at is not None
            or not same_hash(record.key_hash, hash_api_key(key))
        ):
            raise ApiError("BAD_API_KEY", headers={"WWW-Authenticate": "Bearer"})
        repo.touch_api_key(db, record)
        owner = repo.user_by_id(db, record.owner_id) if record.owner_id is not None else None
        if owner is not None and owner.deactivated_at is not None:  # a deactivated user's keys act no more
            raise ApiError("BAD_API_KEY", headers={"WWW-Authenticate": "Bearer"})
        return Principal(user=owner, api_key=record)
    jwt_text = token or cookie
    if jwt_text:
        user = token_user(db, settings, jwt_text)
        if user is None:
            raise ApiError("BAD_TOKEN", headers={"WWW-Authenticate": "Bearer"})
        return Principal(user=user)
    return ANONYMOUS


def token_user(db: Session, settings: Settings, jwt_text: str) -> User | None:
    """The user a token is valid for: signed by us, not expired, naming an active (not deactivated) user, and
    issued since the user last logged out (its version is the user's current token version); else None."""
    claims = read_token(settings.jwt_secret(), jwt_text)
    user_id = token_user_id(claims) if claims else None
    user = repo.user_by_id(db, user_id) if user_id is not None else None
    if (
        user is None
        or claims is None
        or token_version(claims) != user.token_version
        or user.deactivated_at is not None
    ):
        return None
    return user


def get_principal(
    request: Request,
    db: DbSession,
    settings: AppSettings,
    bearer: Annotated[HTTPAuthorizationCredentials | None, Depends(_bearer)],
    api_key: Annotated[str | None, Depends(_api_key_header)],
) -> Principal:
    principal = resolve(
        db, settings, bearer.credentials if bearer else None, api_key, request.cookies.get(SESSION_COOKIE)
    )
    # the pooled connection goes back now: a route that reads no more holds none (however long it waits for a
    # worker), and one that reads more takes one again (the user stays loaded: expire_on_commit is off)
    db.commit()
    request.state.principal = principal.identity
    if (
        principal.api_key is None
        and principal.user is not None
        and principal.user.must_change_password
        and request.url.path not in PASSWORD_CHANGE_PATHS
    ):
        raise ApiError("PASSWORD_CHANGE_REQUIRED")
    return principal


# what a user whose password was reset may still do until they chose their own (server/routes/accounts.py)
PASSWORD_CHANGE_PATHS = frozenset({"/api/v1/me", "/api/v1/me/password", "/api/v1/auth/logout"})


OptionalPrincipal = Annotated[Principal, Depends(get_principal)]


async def require_login(principal: OptionalPrincipal) -> Principal:
    if principal is ANONYMOUS:
        raise ApiError("NOT_AUTHENTICATED", headers={"WWW-Authenticate": "Bearer"})
    return principal


CurrentPrincipal = Annotated[Principal, Depends(require_login)]


def require_scope(scope: str) -> Callable[[Principal], Awaitable[Principal]]:
    async def check(principal: CurrentPrincipal) -> Principal:
        if not principal.has_scope(scope):
            raise ApiError("MISSING_SCOPE", scope=scope)
        return principal

    return check


async def require_admin(principal: CurrentPrincipal) -> Principal:
    if not principal.is_admin():
        raise ApiError("FORBIDDEN")
    return principal


async def practice_principal(principal: OptionalPrincipal, settings: AppSettings) -> Principal:
    """check/run/simulate: anyone while free practice is on; else a user or a key with scope practice."""
    if principal is ANONYMOUS:
        if not settings.free_practice:
            raise ApiError("FREE_PRACTICE_OFF", headers={"WWW-Authenticate": "Bearer"})
    elif not principal.has_scope("practice"):
        raise ApiError("MISSING_SCOPE", scope="practice")
    return principal


PracticePrincipal = Annotated[Principal, Depends(practice_principal)]


def client_address(request: Request) -> str:
    return request.client.host if request.client else "-"


def rate_limit(bucket: str, setting: str) -> Callable[[Request, Principal, Settings], None]:
    """A dependency that counts one request in `bucket` for the principal (or the address if anonymous)."""

    def check(request: Request, principal: OptionalPrincipal, settings: AppSettings) -> None:
        limiter: RateLimiter = request.app.state.limiter
        who = principal.identity if principal is not ANONYMOUS else f"ip:{client_address(request)}"
        wait = limiter.hit(bucket, who, int(getattr(settings, setting)))
        if wait:
            raise ApiError("RATE_LIMITED", headers={"Retry-After": str(wait)}, retry_after=wait)

    return check


async def heavy_job(
    request: Request, principal: OptionalPrincipal, settings: AppSettings
) -> AsyncIterator[None]:
    """A dependency of every route that computes something heavy in a worker (task sheets, pictures, drawings,
    submissions, simulations, 3D scenes and deviations): at most PALTRAINER_HEAVY_JOBS_PER_USER of them at a
    time per user or API key, PALTRAINER_HEAVY_JOBS_PER_ADDRESS per address for anonymous ones; one more is
    answered 429 TOO_MANY_JOBS at once, without waiting for anything (Workers.admit)."""
    workers: Workers = request.app.state.workers
    if principal is ANONYMOUS:
        owner, limit = f"ip:{client_address(request)}", settings.heavy_jobs_per_address
    else:
        owner, limit = principal.identity, settings.heavy_jobs_per_user
    with workers.admit(owner, limit):
        yield


HEAVY = Depends(heavy_job)
