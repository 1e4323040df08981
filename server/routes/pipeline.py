"""POST /check, /run, /simulate: the pipeline for a program text, computed in a worker process.

A trainee in a running exam gets them only as its settings allow (like the live socket and the 3D view):
/check and /run are live diagnostics, /simulate is the 3D view (server/access.py decides)."""

from __future__ import annotations

from typing import Any

from fastapi import APIRouter, Depends

from server import access, services
from server.deps import AppSettings, AppWorkers, DbSession, PracticePrincipal, rate_limit
from server.errors import responses
from server.schemas import CheckResponse, ProgramRequest, RunResponse, SimulateRequest, SimulateResponse
from server.workers import HAS_SIM, job_check, job_run, job_simulate

router = APIRouter(tags=["pipeline"])
ERRORS = responses(401, 403, 404, 413, 422, 429, 503)


@router.post("/check", response_model=CheckResponse, responses=ERRORS,
             dependencies=[Depends(rate_limit("check", "rate_check_per_minute"))])
async def check(req: ProgramRequest, db: DbSession, settings: AppSettings, workers: AppWorkers,
                principal: PracticePrincipal) -> Any:
    """Diagnostics of a program, in the shape of `paltrainer check --json`."""
    access.check(db, principal, "live", req.exercise)
    spec = services.run_spec(db, settings, req)
    db.commit()  # the connection goes back to the pool while the worker computes (as for submissions)
    return await workers.call(job_check, req.program, req.dialect, spec)


@router.post("/run", response_model=RunResponse, responses=ERRORS,
             dependencies=[Depends(rate_limit("check", "rate_check_per_minute"))])
async def run(req: ProgramRequest, db: DbSession, settings: AppSettings, workers: AppWorkers,
              principal: PracticePrincipal) -> Any:
    """The toolpath of a program, in the shape of `paltrainer run --json`."""
    access.check(db, principal, "live", req.exercise)
    spec = services.run_spec(db, settings, req)
    db.commit()  # the connection goes back to the pool while the worker computes (as for submissions)
    return await workers.call(job_run, req.program, req.dialect, spec)


if HAS_SIM:

    @router.post("/simulate", response_model=SimulateResponse, responses=ERRORS,
                 dependencies=[Depends(rate_limit("simulate", "rate_simulate_per_minute"))])
    async def simulate(req: SimulateRequest, db: DbSession, settings: AppSettings, workers: AppWorkers,
                       principal: PracticePrincipal) -> Any:
        """Stock results and events, in the shape of `paltrainer simulate --json`."""
        access.check(db, principal, "viz", req.exercise)
        spec = services.simulate_spec(db, settings, req)
        db.commit()  # the connection goes back to the pool while the worker computes
        return await workers.call(job_simulate, req.program, req.dialect, spec)
