"""POST /check, /run, /simulate: the pipeline for a program text, computed in a worker process.

A trainee in a running exam gets them only as its settings allow (like the live socket and the 3D view):
/check and /run are live diagnostics, /simulate is the 3D view (server/access.py decides)."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from fastapi import APIRouter, Depends
from sqlalchemy.orm import Session
from starlette.concurrency import run_in_threadpool

from server import access, services
from server.config import Settings
from server.deps import HEAVY, AppSettings, AppWorkers, DbSession, PracticePrincipal, Principal, rate_limit
from server.errors import responses
from server.jobs import HAS_SIM, job_check, job_run, job_simulate
from server.schemas import CheckResponse, ProgramRequest, RunResponse, SimulateRequest, SimulateResponse

router = APIRouter(tags=["pipeline"])
ERRORS = responses(401, 403, 404, 413, 422, 429, 503)


def _spec(
    db: Session,
    settings: Settings,
    principal: Principal,
    action: access.Action,
    req: Any,
    make: Callable[[Session, Settings, Any], dict[str, Any]],
) -> dict[str, Any]:
    """In the threadpool (no query on the event loop): may the caller, and the worker's set-up; then the pooled
    connection goes back while the worker computes."""
    access.check(db, principal, action, req.exercise)
    spec = make(db, settings, req)
    db.commit()
    return spec


@router.post(
    "/check",
    response_model=CheckResponse,
    responses=ERRORS,
    dependencies=[Depends(rate_limit("check", "rate_check_per_minute"))],
)
async def check(
    req: ProgramRequest,
    db: DbSession,
    settings: AppSettings,
    workers: AppWorkers,
    principal: PracticePrincipal,
) -> Any:
    """Diagnostics of a program, in the shape of `paltrainer check --json`."""
    spec = await run_in_threadpool(_spec, db, settings, principal, "live", req, services.run_spec)
    return await workers.call(job_check, req.program, req.dialect, spec)


@router.post(
    "/run",
    response_model=RunResponse,
    responses=ERRORS,
    dependencies=[Depends(rate_limit("check", "rate_check_per_minute"))],
)
async def run(
    req: ProgramRequest,
    db: DbSession,
    settings: AppSettings,
    workers: AppWorkers,
    principal: PracticePrincipal,
) -> Any:
    """The toolpath of a program, in the shape of `paltrainer run --json`."""
    spec = await run_in_threadpool(_spec, db, settings, principal, "live", req, services.run_spec)
    return await workers.call(job_run, req.program, req.dialect, spec)


if HAS_SIM:

    @router.post(
        "/simulate",
        response_model=SimulateResponse,
        responses=ERRORS,
        dependencies=[Depends(rate_limit("simulate", "rate_simulate_per_minute")), HEAVY],
    )
    async def simulate(
        req: SimulateRequest,
        db: DbSession,
        settings: AppSettings,
        workers: AppWorkers,
        principal: PracticePrincipal,
    ) -> Any:
        """Stock results and events, in the shape of `paltrainer simulate --json`. One of the caller's heavy
        requests (429 TOO_MANY_JOBS beyond PALTRAINER_HEAVY_JOBS_PER_USER, per address when anonymous)."""
        spec = await run_in_threadpool(_spec, db, settings, principal, "viz", req, services.simulate_spec)
        return await workers.call(job_simulate, req.program, req.dialect, spec)
