"""The 3D view: one viser scene per browser session, reached through the app's own port.

Each session gets a `ViserServer` on 127.0.0.1 (port chosen by the system), made when first asked for
and stopped after it has been idle. The page embeds `/viz/{token}/`; the token is signed and short-lived
and names the session. The WebSocket `/viz/{token}` bridges to the session's viser and lets only the
client→server messages through that the view needs (never the share-tunnel request). The geometry is
computed in worker processes (server/workers.py: job_scene); this module only hands arrays to viser.
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
import threading
import time
import uuid
from dataclasses import dataclass, field
from importlib import resources
from typing import Any

import jwt
import numpy as np

log = logging.getLogger("paltrainer.server")

TOKEN_MINUTES = 30
IDLE_SECONDS = 900.0
# client → server messages the view may send; everything else (ShareUrlRequest, FileTransfer…) is dropped
ALLOWED_CLIENT_MESSAGES = frozenset({
    "ViewerCameraMessage", "ScenePointerMessage", "SceneNodeClickMessage", "SceneNodeDragMessage",
    "GuiUpdateMessage", "GuiButtonHoldMessage", "GuiFormSubmitMessage", "GuiFormDirtyMessage",
    "TransformControlsUpdateMessage", "TransformControlsDragStartMessage", "TransformControlsDragEndMessage",
    "GetRenderResponseMessage",
})
FEED_COLOUR = (20, 90, 200)
RAPID_COLOUR = (230, 120, 20)
DONE_COLOUR = (160, 160, 160)
CURRENT_COLOUR = (220, 20, 60)
STOCK_COLOUR = (190, 195, 205)
TOO_MUCH_COLOUR = (215, 25, 28)  # deviation after grading: material removed that must stay
TOO_LITTLE_COLOUR = (44, 123, 182)  # material left that must go
CONTOUR_COLOUR = (30, 150, 60)  # the programmed contour, beside the tool-centre path under G41/G42
M = 0.001  # the scene is in metres (viser's camera and grid are made for them); the product speaks mm


def viser_page() -> bytes:
    """viser's single-file client (everything inlined: no CDN)."""
    return (resources.files("viser") / "client" / "build" / "index.html").read_bytes()


@dataclass
class Scene:
    """One session's viser server and what it shows."""

    server: Any
    port: int
    used: float = field(default_factory=time.monotonic)
    segments: np.ndarray | None = None  # (N, 2, 3) the toolpath, one segment per move piece
    lines: list[int] = field(default_factory=list)  # the block line of each segment
    tool_radius: float = 3.0
    framed: bool = False  # the camera has been pointed at the part
    has_stock: bool = False
    moves: list[int] = field(default_factory=list)  # the move of each segment
    program: tuple[str, str, dict[str, Any]] | None = None  # text, dialect, worker spec of what is shown
    tiles: dict[str, str] = field(default_factory=dict)  # stock tile shown → its digest (resend only changes)
    generation: int = 0  # counts scene and playhead updates: a late refinement of an older one is dropped
    refining: Any = None  # the task that sends the fine level of detail after the coarse one
    lock: threading.Lock = field(default_factory=threading.Lock)


class Scenes:
    """The sessions' scenes, and the tokens that reach them."""

    def __init__(self, secret: str) -> None:
        self._secret = secret
        self._scenes: dict[str, Scene] = {}
        self._lock = threading.Lock()

    # -- tokens ---------------------------------------------------------------------------------
    def new_token(self) -> str:
        sid = uuid.uuid4().hex
        payload = {"sid": sid, "kind": "viz", "exp": int(time.time()) + TOKEN_MINUTES * 60}
        return jwt.encode(payload, self._secret, algorithm="HS256")

    def sid_of(self, token: str) -> str | None:
        try:
            payload = jwt.decode(token, self._secret, algorithms=["HS256"])
        except jwt.PyJWTError:
            return None
        return str(payload["sid"]) if payload.get("kind") == "viz" and payload.get("sid") else None

    # -- scenes ---------------------------------------------------------------------------------
    def scene(self, sid: str) -> Scene:
        with self._lock:
            self._stop_idle()
            found = self._scenes.get(sid)
            if found is None:
                found = self._scenes[sid] = _new_scene()
            found.used = time.monotonic()
            return found

    def _stop_idle(self) -> None:
        now = time.monotonic()
        for sid, s in list(self._scenes.items()):
            if now - s.used > IDLE_SECONDS:
                del self._scenes[sid]
                with contextlib.suppress(Exception):
                    s.server.stop()

    def stop_all(self) -> None:
        with self._lock:
            for s in self._scenes.values():
                with contextlib.suppress(Exception):
                    s.server.stop()
            self._scenes.clear()

    def __len__(self) -> int:
        return len(self._scenes)


def _new_scene() -> Scene:
    import viser

    server = viser.ViserServer(host="127.0.0.1", port=0, verbose=False)
    server.gui.configure_theme(show_logo=False, show_share_button=False)
    server.scene.set_up_direction("+z")
    server.scene.add_frame("/zero", axes_length=10 * M, axes_radius=0.4 * M)  # the workpiece zero
    return Scene(server, server.get_port())


def show(scene: Scene, data: dict[str, Any]) -> int:
    """Put a program's result into the scene: toolpath (feed blue, rapid orange), the stock's coarse level of
    detail, the tool at the end. Answers the scene's generation (for the fine level's `show_stock`)."""
    s = scene.server.scene
    with scene.lock, scene.server.atomic():
        scene.generation += 1
        feed, rapid = data["feed"] * M, data["rapid"] * M
        if len(feed):
            s.add_line_segments("/toolpath/feed", feed, FEED_COLOUR, thickness=2.0, thickness_units="screen")
        else:
            s.remove_by_name("/toolpath/feed")
        if len(rapid):
            s.add_line_segments("/toolpath/rapid", rapid, RAPID_COLOUR, thickness=1.0, thickness_units="screen")
        else:
            s.remove_by_name("/toolpath/rapid")
        contour = data.get("contour")
        if contour is not None and len(contour):
            s.add_line_segments("/toolpath/contour", contour * M, CONTOUR_COLOUR, thickness=1.5,
                                thickness_units="screen")
        else:
            s.remove_by_name("/toolpath/contour")
        _put_tiles(scene, data["stock"]["coarse"] if data.get("stock") is not None else {})
        s.remove_by_name("/deviation")
        scene.has_stock = data.get("stock") is not None
        if not scene.framed:
            _frame_camera(scene, data)
        scene.segments = data["segments"]
        scene.lines = data["lines"]
        scene.moves = data.get("moves", [])
        scene.tool_radius = float(data.get("tool_radius") or 3.0)
        _tool(scene, tuple(data["tool"]) if data.get("tool") else (0.0, 0.0, 0.0))
        s.remove_by_name("/playback/current")
        return scene.generation


Tiles = dict[str, tuple[str, np.ndarray, np.ndarray]]  # key → (digest, vertices mm, triangles)


def show_stock(scene: Scene, tiles: Tiles, generation: int | None = None) -> bool:
    """Show the stock as `tiles` (e.g. the stock after the current block while playing, or the fine level
    of detail of the whole program); only tiles whose digest changed are sent. With `generation`, nothing
    happens if the scene has moved on since (answers whether it was shown)."""
    with scene.lock:
        if generation is not None and generation != scene.generation:
            return False
        with scene.server.atomic():
            _put_tiles(scene, tiles)
        return True


def _put_tiles(scene: Scene, tiles: Tiles) -> None:
    s = scene.server.scene
    for key in set(scene.tiles) - set(tiles):
        s.remove_by_name(f"/stock/{key}")
        del scene.tiles[key]
    for key, (digest, vertices, triangles) in tiles.items():
        if scene.tiles.get(key) == digest:
            continue
        s.add_mesh_simple(f"/stock/{key}", vertices * M, triangles, color=STOCK_COLOUR, flat_shading=True,
                          cast_shadow=False, receive_shadow=False)
        scene.tiles[key] = digest


def show_deviation(scene: Scene, too_much: np.ndarray, too_little: np.ndarray, cell: float) -> None:
    """Colour the part where it leaves the tolerance band: red where too much material was removed, blue
    where too much is left (points at the cells' centres on the part's surface, mm)."""
    with scene.lock, scene.server.atomic():
        s = scene.server.scene
        s.remove_by_name("/deviation")
        for name, points, colour in (("too_much", too_much, TOO_MUCH_COLOUR), ("too_little", too_little, TOO_LITTLE_COLOUR)):
            if len(points):
                s.add_point_cloud(f"/deviation/{name}", points * M, colors=colour, point_size=cell * M,
                                  point_shape="square", precision="float32",
                                  position=(0.0, 0.0, 0.02 * M))  # just above the surface, not in it


def _tool(scene: Scene, tip: tuple[float, ...]) -> None:
    """The tool as a cylinder standing on its tip (tip in mm)."""
    r = scene.tool_radius
    scene.server.scene.add_cylinder("/tool", radius=r * M, height=4 * r * M, color=CURRENT_COLOUR,
                                    position=(tip[0] * M, tip[1] * M, (tip[2] + 2 * r) * M),
                                    wxyz=_Z_UP, opacity=0.6)


_Z_UP = (0.7071068, 0.7071068, 0.0, 0.0)  # three.js cylinders stand along Y: turn them to Z


def _frame_camera(scene: Scene, data: dict[str, Any]) -> None:
    """Point the camera at the part (stock, else the cutting moves) from the front right, above."""
    if data.get("stock") is not None:
        pts = np.vstack([vertices for _, vertices, _ in data["stock"]["coarse"].values()])
    elif len(data["feed"]):
        pts = data["feed"].reshape(-1, 3)
    else:
        return
    lo, hi = pts.min(axis=0) * M, pts.max(axis=0) * M
    centre = (lo + hi) / 2
    size = float(max(hi - lo)) or 0.1
    eye = centre + np.array([0.9, -1.3, 1.1]) * size
    camera = scene.server.initial_camera
    camera.position, camera.look_at = tuple(eye), tuple(centre)
    camera.near, camera.far = size / 100, size * 100
    for client in scene.server.get_clients().values():
        client.camera.position, client.camera.look_at = tuple(eye), tuple(centre)
    scene.framed = True


def playhead(scene: Scene, index: int) -> int | None:
    """Move the tool to the end of segment `index` and mark it; the block line of that segment."""
    with scene.lock:
        scene.generation += 1
        if scene.segments is None or not len(scene.segments):
            return None
        index = max(0, min(index, len(scene.segments) - 1))
        seg = scene.segments[index]
        s = scene.server.scene
        with scene.server.atomic():
            s.remove_by_name("/deviation")  # it belongs to the finished part
            s.add_line_segments("/playback/current", seg[None, :, :] * M, CURRENT_COLOUR, thickness=5.0,
                                thickness_units="screen")
            _tool(scene, tuple(float(v) for v in seg[1]))
        return scene.lines[index] if index < len(scene.lines) else None


def passes(frame: bytes) -> bool:
    """Whether a client → server frame may reach viser: only the message types the view needs."""
    import msgspec

    try:
        message = msgspec.msgpack.decode(frame)
    except msgspec.DecodeError:
        return False
    kind = message.get("type") if isinstance(message, dict) else None
    if kind in ALLOWED_CLIENT_MESSAGES:
        return True
    log.info("viz message dropped", extra={"job": str(kind)[:60]})
    return False


async def bridge(browser: Any, port: int, subprotocol: str) -> None:
    """Relay frames between the browser's WebSocket and the session's viser until one side closes."""
    import websockets

    async with websockets.connect(f"ws://127.0.0.1:{port}", subprotocols=[subprotocol],  # type: ignore[list-item]
                                  max_size=None, compression=None) as upstream:
        async def up() -> None:
            while True:
                message = await browser.receive()
                if message["type"] == "websocket.disconnect":
                    return
                data = message.get("bytes")
                if data is None:
                    continue
                if passes(data):
                    await upstream.send(data)

        async def down() -> None:
            async for frame in upstream:
                if isinstance(frame, bytes):
                    await browser.send_bytes(frame)
                else:
                    await browser.send_text(frame)

        tasks = [asyncio.create_task(up()), asyncio.create_task(down())]
        done, pending = await asyncio.wait(tasks, return_when=asyncio.FIRST_COMPLETED)
        for t in pending:
            t.cancel()
        for t in done:
            with contextlib.suppress(Exception):
                t.result()
