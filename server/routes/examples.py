"""The built-in examples for free practice ("Beispiel laden"), without an account.

The built-in exercises of kind `write` are the published PAL (and control makers') seed examples: their
programs are public documents, so free practice may load them with the exercise's drawing. Exercises of
kind `complete` and `fix` give only their start program (their reference is the answer to the task), and an
exercise whose `solution` is `never` gives no reference either; nor does one that is in an exam whose results
are not released (server/access.py: nobody asking here is known). Exercises made by instructors never appear.
"""

from __future__ import annotations

import re
from typing import Any, Literal

from fastapi import APIRouter, Depends, Response
from starlette.concurrency import run_in_threadpool

from server import access, services
from server.deps import ANONYMOUS, HEAVY, AppWorkers, DbSession, rate_limit
from server.errors import ApiError, responses
from server.models import Exercise
from server.schemas import Slug

router = APIRouter(prefix="/examples", tags=["examples"])


def _program(exercise: Exercise, sit: access.Situation) -> tuple[str, str] | None:
    """The program free practice may load (and which one it is), or None."""
    document: dict[str, Any] = exercise.document or {}
    start = str(document.get("start_program") or "")
    if (
        document.get("kind", "write") != "write"
        or document.get("solution") == "never"
        or not access.allowed(sit, "reference", exercise.slug)
    ):
        return (start, "start") if start else None
    return exercise.reference_program, "reference"


def _builtin(db: DbSession, slug: str) -> Exercise:
    exercise = services.get_exercise(db, slug)
    if (
        not exercise.builtin
        or exercise.document is None
        or _program(exercise, access.unknown_situation(db)) is None
    ):
        raise ApiError("EXERCISE_NOT_FOUND", exercise=slug)
    return exercise


@router.get("")
def list_examples(db: DbSession) -> list[dict[str, Any]]:
    """The built-in exercises' programs for free practice: slug, titles, dialect, kind, the program and whether
    it is the exercise's reference or its start program, the stock, the tools and (turning) the blank (in the
    exercises' order)."""
    examples = []
    sit = access.unknown_situation(db)
    for exercise in services.sorted_exercises(db):
        program = _program(exercise, sit) if exercise.builtin and exercise.document is not None else None
        if program is None:
            continue
        examples.append(
            {
                "slug": exercise.slug,
                "title_de": exercise.title_de,
                "title_en": exercise.title_en,
                "dialect": exercise.dialect,
                "kind": (exercise.document or {}).get("kind", "write"),
                "program": program[0],
                "program_is": program[1],
                "stock": exercise.stock,
                "tools": exercise.tools,
                "blank": (exercise.document or {}).get(
                    "blank"
                ),  # turning: the bar or tube (free practice's blank)
            }
        )
    return examples


@router.get(
    "/{slug}/drawing.svg",
    response_class=Response,
    responses={
        200: {
            "content": {"image/svg+xml": {}},
            "description": "Dimensioned drawing of the example's part (A4, mm)",
        },
        **responses(404, 429, 503),
    },
    dependencies=[Depends(rate_limit("picture", "rate_picture_per_minute")), HEAVY],
)
async def example_drawing(
    slug: Slug, db: DbSession, workers: AppWorkers, lang: Literal["de", "en"] = "de", download: bool = False
) -> Response:
    """The drawing of a built-in example, as on its exercise page (GET /exercises/{slug}/drawing.svg)."""
    await run_in_threadpool(_builtin, db, slug)  # no query on the event loop
    headers = {"Cache-Control": "public, max-age=300"}
    if download:
        headers["Content-Disposition"] = (
            f'attachment; filename="{re.sub(r"[^a-z0-9-]", "", slug) or "part"}.svg"'
        )
    return Response(
        await services.exercise_drawing(db, workers, ANONYMOUS, slug, lang),
        media_type="image/svg+xml",
        headers=headers,
    )
