"""The rules of assignments while a trainee works (issue 19): which assignment a submission belongs to, whether it
is late or refused, and what an exam that runs for a student forbids (other exercises, hints, the solution …).

Kept apart from server/courses.py (the use cases) so that server/services.py can ask it without an import cycle.
"""

from __future__ import annotations

from dataclasses import dataclass
from datetime import datetime, timedelta
from typing import Any

from sqlalchemy.orm import Session

from server import repository as repo
from server.errors import ApiError
from server.models import Assignment, Exercise, User, now
from server.schemas import utc

# what an exam allows unless its settings say otherwise; practice allows everything, submissions unlimited (0)
EXAM_DEFAULTS: dict[str, Any] = {"live_diagnostics": False, "viz": False, "hints": False, "solution": False,
                                 "free_practice": False, "max_submissions": 1}
PRACTICE_DEFAULTS: dict[str, Any] = {"live_diagnostics": True, "viz": True, "hints": True, "solution": True,
                                     "free_practice": True, "max_submissions": 0}


def settings_of(assignment: Assignment) -> dict[str, Any]:
    defaults = EXAM_DEFAULTS if assignment.mode == "exam" else PRACTICE_DEFAULTS
    return {**defaults, **{k: v for k, v in (assignment.settings or {}).items() if k in defaults}}


def end_of(assignment: Assignment) -> datetime:
    """The deadline; for an exam its end (start + duration)."""
    if assignment.mode == "exam" and assignment.duration_minutes:
        return utc(assignment.opens_at) + timedelta(minutes=assignment.duration_minutes)
    return utc(assignment.deadline)


def student_assignments(db: Session, user_id: int) -> list[Assignment]:
    """The assignments of every course the user is a student of."""
    return list(repo.assignments_of(db, [c.id for c in repo.courses_of(db, user_id, "student")]))


def running_exams(db: Session, user: User | None, at: datetime | None = None) -> list[Assignment]:
    if user is None:
        return []
    t = at or now()
    return [a for a in student_assignments(db, user.id)
            if a.mode == "exam" and utc(a.opens_at) <= t < end_of(a)]


def check_feature(db: Session, user: User | None, feature: str) -> None:
    """403 EXAM_RUNNING if an exam runs for the user and its settings switch `feature` off (hints, solution, …)."""
    for exam in running_exams(db, user):
        if not settings_of(exam)[feature]:
            raise ApiError("EXAM_RUNNING", end=end_of(exam).isoformat())


def check_exercise(db: Session, user: User | None, exercise: Exercise) -> None:
    """Work on `exercise` (drafts, submissions): refused while an exam runs that lacks it (no free practice),
    and after an exam that has it, until its results are released."""
    if user is None:
        return
    t = now()
    for a in student_assignments(db, user.id):
        if a.mode != "exam" or utc(a.opens_at) > t:
            continue
        inside = exercise.slug in a.exercises
        if t < end_of(a):
            if not inside and not settings_of(a)["free_practice"]:
                raise ApiError("EXAM_RUNNING", end=end_of(a).isoformat())
        elif inside and a.released_at is None:
            raise ApiError("EXAM_OVER", assignment=a.id)


@dataclass(frozen=True)
class Context:
    """What a new submission is part of: the assignment (or none), late, held back until released."""

    assignment_id: int | None = None
    late: bool = False
    held: bool = False


def submission_context(db: Session, user: User | None, exercise: Exercise, assignment_id: int | None) -> Context:
    """The assignment a submission belongs to (`assignment_id` named by the trainee, else the running exam or the
    open practice assignment with the exercise), or an ApiError that refuses it."""
    if assignment_id is not None:
        a = repo.assignment_by_id(db, assignment_id)
        if a is None or user is None or repo.membership(db, a.course_id, user.id) is None:
            raise ApiError("ASSIGNMENT_NOT_FOUND", assignment=assignment_id)
        if exercise.slug not in a.exercises:
            raise ApiError("NOT_IN_ASSIGNMENT", exercise=exercise.slug, assignment=a.id)
        return _entry(db, user, a, exercise)
    check_exercise(db, user, exercise)
    if user is None:
        return Context()
    t = now()
    candidates = [a for a in student_assignments(db, user.id)
                  if exercise.slug in a.exercises and utc(a.opens_at) <= t < end_of(a)]
    candidates.sort(key=lambda a: (a.mode != "exam", end_of(a)))  # a running exam first, then the nearest deadline
    return _entry(db, user, candidates[0], exercise) if candidates else Context()


def _entry(db: Session, user: User, a: Assignment, exercise: Exercise) -> Context:
    t = now()
    if t < utc(a.opens_at):
        raise ApiError("ASSIGNMENT_NOT_OPEN", opens_at=utc(a.opens_at).isoformat())
    late = t >= end_of(a)
    if late and a.mode == "exam":
        raise ApiError("EXAM_OVER", assignment=a.id)
    if late and a.late == "refuse":
        raise ApiError("ASSIGNMENT_CLOSED", deadline=end_of(a).isoformat())
    limit = int(settings_of(a)["max_submissions"] or 0)
    if limit:
        done = [s for s in repo.assignment_submissions(db, a.id, user.id)
                if s.exercise_id == exercise.id]
        if len(done) >= limit:
            raise ApiError("ASSIGNMENT_SUBMITTED", exercise=exercise.slug, limit=limit)
    return Context(assignment_id=a.id, late=late, held=a.mode == "exam" and a.released_at is None)


def allows(database: Any, user_id: int | None, feature: str) -> bool:
    """False while an exam that switches `feature` off runs for the user (the live socket asks on connect)."""
    if user_id is None:
        return True
    with database.session() as db:
        user = repo.user_by_id(db, user_id)
        try:
            check_feature(db, user, feature)
        except ApiError:
            return False
    return True
