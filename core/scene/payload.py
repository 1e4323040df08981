"""The scene payload: what the 3D view shows of one program run, defined once.

A worker builds it from the run (`mill_scene`, `lathe_scene`: pure functions of the toolpath, the tool table
and the simulation's result); server/viz.py puts it into the session's scene and keeps its `Playback` for
the playhead; the 3D routes answer from it. The same for the turned part after a playback step
(`TurnedPart`) and the deviation after grading (`SceneDeviation`). Scene mm; a lathe program is already
turned into the lathe's drawing view (core/scene/camera.py: LATHE_AXES).
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass
from typing import TypedDict

import numpy as np
import numpy.typing as npt

from core.diagnostics import Severity
from core.grading import Deviation
from core.grading.turning import ProfileDeviation
from core.pipeline import drawing
from core.scene.camera import LATHE_AXES, Box
from core.scene.meshes import InsertShape, Mesh, Segments, Tiles, ToolShape, Vec3, insert_shape
from core.scene.turned import TurnedProfile, ViewBlank, deviation_band
from core.sim.insert import insert_of
from core.toolpath import CycleJson, Toolpath
from core.tools import ToolTable

MAX_SCENE_SEGMENTS = 20_000  # toolpath segments sent to the 3D view; beyond, the path is cut (and said so)
DRAW_TOLERANCE = 0.05  # mm: arcs as chords that stray at most this far
Points = npt.NDArray[np.float32]  # (n, 3)


class LineState(TypedDict):
    """What is active after a block line, as the page shows it beside the playhead (the program's coordinates:
    on a lathe x is the radius)."""

    plane: str | None
    dimensions: str | None
    compensation: str | None
    zero_offset: str | None
    feed: float
    speed: float
    tool: int | None
    position: list[float]


@dataclass(frozen=True, eq=False)
class StockLevels:
    """The stock after the program as tiles: the coarse level of detail first (also during playback), the fine
    one right after it (milling; None: no finer level)."""

    coarse: Tiles
    fine: Tiles | None = None


@dataclass(frozen=True, eq=False)
class TurnedPart:
    """A turning program's part as the view shows it: its profile (kept for the half-section toggle), the blank
    and the chuck that holds it, its chunks along Z (the stock's tiles)."""

    profile: TurnedProfile
    blank: ViewBlank
    chunks: Tiles


@dataclass(frozen=True, eq=False)
class Playback:
    """Per toolpath segment, what the playhead needs: where it is, its block line, its move, the tool that cuts
    it; and the tools' shapes and the moves' cycles."""

    segments: Segments  # (n, 2, 3), one segment per move piece (arcs as chords)
    lines: list[int]
    moves: list[int]  # the move each segment belongs to (playback shows the stock after that move)
    tools: list[int | None]  # the tool number of each segment
    centre: list[bool]  # lathe: the segment's end is the nose centre (under SRK), not the theoretical tip
    cycles: dict[int, CycleJson]  # move index → the cycle that made it (playback names its step)
    shapes: dict[int, ToolShape | InsertShape]  # tool number → how it is drawn (the tool table's)
    tool_radius: float  # the last tool's radius: a tool without a table entry is a cylinder of it

    def move_at(self, index: int) -> int | None:
        """The move of segment `index` (beyond the end: the last segment's); None without segments."""
        return self.moves[min(max(index, 0), len(self.moves) - 1)] if self.moves else None


@dataclass(frozen=True, eq=False)
class ScenePayload:
    """What the 3D view shows of a program: the toolpath (feed, rapid, the programmed contour where it differs
    from the tool-centre path), the modal state per line, the stock or turned part after it, the tool at the
    end."""

    playback: Playback
    feed: Segments
    rapid: Segments
    contour: Segments
    states: dict[int, LineState]
    tool: Vec3  # where the tool is after the program
    stock: StockLevels | None  # milling: the stock's tiles; turning: the turned part's chunks; None: none
    turned: TurnedPart | None  # turning: the part, its profile and blank
    lathe: bool
    cut: bool  # the toolpath had more segments than the view shows (MAX_SCENE_SEGMENTS, PAL-I019)
    errors: int


@dataclass(frozen=True, eq=False)
class SceneDeviation:
    """Where a program's part leaves the exercise's tolerance band, as the view colours it: milling the surface
    points of the cells (`cell` mm wide), turning revolved `bands` on the part; too much removed (red) and too
    much left (blue) each. The counts are cells or Z samples; the volumes as the geometry criterion counts
    them."""

    too_much: Points
    too_little: Points
    cell: float
    bands: dict[str, Mesh] | None  # turning: {"too_much", "too_little"}
    too_much_count: int
    too_little_count: int
    too_much_mm3: float = 0.0
    too_little_mm3: float = 0.0
    largest_mm: float = 0.0


NO_POINTS: Points = np.zeros((0, 3), np.float32)
NO_DEVIATION = SceneDeviation(NO_POINTS, NO_POINTS, 0.0, None, 0, 0)


def _states(toolpath: Toolpath, lines: list[int]) -> dict[int, LineState]:
    states: dict[int, LineState] = {}
    for line in sorted(set(lines)):
        state, position = toolpath.state_at(line)
        codes = state.codes
        states[line] = {
            "plane": codes.get("plane"),
            "dimensions": codes.get("dimensions"),
            "compensation": codes.get("compensation"),
            "zero_offset": codes.get("zero_offset"),
            "feed": state.feed,
            "speed": state.speed,
            "tool": state.tool,
            "position": [round(v, 3) for v in position],
        }
    return states


def mill_scene(toolpath: Toolpath, tools: ToolTable, stock: StockLevels | None) -> ScenePayload:
    """A program's scene: its moves as segments (at most MAX_SCENE_SEGMENTS, arcs as chords within
    DRAW_TOLERANCE, the drawing's own budget counted first: PAL-I019), the stock after it, the tool at the end
    with its shape from the tool table."""
    segments: list[tuple[Vec3, Vec3]] = []
    rapid: list[bool] = []
    lines: list[int] = []
    moves: list[int] = []
    cycles: dict[int, CycleJson] = {}
    contour: list[tuple[Vec3, Vec3]] = []  # the programmed contour where it differs from the tool-centre path
    drawn, notice = drawing(toolpath, DRAW_TOLERANCE)  # the chords are counted before they are made
    for k, (m, points) in enumerate(zip(toolpath.moves, drawn, strict=False)):
        for a, b in itertools.pairwise(points):
            segments.append((a, b))
            rapid.append(m.kind == "rapid")
            lines.append(m.line)
            moves.append(k)
        cycle = m.cycle_json()
        if cycle is not None:
            cycles[k] = cycle
        if m.programmed_end is not None and m.programmed_end != m.end:
            contour.append((contour[-1][1] if contour else m.programmed_end, m.programmed_end))
    cut = notice is not None or len(segments) > MAX_SCENE_SEGMENTS
    segments, rapid = segments[:MAX_SCENE_SEGMENTS], rapid[:MAX_SCENE_SEGMENTS]
    lines, moves = lines[:MAX_SCENE_SEGMENTS], moves[:MAX_SCENE_SEGMENTS]
    seg = np.asarray(segments, dtype=np.float32).reshape(-1, 2, 3)
    is_rapid = np.asarray(rapid, dtype=bool)
    numbers = [toolpath.moves[k].tool for k in moves]
    last = toolpath.moves[-1] if toolpath.moves else None
    tool = tools.get(last.tool) if last is not None and last.tool is not None else None
    shapes: dict[int, ToolShape | InsertShape] = {
        n: ToolShape.of(t) for n in set(numbers) if n is not None and (t := tools.get(n)) is not None
    }
    playback = Playback(
        seg, lines, moves, numbers, [False] * len(moves), cycles, shapes, tool.radius if tool else 3.0
    )
    return ScenePayload(
        playback,
        feed=seg[~is_rapid],
        rapid=seg[is_rapid],
        contour=np.asarray(contour, dtype=np.float32).reshape(-1, 2, 3),
        states=_states(toolpath, lines),
        tool=toolpath.final_position,
        stock=stock,
        turned=None,
        lathe=False,
        cut=cut,
        errors=sum(d.severity is Severity.ERROR for d in toolpath.diagnostics),
    )


def _to_lathe(segments: Segments) -> Segments:
    """Segments of the program's (x = radius, y, z) in the lathe's drawing view."""
    turned: Segments = (np.asarray(segments, dtype=np.float64).reshape(-1, 2, 3) @ LATHE_AXES.T).astype(
        np.float32
    )
    return turned


def lathe_scene(toolpath: Toolpath, tools: ToolTable, inserts: ToolTable, turned: TurnedPart) -> ScenePayload:
    """A turning program's scene (`mill_scene` of its moves, x = radius) in the lathe's drawing view: the part
    turned from the blank with the chuck, the turret's tools as their inserts (`inserts`: the lathe's tool
    table), under SRK the nose centre's path. The modal states keep the program's coordinates (the page shows
    X as a diameter) and name the plane G18."""
    path = mill_scene(toolpath, tools, None)
    centre = [
        m.programmed_end is not None and bool(np.any(np.abs(np.subtract(m.programmed_end, m.end)) > 1e-6))
        for m in toolpath.moves
    ]
    p = path.playback
    playback = Playback(
        _to_lathe(p.segments),
        p.lines,
        p.moves,
        p.tools,
        [centre[k] for k in p.moves],
        p.cycles,
        {n: insert_shape(insert_of(inserts.get(n), n)) for n in set(p.tools) if n is not None},
        p.tool_radius,
    )
    x, y, z = (float(v) for v in LATHE_AXES @ np.asarray(path.tool, dtype=np.float64))
    states: dict[int, LineState] = {
        line: {**state, "plane": state["plane"] or "G18"} for line, state in path.states.items()
    }
    return ScenePayload(
        playback,
        feed=_to_lathe(path.feed),
        rapid=_to_lathe(path.rapid),
        contour=_to_lathe(path.contour),
        states=states,
        tool=(x, y, z),
        stock=StockLevels(turned.chunks),
        turned=turned,
        lathe=True,
        cut=path.cut,
        errors=path.errors,
    )


def part_box(scene: ScenePayload) -> Box | None:
    """The part's box (mm), for the camera: the stock, else the cutting moves, else the whole path; a lathe's
    with the spindle axis in it (the part is seen as in the drawing, from X0 up) and the chuck's jaws."""
    if scene.stock is not None:
        pts = np.vstack([vertices for _, vertices, _ in scene.stock.coarse.values()])
        if scene.lathe and len(scene.feed):  # the turned part and where the tool cuts (from Z2, say)
            pts = np.vstack([pts, scene.feed.reshape(-1, 3)])
    elif len(scene.feed):
        pts = scene.feed.reshape(-1, 3)
    elif len(scene.playback.segments):
        pts = scene.playback.segments.reshape(-1, 3)
    else:
        return None
    lo, hi = pts.min(axis=0).astype(np.float64), pts.max(axis=0).astype(np.float64)
    if scene.lathe:
        lo[2], hi[2] = min(lo[2], 0.0), max(hi[2], 0.0)
        if scene.turned is not None:
            lo[0] -= 0.08 * float(hi[0] - lo[0]) + 5.0
    return lo, hi


def milled_deviation(d: Deviation) -> SceneDeviation:
    """A milled part's deviation (core.grading.deviation) as the view colours it: the cells' surface points."""
    area = d.part.grid.dx * d.part.grid.dy
    too_much, too_little = d.points("over"), d.points("left")
    return SceneDeviation(
        too_much,
        too_little,
        d.part.grid.dx,
        None,
        len(too_much),
        len(too_little),
        float(d.over.sum()) * area,
        float(d.left.sum()) * area,
        float(max(d.over.max(initial=0.0), d.left.max(initial=0.0))),
    )


def turned_deviation(dev: ProfileDeviation, half: bool) -> SceneDeviation:
    """A turned part's deviation (core.grading.turning.compare_profiles) as the view colours it: revolved
    strips on the submitted part where it leaves the band, the counts in Z samples."""
    part = dev.part
    return SceneDeviation(
        NO_POINTS,
        NO_POINTS,
        0.0,
        {
            "too_much": deviation_band(part, dev.over_outer > 0, dev.over_inner > 0, half),
            "too_little": deviation_band(part, dev.left_outer > 0, dev.left_inner > 0, half),
        },
        int(np.count_nonzero((dev.over_outer > 0) | (dev.over_inner > 0))),
        int(np.count_nonzero((dev.left_outer > 0) | (dev.left_inner > 0))),
        dev.over_volume,
        dev.left_volume,
        max(
            float(np.max(a, initial=0.0))
            for a in (dev.over_outer, dev.left_outer, dev.over_inner, dev.left_inner)
        ),
    )
