"""The 3D view's routes: a token for a session's scene, the scene's content, the playhead, and the
viser client with its WebSocket bridge under /viz/{token} (one public port)."""

from __future__ import annotations

import asyncio
import logging
from typing import Any

from fastapi import APIRouter, Request, WebSocket
from fastapi.responses import Response
from pydantic import BaseModel, Field
from starlette.concurrency import run_in_threadpool

from server import services, viz
from server.deps import AppSettings, AppWorkers, DbSession, PracticePrincipal
from server.errors import ApiError, responses
from server.schemas import ProgramRequest, SimulateRequest
from server.workers import job_deviation, job_scene, job_stock_after

log = logging.getLogger("paltrainer.server")
router = APIRouter(prefix="/viz", tags=["3d view"])
pages = APIRouter(include_in_schema=False)


class VizSession(BaseModel):
    token: str = Field(description="Signed, short-lived; names this browser session's scene")
    url: str = Field(description="The page to embed (an iframe)")


class SceneResult(BaseModel):
    segments: int
    cut: bool = Field(description="The toolpath had more segments than the view shows (20,000)")
    lines: list[int] = Field(description="The block line of each segment, for the playhead")
    errors: int
    states: dict[int, dict[str, Any]] = Field(description="Per block line: plane, G90/G91, compensation, "
                                                          "zero offset, feed, speed, tool, position after it")


class Playhead(BaseModel):
    index: int = Field(ge=0)


def _scenes(request: Request) -> viz.Scenes:
    scenes: viz.Scenes = request.app.state.scenes
    return scenes


def _scene(request: Request, token: str) -> viz.Scene:
    sid = _scenes(request).sid_of(token)
    if sid is None:
        raise ApiError("BAD_TOKEN")
    return _scenes(request).scene(sid)


@router.post("", response_model=VizSession, status_code=201, responses=responses(401))
def new_session(request: Request, _: PracticePrincipal) -> VizSession:
    token = _scenes(request).new_token()
    return VizSession(token=token, url=f"/viz/{token}/")


@router.post("/{token}/scene", response_model=SceneResult, responses=responses(401, 404, 413, 422, 503))
async def put_scene(token: str, body: SimulateRequest, request: Request, db: DbSession, settings: AppSettings,
                    workers: AppWorkers, _: PracticePrincipal) -> SceneResult:
    """Run the program (in a worker) and show its toolpath, the stock after it and the tool. The stock: the
    request's, else the exercise's, else the PAL examples' block; `resolution` is the view's own (0.5 mm)."""
    scene = await run_in_threadpool(_scene, request, token)
    spec = await run_in_threadpool(services.simulate_spec, db, settings, body)
    data: dict[str, Any] = await workers.call(job_scene, body.program, body.dialect, spec)
    generation = await run_in_threadpool(viz.show, scene, data)
    scene.program = (body.program, body.dialect, spec)
    if data["stock"] is not None:  # the coarse level of detail is out; the fine one follows
        scene.refining = asyncio.create_task(run_in_threadpool(viz.show_stock, scene, data["stock"]["fine"], generation))
        scene.refining.add_done_callback(_log_failure)
    return SceneResult(segments=len(data["segments"]), cut=data["cut"], lines=data["lines"], errors=data["errors"],
                       states=data["states"])


def _log_failure(task: asyncio.Task[Any]) -> None:
    if not task.cancelled() and task.exception() is not None:
        log.error("3D view: the fine stock could not be shown", exc_info=task.exception())


@router.post("/{token}/playhead", responses=responses(401))
async def put_playhead(token: str, body: Playhead, request: Request, workers: AppWorkers) -> dict[str, Any]:
    """Move the tool to the end of toolpath segment `index` and show the stock after its move; answers that
    segment's block line."""
    scene = await run_in_threadpool(_scene, request, token)
    line = await run_in_threadpool(viz.playhead, scene, body.index)
    if scene.has_stock and scene.program is not None and scene.moves:
        text, dialect, spec = scene.program
        move = scene.moves[min(body.index, len(scene.moves) - 1)] + 1
        tiles = await workers.call(job_stock_after, text, dialect, spec, move)
        await run_in_threadpool(viz.show_stock, scene, tiles)
    return {"index": body.index, "line": line}


class Deviation(BaseModel):
    too_much: int = Field(description="Cells where too much material was removed (shown red)")
    too_little: int = Field(description="Cells where too much material is left (shown blue)")


@router.post("/{token}/deviation", response_model=Deviation, responses=responses(401, 404, 413, 422, 503))
async def put_deviation(token: str, body: ProgramRequest, request: Request, db: DbSession, settings: AppSettings,
                        workers: AppWorkers, _: PracticePrincipal) -> Deviation:
    """Colour the part of a program for an exercise where it leaves the tolerance band of the reference
    (after grading: red too much removed, blue too much left)."""
    scene = await run_in_threadpool(_scene, request, token)
    if body.exercise is None:
        raise ApiError("EXERCISE_REQUIRED")
    spec = await run_in_threadpool(services.run_spec, db, settings, body)
    data: dict[str, Any] = await workers.call(job_deviation, body.program, spec)
    await run_in_threadpool(viz.show_deviation, scene, data["too_much"], data["too_little"], data["cell"])
    return Deviation(too_much=len(data["too_much"]), too_little=len(data["too_little"]))


@pages.get("/viz/{token}/")
def viewer(token: str, request: Request) -> Response:
    if _scenes(request).sid_of(token) is None:
        return Response("Sitzung abgelaufen – bitte die Seite neu laden.", status_code=401, media_type="text/plain")
    return Response(viz.viser_page(), media_type="text/html", headers={"Cache-Control": "no-cache"})


@pages.websocket("/viz/{token}")
@pages.websocket("/viz/{token}/")
async def viewer_socket(ws: WebSocket, token: str) -> None:
    scenes: viz.Scenes = ws.app.state.scenes
    sid = scenes.sid_of(token)
    offered = [p.strip() for p in ws.headers.get("sec-websocket-protocol", "").split(",") if p.strip()]
    protocol = next((p for p in offered if p.startswith("viser-v")), None)
    if sid is None or protocol is None:
        await ws.close(code=4403)
        return
    scene = await run_in_threadpool(scenes.scene, sid)
    await ws.accept(subprotocol=protocol)
    await viz.bridge(ws, scene.port, protocol)
