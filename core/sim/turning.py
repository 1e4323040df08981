"""The turning simulation: a lathe toolpath run against a bar or tube held as a revolved profile.

The material is r_in(z) < r < r_out(z) on Z samples `resolution` mm apart (face at Z0, the bar towards
−Z, the chuck's jaws on its last `clamp` mm). The moves are the interpreter's (DECISIONS §15: x is the
radius, arcs in the plane G18): without SRK a move is the theoretical tip's path, with SRK the nose
centre's (§16). Every straight piece sweeps the insert's shape (core/sim/insert.py); an outside tool
lowers r_out to the lower envelope of that sweep, an inside tool raises r_in to its upper envelope.
Radii are exact numbers, so the radial error is the arc chords' (CHORD_TOLERANCE) alone.
Events are diagnostics from the catalogue, with the line of the block, as in the milling simulation.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from core.diagnostics import Diagnostic, diag
from core.sim.engine import NO_LINE, _Events
from core.sim.insert import Insert, insert_of, lower_envelope, lower_hull
from core.sim.shapes import Array
from core.toolpath import Dwell, Move, ToolChange, Toolpath
from core.tools import ToolTable

DEFAULT_TURNING_RESOLUTION = 0.05  # mm along Z; radii are not rounded
CHORD_TOLERANCE = 0.002  # mm: arcs become chords that stray at most this far
# Free practice: no table; every station turns with the generic outside tool (insert_of). The milling
# table is no lathe table: its drills and mills would bore on the axis.
DEFAULT_LATHE_TOOLS = ToolTable({})
Point = tuple[float, float]  # (z, x) in the drawing view
PIECE_COST = 200  # samples one swept piece counts for besides its own (its Python work) in the work limit


@dataclass(frozen=True, slots=True)
class Blank:
    """A bar (bore 0) or tube: outer and inner diameter and length in mm, the face at Z0, the bar towards −Z;
    the chuck's jaws hold its last `clamp` mm and reach out to `jaw_diameter`."""

    diameter: float
    length: float
    bore: float = 0.0
    chuck_length: float | None = None  # None: a third of the length, at most 30 mm
    jaw_diameter: float | None = None  # None: the diameter + 40 mm

    def __post_init__(self) -> None:
        values = (self.diameter, self.length, self.bore, self.chuck_length or 0.0, self.jaw_diameter or 0.0)
        if not all(math.isfinite(v) and 0 <= v <= 10_000 for v in values):
            raise ValueError("blank: sizes must be numbers within 0 … 10000 mm")
        if not (self.diameter > 0 and self.length > 0 and self.bore < self.diameter):
            raise ValueError("blank: the diameter and length must be > 0 and the bore less than the diameter")
        if self.chuck_length is not None and self.chuck_length >= self.length:
            raise ValueError("blank: the clamping length must be less than the length")
        if self.jaw_diameter is not None and self.jaw_diameter <= self.diameter:
            raise ValueError("blank: the jaws' diameter must be greater than the blank's")

    @property
    def clamp(self) -> float:
        return self.chuck_length if self.chuck_length is not None else min(30.0, self.length / 3)

    @property
    def jaw_radius(self) -> float:
        return (self.jaw_diameter if self.jaw_diameter is not None else self.diameter + 40.0) / 2

    @property
    def volume(self) -> float:
        return math.pi * (self.diameter**2 - self.bore**2) / 4 * self.length


@dataclass(frozen=True, slots=True)
class LatheMachine:
    rapid_rate: float = 12_000.0  # mm/min along the straight path of a rapid move
    tool_change_time: float = 1.0  # s per turret index
    touch_tolerance: float = 0.01  # mm: a radius changed by less than this is touched, not cut
    # mm: a rapid that takes no more than this from a face (radially or along Z, at least one Z sample) slides
    # along it: a straight retract over the clearance a pass's end leaves (lifting 1 mm from the 3° face of a
    # 93° edge takes 0.05 mm, backing 0.5 mm off the 7° minor edge of a C insert after facing 0.06 mm)
    face_tolerance: float = 0.1


@dataclass(frozen=True, slots=True)
class LatheLimits:
    max_samples: int = 400_000  # Z samples of the profile (coarser beyond, SIM-W002)
    max_updates: int = 40_000_000  # samples visited over all moves, ≈ 10 s (then SIM-E010, stop)
    max_events: int = 100
    max_chords: int = 2_000  # chords of one arc


@dataclass(frozen=True, slots=True)
class RevolvedProfile:
    """The part: sample k covers z0 + k·dz … z0 + (k+1)·dz with material between `inner[k]` and `outer[k]`."""

    z0: float
    dz: float
    outer: Array
    inner: Array
    # a cut below the surface that has not reached it yet (the clearance of a 93° tool at a shoulder leaves a
    # thin wall above it): gap_lo … gap_hi is empty although outer says material; NaN: none
    gap_lo: Array
    gap_hi: Array
    # the line of the block that last moved the outer (inner) surface of each sample, 0: never cut there
    cut_outer: npt.NDArray[np.int64]
    cut_inner: npt.NDArray[np.int64]

    @property
    def zs(self) -> Array:
        zs: Array = self.z0 + (np.arange(len(self.outer), dtype=np.float64) + 0.5) * self.dz
        return zs

    def volume(self) -> float:
        return _volume(self.outer, self.inner, self.gap_lo, self.gap_hi, self.dz)


def _area(outer: Array, inner: Array, gap_lo: Array, gap_hi: Array) -> Array:
    """r_out² − r_in² less the gap's, per sample (the material's ring area / π)."""
    o, i = np.clip(outer, 0, None), np.clip(inner, 0, None)
    area = np.clip(o**2 - i**2, 0, None)
    gap = ~np.isnan(gap_lo)
    if gap.any():
        lo = np.clip(gap_lo[gap], i[gap], o[gap])
        hi = np.clip(gap_hi[gap], i[gap], o[gap])
        area[gap] -= np.clip(hi**2 - lo**2, 0, None)
    return area


def _volume(outer: Array, inner: Array, gap_lo: Array, gap_hi: Array, dz: float) -> float:
    return float(math.pi * np.sum(_area(outer, inner, gap_lo, gap_hi), dtype=np.float64) * dz)


@dataclass(frozen=True, slots=True)
class TurningResult:
    blank: Blank
    resolution: float  # mm along Z
    profile: RevolvedProfile
    removed_volume: float  # mm³
    remaining_volume: float
    cycle_time: float  # s
    time_per_tool: dict[int | None, float]
    events: list[Diagnostic]
    diagnostics: list[Diagnostic]
    cell_updates: int
    complete: bool


class _Stop(Exception):
    pass


def simulate_turning(
    toolpath: Toolpath,
    blank: Blank,
    tools: ToolTable = DEFAULT_LATHE_TOOLS,
    resolution: float = DEFAULT_TURNING_RESOLUTION,
    machine: LatheMachine | None = None,
    *,
    limits: LatheLimits | None = None,
) -> TurningResult:
    """Turn `blank` along `toolpath`: the part left, removed volume, cycle time and events. A station that is
    not a lathe tool in `tools` turns with a generic outside tool (C 80°, R0.4, P1); a drill or mill bores
    on the axis. Raises ValueError only for an invalid resolution."""
    if not (math.isfinite(resolution) and resolution > 0):
        raise ValueError("resolution must be a positive number of mm")
    machine = machine or LatheMachine()
    limits = limits or LatheLimits()
    events = _Events(limits.max_events)
    n = max(1, round(blank.length / resolution))
    if n > limits.max_samples:
        n = limits.max_samples
        events.add(
            diag(
                "SIM-W002",
                NO_LINE,
                requested=float(resolution),
                used=round(blank.length / n, 4),
                limit=limits.max_samples,
            )
        )
    dz = blank.length / n
    profile = RevolvedProfile(
        -blank.length,
        dz,
        np.full(n, blank.diameter / 2),
        np.full(n, blank.bore / 2),
        np.full(n, np.nan),
        np.full(n, np.nan),
        np.zeros(n, dtype=np.int64),
        np.zeros(n, dtype=np.int64),
    )
    run = _Run(profile, blank, tools, machine, limits, events)
    complete = True
    try:
        run.all(toolpath)
    except _Stop:
        complete = False
    remaining = profile.volume()
    return TurningResult(
        blank,
        dz,
        profile,
        blank.volume - remaining,
        remaining,
        sum(run.times.values()),
        dict(run.times),
        events.items,
        list(toolpath.diagnostics),
        run.updates,
        complete,
    )


def _g(r: float, speed: float, limit: float) -> float:
    """∫₀ʳ dr / n(r) with n(r) = min(limit, 1000·V / (2π r)) (G96 with G92): minutes per mm of feed × mm."""
    rc = 1000 * speed / (2 * math.pi * limit) if math.isfinite(limit) else 0.0
    if r <= rc:
        return r / limit
    return (rc / limit if rc > 0 else 0.0) + math.pi * (r * r - rc * rc) / (1000 * speed)


class _Run:
    def __init__(
        self,
        profile: RevolvedProfile,
        blank: Blank,
        tools: ToolTable,
        machine: LatheMachine,
        limits: LatheLimits,
        events: _Events,
    ) -> None:
        self.p, self.blank, self.tools, self.machine, self.limits, self.events = (
            profile,
            blank,
            tools,
            machine,
            limits,
            events,
        )
        self.zs = profile.zs
        self.jaw_samples = math.ceil(blank.clamp / profile.dz)
        self.times: dict[int | None, float] = {}
        self.current: int | None = None
        self.inserts: dict[int, Insert] = {}
        self.updates = 0
        self.last_speed = 0.0  # 1/min at the end of the last move
        self.last_radius: float | None = None  # its programmed radius

    def _time(self, tool: int | None, seconds: float) -> None:
        self.times[tool] = self.times.get(tool, 0.0) + seconds

    def all(self, toolpath: Toolpath) -> None:
        for c in toolpath.commands:
            if isinstance(c, Move):
                self.move(c)
            elif isinstance(c, Dwell):
                self._time(self.current, c.seconds)
            elif isinstance(c, ToolChange):
                self.current = c.tool
                self._time(c.tool, self.machine.tool_change_time)

    # --- time -------------------------------------------------------------------------------

    def seconds(self, mv: Move, path: list[Point], shift: tuple[Point, Point]) -> float:
        length = sum(math.dist(a, b) for a, b in itertools.pairwise(path))
        if mv.kind == "rapid":
            return length / self.machine.rapid_rate * 60
        if mv.feed_unit != "mm/rev":
            return length / mv.feed * 60 if mv.feed > 0 else 0.0
        r_end = path[-1][1] + shift[1][1]
        r_start = path[0][1] + shift[0][1]
        n_end, n_start = mv.spindle, self.last_speed if self.last_radius is not None else mv.spindle
        if mv.feed <= 0 or n_end <= 0 or length == 0:
            return 0.0
        speed, limit = self._css(r_start, n_start, r_end, n_end)
        if speed is None:
            return length / (mv.feed * n_end) * 60
        if len(path) == 2:  # a straight move: the radius changes linearly with the path
            dr = abs(r_end - r_start)
            if dr < 1e-9:
                return (
                    length / (mv.feed * min(limit, 1000 * speed / (2 * math.pi * max(abs(r_end), 1e-9)))) * 60
                )
            if r_start * r_end < 0:  # facing across the centre: both halves from the axis outwards
                g = _g(abs(r_end), speed, limit) + _g(abs(r_start), speed, limit)
            else:
                g = abs(_g(abs(r_end), speed, limit) - _g(abs(r_start), speed, limit))
            return 60 / mv.feed * length / dr * g
        total = 0.0
        m = len(path) - 1
        for k, (a, b) in enumerate(itertools.pairwise(path)):
            off = shift[0][1] + (shift[1][1] - shift[0][1]) * (k + 0.5) / m
            r = max(abs((a[1] + b[1]) / 2 + off), 1e-9)
            total += math.dist(a, b) / (mv.feed * min(limit, 1000 * speed / (2 * math.pi * r)))
        return total * 60

    @staticmethod
    def _css(r0: float, n0: float, r1: float, n1: float) -> tuple[float | None, float]:
        """G96 V (m/min) and the G92 limit (1/min, inf: not reached) that give speed n0 at radius r0 and n1 at r1;
        (None, 0) when the speed is constant along the move (G97, or no change of radius)."""
        if n0 <= 0 or abs(n0 - n1) <= 1e-6 * max(n0, n1) or abs(abs(r0) - abs(r1)) < 1e-9:
            return None, 0.0
        v0, v1 = 2 * math.pi * abs(r0) * n0 / 1000, 2 * math.pi * abs(r1) * n1 / 1000
        if abs(v0 - v1) <= 1e-4 * max(v0, v1):
            return max(v0, v1), math.inf
        if v0 < v1 and abs(r0) < abs(r1):  # the start is at the limit
            return v1, n0
        if v1 < v0 and abs(r1) < abs(r0):
            return v0, n1
        return None, 0.0  # the speed changed with the block (a new S or V): take the block's own

    # --- one move ---------------------------------------------------------------------------

    def insert(self, number: int) -> Insert:
        ins = self.inserts.get(number)
        if ins is None:
            ins = self.inserts[number] = insert_of(self.tools.get(number), number)
        return ins

    def move(self, mv: Move) -> None:
        self.current = mv.tool
        srk = mv.programmed_end is not None and math.dist(mv.programmed_end, mv.end) > 1e-6
        ins = self.insert(mv.tool) if mv.tool is not None else None
        # the nose centre = the programmed position (SRK) or the theoretical tip − (tip − centre)
        off = (0.0, 0.0) if srk or ins is None else (-ins.tip[0], -ins.tip[1])
        if mv.kind == "arc":
            raw = mv.points(CHORD_TOLERANCE, max_chords=self.limits.max_chords)
        else:
            raw = [mv.start, mv.end]
        path = [(p[2] + off[0], p[0] + off[1]) for p in raw]
        prog = mv.programmed_end if mv.programmed_end is not None else mv.end
        shift_end = (0.0, prog[0] - path[-1][1])
        shift_start = (0.0, (self.last_radius - path[0][1]) if self.last_radius is not None else shift_end[1])
        self._time(mv.tool, self.seconds(mv, path, (shift_start, shift_end)))
        self.last_speed, self.last_radius = mv.spindle, prog[0]
        if ins is not None:
            self.cut(mv, ins, path)

    def _window(self, zlo: float, zhi: float) -> tuple[int, int]:
        i0 = max(0, math.floor((zlo - self.p.z0) / self.p.dz - 0.5))
        i1 = min(len(self.zs), math.ceil((zhi - self.p.z0) / self.p.dz + 0.5))
        return i0, max(i0, i1)

    def _envelope(
        self,
        pieces: Iterable[tuple[Point, Point]],
        shape: tuple[Point, ...],
        radius: float,
        upper: bool,
        i0: int,
        i1: int,
        mv: Move,
    ) -> Array:
        """The lower (or upper) envelope of `shape` swept along `pieces` on the samples i0 … i1−1; each piece
        works on the samples under its own sweep only."""
        zs = self.zs[i0:i1]
        env = np.full(zs.shape, np.inf)
        sign = -1.0 if upper else 1.0
        zmin = min(z for z, _ in shape) - radius
        zmax = max(z for z, _ in shape) + radius
        for a, b in pieces:
            j0, j1 = self._window(min(a[0], b[0]) + zmin, max(a[0], b[0]) + zmax)
            j0, j1 = max(j0, i0) - i0, min(j1, i1) - i0
            if j1 <= j0:
                continue
            pts = [(a[0] + z, sign * (a[1] + x)) for z, x in shape] + [
                (b[0] + z, sign * (b[1] + x)) for z, x in shape
            ]
            self.updates += j1 - j0 + PIECE_COST
            if self.updates > self.limits.max_updates:
                self.events.add(diag("SIM-E010", mv.span, limit=self.limits.max_updates))
                raise _Stop
            part = env[j0:j1]
            np.minimum(part, lower_envelope(zs[j0:j1], lower_hull(pts), radius), out=part)
        return sign * env

    def cut(self, mv: Move, ins: Insert, path: list[Point]) -> None:
        r = ins.radius
        zc = [z for z, _ in ins.core]
        zlo = min(z for z, _ in path) + min(zc) - r
        zhi = max(z for z, _ in path) + max(zc) + r
        if zhi < self.p.z0 or zlo > 0:
            return
        i0, i1 = self._window(zlo, zhi)
        if i1 <= i0:
            return
        pieces = list(itertools.pairwise(path))
        low = self._envelope(pieces, ins.core, r, False, i0, i1, mv)
        high = self._envelope(pieces, ins.core, r, True, i0, i1, mv)
        if not ins.inside and ins.holder:  # above the holder's underside the tool reaches out of the part
            hz = [z for z, _ in ins.holder]
            h0 = min(z for z, _ in path) + min(hz)
            h1 = max(z for z, _ in path) + max(hz)
            zs = self.zs[i0:i1]
            high[(zs >= h0) & (zs <= h1)] = np.inf
        outer, inner = self.p.outer[i0:i1], self.p.inner[i0:i1]
        glo, ghi = self.p.gap_lo[i0:i1], self.p.gap_hi[i0:i1]
        tol = self.machine.touch_tolerance
        material = outer > inner
        prior = (outer.copy(), inner.copy(), glo.copy(), ghi.copy()) if mv.kind == "rapid" else None
        before = _volume(outer, inner, glo, ghi, self.p.dz)
        # the swept shape covers low … high at each z: it cuts where it reaches the surface it comes from, and
        # takes a gap below the surface with it; a cut that stays inside the material becomes a gap
        if ins.inside:
            old = inner.copy()
            reach = material & (low <= inner + tol)
            new = np.where(reach, np.minimum(np.maximum(inner, high), outer), inner)
            with np.errstate(invalid="ignore"):
                joined = reach & (new >= glo - tol)
                # what the cut took ends where the gap it opens begins (the gap was empty already)
                taken = np.where(joined & (new <= ghi + tol), glo, new)
            new = np.where(joined, np.maximum(new, ghi), new)
        else:
            old = outer.copy()
            reach = material & (high >= outer - tol)
            new = np.where(reach, np.maximum(np.minimum(outer, low), np.maximum(inner, 0.0)), outer)
            new = np.maximum(new, 0.0)
            with np.errstate(invalid="ignore"):
                joined = reach & (new <= ghi + tol)
                taken = np.where(joined & (new >= glo - tol), ghi, new)
            new = np.where(joined, np.minimum(new, glo), new)
        glo[joined] = np.nan
        ghi[joined] = np.nan
        surface = inner if ins.inside else outer
        surface[:] = new
        ulo, uhi = np.maximum(low, inner), np.minimum(high, outer)
        under = material & ~reach & (uhi - ulo > tol)
        if under.any():
            self._gap(under, ulo, uhi, glo, ghi, inner, outer, ins.inside, tol)
        cut = (np.abs(new - old) > tol) | under
        moved = np.abs(surface - old) > tol  # the surface this move leaves (the grader names its line)
        (self.p.cut_inner if ins.inside else self.p.cut_outer)[i0:i1][moved] = mv.line
        removed = before - _volume(outer, inner, glo, ghi, self.p.dz)
        if not ins.inside:
            jaws = self.jaw_samples - i0
            if jaws > 0 and bool(np.any(low[:jaws] < self.blank.jaw_radius)):
                k = int(np.argmax(low[:jaws] < self.blank.jaw_radius))
                self.events.add(
                    diag(
                        "SIM-E012",
                        mv.span,
                        tool=mv.tool,
                        z=round(float(self.zs[i0 + k]), 3),
                        jaw=round(self.p.z0 + self.blank.clamp, 3),
                    )
                )
        if prior is not None and bool(cut.any()):
            cut = self._deep(
                ins.inside, i0, prior, tol
            )  # a rapid sliding along a face it touches is no collision
        old = np.where(under, uhi, old)
        new = np.where(under, ulo, taken)
        if removed > 1e-6 and bool(cut.any()):
            self._cut_events(mv, ins, path, removed, cut, old, new, i0)
        if ins.holder:
            self._holder(mv, ins, pieces)

    def _deep(
        self, inside: bool, i0: int, before: tuple[Array, Array, Array, Array], tol: float
    ) -> npt.NDArray[np.bool_]:
        """The samples of the window from i0 where a rapid took material deeper than `face_tolerance` from the
        space that was open before it, both radially and along Z: a cut into the part. Less is a tool sliding
        along a face it touches (a straight retract over the clearance a 93° edge leaves at the end of a pass).
        `before` is the window's outer, inner, gap_lo and gap_hi before the move; the profile holds them after.
        """
        n = len(before[0])
        b_out, b_in, b_lo, b_hi = before
        a_out, a_in, a_lo, a_hi = (
            a[i0 : i0 + n] for a in (self.p.outer, self.p.inner, self.p.gap_lo, self.p.gap_hi)
        )
        gap_b, gap_a = ~np.isnan(b_lo), ~np.isnan(a_lo)
        # the thickness taken at each sample, radially (the ring's area over its circumference)
        thick = (_area(b_out, b_in, b_lo, b_hi) - _area(a_out, a_in, a_lo, a_hi)) / np.maximum(
            2 * b_out, 1e-9
        )
        face = self.machine.face_tolerance
        # the deepest radius taken: where the part after the move first leaves the material before it, going
        # into the part from its cutting side
        if inside:
            exit_b, exit_a = np.where(gap_b, b_hi, b_in), np.where(gap_a, a_hi, a_in)
            deepest = np.where(exit_a > exit_b + tol, exit_a, np.where(gap_b, b_lo, b_in))
        else:
            exit_b, exit_a = np.where(gap_b, b_lo, b_out), np.where(gap_a, a_lo, a_out)
            deepest = np.where(exit_a < exit_b - tol, exit_a, np.where(gap_b, b_hi, b_out))
        reach = max(1, math.floor(face / self.p.dz + 0.5))
        # the profile before the move from reach samples before the window to reach after; beyond the bar: open
        lo, hi = max(0, i0 - reach), min(len(self.zs), i0 + n + reach)
        pad = (reach - (i0 - lo), reach - (hi - i0 - n))
        rows = []
        for arr, old, fill in (
            (self.p.outer, b_out, -np.inf),
            (self.p.inner, b_in, np.inf),
            (self.p.gap_lo, b_lo, np.nan),
            (self.p.gap_hi, b_hi, np.nan),
        ):
            row = arr[lo:hi].copy()
            row[i0 - lo : i0 - lo + n] = old
            rows.append(np.pad(row, pad, constant_values=fill))
        deep = thick > max(face, tol)
        for k in range(-reach, reach + 1):
            if k == 0:
                continue
            o, i, g_lo, g_hi = (row[reach + k : reach + k + n] for row in rows)
            with np.errstate(invalid="ignore"):
                open_ = (
                    (o <= deepest + tol)
                    | (i >= deepest - tol)
                    | ((deepest >= g_lo - tol) & (deepest <= g_hi + tol))
                )
            deep &= ~open_
        return deep

    @staticmethod
    def _gap(
        under: npt.NDArray[np.bool_],
        ulo: Array,
        uhi: Array,
        glo: Array,
        ghi: Array,
        inner: Array,
        outer: Array,
        inside: bool,
        tol: float,
    ) -> None:
        """Add the cut ulo … uhi below the surface to the gaps (joined with an overlapping one, else the wider
        of the two kept); a gap that now reaches the surface opens it."""
        with np.errstate(invalid="ignore"):
            empty = np.isnan(glo)
            overlap = ~empty & (ulo <= ghi + tol) & (uhi >= glo - tol)
            wider = ~empty & ~overlap & (uhi - ulo > ghi - glo)
        take = under & (empty | wider)
        glo[take], ghi[take] = ulo[take], uhi[take]
        join = under & overlap
        glo[join] = np.minimum(glo[join], ulo[join])
        ghi[join] = np.maximum(ghi[join], uhi[join])
        with np.errstate(invalid="ignore"):
            opens = under & ((glo <= inner + tol) if inside else (ghi >= outer - tol))
        if inside:
            inner[opens] = ghi[opens]
        else:
            outer[opens] = glo[opens]
        glo[opens] = np.nan
        ghi[opens] = np.nan

    def _cut_events(
        self,
        mv: Move,
        ins: Insert,
        path: list[Point],
        removed: float,
        cut: npt.NDArray[np.bool_],
        old: Array,
        new: Array,
        i0: int,
    ) -> None:
        volume = round(removed, 1)
        if mv.kind == "rapid":
            self.events.add(diag("SIM-E001", mv.span, volume=volume))
        elif mv.spindle == 0:
            self.events.add(diag("SIM-E006", mv.span, volume=volume))
        elif mv.feed == 0:
            self.events.add(diag("SIM-E008", mv.span, volume=volume))
        dz, dx = path[-1][0] - path[0][0], path[-1][1] - path[0][1]
        length = math.hypot(dz, dx)
        if length < 1e-9 or mv.kind == "rapid":
            return
        zs = self.zs[i0 : i0 + len(cut)][cut]
        nz, nx = -dx / length, dz / length  # across the feed direction
        proj = np.concatenate([nz * zs + nx * old[cut], nz * zs + nx * new[cut]])
        depth = float(np.ptp(proj)) if len(proj) else 0.0
        if ins.kind != "groove" and depth > ins.cutting_length + self.machine.touch_tolerance:
            self.events.add(
                diag(
                    "SIM-E013",
                    mv.span,
                    tool=mv.tool,
                    depth=round(depth, 3),
                    length=round(ins.cutting_length, 3),
                )
            )
        if ins.kind == "groove" and abs(dz) > abs(dx) + 1e-9:
            self.events.add(
                diag("SIM-E014", mv.span, tool=mv.tool, what="Stechdrehmeißel", what_en="grooving tool")
            )
        elif ins.kind == "thread" and (abs(dx) > abs(dz) + 1e-9 or dz * ins.direction < -1e-9):
            self.events.add(
                diag("SIM-E014", mv.span, tool=mv.tool, what="Gewindedrehmeißel", what_en="threading tool")
            )

    def _holder(self, mv: Move, ins: Insert, pieces: list[tuple[Point, Point]]) -> None:
        hz = [z for z, _ in ins.holder]
        zlo = min(min(a[0], b[0]) for a, b in pieces) + min(hz)
        zhi = max(max(a[0], b[0]) for a, b in pieces) + max(hz)
        i0, i1 = self._window(zlo, zhi)
        if i1 <= i0:
            return
        outer, inner = self.p.outer[i0:i1], self.p.inner[i0:i1]
        material = outer > inner
        if not material.any():
            return
        tol = self.machine.touch_tolerance
        # a straight holder: its sweep along the move's chord is enough
        chord = [(pieces[0][0], pieces[-1][1])]
        if ins.inside:
            top = self._envelope(chord, ins.holder, 0.0, True, i0, i1, mv)
            bottom = self._envelope(chord, ins.holder, 0.0, False, i0, i1, mv)
            hit = material & ((top - inner > tol) | (-bottom - inner > tol))
        else:
            low = self._envelope(chord, ins.holder, 0.0, False, i0, i1, mv)
            hit = material & (outer - low > tol)
        if hit.any():
            k = int(np.argmax(hit))
            self.events.add(
                diag(
                    "SIM-E011",
                    mv.span,
                    tool=mv.tool,
                    z=round(float(self.zs[i0 + k]), 3),
                    d=round(2 * float(outer[k] if not ins.inside else inner[k]), 3),
                )
            )
