"""The caller's own work: progress per exercise, and "Meine Abgaben" for one exercise."""

from __future__ import annotations

from typing import Annotated

from fastapi import APIRouter, Query

from server import services
from server.deps import CurrentPrincipal, DbSession
from server.errors import responses
from server.schemas import MySubmission, Progress, Slug

router = APIRouter(prefix="/me", tags=["accounts"])


@router.get("/progress", response_model=list[Progress], responses=responses(401, 403))
def my_progress(db: DbSession, principal: CurrentPrincipal) -> list[Progress]:
    """Per exercise, in the list's order: not started, a draft, or submitted (with the best score)."""
    return services.my_progress(db, principal)


@router.get("/submissions", response_model=list[MySubmission], responses=responses(401, 403, 404, 422))
def my_submissions(
    db: DbSession,
    principal: CurrentPrincipal,
    exercise: Annotated[Slug, Query(description="The exercise's slug")],
) -> list[MySubmission]:
    """The caller's own submissions to one exercise, newest first (at most 200): score, time, criteria and the
    program (to load it into the editor)."""
    return services.my_submissions(db, principal, exercise)
