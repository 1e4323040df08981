"""The milling simulation: a toolpath run against a box of stock held as a height map.

`simulate` walks the interpreter's commands in execution order. Every move lowers the height map
to the swept envelope of the tool's cutting part (core/sim/sweep.py) on the cells under the move's
bounding box only; the checks that need more (volume cut at rapid, plunging, shank and holder) run
only where they can fire. Events are diagnostics from the catalogue, with the line of the block.
"""

from __future__ import annotations

import dataclasses
import itertools
import math
from collections.abc import Iterator, Mapping
from dataclasses import dataclass, field

import numpy as np

from core.diagnostics import Diagnostic, diag
from core.sim.shapes import Array, Cutter, cutter_of, flat
from core.sim.sweep import Grid, arc_envelope, line_envelope
from core.sim.tooltable import DEFAULT_SIM_TOOLS
from core.syntax.blocks import Span
from core.toolpath import Dwell, Move, ToolChange, Toolpath, Vec3
from core.tools import Tool, ToolTable

DEFAULT_RESOLUTION = 0.1  # mm; the grading resolution
NO_LINE = Span(0, 0, 0, 0)  # events of the run as a whole (line 0)


@dataclass(frozen=True, slots=True)
class Stock:
    """A box of stock between two corners in workpiece coordinates (mm)."""

    x0: float
    y0: float
    z0: float
    x1: float
    y1: float
    z1: float

    def __post_init__(self) -> None:
        values = (self.x0, self.y0, self.z0, self.x1, self.y1, self.z1)
        if not all(math.isfinite(v) and abs(v) <= 100_000 for v in values):
            raise ValueError("stock corners must be finite numbers within ±100000 mm")
        if not (self.x1 > self.x0 and self.y1 > self.y0 and self.z1 > self.z0):
            raise ValueError("stock: the second corner must be greater than the first in X, Y and Z")

    @property
    def volume(self) -> float:
        return (self.x1 - self.x0) * (self.y1 - self.y0) * (self.z1 - self.z0)


@dataclass(frozen=True, slots=True)
class Machine:
    """The machine profile: rates and times for the cycle time, and the parts that can collide."""

    rapid_rate: float = 10_000.0  # mm/min along the straight path of a rapid move
    tool_change_time: float = 6.0  # s per tool change
    holder_diameter: float = 63.0  # mm; the holder's bottom sits at the tool's overall length
    spindle_diameter: float = 80.0  # mm; what hits the stock when no tool is in the spindle
    table_z: float | None = None  # top of the machine table; None: the stock's base
    touch_tolerance: float = 0.01  # mm; a cell lowered by less than this is touched, not cut
    core_fraction: float = 0.1  # radius of the non-cutting centre of a non-centre-cutting tool / radius


@dataclass(frozen=True, slots=True)
class SimLimits:
    """Explicit limits of one simulation; hitting one is an event, never a hang."""

    max_cells: int = 16_000_000  # cells of the height map (coarser cells beyond, SIM-W002)
    max_cell_updates: int = 2_000_000_000  # cells visited over all moves (then SIM-E010, stop)
    max_events: int = 100  # further events are dropped with one SIM-W003
    max_pieces: int = 20_000  # pieces one move is split into (helix chords, long diagonals)


@dataclass(frozen=True, slots=True)
class HeightMap:
    """The stock after machining: `heights[j, i]` is the top of the material over cell (i, j)."""

    grid: Grid
    base: float
    top: float
    heights: Array

    def volume(self) -> float:
        h = np.clip(self.heights, self.base, self.top)
        return float(np.sum(h - self.base, dtype=np.float64)) * self.grid.dx * self.grid.dy


@dataclass(frozen=True, slots=True)
class SimResult:
    stock: Stock
    resolution: float  # mm; the cell size used (the requested one unless SIM-W002)
    heightmap: HeightMap
    removed_volume: float  # mm³
    remaining_volume: float  # mm³
    cycle_time: float  # s
    time_per_tool: dict[int | None, float]  # s; None: moves and dwells with no tool
    events: list[Diagnostic]
    diagnostics: list[Diagnostic]  # the interpreter's, passed through
    cell_updates: int
    complete: bool  # False: stopped at a limit (SIM-E010)


@dataclass
class _Events:
    limit: int
    items: list[Diagnostic] = field(default_factory=list)
    seen: set[tuple[str, int]] = field(default_factory=set)
    full: bool = False

    def add(self, d: Diagnostic) -> None:
        key = (d.code, d.span.line)
        if key in self.seen or self.full:
            return
        self.seen.add(key)
        if len(self.items) >= self.limit - 1:
            self.items.append(diag("SIM-W003", d.span, limit=self.limit))
            self.full = True
            return
        self.items.append(d)


class _Stop(Exception):
    pass


def make_grid(stock: Stock, resolution: float, limits: SimLimits) -> tuple[Grid, float]:
    """The cells covering `stock` at about `resolution` mm, coarsened to at most `limits.max_cells`."""
    if not (math.isfinite(resolution) and resolution > 0):
        raise ValueError("resolution must be a positive number of mm")
    w, h = stock.x1 - stock.x0, stock.y1 - stock.y0
    res = resolution
    while True:
        nx, ny = max(1, round(w / res)), max(1, round(h / res))
        if nx * ny <= limits.max_cells:
            break
        res = max(res * math.sqrt(nx * ny / limits.max_cells) * 1.001, res * 1.001)
    return Grid(stock.x0, stock.y0, w / nx, h / ny, nx, ny), res


def simulate(
    toolpath: Toolpath,
    stock: Stock,
    tools: ToolTable = DEFAULT_SIM_TOOLS,
    resolution: float = DEFAULT_RESOLUTION,
    machine: Machine | None = None,
    *,
    expected_diameters: Mapping[int, float] | None = None,
    limits: SimLimits | None = None,
) -> SimResult:
    """Machine `stock` along `toolpath`: the stock left, removed volume, cycle time and events.

    `expected_diameters` maps a T number to the diameter an exercise states for it (SIM-W001 when
    the table differs). Raises ValueError only for an invalid resolution; bad programs give events.
    """
    machine = machine or Machine()
    limits = limits or SimLimits()
    grid, used = make_grid(stock, resolution, limits)
    events = _Events(limits.max_events)
    if used != resolution:
        events.add(
            diag(
                "SIM-W002", NO_LINE, requested=float(resolution), used=round(used, 4), limit=limits.max_cells
            )
        )
    heights = np.full((grid.ny, grid.nx), stock.z1, dtype=np.float64)
    run = _Run(grid, heights, stock, tools, machine, limits, events)
    complete = True
    try:
        run.all(toolpath, expected_diameters or {})
    except _Stop:
        complete = False
    hm = HeightMap(grid, stock.z0, stock.z1, np.clip(heights, stock.z0, stock.z1))
    remaining = hm.volume()
    total = float(grid.nx * grid.ny) * grid.dx * grid.dy * (stock.z1 - stock.z0)
    return SimResult(
        stock,
        used,
        hm,
        total - remaining,
        remaining,
        sum(run.times.values()),
        dict(run.times),
        events.items,
        list(toolpath.diagnostics),
        run.updates,
        complete,
    )


class _Run:
    """The mutable state of one simulation (private to `simulate`)."""

    def __init__(
        self,
        grid: Grid,
        heights: Array,
        stock: Stock,
        tools: ToolTable,
        machine: Machine,
        limits: SimLimits,
        events: _Events,
    ) -> None:
        self.grid, self.h, self.stock, self.tools = grid, heights, stock, tools
        self.machine, self.limits, self.events = machine, limits, events
        self.table_z = stock.z0 if machine.table_z is None else machine.table_z
        self.times: dict[int | None, float] = {}
        self.current: int | None = None  # the tool in the spindle
        self.updates = 0
        self.shift: dict[int | None, float] = {}  # tip Z − programmed Z per tool (TC length + TL)
        self.cell_area = grid.dx * grid.dy

    def _time(self, tool: int | None, seconds: float) -> None:
        self.times[tool] = self.times.get(tool, 0.0) + seconds

    def all(self, toolpath: Toolpath, expected: Mapping[int, float]) -> None:
        for c in toolpath.commands:
            if isinstance(c, Move) and c.kind == "arc" and c.plane != "G17":
                # arcs in the planes G18/G19 (ISO, Beckhoff) as chords within a quarter cell, at most max_pieces
                pts = c.points(self.grid.dx / 4, max_chords=self.limits.max_pieces)
                for a, b in itertools.pairwise(pts):
                    self.move(
                        dataclasses.replace(
                            c,
                            kind="feed",
                            start=a,
                            end=b,
                            center=None,
                            direction=None,
                            radius=None,
                            angle=None,
                        )
                    )
            elif isinstance(c, Move):
                self.move(c)
            elif isinstance(c, Dwell):
                self._time(self.current, c.seconds)
            elif isinstance(c, ToolChange):
                self.tool_change(c, expected)

    def tool_change(self, c: ToolChange, expected: Mapping[int, float]) -> None:
        self.current = c.tool
        self._time(c.tool, self.machine.tool_change_time)
        if c.tool is None:
            return
        tool = self.tools.get(c.tool)
        if tool is None:
            self.events.add(diag("SIM-E009", c.span, tool=c.tool))
            return
        self.shift[c.tool] = tool.offset(c.tc).length + c.tl - tool.length
        want = expected.get(c.tool)
        if want is not None and abs(want - tool.diameter) > 1e-6:
            self.events.add(
                diag("SIM-W001", c.span, tool=c.tool, actual=float(tool.diameter), expected=float(want))
            )

    # --- one move ---------------------------------------------------------------------------

    def move(self, mv: Move) -> None:
        length = _length(mv)
        if mv.kind == "rapid":
            seconds = length / self.machine.rapid_rate * 60
        else:
            rate = mv.feed * mv.spindle if mv.feed_unit == "mm/rev" else mv.feed
            seconds = length / rate * 60 if rate > 0 else 0.0
        self.current = mv.tool
        self._time(mv.tool, seconds)
        dz = self.shift.get(mv.tool, 0.0)
        zmin = min(mv.start[2], mv.end[2]) + dz
        if zmin < self.table_z - 1e-6:
            self.events.add(diag("SIM-E005", mv.span, z=round(zmin, 4), base=float(self.table_z)))
        if zmin >= self.stock.z1:
            return
        if mv.tool is None:
            nose = flat(self.machine.spindle_diameter / 2)
            for a, b, arc in _pieces(mv, dz, nose.radius, self.grid, self.limits, self.stock.z1):
                win, env = self._envelope(mv, nose, a, b, arc, 0.0)
                if win is not None and env is not None and self._hits(win, env):
                    self.events.add(diag("SIM-E007", mv.span))
                    return
            return
        tool = self.tools.get(mv.tool)
        if tool is None:
            self.events.add(diag("SIM-E009", mv.span, tool=mv.tool))
            return
        self._cut(mv, tool, cutter_of(tool), dz, zmin)

    def _cut(self, mv: Move, tool: Tool, cutter: Cutter, dz: float, zmin: float) -> None:
        tol = self.machine.touch_tolerance
        watch_volume = mv.kind == "rapid" or mv.spindle == 0 or mv.feed == 0
        plunging = not tool.centre_cutting and mv.end[2] < mv.start[2] - 1e-9
        shank_r = max(tool.shank, tool.diameter) / 2
        holder_r = self.machine.holder_diameter / 2
        check_shank = zmin + tool.flute_length < self.stock.z1
        check_holder = zmin + tool.length < self.stock.z1
        reach = max(cutter.radius, shank_r if check_shank else 0.0, holder_r if check_holder else 0.0)
        volume = 0.0
        for a, b, arc in _pieces(mv, dz, reach, self.grid, self.limits, self.stock.z1):
            win, env = self._envelope(mv, cutter, a, b, arc, 0.0)
            if win is None or env is None:
                continue
            j0, j1, i0, i1 = win
            sub = self.h[j0:j1, i0:i1]
            if watch_volume:
                cut = sub - env
                volume += float(np.sum(cut[cut > tol])) * self.cell_area
            if plunging and b[2] < a[2]:
                core = flat(
                    max(cutter.radius * self.machine.core_fraction, 1.5 * max(self.grid.dx, self.grid.dy))
                )
                w2, e2 = self._envelope(mv, core, a, b, arc, 0.0)
                if w2 is not None and e2 is not None and self._hits(w2, e2):
                    self.events.add(diag("SIM-E002", mv.span, tool=mv.tool))
            if check_shank:
                self._collide(mv, "SIM-E003", shank_r, tool.flute_length, a, b, arc, zmin)
            if check_holder:
                self._collide(mv, "SIM-E004", holder_r, tool.length, a, b, arc, zmin)
            if zmin < self.stock.z0:
                np.maximum(env, self.stock.z0, out=env)
            np.minimum(sub, env, out=sub)
        if volume > 0:
            if mv.kind == "rapid":
                self.events.add(diag("SIM-E001", mv.span, volume=round(volume, 1)))
            elif mv.spindle == 0:
                self.events.add(diag("SIM-E006", mv.span, volume=round(volume, 1)))
            elif mv.feed == 0:
                self.events.add(diag("SIM-E008", mv.span, volume=round(volume, 1)))

    def _collide(
        self, mv: Move, code: str, radius: float, above: float, a: Vec3, b: Vec3, arc: bool, zmin: float
    ) -> None:
        """`code` when a flat cylinder of `radius` whose bottom is `above` mm over the tip meets material."""
        win, env = self._envelope(mv, flat(radius), a, b, arc, above)
        if win is None or env is None:
            return
        j0, j1, i0, i1 = win
        sub = self.h[j0:j1, i0:i1]
        over = sub - env > self.machine.touch_tolerance
        if over.any():
            depth = float(np.max(sub[over])) - zmin
            self.events.add(diag(code, mv.span, tool=mv.tool, depth=round(depth, 3), length=float(above)))

    def _hits(self, win: tuple[int, int, int, int], env: Array) -> bool:
        j0, j1, i0, i1 = win
        return bool(np.any(self.h[j0:j1, i0:i1] - env > self.machine.touch_tolerance))

    def _envelope(
        self, mv: Move, c: Cutter, a: Vec3, b: Vec3, arc: bool, above: float
    ) -> tuple[tuple[int, int, int, int] | None, Array | None]:
        a2 = (a[0], a[1], a[2] + above)
        b2 = (b[0], b[1], b[2] + above)
        if arc:
            assert mv.center is not None and mv.angle is not None
            cx, cy = mv.center[0], mv.center[1]
            xmin, xmax, ymin, ymax = _arc_box(mv)
        else:
            cx = cy = 0.0
            xmin, xmax = min(a[0], b[0]), max(a[0], b[0])
            ymin, ymax = min(a[1], b[1]), max(a[1], b[1])
        r = c.radius
        win = self.grid.window(xmin - r, xmax + r, ymin - r, ymax + r)
        if win is None:
            return None, None
        j0, j1, i0, i1 = win
        cells = (j1 - j0) * (i1 - i0)
        self.updates += cells
        if self.updates > self.limits.max_cell_updates:
            self.events.add(diag("SIM-E010", mv.span, limit=self.limits.max_cell_updates))
            raise _Stop
        if arc:
            assert mv.angle is not None
            env = arc_envelope(
                self.grid, win, c, a2, b2, (cx, cy, a2[2]), mv.direction == "ccw", math.radians(mv.angle)
            )
        else:
            env = line_envelope(self.grid, win, c, a2, b2)
        return win, env


def _length(mv: Move) -> float:
    dz = mv.end[2] - mv.start[2]
    if mv.kind == "arc" and mv.radius is not None and mv.angle is not None:
        return math.hypot(mv.radius * math.radians(mv.angle), dz)
    return math.dist(mv.start, mv.end)


def _arc_box(mv: Move) -> tuple[float, float, float, float]:
    """Bounding box in XY of a planar arc."""
    assert mv.center is not None and mv.angle is not None
    cx, cy = mv.center[0], mv.center[1]
    r = math.hypot(mv.start[0] - cx, mv.start[1] - cy)
    xs, ys = [mv.start[0], mv.end[0]], [mv.start[1], mv.end[1]]
    t0 = math.atan2(mv.start[1] - cy, mv.start[0] - cx)
    sweep = math.radians(mv.angle)
    ccw = mv.direction == "ccw"
    for k in range(4):
        t = k * math.pi / 2
        rel = ((t - t0) if ccw else (t0 - t)) % (2 * math.pi)
        if rel <= sweep + 1e-12:
            xs.append(cx + r * math.cos(t))
            ys.append(cy + r * math.sin(t))
    return min(xs), max(xs), min(ys), max(ys)


def _pieces(
    mv: Move, dz: float, reach: float, grid: Grid, limits: SimLimits, top: float
) -> Iterator[tuple[Vec3, Vec3, bool]]:
    """The move as (start, end, is_planar_arc) pieces with the tip shift `dz` applied, without the part of
    a straight move that lies above `top` (the stock's top).

    A planar arc stays one piece; a helix becomes chords with a sagitta under a quarter cell; a
    long diagonal line becomes pieces about a tool diameter long so that the windows stay tight.
    """
    a = (mv.start[0], mv.start[1], mv.start[2] + dz)
    b = (mv.end[0], mv.end[1], mv.end[2] + dz)
    cell = max(grid.dx, grid.dy)
    if mv.kind == "arc" and mv.center is not None and mv.angle is not None:
        if abs(b[2] - a[2]) < 1e-9:
            yield a, b, True
            return
        cx, cy = mv.center[0], mv.center[1]
        r = math.hypot(a[0] - cx, a[1] - cy)
        sweep = math.radians(mv.angle)
        step = 2 * math.acos(max(-1.0, 1 - cell / 4 / r)) if r > cell / 4 else sweep
        n = min(limits.max_pieces, max(1, math.ceil(sweep / max(step, 1e-9))))
        t0 = math.atan2(a[1] - cy, a[0] - cx)
        sign = 1.0 if mv.direction == "ccw" else -1.0
        prev = a
        for k in range(1, n + 1):
            if k == n:
                nxt = b
            else:
                t = t0 + sign * sweep * k / n
                nxt = (cx + r * math.cos(t), cy + r * math.sin(t), a[2] + (b[2] - a[2]) * k / n)
            yield prev, nxt, False
            prev = nxt
        return
    if max(a[2], b[2]) > top > min(a[2], b[2]):  # the part above the stock's top cannot touch it
        t = (top - a[2]) / (b[2] - a[2])
        cut = (a[0] + (b[0] - a[0]) * t, a[1] + (b[1] - a[1]) * t, top)
        a, b = (cut, b) if a[2] > top else (a, cut)
    ddx, ddy = abs(b[0] - a[0]), abs(b[1] - a[1])
    length = math.hypot(ddx, ddy)
    box = (ddx + 2 * reach) * (ddy + 2 * reach)
    swept = 2 * reach * length + math.pi * reach * reach
    if box <= 2 * swept or length < 1e-9:
        yield a, b, False
        return
    n = min(limits.max_pieces, math.ceil(length / max(2 * reach, 4 * cell)))
    prev = a
    for k in range(1, n + 1):
        nxt = (
            b
            if k == n
            else (a[0] + (b[0] - a[0]) * k / n, a[1] + (b[1] - a[1]) * k / n, a[2] + (b[2] - a[2]) * k / n)
        )
        yield prev, nxt, False
        prev = nxt
