"""Courses (Klassen), their members and assignments; exams: the automatic submission at the end and releasing
the results (issue 19). The rules a trainee meets while working are in server/access.py."""

from __future__ import annotations

import asyncio
import logging
from dataclasses import dataclass
from datetime import datetime, timedelta
from typing import Annotated, Any, Literal, cast

from pydantic import BaseModel, ConfigDict, Field
from sqlalchemy.orm import Session
from starlette.concurrency import run_in_threadpool

from server import access, services
from server import repository as repo
from server.db import Database
from server.deps import Principal
from server.errors import ApiError
from server.export import excel_csv
from server.jobs import job_submission
from server.lti import ags as lti_ags
from server.models import Assignment, Course, Exercise, User, now
from server.schemas import CLEAN, ImportedUser, OverrideOut, Slug, Time, Title, Username, length, utc
from server.workers import Workers

log = logging.getLogger("paltrainer.server")

# --- request and response bodies ---------------------------------------------------------------------

JoinCode = Annotated[str, length(32, min_length=1), CLEAN]


class CourseCreate(BaseModel):
    model_config = ConfigDict(extra="forbid")

    name: Title
    instructors: list[Username] = Field(
        default=[], max_length=20, description="Further instructors (the creating instructor is one anyway)"
    )


class CourseUpdate(BaseModel):
    model_config = ConfigDict(extra="forbid")

    name: Title | None = None
    new_join_code: bool = Field(
        default=False, description="Replace the join code (the old one stops working)"
    )


class CourseOut(BaseModel):
    id: int
    name: str
    join_code: str | None = Field(description="Instructors and admins only")
    instructors: list[str]
    students: int
    created_at: Time


class JoinRequest(BaseModel):
    model_config = ConfigDict(extra="forbid")

    code: JoinCode


class MemberIn(BaseModel):
    model_config = ConfigDict(extra="forbid")

    username: Username
    role: Literal["student", "instructor"] = "student"


class MemberOut(BaseModel):
    username: str
    role: Literal["student", "instructor"]
    signed_up: bool = Field(
        default=False,
        description="The student made their own account with this course's join code (self-registration)",
    )


class ImportedMembers(BaseModel):
    users: list[ImportedUser]


class AssignmentSettings(BaseModel):
    """What trainees may use while working on it; an exam defaults to exam conditions (all off, one submission),
    practice to everything on (unlimited submissions: 0)."""

    model_config = ConfigDict(extra="forbid")

    live_diagnostics: bool | None = None
    viz: bool | None = None
    hints: bool | None = None
    solution: bool | None = None
    free_practice: bool | None = None
    max_submissions: int | None = Field(default=None, ge=0, le=1000)


class AssignmentCreate(BaseModel):
    model_config = ConfigDict(extra="forbid")

    title: Title
    exercises: list[Slug] = Field(min_length=1, max_length=50)
    mode: Literal["practice", "exam"] = "practice"
    late: Literal["accept", "refuse"] = "accept"
    opens_at: Time
    deadline: Time | None = Field(
        default=None, description="Practice: required; an exam ends after its duration"
    )
    duration_minutes: int | None = Field(default=None, ge=1, le=24 * 60, description="Exams: e.g. 90")
    settings: AssignmentSettings = AssignmentSettings()


class AssignmentUpdate(BaseModel):
    model_config = ConfigDict(extra="forbid")

    title: Title | None = None
    exercises: list[Slug] | None = Field(default=None, min_length=1, max_length=50)
    late: Literal["accept", "refuse"] | None = None
    opens_at: Time | None = None
    deadline: Time | None = None
    duration_minutes: int | None = Field(default=None, ge=1, le=24 * 60)
    settings: AssignmentSettings | None = None


class AssignmentOut(BaseModel):
    id: int
    course: int
    course_name: str
    title: str
    exercises: list[str]
    mode: Literal["practice", "exam"]
    late: Literal["accept", "refuse"]
    opens_at: Time
    deadline: Time = Field(description="For an exam: its end (opens_at + duration)")
    duration_minutes: int | None
    settings: dict[str, Any]
    released: bool
    created_at: Time


class MyExercise(BaseModel):
    exercise: str
    submitted: bool
    draft: bool = Field(default=False, description="A draft of it is saved (an exam's own draft for an exam)")
    late: bool = False
    auto: bool = Field(default=False, description="The last draft, submitted at the exam's end")
    submission: int | None = None
    score: int | None = Field(default=None, description="Exams: only once the results are released")
    max_score: int | None = None
    criteria: list[dict[str, Any]] | None = None
    override: OverrideOut | None = None
    program: str | None = None


class MyAssignment(AssignmentOut):
    status: Literal["upcoming", "open", "running", "submitting", "submitted", "late", "closed"] = Field(
        description="submitting: the exam is over and its last drafts are being submitted (a moment)"
    )
    seconds_left: int | None = Field(description="Until the deadline / the exam's end, while open")
    seconds_to_start: int | None = Field(
        default=None,
        description="Until it opens, while upcoming (the server's clock: a page need not trust its own)",
    )
    results_visible: bool
    items: list[MyExercise]


class AssignmentResultCell(BaseModel):
    submission: int
    score: int | None = Field(description="The score that counts: the teacher's, where one is set")
    max_score: int | None
    late: bool
    auto: bool
    overridden: bool = Field(default=False, description="The score was set by an instructor")
    created_at: Time
    exercise_version: int | None = Field(
        default=None, description="The exercise's version it was graded against"
    )
    version_note: str = Field(
        default="", description='"Version 1" when that is not the exercise\'s current one'
    )


class AssignmentResultRow(BaseModel):
    username: str
    results: dict[str, AssignmentResultCell]
    total: int | None = Field(
        description="The sum over every gradable exercise of the assignment (one not handed in counts 0)"
    )
    max_total: int | None = Field(description="The sum of their maximum scores")
    percent: float | None = Field(default=None, description="total / max_total in %, one decimal")


class AssignmentResults(BaseModel):
    assignment: int
    title: str
    exercises: list[str]
    released: bool
    trainees: list[AssignmentResultRow]


def max_score_of(exercise: Exercise) -> int | None:
    """An exercise's maximum score (its rubric's points); None: not gradable."""
    rubric = (exercise.document or {}).get("rubric") if exercise.document else None
    return sum(int(c.get("points", 0)) for c in rubric) if isinstance(rubric, list) and rubric else None


# --- courses -----------------------------------------------------------------------------------------


def _user(principal: Principal) -> User:
    """Courses are for logged-in users (API keys: no)."""
    if principal.api_key is not None or principal.user is None:
        raise ApiError("FORBIDDEN")
    return principal.user


def _is_admin(user: User) -> bool:
    return user.role == "admin"


def course_for(db: Session, principal: Principal, course_id: int, manage: bool = False) -> Course:
    """The course if the caller may see it (admins, its members; `manage`: admins and its instructors); else 404
    (403 for a student of the course asking to manage it)."""
    user = _user(principal)
    course = repo.course_by_id(db, course_id)
    member = repo.membership(db, course_id, user.id) if course else None
    if course is None or (member is None and not _is_admin(user)):
        raise ApiError("COURSE_NOT_FOUND", course=course_id)
    if manage and not _is_admin(user) and (member is None or member.role != "instructor"):
        raise ApiError("FORBIDDEN")
    return course


def _manages(db: Session, user: User, course_id: int) -> bool:
    if _is_admin(user):
        return True
    member = repo.membership(db, course_id, user.id)
    return member is not None and member.role == "instructor"


def course_out(db: Session, course: Course, user: User) -> CourseOut:
    rows = repo.members(db, course.id)
    return CourseOut(
        id=course.id,
        name=course.name,
        join_code=course.join_code if _manages(db, user, course.id) else None,
        instructors=[u.username for m, u in rows if m.role == "instructor"],
        students=sum(1 for m, _ in rows if m.role == "student"),
        created_at=course.created_at,
    )


def list_courses(db: Session, principal: Principal) -> list[CourseOut]:
    """Admins: every course; everyone else: the courses they are in."""
    user = _user(principal)
    courses = repo.courses_of(db) if _is_admin(user) else repo.courses_of(db, user.id)
    return [course_out(db, c, user) for c in courses]


def create_course(db: Session, principal: Principal, body: CourseCreate) -> CourseOut:
    user = _user(principal)
    if user.role not in ("instructor", "admin"):
        raise ApiError("FORBIDDEN")
    ids = [] if _is_admin(user) else [user.id]
    for name in body.instructors:
        other = services.instructor_named(db, name)
        if other.id not in ids:
            ids.append(other.id)
    for _ in range(3):
        try:
            return course_out(db, repo.create_course(db, body.name, repo.new_join_code(), ids), user)
        except repo.Duplicate:
            continue  # the join code was taken: draw another
    raise ApiError("CONFLICT")


def update_course(db: Session, principal: Principal, course_id: int, body: CourseUpdate) -> CourseOut:
    course = course_for(db, principal, course_id, manage=True)
    fields: dict[str, Any] = {}
    if body.name is not None:
        fields["name"] = body.name
    if body.new_join_code:
        fields["join_code"] = repo.new_join_code()
    return course_out(db, repo.update_course(db, course, fields), _user(principal))


def delete_course(db: Session, principal: Principal, course_id: int) -> None:
    """The course, its memberships and assignments; the submissions stay (without their assignment)."""
    repo.delete_course(db, course_for(db, principal, course_id, manage=True))


def list_members(db: Session, principal: Principal, course_id: int) -> list[MemberOut]:
    course_for(db, principal, course_id, manage=True)
    return [
        MemberOut(
            username=u.username,
            role=m.role,  # type: ignore[arg-type]
            signed_up=u.signup_course_id == course_id,
        )
        for m, u in repo.members(db, course_id)
    ]


def add_member(db: Session, principal: Principal, course_id: int, body: MemberIn) -> MemberOut:
    """Who may enrol whom: a further instructor of the course must be an instructor (or admin) account; a student
    must be a student account, and an instructor adds only the students they manage (made by them, by their class
    list, or put under them by an admin) — everybody else joins with the course's code, or an admin adds them.
    An account the caller may not add answers as one that does not exist (no user-name oracle)."""
    course_for(db, principal, course_id, manage=True)
    caller = _user(principal)
    other: User | None
    if body.role == "instructor":
        other = services.instructor_named(db, body.username)
    else:
        other = repo.user_by_name(db, body.username)
        if other is None or not (_is_admin(caller) or other.instructor_id == caller.id):
            raise ApiError("USER_NOT_FOUND", user=body.username)
        if other.role != "student":
            raise ApiError("NOT_A_STUDENT", user=body.username)
    repo.add_member(db, course_id, other.id, body.role)
    return MemberOut(username=other.username, role=body.role)


def remove_member(db: Session, principal: Principal, course_id: int, username: str) -> None:
    course_for(db, principal, course_id, manage=True)
    other = repo.user_by_name(db, username)
    if other is None or repo.membership(db, course_id, other.id) is None:
        raise ApiError("USER_NOT_FOUND", user=username)
    repo.remove_member(db, course_id, other.id)


def import_members(db: Session, principal: Principal, course_id: int, data: bytes) -> ImportedMembers:
    """A class list (the format of POST /users/import): new students, all in this course."""
    course_for(db, principal, course_id, manage=True)
    users = services.import_class_list(db, data, None)
    for row in repo.users_by_names(db, [u.username for u in users]):
        repo.add_member(db, course_id, row.id, "student")
    return ImportedMembers(users=users)


def join(db: Session, principal: Principal, code: str) -> CourseOut:
    """A student joins the course with `code` (case and spaces do not matter); joining twice is fine. Every
    failure — no such code, or an account that cannot join as a student — is the same 404."""
    user = _user(principal)
    course = repo.course_by_code(db, code.strip().upper())
    if course is None or user.role != "student":
        raise ApiError("JOIN_CODE_INVALID")
    member = repo.membership(db, course.id, user.id)
    if member is None:
        repo.add_member(db, course.id, user.id, "student")
    return course_out(db, course, user)


# --- assignments ---------------------------------------------------------------------------------------


def assignment_out(db: Session, a: Assignment, student: bool = False) -> AssignmentOut:
    """The assignment; to a student an exam names its exercises only from its start."""
    course = repo.course_by_id(db, a.course_id)
    hidden = student and a.mode == "exam" and now() < utc(a.opens_at)
    return AssignmentOut(
        id=a.id,
        course=a.course_id,
        course_name=course.name if course else "",
        title=a.title,
        exercises=[] if hidden else list(a.exercises),
        mode=a.mode,  # type: ignore[arg-type]
        late=a.late,  # type: ignore[arg-type]
        opens_at=a.opens_at,
        deadline=access.end_of(a),
        duration_minutes=a.duration_minutes,
        settings=access.settings_of(a),
        released=a.released_at is not None,
        created_at=a.created_at,
    )


def _check_exercises(db: Session, user: User, slugs: list[str]) -> list[str]:
    """Built-in exercises and the instructor's own (admins: any); each once, in the given order."""
    out: list[str] = []
    for slug in slugs:
        exercise = services.get_exercise(db, slug)
        if not (exercise.builtin or _is_admin(user) or exercise.owner_id == user.id):
            raise ApiError("FORBIDDEN")
        if slug not in out:
            out.append(slug)
    return out


def _times(mode: str, opens_at: datetime, deadline: datetime | None, duration: int | None) -> datetime:
    """The stored deadline (an exam's end); ASSIGNMENT_TIMES when they do not fit."""
    if mode == "exam":
        if duration is None:
            raise ApiError(
                "ASSIGNMENT_TIMES",
                detail="eine Prüfung braucht eine Dauer (duration_minutes)",
                detail_en="an exam needs a duration (duration_minutes)",
            )
        return utc(opens_at) + timedelta(minutes=duration)
    if deadline is None:
        raise ApiError(
            "ASSIGNMENT_TIMES",
            detail="es fehlt die Abgabefrist (deadline)",
            detail_en="the deadline is missing",
        )
    if utc(deadline) <= utc(opens_at):
        raise ApiError(
            "ASSIGNMENT_TIMES",
            detail="die Abgabefrist liegt nicht nach der Freigabe",
            detail_en="the deadline is not after the opening time",
        )
    return deadline


def _settings(body: AssignmentSettings | None) -> dict[str, Any]:
    return {k: v for k, v in (body.model_dump() if body else {}).items() if v is not None}


def list_assignments(db: Session, principal: Principal, course_id: int) -> list[AssignmentOut]:
    course_for(db, principal, course_id)
    student = not _manages(db, _user(principal), course_id)
    return [assignment_out(db, a, student) for a in repo.assignments_of(db, [course_id])]


def create_assignment(
    db: Session, principal: Principal, course_id: int, body: AssignmentCreate
) -> AssignmentOut:
    course_for(db, principal, course_id, manage=True)
    slugs = _check_exercises(db, _user(principal), body.exercises)
    deadline = _times(body.mode, body.opens_at, body.deadline, body.duration_minutes)
    a = repo.create_assignment(
        db,
        course_id=course_id,
        title=body.title,
        exercises=slugs,
        mode=body.mode,
        late="refuse" if body.mode == "exam" else body.late,
        opens_at=body.opens_at,
        deadline=deadline,
        duration_minutes=body.duration_minutes if body.mode == "exam" else None,
        settings=_settings(body.settings),
    )
    return assignment_out(db, a)


def assignment_for(db: Session, principal: Principal, assignment_id: int, manage: bool = False) -> Assignment:
    a = repo.assignment_by_id(db, assignment_id)
    if a is None:
        raise ApiError("ASSIGNMENT_NOT_FOUND", assignment=assignment_id)
    try:
        course_for(db, principal, a.course_id, manage)
    except ApiError as err:
        if err.code == "COURSE_NOT_FOUND":
            raise ApiError("ASSIGNMENT_NOT_FOUND", assignment=assignment_id) from None
        raise
    return a


def update_assignment(
    db: Session, principal: Principal, assignment_id: int, body: AssignmentUpdate
) -> AssignmentOut:
    a = assignment_for(db, principal, assignment_id, manage=True)
    fields = body.model_dump(exclude_unset=True)
    if fields.get("exercises") is not None:
        a.exercises = _check_exercises(db, _user(principal), body.exercises or [])
    for name in ("title", "late", "opens_at", "duration_minutes"):
        if fields.get(name) is not None:
            setattr(a, name, fields[name])
    if body.settings is not None:
        a.settings = _settings(body.settings)
    if a.mode == "exam":
        a.late = "refuse"
    a.deadline = _times(
        a.mode,
        a.opens_at,
        body.deadline or (a.deadline if a.mode == "practice" else None),
        a.duration_minutes,
    )
    repo.save(db, a)
    return assignment_out(db, a)


def delete_assignment(db: Session, principal: Principal, assignment_id: int) -> None:
    repo.delete_row(db, assignment_for(db, principal, assignment_id, manage=True))


def get_assignment(db: Session, principal: Principal, assignment_id: int) -> AssignmentOut:
    a = assignment_for(db, principal, assignment_id)
    return assignment_out(db, a, student=not _manages(db, _user(principal), a.course_id))


async def assignment_sheets(
    db: Session, workers: Workers, principal: Principal, assignment_id: int, lang: str
) -> bytes:
    """The assignment's exercises as one printed task sheet (instructors; students once it is open): each
    exercise's pages rendered (and kept) on their own, then put together (services.task_sheet)."""

    def read() -> tuple[list[dict[str, Any]], list[tuple[str, bytes] | None]]:  # in the threadpool
        a = assignment_for(db, principal, assignment_id)
        if not _manages(db, _user(principal), a.course_id) and now() < utc(a.opens_at):
            raise ApiError("ASSIGNMENT_NOT_OPEN", opens_at=utc(a.opens_at).isoformat())
        exercises = [
            e
            for e in (repo.exercise_by_slug(db, s) for s in a.exercises)
            if e is not None and e.document is not None
        ]
        own = [
            repo.exercise_drawing(db, e.id) for e in exercises
        ]  # the authors' own drawings, printed instead
        db.commit()  # the pooled connection goes back before the wait for the workers
        return (
            [e.document for e in exercises if e.document is not None],
            [(d.media_type, d.data) if d is not None else None for d in own],
        )

    documents, drawings = await run_in_threadpool(read)
    if not documents:
        raise ApiError("NOT_FOUND")
    return await services.task_sheet(workers, documents, lang, drawings)


def release(db: Session, principal: Principal, assignment_id: int) -> AssignmentOut:
    """Students see their exam results from now on (score, criteria, program)."""
    a = assignment_for(db, principal, assignment_id, manage=True)
    if a.mode == "exam" and now() < access.end_of(a):
        raise ApiError("EXAM_NOT_OVER")
    if a.released_at is None:
        a.released_at = now()
        repo.save(db, a)
    repo.release_submissions(db, a.id)
    return assignment_out(db, a)


# --- the end of an exam: the last drafts become submissions -------------------------------------------

FINALIZE_LEASE = timedelta(minutes=10)  # a replica that stopped while finalising is taken over after this
FINALIZE_GRADING_AT_ONCE = 4  # drafts graded at the same time (the workers queue the rest)


@dataclass(frozen=True)
class _Finalising:
    """An ended exam whose lease this caller holds, and the drafts it still has to submit."""

    assignment: Assignment
    limit: int
    exercises: dict[int, Exercise]
    drafts: list[tuple[int, int, str]]  # user, exercise, program


def _claim(db: Session, a: Assignment) -> _Finalising | None:
    """The exam's lease and its work, if it has ended, is not finalised and no other caller holds it."""
    t = now()
    if a.mode != "exam" or a.finalized_at is not None or t < access.end_of(a):
        return None
    if not repo.claim_finalizing(db, a.id, t, t + FINALIZE_LEASE):
        return None  # another task or replica is at it
    students = {user.id for member, user in repo.members(db, a.course_id) if member.role == "student"}
    exercises = {e.id: e for e in (repo.exercise_by_slug(db, slug) for slug in a.exercises) if e is not None}
    done = {(s.user_id, s.exercise_id) for s in repo.assignment_submissions(db, a.id)}
    drafts = [
        (d.user_id, d.exercise_id, d.program)
        for d in repo.exam_drafts(db, a.id)
        if d.user_id in students and d.exercise_id in exercises and (d.user_id, d.exercise_id) not in done
    ]
    db.commit()  # no connection is held while the workers grade
    return _Finalising(a, int(access.settings_of(a)["max_submissions"] or 0), exercises, drafts)


def _store_finalised(db: Session, work: _Finalising, results: list[dict[str, Any]]) -> int:
    a, made = work.assignment, 0
    for (user_id, exercise_id, program), result in zip(work.drafts, results, strict=True):
        exercise = work.exercises[exercise_id]
        fields = {
            "exercise_id": exercise.id,
            "user_id": user_id,
            "program": program,
            "dialect": exercise.dialect,
            "error_count": result["errors"],
            "warning_count": result["warnings"],
            "result": {"diagnostics": result["diagnostics"], "summary": result["summary"]},
            "grading": result["grading"],
            "idempotency_key": f"exam{a.id}:u{user_id}:{exercise.slug}",
            "assignment_id": a.id,
            "late": False,
            "held": a.released_at is None,
            "auto": True,
            "exercise_version": exercise.version,
        }
        try:
            submission = services.store_attempt(db, fields, work.limit, exercise.slug)
        except (repo.Duplicate, ApiError):
            continue  # stored by an earlier finaliser, or the trainee's own submission came first
        made += 1
        lti_ags.after_graded(db, submission)  # sent to the platform once the results are released
    repo.finish_finalizing(db, a.id, now())
    return made


async def finalize_exam(db: Session, workers: Workers, a: Assignment) -> int:
    """After an exam's end, submit every student's last saved draft of that exam for each exam exercise they did
    not submit. One caller at a time does it, across replicas (a lease on the exam's row); each draft is graded
    once and stored once (an idempotency key per student and exercise; the attempt limit holds against a
    submission that raced it). Readers never call this: the background task does. The database is used in the
    thread pool only. Returns the number of new submissions."""
    work = await run_in_threadpool(_claim, db, a)
    if work is None:
        return 0
    at_once = asyncio.Semaphore(FINALIZE_GRADING_AT_ONCE)

    async def graded(program: str, exercise_id: int) -> dict[str, Any]:
        async with at_once:
            exercise = work.exercises[exercise_id]
            result: dict[str, Any] = await workers.call(
                job_submission, program, exercise.dialect, services.exercise_spec(exercise, False)
            )
            return result

    results = await asyncio.gather(*(graded(program, eid) for _, eid, program in work.drafts))
    made: int = await run_in_threadpool(_store_finalised, db, work, list(results))
    return made


async def finalize_ended_exams(database: Database, workers: Workers) -> int:
    made = 0
    with database.session() as db:
        for a in await run_in_threadpool(repo.unfinalized_exams, db, now()):
            made += await finalize_exam(db, workers, a)
    return made


async def finalizer(database: Database, workers: Workers, every: float) -> None:
    """The app's background task: ended exams are finalised a few seconds after their end, whether anybody looks
    or not; pages only read (MyAssignment.status "submitting" until it is done)."""
    while True:
        try:
            await finalize_ended_exams(database, workers)
        except asyncio.CancelledError:
            raise
        except Exception:  # a failed round is retried on the next one
            log.exception("finalising ended exams failed")
        await asyncio.sleep(every)


# --- what the trainee sees, what the instructor sees --------------------------------------------------------


def my_assignments(db: Session, principal: Principal) -> list[MyAssignment]:
    """The caller's assignments (as a student of the course) with deadline, status and their submissions; an
    exam's scores only once released, its exercises only from its start. Only reads (the background task
    submits an ended exam's drafts)."""
    user = _user(principal)
    out = []
    t = now()
    sit = access.situation(db, user)
    drafts = {(d.assignment_id, d.exercise_id) for d in repo.all_drafts_of(db, user.id)}
    for a in repo.student_assignments(db, user.id):
        subs = repo.assignment_submissions(db, a.id, user.id)
        scope = (
            a.id if a.mode == "exam" else None
        )  # an exam's drafts are its own; practice has the practice draft
        items = []
        for slug in [] if a.mode == "exam" and t < utc(a.opens_at) else a.exercises:
            exercise = repo.exercise_by_slug(db, slug)
            mine = [s for s in subs if exercise is not None and s.exercise_id == exercise.id]
            drafted = exercise is not None and (scope, exercise.id) in drafts
            if not mine:
                items.append(MyExercise(exercise=slug, submitted=False, draft=drafted))
                continue
            best = services.best_of(mine)
            visible = access.grade_visible(sit, best, slug)
            score, max_score = services._score(best) if visible else (None, None)
            grading = services.grading_view(best.grading, False) if visible else None
            items.append(
                MyExercise(
                    exercise=slug,
                    submitted=True,
                    draft=drafted,
                    late=best.late,
                    auto=best.auto,
                    submission=best.id,
                    score=score,
                    max_score=max_score,
                    criteria=grading["criteria"] if grading else None,
                    override=services.override_out(db, best) if visible else None,
                    program=best.program if visible or a.mode != "exam" else None,
                )
            )
        end = access.end_of(a)
        all_done = all(i.submitted for i in items)
        status: Literal["upcoming", "open", "running", "submitting", "submitted", "late", "closed"]
        if t < utc(a.opens_at):
            status = "upcoming"
        elif t < end:
            status = "submitted" if all_done else "running" if a.mode == "exam" else "open"
        elif a.mode == "exam" and a.finalized_at is None:
            status = "submitting"
        elif all_done:
            status = "late" if any(i.late for i in items) else "submitted"
        else:
            status = "open" if a.mode == "practice" and a.late == "accept" else "closed"
        out.append(
            MyAssignment(
                **assignment_out(db, a, student=True).model_dump(),
                status=status,
                seconds_left=int((end - t).total_seconds()) if utc(a.opens_at) <= t < end else None,
                seconds_to_start=int((utc(a.opens_at) - t).total_seconds()) if t < utc(a.opens_at) else None,
                results_visible=a.mode != "exam" or a.released_at is not None,
                items=items,
            )
        )
    return out


def assignment_results(db: Session, principal: Principal, assignment_id: int) -> AssignmentResults:
    """Students × the assignment's exercises with the best score (instructors of the course and admins); the
    submissions are read in their light columns (repo.assignment_scores: no program, diagnostics or criteria)."""
    a = assignment_for(db, principal, assignment_id, manage=True)
    found = [e for e in (repo.exercise_by_slug(db, s) for s in a.exercises) if e is not None]
    exercises = {e.id: e.slug for e in found}
    versions = {e.id: e.version for e in found}
    max_total = sum(max_score_of(e) or 0 for e in found)  # every gradable exercise counts, tried or not
    by_user: dict[int, list[repo.Scored]] = {}
    for s in repo.assignment_scores(db, a.id):
        if s.user_id is not None:
            by_user.setdefault(s.user_id, []).append(s)
    rows = []
    for member, user in sorted(repo.members(db, a.course_id), key=lambda mu: mu[1].username.casefold()):
        if member.role != "student":
            continue
        cells: dict[str, AssignmentResultCell] = {}
        for eid, slug in exercises.items():
            mine = [s for s in by_user.get(user.id, []) if s.exercise_id == eid]
            if mine:
                # Scored carries what best_of reads of a Submission (its grading's score and the override)
                best = cast(repo.Scored, services.best_of(mine))  # type: ignore[arg-type]
                score, max_score = services._score(best)  # type: ignore[arg-type]
                cells[slug] = AssignmentResultCell(
                    submission=best.id,
                    score=score,
                    max_score=max_score,
                    late=best.late,
                    auto=best.auto,
                    overridden=best.overridden,
                    created_at=best.created_at,
                    exercise_version=best.exercise_version,
                    version_note=services.version_note(best.exercise_version, versions[eid]),
                )
        total = sum(c.score or 0 for c in cells.values())
        rows.append(
            AssignmentResultRow(
                username=user.username,
                results=cells,
                total=total if max_total else None,
                max_total=max_total or None,
                percent=round(100 * total / max_total, 1) if max_total else None,
            )
        )
    return AssignmentResults(
        assignment=a.id,
        title=a.title,
        exercises=list(a.exercises),
        released=a.released_at is not None,
        trainees=rows,
    )


RESULT_COLUMNS = (
    "Benutzer",
    "Aufgabe",
    "Punktzahl",
    "Höchstpunktzahl",
    "Prozent",
    "Verspätet",
    "Automatisch abgegeben",
    "Abgabe",
    "Zeitpunkt",
    "Von der Lehrkraft geändert",
)


def assignment_results_csv(db: Session, principal: Principal, assignment_id: int) -> str:
    """The results for German Excel (the project's CSV: `;`, UTF-8 with BOM, decimal comma, local time)."""
    table = assignment_results(db, principal, assignment_id)
    rows: list[list[object]] = []
    for trainee in table.trainees:
        for slug in table.exercises:
            cell = trainee.results.get(slug)
            if cell is None:
                rows.append([trainee.username, slug, "", "", "", "", "", "", "", ""])
                continue
            percent = (
                services.decimal_comma(100 * cell.score / cell.max_score)
                if cell.score is not None and cell.max_score
                else ""
            )
            rows.append(
                [
                    trainee.username,
                    slug,
                    "" if cell.score is None else cell.score,
                    "" if cell.max_score is None else cell.max_score,
                    percent,
                    "ja" if cell.late else "nein",
                    "ja" if cell.auto else "nein",
                    cell.submission,
                    services.berlin_time(cell.created_at),
                    "ja" if cell.overridden else "nein",
                ]
            )
        if trainee.max_total:  # the sum over the whole assignment, as the matrix shows it
            rows.append(
                [
                    trainee.username,
                    "Summe",
                    trainee.total,
                    trainee.max_total,
                    services.decimal_comma(trainee.percent or 0.0),
                    "",
                    "",
                    "",
                    "",
                    "",
                ]
            )
    return excel_csv(RESULT_COLUMNS, rows)
