"""LTI grades and roster for instructors: the grade passback's status (GET /lti/scores), a failed passback sent
again (POST /lti/scores/{id}/retry), the platform course's roster pulled into a course
(POST /courses/{id}/lti/roster). Course instructors see and do this for their courses, admins for all."""

from __future__ import annotations

from datetime import datetime
from typing import Annotated, Any, Literal

from fastapi import APIRouter, Path, Query
from pydantic import BaseModel
from sqlalchemy import select

from server import courses
from server.deps import CurrentPrincipal, DbSession
from server.errors import ApiError, ErrorBody, responses
from server.lti import ags, nrps
from server.models import CourseMember, LtiContext, LtiPlatform, LtiScore, LtiUser, Submission, User
from server.schemas import DB_INT_MAX, Slug, utc

router = APIRouter(tags=["lti"])
Id = Annotated[int, Path(ge=1, le=DB_INT_MAX)]
State = Literal["pending", "sent", "failed", "superseded"]
BAD_GATEWAY: dict[int | str, dict[str, Any]] = {
    502: {"model": ErrorBody, "description": "The learning platform did not answer as expected"}
}
MAX_ROWS = 2000


class ScoreOut(BaseModel):
    """One grade on its way to (or in) the platform's gradebook."""

    id: int
    submission: int
    user: str | None  # our user name
    name: str  # the name the platform gave
    exercise: str
    assignment: int | None
    course: int | None
    score: float | None  # of 100, as sent (the trainee's best so far)
    state: State
    attempts: int
    last_error: str | None
    next_attempt_at: datetime | None  # pending only
    sent_at: datetime | None
    created_at: datetime


class ScoresOut(BaseModel):
    counts: dict[str, int]  # rows per state
    scores: list[ScoreOut]  # newest first


def _taught(db: DbSession, user: User) -> list[int]:
    return list(
        db.scalars(
            select(CourseMember.course_id).where(
                CourseMember.user_id == user.id, CourseMember.role == "instructor"
            )
        )
    )


def _score_out(row: LtiScore, sub: Submission, user: User | None, name: str) -> ScoreOut:
    return ScoreOut(
        id=row.id,
        submission=row.submission_id,
        user=user.username if user else None,
        name=name,
        exercise=row.exercise_slug,
        assignment=sub.assignment_id,
        course=row.course_id,
        score=row.score_given,
        state=row.state,  # type: ignore[arg-type]
        attempts=row.attempts,
        last_error=row.last_error,
        next_attempt_at=utc(row.next_attempt_at) if row.state == "pending" else None,
        sent_at=utc(row.sent_at) if row.sent_at else None,
        created_at=utc(row.created_at),
    )


def _row_for(db: DbSession, principal: CurrentPrincipal, score_id: int) -> LtiScore:
    """A score row the caller may manage: an admin, or an instructor of its course."""
    row = db.get(LtiScore, score_id)
    user = principal.user if principal.api_key is None else None
    if row is None or user is None:
        raise ApiError("LTI_SCORE_NOT_FOUND", score=score_id)
    if user.role != "admin" and (row.course_id is None or row.course_id not in _taught(db, user)):
        raise ApiError("LTI_SCORE_NOT_FOUND", score=score_id)
    return row


@router.get("/lti/scores", response_model=ScoresOut, responses=responses(401, 403, 404, 422))
def scores(
    db: DbSession,
    principal: CurrentPrincipal,
    course: Annotated[int | None, Query(ge=1, le=DB_INT_MAX)] = None,
    assignment: Annotated[int | None, Query(ge=1, le=DB_INT_MAX)] = None,
    exercise: Annotated[Slug | None, Query()] = None,
    state: Annotated[State | None, Query()] = None,
) -> ScoresOut:
    """The grade passback to the learning platforms: per submission its state (pending: waiting or retried
    with backoff; sent; failed: given up, may be retried; superseded: a newer score carried it), attempts and
    the platform's last error. Filters: course, assignment, exercise, state. Admins: all; instructors: the
    courses they teach."""
    if principal.api_key is not None or principal.user is None:
        raise ApiError("FORBIDDEN")
    user = principal.user
    q = (
        select(LtiScore, Submission, User, LtiUser.name)
        .join(Submission, Submission.id == LtiScore.submission_id)
        .outerjoin(User, User.id == LtiScore.user_id)
        .outerjoin(LtiUser, (LtiUser.platform_id == LtiScore.platform_id) & (LtiUser.sub == LtiScore.lti_sub))
    )
    if course is not None:
        courses.course_for(db, principal, course, manage=True)
        q = q.where(LtiScore.course_id == course)
    if assignment is not None:
        courses.assignment_for(db, principal, assignment, manage=True)
        q = q.where(Submission.assignment_id == assignment)
    if course is None and assignment is None and user.role != "admin":
        if user.role != "instructor":
            raise ApiError("FORBIDDEN")
        q = q.where(LtiScore.course_id.in_(_taught(db, user)))
    if exercise is not None:
        q = q.where(LtiScore.exercise_slug == exercise)
    if state is not None:
        q = q.where(LtiScore.state == state)
    rows = db.execute(q.order_by(LtiScore.id.desc()).limit(MAX_ROWS)).all()
    out = [_score_out(r[0], r[1], r[2], r[3] or "") for r in rows]
    counts = {s: 0 for s in ("pending", "sent", "failed", "superseded")}
    for s in out:
        counts[s.state] += 1
    return ScoresOut(counts=counts, scores=out)


@router.post("/lti/scores/{score_id}/retry", response_model=ScoreOut, responses=responses(401, 404, 409))
def retry(score_id: Id, db: DbSession, principal: CurrentPrincipal) -> ScoreOut:
    """A failed passback back into the queue (sent within seconds if the platform answers)."""
    row = _row_for(db, principal, score_id)
    if row.state != "failed":
        raise ApiError("LTI_SCORE_NOT_FAILED")
    ags.retry(db, row)
    sub = db.get(Submission, row.submission_id)
    assert sub is not None
    lti_user = db.scalars(
        select(LtiUser).where(LtiUser.platform_id == row.platform_id, LtiUser.sub == row.lti_sub)
    ).first()
    return _score_out(
        row, sub, db.get(User, row.user_id) if row.user_id else None, lti_user.name if lti_user else ""
    )


class LinkedCourse(BaseModel):
    """A learning-platform course linked to this course (made by an instructor's launch from it)."""

    platform: str  # the platform's name
    context: str  # the platform course's title
    roster: bool  # the platform offers its roster (NRPS): POST …/lti/roster can pull it


@router.get("/courses/{course_id}/lti", response_model=list[LinkedCourse], responses=responses(401, 403, 404))
def linked_courses(course_id: Id, db: DbSession, principal: CurrentPrincipal) -> list[LinkedCourse]:
    """The course's instructors and admins: the learning-platform courses linked to it (empty: none)."""
    courses.course_for(db, principal, course_id, manage=True)
    rows = db.execute(
        select(LtiContext, LtiPlatform)
        .join(LtiPlatform, LtiPlatform.id == LtiContext.platform_id)
        .where(LtiContext.course_id == course_id)
        .order_by(LtiContext.id)
    ).all()
    return [
        LinkedCourse(platform=p.name or p.issuer, context=c.title, roster=c.memberships_url is not None)
        for c, p in rows
    ]


@router.post(
    "/courses/{course_id}/lti/roster",
    response_model=nrps.RosterOut,
    responses={**responses(401, 403, 404, 409), **BAD_GATEWAY},
)
async def pull_roster(course_id: Id, db: DbSession, principal: CurrentPrincipal) -> nrps.RosterOut:
    """The course's instructors and admins: the members of the linked learning-platform course (Names and Role
    Provisioning Services) become users and members here (Learner → student, Instructor → instructor)."""
    courses.course_for(db, principal, course_id, manage=True)
    return await nrps.pull_roster(db, course_id)
