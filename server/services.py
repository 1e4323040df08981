"""What the routes do, one function per use case: rules (who may see what), limits, calls to repository and workers."""

from __future__ import annotations

import asyncio
import csv
import hashlib
import json
import re
import secrets
from dataclasses import dataclass
from typing import Any

import yaml  # type: ignore[import-untyped, unused-ignore]
from pydantic import ValidationError
from sqlalchemy.orm import Session
from starlette.concurrency import run_in_threadpool

from core.exercises import Exercise as ExerciseDocument
from core.exercises import field_problem
from core.pipeline import DIALECTS
from core.sheet import SheetUnavailable, pdf_engine
from server import access, drawings
from server import repository as repo
from server.config import Settings
from server.deps import Principal
from server.errors import ApiError
from server.export import excel_cell, excel_csv
from server.jobs import (
    job_drawing,
    job_merge_pdfs,
    job_picture,
    job_sheet,
    job_submission,
    job_validate_exercise,
)
from server.lti import ags as lti_ags
from server.models import ApiKey, Exercise, Submission, User, now
from server.schemas import (
    LTI_NAME_DE,
    LTI_NAME_EN,
    ApiKeyCreated,
    ApiKeyOut,
    DraftOut,
    ExerciseCreate,
    ExerciseOut,
    ExerciseUpdate,
    Hint,
    ImportedUser,
    ImportedUsers,
    LmsResult,
    MySubmission,
    OverrideIn,
    OverrideOut,
    ProgramRequest,
    Progress,
    ResultCell,
    ResultExercise,
    ResultRow,
    Results,
    SimulateRequest,
    Solution,
    SubmissionCreate,
    SubmissionOut,
    UserCreate,
    UserOut,
    lti_reserved,
    utc,
)
from server.security import hash_password, new_api_key, password_problem, verify_password
from server.seed import document_from_fields, exercise_fields
from server.tasktext import task_view
from server.workers import Workers, content_key

VERSION_NOTE = ("Version {v}", "version {v}")

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
        spec.update(
            exercise=exercise.document, exercise_key=f"{exercise.id}:{exercise.updated_at.isoformat()}"
        )
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
        ok = (
            len(lo) == len(hi) == 3
            and all(abs(v) <= 100_000 for v in lo + hi)
            and all(b > a for a, b in zip(lo, hi, strict=True))
        )
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


def create_user(db: Session, username: str, password: str, role: str, instructor: User | None = None) -> User:
    if repo.user_by_name(db, username) is not None:
        raise ApiError("USER_EXISTS", user=username)
    try:
        return repo.create_user(
            db, username, hash_password(password), role, instructor.id if instructor else None
        )
    except repo.Duplicate:
        raise ApiError("USER_EXISTS", user=username) from None


def user_out(user: User, instructor: str | None = None) -> UserOut:
    return UserOut(
        id=user.id,
        username=user.username,
        role=user.role,  # type: ignore[arg-type]
        created_at=user.created_at,
        instructor=instructor,
        active=user.deactivated_at is None,
        must_change_password=user.must_change_password,
        signed_up_to=user.signup_course_id,
    )


def create_api_key(db: Session, name: str, scopes: list[str], owner: User | None) -> tuple[ApiKey, str]:
    key, prefix, key_hash = new_api_key()
    record = repo.create_api_key(db, name, prefix, key_hash, sorted(set(scopes)), owner.id if owner else None)
    return record, key


def api_key_out(db: Session, key: ApiKey) -> ApiKeyOut:
    owner = repo.user_by_id(db, key.owner_id) if key.owner_id is not None else None
    return ApiKeyOut(
        id=key.id,
        name=key.name,
        prefix=key.prefix,
        scopes=key.scopes,  # type: ignore[arg-type]
        owner=owner.username if owner else None,
        created_at=key.created_at,
        last_used_at=key.last_used_at,
        revoked_at=key.revoked_at,
    )


def api_key_created(db: Session, key: ApiKey, secret: str) -> ApiKeyCreated:
    return ApiKeyCreated(**api_key_out(db, key).model_dump(), key=secret)


def visible_api_keys(db: Session, principal: Principal) -> list[ApiKeyOut]:
    owner = None if principal.is_admin() else principal.user_id
    return [api_key_out(db, k) for k in repo.list_api_keys(db, owner)]


def revoke_api_key(db: Session, principal: Principal, key_id: int) -> ApiKeyOut:
    key = repo.api_key_by_id(db, key_id)
    if key is None or not (
        principal.is_admin() or (key.owner_id is not None and key.owner_id == principal.user_id)
    ):
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


def exercise_out(
    db: Session,
    exercise: Exercise,
    principal: Principal,
    sit: access.Situation | None = None,
    own_drawing: str | None | bool = True,
) -> ExerciseOut:
    """The exercise as `principal` may see it (`sit`: their situation, when the caller has it already;
    `own_drawing`: the media type of its own drawing when the caller read it, True: read it here)."""
    owner = repo.user_by_id(db, exercise.owner_id) if exercise.owner_id is not None else None
    full = can_manage(principal, exercise)
    if full:  # not while an exam of a course they sit as a student withholds it
        sit = sit or access.situation(db, access.acting_user(principal), exercise.slug)
        full = access.allowed(sit, "reference", exercise.slug)
    rubric = exercise.rubric
    if not full and isinstance(rubric, dict) and isinstance(rubric.get("criteria"), list):
        rubric = {
            **rubric,
            "criteria": [c for c in rubric["criteria"] if not (isinstance(c, dict) and c.get("hidden"))],
        }
    return ExerciseOut(
        slug=exercise.slug,
        title_de=exercise.title_de,
        title_en=exercise.title_en,
        task_de=exercise.task_de,
        task_en=exercise.task_en,
        dialect=exercise.dialect,
        stock=exercise.stock,
        tools=exercise.tools,
        rubric=rubric,
        gradable=exercise.document is not None,
        owner=owner.username if owner else None,
        builtin=exercise.builtin,
        created_at=exercise.created_at,
        updated_at=exercise.updated_at,
        reference_program=exercise.reference_program if full else None,
        hidden_criteria=exercise.hidden_criteria if full else None,
        visibility=exercise.visibility,
        version=exercise.version,
        archived=exercise.archived_at is not None,
        own_drawing=own_drawing if not isinstance(own_drawing, bool) else _own_drawing_type(db, exercise),
        document=exercise.document if full else None,
        **_document_view(exercise.document),
        **_list_view(exercise),
        **task_view(exercise),
    )


def _own_drawing_type(db: Session, exercise: Exercise) -> str | None:
    found = repo.own_drawings(db, [exercise.id]).get(exercise.id)
    return found[0] if found else None


def exercise_seen(
    db: Session, principal: Principal, slug: str, sit: access.Situation | None = None
) -> Exercise:
    """The exercise `slug` if the caller sees it (server/access.py, rules 6–9); EXERCISE_NOT_FOUND alike for names
    that do not exist."""
    exercise = get_exercise(db, slug)
    access.require_seen(sit or access.situation(db, access.acting_user(principal), slug), slug)
    return exercise


def visible_exercises(
    db: Session, principal: Principal, mine: bool = False, archived: bool = False
) -> list[ExerciseOut]:
    """The list: what the caller sees (not archived ones unless `archived`); `mine`: only those they manage
    (instructors: their own; admins: every exercise not built in)."""
    user = access.acting_user(principal)
    sit = access.situation(db, user)  # one for every exercise: the user's courses
    shown = [e for e in sorted_exercises(db) if sit.sees(e.slug) and (archived or e.archived_at is None)]
    if mine:
        shown = [e for e in shown if can_manage(principal, e) and not e.builtin]
    drawn = repo.own_drawings(db, [e.id for e in shown])
    return [exercise_out(db, e, principal, sit, drawn[e.id][0] if e.id in drawn else None) for e in shown]


def _document_view(document: dict[str, Any] | None) -> dict[str, Any]:
    """What the exercise page shows from the grader's document: kind, start program, cutting data."""
    if not document:
        return {}
    return {
        "kind": document.get("kind", "write"),
        "start_program": document.get("start_program", ""),
        "locked_lines": document.get("locked_lines", []),
        "cutting_data": document.get("cutting_data", []),
    }


async def exercise_picture(db: Session, workers: Workers, principal: Principal, slug: str) -> bytes:
    """A top view of the finished part (the reference machined on the stock), darker where deeper; made once per
    content of the exercise (Workers.cached)."""

    def read() -> tuple[dict[str, Any], str]:  # in the threadpool: no query on the event loop
        exercise = exercise_seen(db, principal, slug)
        if exercise.document is None:
            raise ApiError("NOT_FOUND")
        db.commit()  # the pooled connection goes back before the wait for a worker
        return exercise.document, content_key("picture", exercise.document)

    document, key = await run_in_threadpool(read)
    picture: bytes = await workers.cached(key, job_picture, document)
    return picture


async def exercise_drawing(db: Session, workers: Workers, principal: Principal, slug: str, lang: str) -> str:
    """The dimensioned drawing of the exercise's part (SVG, core/drawing); made once per content and language.
    An author's own drawing instead, where there is one (server/drawings.py)."""

    def read() -> tuple[dict[str, Any], str, str | None]:  # in the threadpool: no query on the event loop
        exercise = exercise_seen(db, principal, slug)
        own = repo.exercise_drawing(db, exercise.id)
        if own is not None:
            svg = drawings.as_svg(own.media_type, own.data, lang)
            db.commit()
            return {}, "", svg
        if exercise.document is None:
            raise ApiError("NOT_FOUND")
        db.commit()  # the pooled connection goes back before the wait for a worker
        return exercise.document, content_key("drawing", exercise.document, lang), None

    document, key, own_svg = await run_in_threadpool(read)
    if own_svg is not None:
        return own_svg
    svg: str = await workers.cached(key, job_drawing, document, lang)
    return svg


def own_drawing(db: Session, principal: Principal, slug: str) -> drawings.Drawing:
    """The author's own drawing of an exercise as uploaded (for a PDF: what the page links to)."""
    exercise = exercise_seen(db, principal, slug)
    row = repo.exercise_drawing(db, exercise.id)
    if row is None:
        raise ApiError("NOT_FOUND")
    return drawings.Drawing(row.media_type, row.filename, row.data)


def set_own_drawing(db: Session, principal: Principal, slug: str, data: bytes, filename: str) -> ExerciseOut:
    """Upload (or replace) the exercise's own drawing: checked by its bytes (server/drawings.py)."""
    exercise = _managed(db, principal, slug)
    drawing = drawings.checked(data, filename)
    repo.set_exercise_drawing(db, exercise, drawing.media_type, drawing.filename, drawing.data)
    return exercise_out(db, exercise, principal, own_drawing=drawing.media_type)


def remove_own_drawing(db: Session, principal: Principal, slug: str) -> None:
    """Back to the drawing generated from the reference."""
    exercise = _managed(db, principal, slug)
    if not repo.delete_exercise_drawing(db, exercise):
        raise ApiError("NOT_FOUND")


async def drawing_preview(workers: Workers, document: dict[str, Any], lang: str) -> str:
    """The drawing of an exercise as the editor holds it, not saved (reference, dialect, blank, tools …): what is
    missing is filled in (id, title, task); EXERCISE_INVALID with every error at once where it cannot be drawn."""
    data = {"id": "vorschau", "title": {"de": "Vorschau"}, "task": {"de": ""}, **document}
    if not isinstance(data.get("title"), dict) or not str(data["title"].get("de") or "").strip():
        data["title"] = {"de": "Vorschau"}
    try:
        checked = await run_in_threadpool(
            lambda: ExerciseDocument.model_validate(data).model_dump(mode="json")
        )
    except ValidationError as err:
        problems = [field_problem(e) for e in err.errors()]
        raise ApiError(
            "EXERCISE_INVALID",
            detail="; ".join(f"{p['field']}: {p['message']}" for p in problems),
            detail_en="; ".join(f"{p['field']}: {p['message_en']}" for p in problems),
            errors=problems,
        ) from None
    svg: str = await workers.cached(content_key("drawing", checked, lang), job_drawing, checked, lang)
    return svg


async def task_sheet(
    workers: Workers,
    documents: list[dict[str, Any]],
    lang: str,
    own: list[tuple[str, bytes] | None] | None = None,
) -> bytes:
    """Exercises as a printed task sheet (PDF, core/sheet): each exercise's pages are a worker job of their own,
    kept by content (the exercise's document and the language: an edited exercise is rendered again), and several
    are put together in one more job (kept as well) — no job grows with the number of exercises, and a class
    asking for the same sheets costs one rendering. 503 PDF_UNAVAILABLE where WeasyPrint cannot be loaded:
    checked here first (off the event loop: the first import takes a second), so that no worker is taken for it
    and the rest of the server is unaffected. The caller holds no pooled database connection."""
    try:
        await asyncio.to_thread(pdf_engine)
        drawn = own or [None] * len(documents)  # the authors' own drawings (media type, bytes), if any
        keys = await run_in_threadpool(
            lambda: [
                content_key("sheet", d, lang, o[0], hashlib.sha256(o[1]).hexdigest())
                if o
                else content_key("sheet", d, lang)
                for d, o in zip(documents, drawn, strict=True)
            ]
        )
        parts: list[bytes] = []
        for document, key, drawing in zip(
            documents, keys, drawn, strict=True
        ):  # one job at a time per request
            parts.append(await workers.cached(key, job_sheet, document, lang, drawing))
        if len(parts) == 1:
            return parts[0]
        pdf: bytes = await workers.cached(content_key("sheets", keys), job_merge_pdfs, parts)
    except SheetUnavailable as err:
        raise ApiError("PDF_UNAVAILABLE", detail=err.message, detail_en=err.message_en) from None
    return pdf


async def exercise_sheet(db: Session, workers: Workers, principal: Principal, slug: str, lang: str) -> bytes:
    """The exercise's printed task sheet with its empty programming form (PDF)."""

    def read() -> tuple[
        dict[str, Any], tuple[str, bytes] | None
    ]:  # in the threadpool: no query on the event loop
        exercise = exercise_seen(db, principal, slug)
        if exercise.document is None:
            raise ApiError("NOT_FOUND")
        row = repo.exercise_drawing(db, exercise.id)
        db.commit()  # the pooled connection goes back before the wait for a worker
        return exercise.document, (row.media_type, row.data) if row is not None else None

    document, drawing = await run_in_threadpool(read)
    return await task_sheet(workers, [document], lang, [drawing])


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
    """An exercise from fields (the document path is `save_document`)."""
    require_instructor(principal)
    check_program(settings, body.reference_program, body.dialect)
    if repo.exercise_by_slug(db, body.slug) is not None:
        raise ApiError("EXERCISE_EXISTS", exercise=body.slug)
    fields = body.model_dump(mode="json", exclude={"document"})
    try:
        return repo.create_exercise(
            db, {**fields, "document": document_from_fields(fields)}, principal.user_id
        )
    except repo.Duplicate:
        raise ApiError("EXERCISE_EXISTS", exercise=body.slug) from None


def _invalid(problems: list[dict[str, str]]) -> ApiError:
    return ApiError(
        "EXERCISE_INVALID",
        detail="; ".join(f"Feld `{p['field']}`: {p['message']}" for p in problems),
        detail_en="; ".join(f"field `{p['field']}`: {p['message_en']}" for p in problems),
        errors=problems,
    )


async def checked_document(settings: Settings, workers: Workers, text: str, graded: bool) -> ExerciseDocument:
    """An exercise file or the editor's document (YAML or JSON, docs/exercises.md) validated with every error at
    once (EXERCISE_INVALID, details.errors: {field, message, message_en}); `graded`: its reference must also score
    full marks (REFERENCE_NOT_CLEAN, also as an error of the field `reference`)."""
    if len(text) > settings.max_program_chars * 2:
        raise ApiError("PROGRAM_TOO_LARGE", size=len(text), limit=settings.max_program_chars * 2)
    checked = await workers.call(job_validate_exercise, text, graded)
    if "invalid" in checked:
        problems = checked.get("problems") or [
            {"field": "(Aufgabe)", "message": checked["invalid"], "message_en": checked.get("invalid_en", "")}
        ]
        raise ApiError(
            "EXERCISE_INVALID",
            detail=checked["invalid"],
            detail_en=checked.get("invalid_en", ""),
            errors=problems,
        )
    if "reference" in checked:
        ref = checked["reference"]
        error = ApiError(
            "REFERENCE_NOT_CLEAN",
            score=ref["score"],
            max_score=ref["max_score"],
            detail=ref["detail"],
            detail_en=ref["detail_en"],
        )
        raise ApiError(
            "REFERENCE_NOT_CLEAN",
            score=ref["score"],
            max_score=ref["max_score"],
            detail=ref["detail"],
            detail_en=ref["detail_en"],
            errors=[{"field": "reference", "message": error.message, "message_en": error.message_en}],
        )
    return ExerciseDocument.model_validate(checked["document"])


async def import_exercise(
    db: Session,
    settings: Settings,
    workers: Workers,
    principal: Principal,
    text: str,
    visibility: str = "public",
) -> Exercise:
    """An instructor's exercise file (YAML or JSON, docs/exercises.md), validated: the file itself, and its
    reference must score full marks."""
    require_instructor(principal)
    document = await checked_document(settings, workers, text, True)
    return await run_in_threadpool(_store_exercise, db, document, principal.user_id, visibility)


async def create_from_document(
    db: Session, settings: Settings, workers: Workers, principal: Principal, body: ExerciseCreate
) -> Exercise:
    """The editor's "Speichern" of a new exercise: its document validated (every error at once); a published one
    (visibility courses or public) also with a reference that scores full marks."""
    require_instructor(principal)
    text = json.dumps(body.document, ensure_ascii=False)
    document = await checked_document(settings, workers, text, body.visibility != "draft")
    return await run_in_threadpool(_store_exercise, db, document, principal.user_id, body.visibility)


def _store_exercise(
    db: Session, document: ExerciseDocument, owner_id: int | None, visibility: str = "public"
) -> Exercise:
    if repo.exercise_by_slug(db, document.id) is not None:
        raise ApiError(
            "EXERCISE_EXISTS",
            exercise=document.id,
            errors=[
                {
                    "field": "id",
                    "message": f"die Kennung »{document.id}« gibt es schon",
                    "message_en": f"the slug '{document.id}' exists already",
                }
            ],
        )
    try:
        return repo.create_exercise(db, {**exercise_fields(document), "visibility": visibility}, owner_id)
    except repo.Duplicate:
        raise ApiError("EXERCISE_EXISTS", exercise=document.id) from None


EXERCISE_FIELDS = (
    "slug",
    "title_de",
    "title_en",
    "task_de",
    "task_en",
    "dialect",
    "stock",
    "tools",
    "reference_program",
    "rubric",
    "hidden_criteria",
)
CONTENT_FIELDS = (
    *EXERCISE_FIELDS,
    "document",
)  # what an edit changes: a published exercise gets a new version


NULLABLE_EXERCISE_FIELDS = ("stock", "tools", "rubric", "hidden_criteria")


def _managed(db: Session, principal: Principal, slug: str) -> Exercise:
    """An exercise the caller manages (its author, admins); FORBIDDEN for one they only see."""
    require_instructor(principal)
    exercise = exercise_seen(db, principal, slug)
    if not can_manage(principal, exercise):
        raise ApiError("FORBIDDEN")
    return exercise


def _apply(db: Session, principal: Principal, exercise: Exercise, fields: dict[str, Any]) -> Exercise:
    """Store an edit. One that changes the content of a published exercise (not a draft) keeps the document as it
    was (ExerciseVersion) and raises the version: submissions name the version they were graded against."""
    changed = any(k in fields and fields[k] != getattr(exercise, k) for k in CONTENT_FIELDS)
    if changed and exercise.visibility != "draft":
        repo.add_exercise_version(db, exercise, principal.user_id)
        fields = {**fields, "version": exercise.version + 1}
    return repo.update_exercise(db, exercise, fields)


def _state_fields(body: ExerciseUpdate) -> dict[str, Any]:
    fields: dict[str, Any] = {}
    if body.visibility is not None:
        fields["visibility"] = body.visibility
    if body.archived is not None:
        fields["archived_at"] = now() if body.archived else None
    return fields


def update_exercise(
    db: Session, settings: Settings, principal: Principal, slug: str, body: ExerciseUpdate
) -> Exercise:
    exercise = _managed(db, principal, slug)
    fields = {
        k: v
        for k, v in body.model_dump(
            mode="json", exclude_unset=True, exclude={"document", "visibility", "archived"}
        ).items()
        if v is not None or k in NULLABLE_EXERCISE_FIELDS
    }
    if fields:
        check_program(
            settings, fields.get("reference_program", ""), fields.get("dialect") or exercise.dialect
        )
        merged = {**{name: getattr(exercise, name) for name in EXERCISE_FIELDS}, **fields}
        fields["document"] = document_from_fields(merged, exercise.document)
    return _apply(db, principal, exercise, {**fields, **_state_fields(body)})


async def update_from_document(
    db: Session, settings: Settings, workers: Workers, principal: Principal, slug: str, body: ExerciseUpdate
) -> Exercise:
    """The editor's "Speichern" of an exercise: the whole document (its id stays the slug); validated with every
    error at once; published (or to be published) with a reference that scores full marks."""
    exercise = await run_in_threadpool(_managed, db, principal, slug)
    visibility = body.visibility or exercise.visibility
    db.commit()  # no pooled connection held while the worker checks
    text = json.dumps({**(body.document or {}), "id": slug}, ensure_ascii=False)
    document = await checked_document(settings, workers, text, visibility != "draft")
    fields = {k: v for k, v in exercise_fields(document).items() if k != "slug"}
    return await run_in_threadpool(
        lambda: _apply(db, principal, _managed(db, principal, slug), {**fields, **_state_fields(body)})
    )


async def publish_check(
    settings: Settings, workers: Workers, exercise: Exercise, body: ExerciseUpdate
) -> None:
    """Publishing (a draft made visible) needs a gradable exercise whose reference scores full marks."""
    if body.visibility in ("courses", "public") and exercise.visibility == "draft" and body.document is None:
        if exercise.document is None:
            raise _invalid(
                [
                    {
                        "field": "reference",
                        "message": "die Aufgabe ist nicht vollständig (bewertbar)",
                        "message_en": "the exercise is not complete (gradable)",
                    }
                ]
            )
        await checked_document(settings, workers, json.dumps(exercise.document, ensure_ascii=False), True)


def delete_exercise(db: Session, principal: Principal, slug: str) -> bool:
    """Delete an exercise; one with submissions is archived instead (hidden, its submissions kept). True: archived."""
    exercise = _managed(db, principal, slug)
    if exercise.builtin:
        raise ApiError("FORBIDDEN")
    if repo.exercise_has_submissions(db, exercise):
        repo.update_exercise(db, exercise, {"archived_at": exercise.archived_at or now()})
        return True
    repo.delete_exercise(db, exercise)
    return False


def _copy_slug(db: Session, slug: str) -> str:
    base = re.sub(r"-kopie(-\d+)?$", "", slug)[:68] + "-kopie"
    for n in range(1, 1000):
        candidate = base if n == 1 else f"{base}-{n}"
        if repo.exercise_by_slug(db, candidate) is None:
            return candidate
    return f"{base}-{secrets.token_hex(4)}"


def duplicate_exercise(db: Session, principal: Principal, slug: str) -> Exercise:
    """A copy of a built-in exercise or one's own (admins: any) as a new draft of the caller, with a new slug."""
    require_instructor(principal)
    source = exercise_seen(db, principal, slug)
    if not (source.builtin or can_manage(principal, source)):
        raise ApiError("EXERCISE_NOT_COPYABLE")
    if source.document is None:
        raise _invalid(
            [
                {
                    "field": "(Aufgabe)",
                    "message": "die Aufgabe ist nicht vollständig (bewertbar)",
                    "message_en": "the exercise is not complete (gradable)",
                }
            ]
        )
    new_slug = _copy_slug(db, slug)
    doc = dict(source.document)
    title = dict(doc.get("title") or {})
    title["de"] = f"{title.get('de', source.title_de)} (Kopie)"[:200]
    if title.get("en"):
        title["en"] = f"{title['en']} (copy)"[:200]
    doc.update(id=new_slug, title=title, order=None, source=f"Kopie von {slug}")
    document = ExerciseDocument.model_validate(doc)
    fields = {**exercise_fields(document), "visibility": "draft"}
    try:
        copy = repo.create_exercise(db, fields, principal.user_id)
    except repo.Duplicate:
        raise ApiError("CONFLICT") from None
    row = repo.exercise_drawing(db, source.id)
    if row is not None:
        repo.set_exercise_drawing(db, copy, row.media_type, row.filename, row.data)
    return copy


def export_exercise(db: Session, principal: Principal, slug: str) -> str:
    """The exercise as a file in the exercise format (YAML, docs/exercises.md): what `import` reads back."""
    exercise = _managed(db, principal, slug)
    if exercise.document is None:
        raise ApiError("NOT_FOUND")
    return str(yaml.safe_dump(exercise.document, allow_unicode=True, sort_keys=False, width=120))


# --- submissions ----------------------------------------------------------------------------


def grading_view(grading: dict[str, Any] | None, full: bool) -> dict[str, Any] | None:
    """The grade as its reader may see it: without hidden criteria unless they manage the exercise."""
    if grading is None or full:
        return grading
    return {**grading, "criteria": [c for c in grading.get("criteria", []) if not c.get("hidden")]}


class Readers:
    """The situations of submissions' authors, read once per author while a list is written."""

    def __init__(self, db: Session) -> None:
        self.db = db
        self.known: dict[int, access.Situation] = {}

    def of(self, author: User | None, submission: Submission, slug: str) -> access.Situation:
        if author is None or submission.external_user is not None:
            return access.situation(self.db, None, slug)
        if author.id not in self.known:
            self.known[author.id] = access.situation(self.db, author, slug)
        return self.known[author.id]


def submission_out(
    db: Session,
    submission: Submission,
    exercise: Exercise,
    author: User | None,
    detail: bool,
    principal: Principal,
    readers: Readers | None = None,
) -> SubmissionOut:
    """A submission as its reader may see it. Its author (or the key that made it) sees an exam's submission as
    handed in and nothing else until the results are released, and no score or criteria of a practice
    submission while the exercise is in an unreleased exam of their course (server/access.py); instructors see
    the whole grade of what they may see (their students' work on any exercise)."""
    result = submission.result
    own = (principal.user_id is not None and submission.user_id == principal.user_id) or (
        principal.api_key is not None and submission.api_key_id == principal.api_key.id
    )
    held = submission.held and own
    if own:
        sit = (readers or Readers(db)).of(author, submission, exercise.slug)
        visible = access.grade_visible(sit, submission, exercise.slug)
        full = can_manage(principal, exercise) and access.allowed(sit, "reference", exercise.slug)
    else:
        visible, full = True, can_manage(principal, exercise) or principal.is_instructor()
    grading = grading_view(submission.grading, full) if visible else None
    score = _score(submission)[0] if grading else None
    return SubmissionOut(
        id=submission.id,
        exercise=exercise.slug,
        user=author.username if author else None,
        exercise_title=exercise.title_de,
        exercise_title_en=exercise.title_en or "",
        external_user=submission.external_user,
        dialect=submission.dialect,
        created_at=submission.created_at,
        error_count=None if held else submission.error_count,
        warning_count=None if held else submission.warning_count,
        grading=grading,
        score=score,
        held=held,
        override=override_out(db, submission) if grading else None,
        summary=None if held else result["summary"],
        diagnostics=result["diagnostics"] if detail and not held else None,
        program=submission.program if detail else None,
        lms=lms_result(
            grading, score, submission.override_comment if submission.override_score is not None else None
        ),
        exercise_version=submission.exercise_version,
        version_note=version_note(submission.exercise_version, exercise.version),
    )


def version_note(graded: int | None, current: int) -> str:
    """ "Version 1" where a submission was graded against an earlier version of its exercise, else ""."""
    return VERSION_NOTE[0].format(v=graded) if graded is not None and graded != current else ""


def lms_result(
    grading: dict[str, Any] | None, score: int | None = None, teacher: str | None = None
) -> LmsResult | None:
    """The grade as a learning platform takes it — the score that counts (`score`: the teacher's, if set) — and a
    comment naming what lost points (as the reader may see it), the teacher's comment first."""
    if grading is None:
        return None
    lost = [c for c in grading.get("criteria", []) if c.get("status") != "passed"]
    if lost:
        comment = " ".join(f"{c['message']} (−{c['max_points'] - c['points']})" for c in lost)
        comment_en = " ".join(f"{c['message_en']} (−{c['max_points'] - c['points']})" for c in lost)
    else:
        comment, comment_en = "Alle Kriterien erfüllt.", "All criteria met."
    if teacher:
        comment, comment_en = f"{teacher} {comment}", f"{teacher} {comment_en}"
    return LmsResult(
        score=int(grading["score"]) if score is None else score,
        maximum=int(grading["max_score"]),
        comment=comment,
        comment_en=comment_en,
    )


@dataclass(frozen=True)
class _Pending:
    """A submission checked and ready for the worker to grade (what `_prepare_submission` found)."""

    exercise: Exercise
    verdict: access.Verdict
    stored_key: str | None
    external: str | None


async def create_submission(
    db: Session,
    settings: Settings,
    workers: Workers,
    principal: Principal,
    body: SubmissionCreate,
    idempotency_key: str | None = None,
) -> tuple[SubmissionOut, bool]:
    """Grade and store a submission; with an idempotency key already used by the same caller, the stored one
    (and False: nothing new was made). The database is read and written in the thread pool, never on the event
    loop, and no connection is held while the worker grades (many submissions waiting at once must not take
    every pooled connection)."""
    pending = await run_in_threadpool(_prepare_submission, db, settings, principal, body, idempotency_key)
    if isinstance(pending, SubmissionOut):
        return pending, False
    result = await workers.call(
        job_submission,
        body.program,
        pending.exercise.dialect,
        exercise_spec(pending.exercise, body.skip_blocks),
    )
    return await run_in_threadpool(_store_submission, db, settings, principal, body, pending, result)


def _prepare_submission(
    db: Session, settings: Settings, principal: Principal, body: SubmissionCreate, idempotency_key: str | None
) -> _Pending | SubmissionOut:
    """The checks before grading (scope, the exam rules, the limit); the earlier submission for a repeated
    idempotency key. Gives the connection back."""
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
            return earlier
    exercise = get_exercise(db, body.exercise)  # access.check refuses one the caller does not see
    check_program(settings, body.program, exercise.dialect)
    external = body.external_user if principal.api_key is not None else None
    verdict = access.check(db, principal, "submit", exercise.slug, body.assignment, external)
    target = verdict.assignment
    if (
        target is not None
        and verdict.limit
        and principal.user_id is not None
        and repo.count_attempts(db, target.id, principal.user_id, exercise.id) >= verdict.limit
    ):
        raise ApiError("ASSIGNMENT_SUBMITTED", exercise=exercise.slug, limit=verdict.limit)
    db.commit()
    return _Pending(exercise, verdict, stored_key, external)


def _store_submission(
    db: Session,
    settings: Settings,
    principal: Principal,
    body: SubmissionCreate,
    pending: _Pending,
    result: dict[str, Any],
) -> tuple[SubmissionOut, bool]:
    exercise, verdict, target = pending.exercise, pending.verdict, pending.verdict.assignment
    fields = {
        "exercise_id": exercise.id,
        "user_id": principal.user_id,
        "api_key_id": principal.api_key.id if principal.api_key else None,
        "external_user": pending.external,
        "program": body.program,
        "dialect": exercise.dialect,
        "error_count": result["errors"],
        "warning_count": result["warnings"],
        "result": {"diagnostics": result["diagnostics"], "summary": result["summary"]},
        "grading": result["grading"],
        "idempotency_key": pending.stored_key,
        "assignment_id": target.id if target else None,
        "late": verdict.late,
        "held": verdict.held,
        "exercise_version": exercise.version,
    }
    try:
        submission = store_attempt(db, fields, verdict.limit if target is not None else 0, exercise.slug)
    except repo.Duplicate:
        # a retry with the same key was stored while this one was graded: answer with that one
        earlier = _earlier_submission(db, principal, pending.stored_key, body) if pending.stored_key else None
        if earlier is None:
            raise ApiError("CONFLICT") from None
        return earlier, False
    repo.summarise_submissions(db, submission, settings.submissions_with_details)  # the storage quota
    lti_ags.after_graded(
        db, submission
    )  # the grade to the learning platform's gradebook, if it came from one
    return submission_out(db, submission, exercise, principal.user, True, principal), True


def store_attempt(db: Session, fields: dict[str, Any], limit: int, slug: str) -> Submission:
    """Store a submission; to an assignment with a limit as its next attempt (1 … limit), which the database
    holds unique: of submissions racing for the last attempt one is stored, the others are refused with 409
    ASSIGNMENT_SUBMITTED. repo.Duplicate for any other unique key (the idempotency key)."""
    if not limit or fields.get("user_id") is None:
        return repo.create_submission(db, **fields)
    for _ in range(limit):
        done = repo.count_attempts(db, fields["assignment_id"], fields["user_id"], fields["exercise_id"])
        if done >= limit:
            break
        try:
            return repo.create_submission(db, **fields, attempt=done + 1)
        except repo.Duplicate:
            if fields.get("idempotency_key") and repo.submission_by_idempotency_key(
                db, fields["idempotency_key"]
            ):
                raise
            continue  # another submission took this attempt: count again
    raise ApiError("ASSIGNMENT_SUBMITTED", exercise=slug, limit=limit)


def may_name_learners(principal: Principal) -> bool:
    """Who may submit for a learner of a learning platform (external_user): the operator's keys (no owner) and
    keys of instructors and admins; a student's key would let a student submit in anyone's name."""
    if principal.api_key is None:
        return False
    return principal.api_key.owner_id is None or principal.is_instructor()


def _earlier_submission(
    db: Session, principal: Principal, stored_key: str, body: SubmissionCreate
) -> SubmissionOut | None:
    """The submission stored under this caller's idempotency key, if the request is the same; else a conflict."""
    earlier = repo.submission_by_idempotency_key(db, stored_key)
    if earlier is None:
        return None
    exercise = repo.exercise_by_id(db, earlier.exercise_id)
    if exercise is None or exercise.slug != body.exercise or earlier.program != body.program:
        raise ApiError("IDEMPOTENCY_CONFLICT")
    return submission_out(db, earlier, exercise, principal.user, True, principal)


def visible_submissions(
    db: Session, principal: Principal, exercise: str | None
) -> list[tuple[Submission, Exercise, User | None]]:
    """Students: their own; instructors: their own, those to their exercises and their students' work
    (repo.instructed); admins: all; API keys: those made through the key plus what their owner may see."""
    if not principal.has_scope("submissions:read"):
        raise ApiError("MISSING_SCOPE", scope="submissions:read")
    if exercise is not None:
        get_exercise(db, exercise)
    admin = principal.user is not None and principal.user.role == "admin"
    instructor = principal.user_id if principal.is_instructor() else None
    return list(
        repo.list_submissions(
            db,
            user_id=principal.user_id,
            owner_id=instructor,
            instructor_id=instructor,
            api_key_id=principal.api_key.id if principal.api_key else None,
            exercise_slug=exercise,
            everything=admin,
        )
    )


def may_see(
    principal: Principal, submission: Submission, exercise: Exercise, instructed: bool = False
) -> bool:
    """Admins: all; everyone their own; instructors: those to their exercises and their students' work
    (`instructed`: an assignment of a course they teach, or the practice of a student they manage —
    repo.instructed); keys: those made through the key, plus what their owner may see."""
    if principal.user is not None and principal.user.role == "admin":
        return True
    if principal.user_id is not None and submission.user_id == principal.user_id:
        return True
    if principal.is_instructor() and exercise.owner_id == principal.user_id:
        return True
    if principal.is_instructor() and instructed:
        return True
    return principal.api_key is not None and submission.api_key_id == principal.api_key.id


def get_submission(db: Session, principal: Principal, submission_id: int) -> SubmissionOut:
    """Someone else's submission is 404, as if it did not exist."""
    if not principal.has_scope("submissions:read"):
        raise ApiError("MISSING_SCOPE", scope="submissions:read")
    submission = repo.submission_by_id(db, submission_id)
    exercise = repo.exercise_by_id(db, submission.exercise_id) if submission else None
    author = (
        repo.user_by_id(db, submission.user_id) if submission and submission.user_id is not None else None
    )
    instructed = (
        principal.is_instructor()
        and submission is not None
        and principal.user_id is not None
        and repo.instructs(db, principal.user_id, submission.id)
    )
    if submission is None or exercise is None or not may_see(principal, submission, exercise, instructed):
        raise ApiError("SUBMISSION_NOT_FOUND", submission=submission_id)
    return submission_out(db, submission, exercise, author, True, principal)


CSV_COLUMNS = (
    "Abgabe",
    "Aufgabe",
    "Benutzer",
    "Lernplattform-Kennung",
    "Zeitpunkt",
    "Fehler",
    "Warnungen",
    "Bewegungen",
    "Punktzahl",
    "Höchstpunktzahl",
)


def submissions_csv(db: Session, principal: Principal, exercise: str | None) -> str:
    """The submissions the caller may read, one row each, for German Excel (server/export.py: `;`, UTF-8 with BOM,
    German local time); the score is the teacher's where they changed it."""
    if not principal.is_instructor():
        raise ApiError("FORBIDDEN")
    return excel_csv(
        CSV_COLUMNS,
        (
            [
                s.id,
                e.slug,
                u.username if u else "",
                s.external_user or "",
                utc(s.created_at),
                s.error_count,
                s.warning_count,
                s.result["summary"]["moves"],
                _score(s)[0],
                s.grading["max_score"] if s.grading else None,
            ]
            for s, e, u in visible_submissions(db, principal, exercise)
        ),
    )


# --- the exercise list: order and dialect names (issue 15) ------------------------------------


def _list_view(exercise: Exercise) -> dict[str, Any]:
    """What the list shows besides the fields: place in the set, the dialect's names, hints, solution policy."""
    document = exercise.document or {}
    dialect = DIALECTS.get(exercise.dialect)
    return {
        "order": document.get("order"),
        "hint_count": len(document.get("hints") or []),
        "solution": document.get("solution") or "after_submission",
        "dialect_title": dialect.title_de if dialect else exercise.dialect,
        "dialect_title_en": dialect.title_en if dialect else exercise.dialect,
    }


_DIALECT_ORDER = {name: i for i, name in enumerate(DIALECTS)}


def _natural(text: str) -> tuple[tuple[int, int | str], ...]:
    """A sort key that compares the numbers in a text as numbers: G2 before G3 before G23."""
    # ASCII digits only: "²" is a digit to str.isdigit() but no number to int()
    return tuple(
        (0, int(part)) if part.isascii() and part.isdigit() else (1, part)
        for part in re.split(r"([0-9]+)", text.casefold())
        if part
    )


def list_order(exercise: Exercise) -> tuple[Any, ...]:
    """Sets (dialects) in their fixed order; within one, by `order` (exercises without one last), then title."""
    order = (exercise.document or {}).get("order")
    return (
        _DIALECT_ORDER.get(exercise.dialect, len(_DIALECT_ORDER)),
        order is None,
        order if isinstance(order, int) else 0,
        _natural(exercise.title_de),
        exercise.slug,
    )


def sorted_exercises(db: Session) -> list[Exercise]:
    return sorted(repo.list_exercises(db), key=list_order)


# --- drafts (issue 15) -------------------------------------------------------------------------


def _draft_user(principal: Principal) -> int:
    """Drafts belong to users (a browser's editor); API keys have none."""
    if principal.api_key is not None or principal.user is None:
        raise ApiError("DRAFTS_USERS_ONLY")
    return principal.user.id


def get_draft(db: Session, principal: Principal, slug: str, assignment: int | None = None) -> DraftOut:
    """The draft the editor starts with: the named exam's, else the running exam's with this exercise, else the
    practice draft (server/access.py decides which and whether)."""
    user_id = _draft_user(principal)
    exercise = get_exercise(db, slug)
    scope = access.check(db, principal, "read_draft", slug, assignment).draft_scope
    row = repo.draft(db, user_id, exercise.id, scope)
    return DraftOut(
        exercise=slug,
        assignment=scope,
        program=row.program if row else None,
        updated_at=row.updated_at if row else None,
    )


def save_draft(
    db: Session,
    settings: Settings,
    principal: Principal,
    slug: str,
    program: str,
    assignment: int | None = None,
) -> DraftOut:
    """Replace the caller's draft (the same text twice is the same state: PUT is idempotent)."""
    user_id = _draft_user(principal)
    exercise = get_exercise(db, slug)
    if len(program) > settings.max_program_chars:
        raise ApiError("PROGRAM_TOO_LARGE", size=len(program), limit=settings.max_program_chars)
    scope = access.check(db, principal, "draft", slug, assignment).draft_scope
    row = repo.save_draft(db, user_id, exercise.id, program, scope)
    return DraftOut(exercise=slug, assignment=scope, program=row.program, updated_at=row.updated_at)


def delete_draft(db: Session, principal: Principal, slug: str, assignment: int | None = None) -> None:
    user_id = _draft_user(principal)
    exercise = get_exercise(db, slug)
    scope = access.check(db, principal, "draft", slug, assignment).draft_scope
    repo.delete_draft(db, user_id, exercise.id, scope)


# --- the trainee's history and progress (issue 15) -------------------------------------------------

HISTORY_LIMIT = 200  # newest submissions shown per exercise


def _score(submission: Submission) -> tuple[int | None, int | None]:
    """The score that counts (the teacher's override, else the grader's) and the maximum; None, None: ungraded."""
    grading = submission.grading
    if not grading:
        return None, None
    override = getattr(submission, "override_score", None)  # repo.Scored has it in its score already
    return int(grading["score"] if override is None else override), int(grading["max_score"])


def override_out(db: Session, submission: Submission) -> OverrideOut | None:
    """The teacher's last word on a submission, as its readers see it; None where there is none."""
    if submission.override_score is None or submission.override_at is None:
        return None
    by = repo.user_by_id(db, submission.override_by) if submission.override_by is not None else None
    auto = int(submission.grading["score"]) if submission.grading else None
    comment = submission.override_comment or ""
    tail_de, tail_en = (f" – {comment}", f" – {comment}") if comment else ("", "")
    return OverrideOut(
        score=submission.override_score,
        automatic_score=auto,
        comment=comment,
        by=by.username if by else None,
        at=submission.override_at,
        message=f"Punktzahl von der Lehrkraft geändert: {submission.override_score} statt {auto}{tail_de}",
        message_en=f"Score changed by the instructor: {submission.override_score} instead of {auto}{tail_en}",
    )


def set_override(
    db: Session, principal: Principal, submission_id: int, body: OverrideIn | None
) -> SubmissionOut:
    """The teacher's last word: admins, and instructors whose course the submission belongs to or who manage its
    author (repo.instructed), set its score and a comment (None: back to the grader's score). The results tables,
    their CSV and the learning platform's gradebook use it from then on."""
    if principal.api_key is not None or principal.user is None or not principal.is_instructor():
        raise ApiError("FORBIDDEN")
    submission = repo.submission_by_id(db, submission_id)
    exercise = repo.exercise_by_id(db, submission.exercise_id) if submission else None
    if (
        submission is None
        or exercise is None
        or not (principal.user.role == "admin" or repo.instructs(db, principal.user.id, submission.id))
    ):
        raise ApiError("SUBMISSION_NOT_FOUND", submission=submission_id)
    if body is not None:
        if not submission.grading:
            raise ApiError("NOT_GRADED", submission=submission_id)
        limit = int(submission.grading["max_score"])
        if body.score > limit:
            raise ApiError("OVERRIDE_OUT_OF_RANGE", score=body.score, max_score=limit)
    repo.set_override(
        db, submission, body.score if body else None, body.comment if body else "", principal.user.id
    )
    lti_ags.regraded(db, submission)  # the platform's gradebook follows
    author = repo.user_by_id(db, submission.user_id) if submission.user_id is not None else None
    return submission_out(db, submission, exercise, author, True, principal)


def best_of(submissions: list[Submission]) -> Submission:
    """The best graded submission (the newest of equal scores; `submissions` newest first), else the newest."""
    best = submissions[0]
    for s in submissions:
        if _score(s)[0] is not None and (_score(best)[0] is None or _score(s)[0] > _score(best)[0]):  # type: ignore[operator]
            best = s
    return best


def my_submissions(db: Session, principal: Principal, slug: str) -> list[MySubmission]:
    """The caller's own submissions to one exercise, newest first, with program and criteria (as far as they may
    see them now: server/access.py)."""
    if not principal.has_scope("submissions:read"):
        raise ApiError("MISSING_SCOPE", scope="submissions:read")
    exercise = get_exercise(db, slug)
    if principal.user_id is None:
        return []
    sit = access.situation(db, access.acting_user(principal), slug)
    full = can_manage(principal, exercise) and access.allowed(sit, "reference", slug)
    out = []
    for s in repo.own_submissions(db, principal.user_id, exercise.id, HISTORY_LIMIT):
        visible = access.grade_visible(sit, s, slug)
        score, max_score = _score(s) if visible else (None, None)
        grading = grading_view(s.grading, full) if visible else None
        out.append(
            MySubmission(
                id=s.id,
                exercise=slug,
                created_at=s.created_at,
                score=score,
                max_score=max_score,
                override=override_out(db, s) if visible else None,
                error_count=None if s.held else s.error_count,
                warning_count=None if s.held else s.warning_count,
                held=s.held,
                criteria=grading["criteria"] if grading else [],
                program=s.program,
            )
        )
    return out


def my_progress(db: Session, principal: Principal) -> list[Progress]:
    """Per exercise (in list order): not started, a draft, or submitted with the best score (as far as the caller
    may see it now)."""
    if not principal.has_scope("submissions:read"):
        raise ApiError("MISSING_SCOPE", scope="submissions:read")
    by_exercise: dict[int, list[Submission]] = {}
    drafts: dict[int, Any] = {}
    sit = access.situation(db, access.acting_user(principal))
    if principal.user_id is not None:
        for s in repo.own_submissions(db, principal.user_id):
            if s.held:
                continue  # an exam's, before its results are released
            by_exercise.setdefault(s.exercise_id, []).append(s)
        if principal.api_key is None:
            drafts = {d.exercise_id: d.updated_at for d in repo.drafts_of(db, principal.user_id)}
    out = []
    for e in sorted_exercises(db):
        subs = by_exercise.get(e.id, [])
        shown = [s for s in subs if access.grade_visible(sit, s, e.slug)]
        best = best_of(shown) if shown else None
        score, max_score = _score(best) if best else (None, None)
        status = "submitted" if subs else "draft" if e.id in drafts else "not_started"
        out.append(
            Progress(
                exercise=e.slug,
                status=status,  # type: ignore[arg-type]
                best_score=score,
                max_score=max_score,
                best_submission=best.id if best else None,
                submissions=len(subs),
                draft_updated_at=drafts.get(e.id),
            )
        )
    return out


# --- hints and the reference solution (issue 15) --------------------------------------------------


def hint(db: Session, principal: Principal, slug: str, number: int) -> Hint:
    """The exercise's hints one at a time (1 … count), as far as server/access.py allows them now."""
    exercise = get_exercise(db, slug)
    access.check(db, principal, "hints", slug)
    hints = (exercise.document or {}).get("hints") or []
    if not 1 <= number <= len(hints):
        raise ApiError("HINT_NOT_FOUND", hint=number, count=len(hints))
    h = hints[number - 1]
    return Hint(
        exercise=slug, number=number, count=len(hints), text=h.get("de", ""), text_en=h.get("en") or ""
    )


def solution(db: Session, principal: Principal, slug: str) -> Solution:
    """The reference program: always for admins, the exercise's owner and the instructors of a course that sets
    it (an assignment with it), unless an exam of a course they sit as a student withholds it
    (server/access.py); everybody else — students, and instructors for other instructors' exercises — as the
    exercise's `solution` allows (never, after their first submission, after a submission with full marks)."""
    exercise = get_exercise(db, slug)
    policy = (exercise.document or {}).get("solution") or "after_submission"
    access.check(db, principal, "solution", slug)
    if not _answers_for(db, principal, exercise):
        own = (
            list(repo.own_submissions(db, principal.user_id, exercise.id))
            if principal.user_id is not None
            else []
        )
        if policy == "never":
            raise ApiError("SOLUTION_NEVER")
        if policy == "after_submission" and not own:
            raise ApiError("SOLUTION_AFTER_SUBMISSION")
        if policy == "after_full_marks" and not any(
            _score(s)[0] is not None and _score(s)[0] == _score(s)[1] for s in own
        ):
            raise ApiError("SOLUTION_AFTER_FULL_MARKS")
    return Solution(
        exercise=slug,
        program=exercise.reference_program,
        dialect=exercise.dialect,
        policy=policy,  # type: ignore[arg-type]
    )  # the document was validated (core.exercises)


def _answers_for(db: Session, principal: Principal, exercise: Exercise) -> bool:
    """Who sees an exercise's reference whatever its policy: admins, its owner, the instructors who set it."""
    user = principal.user
    if user is None or user.role not in ("instructor", "admin"):
        return False
    return (
        user.role == "admin"
        or exercise.owner_id == user.id
        or any(exercise.slug in a.exercises for a in repo.taught_assignments(db, user.id))
    )


# --- users: instructors and their students, class lists (issue 15) -------------------------------


def instructor_named(db: Session, name: str) -> User:
    """The user `name`, who must be an instructor or an admin (someone who can manage students)."""
    user = repo.user_by_name(db, name)
    if user is None:
        raise ApiError("USER_NOT_FOUND", user=name)
    if user.role not in ("instructor", "admin"):
        raise ApiError("NOT_AN_INSTRUCTOR", user=name)
    return user


def _managing_instructor(
    db: Session, principal: Principal, name: str | None, role: str = "student"
) -> User | None:
    """Who will manage users made by `principal`: admins name anyone (or nobody); instructors make students
    managed by themselves only."""
    if principal.api_key is not None or principal.user is None:
        raise ApiError("FORBIDDEN")
    if principal.user.role == "admin":
        return instructor_named(db, name) if name else None
    if principal.user.role == "instructor" and role == "student" and name in (None, principal.user.username):
        return principal.user
    raise ApiError("FORBIDDEN")


def create_user_by(db: Session, principal: Principal, body: UserCreate) -> UserOut:
    instructor = _managing_instructor(db, principal, body.instructor, body.role)
    user = create_user(db, body.username, body.password, body.role, instructor)
    return user_out(user, instructor.username if instructor else None)


def set_instructor(db: Session, username: str, instructor_name: str | None) -> UserOut:
    """Put an existing user under an instructor (or nobody): they then see the user's submissions."""
    user = repo.user_by_name(db, username)
    if user is None:
        raise ApiError("USER_NOT_FOUND", user=username)
    instructor = instructor_named(db, instructor_name) if instructor_name else None
    repo.set_instructor(db, user, instructor.id if instructor else None)
    return user_out(user, instructor.username if instructor else None)


def visible_users(db: Session, principal: Principal) -> list[UserOut]:
    """Admins: every user; instructors: the students they manage."""
    if principal.is_admin():
        users = list(repo.list_users(db))
    elif principal.api_key is None and principal.is_instructor():
        users = list(repo.students_of(db, principal.user_id))  # type: ignore[arg-type]
    else:
        raise ApiError("FORBIDDEN")
    names = (
        {u.id: u.username for u in repo.list_users(db)}
        if principal.is_admin()
        else {principal.user_id: principal.user.username if principal.user else None}
    )
    return [user_out(u, names.get(u.instructor_id) if u.instructor_id else None) for u in users]


CLASS_LIST_MAX = 100  # rows of one class list (each password is hashed with argon2: a fraction of a second)
_HEADER_NAMES = {"name", "username", "benutzer", "benutzername", "login", "anmeldename"}
_PASSWORD_ALPHABET = "abcdefghjkmnpqrstuvwxyzABCDEFGHJKLMNPQRSTUVWXYZ23456789"  # no 0/O, 1/l/I
_NAME_RE = re.compile(r"^[A-Za-z0-9_.@-]{1,80}$")


def new_password(length: int = 12) -> str:
    return "".join(secrets.choice(_PASSWORD_ALPHABET) for _ in range(length))


def parse_class_list(data: bytes) -> list[tuple[str, str | None]]:
    """(name, password or None) per row of a class list: CSV with `;` or `,`, UTF-8 with or without BOM,
    columns name;password or name only, an optional header row. ApiError CLASS_LIST_INVALID names every bad row."""
    try:
        text = data.decode("utf-8-sig")
    except UnicodeDecodeError:
        raise ApiError(
            "CLASS_LIST_INVALID",
            detail="die Datei ist nicht UTF-8-kodiert",
            detail_en="the file is not UTF-8 encoded",
            errors=[],
        ) from None
    lines = [line for line in text.splitlines() if line.strip()]
    delimiter = ";" if lines and ";" in lines[0] else ","
    rows = list(csv.reader(lines, delimiter=delimiter))
    if rows and rows[0] and rows[0][0].strip().casefold() in _HEADER_NAMES:
        rows, first = rows[1:], 2
    else:
        first = 1
    errors: list[dict[str, Any]] = []
    out: list[tuple[str, str | None]] = []
    seen: set[str] = set()

    def bad(row: int, de: str, en: str) -> None:
        errors.append({"row": row, "message": de, "message_en": en})

    if not rows:
        bad(1, "keine Namen in der Liste", "no names in the list")
    if len(rows) > CLASS_LIST_MAX:
        bad(first + CLASS_LIST_MAX, f"mehr als {CLASS_LIST_MAX} Zeilen", f"more than {CLASS_LIST_MAX} rows")
        rows = rows[:CLASS_LIST_MAX]
    for i, cells in enumerate(rows, start=first):
        name = cells[0].strip() if cells else ""
        password = cells[1].strip() if len(cells) > 1 and cells[1].strip() else None
        if not _NAME_RE.match(name):
            bad(
                i,
                f"Name »{name[:80]}«: nur Buchstaben ohne Umlaute, Ziffern und _ . @ - (höchstens 80 Zeichen)",
                f"name '{name[:80]}': only letters without umlauts, digits and _ . @ - (at most 80 characters)",
            )
        elif lti_reserved(name):
            bad(i, f"Name »{name}«: {LTI_NAME_DE}", f"name '{name}': {LTI_NAME_EN}")
        elif name.casefold() in seen:
            bad(i, f"Name »{name}« steht doppelt in der Liste", f"name '{name}' appears twice in the list")
        seen.add(name.casefold())
        problem = password_problem(password) if password is not None else None
        if problem is not None:
            bad(i, *problem)
        out.append((name, password))
    if errors:
        raise ApiError(
            "CLASS_LIST_INVALID",
            errors=errors,
            detail="; ".join(f"Zeile {e['row']}: {e['message']}" for e in errors[:5]),
            detail_en="; ".join(f"row {e['row']}: {e['message_en']}" for e in errors[:5]),
        )
    return out


def import_class_list(db: Session, data: bytes, instructor: User | None) -> list[ImportedUser]:
    """Students from a class list, managed by `instructor`: all of them or none (a name taken: 409 with the
    names). Passwords the list does not give are generated and returned this once."""
    rows = parse_class_list(data)
    taken = [u.username for u in repo.users_by_names(db, [n for n, _ in rows])]
    if taken:
        raise ApiError("USER_EXISTS", user=", ".join(sorted(taken)))
    passwords = [(name, given or new_password(), given is None) for name, given in rows]
    try:
        repo.create_users(
            db,
            [
                (n, hash_password(p), "student", instructor.id if instructor else None)
                for n, p, _ in passwords
            ],
        )
    except repo.Duplicate:
        raise ApiError("CONFLICT") from None
    return [
        ImportedUser(
            username=n,
            role="student",
            instructor=instructor.username if instructor else None,
            password=p if generated else None,
        )
        for n, p, generated in passwords
    ]


def import_class_list_by(
    db: Session, principal: Principal, data: bytes, instructor: str | None
) -> ImportedUsers:
    """An instructor imports students for themselves; an admin for any instructor (or none)."""
    manager = _managing_instructor(db, principal, instructor)
    return ImportedUsers(users=import_class_list(db, data, manager))


# --- the results table (issue 15) -------------------------------------------------------------------


def results(db: Session, principal: Principal) -> Results:
    """Trainees × exercises with the best score: for instructors their students and whoever submitted to their
    exercises, for admins everyone; the columns are the exercises anyone of them submitted to. The submissions
    are read in their light columns (repo.scored_submissions: no program, diagnostics or criteria) for the same
    readers as visible_submissions."""
    if not principal.has_scope("submissions:read"):
        raise ApiError("MISSING_SCOPE", scope="submissions:read")
    if not principal.is_instructor():
        raise ApiError("FORBIDDEN")
    users = {u.id: u for u in repo.list_users(db)}
    admin = principal.user is not None and principal.user.role == "admin"
    if admin:
        members = {u.id for u in users.values() if u.role == "student"}
    else:
        members = {u.id for u in repo.students_of(db, principal.user_id)}  # type: ignore[arg-type]
    instructor = principal.user_id  # an instructor (checked above) or a key acting for one
    scored = repo.scored_submissions(
        db,
        user_id=principal.user_id,
        owner_id=instructor,
        instructor_id=instructor,
        api_key_id=principal.api_key.id if principal.api_key else None,
        everything=admin,
    )
    cells: dict[tuple[int, int], list[repo.Scored]] = {}
    for s in scored:
        if s.user_id is None or s.user_id == principal.user_id or s.user_id not in users:
            continue  # learning-platform learners have no account; the caller's own tries are not a trainee's
        cells.setdefault((s.user_id, s.exercise_id), []).append(s)
        members.add(s.user_id)
    exercises = repo.exercises_by_ids(db, (eid for _, eid in cells))
    columns = sorted(exercises, key=list_order)
    rows = []
    for uid in sorted(members, key=lambda i: users[i].username.casefold()):
        row: dict[str, ResultCell] = {}
        for e in columns:
            subs = cells.get((uid, e.id))
            if subs:
                best = best_of(subs)  # type: ignore[arg-type]  # Scored has the score as its grading
                score, max_score = _score(best)
                row[e.slug] = ResultCell(
                    best_score=score,
                    max_score=max_score,
                    best_submission=best.id,
                    overridden=bool(getattr(best, "overridden", False)),
                    submissions=[s.id for s in subs],
                    created_at=best.created_at,
                    exercise_version=getattr(best, "exercise_version", None),
                    version_note=version_note(getattr(best, "exercise_version", None), e.version),
                )
        manager = users.get(users[uid].instructor_id) if users[uid].instructor_id else None  # type: ignore[arg-type]
        rows.append(
            ResultRow(
                username=users[uid].username, instructor=manager.username if manager else None, results=row
            )
        )
    return Results(
        exercises=[ResultExercise(slug=e.slug, title_de=e.title_de, title_en=e.title_en) for e in columns],
        trainees=rows,
    )


RESULTS_COLUMNS = (
    "Benutzer",
    "Lehrkraft",
    "Aufgabe",
    "Titel",
    "Beste Punktzahl",
    "Höchstpunktzahl",
    "Prozent",
    "Abgaben",
    "Beste Abgabe",
    "Zeitpunkt",
)


def berlin_time(value: Any) -> str:
    """A stored time as German Excel reads it: local time in Germany, to the second."""
    return str(excel_cell(utc(value)))


def decimal_comma(value: float) -> str:
    return f"{value:.1f}".replace(".", ",")


def results_csv(db: Session, principal: Principal) -> str:
    """The results table for German Excel: `;`, UTF-8 with BOM, decimal comma, local time; one row per trainee
    and exercise (empty cells: not tried)."""
    table = results(db, principal)
    rows = []
    for trainee in table.trainees:
        for e in table.exercises:
            cell = trainee.results.get(e.slug)
            if cell is None:
                rows.append(
                    [trainee.username, trainee.instructor or "", e.slug, e.title_de, "", "", "", 0, "", ""]
                )
                continue
            percent = (
                decimal_comma(100 * cell.best_score / cell.max_score)
                if cell.best_score is not None and cell.max_score
                else ""
            )
            rows.append(
                [
                    trainee.username,
                    trainee.instructor or "",
                    e.slug,
                    e.title_de,
                    "" if cell.best_score is None else cell.best_score,
                    "" if cell.max_score is None else cell.max_score,
                    percent,
                    len(cell.submissions),
                    cell.best_submission,
                    berlin_time(cell.created_at),
                ]
            )
    return excel_csv(RESULTS_COLUMNS, rows)
