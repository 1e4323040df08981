"""Assignments of a course (practice and exams), their results and task sheets; the trainee's own."""

from __future__ import annotations

from typing import Annotated, Any, Literal

from fastapi import APIRouter, Depends, Path, Response

from server import courses, insights
from server.courses import AssignmentCreate, AssignmentOut, AssignmentResults, AssignmentUpdate, MyAssignment
from server.deps import HEAVY, AppWorkers, CurrentPrincipal, DbSession, rate_limit
from server.errors import responses
from server.schemas import DB_INT_MAX

router = APIRouter(tags=["assignments"])
Id = Annotated[int, Path(ge=1, le=DB_INT_MAX)]
CSV_RESPONSE: dict[int | str, dict[str, Any]] = {
    200: {
        "content": {"application/json": {}, "text/csv": {"schema": {"type": "string"}}},
        "description": "JSON; with ?format=csv (or /results.csv) one row per trainee and exercise: "
        "`;`, UTF-8 with BOM, decimal comma, German time",
    }
}


@router.get(
    "/courses/{course_id}/assignments", response_model=list[AssignmentOut], responses=responses(401, 403, 404)
)
def list_assignments(course_id: Id, db: DbSession, principal: CurrentPrincipal) -> list[AssignmentOut]:
    return courses.list_assignments(db, principal, course_id)


@router.post(
    "/courses/{course_id}/assignments",
    response_model=AssignmentOut,
    status_code=201,
    responses=responses(401, 403, 404, 409, 422),
)
def create_assignment(
    course_id: Id, body: AssignmentCreate, db: DbSession, principal: CurrentPrincipal
) -> AssignmentOut:
    """Instructors of the course: exercises (built-in or their own), opening time and deadline (an exam: start
    and `duration_minutes`), `late` accept/refuse, settings (an exam: exam conditions unless changed)."""
    return courses.create_assignment(db, principal, course_id, body)


@router.get("/me/assignments", response_model=list[MyAssignment], responses=responses(401, 403, 503))
def my_assignments(db: DbSession, principal: CurrentPrincipal) -> list[MyAssignment]:
    """The caller's assignments with deadline, status and their submissions (an exam's scores once released;
    its exercises from its start; status `submitting` for the moment after its end until its last drafts are
    submitted)."""
    return courses.my_assignments(db, principal)


@router.get(
    "/assignments/{assignment_id}", response_model=AssignmentOut, responses=responses(401, 403, 404, 503)
)
def get_assignment(assignment_id: Id, db: DbSession, principal: CurrentPrincipal) -> AssignmentOut:
    return courses.get_assignment(db, principal, assignment_id)


@router.patch(
    "/assignments/{assignment_id}", response_model=AssignmentOut, responses=responses(401, 403, 404, 422)
)
def update_assignment(
    assignment_id: Id, body: AssignmentUpdate, db: DbSession, principal: CurrentPrincipal
) -> AssignmentOut:
    return courses.update_assignment(db, principal, assignment_id, body)


@router.delete("/assignments/{assignment_id}", status_code=204, responses=responses(401, 403, 404))
def delete_assignment(assignment_id: Id, db: DbSession, principal: CurrentPrincipal) -> Response:
    """The assignment; its submissions stay (without it)."""
    courses.delete_assignment(db, principal, assignment_id)
    return Response(status_code=204)


@router.post(
    "/assignments/{assignment_id}/release",
    response_model=AssignmentOut,
    responses=responses(401, 403, 404, 409),
)
def release(assignment_id: Id, db: DbSession, principal: CurrentPrincipal) -> AssignmentOut:
    """Students see their results of this exam from now on (score, criteria, program)."""
    return courses.release(db, principal, assignment_id)


def _csv(text: str, assignment_id: int) -> Response:
    return Response(
        text.encode("utf-8"),
        media_type="text/csv; charset=utf-8",
        headers={"Content-Disposition": f'attachment; filename="auftrag-{assignment_id}.csv"'},
    )


@router.get(
    "/assignments/{assignment_id}/results",
    response_model=AssignmentResults,
    responses={**CSV_RESPONSE, **responses(401, 403, 404, 503)},
)
def results(
    assignment_id: Id, db: DbSession, principal: CurrentPrincipal, format: Literal["json", "csv"] = "json"
) -> AssignmentResults | Response:
    """Instructors of the course: students × exercises with the best score, late and automatic submissions."""
    if format == "csv":
        return _csv(courses.assignment_results_csv(db, principal, assignment_id), assignment_id)
    return courses.assignment_results(db, principal, assignment_id)


@router.get(
    "/assignments/{assignment_id}/results.csv",
    response_class=Response,
    responses={200: CSV_RESPONSE[200], **responses(401, 403, 404, 503)},
)
def results_csv(assignment_id: Id, db: DbSession, principal: CurrentPrincipal) -> Response:
    return _csv(courses.assignment_results_csv(db, principal, assignment_id), assignment_id)


@router.get(
    "/assignments/{assignment_id}/insights",
    response_model=insights.AssignmentInsights,
    responses=responses(401, 403, 404, 503),
)
def class_insights(
    assignment_id: Id, db: DbSession, principal: CurrentPrincipal
) -> insights.AssignmentInsights:
    """Instructors of the course: per exercise the class's most frequent diagnostics and the criteria most
    students lost, with the block where most of them lost it (each student's best submission counts)."""
    return insights.assignment_insights(db, principal, assignment_id)


@router.get(
    "/assignments/{assignment_id}/sheets.pdf",
    response_class=Response,
    responses={
        200: {"content": {"application/pdf": {}}, "description": "The assignment's task sheets (A4)"},
        **responses(401, 403, 404, 409, 429, 503),
    },
    dependencies=[Depends(rate_limit("picture", "rate_picture_per_minute")), HEAVY],
)
async def sheets(
    assignment_id: Id,
    db: DbSession,
    workers: AppWorkers,
    principal: CurrentPrincipal,
    lang: Literal["de", "en"] = "de",
) -> Response:
    """The printed task sheets of the assignment's exercises, one after the other (core/sheet): each exercise's
    pages on their own (its footer and page numbers), rendered once per content and language. One of the caller's
    heavy requests (429 TOO_MANY_JOBS beyond PALTRAINER_HEAVY_JOBS_PER_USER)."""
    pdf = await courses.assignment_sheets(db, workers, principal, assignment_id, lang)
    return Response(
        pdf,
        media_type="application/pdf",
        headers={"Content-Disposition": f'inline; filename="auftrag-{assignment_id}.pdf"'},
    )
