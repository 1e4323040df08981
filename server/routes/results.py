"""The results table for instructors: trainees × exercises with the best score, as JSON and as CSV for Excel."""

from __future__ import annotations

from fastapi import APIRouter, Response

from server import services
from server.deps import CurrentPrincipal, DbSession
from server.errors import responses
from server.schemas import Results

router = APIRouter(tags=["submissions"])


@router.get("/results", response_model=Results, responses=responses(401, 403))
def results(db: DbSession, principal: CurrentPrincipal) -> Results:
    """Instructors: their students (and whoever submitted to their exercises); admins: every trainee."""
    return services.results(db, principal)


@router.get(
    "/results.csv",
    response_class=Response,
    responses={
        200: {
            "content": {"text/csv": {"schema": {"type": "string"}}},
            "description": "One row per trainee and exercise; `;`, UTF-8 with BOM, decimal comma, German time",
        },
        **responses(401, 403),
    },
)
def results_csv(db: DbSession, principal: CurrentPrincipal) -> Response:
    return Response(
        services.results_csv(db, principal).encode("utf-8"),
        media_type="text/csv; charset=utf-8",
        headers={"Content-Disposition": 'attachment; filename="ergebnisse.csv"'},
    )
