"""Every database query of the server: routes and the CLI call these, never SQL of their own."""

from __future__ import annotations

import secrets
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from datetime import datetime
from typing import Any, TypeVar

from sqlalchemy import func, or_, select, update
from sqlalchemy.exc import IntegrityError
from sqlalchemy.orm import Session

from server.models import (
    ApiKey,
    Assignment,
    Base,
    Course,
    CourseMember,
    Draft,
    Exercise,
    ExerciseDrawing,
    ExerciseVersion,
    GradeOverride,
    Submission,
    User,
    now,
)

_Row = TypeVar("_Row", bound=Base)


class Duplicate(Exception):
    """A row with the same unique key is there already: a concurrent request stored it first."""


def _insert(db: Session, row: _Row) -> _Row:
    """Store a new row; Duplicate (rolled back) if a unique key is taken, however close the other request was."""
    db.add(row)
    try:
        db.commit()
    except IntegrityError as err:
        db.rollback()
        raise Duplicate(str(err.orig)) from err
    return row


# --- users -------------------------------------------------------------------------------


def user_by_name(db: Session, username: str) -> User | None:
    return db.scalars(select(User).where(User.username == username)).first()


def user_by_id(db: Session, user_id: int) -> User | None:
    return db.get(User, user_id)


def create_user(
    db: Session, username: str, password_hash: str, role: str, instructor_id: int | None = None
) -> User:
    user = _insert(
        db, User(username=username, password_hash=password_hash, role=role, instructor_id=instructor_id)
    )
    if instructor_id is not None:
        enrol_managed(db, user.id, instructor_id)
    return user


def create_users(db: Session, rows: Sequence[tuple[str, str, str, int | None]]) -> list[User]:
    """Several users (name, password hash, role, instructor id) in one transaction: all or none (Duplicate)."""
    users = [User(username=n, password_hash=h, role=r, instructor_id=i) for n, h, r, i in rows]
    db.add_all(users)
    try:
        db.commit()
    except IntegrityError as err:
        db.rollback()
        raise Duplicate(str(err.orig)) from err
    for u in users:
        if u.instructor_id is not None:
            enrol_managed(db, u.id, u.instructor_id)
    return users


def users_by_names(db: Session, names: Sequence[str]) -> Sequence[User]:
    return db.scalars(select(User).where(User.username.in_(list(names)))).all() if names else []


def set_instructor(db: Session, user: User, instructor_id: int | None) -> None:
    if user.instructor_id is not None and user.instructor_id != instructor_id:
        for course in courses_of(db, user.instructor_id, "instructor"):
            if course.name == DEFAULT_COURSE:
                remove_member(db, course.id, user.id)
    user.instructor_id = instructor_id
    db.commit()
    if instructor_id is not None:
        enrol_managed(db, user.id, instructor_id)


DEFAULT_COURSE = "Meine Klasse"  # where students an instructor creates or is given go (migration 0006 too)
_CODE_ALPHABET = "ABCDEFGHJKLMNPQRSTUVWXYZ23456789"  # no 0/O, 1/I


def new_join_code() -> str:
    return "".join(secrets.choice(_CODE_ALPHABET) for _ in range(8))


def enrol_managed(db: Session, user_id: int, instructor_id: int) -> None:
    """A student put under an instructor joins the instructor's course "Meine Klasse" (made if missing)."""
    if user_id != instructor_id:
        add_member(
            db, default_course(db, instructor_id, DEFAULT_COURSE, new_join_code()).id, user_id, "student"
        )


def students_of(db: Session, instructor_id: int) -> Sequence[User]:
    """The students of every course the instructor teaches, by name."""
    return db.scalars(
        select(User).where(User.id.in_(taught_students(instructor_id))).order_by(User.username)
    ).all()


def list_users(db: Session) -> Sequence[User]:
    return db.scalars(select(User).order_by(User.username)).all()


def set_password(db: Session, user: User, password_hash: str) -> None:
    user.password_hash = password_hash
    db.commit()


# --- API keys ----------------------------------------------------------------------------


def create_api_key(
    db: Session, name: str, prefix: str, key_hash: str, scopes: list[str], owner_id: int | None
) -> ApiKey:
    return _insert(db, ApiKey(name=name, prefix=prefix, key_hash=key_hash, scopes=scopes, owner_id=owner_id))


def api_key_by_prefix(db: Session, prefix: str) -> ApiKey | None:
    return db.scalars(select(ApiKey).where(ApiKey.prefix == prefix)).first()


def api_key_by_id(db: Session, key_id: int) -> ApiKey | None:
    return db.get(ApiKey, key_id)


def list_api_keys(db: Session, owner_id: int | None = None) -> Sequence[ApiKey]:
    q = select(ApiKey).order_by(ApiKey.id)
    if owner_id is not None:
        q = q.where(ApiKey.owner_id == owner_id)
    return db.scalars(q).all()


def touch_api_key(db: Session, key: ApiKey) -> None:
    key.last_used_at = now()
    db.commit()


def revoke_api_key(db: Session, key: ApiKey) -> None:
    if key.revoked_at is None:
        key.revoked_at = now()
        db.commit()


# --- exercises ---------------------------------------------------------------------------


def list_exercises(db: Session) -> Sequence[Exercise]:
    return db.scalars(select(Exercise).order_by(Exercise.slug)).all()


def exercise_by_slug(db: Session, slug: str) -> Exercise | None:
    return db.scalars(select(Exercise).where(Exercise.slug == slug)).first()


def exercise_by_id(db: Session, exercise_id: int) -> Exercise | None:
    return db.get(Exercise, exercise_id)


def create_exercise(
    db: Session, fields: dict[str, Any], owner_id: int | None, builtin: bool = False
) -> Exercise:
    return _insert(db, Exercise(**fields, owner_id=owner_id, builtin=builtin))


def update_exercise(db: Session, exercise: Exercise, fields: dict[str, Any]) -> Exercise:
    for name, value in fields.items():
        setattr(exercise, name, value)
    db.commit()
    return exercise


def exercise_has_submissions(db: Session, exercise: Exercise) -> bool:
    n = db.scalar(select(func.count()).select_from(Submission).where(Submission.exercise_id == exercise.id))
    return bool(n)


def delete_exercise(db: Session, exercise: Exercise) -> None:
    db.delete(exercise)
    db.commit()


def restricted_exercises(db: Session) -> Sequence[tuple[str, int | None, str, bool]]:
    """(slug, owner_id, visibility, archived) of every exercise not simply public: drafts, course-only, archived."""
    rows = db.execute(
        select(Exercise.slug, Exercise.owner_id, Exercise.visibility, Exercise.archived_at).where(
            or_(Exercise.visibility != "public", Exercise.archived_at.is_not(None))
        )
    ).all()
    return [(r[0], r[1], r[2], r[3] is not None) for r in rows]


def course_instructors_of(db: Session, user_id: int) -> set[int]:
    """The instructors of every course the user is a member of (in any role)."""
    courses = select(CourseMember.course_id).where(CourseMember.user_id == user_id)
    return set(
        db.scalars(
            select(CourseMember.user_id).where(
                CourseMember.course_id.in_(courses), CourseMember.role == "instructor"
            )
        ).all()
    )


def add_exercise_version(db: Session, exercise: Exercise, created_by: int | None) -> None:
    """Keep the exercise's current document as its version `exercise.version` (before an edit makes a new one)."""
    db.add(
        ExerciseVersion(
            exercise_id=exercise.id,
            version=exercise.version,
            title_de=exercise.title_de,
            document=exercise.document,
            created_by=created_by,
        )
    )


def exercise_versions(db: Session, exercise_id: int) -> Sequence[ExerciseVersion]:
    return db.scalars(
        select(ExerciseVersion)
        .where(ExerciseVersion.exercise_id == exercise_id)
        .order_by(ExerciseVersion.version)
    ).all()


def exercise_drawing(db: Session, exercise_id: int) -> ExerciseDrawing | None:
    return db.scalars(select(ExerciseDrawing).where(ExerciseDrawing.exercise_id == exercise_id)).first()


def own_drawings(db: Session, exercise_ids: Iterable[int]) -> dict[int, tuple[str, str]]:
    """exercise id → (media type, file name) of the exercises with an own drawing."""
    ids = list(exercise_ids)
    if not ids:
        return {}
    rows = db.execute(
        select(ExerciseDrawing.exercise_id, ExerciseDrawing.media_type, ExerciseDrawing.filename).where(
            ExerciseDrawing.exercise_id.in_(ids)
        )
    ).all()
    return {r[0]: (r[1], r[2]) for r in rows}


def set_exercise_drawing(
    db: Session, exercise: Exercise, media_type: str, filename: str, data: bytes
) -> None:
    row = exercise_drawing(db, exercise.id)
    if row is None:
        db.add(ExerciseDrawing(exercise_id=exercise.id, media_type=media_type, filename=filename, data=data))
    else:
        row.media_type, row.filename, row.data, row.created_at = media_type, filename, data, now()
    exercise.updated_at = now()  # what is cached by content (pictures, sheets) is made anew
    db.commit()


def delete_exercise_drawing(db: Session, exercise: Exercise) -> bool:
    row = exercise_drawing(db, exercise.id)
    if row is None:
        return False
    db.delete(row)
    exercise.updated_at = now()
    db.commit()
    return True


# --- submissions -------------------------------------------------------------------------


def create_submission(db: Session, **fields: Any) -> Submission:
    return _insert(db, Submission(**fields))


def submission_by_id(db: Session, submission_id: int) -> Submission | None:
    return db.get(Submission, submission_id)


def submission_by_idempotency_key(db: Session, key: str) -> Submission | None:
    return db.scalars(select(Submission).where(Submission.idempotency_key == key)).first()


def list_submissions(
    db: Session,
    *,
    user_id: int | None = None,
    owner_id: int | None = None,
    api_key_id: int | None = None,
    exercise_slug: str | None = None,
    everything: bool = False,
    instructor_id: int | None = None,
) -> Sequence[tuple[Submission, Exercise, User | None]]:
    """Submissions with their exercise and author, newest first, filtered by who may see them.

    `user_id`: the author's own; `owner_id`: those to exercises that user owns; `api_key_id`: those
    made through that key; `instructor_id`: those of the students that instructor manages; `everything`:
    all (admins).
    """
    q = (
        select(Submission, Exercise, User)
        .join(Exercise, Submission.exercise_id == Exercise.id)
        .outerjoin(User, Submission.user_id == User.id)
    )
    if not everything:
        visible = visible_to(
            user_id=user_id, owner_id=owner_id, api_key_id=api_key_id, instructor_id=instructor_id
        )
        if visible is None:
            return []
        q = q.where(visible)
    if exercise_slug is not None:
        q = q.where(Exercise.slug == exercise_slug)
    rows = db.execute(q.order_by(Submission.created_at.desc(), Submission.id.desc())).all()
    return [(r[0], r[1], r[2]) for r in rows]


def own_submissions(
    db: Session, user_id: int, exercise_id: int | None = None, limit: int | None = None
) -> Sequence[Submission]:
    """A user's own submissions (to one exercise), newest first."""
    q = select(Submission).where(Submission.user_id == user_id)
    if exercise_id is not None:
        q = q.where(Submission.exercise_id == exercise_id)
    q = q.order_by(Submission.created_at.desc(), Submission.id.desc())
    return db.scalars(q.limit(limit) if limit else q).all()


# --- submissions without their program and diagnostics: results, insights, the storage quota --------------


@dataclass(frozen=True)
class Scored:
    """A submission's light columns: what the results tables, the insights' choice of each student's best and
    the storage quota need — not its program, diagnostics or criteria. `grading` has the score only (enough for
    services.best_of and services._score)."""

    id: int
    user_id: int | None
    exercise_id: int
    assignment_id: int | None
    created_at: datetime
    late: bool
    auto: bool
    held: bool
    score: int | None
    max_score: int | None
    overridden: bool = False
    exercise_version: int | None = None  # the exercise's version it was graded against

    @property
    def grading(self) -> dict[str, int] | None:
        if self.score is None or self.max_score is None:
            return None
        return {"score": self.score, "max_score": self.max_score}


# the score that counts: the teacher's override, else the grader's (read from the grade in the database)
_SCORE = func.coalesce(Submission.override_score, Submission.grading["score"].as_float())
_MAX_SCORE = Submission.grading["max_score"].as_float()
_SCORED = (
    Submission.id,
    Submission.user_id,
    Submission.exercise_id,
    Submission.assignment_id,
    Submission.created_at,
    Submission.late,
    Submission.auto,
    Submission.held,
    _SCORE,
    _MAX_SCORE,
    Submission.override_score.is_not(None),
    Submission.exercise_version,
)
_NEWEST = (Submission.created_at.desc(), Submission.id.desc())


def _scored(rows: Iterable[Any]) -> list[Scored]:
    return [
        Scored(
            r[0],
            r[1],
            r[2],
            r[3],
            r[4],
            bool(r[5]),
            bool(r[6]),
            bool(r[7]),
            None if r[8] is None or r[9] is None else int(r[8]),
            None if r[9] is None else int(r[9]),
            bool(r[10]),
            r[11],
        )
        for r in rows
    ]


def visible_to(
    *,
    user_id: int | None = None,
    owner_id: int | None = None,
    api_key_id: int | None = None,
    instructor_id: int | None = None,
) -> Any:
    """The condition of `list_submissions` on submissions (joined with their exercise) for these readers, or None
    when it has none (nothing is visible)."""
    conds = []
    if user_id is not None:
        conds.append(Submission.user_id == user_id)
    if owner_id is not None:
        conds.append(Exercise.owner_id == owner_id)
    if api_key_id is not None:
        conds.append(Submission.api_key_id == api_key_id)
    if instructor_id is not None:  # their courses' work, and their managed students' practice
        conds.append(instructed(instructor_id))
    return or_(*conds) if conds else None


def scored_submissions(
    db: Session,
    *,
    user_id: int | None = None,
    owner_id: int | None = None,
    api_key_id: int | None = None,
    everything: bool = False,
    instructor_id: int | None = None,
) -> list[Scored]:
    """What `list_submissions` gives the same readers, newest first, in light columns (Scored)."""
    q = select(*_SCORED).join(Exercise, Submission.exercise_id == Exercise.id)
    if not everything:
        cond = visible_to(
            user_id=user_id, owner_id=owner_id, api_key_id=api_key_id, instructor_id=instructor_id
        )
        if cond is None:
            return []
        q = q.where(cond)
    return _scored(db.execute(q.order_by(*_NEWEST)).all())


def assignment_scores(db: Session, assignment_id: int, limit: int | None = None) -> list[Scored]:
    """An assignment's submissions by users (not learning-platform learners), newest first, in light columns."""
    q = (
        select(*_SCORED)
        .where(Submission.assignment_id == assignment_id, Submission.user_id.is_not(None))
        .order_by(*_NEWEST)
    )
    return _scored(db.execute(q.limit(limit) if limit is not None else q).all())


def submission_details(db: Session, ids: Sequence[int]) -> Sequence[Any]:
    """Program, result (diagnostics, summary) and grade of these submissions only: rows with .id, .program,
    .result, .grading."""
    if not ids:
        return []
    return db.execute(
        select(Submission.id, Submission.program, Submission.result, Submission.grading)
        .where(Submission.id.in_(list(ids)))
        .order_by(Submission.id)
    ).all()


def exercises_by_ids(db: Session, ids: Iterable[int]) -> Sequence[Exercise]:
    wanted = list(set(ids))
    return db.scalars(select(Exercise).where(Exercise.id.in_(wanted))).all() if wanted else []


def set_override(db: Session, submission: Submission, score: int | None, comment: str, by: int) -> None:
    """The teacher's score (None: back to the grader's) and comment on a submission; the change is kept."""
    at = now()
    submission.override_score = score
    submission.override_comment = comment if score is not None else None
    submission.override_by, submission.override_at = (by, at) if score is not None else (None, None)
    db.add(
        GradeOverride(submission_id=submission.id, score=score, comment=comment, by_user_id=by, created_at=at)
    )
    db.commit()


def overrides_of(db: Session, submission_id: int) -> Sequence[GradeOverride]:
    return db.scalars(
        select(GradeOverride)
        .where(GradeOverride.submission_id == submission_id)
        .order_by(GradeOverride.created_at, GradeOverride.id)
    ).all()


def summarise_submissions(db: Session, submission: Submission, keep: int) -> int:
    """The storage quota of one author (user; else API key and learner) and exercise, after `submission` was
    stored: the newest `keep` submissions keep their diagnostics, and so does the best one of practice and of each
    assignment (what the results tables and the insights count); the older ones are summarised — their
    diagnostics list is dropped, their summary keeps how many there were (`diagnostics`), and program, counts and
    grade stay (what the history and the tables show). Returns how many were summarised now; each is summarised
    once (`summarised` in its result)."""
    if submission.user_id is not None:
        author = [Submission.user_id == submission.user_id]
    else:
        learner = (
            Submission.external_user.is_(None)
            if submission.external_user is None
            else Submission.external_user == submission.external_user
        )
        author = [Submission.user_id.is_(None), Submission.api_key_id == submission.api_key_id, learner]
    same = [Submission.exercise_id == submission.exercise_id, *author]
    newest = select(Submission.id).where(*same).order_by(*_NEWEST).limit(keep)
    older = db.execute(
        select(Submission.id, Submission.assignment_id).where(
            *same, Submission.id.not_in(newest), Submission.result["summarised"].as_boolean().is_(None)
        )
    ).all()
    if not older:
        return 0
    best = set()
    for scope in {
        row[1] for row in older
    }:  # the best of practice (None) and of each assignment, as best_of chooses
        in_scope = Submission.assignment_id.is_(None) if scope is None else Submission.assignment_id == scope
        best.add(
            db.scalar(
                select(Submission.id)
                .where(*same, in_scope, _SCORE.is_not(None))
                .order_by(_SCORE.desc(), *_NEWEST)
                .limit(1)
            )
        )
    done = 0
    for row_id, result in db.execute(
        select(Submission.id, Submission.result).where(
            Submission.id.in_([row[0] for row in older if row[0] not in best])
        )
    ).all():
        result = dict(result or {})
        summary = dict(result.get("summary") or {})
        summary.setdefault("diagnostics", len(result.get("diagnostics") or []))
        db.execute(
            update(Submission)
            .where(Submission.id == row_id)
            .values(result={**result, "diagnostics": [], "summary": summary, "summarised": True})
            .execution_options(synchronize_session=False)
        )
        done += 1
    db.commit()
    return done


# --- drafts ------------------------------------------------------------------------------


def draft(db: Session, user_id: int, exercise_id: int, assignment_id: int | None = None) -> Draft | None:
    """The practice draft (`assignment_id` None) or the draft for that exam."""
    scope = Draft.assignment_id.is_(None) if assignment_id is None else Draft.assignment_id == assignment_id
    return db.scalars(
        select(Draft).where(Draft.user_id == user_id, Draft.exercise_id == exercise_id, scope)
    ).first()


def save_draft(
    db: Session, user_id: int, exercise_id: int, program: str, assignment_id: int | None = None
) -> Draft:
    """Insert or replace the draft; two tabs saving at the same moment end with one row (the later text)."""
    for _ in range(3):
        row = draft(db, user_id, exercise_id, assignment_id)
        if row is not None:
            row.program, row.updated_at = program, now()
            db.commit()
            return row
        try:
            return _insert(
                db,
                Draft(
                    user_id=user_id,
                    exercise_id=exercise_id,
                    assignment_id=assignment_id,
                    program=program,
                    updated_at=now(),
                ),
            )
        except Duplicate:
            continue  # the other request inserted it first: update that row
    raise Duplicate("draft")


def delete_draft(db: Session, user_id: int, exercise_id: int, assignment_id: int | None = None) -> None:
    row = draft(db, user_id, exercise_id, assignment_id)
    if row is not None:
        db.delete(row)
        db.commit()


def drafts_of(db: Session, user_id: int) -> Sequence[Draft]:
    """The user's practice drafts (an exam's drafts stay with the exam)."""
    return db.scalars(select(Draft).where(Draft.user_id == user_id, Draft.assignment_id.is_(None))).all()


def all_drafts_of(db: Session, user_id: int) -> Sequence[Draft]:
    """The user's drafts, practice and exams' alike."""
    return db.scalars(select(Draft).where(Draft.user_id == user_id)).all()


def exam_drafts(db: Session, assignment_id: int) -> Sequence[Draft]:
    return db.scalars(select(Draft).where(Draft.assignment_id == assignment_id)).all()


# --- courses and assignments (issue 19) ----------------------------------------------------------


def create_course(db: Session, name: str, join_code: str, instructor_ids: Sequence[int]) -> Course:
    course = _insert(db, Course(name=name, join_code=join_code))
    for uid in instructor_ids:
        add_member(db, course.id, uid, "instructor")
    return course


def course_by_id(db: Session, course_id: int) -> Course | None:
    return db.get(Course, course_id)


def course_by_code(db: Session, code: str) -> Course | None:
    return db.scalars(select(Course).where(Course.join_code == code)).first()


def courses_of(db: Session, user_id: int | None = None, role: str | None = None) -> Sequence[Course]:
    """Every course (user_id None), or those the user is a member of (as `role`), by name."""
    q = select(Course)
    if user_id is not None:
        sub = select(CourseMember.course_id).where(CourseMember.user_id == user_id)
        if role is not None:
            sub = sub.where(CourseMember.role == role)
        q = q.where(Course.id.in_(sub))
    return db.scalars(q.order_by(Course.name, Course.id)).all()


def update_course(db: Session, course: Course, fields: dict[str, Any]) -> Course:
    for name, value in fields.items():
        setattr(course, name, value)
    db.commit()
    return course


def delete_course(db: Session, course: Course) -> None:
    db.delete(course)
    db.commit()


def members(db: Session, course_id: int) -> Sequence[tuple[CourseMember, User]]:
    rows = db.execute(
        select(CourseMember, User)
        .join(User, CourseMember.user_id == User.id)
        .where(CourseMember.course_id == course_id)
        .order_by(CourseMember.role, User.username)
    ).all()
    return [(r[0], r[1]) for r in rows]


def membership(db: Session, course_id: int, user_id: int) -> CourseMember | None:
    return db.scalars(
        select(CourseMember).where(CourseMember.course_id == course_id, CourseMember.user_id == user_id)
    ).first()


def add_member(db: Session, course_id: int, user_id: int, role: str) -> CourseMember:
    """Idempotent: an existing member keeps their row (with the new role)."""
    row = membership(db, course_id, user_id)
    if row is not None:
        row.role = role
        db.commit()
        return row
    try:
        return _insert(db, CourseMember(course_id=course_id, user_id=user_id, role=role))
    except Duplicate:
        row = membership(db, course_id, user_id)
        assert row is not None
        return row


def remove_member(db: Session, course_id: int, user_id: int) -> None:
    row = membership(db, course_id, user_id)
    if row is not None:
        db.delete(row)
        db.commit()


def taught_students(instructor_id: int) -> Any:
    """A subquery: the ids of the students of every course the user teaches."""
    taught = select(CourseMember.course_id).where(
        CourseMember.user_id == instructor_id, CourseMember.role == "instructor"
    )
    return select(CourseMember.user_id).where(
        CourseMember.course_id.in_(taught), CourseMember.role == "student"
    )


def instructed(instructor_id: int) -> Any:
    """A condition on submissions: what an instructor sees of their students' work — the submissions to the
    assignments of every course they teach, and the practice (no assignment) of the students they manage. Not a
    student's work in another course, nor the practice of a student who merely joined their course."""
    taught = select(CourseMember.course_id).where(
        CourseMember.user_id == instructor_id, CourseMember.role == "instructor"
    )
    managed = select(User.id).where(User.instructor_id == instructor_id)
    return or_(
        Submission.assignment_id.in_(select(Assignment.id).where(Assignment.course_id.in_(taught))),
        (Submission.assignment_id.is_(None)) & Submission.user_id.in_(managed),
    )


def instructs(db: Session, instructor_id: int, submission_id: int) -> bool:
    """Whether the submission is among what the instructor sees of their students' work (`instructed`)."""
    return bool(
        db.scalar(
            select(func.count())
            .select_from(Submission)
            .where(Submission.id == submission_id, instructed(instructor_id))
        )
    )


def default_course(db: Session, instructor_id: int, name: str, join_code: str) -> Course:
    """The instructor's course `name` (the first one so named), made if there is none."""
    for course in courses_of(db, instructor_id, "instructor"):
        if course.name == name:
            return course
    return create_course(db, name, join_code, [instructor_id])


def create_assignment(db: Session, **fields: Any) -> Assignment:
    return _insert(db, Assignment(**fields))


def assignment_by_id(db: Session, assignment_id: int) -> Assignment | None:
    return db.get(Assignment, assignment_id)


def assignments_of(db: Session, course_ids: Sequence[int]) -> Sequence[Assignment]:
    if not course_ids:
        return []
    return db.scalars(
        select(Assignment)
        .where(Assignment.course_id.in_(list(course_ids)))
        .order_by(Assignment.opens_at, Assignment.id)
    ).all()


def student_assignments(db: Session, user_id: int) -> Sequence[Assignment]:
    """The assignments of every course the user is a student of (their role in the course decides, not their
    account's role)."""
    courses = select(CourseMember.course_id).where(
        CourseMember.user_id == user_id, CourseMember.role == "student"
    )
    return db.scalars(
        select(Assignment)
        .where(Assignment.course_id.in_(courses))
        .order_by(Assignment.opens_at, Assignment.id)
    ).all()


def taught_assignments(db: Session, instructor_id: int) -> Sequence[Assignment]:
    """The assignments of every course the user teaches."""
    courses = select(CourseMember.course_id).where(
        CourseMember.user_id == instructor_id, CourseMember.role == "instructor"
    )
    return db.scalars(select(Assignment).where(Assignment.course_id.in_(courses))).all()


def unreleased_exams(db: Session) -> Sequence[Assignment]:
    """Every exam whose results are not released: upcoming, running, or ended and held."""
    return db.scalars(
        select(Assignment).where(Assignment.mode == "exam", Assignment.released_at.is_(None))
    ).all()


def unfinalized_exams(db: Session, before: datetime) -> Sequence[Assignment]:
    return db.scalars(
        select(Assignment).where(
            Assignment.mode == "exam", Assignment.finalized_at.is_(None), Assignment.deadline <= before
        )
    ).all()


def claim_finalizing(db: Session, assignment_id: int, at: datetime, until: datetime) -> bool:
    """Take the lease of finalising an ended exam: True for the one caller (of any replica) that got it; an
    expired lease (its replica stopped) can be taken again."""
    claimed = db.execute(
        update(Assignment)
        .where(
            Assignment.id == assignment_id,
            Assignment.finalized_at.is_(None),
            or_(Assignment.finalizing_until.is_(None), Assignment.finalizing_until < at),
        )
        .values(finalizing_until=until)
        .execution_options(synchronize_session=False)
    )
    db.commit()
    return bool(claimed.rowcount)  # type: ignore[attr-defined]


def finish_finalizing(db: Session, assignment_id: int, at: datetime) -> None:
    db.execute(
        update(Assignment)
        .where(Assignment.id == assignment_id)
        .values(finalized_at=at, finalizing_until=None)
        .execution_options(synchronize_session=False)
    )
    db.commit()


def count_attempts(db: Session, assignment_id: int, user_id: int, exercise_id: int) -> int:
    """The submissions of a user to one exercise of an assignment."""
    return int(
        db.scalar(
            select(func.count())
            .select_from(Submission)
            .where(
                Submission.assignment_id == assignment_id,
                Submission.user_id == user_id,
                Submission.exercise_id == exercise_id,
            )
        )
        or 0
    )


def save(db: Session, row: Base) -> None:
    """Commit the changes made to `row`."""
    db.add(row)
    db.commit()


def delete_row(db: Session, row: Base) -> None:
    db.delete(row)
    db.commit()


def assignment_submissions(
    db: Session, assignment_id: int, user_id: int | None = None
) -> Sequence[Submission]:
    """An assignment's submissions (one user's), newest first."""
    q = select(Submission).where(Submission.assignment_id == assignment_id)
    if user_id is not None:
        q = q.where(Submission.user_id == user_id)
    return db.scalars(q.order_by(Submission.created_at.desc(), Submission.id.desc())).all()


def release_submissions(db: Session, assignment_id: int) -> None:
    for s in assignment_submissions(db, assignment_id):
        s.held = False
    db.commit()


def ready(db: Session) -> datetime:
    """A trivial query: the database answers."""
    db.execute(select(1))
    return now()
