"""Drafts: the editor's text per user and exercise, saved while typing and brought back on the next visit."""

from __future__ import annotations

from fastapi import APIRouter, Depends, Response

from server import services
from server.deps import AppSettings, CurrentPrincipal, DbSession, rate_limit
from server.errors import responses
from server.schemas import DraftIn, DraftOut, Slug

router = APIRouter(prefix="/exercises", tags=["drafts"])


@router.get("/{slug}/draft", response_model=DraftOut, responses=responses(401, 403, 404))
def get_draft(slug: Slug, db: DbSession, principal: CurrentPrincipal) -> DraftOut:
    """The caller's draft; `program: null` when there is none (the editor starts from the start program)."""
    return services.get_draft(db, principal, slug)


@router.put("/{slug}/draft", response_model=DraftOut, responses=responses(401, 403, 404, 413, 422, 429),
            dependencies=[Depends(rate_limit("draft", "rate_draft_per_minute"))])
def save_draft(slug: Slug, body: DraftIn, db: DbSession, settings: AppSettings,
               principal: CurrentPrincipal) -> DraftOut:
    """Replace the caller's draft with `program` (idempotent)."""
    return services.save_draft(db, settings, principal, slug, body.program)


@router.delete("/{slug}/draft", status_code=204, responses=responses(401, 403, 404))
def delete_draft(slug: Slug, db: DbSession, principal: CurrentPrincipal) -> Response:
    """Forget the caller's draft ("Zurücksetzen"); nothing to forget is fine too."""
    services.delete_draft(db, principal, slug)
    return Response(status_code=204)
