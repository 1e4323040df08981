"""Users: admins manage everyone; instructors create students they manage, one by one or from a class list."""

from __future__ import annotations

from typing import Annotated

from fastapi import APIRouter, Depends, Query, Request
from starlette.concurrency import run_in_threadpool

from server import repository as repo
from server import services
from server.deps import CurrentPrincipal, DbSession, Principal, require_admin
from server.errors import ApiError, responses
from server.schemas import ImportedUsers, UserCreate, Username, UserOut, UserUpdate

router = APIRouter(prefix="/users", tags=["accounts"])


@router.get("", response_model=list[UserOut], responses=responses(401, 403))
def list_users(db: DbSession, principal: CurrentPrincipal) -> list[UserOut]:
    """Admins: every user; instructors: the students they manage."""
    return services.visible_users(db, principal)


@router.post("", response_model=UserOut, status_code=201, responses=responses(401, 403, 404, 409, 422))
def create_user(body: UserCreate, db: DbSession, principal: CurrentPrincipal) -> UserOut:
    """Admins: any user, managed by the instructor named in `instructor` (or nobody); instructors: students,
    managed by themselves."""
    return services.create_user_by(db, principal, body)


@router.patch("/{username}", response_model=UserOut, responses=responses(401, 403, 404, 409, 422))
def update_user(
    username: Username,
    body: UserUpdate,
    db: DbSession,
    principal: Annotated[Principal, Depends(require_admin)],
) -> UserOut:
    """Admins: change a user's role (`{"role": "instructor"}`; not their own), put a user under an instructor
    (`{"instructor": NAME}`) or under nobody (`null`); a field left out stays as it is."""
    user = repo.user_by_name(db, username)
    if user is None:
        raise ApiError("USER_NOT_FOUND", user=username)
    if body.instructor is not None:  # checked before anything changes
        services.instructor_named(db, body.instructor)
    if body.role is not None and body.role != user.role:
        if user.id == principal.user_id:  # the last admin would lock everyone out; another admin does it
            raise ApiError("OWN_ACCOUNT")
        user.role = body.role
        db.commit()
    if "instructor" in body.model_fields_set:
        return services.set_instructor(db, username, body.instructor)
    instructor = repo.user_by_id(db, user.instructor_id) if user.instructor_id is not None else None
    return services.user_out(user, instructor.username if instructor else None)


@router.post(
    "/import",
    response_model=ImportedUsers,
    status_code=201,
    responses=responses(401, 403, 404, 409, 413, 422),
    openapi_extra={
        "requestBody": {"required": True, "content": {"text/csv": {"schema": {"type": "string"}}}}
    },
)
async def import_users(
    request: Request,
    db: DbSession,
    principal: CurrentPrincipal,
    instructor: Annotated[
        Username | None, Query(description="Admins: the instructor who manages the new students")
    ] = None,
) -> ImportedUsers:
    """A class list as CSV (`;` or `,`, UTF-8 with or without BOM; columns name;password or name only, an
    optional header row; at most 100 rows) → students managed by the calling instructor (admins: by `instructor`).
    All or none; generated passwords are in the answer, this once."""
    data = await request.body()
    # hashing the passwords takes a while (argon2): off the event loop
    return await run_in_threadpool(services.import_class_list_by, db, principal, data, instructor)
