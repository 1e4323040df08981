"""GET /healthz (the process answers) and GET /readyz (database and workers answer)."""

from __future__ import annotations

from fastapi import APIRouter
from sqlalchemy.exc import SQLAlchemyError

from server import repository as repo
from server.deps import AppWorkers, DbSession
from server.errors import ApiError, responses
from server.schemas import Health, Ready

router = APIRouter(tags=["health"])


@router.get("/healthz", response_model=Health)
def healthz() -> Health:
    return Health(status="ok")


@router.get("/readyz", response_model=Ready, responses=responses(503))
def readyz(db: DbSession, workers: AppWorkers) -> Ready:
    try:
        repo.ready(db)
    except SQLAlchemyError:
        raise ApiError("NOT_READY", detail="database") from None
    if not workers.ready:  # no worker process can take a job (all of them dead or still starting)
        raise ApiError("NOT_READY", detail="workers")
    return Ready(status="ready", database="ok", workers="ok")
