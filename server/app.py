"""The FastAPI application: settings, database (migrated on start), worker processes, routes under /api/v1."""

from __future__ import annotations

import asyncio
import gc
import json
import logging
from collections.abc import AsyncIterator
from contextlib import asynccontextmanager
from pathlib import Path
from typing import Any

from fastapi import APIRouter, FastAPI
from fastapi.middleware.cors import CORSMiddleware
from fastapi.openapi.utils import get_openapi
from fastapi.staticfiles import StaticFiles

from server import errors, live, viz
from server.config import Settings
from server.courses import finalizer as exam_finalizer
from server.db import Database, migrate, startup_lock
from server.loopwatch import LoopWatch
from server.lti import ags as lti_ags
from server.middleware import RequestMiddleware, SecurityHeadersMiddleware
from server.ratelimit import RateLimiter
from server.routes import (
    accounts,
    admin,
    assignments,
    auth,
    courses,
    dialects,
    drafts,
    examples,
    exercises,
    health,
    me,
    pages,
    pipeline,
    results,
    submissions,
    users,
)
from server.routes import lti as lti_routes
from server.routes import lti_grades as lti_grade_routes
from server.routes import viz as viz_routes
from server.seed import load_exercises
from server.workers import Workers

log = logging.getLogger("paltrainer.server")
API_PREFIX = "/api/v1"


def prepare_database(settings: Settings) -> Database:
    """Migrate to the newest schema and load the built-in exercises."""
    database = Database(settings)
    with startup_lock(database.engine):  # replicas starting at once: one after the other
        migrate(database.engine)
        if settings.load_exercises:
            with database.session() as db:
                n = load_exercises(db, settings.exercises_dir)
            log.info("exercises loaded", extra={"job": f"{n} built-in"})
    return database


def command_database() -> Database:
    """The database for a command of `paltrainer admin` (users, keys, LTI platforms): migrated, without
    loading the exercises."""
    settings = Settings()
    return prepare_database(settings.model_copy(update={"load_exercises": False}))


def install_openapi(app: FastAPI) -> None:
    """FastAPI documents its validation errors as HTTPValidationError; ours have the ErrorBody shape."""

    def openapi() -> dict[str, Any]:
        if app.openapi_schema is None:
            doc = get_openapi(
                title=app.title, version=app.version, description=app.description, routes=app.routes
            )
            schemas = doc.setdefault("components", {}).setdefault("schemas", {})
            schemas.pop("HTTPValidationError", None)
            schemas.pop("ValidationError", None)
            text = json.dumps(doc).replace(
                "#/components/schemas/HTTPValidationError", "#/components/schemas/ErrorBody"
            )
            doc = json.loads(text)
            error = {"application/json": {"schema": {"$ref": "#/components/schemas/ErrorBody"}}}
            for methods in doc.get("paths", {}).values():
                for op in methods.values():
                    for status, resp in op.get("responses", {}).items():
                        if status.startswith(("4", "5")):
                            resp["content"] = error
            app.openapi_schema = doc
        return app.openapi_schema

    app.openapi = openapi  # type: ignore[method-assign]


STATIC = Path(__file__).resolve().parent / "static"  # the built editor (web/: npm run build)


def create_app(settings: Settings | None = None) -> FastAPI:
    settings = settings or Settings()

    @asynccontextmanager
    async def lifespan(app: FastAPI) -> AsyncIterator[None]:
        app.state.db = prepare_database(settings)
        app.state.workers.start()
        watch = LoopWatch(settings.loop_stall_seconds) if settings.loop_stall_seconds else None
        if watch is not None:
            watch.start()
        # ended exams: the last drafts are submitted even when nobody asks (issue 19)
        finalizer = asyncio.create_task(
            exam_finalizer(app.state.db, app.state.workers, settings.finalize_seconds)
        )
        # LTI grade passback: the score queue is sent (and retried) even when nobody asks (issue 20)
        score_drainer = asyncio.create_task(lti_ags.drainer(app.state.db))
        gc.collect()
        gc.freeze()  # what start-up loaded stays: full collections need not walk it again
        try:
            yield
        finally:
            finalizer.cancel()
            score_drainer.cancel()
            if watch is not None:
                watch.stop()
            app.state.scenes.stop_all()
            app.state.workers.stop()
            app.state.db.engine.dispose()

    app = FastAPI(
        title="PAL Trainer API",
        version="1",
        description="Check, run and simulate PAL programs; exercises, submissions, accounts. "
        'Errors: `{"error": {"code", "message" (German), "message_en", "details"}}`.',
        lifespan=lifespan,
        docs_url=None,  # /docs is served by server/routes/pages.py from our own Swagger UI files
        redoc_url=None,
    )
    app.state.settings = settings
    app.state.limiter = RateLimiter(settings.redis_url)
    app.state.workers = Workers(settings.workers, settings.job_seconds)
    app.state.scenes = viz.Scenes(settings.jwt_secret(), settings)
    errors.install(app)
    pages.install_not_found(app)
    api = APIRouter(prefix=API_PREFIX)
    for module in (
        pipeline,
        auth,
        accounts,
        me,
        users,
        exercises,
        examples,
        drafts,
        submissions,
        results,
        dialects,
        viz_routes,
        courses,
        assignments,
    ):
        api.include_router(module.router)
    api.include_router(live.router)
    api.include_router(lti_grade_routes.router)  # grade passback status and roster (issue 20)
    app.include_router(api)
    app.include_router(health.router)
    app.include_router(pages.router)
    app.include_router(viz_routes.pages)
    lti_routes.install(app)  # /lti/… (issue 20)
    app.include_router(admin.router)  # /api/v1/admin/…: the admin page's platforms and keys
    app.mount("/static", StaticFiles(directory=STATIC, check_dir=False), name="static")

    install_openapi(app)
    if settings.cors_origins:
        app.add_middleware(
            CORSMiddleware,
            allow_origins=settings.cors_origins,
            allow_credentials=True,
            allow_methods=["GET", "POST", "PUT", "PATCH", "DELETE"],
            allow_headers=["Authorization", "Content-Type", "X-API-Key", "X-Request-ID"],
        )
    app.add_middleware(RequestMiddleware, max_body_bytes=settings.max_body_bytes)
    app.add_middleware(SecurityHeadersMiddleware, settings=settings)  # outermost: the 413s get them too
    return app
