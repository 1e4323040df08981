"""The 3D view: one viser scene per browser session, reached through the app's own port.

Each session gets a `ViserServer` on 127.0.0.1 (port chosen by the system), made when first asked for
and stopped after it has been idle. The page embeds `/viz/{token}/`; the token is signed and short-lived
and names the session. The WebSocket `/viz/{token}` bridges to the session's viser and lets only the
client→server messages through that the view needs (never the share-tunnel request). The geometry is
core/scene's, computed in worker processes (server/jobs.py); this module only hands its arrays to viser:
the nodes, their colours and materials, the camera and what the layers and the playhead show.
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
import re
import threading
import time
import uuid
from dataclasses import dataclass, field
from importlib import resources
from typing import Any

import jwt
import numpy as np

from core.scene.camera import FOV, Box, camera_for, home
from core.scene.meshes import (
    InsertShape,
    Tiles,
    ToolShape,
    dashed,
    footprint,
    insert_mesh,
    insert_meshes,
    spindle_axis,
    stock_outline,
    tool_mesh,
)
from core.scene.payload import Playback, SceneDeviation, ScenePayload, TurnedPart, part_box
from core.scene.turned import TurnedProfile, ViewBlank, chuck_meshes

log = logging.getLogger("paltrainer.server")

TOKEN_MINUTES = 30
VIZ_COOKIE = "paltrainer_viz"  # an anonymous browser's 3D id: its tokens drive only its own scenes
# client → server messages the view may send; everything else (ShareUrlRequest, FileTransfer…) is dropped
ALLOWED_CLIENT_MESSAGES = frozenset(
    {
        "ViewerCameraMessage",
        "ScenePointerMessage",
        "SceneNodeClickMessage",
        "SceneNodeDragMessage",
        "GuiUpdateMessage",
        "GuiButtonHoldMessage",
        "GuiFormSubmitMessage",
        "GuiFormDirtyMessage",
        "TransformControlsUpdateMessage",
        "TransformControlsDragStartMessage",
        "TransformControlsDragEndMessage",
        "GetRenderResponseMessage",
    }
)
# the colours of docs/UI.md (the page's legend shows the same)
FEED_COLOUR = (21, 101, 192)  # feed moves: solid blue
RAPID_COLOUR = (239, 108, 0)  # rapid moves: dashed orange
CURRENT_COLOUR = (220, 20, 60)
STOCK_COLOUR = (184, 190, 201)
BACKGROUND = (198, 205, 215)
TOO_MUCH_COLOUR = (198, 40, 40)  # deviation after grading: material removed that must stay (red)
TOO_LITTLE_COLOUR = (30, 136, 229)  # material left that must go (blue)
CONTOUR_COLOUR = (46, 125, 50)  # the programmed contour (green), beside the tool-centre path under G41/G42
TOOL_COLOUR = (150, 160, 172)  # the cutting part; the shank darker, the cutting edges dark
SHANK_COLOUR = (95, 102, 112)
OUTLINE_COLOUR = (88, 96, 108)  # the stock's box, thin
EDGE_COLOUR = (40, 44, 52)
TOOL_OPACITY = 0.45
M = 0.001  # the scene is in metres (viser's camera and grid are made for them); the product speaks mm
LAYERS = ("rapid", "feed", "contour", "stock")
# the turn of core/scene/camera.py's LATHE_AXES (the lathe's drawing view) for the zero's axes: X up, Z right
LATHE_ZERO = (0.0, float(np.sqrt(0.5)), 0.0, float(np.sqrt(0.5)))
AXIS_COLOUR = (70, 76, 86)  # the spindle axis, dash-dotted as on a drawing
INSERT_COLOUR = (120, 130, 142)
CUT_COLOUR = (222, 184, 135)  # the cut face of the half section, like the hatched area of a section drawing
CHUCK_COLOUR = (84, 90, 100)
JAW_COLOUR = (128, 136, 148)


def viser_page() -> bytes:
    """viser's single-file client (everything inlined: no CDN) with our stylesheet, which hides viser's own
    panel, connection status, WebSocket address and notices: the page around it has the controls. Its
    application evaluates no string as code (`viser_client`), so the page runs under a policy without
    'unsafe-eval'. Made once per process."""
    with _PAGE_LOCK:
        global _PAGE
        if _PAGE is None:
            page = (resources.files("viser") / "client" / "build" / "index.html").read_bytes()
            page = page.replace(b"</head>", b'<link rel="stylesheet" href="/static/viz-frame.css"></head>', 1)
            _PAGE = _repacked(page)
        return _PAGE


_PAGE: bytes | None = None
_PAGE_LOCK = threading.Lock()
# viser's client page: an inline loader unpacks the application (stylesheet and module script, zstd, in the
# base-88 attribute data-p; data-ss and data-cs their sizes in bytes) and inserts it as an inline script
ZSTD_LEVEL = 9
_PACKED = re.compile(rb'data-p="([^"]*)"|data-ss="(\d+)"|data-cs="(\d+)"')
BASE88 = b"!#$%()*+,-./0123456789:;=?@ABCDEFGHIJKLMNOPQRSTUVWXYZ[\\]^_abcdefghijklmnopqrstuvwxyz{|}~"
# The two places where viser's application evaluates text as code (Function(…)), both for what this view never
# shows: (1) at load it sets up the sorter of Gaussian splats, WebAssembly bound with embind, which builds its
# call wrappers from strings — under a policy without 'unsafe-eval' that is an uncaught EvalError on every page
# load; it is set up on first use instead (a splat, which our scenes never contain). (2) A server message may
# carry JavaScript to run (RunJavascriptMessage, never sent by us): such a message runs nothing. (3) An idle view
# draws its scene again every second, a safety net for changes that ask for no frame (every change of our scenes
# asks for one): without graphics acceleration each such frame costs the processor, so an idle view redraws every
# ten seconds instead (VIEW_REDRAW_MS).
VIEW_REDRAW_MS = 10_000
CLIENT_PATCHES = (
    (
        # (?<!…): a name starts at a name's first character, not at each of its characters (10x faster)
        re.compile(
            rb"(?<![\w$])([\w$]+)=fetch\(([\w$]+)\)\.then\(e=>e\.arrayBuffer\(\)\)\.then\(e=>([\w$]+)\(\{wasmBinary:e\}\)\)"
        ),
        (
            rb"\1={then:(ok$,no$)=>(\1.p??=fetch(\2).then(e=>e.arrayBuffer()).then(e=>\3({wasmBinary:e})))"
            rb".then(ok$,no$)}"
        ),
    ),
    (
        re.compile(rb"case`RunJavascriptMessage`:Function\([\w$]+\.source\)\(\);return;"),
        rb"case`RunJavascriptMessage`:return;",
    ),
    (
        re.compile(rb"(\.requestRender\(\);let [\w$]+=setInterval\(\(\)=>[\w$]+\(\),)[A-Za-z_$][\w$]*\)"),
        rb"\g<1>%d)" % VIEW_REDRAW_MS,
    ),
)


def _warm_page() -> None:
    with contextlib.suppress(Exception):  # the first request for the page says what went wrong
        viser_page()


def base88_decode(text: bytes) -> bytes:
    """viser's base-88 (five digits for four bytes, big-endian; a rest of k + 1 digits for k bytes)."""
    digits = np.zeros(256, dtype=np.uint64)
    digits[np.frombuffer(BASE88, dtype=np.uint8)] = np.arange(len(BASE88), dtype=np.uint64)
    whole = len(text) - len(text) % 5
    groups = digits[np.frombuffer(text[:whole], dtype=np.uint8)].reshape(-1, 5)
    values = np.zeros(len(groups), dtype=np.uint64)
    for column in range(5):
        values = values * np.uint64(88) + groups[:, column]
    out = values.astype(">u4").tobytes()
    if len(text) > whole:
        rest = 0
        for c in text[whole:]:
            rest = rest * 88 + BASE88.index(c)
        out += rest.to_bytes(len(text) - whole - 1, "big")
    return out


def base88_encode(data: bytes) -> bytes:
    whole = len(data) - len(data) % 4
    values = np.frombuffer(data[:whole], dtype=">u4").astype(np.uint64)
    table = np.frombuffer(BASE88, dtype=np.uint8)
    columns = [table[(values // np.uint64(88**k)) % np.uint64(88)] for k in range(4, -1, -1)]
    out = np.stack(columns, axis=1).tobytes() if len(values) else b""
    if len(data) > whole:
        rest, tail = int.from_bytes(data[whole:], "big"), b""
        for _ in range(len(data) - whole + 1):
            rest, digit = divmod(rest, 88)
            tail = BASE88[digit : digit + 1] + tail
        out += tail
    return out


def viser_client(page: bytes) -> tuple[bytes, bytes] | None:
    """The stylesheet and the application script packed in viser's page; None if it is packed otherwise."""
    import zstandard

    found = {m.lastindex: m.group(m.lastindex) for m in _PACKED.finditer(page) if m.lastindex}
    if set(found) != {1, 2, 3}:
        return None
    style, code = int(found[2]), int(found[3])
    raw = zstandard.ZstdDecompressor().decompress(base88_decode(found[1]), max_output_size=style + code)
    return raw[:style], raw[style : style + code]


def _repacked(page: bytes) -> bytes:
    """The page with its application patched (CLIENT_PATCHES) and packed again as viser packs it; the page
    as it is (and a log line) where viser packs it otherwise or a patch finds nothing to change."""
    import zstandard

    unpacked = viser_client(page)
    if unpacked is None:
        log.warning("3D view: viser's page is not packed as expected; served as it is")
        return page
    style, code = unpacked
    for pattern, replacement in CLIENT_PATCHES:
        code, count = pattern.subn(replacement, code)
        if count == 0:
            log.warning(
                "3D view: a change to viser's client did not apply; served as it is",
                extra={"job": pattern.pattern[:60].decode("ascii", "replace")},
            )
            return page
    # level 9: 80 ms for viser's 2,7 MB; level 19 packs it 7 % smaller (631 against 679 kB) but takes 1,3 s of CPU at
    # every server start, and under load several seconds
    packed = base88_encode(zstandard.ZstdCompressor(level=ZSTD_LEVEL).compress(style + code))
    sizes = {1: b'data-p="' + packed + b'"', 2: b'data-ss="%d"' % len(style), 3: b'data-cs="%d"' % len(code)}
    return _PACKED.sub(lambda m: sizes[m.lastindex or 1], page)


@dataclass(frozen=True)
class Ticket:
    """What a 3D token says: the scene, who may drive it, and whose cap of live scenes it counts in."""

    sid: str
    owner: str  # "user:<id>", "key:<prefix>" or "anon:<the browser's 3D cookie>"
    quota: str  # "user:<id>", "key:<prefix>" or, for an anonymous browser, "ip:<address>"

    @property
    def owner_kind(self) -> str:
        return {"anon": "anonymous"}.get(self.owner.split(":", 1)[0], self.owner.split(":", 1)[0])


@dataclass
class Scene:
    """One session's viser server and what it shows."""

    server: Any
    port: int
    ticket: Ticket | None = None
    started: float = field(default_factory=time.monotonic)
    used: float = field(default_factory=time.monotonic)
    playback: Playback | None = None  # the toolpath's segments shown, for the playhead
    # the shape the tool node shows now (a turning tool without a table entry: its nose radius)
    tool_key: ToolShape | InsertShape | float | None = None
    framed: bool = False  # the camera has been pointed at the part
    bounds: Box | None = None  # the part's box (payload.part_box), mm
    aspect: float = 1.3  # the view's width / height, as the page last said
    view: str = "iso"
    layers: dict[str, bool] = field(default_factory=lambda: dict.fromkeys(LAYERS, True))
    nodes: dict[str, Any] = field(
        default_factory=dict
    )  # the handles of the nodes the layers and playback move
    has_stock: bool = False
    lathe: bool = False  # a turning program: the lathe's drawing view (camera.LATHE_AXES), the turned part
    half: bool = False  # the turned part cut open (half section)
    profile: TurnedProfile | None = None  # the turned part shown (its chunks: the stock tiles)
    blank: ViewBlank | None = None  # and its blank
    chuck_key: tuple[ViewBlank, bool] | None = None  # the blank and cut the chuck node shows now
    program: tuple[str, str, dict[str, Any]] | None = None  # text, dialect, worker spec of what is shown
    exercise: str | None = None  # the exercise of what is shown (server/access.py asks about it)
    tiles: dict[str, str] = field(default_factory=dict)  # stock tile shown → its digest (resend only changes)
    generation: int = 0  # counts scene and playhead updates: a late refinement of an older one is dropped
    refining: Any = None  # the task that sends the fine level of detail after the coarse one
    lock: threading.Lock = field(default_factory=threading.Lock)


class Scenes:
    """The sessions' scenes, and the tokens that reach them. Live scenes are capped per user (or key), per
    address (anonymous browsers) and in all; making room stops the scene idle the longest."""

    def __init__(self, secret: str, settings: Any = None) -> None:
        self._secret = secret
        self.per_user = int(getattr(settings, "viz_sessions_per_user", 3))
        self.per_address = int(getattr(settings, "viz_sessions_per_address", 40))
        self.total = int(getattr(settings, "viz_sessions_max", 200))
        self.idle_seconds = float(getattr(settings, "viz_idle_seconds", 900.0))
        self.replica = str(
            getattr(settings, "replica_id", "") or ""
        )  # the tokens' prefix (deploy/haproxy.cfg)
        self._scenes: dict[str, Scene] = {}
        self._lock = threading.Lock()
        if (
            _PAGE is None
        ):  # viser's page is unpacked, changed and packed again once (about 1.5 s): not on a request
            threading.Thread(target=_warm_page, name="viser-page", daemon=True).start()

    # -- tokens ---------------------------------------------------------------------------------
    def new_token(self, owner: str = "anon:-", quota: str = "ip:-") -> str:
        sid = uuid.uuid4().hex
        payload = {
            "sid": sid,
            "kind": "viz",
            "own": owner,
            "quota": quota,
            "exp": int(time.time()) + TOKEN_MINUTES * 60,
        }
        signed = jwt.encode(payload, self._secret, algorithm="HS256")
        return f"{self.replica}.{signed}" if self.replica else signed

    def elsewhere(self, token: str) -> bool:
        """The token names another replica: its scene lives there (or died with it), never here."""
        return bool(self.replica) and replica_of(token) != self.replica

    def ticket(self, token: str) -> Ticket | None:
        """What a token of this replica says; None if it is invalid, expired or another replica's."""
        if replica_of(token) != self.replica:
            return None
        try:
            payload = jwt.decode(".".join(token.split(".")[-3:]), self._secret, algorithms=["HS256"])
        except jwt.PyJWTError:
            return None
        if payload.get("kind") != "viz" or not payload.get("sid") or not payload.get("own"):
            return None
        return Ticket(str(payload["sid"]), str(payload["own"]), str(payload.get("quota") or payload["own"]))

    def sid_of(self, token: str) -> str | None:
        found = self.ticket(token)
        return found.sid if found else None

    # -- scenes ---------------------------------------------------------------------------------
    def live(self, ticket: Ticket) -> Scene | None:
        """The ticket's scene if it is live (nothing is started)."""
        with self._lock:
            return self._scenes.get(ticket.sid)

    def scene(self, ticket: Ticket) -> Scene:
        """The ticket's scene, started if it is not live (after making room within the caps)."""
        stopped: list[tuple[Scene, str]] = []
        try:
            with self._lock:
                now = time.monotonic()
                stopped += [(s, "idle") for s in self._take(lambda s: now - s.used > self.idle_seconds)]
                found = self._scenes.get(ticket.sid)
                if found is None:
                    cap = self.per_address if ticket.quota.startswith("ip:") else self.per_user
                    stopped += [
                        (s, "evicted")
                        for s in self._make_room(
                            lambda s: s.ticket is not None and s.ticket.quota == ticket.quota, cap
                        )
                    ]
                    stopped += [(s, "evicted") for s in self._make_room(lambda s: True, self.total)]
                    found = self._scenes[ticket.sid] = _new_scene(ticket)
                    log.info(
                        "3D view started",
                        extra={
                            "viz": {
                                "session": ticket.sid[:8],
                                "owner": ticket.owner_kind,
                                "port": found.port,
                                "live": len(self._scenes),
                            }
                        },
                    )
                found.used = time.monotonic()
                return found
        finally:
            for s, reason in stopped:
                _stop(s, reason)

    def _take(self, which: Any) -> list[Scene]:
        gone = [sid for sid, s in self._scenes.items() if which(s)]
        return [self._scenes.pop(sid) for sid in gone]

    def _make_room(self, which: Any, cap: int) -> list[Scene]:
        """Take the scenes idle the longest among `which` until one more fits under `cap`."""
        mine = sorted((s for s in self._scenes.values() if which(s)), key=lambda s: s.used)
        gone = mine[: max(0, len(mine) - max(cap, 1) + 1)]
        for s in gone:
            if s.ticket is not None:
                self._scenes.pop(s.ticket.sid, None)
        return gone

    def sids(self) -> set[str]:
        with self._lock:
            return set(self._scenes)

    def stop_all(self) -> None:
        with self._lock:
            scenes = list(self._scenes.values())
            self._scenes.clear()
        for s in scenes:
            _stop(s, "shutdown")

    def __len__(self) -> int:
        return len(self._scenes)


def replica_of(token: str) -> str:
    """The replica a 3D token names: "r2.eyJ…" (a JWT has three parts; a fourth in front names the replica
    that made it, REPLICA_ID) → "r2"; a token without one is a single server's → ""."""
    parts = token.split(".")
    return parts[0] if len(parts) == 4 else ""


def _stop(scene: Scene, reason: str) -> None:
    with contextlib.suppress(Exception):
        scene.server.stop()
    ticket = scene.ticket
    log.info(
        "3D view stopped",
        extra={
            "viz": {
                "session": ticket.sid[:8] if ticket else "-",
                "owner": ticket.owner_kind if ticket else "-",
                "reason": reason,
                "seconds": round(time.monotonic() - scene.started, 1),
            }
        },
    )


def _quiet_viser() -> None:
    """viser prints a banner per server (and "Server stopped") with rich straight to standard output; our log
    has one structured line per session instead. Only what viser's own modules print is held back."""
    import sys

    import rich

    if getattr(rich.print, "_viser_quiet", False):
        return
    original = rich.print

    def print_(*objects: Any, **kwargs: Any) -> None:
        caller = sys._getframe(1).f_globals.get("__name__", "")
        if caller.startswith("viser"):
            log.debug("viser", extra={"job": str(objects[0])[:200] if objects else ""})
            return
        original(*objects, **kwargs)

    print_._viser_quiet = True  # type: ignore[attr-defined]
    rich.print = print_


def _new_scene(ticket: Ticket | None = None) -> Scene:
    import viser

    _quiet_viser()
    server = viser.ViserServer(host="127.0.0.1", port=0, verbose=False)
    server.gui.configure_theme(show_logo=False, show_share_button=False)
    server.scene.set_up_direction("+z")
    # lit by lights alone, without viser's environment map: with it a computer without graphics acceleration
    # (software WebGL, as many school computers) spends 0.6 s of processor time on every frame, without it 0.1 s.
    # No shadows (our meshes cast none). An even light and one from the front right above: the blank's top is
    # the lightest face, its front and right side differ.
    server.scene.configure_environment_map(None)
    server.scene.configure_default_lights(cast_shadow=False)
    server.scene.add_light_ambient("/light/ambient", intensity=1.0)
    server.scene.add_light_directional("/light/front", intensity=1.9, position=(0.55, -0.55, 0.9))
    server.scene.add_frame("/zero", axes_length=10 * M, axes_radius=0.4 * M)  # the workpiece zero
    # a grey-blue backdrop: the blank's lit top face is lighter, its sides darker (on white the top would vanish)
    server.scene.set_background_image(np.full((2, 2, 3), BACKGROUND, dtype=np.uint8), format="png")
    return Scene(server, server.get_port(), ticket)


def show(scene: Scene, shown: ScenePayload) -> int:
    """Put a program's result into the scene: toolpath (feed solid blue, rapid dashed orange, the programmed
    contour green), the stock's coarse level of detail, the tool at the end. Answers the scene's generation
    (for the fine level's `show_stock`)."""
    s = scene.server.scene
    with scene.lock, scene.server.atomic():
        scene.generation += 1
        lines = {
            "feed": (shown.feed, FEED_COLOUR, 2.0),
            "rapid": (dashed(shown.rapid), RAPID_COLOUR, 1.5),
            "contour": (shown.contour, CONTOUR_COLOUR, 1.5),
        }
        for name, (segments, colour, thickness) in lines.items():
            if len(segments):
                scene.nodes[name] = s.add_line_segments(
                    f"/toolpath/{name}",
                    segments * M,
                    colour,
                    thickness=thickness,
                    thickness_units="screen",
                    visible=scene.layers[name],
                )
            else:
                s.remove_by_name(f"/toolpath/{name}")
                scene.nodes.pop(name, None)
        if "stock" not in scene.nodes:
            scene.nodes["stock"] = s.add_frame("/stock", show_axes=False, visible=scene.layers["stock"])
        _put_tiles(scene, shown.stock.coarse if shown.stock is not None else {})
        s.remove_by_name("/deviation")
        scene.has_stock = shown.stock is not None
        if shown.lathe != scene.lathe:  # another kind of machine: its own zero axes and its own first view
            scene.lathe, scene.framed = shown.lathe, False
            s.add_frame(
                "/zero",
                axes_length=10 * M,
                axes_radius=0.4 * M,
                wxyz=LATHE_ZERO if shown.lathe else (1.0, 0.0, 0.0, 0.0),
            )
        turned = shown.turned
        scene.profile, scene.blank = (turned.profile, turned.blank) if turned else (None, None)
        _chuck(scene)
        bounds = part_box(shown)
        _axis(scene, bounds)
        if scene.has_stock and not shown.lathe and bounds is not None:  # the blank's edges, with the stock
            s.add_line_segments(
                "/stock/outline",
                stock_outline(*bounds) * M,
                OUTLINE_COLOUR,
                thickness=1.2,
                thickness_units="screen",
            )
        else:
            s.remove_by_name("/stock/outline")
        if bounds is not None and (
            not scene.framed
            or scene.bounds is None
            or not all(np.allclose(a, b) for a, b in zip(bounds, scene.bounds, strict=True))
        ):
            scene.bounds = bounds
            _look(scene, scene.view if scene.framed else home(scene.lathe))
        scene.playback = p = shown.playback
        last = p.tools[-1] if p.tools else None
        _tool(
            scene,
            p.shapes.get(last) if last is not None else None,
            shown.tool,
            bool(p.centre[-1]) if p.centre else False,
        )
        s.remove_by_name("/playback/current")
        return scene.generation


def _axis(scene: Scene, bounds: Box | None) -> None:
    """A lathe's spindle axis (Z), dash-dotted as the centre line of a drawing, a little beyond the part."""
    s = scene.server.scene
    if not scene.lathe or bounds is None:
        s.remove_by_name("/axis")
        return
    points = spindle_axis(float(bounds[0][0]), float(bounds[1][0]))
    s.add_line_segments("/axis", points * M, AXIS_COLOUR, thickness=1.0, thickness_units="screen")


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
        if key.startswith(
            "z"
        ):  # a chunk of a turned part: round (smooth normals), its cut face the section's
            cut = key.endswith("_cut")
            s.add_mesh_simple(
                f"/stock/{key}",
                vertices * M,
                triangles,
                color=CUT_COLOUR if cut else STOCK_COLOUR,
                flat_shading=cut,
                side="double",
                cast_shadow=False,
                receive_shadow=False,
            )
        else:
            s.add_mesh_simple(
                f"/stock/{key}",
                vertices * M,
                triangles,
                color=STOCK_COLOUR,
                flat_shading=True,
                cast_shadow=False,
                receive_shadow=False,
            )
        scene.tiles[key] = digest


def show_deviation(scene: Scene, deviation: SceneDeviation) -> None:
    """Colour the part where it leaves the tolerance band: red where too much material was removed, blue
    where too much is left — a milled part as points at the cells' centres on its surface, a turned part as
    bands around it. The camera goes back to the view that shows the whole part, so the colours are in sight
    without moving it."""
    with scene.lock, scene.server.atomic():
        s = scene.server.scene
        s.remove_by_name("/deviation")
        s.remove_by_name("/playback/current")
        size = max(deviation.cell, 0.4) * M  # at least a few pixels: a thin gouge must still show
        bands, coloured = deviation.bands or {}, False
        for name, points, colour in (
            ("too_much", deviation.too_much, TOO_MUCH_COLOUR),
            ("too_little", deviation.too_little, TOO_LITTLE_COLOUR),
        ):
            if len(points):
                s.add_point_cloud(
                    f"/deviation/{name}",
                    points * M,
                    colors=colour,
                    point_size=size,
                    point_shape="square",
                    precision="float32",
                    point_shading="flat",
                    position=(0.0, 0.0, 0.05 * M),
                )  # just above the surface, not in it
                coloured = True
            vertices, triangles = bands.get(name) or (None, ())
            if vertices is not None and len(triangles):
                coloured = True
                s.add_mesh_simple(
                    f"/deviation/{name}",
                    vertices * M,
                    triangles,
                    color=colour,
                    side="double",
                    cast_shadow=False,
                    receive_shadow=False,
                )
        if scene.bounds is not None and coloured:
            _look(scene, home(scene.lathe))


# -- the tool ----------------------------------------------------------------------------------------------


def _turning_tool(scene: Scene, shape: InsertShape | None, point: tuple[float, ...], centre: bool) -> None:
    """A turning tool as its insert (its outline from the tool table: C/D/V, grooving, thread; the nose
    radius) on its holder, in the plane of the drawing view; `point` is its theoretical tip, or under SRK
    (`centre`) its nose centre. A segment without a tool: a generic 80° insert."""
    s = scene.server.scene
    key = shape if shape is not None else 0.0
    tip = shape.position((point[0], point[1], point[2]), centre) if shape is not None else point
    position = (tip[0] * M, tip[1] * M, tip[2] * M)
    if key == scene.tool_key:
        scene.nodes["tool"].position = position
        return
    meshes, opacity, flat = (
        (insert_meshes(shape), 0.85, True) if shape is not None else (insert_mesh(), 0.7, False)
    )
    scene.nodes["tool"] = s.add_frame("/tool", show_axes=False, position=position)
    cutter_v, cutter_t = meshes.cutter
    s.add_mesh_simple(
        "/tool/cutter",
        cutter_v * M,
        cutter_t,
        color=INSERT_COLOUR,
        opacity=opacity,
        flat_shading=flat,
        side="double",
        cast_shadow=False,
        receive_shadow=False,
    )
    if meshes.shank is not None:
        holder_v, holder_t = meshes.shank
        s.add_mesh_simple(
            "/tool/shank",
            holder_v * M,
            holder_t,
            color=SHANK_COLOUR,
            opacity=TOOL_OPACITY,
            flat_shading=flat,
            side="double",
            cast_shadow=False,
            receive_shadow=False,
        )
    else:
        s.remove_by_name("/tool/shank")
    s.add_line_segments("/tool/edges", meshes.edges * M, EDGE_COLOUR, thickness=1.5, thickness_units="screen")
    scene.tool_key = key


def _tool(
    scene: Scene, shape: ToolShape | InsertShape | None, tip: tuple[float, ...], centre: bool = False
) -> None:
    """The tool, upright on its tip at `tip` (mm): built when its shape changes, else only moved. (viser's
    meshes are given in scene coordinates, Z up: nothing needs turning.) On a lathe: the turning tool, its
    theoretical tip at `tip` (or, `centre`, under SRK, its nose centre)."""
    if scene.lathe:
        if (
            scene.nodes.pop("tool_footprint", None) is not None
        ):  # the milling tool's, before a turning program
            scene.server.scene.remove_by_name("/tool/footprint")
        scene.nodes.pop("tool_body", None)
        _turning_tool(scene, shape if isinstance(shape, InsertShape) else None, tip, centre)
        return
    if not isinstance(shape, ToolShape):  # no tool table entry: a plain cylinder of the tool's radius
        shape = ToolShape.cylinder(scene.playback.tool_radius if scene.playback else 3.0)
    s = scene.server.scene
    position = (tip[0] * M, tip[1] * M, tip[2] * M)
    if shape == scene.tool_key:
        scene.nodes["tool"].position = position
        return
    meshes = tool_mesh(shape)
    assert meshes.shank is not None
    (cut_v, cut_t), (shank_v, shank_t) = meshes.cutter, meshes.shank
    scene.nodes["tool"] = s.add_frame("/tool", show_axes=False, position=position)
    body = scene.view != "top"
    # see-through: a Ø25 end mill is taller than the part and would hide what it cuts
    scene.nodes["tool_body"] = [
        s.add_mesh_simple(
            "/tool/cutter",
            cut_v * M,
            cut_t,
            color=TOOL_COLOUR,
            opacity=TOOL_OPACITY,
            cast_shadow=False,
            receive_shadow=False,
            visible=body,
        ),
        s.add_mesh_simple(
            "/tool/shank",
            shank_v * M,
            shank_t,
            color=SHANK_COLOUR,
            opacity=TOOL_OPACITY,
            cast_shadow=False,
            receive_shadow=False,
            visible=body,
        ),
        s.add_line_segments(
            "/tool/edges",
            meshes.edges * M,
            EDGE_COLOUR,
            thickness=1.5,
            thickness_units="screen",
            visible=body,
        ),
    ]
    # from above the tool would cover the part it cuts: there only the circle it cuts is drawn
    scene.nodes["tool_footprint"] = s.add_line_segments(
        "/tool/footprint",
        footprint(shape.diameter / 2) * M,
        EDGE_COLOUR,
        thickness=2.0,
        thickness_units="screen",
        visible=not body,
    )
    scene.tool_key = shape


def _tool_for_view(scene: Scene) -> None:
    """The milling tool whole in every view but the top one; from above only the circle it cuts."""
    body = scene.view != "top" or scene.lathe
    for handle in scene.nodes.get("tool_body", []):
        handle.visible = body
    if "tool_footprint" in scene.nodes:
        scene.nodes["tool_footprint"].visible = not body


# -- the camera and the layers ------------------------------------------------------------------------------


def _look(scene: Scene, view: str) -> None:
    """Point the camera (of the connected browsers, and of any that connect later) at the part."""
    if scene.bounds is None:
        return
    eye, target = camera_for(scene.bounds, view, scene.aspect, FOV, scene.lathe)
    eye_m, target_m = tuple(float(v) for v in eye * M), tuple(float(v) for v in target * M)
    size = float(np.linalg.norm(scene.bounds[1] - scene.bounds[0])) * M or 0.1
    camera = scene.server.initial_camera
    camera.position, camera.look_at = eye_m, target_m
    camera.near, camera.far, camera.fov = size / 200, size * 50, FOV
    for client in scene.server.get_clients().values():
        with contextlib.suppress(Exception):  # a browser that has not yet told its camera
            client.camera.fov = FOV
            client.camera.position, client.camera.look_at = eye_m, target_m
    scene.framed = True
    scene.view = view
    _tool_for_view(scene)


def set_view(scene: Scene, view: str, aspect: float | None = None) -> None:
    """Top, front, iso, or reset (the first view again, after the trainee turned the part: iso, on a lathe
    the drawing view from the front)."""
    with scene.lock:
        if aspect:
            scene.aspect = float(min(max(aspect, 0.2), 5.0))
        _look(scene, home(scene.lathe) if view == "reset" else view)


def set_layers(scene: Scene, layers: dict[str, bool]) -> dict[str, bool]:
    """Show or hide rapid moves, feed moves, the programmed contour, the stock."""
    with scene.lock, scene.server.atomic():
        for name, on in layers.items():
            if name not in LAYERS:
                continue
            scene.layers[name] = bool(on)
            handle = scene.nodes.get(name)
            if handle is not None:
                handle.visible = bool(on)
        return dict(scene.layers)


def playhead(scene: Scene, index: int) -> int | None:
    """Move the tool to the end of segment `index` and mark it; the block line of that segment."""
    with scene.lock:
        scene.generation += 1
        p = scene.playback
        if p is None or not len(p.segments):
            return None
        index = max(0, min(index, len(p.segments) - 1))
        seg = p.segments[index]
        s = scene.server.scene
        with scene.server.atomic():
            s.remove_by_name("/deviation")  # it belongs to the finished part
            s.add_line_segments(
                "/playback/current",
                seg[None, :, :] * M,
                CURRENT_COLOUR,
                thickness=5.0,
                thickness_units="screen",
            )
            number = p.tools[index] if index < len(p.tools) else None
            centre = index < len(p.centre) and p.centre[index]
            _tool(
                scene,
                p.shapes.get(number) if number is not None else None,
                tuple(float(v) for v in seg[1]),
                centre,
            )
        return p.lines[index] if index < len(p.lines) else None


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

    async with websockets.connect(
        f"ws://127.0.0.1:{port}",
        subprotocols=[subprotocol],  # type: ignore[list-item]
        max_size=None,
        compression=None,
    ) as upstream:

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


# -- the turned part (a lathe dialect): core/scene/turned.py's chunks and chuck ------------------------------


def _chuck(scene: Scene) -> None:
    """The chuck and its jaws at the left end of the turned part; rebuilt only when the blank or the cut changes."""
    s = scene.server.scene
    if not scene.lathe or scene.blank is None:
        if scene.chuck_key is not None:
            s.remove_by_name("/chuck")
            scene.chuck_key = None
        return
    key = (scene.blank, scene.half)
    if key == scene.chuck_key:
        return
    meshes = chuck_meshes(scene.blank, scene.half)
    s.add_frame("/chuck", show_axes=False)
    v, t = meshes.body
    s.add_mesh_simple(
        "/chuck/body", v * M, t, color=CHUCK_COLOUR, side="double", cast_shadow=False, receive_shadow=False
    )
    v, t = meshes.jaws
    s.add_mesh_simple(
        "/chuck/jaws",
        v * M,
        t,
        color=JAW_COLOUR,
        flat_shading=True,
        side="double",
        cast_shadow=False,
        receive_shadow=False,
    )
    scene.chuck_key = key


def show_turned(scene: Scene, turned: TurnedPart, generation: int | None = None) -> bool:
    """Show a turned part (after a playback step): only changed chunks are sent."""
    with scene.lock:
        if generation is not None and generation != scene.generation:
            return False
        with scene.server.atomic():
            scene.profile, scene.blank = turned.profile, turned.blank
            _put_tiles(scene, turned.chunks)
            _chuck(scene)
        return True


def set_half(scene: Scene, half: bool, chunks: Tiles | None) -> bool:
    """Cut the turned part open (a half section: the back half and the cut face) or show it whole again."""
    with scene.lock, scene.server.atomic():
        scene.half = bool(half)
        if chunks is not None and scene.lathe:
            _put_tiles(scene, chunks)
        _chuck(scene)
        return scene.half
