"""Exercises: everyone with scope exercises:read lists and reads; instructors manage their own, admins all."""

from __future__ import annotations

import re
from typing import Annotated, Literal

from fastapi import APIRouter, Depends, Path, Query, Request, Response
from starlette.concurrency import run_in_threadpool

from core.sheet.tasktext import task_html
from server import drawings, services
from server.deps import (
    HEAVY,
    AppSettings,
    AppWorkers,
    CurrentPrincipal,
    DbSession,
    Principal,
    rate_limit,
    require_scope,
)
from server.errors import ApiError, responses
from server.schemas import (
    DrawingPreviewIn,
    ExerciseCreate,
    ExerciseOut,
    ExerciseUpdate,
    Hint,
    Slug,
    Solution,
    TaskPreview,
    TaskPreviewIn,
    Visibility,
)

router = APIRouter(prefix="/exercises", tags=["exercises"])
Reader = Annotated[Principal, Depends(require_scope("exercises:read"))]
# the picture, drawing and sheet: rate-limited, and counted among the caller's heavy requests (429 TOO_MANY_JOBS);
# their database work runs in the threadpool and gives the connection back before the wait for a worker
PICTURE = [Depends(rate_limit("picture", "rate_picture_per_minute")), HEAVY]
SHEET_NAME = {"de": "aufgabenblatt", "en": "task-sheet"}


@router.get("", response_model=list[ExerciseOut], responses=responses(401, 403))
def list_exercises(
    db: DbSession, principal: Reader, mine: bool = False, archived: bool = False
) -> list[ExerciseOut]:
    """The exercises the caller sees (drafts only their author's, "courses" only the author's courses', docs/
    server.md), in the order of their sets: by dialect, then the exercise's `order`, then title. `mine`: only those
    the caller manages (not built in); `archived`: archived ones too."""
    return services.visible_exercises(db, principal, mine, archived)


@router.post(
    "/drawing-preview",
    response_class=Response,
    responses={
        200: {
            "content": {"image/svg+xml": {}},
            "description": "The drawing of the editor's unsaved exercise",
        },
        **responses(401, 403, 413, 422, 429, 503),
    },
    dependencies=PICTURE,
)
async def drawing_preview(
    body: DrawingPreviewIn, workers: AppWorkers, principal: CurrentPrincipal
) -> Response:
    """The dimensioned drawing of an exercise as the editor holds it, before it is saved: its reference, dialect,
    stock or blank and tools (the other fields are filled in). Instructors; 422 EXERCISE_INVALID with every error."""
    services.require_instructor(principal)
    return Response(
        await services.drawing_preview(workers, body.document, body.lang),
        media_type="image/svg+xml",
        headers={"Cache-Control": "no-store"},
    )


@router.post("/task-preview", response_model=TaskPreview, responses=responses(401, 403, 422))
def task_preview(body: TaskPreviewIn, principal: CurrentPrincipal) -> TaskPreview:
    """A task's Markdown as the exercise page and the sheet show it (the same subset, the same renderer)."""
    services.require_instructor(principal)
    return TaskPreview(html=task_html(body.markdown))


@router.get("/{slug}", response_model=ExerciseOut, responses=responses(401, 403, 404))
def get_exercise(slug: Slug, db: DbSession, principal: Reader) -> ExerciseOut:
    """Reference program, hidden criteria and the whole document only for the exercise's owner and admins."""
    return services.exercise_out(db, services.exercise_seen(db, principal, slug), principal)


@router.post(
    "/{slug}/duplicate", response_model=ExerciseOut, status_code=201, responses=responses(401, 403, 404, 422)
)
def duplicate_exercise(slug: Slug, db: DbSession, principal: CurrentPrincipal) -> ExerciseOut:
    """A copy of a built-in exercise or one's own as a new draft of the caller (instructors, admins), slug
    "<slug>-kopie" (or -kopie-2 …), title "… (Kopie)"."""
    return services.exercise_out(db, services.duplicate_exercise(db, principal, slug), principal)


@router.get(
    "/{slug}/export",
    response_class=Response,
    responses={
        200: {"content": {"application/yaml": {}}, "description": "The exercise file (docs/exercises.md)"},
        **responses(401, 403, 404),
    },
)
def export_exercise(slug: Slug, db: DbSession, principal: CurrentPrincipal) -> Response:
    """The exercise as a YAML file in the exercise format, with its reference: what `POST /exercises/import` reads
    (its owner and admins)."""
    name = re.sub(r"[^a-z0-9-]", "", slug) or "exercise"
    return Response(
        services.export_exercise(db, principal, slug),
        media_type="application/yaml; charset=utf-8",
        headers={"Content-Disposition": f'attachment; filename="{name}.yaml"'},
    )


@router.put(
    "/{slug}/own-drawing",
    response_model=ExerciseOut,
    responses=responses(401, 403, 404, 413, 422),
    openapi_extra={
        "requestBody": {
            "required": True,
            "content": {"application/octet-stream": {"schema": {"type": "string", "format": "binary"}}},
        }
    },
)
async def upload_drawing(
    slug: Slug,
    request: Request,
    db: DbSession,
    principal: CurrentPrincipal,
    filename: Annotated[str, Query(max_length=200)] = "zeichnung",
) -> ExerciseOut:
    """The author's own drawing (PDF, PNG or SVG; at most 2 MB; recognised by its content; an SVG without scripts,
    event handlers or external references): shown to trainees and printed on the sheet instead of the generated
    drawing."""
    data = bytearray()
    async for chunk in request.stream():
        data += chunk
        if len(data) > drawings.MAX_DRAWING_BYTES:
            raise ApiError("DRAWING_TOO_LARGE", size=len(data), limit=drawings.MAX_DRAWING_BYTES)
    return await run_in_threadpool(services.set_own_drawing, db, principal, slug, bytes(data), filename)


@router.delete("/{slug}/own-drawing", status_code=204, responses=responses(401, 403, 404))
def remove_drawing(slug: Slug, db: DbSession, principal: CurrentPrincipal) -> Response:
    """Back to the drawing generated from the reference."""
    services.remove_own_drawing(db, principal, slug)
    return Response(status_code=204)


@router.get(
    "/{slug}/own-drawing",
    response_class=Response,
    responses={
        200: {"content": {"application/pdf": {}, "image/png": {}, "image/svg+xml": {}}},
        **responses(401, 403, 404),
    },
)
def get_own_drawing(slug: Slug, db: DbSession, principal: Reader) -> Response:
    """The author's own drawing as uploaded (for a PDF: what the exercise page opens)."""
    drawing = services.own_drawing(db, principal, slug)
    return Response(
        drawing.data,
        media_type=drawing.media_type,
        headers={
            "Cache-Control": "private, max-age=60",
            "Content-Security-Policy": "default-src 'none'; style-src 'unsafe-inline'; sandbox",
            "Content-Disposition": f'inline; filename="{re.sub(r"[^A-Za-z0-9._-]", "_", drawing.filename)}"',
        },
    )


@router.get("/{slug}/hints/{number}", response_model=Hint, responses=responses(401, 403, 404, 422))
def exercise_hint(
    slug: Slug, number: Annotated[int, Path(ge=1, le=1000)], db: DbSession, principal: Reader
) -> Hint:
    """The exercise's hint `number` (1 … `hint_count`), one at a time ("Tipp anzeigen")."""
    return services.hint(db, principal, slug, number)


@router.get("/{slug}/solution", response_model=Solution, responses=responses(401, 403, 404))
def exercise_solution(slug: Slug, db: DbSession, principal: Reader) -> Solution:
    """The reference program. Students: as the exercise's `solution` allows (`never`, `after_submission`,
    `after_full_marks`), else 403 with the reason; instructors and admins always."""
    return services.solution(db, principal, slug)


@router.get(
    "/{slug}/picture.png",
    response_class=Response,
    responses={
        200: {"content": {"image/png": {}}, "description": "Top view of the finished part"},
        **responses(401, 403, 404, 429, 503),
    },
    dependencies=PICTURE,
)
async def exercise_picture(slug: Slug, db: DbSession, workers: AppWorkers, principal: Reader) -> Response:
    """The finished part seen from above (the reference machined on the stock), darker where deeper."""
    return Response(
        await services.exercise_picture(db, workers, principal, slug),
        media_type="image/png",
        headers={"Cache-Control": "private, max-age=300"},
    )


@router.get(
    "/{slug}/drawing.svg",
    response_class=Response,
    responses={
        200: {
            "content": {"image/svg+xml": {}},
            "description": "Dimensioned drawing of the finished part (A4, mm)",
        },
        **responses(401, 403, 404, 429, 503),
    },
    dependencies=PICTURE,
)
async def exercise_drawing(
    slug: Slug,
    db: DbSession,
    workers: AppWorkers,
    principal: Reader,
    lang: Literal["de", "en"] = "de",
    download: bool = False,
) -> Response:
    """The part as a PAL exam draws it: top view and section, coordinate dimensions from the workpiece zero,
    radii, chamfers, depths and a title block (docs/drawings.md). `download=true` offers it as a file."""
    headers = {
        "Cache-Control": "private, max-age=300",
        "Content-Security-Policy": "default-src 'none'; style-src 'unsafe-inline'; img-src data:",
    }
    if download:
        headers["Content-Disposition"] = (
            f'attachment; filename="{re.sub(r"[^a-z0-9-]", "", slug) or "part"}.svg"'
        )
    return Response(
        await services.exercise_drawing(db, workers, principal, slug, lang),
        media_type="image/svg+xml",
        headers=headers,
    )


@router.get(
    "/{slug}/sheet.pdf",
    response_class=Response,
    responses={
        200: {
            "content": {"application/pdf": {}},
            "description": "Printed task sheet with the programming form (A4)",
        },
        **responses(401, 403, 404, 429, 503),
    },
    dependencies=PICTURE,
)
async def exercise_sheet(
    slug: Slug, db: DbSession, workers: AppWorkers, principal: Reader, lang: Literal["de", "en"] = "de"
) -> Response:
    """The exercise for paper practice, as the PAL exam hands it out: title, task, the dimensioned drawing,
    blank, tools and cutting data, then the empty programming form (docs/drawings.md). 503 PDF_UNAVAILABLE
    where the server cannot make PDF (WeasyPrint or its system libraries missing)."""
    name = re.sub(r"[^a-z0-9-]", "", slug) or "exercise"
    return Response(
        await services.exercise_sheet(db, workers, principal, slug, lang),
        media_type="application/pdf",
        headers={
            "Cache-Control": "private, max-age=300",
            "Content-Disposition": f'inline; filename="{name}-{SHEET_NAME[lang]}.pdf"',
        },
    )


@router.post(
    "", response_model=ExerciseOut, status_code=201, responses=responses(401, 403, 409, 413, 422, 429, 503)
)
async def create_exercise(
    body: ExerciseCreate,
    db: DbSession,
    settings: AppSettings,
    workers: AppWorkers,
    principal: CurrentPrincipal,
) -> ExerciseOut:
    """From fields, or (the editor) from `document`, the whole exercise in the exercise format: validated with
    every error at once (422 EXERCISE_INVALID, details.errors: field, message, message_en); unless a draft, its
    reference must score full marks. Visibility: without `document` public unless given, with it draft."""
    if body.document is not None:
        exercise = await services.create_from_document(db, settings, workers, principal, body)
    else:
        exercise = await run_in_threadpool(services.create_exercise, db, settings, principal, body)
    return await run_in_threadpool(services.exercise_out, db, exercise, principal)


@router.post(
    "/import",
    response_model=ExerciseOut,
    status_code=201,
    responses=responses(401, 403, 409, 413, 422, 429, 503),
    dependencies=[HEAVY],
    openapi_extra={
        "requestBody": {
            "required": True,
            "content": {
                "application/yaml": {"schema": {"type": "string"}},
                "application/json": {"schema": {"type": "object"}},
            },
        }
    },
)
async def import_exercise(
    request: Request,
    db: DbSession,
    settings: AppSettings,
    workers: AppWorkers,
    principal: CurrentPrincipal,
    visibility: Visibility = "public",
) -> ExerciseOut:
    """Create an exercise from a file in the exercise format (docs/exercises.md), YAML or JSON, with the
    reference inline. It is validated (every error at once), and its reference must score full marks; the
    messages say why not. `visibility`: who sees it (the editor's import: draft)."""
    text = (await request.body()).decode("utf-8", errors="replace")
    exercise = await services.import_exercise(db, settings, workers, principal, text, visibility)
    return await run_in_threadpool(services.exercise_out, db, exercise, principal)


@router.patch("/{slug}", response_model=ExerciseOut, responses=responses(401, 403, 404, 413, 422, 429, 503))
async def update_exercise(
    slug: Slug,
    body: ExerciseUpdate,
    db: DbSession,
    settings: AppSettings,
    workers: AppWorkers,
    principal: CurrentPrincipal,
) -> ExerciseOut:
    """Change fields, or (the editor) the whole `document`; `visibility`; `archived: false` takes it back from the
    archive. An edit of the content of a published exercise makes a new version (`version`); submissions keep the
    version they were graded against. Publishing needs a reference that scores full marks."""
    if body.document is not None:
        exercise = await services.update_from_document(db, settings, workers, principal, slug, body)
    else:
        current = await run_in_threadpool(services.exercise_seen, db, principal, slug)
        await services.publish_check(settings, workers, current, body)
        exercise = await run_in_threadpool(services.update_exercise, db, settings, principal, slug, body)
    return await run_in_threadpool(services.exercise_out, db, exercise, principal)


@router.delete("/{slug}", status_code=204, responses=responses(401, 403, 404))
def delete_exercise(slug: Slug, db: DbSession, principal: CurrentPrincipal) -> Response:
    """Delete one's exercise; with submissions it is archived instead: hidden from trainees, its submissions kept
    (PATCH archived=false brings it back)."""
    services.delete_exercise(db, principal, slug)
    return Response(status_code=204)
