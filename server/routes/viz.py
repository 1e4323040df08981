"""The 3D view's routes: a token for a session's scene, the scene's content, the playhead, the camera views and
layers, the picture of the current state, and the viser client with its WebSocket bridge under /viz/{token}
(one public port).

A token names its scene and its creator: the user (or API key), or for an anonymous browser the 3D cookie it
was given with the token. Only the creator may drive or open the scene (403 VIZ_FOREIGN otherwise). Every
route that starts work is rate-limited per user or address; live scenes are capped (server/viz.py)."""

from __future__ import annotations

import asyncio
import contextlib
import dataclasses
import logging
import re
import secrets
from collections.abc import Mapping
from typing import Any, Literal

from fastapi import APIRouter, Depends, Request, Response, WebSocket, WebSocketDisconnect
from pydantic import BaseModel, Field
from sqlalchemy.orm import Session
from starlette.concurrency import run_in_threadpool

from core.scene.payload import SceneDeviation, ScenePayload
from server import access, services, viz
from server.config import Settings
from server.db import Database
from server.deps import (
    ANONYMOUS,
    HEAVY,
    SESSION_COOKIE,
    AppSettings,
    AppWorkers,
    DbSession,
    OptionalPrincipal,
    PracticePrincipal,
    Principal,
    client_address,
    rate_limit,
    resolve,
)
from server.errors import ApiError, responses
from server.jobs import (
    is_lathe,
    job_picture_now,
    job_picture_svg,
    job_scene,
    job_stock_after,
    job_turned_after,
    job_turned_chunks,
    job_view_deviation,
)
from server.schemas import ProgramRequest, SimulateRequest

log = logging.getLogger("paltrainer.server")
router = APIRouter(prefix="/viz", tags=["3d view"])
pages = APIRouter(include_in_schema=False)

NEW_LIMIT = [Depends(rate_limit("viz", "rate_viz_per_minute"))]
# scenes, deviations and pictures are heavy requests too: at most PALTRAINER_HEAVY_JOBS_PER_USER at a time
SCENE_LIMIT = [Depends(rate_limit("viz-scene", "rate_viz_scene_per_minute")), HEAVY]
STEP_LIMIT = [Depends(rate_limit("viz-step", "rate_viz_playhead_per_minute"))]
PICTURE_LIMIT = [Depends(rate_limit("picture", "rate_picture_per_minute")), HEAVY]
_COOKIE_VALUE = re.compile(r"^[A-Za-z0-9_-]{16,64}$")


class VizSession(BaseModel):
    token: str = Field(description="Signed, short-lived; names this browser session's scene and its creator")
    url: str = Field(description="The page to embed (an iframe)")


class SceneResult(BaseModel):
    segments: int
    cut: bool = Field(description="The toolpath had more segments than the view shows (20,000)")
    lines: list[int] = Field(description="The block line of each segment, for the playhead")
    errors: int
    states: Mapping[int, Mapping[str, Any]] = Field(
        description="Per block line: plane, G90/G91, compensation, "
        "zero offset, feed, speed, tool, position after it "
        "(on a lathe x is the radius)"
    )
    lathe: bool = Field(
        default=False,
        description="A turning dialect: the lathe's drawing view (Z right, X up, "
        "the chuck left) with the part turned from the blank",
    )
    blank: dict[str, float] | None = Field(
        default=None,
        description="Turning: the blank shown (diameter, inner_diameter, length, clamp, jaw_radius; mm)",
    )


class Playhead(BaseModel):
    index: int = Field(ge=0)


class Section(BaseModel):
    half: bool = Field(
        description="Turning: cut the part open (the back half and the cut face) or show it whole"
    )


class View(BaseModel):
    view: Literal["iso", "top", "front", "reset"] = Field(description="reset: the iso view again")
    aspect: float | None = Field(default=None, gt=0, le=10, description="The view's width / height in pixels")


class Layers(BaseModel):
    rapid: bool | None = None
    feed: bool | None = None
    contour: bool | None = Field(default=None, description="The programmed contour (under G41/G42)")
    stock: bool | None = None


class Deviation(BaseModel):
    too_much: int = Field(description="Cells where too much material was removed (shown red)")
    too_little: int = Field(description="Cells where too much material is left (shown blue)")
    too_much_mm3: float = Field(description="Volume removed that must stay, mm³ (beyond the tolerance band)")
    too_little_mm3: float = Field(description="Volume left standing that must go, mm³")
    largest_mm: float = Field(description="The largest deviation beyond the tolerance band, mm")


def _scenes(request: Request | WebSocket) -> viz.Scenes:
    scenes: viz.Scenes = request.app.state.scenes
    return scenes


def _who(principal: Principal, cookie: str | None) -> str:
    """Who is asking, as tokens name their creators."""
    if principal.user is not None:
        return f"user:{principal.user.id}"
    if principal.api_key is not None:
        return f"key:{principal.api_key.prefix}"
    return f"anon:{cookie}" if cookie and _COOKIE_VALUE.match(cookie) else "anon:-"


def _ticket(scenes: viz.Scenes, token: str, who: str) -> viz.Ticket:
    ticket = scenes.ticket(token)
    if ticket is None:  # another replica's token: that replica stopped (the page opens a scene here)
        raise ApiError("VIZ_ELSEWHERE" if scenes.elsewhere(token) else "BAD_TOKEN")
    if ticket.owner != who or who == "anon:-":
        raise ApiError("VIZ_FOREIGN")
    return ticket


def _scene(request: Request, token: str, principal: Principal) -> viz.Scene:
    ticket = _ticket(_scenes(request), token, _who(principal, request.cookies.get(viz.VIZ_COOKIE)))
    return _scenes(request).scene(ticket)


def _allowed(database: Database, principal: Principal, action: access.Action, exercise: str | None) -> None:
    """server/access.py on the 3D view: an exam that runs for the trainee may switch it off; the deviation
    compares with a reference an exam may withhold; nobody unknown sees an exercise of a running exam."""
    with database.session() as db:
        access.check(db, principal, action, exercise)


async def _gate(request: Request, principal: Principal, action: access.Action, exercise: str | None) -> None:
    await run_in_threadpool(_allowed, request.app.state.db, principal, action, exercise)


def _spec(make: Any, db: Session, settings: Settings, body: Any) -> dict[str, Any]:
    """The worker's set-up (services.run_spec or simulate_spec), in the threadpool; then the pooled connection
    goes back while the worker runs (as for submissions)."""
    spec: dict[str, Any] = make(db, settings, body)
    db.commit()
    return spec


async def _driven(request: Request, token: str, principal: Principal) -> viz.Scene:
    """The scene of a token for the calls that move what it shows (playhead, section, view, layers)."""
    scene = await run_in_threadpool(_scene, request, token, principal)
    await _gate(request, principal, "viz", scene.exercise)
    return scene


@router.post(
    "", response_model=VizSession, status_code=201, responses=responses(401, 429), dependencies=NEW_LIMIT
)
def new_session(
    request: Request, response: Response, db: DbSession, settings: AppSettings, principal: PracticePrincipal
) -> VizSession:
    """A token for a new scene of this user, key or (anonymous) browser; an anonymous browser gets its 3D
    cookie with it (HttpOnly), which its later calls must carry. Refused while an exam without 3D runs for the
    trainee."""
    access.check(db, principal, "viz")
    cookie = request.cookies.get(viz.VIZ_COOKIE)
    if principal is ANONYMOUS and (not cookie or not _COOKIE_VALUE.match(cookie)):
        cookie = secrets.token_urlsafe(24)
    if principal is ANONYMOUS:
        response.set_cookie(
            viz.VIZ_COOKIE,
            cookie or "",
            httponly=True,
            samesite="strict",
            secure=settings.cookie_secure,
            path="/",
        )
    owner = _who(principal, cookie)
    quota = f"ip:{client_address(request)}" if principal is ANONYMOUS else owner
    token = _scenes(request).new_token(owner, quota)
    return VizSession(token=token, url=f"/viz/{token}/")


@router.post(
    "/{token}/scene",
    response_model=SceneResult,
    responses=responses(401, 403, 404, 410, 413, 422, 429, 503),
    dependencies=SCENE_LIMIT,
)
async def put_scene(
    token: str,
    body: SimulateRequest,
    request: Request,
    db: DbSession,
    settings: AppSettings,
    workers: AppWorkers,
    principal: PracticePrincipal,
) -> SceneResult:
    """Run the program (in a worker) and show its toolpath, the stock after it and the tool. The stock: the
    request's, else the exercise's, else the PAL examples' block; `resolution` is the view's own (0.5 mm).
    A turning program (TRAUB) is shown in the lathe's drawing view — Z right, X up, the chuck on the left —
    with the part turned from the blank (the request's, the exercise's, else a bar around the program) in
    chunks along Z (`lathe` and `blank` in the answer)."""
    await _gate(
        request, principal, "viz", body.exercise
    )  # an exam that runs for the trainee may switch 3D off
    scene = await run_in_threadpool(_scene, request, token, principal)
    spec = await run_in_threadpool(_spec, services.simulate_spec, db, settings, body)
    if body.blank is not None:
        spec["blank"] = body.blank.model_dump()
    spec["half"] = scene.half
    shown: ScenePayload = await workers.call(job_scene, body.program, body.dialect, spec)
    generation = await run_in_threadpool(viz.show, scene, shown)
    scene.program, scene.exercise = (body.program, body.dialect, spec), body.exercise
    if (
        shown.stock is not None and shown.stock.fine is not None
    ):  # the coarse level is out; the fine one follows
        scene.refining = asyncio.create_task(
            run_in_threadpool(viz.show_stock, scene, shown.stock.fine, generation)
        )
        scene.refining.add_done_callback(_log_failure)
    return SceneResult(
        segments=len(shown.playback.segments),
        cut=shown.cut,
        lines=shown.playback.lines,
        errors=shown.errors,
        states=shown.states,
        lathe=shown.lathe,
        blank=dataclasses.asdict(shown.turned.blank) if shown.turned else None,
    )


def _log_failure(task: asyncio.Task[Any]) -> None:
    if not task.cancelled() and task.exception() is not None:
        log.error("3D view: the fine stock could not be shown", exc_info=task.exception())


@router.post("/{token}/playhead", responses=responses(401, 403, 410, 429), dependencies=STEP_LIMIT)
async def put_playhead(
    token: str, body: Playhead, request: Request, workers: AppWorkers, principal: PracticePrincipal
) -> dict[str, Any]:
    """Move the tool to the end of toolpath segment `index` and show the stock after its move; answers that
    segment's block line and, for a move a cycle made, the cycle ({code, pass, of}; PAL: defined_in_line)."""
    scene = await _driven(request, token, principal)
    line = await run_in_threadpool(viz.playhead, scene, body.index)
    playback = scene.playback
    move = playback.move_at(body.index) if playback is not None else None
    if scene.has_stock and scene.program is not None and move is not None:
        text, dialect, spec = scene.program
        if scene.lathe:  # the turned part after that move, its changed chunks only
            turned = await workers.call(
                job_turned_after, text, dialect, {**spec, "half": scene.half}, move + 1
            )
            await run_in_threadpool(viz.show_turned, scene, turned)
        else:
            tiles = await workers.call(job_stock_after, text, dialect, spec, move + 1)
            await run_in_threadpool(viz.show_stock, scene, tiles)
    cycle = playback.cycles.get(move) if playback is not None and move is not None else None
    return {"index": body.index, "line": line, "cycle": cycle}


@router.post("/{token}/section", responses=responses(401, 403, 410, 422, 429, 503), dependencies=STEP_LIMIT)
async def put_section(
    token: str, body: Section, request: Request, workers: AppWorkers, principal: PracticePrincipal
) -> dict[str, bool]:
    """Turning: cut the part open along the drawing plane to show bores and grooves (the back half with the cut
    face, the chuck halved too) or show it whole; kept for the session's next programs. Answers the state."""
    scene = await _driven(request, token, principal)
    chunks = None
    if scene.lathe and scene.profile is not None:
        chunks = await workers.call(job_turned_chunks, scene.profile, body.half)
    return {"half": await run_in_threadpool(viz.set_half, scene, body.half, chunks)}


@router.post("/{token}/view", responses=responses(401, 403, 410, 422, 429), dependencies=STEP_LIMIT)
async def put_view(token: str, body: View, request: Request, principal: PracticePrincipal) -> dict[str, str]:
    """Point the camera at the part from above, from the front or from the front right above (iso), the part
    centred and filling the view."""
    scene = await _driven(request, token, principal)
    await run_in_threadpool(viz.set_view, scene, body.view, body.aspect)
    return {"view": scene.view}


@router.post("/{token}/layers", responses=responses(401, 403, 410, 422, 429), dependencies=STEP_LIMIT)
async def put_layers(
    token: str, body: Layers, request: Request, principal: PracticePrincipal
) -> dict[str, bool]:
    """Show or hide the rapid moves, the feed moves, the programmed contour and the stock; answers all four."""
    scene = await _driven(request, token, principal)
    return await run_in_threadpool(viz.set_layers, scene, body.model_dump(exclude_none=True))


@router.post(
    "/{token}/deviation",
    response_model=Deviation,
    responses=responses(401, 403, 404, 410, 413, 422, 429, 503),
    dependencies=SCENE_LIMIT,
)
async def put_deviation(
    token: str,
    body: ProgramRequest,
    request: Request,
    db: DbSession,
    settings: AppSettings,
    workers: AppWorkers,
    principal: PracticePrincipal,
) -> Deviation:
    """Colour the part of a program for an exercise where it leaves the tolerance band of the reference
    (after grading: red too much removed, blue too much left), with the volumes in mm³ and the largest
    deviation in mm."""
    scene = await run_in_threadpool(_scene, request, token, principal)
    if body.exercise is None:
        raise ApiError("EXERCISE_REQUIRED")
    await _gate(request, principal, "deviation", body.exercise)  # it compares with the reference
    spec = await run_in_threadpool(_spec, services.run_spec, db, settings, body)
    deviation: SceneDeviation = await workers.call(
        job_view_deviation, body.program, {**spec, "half": scene.half}
    )
    await run_in_threadpool(viz.show_deviation, scene, deviation)
    return Deviation(
        too_much=deviation.too_much_count,
        too_little=deviation.too_little_count,
        too_much_mm3=round(deviation.too_much_mm3, 2),
        too_little_mm3=round(deviation.too_little_mm3, 2),
        largest_mm=round(deviation.largest_mm, 3),
    )


@router.post(
    "/picture.png",
    response_class=Response,
    dependencies=PICTURE_LIMIT,
    responses={
        200: {
            "content": {"image/png": {}},
            "description": "The stock after the program, from above (darker = deeper)",
        },
        **responses(401, 413, 422, 429, 503),
    },
)
async def picture(
    body: SimulateRequest,
    request: Request,
    db: DbSession,
    settings: AppSettings,
    workers: AppWorkers,
    principal: PracticePrincipal,
) -> Response:
    """The stock after the program seen from above, rendered on the server: what the page shows while the 3D
    view is off (no graphics acceleration). Needs no 3D session. For a turning program (TRAUB): the turned
    part after it as a half section in the lathe's drawing view, Z right, X up (header `X-Picture-View: lathe`)."""
    await _gate(request, principal, "viz", body.exercise)  # the 3D view's stand-in follows its rules
    body.resolution = max(body.resolution, 0.25)  # a picture of at most 480 pixels needs no finer cells
    spec = await run_in_threadpool(_spec, services.simulate_spec, db, settings, body)
    png: bytes = await workers.call(job_picture_now, body.program, body.dialect, spec)
    # a turning program's picture is its turned part in half section (the page words its caption so)
    view = {"X-Picture-View": "lathe"} if is_lathe(body.dialect) else {}
    return Response(png, media_type="image/png", headers={"Cache-Control": "no-store", **view})


@router.post(
    "/picture.svg",
    response_class=Response,
    dependencies=PICTURE_LIMIT,
    responses={
        200: {"content": {"image/svg+xml": {}}, "description": "The 2D picture of the program's result"},
        **responses(401, 413, 422, 429, 503),
    },
)
async def picture_svg(
    body: SimulateRequest,
    request: Request,
    db: DbSession,
    settings: AppSettings,
    workers: AppWorkers,
    principal: PracticePrincipal,
    lang: Literal["de", "en"] = "de",
) -> Response:
    """The 2D view of the program's result, rendered on the server as SVG: what the page shows while the 3D view
    is off (no graphics acceleration). Milling: the plan view — the stock's outline, the depths as a colour
    ramp with its legend in mm, the tool-centre path (rapid dashed, feed solid), the programmed contour, axes
    with coordinates, the workpiece zero and the blocks an error kept from running. Turning (TRAUB): the
    drawing view, Z right, X up, the part in half section with the same path and marks. The height map has at
    most 400 cells along the stock's longer side (0.25 mm at the finest) and the path at most 8000 points;
    the headers say what was drawn (`X-Picture-View` mill or lathe, `X-Picture-Raster`, `X-Picture-Cell`,
    `X-Picture-Path-Cut`)."""
    await _gate(request, principal, "viz", body.exercise)  # the 3D view's stand-in follows its rules
    spec = await run_in_threadpool(_spec, services.simulate_spec, db, settings, body)
    if body.blank is not None:
        spec["blank"] = body.blank.model_dump()
    data: dict[str, Any] = await workers.call(job_picture_svg, body.program, body.dialect, spec, lang)
    info = data["info"]
    headers = {
        "Cache-Control": "no-store",
        "X-Picture-View": str(info.get("view", "mill")),
        "X-Picture-Path-Cut": str(info.get("path_cut", "false")),
    }
    if "raster" in info:
        headers.update({"X-Picture-Raster": str(info["raster"]), "X-Picture-Cell": str(info["cell"])})
    return Response(data["svg"].encode("utf-8"), media_type="image/svg+xml", headers=headers)


@pages.get("/viz/{token}/")
def viewer(token: str, request: Request, principal: OptionalPrincipal) -> Response:
    scenes = _scenes(request)
    ticket = scenes.ticket(token)
    if ticket is None and scenes.elsewhere(token):
        return Response(
            "Diese 3D-Ansicht lief auf einem anderen Server – bitte die Seite neu laden.",
            status_code=410,
            media_type="text/plain",
        )
    if ticket is None:
        return Response(
            "Sitzung abgelaufen – bitte die Seite neu laden.", status_code=401, media_type="text/plain"
        )
    if ticket.owner != _who(principal, request.cookies.get(viz.VIZ_COOKIE)):
        return Response(
            "Diese 3D-Ansicht gehört zu einer anderen Sitzung.", status_code=403, media_type="text/plain"
        )
    scenes.scene(ticket)
    return Response(viz.viser_page(), media_type="text/html", headers={"Cache-Control": "no-cache"})


def _ws_who(database: Database, settings: Settings, ws: WebSocket, exercise: str | None) -> str | None:
    """Who opens the viewer's socket, if the 3D view is allowed to them now (server/access.py); else None."""
    try:
        with database.session() as db:
            principal = resolve(db, settings, None, None, ws.cookies.get(SESSION_COOKIE))
            access.check(db, principal, "viz", exercise)
    except ApiError:
        return None
    return _who(principal, ws.cookies.get(viz.VIZ_COOKIE))


@pages.websocket("/viz/{token}")
@pages.websocket("/viz/{token}/")
async def viewer_socket(ws: WebSocket, token: str) -> None:
    scenes = _scenes(ws)
    ticket = scenes.ticket(token)
    offered = [p.strip() for p in ws.headers.get("sec-websocket-protocol", "").split(",") if p.strip()]
    protocol = next((p for p in offered if p.startswith("viser-v")), None)
    shown = scenes.live(ticket) if ticket else None
    who = (
        await run_in_threadpool(
            _ws_who, ws.app.state.db, ws.app.state.settings, ws, shown.exercise if shown else None
        )
        if ticket
        else None
    )
    if ticket is None or protocol is None or who != ticket.owner:
        await ws.close(code=4410 if scenes.elsewhere(token) else 4403)
        return
    scene = await run_in_threadpool(scenes.scene, ticket)
    await ws.accept(subprotocol=protocol)
    await viz.bridge(ws, scene.port, protocol)


@pages.websocket("/viz/{token}/alive")
async def alive_socket(ws: WebSocket, token: str) -> None:
    """Open as long as this replica holds the token's scene: the page watches it (web/src/viz.js) and opens a
    new scene, on another replica, as soon as it closes. Says nothing; closes 4410 for another replica's token
    (that replica stopped) and 4401 for an invalid one."""
    scenes = _scenes(ws)
    if scenes.ticket(token) is None:
        await ws.close(code=4410 if scenes.elsewhere(token) else 4401)
        return
    await ws.accept()
    with contextlib.suppress(WebSocketDisconnect):
        while True:
            await ws.receive_text()  # the page sends nothing; this waits for its close
