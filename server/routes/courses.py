"""Courses (Klassen): list/create, one course, its members (add, remove, a class list), joining with a code."""

from __future__ import annotations

from typing import Annotated

from fastapi import APIRouter, Depends, Path, Request, Response
from starlette.concurrency import run_in_threadpool

from server import courses
from server.courses import (
    CourseCreate,
    CourseOut,
    CourseUpdate,
    ImportedMembers,
    JoinRequest,
    MemberIn,
    MemberOut,
)
from server.deps import AppSettings, CurrentPrincipal, DbSession, client_address, rate_limit
from server.errors import ApiError, responses
from server.ratelimit import RateLimiter
from server.schemas import DB_INT_MAX, Username

router = APIRouter(prefix="/courses", tags=["courses"])
CourseId = Annotated[int, Path(ge=1, le=DB_INT_MAX)]


@router.get("", response_model=list[CourseOut], responses=responses(401, 403))
def list_courses(db: DbSession, principal: CurrentPrincipal) -> list[CourseOut]:
    """Admins: every course; instructors and students: the courses they are in."""
    return courses.list_courses(db, principal)


@router.post("", response_model=CourseOut, status_code=201, responses=responses(401, 403, 404, 409, 422))
def create_course(body: CourseCreate, db: DbSession, principal: CurrentPrincipal) -> CourseOut:
    """Instructors (who teach it) and admins; the answer has the join code for the students."""
    return courses.create_course(db, principal, body)


@router.post(
    "/join",
    response_model=CourseOut,
    responses=responses(401, 403, 404, 422, 429),
    dependencies=[Depends(rate_limit("join", "rate_join_per_minute"))],
)
def join_course(
    body: JoinRequest, request: Request, db: DbSession, settings: AppSettings, principal: CurrentPrincipal
) -> CourseOut:
    """A student joins the course with this join code (404 JOIN_CODE_INVALID for every failure); tries are
    limited per user and per address."""
    limiter: RateLimiter = request.app.state.limiter
    wait = limiter.hit("join-address", f"ip:{client_address(request)}", settings.rate_join_address_per_minute)
    if wait:
        raise ApiError("RATE_LIMITED", headers={"Retry-After": str(wait)}, retry_after=wait)
    return courses.join(db, principal, body.code)


@router.get("/{course_id}", response_model=CourseOut, responses=responses(401, 403, 404))
def get_course(course_id: CourseId, db: DbSession, principal: CurrentPrincipal) -> CourseOut:
    return courses.course_out(db, courses.course_for(db, principal, course_id), principal.user)  # type: ignore[arg-type]


@router.patch("/{course_id}", response_model=CourseOut, responses=responses(401, 403, 404, 422))
def update_course(
    course_id: CourseId, body: CourseUpdate, db: DbSession, principal: CurrentPrincipal
) -> CourseOut:
    return courses.update_course(db, principal, course_id, body)


@router.delete("/{course_id}", status_code=204, responses=responses(401, 403, 404))
def delete_course(course_id: CourseId, db: DbSession, principal: CurrentPrincipal) -> Response:
    """The course with its memberships and assignments; submissions stay."""
    courses.delete_course(db, principal, course_id)
    return Response(status_code=204)


@router.get("/{course_id}/members", response_model=list[MemberOut], responses=responses(401, 403, 404))
def list_members(course_id: CourseId, db: DbSession, principal: CurrentPrincipal) -> list[MemberOut]:
    """The course's instructors and admins."""
    return courses.list_members(db, principal, course_id)


@router.post(
    "/{course_id}/members",
    response_model=MemberOut,
    status_code=201,
    responses=responses(401, 403, 404, 422, 429),
    dependencies=[Depends(rate_limit("enrol", "rate_enrol_per_minute"))],
)
def add_member(course_id: CourseId, body: MemberIn, db: DbSession, principal: CurrentPrincipal) -> MemberOut:
    """A student the caller manages (admins: any student account), or an instructor account as a further
    instructor; adding twice is fine. Anybody else is 404 USER_NOT_FOUND, as if there were no such user:
    they join with the course's code."""
    return courses.add_member(db, principal, course_id, body)


@router.delete("/{course_id}/members/{username}", status_code=204, responses=responses(401, 403, 404))
def remove_member(
    course_id: CourseId, username: Username, db: DbSession, principal: CurrentPrincipal
) -> Response:
    courses.remove_member(db, principal, course_id, username)
    return Response(status_code=204)


@router.post(
    "/{course_id}/members/import",
    response_model=ImportedMembers,
    status_code=201,
    responses=responses(401, 403, 404, 409, 413, 422),
    openapi_extra={
        "requestBody": {"required": True, "content": {"text/csv": {"schema": {"type": "string"}}}}
    },
)
async def import_members(
    course_id: CourseId, request: Request, db: DbSession, principal: CurrentPrincipal
) -> ImportedMembers:
    """A class list as for POST /users/import: new students, all in this course (generated passwords in the
    answer, this once)."""
    data = await request.body()
    return await run_in_threadpool(courses.import_members, db, principal, course_id, data)
