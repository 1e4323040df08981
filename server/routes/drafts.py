"""Drafts: the editor's text per user and exercise, saved while typing and brought back on the next visit."""

from __future__ import annotations

from typing import Annotated

from fastapi import APIRouter, Depends, Query, Response

from server import services
from server.deps import AppSettings, CurrentPrincipal, DbSession, rate_limit
from server.errors import responses
from server.schemas import DB_INT_MAX, DraftIn, DraftOut, Slug

router = APIRouter(prefix="/exercises", tags=["drafts"])
AssignmentParam = Annotated[
    int | None,
    Query(
        ge=1,
        le=DB_INT_MAX,
        description="The exam the draft is for (its page names it); without it the running exam "
        "with this exercise, else the practice draft",
    ),
]


@router.get("/{slug}/draft", response_model=DraftOut, responses=responses(401, 403, 404))
def get_draft(
    slug: Slug, db: DbSession, principal: CurrentPrincipal, assignment: AssignmentParam = None
) -> DraftOut:
    """The caller's draft; `program: null` when there is none (the editor starts from the start program). An
    exam's drafts are its own: it starts from the start program, never from a practice draft."""
    return services.get_draft(db, principal, slug, assignment)


@router.put(
    "/{slug}/draft",
    response_model=DraftOut,
    responses=responses(401, 403, 404, 413, 422, 429),
    dependencies=[Depends(rate_limit("draft", "rate_draft_per_minute"))],
)
def save_draft(
    slug: Slug,
    body: DraftIn,
    db: DbSession,
    settings: AppSettings,
    principal: CurrentPrincipal,
    assignment: AssignmentParam = None,
) -> DraftOut:
    """Replace the caller's draft with `program` (idempotent); refused after an exam's end (EXAM_OVER)."""
    return services.save_draft(db, settings, principal, slug, body.program, assignment)


@router.delete("/{slug}/draft", status_code=204, responses=responses(401, 403, 404))
def delete_draft(
    slug: Slug, db: DbSession, principal: CurrentPrincipal, assignment: AssignmentParam = None
) -> Response:
    """Forget the caller's draft ("Zurücksetzen"); nothing to forget is fine too."""
    services.delete_draft(db, principal, slug, assignment)
    return Response(status_code=204)
