"""Submissions: create (→ the grade, diagnostics and a run summary), list what one may see, one in detail,
CSV export for instructors."""

from __future__ import annotations

from typing import Annotated

from fastapi import APIRouter, Depends, Header, Path, Query, Response
from fastapi.responses import PlainTextResponse

from server import services
from server.deps import HEAVY, AppSettings, AppWorkers, CurrentPrincipal, DbSession, rate_limit
from server.errors import responses
from server.schemas import DB_INT_MAX, OverrideIn, Slug, SubmissionCreate, SubmissionOut

router = APIRouter(prefix="/submissions", tags=["submissions"])


@router.post(
    "",
    response_model=SubmissionOut,
    status_code=201,
    responses={
        200: {"model": SubmissionOut, "description": "A repeated request (same Idempotency-Key)"},
        **responses(401, 403, 404, 409, 413, 422, 429, 503),
    },
    dependencies=[Depends(rate_limit("submit", "rate_submit_per_minute")), HEAVY],
)
async def create_submission(
    body: SubmissionCreate,
    db: DbSession,
    settings: AppSettings,
    workers: AppWorkers,
    principal: CurrentPrincipal,
    response: Response,
    idempotency_key: str | None = Header(
        default=None,
        max_length=200,
        description="Repeating a request with the same key (per user or API key) returns "
        "the submission made the first time (200) instead of a new one",
    ),
) -> SubmissionOut:
    submission, created = await services.create_submission(
        db, settings, workers, principal, body, idempotency_key
    )
    if not created:
        response.status_code = 200
    return submission


@router.get("", response_model=list[SubmissionOut], responses=responses(401, 403, 404))
def list_submissions(
    db: DbSession,
    principal: CurrentPrincipal,
    exercise: Annotated[Slug | None, Query(description="Only this exercise's")] = None,
) -> list[SubmissionOut]:
    """Students: their own; instructors: also those to their exercises; admins: all."""
    readers = services.Readers(db)
    return [
        services.submission_out(db, s, e, u, False, principal, readers)
        for s, e, u in services.visible_submissions(db, principal, exercise)
    ]


@router.get(
    "/export.csv",
    response_class=PlainTextResponse,
    responses={
        200: {
            "content": {"text/csv": {"schema": {"type": "string"}}},
            "description": "CSV, one row per submission",
        },
        **responses(401, 403, 404),
    },
)
def export_csv(
    db: DbSession,
    principal: CurrentPrincipal,
    exercise: Annotated[Slug | None, Query(description="Only this exercise's")] = None,
) -> PlainTextResponse:
    """Instructors: the submissions to their exercises; admins: all."""
    text = services.submissions_csv(db, principal, exercise)
    return PlainTextResponse(
        text,
        media_type="text/csv; charset=utf-8",
        headers={"Content-Disposition": 'attachment; filename="submissions.csv"'},
    )


@router.get("/{submission_id}", response_model=SubmissionOut, responses=responses(401, 403, 404))
def get_submission(
    submission_id: Annotated[int, Path(ge=1, le=DB_INT_MAX)], db: DbSession, principal: CurrentPrincipal
) -> SubmissionOut:
    return services.get_submission(db, principal, submission_id)


@router.put(
    "/{submission_id}/override", response_model=SubmissionOut, responses=responses(401, 403, 404, 409, 422)
)
def set_override(
    submission_id: Annotated[int, Path(ge=1, le=DB_INT_MAX)],
    body: OverrideIn,
    db: DbSession,
    principal: CurrentPrincipal,
) -> SubmissionOut:
    """The teacher's last word: the score that counts instead of the grader's (0 … max_score) and a comment the
    trainee reads ("Punktzahl von der Lehrkraft geändert: 80 statt 50 – …"). Admins, and instructors of the
    course the submission was made in or who manage its author; who and when is kept. Results tables, CSV and
    the learning platform's gradebook use it."""
    return services.set_override(db, principal, submission_id, body)


@router.delete("/{submission_id}/override", response_model=SubmissionOut, responses=responses(401, 403, 404))
def remove_override(
    submission_id: Annotated[int, Path(ge=1, le=DB_INT_MAX)], db: DbSession, principal: CurrentPrincipal
) -> SubmissionOut:
    """Back to the grader's score (the change is kept)."""
    return services.set_override(db, principal, submission_id, None)
