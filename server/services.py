"""What the routes do, one function per use case: rules (who may see what), limits, calls to repository and workers."""

from __future__ import annotations

from typing import Any

from sqlalchemy.orm import Session

from core.exercises import Exercise as ExerciseDocument
from core.pipeline import DIALECTS
from server import repository as repo
from server.config import Settings
from server.deps import Principal
from server.errors import ApiError
from server.export import csv_text
from server.models import ApiKey, Exercise, Submission, User
from server.schemas import (
    ApiKeyCreated,
    ApiKeyOut,
    ExerciseCreate,
    ExerciseOut,
    ExerciseUpdate,
    LmsResult,
    ProgramRequest,
    SimulateRequest,
    SubmissionCreate,
    SubmissionOut,
    UserOut,
    utc,
)
from server.security import hash_password, new_api_key, verify_password
from server.seed import document_from_fields, exercise_fields
from server.workers import Workers, job_drawing, job_picture, job_submission, job_validate_exercise

# --- pipeline requests ----------------------------------------------------------------------


def check_program(settings: Settings, program: str, dialect: str) -> None:
    if dialect not in DIALECTS:
        raise ApiError("UNKNOWN_DIALECT", dialect=dialect)
    if len(program) > settings.max_program_chars:
        raise ApiError("PROGRAM_TOO_LARGE", size=len(program), limit=settings.max_program_chars)


def exercise_spec(exercise: Exercise, skip_blocks: bool | None) -> dict[str, Any]:
    """How to run a program for `exercise`: its whole document when the grader can read it, else its tools."""
    spec: dict[str, Any] = {"skip_blocks": skip_blocks, "stock": exercise.stock}
    if exercise.document is not None:
        spec.update(exercise=exercise.document, exercise_key=f"{exercise.id}:{exercise.updated_at.isoformat()}")
    elif exercise.tools:
        spec.update(tools=exercise.tools, replace_tools=True)
    return spec


def run_spec(db: Session, settings: Settings, req: ProgramRequest) -> dict[str, Any]:
    """The worker's set-up for a check/run/simulate request (validated: dialect, size, exercise)."""
    check_program(settings, req.program, req.dialect)
    if req.exercise is not None:
        exercise = repo.exercise_by_slug(db, req.exercise)
        if exercise is None:
            raise ApiError("EXERCISE_NOT_FOUND", exercise=req.exercise)
        spec = exercise_spec(exercise, req.skip_blocks)
    else:
        spec = {"skip_blocks": req.skip_blocks}
    if req.tools:
        spec["tools"] = [*(spec.get("tools") or []), *(t.model_dump() for t in req.tools)]
    return spec


DEFAULT_STOCK = {"min": [0.0, 0.0, -30.0], "max": [80.0, 70.0, 0.0]}


def simulate_spec(db: Session, settings: Settings, req: SimulateRequest) -> dict[str, Any]:
    """The worker's set-up for a simulation: the run's, plus a checked stock box and the resolution."""
    spec = run_spec(db, settings, req)
    stock = req.stock.model_dump() if req.stock is not None else spec.get("stock") or DEFAULT_STOCK
    try:
        lo, hi = [float(v) for v in stock["min"]], [float(v) for v in stock["max"]]
        ok = len(lo) == len(hi) == 3 and all(abs(v) <= 100_000 for v in lo + hi) and all(
            b > a for a, b in zip(lo, hi, strict=True))
    except (KeyError, TypeError, ValueError):
        ok = False
    if not ok:
        raise ApiError("BAD_STOCK")
    spec.update(stock={"min": lo, "max": hi}, resolution=req.resolution)
    return spec


# --- accounts -------------------------------------------------------------------------------


def login(db: Session, username: str, password: str) -> User:
    user = repo.user_by_name(db, username)
    if not verify_password(password, user.password_hash if user else None) or user is None:
        raise ApiError("BAD_CREDENTIALS", headers={"WWW-Authenticate": "Bearer"})
    return user


def create_user(db: Session, username: str, password: str, role: str) -> User:
    if repo.user_by_name(db, username) is not None:
        raise ApiError("USER_EXISTS", user=username)
    try:
        return repo.create_user(db, username, hash_password(password), role)
    except repo.Duplicate:
        raise ApiError("USER_EXISTS", user=username) from None


def user_out(user: User) -> UserOut:
    return UserOut(id=user.id, username=user.username, role=user.role,  # type: ignore[arg-type]
                   created_at=user.created_at)


def create_api_key(db: Session, name: str, scopes: list[str], owner: User | None) -> tuple[ApiKey, str]:
    key, prefix, key_hash = new_api_key()
    record = repo.create_api_key(db, name, prefix, key_hash, sorted(set(scopes)), owner.id if owner else None)
    return record, key


def api_key_out(db: Session, key: ApiKey) -> ApiKeyOut:
    owner = repo.user_by_id(db, key.owner_id) if key.owner_id is not None else None
    return ApiKeyOut(id=key.id, name=key.name, prefix=key.prefix, scopes=key.scopes,  # type: ignore[arg-type]
                     owner=owner.username if owner else None, created_at=key.created_at,
                     last_used_at=key.last_used_at, revoked_at=key.revoked_at)


def api_key_created(db: Session, key: ApiKey, secret: str) -> ApiKeyCreated:
    return ApiKeyCreated(**api_key_out(db, key).model_dump(), key=secret)


def visible_api_keys(db: Session, principal: Principal) -> list[ApiKeyOut]:
    owner = None if principal.is_admin() else principal.user_id
    return [api_key_out(db, k) for k in repo.list_api_keys(db, owner)]


def revoke_api_key(db: Session, principal: Principal, key_id: int) -> ApiKeyOut:
    key = repo.api_key_by_id(db, key_id)
    if key is None or not (principal.is_admin() or (key.owner_id is not None and key.owner_id == principal.user_id)):
        raise ApiError("API_KEY_NOT_FOUND", key=key_id)
    repo.revoke_api_key(db, key)
    return api_key_out(db, key)


# --- exercises ------------------------------------------------------------------------------


def can_manage(principal: Principal, exercise: Exercise) -> bool:
    """Admins manage every exercise; instructors their own (keys: only with scope exercises:write)."""
    if not principal.has_scope("exercises:write") or principal.user is None:
        return False
    if principal.user.role == "admin":
        return True
    return principal.user.role == "instructor" and exercise.owner_id == principal.user.id


def exercise_out(db: Session, exercise: Exercise, principal: Principal) -> ExerciseOut:
    owner = repo.user_by_id(db, exercise.owner_id) if exercise.owner_id is not None else None
    full = can_manage(principal, exercise)
    rubric = exercise.rubric
    if not full and isinstance(rubric, dict) and isinstance(rubric.get("criteria"), list):
        rubric = {**rubric, "criteria": [c for c in rubric["criteria"] if not (isinstance(c, dict) and c.get("hidden"))]}
    return ExerciseOut(
        slug=exercise.slug, title_de=exercise.title_de, title_en=exercise.title_en, task_de=exercise.task_de,
        task_en=exercise.task_en, dialect=exercise.dialect, stock=exercise.stock,
        tools=exercise.tools, rubric=rubric, gradable=exercise.document is not None,
        owner=owner.username if owner else None, builtin=exercise.builtin, created_at=exercise.created_at,
        updated_at=exercise.updated_at, reference_program=exercise.reference_program if full else None,
        hidden_criteria=exercise.hidden_criteria if full else None,
        **_document_view(exercise.document),
    )


def _document_view(document: dict[str, Any] | None) -> dict[str, Any]:
    """What the exercise page shows from the grader's document: kind, start program, cutting data."""
    if not document:
        return {}
    return {"kind": document.get("kind", "write"), "start_program": document.get("start_program", ""),
            "locked_lines": document.get("locked_lines", []), "cutting_data": document.get("cutting_data", [])}


async def exercise_picture(db: Session, workers: Workers, slug: str) -> bytes:
    """A top view of the finished part (the reference machined on the stock), darker where deeper."""
    exercise = get_exercise(db, slug)
    if exercise.document is None:
        raise ApiError("NOT_FOUND")
    picture: bytes = await workers.call(job_picture, exercise.document)
    return picture


async def exercise_drawing(db: Session, workers: Workers, slug: str, lang: str) -> str:
    """The dimensioned drawing of the exercise's part (SVG, core/drawing)."""
    exercise = get_exercise(db, slug)
    if exercise.document is None:
        raise ApiError("NOT_FOUND")
    svg: str = await workers.call(job_drawing, exercise.document, lang)
    return svg


def get_exercise(db: Session, slug: str) -> Exercise:
    exercise = repo.exercise_by_slug(db, slug)
    if exercise is None:
        raise ApiError("EXERCISE_NOT_FOUND", exercise=slug)
    return exercise


def require_instructor(principal: Principal) -> None:
    if not principal.has_scope("exercises:write"):
        raise ApiError("MISSING_SCOPE", scope="exercises:write")
    if not principal.is_instructor():
        raise ApiError("FORBIDDEN")


def create_exercise(db: Session, settings: Settings, principal: Principal, body: ExerciseCreate) -> Exercise:
    require_instructor(principal)
    check_program(settings, body.reference_program, body.dialect)
    if repo.exercise_by_slug(db, body.slug) is not None:
        raise ApiError("EXERCISE_EXISTS", exercise=body.slug)
    fields = body.model_dump(mode="json")
    try:
        return repo.create_exercise(db, {**fields, "document": document_from_fields(fields)}, principal.user_id)
    except repo.Duplicate:
        raise ApiError("EXERCISE_EXISTS", exercise=body.slug) from None


async def import_exercise(db: Session, settings: Settings, workers: Workers, principal: Principal,
                          text: str) -> Exercise:
    """An instructor's exercise file (YAML or JSON, docs/exercises.md), validated: the file itself, and its
    reference must score full marks."""
    require_instructor(principal)
    if len(text) > settings.max_program_chars * 2:
        raise ApiError("PROGRAM_TOO_LARGE", size=len(text), limit=settings.max_program_chars * 2)
    checked = await workers.call(job_validate_exercise, text)
    if "invalid" in checked:
        raise ApiError("EXERCISE_INVALID", detail=checked["invalid"])
    if "reference" in checked:
        ref = checked["reference"]
        raise ApiError("REFERENCE_NOT_CLEAN", score=ref["score"], max_score=ref["max_score"], detail=ref["detail"],
                       detail_en=ref["detail_en"])
    document = ExerciseDocument.model_validate(checked["document"])
    if repo.exercise_by_slug(db, document.id) is not None:
        raise ApiError("EXERCISE_EXISTS", exercise=document.id)
    try:
        return repo.create_exercise(db, exercise_fields(document), principal.user_id)
    except repo.Duplicate:
        raise ApiError("EXERCISE_EXISTS", exercise=document.id) from None


EXERCISE_FIELDS = ("slug", "title_de", "title_en", "task_de", "task_en", "dialect", "stock", "tools",
                   "reference_program", "rubric", "hidden_criteria")


NULLABLE_EXERCISE_FIELDS = ("stock", "tools", "rubric", "hidden_criteria")


def update_exercise(db: Session, settings: Settings, principal: Principal, slug: str,
                    body: ExerciseUpdate) -> Exercise:
    require_instructor(principal)
    exercise = get_exercise(db, slug)
    if not can_manage(principal, exercise):
        raise ApiError("FORBIDDEN")
    fields = {k: v for k, v in body.model_dump(mode="json", exclude_unset=True).items()
              if v is not None or k in NULLABLE_EXERCISE_FIELDS}
    check_program(settings, fields.get("reference_program", ""), fields.get("dialect") or exercise.dialect)
    merged = {**{name: getattr(exercise, name) for name in EXERCISE_FIELDS}, **fields}
    return repo.update_exercise(db, exercise, {**fields, "document": document_from_fields(merged, exercise.document)})


def delete_exercise(db: Session, principal: Principal, slug: str) -> None:
    require_instructor(principal)
    exercise = get_exercise(db, slug)
    if not can_manage(principal, exercise):
        raise ApiError("FORBIDDEN")
    if repo.exercise_has_submissions(db, exercise):
        raise ApiError("EXERCISE_HAS_SUBMISSIONS", exercise=slug)
    repo.delete_exercise(db, exercise)


# --- submissions ----------------------------------------------------------------------------


def grading_view(grading: dict[str, Any] | None, full: bool) -> dict[str, Any] | None:
    """The grade as its reader may see it: without hidden criteria unless they manage the exercise."""
    if grading is None or full:
        return grading
    return {**grading, "criteria": [c for c in grading.get("criteria", []) if not c.get("hidden")]}


def submission_out(submission: Submission, exercise: Exercise, author: User | None, detail: bool,
                   principal: Principal) -> SubmissionOut:
    result = submission.result
    grading = grading_view(submission.grading, can_manage(principal, exercise))
    return SubmissionOut(
        id=submission.id, exercise=exercise.slug, user=author.username if author else None,
        external_user=submission.external_user, dialect=submission.dialect, created_at=submission.created_at,
        error_count=submission.error_count, warning_count=submission.warning_count, grading=grading,
        score=grading["score"] if grading else None,
        summary=result["summary"], diagnostics=result["diagnostics"] if detail else None,
        program=submission.program if detail else None, lms=lms_result(grading),
    )


def lms_result(grading: dict[str, Any] | None) -> LmsResult | None:
    """The grade as a learning platform takes it; the comment names what lost points (as the reader may see it)."""
    if grading is None:
        return None
    lost = [c for c in grading.get("criteria", []) if c.get("status") != "passed"]
    if lost:
        comment = " ".join(f"{c['message']} (−{c['max_points'] - c['points']})" for c in lost)
        comment_en = " ".join(f"{c['message_en']} (−{c['max_points'] - c['points']})" for c in lost)
    else:
        comment, comment_en = "Alle Kriterien erfüllt.", "All criteria met."
    return LmsResult(score=int(grading["score"]), maximum=int(grading["max_score"]), comment=comment,
                     comment_en=comment_en)


async def create_submission(db: Session, settings: Settings, workers: Workers, principal: Principal,
                            body: SubmissionCreate, idempotency_key: str | None = None) -> tuple[SubmissionOut, bool]:
    """Grade and store a submission; with an idempotency key already used by the same caller, the stored one
    (and False: nothing new was made)."""
    if not principal.has_scope("submissions:write"):
        raise ApiError("MISSING_SCOPE", scope="submissions:write")
    if body.external_user is not None and principal.api_key is not None and not may_name_learners(principal):
        raise ApiError("EXTERNAL_USER_FORBIDDEN")
    stored_key = None
    if idempotency_key:
        who = f"k{principal.api_key.id}" if principal.api_key else f"u{principal.user_id}"
        stored_key = f"{who}:{idempotency_key}"
        earlier = _earlier_submission(db, principal, stored_key, body)
        if earlier is not None:
            return earlier, False
    exercise = get_exercise(db, body.exercise)
    check_program(settings, body.program, exercise.dialect)
    result = await workers.call(job_submission, body.program, exercise.dialect,
                                exercise_spec(exercise, body.skip_blocks))
    try:
        submission = repo.create_submission(
            db, exercise_id=exercise.id, user_id=principal.user_id,
            api_key_id=principal.api_key.id if principal.api_key else None,
            external_user=body.external_user if principal.api_key else None, program=body.program,
            dialect=exercise.dialect, error_count=result["errors"], warning_count=result["warnings"],
            result={"diagnostics": result["diagnostics"], "summary": result["summary"]}, grading=result["grading"],
            idempotency_key=stored_key,
        )
    except repo.Duplicate:
        # a retry with the same key was stored while this one was graded: answer with that one
        earlier = _earlier_submission(db, principal, stored_key, body) if stored_key else None
        if earlier is None:
            raise ApiError("CONFLICT") from None
        return earlier, False
    return submission_out(submission, exercise, principal.user, True, principal), True


def may_name_learners(principal: Principal) -> bool:
    """Who may submit for a learner of a learning platform (external_user): the operator's keys (no owner) and
    keys of instructors and admins; a student's key would let a student submit in anyone's name."""
    if principal.api_key is None:
        return False
    return principal.api_key.owner_id is None or principal.is_instructor()


def _earlier_submission(db: Session, principal: Principal, stored_key: str,
                        body: SubmissionCreate) -> SubmissionOut | None:
    """The submission stored under this caller's idempotency key, if the request is the same; else a conflict."""
    earlier = repo.submission_by_idempotency_key(db, stored_key)
    if earlier is None:
        return None
    exercise = repo.exercise_by_id(db, earlier.exercise_id)
    if exercise is None or exercise.slug != body.exercise or earlier.program != body.program:
        raise ApiError("IDEMPOTENCY_CONFLICT")
    return submission_out(earlier, exercise, principal.user, True, principal)


def visible_submissions(db: Session, principal: Principal,
                        exercise: str | None) -> list[tuple[Submission, Exercise, User | None]]:
    """Students: their own; instructors: their own and those to their exercises; admins: all;
    API keys: those made through the key plus what their owner may see."""
    if not principal.has_scope("submissions:read"):
        raise ApiError("MISSING_SCOPE", scope="submissions:read")
    if exercise is not None:
        get_exercise(db, exercise)
    admin = principal.user is not None and principal.user.role == "admin"
    return list(repo.list_submissions(
        db, user_id=principal.user_id, owner_id=principal.user_id if principal.is_instructor() else None,
        api_key_id=principal.api_key.id if principal.api_key else None, exercise_slug=exercise,
        everything=admin))


def may_see(principal: Principal, submission: Submission, exercise: Exercise) -> bool:
    if principal.user is not None and principal.user.role == "admin":
        return True
    if principal.user_id is not None and submission.user_id == principal.user_id:
        return True
    if principal.is_instructor() and exercise.owner_id == principal.user_id:
        return True
    return principal.api_key is not None and submission.api_key_id == principal.api_key.id


def get_submission(db: Session, principal: Principal, submission_id: int) -> SubmissionOut:
    """Someone else's submission is 404, as if it did not exist."""
    if not principal.has_scope("submissions:read"):
        raise ApiError("MISSING_SCOPE", scope="submissions:read")
    submission = repo.submission_by_id(db, submission_id)
    exercise = repo.exercise_by_id(db, submission.exercise_id) if submission else None
    if submission is None or exercise is None or not may_see(principal, submission, exercise):
        raise ApiError("SUBMISSION_NOT_FOUND", submission=submission_id)
    author = repo.user_by_id(db, submission.user_id) if submission.user_id is not None else None
    return submission_out(submission, exercise, author, True, principal)


CSV_COLUMNS = ("id", "exercise", "user", "external_user", "created_at", "error_count", "warning_count",
               "moves", "score", "max_score")


def submissions_csv(db: Session, principal: Principal, exercise: str | None) -> str:
    if not principal.is_instructor():
        raise ApiError("FORBIDDEN")
    return csv_text(CSV_COLUMNS, (
        [s.id, e.slug, u.username if u else "", s.external_user or "", utc(s.created_at).isoformat(),
         s.error_count, s.warning_count, s.result["summary"]["moves"],
         s.grading["score"] if s.grading else "", s.grading["max_score"] if s.grading else ""]
        for s, e, u in visible_submissions(db, principal, exercise)))
