"""Exercises: everyone with scope exercises:read lists and reads; instructors manage their own, admins all."""

from __future__ import annotations

import re
from typing import Annotated, Literal

from fastapi import APIRouter, Depends, Path, Request, Response
from starlette.concurrency import run_in_threadpool

from server import access, services
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
from server.errors import responses
from server.schemas import ExerciseCreate, ExerciseOut, ExerciseUpdate, Hint, Slug, Solution

router = APIRouter(prefix="/exercises", tags=["exercises"])
Reader = Annotated[Principal, Depends(require_scope("exercises:read"))]
# the picture, drawing and sheet: rate-limited, and counted among the caller's heavy requests (429 TOO_MANY_JOBS);
# their database work runs in the threadpool and gives the connection back before the wait for a worker
PICTURE = [Depends(rate_limit("picture", "rate_picture_per_minute")), HEAVY]
SHEET_NAME = {"de": "aufgabenblatt", "en": "task-sheet"}


@router.get("", response_model=list[ExerciseOut], responses=responses(401, 403))
def list_exercises(db: DbSession, principal: Reader) -> list[ExerciseOut]:
    """In the order of their sets: by dialect, then the exercise's `order`, then title."""
    sit = access.situation(db, access.acting_user(principal))  # one for every exercise: the user's courses
    return [services.exercise_out(db, e, principal, sit) for e in services.sorted_exercises(db)]


@router.get("/{slug}", response_model=ExerciseOut, responses=responses(401, 403, 404))
def get_exercise(slug: Slug, db: DbSession, principal: Reader) -> ExerciseOut:
    """Reference program and hidden criteria only for the exercise's owner and admins."""
    return services.exercise_out(db, services.get_exercise(db, slug), principal)


@router.get("/{slug}/hints/{number}", response_model=Hint, responses=responses(401, 403, 404, 422))
def exercise_hint(slug: Slug, number: Annotated[int, Path(ge=1, le=1000)], db: DbSession, principal: Reader) -> Hint:
    """The exercise's hint `number` (1 … `hint_count`), one at a time ("Tipp anzeigen")."""
    return services.hint(db, principal, slug, number)


@router.get("/{slug}/solution", response_model=Solution, responses=responses(401, 403, 404))
def exercise_solution(slug: Slug, db: DbSession, principal: Reader) -> Solution:
    """The reference program. Students: as the exercise's `solution` allows (`never`, `after_submission`,
    `after_full_marks`), else 403 with the reason; instructors and admins always."""
    return services.solution(db, principal, slug)


@router.get("/{slug}/picture.png", response_class=Response, responses={
    200: {"content": {"image/png": {}}, "description": "Top view of the finished part"},
    **responses(401, 403, 404, 429, 503)}, dependencies=PICTURE)
async def exercise_picture(slug: Slug, db: DbSession, workers: AppWorkers, principal: Reader) -> Response:
    """The finished part seen from above (the reference machined on the stock), darker where deeper."""
    return Response(await services.exercise_picture(db, workers, slug), media_type="image/png",
                    headers={"Cache-Control": "private, max-age=300"})


@router.get("/{slug}/drawing.svg", response_class=Response, responses={
    200: {"content": {"image/svg+xml": {}}, "description": "Dimensioned drawing of the finished part (A4, mm)"},
    **responses(401, 403, 404, 429, 503)}, dependencies=PICTURE)
async def exercise_drawing(slug: Slug, db: DbSession, workers: AppWorkers, principal: Reader,
                           lang: Literal["de", "en"] = "de", download: bool = False) -> Response:
    """The part as a PAL exam draws it: top view and section, coordinate dimensions from the workpiece zero,
    radii, chamfers, depths and a title block (docs/drawings.md). `download=true` offers it as a file."""
    headers = {"Cache-Control": "private, max-age=300"}
    if download:
        headers["Content-Disposition"] = f'attachment; filename="{re.sub(r"[^a-z0-9-]", "", slug) or "part"}.svg"'
    return Response(await services.exercise_drawing(db, workers, slug, lang), media_type="image/svg+xml",
                    headers=headers)


@router.get("/{slug}/sheet.pdf", response_class=Response, responses={
    200: {"content": {"application/pdf": {}}, "description": "Printed task sheet with the programming form (A4)"},
    **responses(401, 403, 404, 429, 503)}, dependencies=PICTURE)
async def exercise_sheet(slug: Slug, db: DbSession, workers: AppWorkers, principal: Reader,
                         lang: Literal["de", "en"] = "de") -> Response:
    """The exercise for paper practice, as the PAL exam hands it out: title, task, the dimensioned drawing,
    blank, tools and cutting data, then the empty programming form (docs/drawings.md). 503 PDF_UNAVAILABLE
    where the server cannot make PDF (WeasyPrint or its system libraries missing)."""
    name = re.sub(r"[^a-z0-9-]", "", slug) or "exercise"
    return Response(await services.exercise_sheet(db, workers, slug, lang), media_type="application/pdf",
                    headers={"Cache-Control": "private, max-age=300",
                             "Content-Disposition": f'inline; filename="{name}-{SHEET_NAME[lang]}.pdf"'})


@router.post("", response_model=ExerciseOut, status_code=201, responses=responses(401, 403, 409, 413, 422))
def create_exercise(body: ExerciseCreate, db: DbSession, settings: AppSettings,
                    principal: CurrentPrincipal) -> ExerciseOut:
    return services.exercise_out(db, services.create_exercise(db, settings, principal, body), principal)


@router.post("/import", response_model=ExerciseOut, status_code=201,
             responses=responses(401, 403, 409, 413, 422, 429, 503), dependencies=[HEAVY],
             openapi_extra={"requestBody": {"required": True, "content": {
                 "application/yaml": {"schema": {"type": "string"}},
                 "application/json": {"schema": {"type": "object"}}}}})
async def import_exercise(request: Request, db: DbSession, settings: AppSettings, workers: AppWorkers,
                          principal: CurrentPrincipal) -> ExerciseOut:
    """Create an exercise from a file in the exercise format (docs/exercises.md), YAML or JSON, with the
    reference inline. It is validated, and its reference must score full marks; the messages say why not."""
    text = (await request.body()).decode("utf-8", errors="replace")
    exercise = await services.import_exercise(db, settings, workers, principal, text)
    return await run_in_threadpool(services.exercise_out, db, exercise, principal)


@router.patch("/{slug}", response_model=ExerciseOut, responses=responses(401, 403, 404, 413, 422))
def update_exercise(slug: Slug, body: ExerciseUpdate, db: DbSession, settings: AppSettings,
                    principal: CurrentPrincipal) -> ExerciseOut:
    return services.exercise_out(db, services.update_exercise(db, settings, principal, slug, body), principal)


@router.delete("/{slug}", status_code=204, responses=responses(401, 403, 404, 409))
def delete_exercise(slug: Slug, db: DbSession, principal: CurrentPrincipal) -> Response:
    services.delete_exercise(db, principal, slug)
    return Response(status_code=204)
