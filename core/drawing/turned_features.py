"""What the drawing of a turned part dimensions, read from the reference's toolpath and its turned part.

The part (its outline to draw) is the turning simulation's revolved profile (core/sim/turning.py) of the
program without its thread passes, so that a thread shows at its nominal size and the thread itself is
drawn by convention. The numbers are the program's: every diameter is twice a programmed radius (X is a
diameter on the lathe) or a drill's diameter from the tool table, every length a programmed Z, every radius
and chamfer a programmed transition. A programmed element counts where it lies on the turned part's surface
(not the roughing passes, approach and lift moves in the air); a radius or 45° chamfer between two lines is
dimensioned to its sharp corner, as drawings do.
"""

from __future__ import annotations

import copy
import itertools
import math
from dataclasses import dataclass, field

import numpy as np
import numpy.typing as npt

from core.drawing.features import clip_line, start_and_sweep
from core.exercises import Exercise
from core.interpreter.state import RunSetup
from core.pipeline import run
from core.sim.turning import DEFAULT_LATHE_TOOLS, Blank, simulate_turning
from core.toolpath import Move, Toolpath
from core.tools import Tool, ToolTable

P = tuple[float, float]  # (z, r): along the spindle axis, radius
EPS = 1e-6
ROUGHING = frozenset({"G70", "G71", "G72"})  # their passes are no contour (the finishing cut is)
SAME = 1e-3  # mm: values closer than this are one dimension
SAMPLES = 48  # points per element checked against the part's surface
ON_PART = (
    0.5  # the share of an element's points on the surface that makes it the part's (a groove may cut it)
)
PROBES = (1.0, 3.0)  # mm beyond an element's end where the outline is looked for (edge or not)
OUTLINE_TOLERANCE = (
    0.005  # mm: the profile's outline simplified within this (drawn far finer than a line width)
)


@dataclass(frozen=True, slots=True)
class Seg:
    """A programmed line or arc in the (z, r) half plane; `dims` says which of its ends are programmed points."""

    a: P
    b: P
    centre: P | None = None
    radius: float = 0.0
    cw: bool = False
    line: int = 0
    tool: int | None = None
    dims: tuple[bool, bool] = (True, True)
    drilled: bool = False  # a drill's bore: its radius is the tool's
    compensated: bool = False  # programmed under SRK: the element is the part's edge, not the tip's path

    def point(self, t: float) -> P:
        if self.centre is None:
            return (self.a[0] + (self.b[0] - self.a[0]) * t, self.a[1] + (self.b[1] - self.a[1]) * t)
        a0, sweep = self.angles()
        a = a0 + sweep * t
        return (self.centre[0] + self.radius * math.cos(a), self.centre[1] + self.radius * math.sin(a))

    def angles(self) -> tuple[float, float]:
        """Start angle and signed sweep in the (z, r) plane (radians, counter-clockwise positive)."""
        assert self.centre is not None
        return start_and_sweep(self.a, self.b, self.centre, self.cw)

    def length(self) -> float:
        if self.centre is None:
            return math.dist(self.a, self.b)
        return abs(self.angles()[1]) * self.radius

    def direction(self, at_end: bool) -> P:
        """The unit tangent in the direction of travel at the start or the end."""
        if self.centre is None:
            d = (self.b[0] - self.a[0], self.b[1] - self.a[1])
        else:
            p = self.b if at_end else self.a
            v = (p[0] - self.centre[0], p[1] - self.centre[1])
            d = (v[1], -v[0]) if self.cw else (-v[1], v[0])
        n = math.hypot(*d) or 1.0
        return (d[0] / n, d[1] / n)

    @property
    def cylinder(self) -> bool:
        return self.centre is None and abs(self.a[1] - self.b[1]) < EPS and abs(self.a[0] - self.b[0]) > EPS

    @property
    def face(self) -> bool:
        return self.centre is None and abs(self.a[0] - self.b[0]) < EPS and abs(self.a[1] - self.b[1]) > EPS


@dataclass(frozen=True, slots=True)
class Thread:
    """A thread over z_lo … z_hi: nominal diameter, pitch, the radius of its other line (root outside, nominal
    inside the core hole), inside or outside."""

    z_lo: float
    z_hi: float
    nominal: float
    pitch: float
    other: float
    inside: bool
    line: int


@dataclass
class TurnedPart:
    """The turned part and what its drawing dimensions."""

    blank: Blank
    loops: list[list[P]]  # closed outlines (z, r ≥ 0) of the solids: front face, outside, back face, bore
    outer: npt.NDArray[np.float64]  # outer radius by Z sample (profile.zs)
    inner: npt.NDArray[np.float64]
    zs: npt.NDArray[np.float64]
    dz: float
    surface: list[Seg] = field(default_factory=list)  # programmed elements on the part (clipped to the blank)
    whole: list[bool] = field(default_factory=list)  # … lying on the part over their whole length
    inside: list[bool] = field(default_factory=list)  # … on the bore
    corners: dict[int, P] = field(default_factory=dict)  # (element index at its end) → the sharp corner
    fillets: list[int] = field(default_factory=list)  # indices of radii between two lines
    chamfers: list[tuple[int, float]] = field(default_factory=list)  # (index, leg)
    threads: list[Thread] = field(default_factory=list)
    grooves: list[tuple[float, float, float]] = field(default_factory=list)  # (z_lo, z_hi, bottom radius)
    groove_walls: set[float] = field(default_factory=set)  # the grooves' walls that are programmed Z values
    known_r: set[float] = field(default_factory=set)  # the radii and Z the program gives (rounded to 1 µm)
    known_z: set[float] = field(default_factory=set)
    z_values: list[float] = field(default_factory=list)  # the programmed Z of the part's edges, 0 first

    def radius_at(self, z: float, inside: bool = False) -> float:
        k = int(np.clip(np.searchsorted(self.zs, z), 0, len(self.zs) - 1))
        return float(self.inner[k] if inside else self.outer[k])

    def machined_from(self) -> float:
        """The Z where the turning ends towards the chuck: the last sample changed from the blank, or the
        deepest dimensioned Z."""
        changed = (self.outer < self.blank.diameter / 2 - 0.01) | (self.inner > self.blank.bore / 2 + 0.01)
        found = [float(self.zs[changed].min())] if changed.any() else []
        return min(found + self.z_values + [0.0])

    def silhouette(self, z: float, reach: float) -> float:
        """The largest outer radius within `reach` mm of z (where an extension line leaves the part)."""
        near = np.abs(self.zs - z) <= reach
        return float(self.outer[near].max()) if near.any() else self.radius_at(z)


# ---- the part ---------------------------------------------------------------------------------------------


def _setup(exercise: Exercise) -> tuple[RunSetup, ToolTable]:
    tools = exercise.tool_table() if exercise.tools else DEFAULT_LATHE_TOOLS
    return RunSetup(
        tools=tools,
        zero_offsets=tuple(exercise.zero_offsets.items()),
        subprograms=tuple(exercise.subprograms.items()),
    ), tools


def _without_threads(toolpath: Toolpath) -> Toolpath:
    """The run without its threads: the thread moves and the other moves of their blocks (a cycle's infeed
    and lift, which would cut the thread's run-out into the part the drawing shows at its nominal size)."""
    blocks = {(m.span.line, m.call_stack) for m in toolpath.moves if m.thread}
    plain = copy.copy(toolpath)
    plain.commands = [
        c
        for c in toolpath.commands
        if not (
            isinstance(c, Move)
            and (c.thread or (c.cycle is not None and (c.span.line, c.call_stack) in blocks))
        )
    ]
    return plain


def _simplify(points: list[P], tolerance: float) -> list[P]:
    """Ramer–Douglas–Peucker: the points that keep the polyline within `tolerance`."""
    if len(points) < 3:
        return points
    pts = np.asarray(points)
    keep = np.zeros(len(pts), dtype=bool)
    keep[0] = keep[-1] = True
    stack = [(0, len(pts) - 1)]
    while stack:
        i, j = stack.pop()
        if j <= i + 1:
            continue
        a, b = pts[i], pts[j]
        d = b - a
        n = math.hypot(*d)
        rel = pts[i + 1 : j] - a
        dist = np.abs(d[0] * rel[:, 1] - d[1] * rel[:, 0]) / n if n > EPS else np.hypot(rel[:, 0], rel[:, 1])
        k = int(np.argmax(dist))
        if dist[k] > tolerance:
            keep[i + 1 + k] = True
            stack += [(i, i + 1 + k), (i + 1 + k, j)]
    return [(float(z), float(r)) for z, r in pts[keep]]


def loops(
    outer: npt.NDArray[np.float64], inner: npt.NDArray[np.float64], z0: float, dz: float
) -> list[list[P]]:
    """The closed outline (z, r) of each solid of a profile whose sample k covers z0 + k·dz … z0 + (k+1)·dz
    (separate solids where a cut goes right through): front face, outside, back face, bore."""
    outer = np.clip(outer, 0, None)
    inner = np.clip(inner, 0, None)
    solid = np.concatenate([[False], outer - inner > 1e-6, [False]])
    edges = np.flatnonzero(np.diff(solid.astype(np.int8)))
    zs = z0 + (np.arange(len(outer)) + 0.5) * dz
    out = []
    for a, b in zip(edges[::2], edges[1::2], strict=True):
        lo, hi = z0 + a * dz, z0 + b * dz
        top = [(hi, float(outer[b - 1]))] + [
            (float(z), float(r)) for z, r in zip(zs[a:b][::-1], outer[a:b][::-1], strict=True)
        ]
        top += [(lo, float(outer[a]))]
        bore = [(lo, float(inner[a]))] + [
            (float(z), float(r)) for z, r in zip(zs[a:b], inner[a:b], strict=True)
        ]
        bore += [(hi, float(inner[b - 1]))]
        out.append(_simplify(top, OUTLINE_TOLERANCE) + _simplify(bore, OUTLINE_TOLERANCE))
    return out


def _distance(points: npt.NDArray[np.float64], loops: list[list[P]]) -> npt.NDArray[np.float64]:
    """Each point's distance to the nearest outline segment."""
    segs = [(p, q) for loop in loops for p, q in itertools.pairwise(loop + loop[:1])]
    if not segs:
        return np.full(len(points), np.inf)
    a = np.array([s[0] for s in segs])
    b = np.array([s[1] for s in segs])
    d = b - a
    n2 = np.maximum((d**2).sum(axis=1), 1e-18)
    rel = points[:, None, :] - a[None, :, :]
    t = np.clip((rel * d[None]).sum(axis=2) / n2[None], 0.0, 1.0)
    nearest = a[None] + t[..., None] * d[None]
    dist: npt.NDArray[np.float64] = np.sqrt(((points[:, None, :] - nearest) ** 2).sum(axis=2)).min(axis=1)
    return dist


# ---- the programmed elements ---------------------------------------------------------------------------


def _elements(toolpath: Toolpath, tools: ToolTable) -> list[Seg]:
    """The programmed lines and arcs of the cutting moves (not threads), in program order; a drill's bore as
    its cylinder and point."""
    out: list[Seg] = []
    previous: P | None = None
    drilled: dict[int, tuple[float, float, Tool, int]] = {}  # tool → (deepest tip, start z, tool, line)
    for m in toolpath.moves:
        pe = m.programmed_end if m.programmed_end is not None else m.end
        end = (pe[2], pe[0])
        start = previous if previous is not None else (m.start[2], m.start[0])
        previous = end
        if (
            m.kind == "rapid"
            or m.thread
            or m.plane != "G18"
            or (m.cycle is not None and m.cycle[0] in ROUGHING)
        ):
            continue
        compensated = m.programmed_end is not None and math.dist(m.programmed_end, m.end) > EPS
        tool = tools.get(m.tool) if m.tool is not None else None
        if tool is not None and tool.kind != "turning":
            if abs(m.start[0]) < EPS and abs(m.end[0]) < EPS and m.end[2] < m.start[2]:
                deepest = drilled.get(tool.number)
                if deepest is None or m.end[2] < deepest[0]:
                    drilled[tool.number] = (m.end[2], m.start[2], tool, m.span.line)
            continue
        if m.kind == "arc" and m.center is not None:
            centre = (m.center[2], m.center[0])
            radius = math.dist(start, centre)
            if radius > EPS and math.dist(start, end) > EPS:
                out.append(
                    Seg(
                        start,
                        end,
                        centre,
                        radius,
                        m.direction == "cw",
                        m.span.line,
                        m.tool,
                        compensated=compensated,
                    )
                )
        elif math.dist(start, end) > EPS:
            out.append(Seg(start, end, line=m.span.line, tool=m.tool, compensated=compensated))
    for tip, _, tool, line in drilled.values():
        r = tool.diameter / 2
        angle = tool.point_angle or (
            118.0 if tool.kind == "twist_drill" else 90.0 if tool.kind == "spot_drill" else 180.0
        )
        h = r / math.tan(math.radians(angle / 2)) if angle < 179.9 else 0.0
        if h < -tip - EPS:  # the cylinder from the face to where the point begins
            out.append(
                Seg((0.0, r), (tip + h, r), line=line, tool=tool.number, dims=(True, False), drilled=True)
            )
        out.append(
            Seg((tip + h, r), (tip, 0.0), line=line, tool=tool.number, dims=(False, True), drilled=True)
        )
    return out


def _clip(e: Seg, blank: Blank) -> tuple[float, float] | None:
    """The parameters (0…1) of the part of `e` inside the blank's half section; None: none of it. A line is
    clipped exactly (Liang–Barsky), an arc on fine samples."""
    box = (-blank.length, 0.0, blank.bore / 2, blank.diameter / 2)
    if e.centre is None:
        return clip_line(e.a, e.b, box)
    ts = np.linspace(0.0, 1.0, 201)
    inside = [
        float(t)
        for t in ts
        if box[0] - SAME <= e.point(float(t))[0] <= box[1] + SAME
        and box[2] - SAME <= e.point(float(t))[1] <= box[3] + SAME
    ]
    return (inside[0], inside[-1]) if len(inside) >= 2 else None


def _nose(e: Seg, tools: ToolTable) -> float:
    tool = tools.get(e.tool) if e.tool is not None else None
    return tool.nose_radius if tool is not None and tool.kind == "turning" else 0.4 if tool is None else 0.0


def _tolerance(e: Seg, tools: ToolTable, dz: float) -> float:
    """How far a programmed element may be from the turned surface and still be on it: the profile's
    sampling, and for an uncompensated slope or arc the nose radius's error (the tip is not the edge)."""
    base = max(0.06, 1.5 * dz)
    if e.drilled or e.cylinder or e.face or e.compensated:
        return base
    return base + 0.5 * _nose(e, tools)


def _corner(part: TurnedPart, p: P, beyond: P, tol: float) -> bool:
    """Whether the outline turns at the element's end p: 1 or 3 mm further straight on (`beyond`, the
    element's direction at p) is off the part or outside the blank (a pass that starts or ends in the middle
    of a face or cylinder makes no edge there; an inside corner's nose radius is less than 1 mm)."""
    for d in PROBES:
        q = np.array([[p[0] + d * beyond[0], p[1] + d * beyond[1]]])
        if not (
            -part.blank.length - SAME <= q[0, 0] <= SAME and 0.0 <= q[0, 1] <= part.blank.diameter / 2 + SAME
        ):
            return True
        if _distance(q, part.loops)[0] > tol:
            return True
    return False


def _on_surface(part: TurnedPart, elements: list[Seg], tools: ToolTable, dz: float) -> None:
    for e in elements:
        span = _clip(e, part.blank)
        if span is None:
            continue
        t0, t1 = span
        ts = np.linspace(t0, t1, SAMPLES + 1)
        pts = np.array([e.point(float(t)) for t in ts])
        tol = _tolerance(e, tools, dz)
        dist = _distance(pts, part.loops)
        near = dist <= tol
        # a drill's bore is the part's wherever it is left (a boring bar may have widened the rest of it)
        if (near.sum() < 3 if e.drilled else near.mean() < ON_PART) or e.length() * (t1 - t0) < SAME:
            continue
        reach = tol + _nose(e, tools)  # the nose leaves its radius in an inside corner
        along = (ts - t0) * e.length()
        middle = (along > reach) & (along < (t1 - t0) * e.length() - reach)  # off the ends' corners
        a, b = e.point(t0), e.point(t1)
        a, b = (float(a[0]), float(a[1])), (float(b[0]), float(b[1]))
        # on the part all along, or all along from the front face on (a chamfer programmed from in front of the
        # face, G0 X26 Z0.5 / G1 X30 D1.5: on the part it is the chamfer from the face)
        whole = bool(near[middle].all()) and (t0 < EPS or abs(a[0]) < SAME) and t1 > 1 - EPS
        u, v = e.direction(False), e.direction(True)
        dims = (
            e.dims[0] and t0 < EPS and bool(dist[0] <= reach) and _corner(part, a, (-u[0], -u[1]), tol),
            e.dims[1] and t1 > 1 - EPS and bool(dist[-1] <= reach) and _corner(part, b, v, tol),
        )
        mid = e.point((t0 + t1) / 2)
        inside = e.drilled or abs(mid[1] - part.radius_at(mid[0], True)) < abs(
            mid[1] - part.radius_at(mid[0])
        )
        part.surface.append(
            Seg(
                e.a if t0 < EPS else a,
                e.b if t1 > 1 - EPS else b,
                e.centre,
                e.radius,
                e.cw,
                e.line,
                e.tool,
                dims,
                e.drilled,
                e.compensated,
            )
        )
        part.whole.append(whole)
        part.inside.append(inside)


def _cross(p: P, u: P, q: P, v: P) -> P | None:
    """Where the lines p + s·u and q + t·v meet."""
    den = u[0] * v[1] - u[1] * v[0]
    if abs(den) < 1e-9:
        return None
    s = ((q[0] - p[0]) * v[1] - (q[1] - p[1]) * v[0]) / den
    return (p[0] + s * u[0], p[1] + s * u[1])


def _transitions(part: TurnedPart) -> None:
    """Radii tangent to two lines and 45° chamfers between perpendicular lines: dimensioned to the corner.
    The front face (Z0) counts as a line where a chamfer starts on it."""
    s = part.surface
    for i, e in enumerate(s):
        prev = s[i - 1] if i > 0 and math.dist(s[i - 1].b, e.a) < SAME else None
        nxt = s[i + 1] if i + 1 < len(s) and math.dist(e.b, s[i + 1].a) < SAME else None
        if not part.whole[i]:
            continue
        u = prev.direction(True) if prev is not None and prev.centre is None else None
        v = nxt.direction(False) if nxt is not None and nxt.centre is None else None
        if e.centre is None and u is None and v is not None and abs(e.a[0]) < SAME:
            u = (0.0, 1.0 if e.b[1] > e.a[1] else -1.0)  # a chamfer from the face
        if u is None or v is None:
            continue
        corner = _cross(e.a, u, e.b, v)
        if corner is None:
            continue
        if e.centre is not None:
            t0, t1 = e.direction(False), e.direction(True)
            if u[0] * t0[0] + u[1] * t0[1] > 1 - 1e-6 and v[0] * t1[0] + v[1] * t1[1] > 1 - 1e-6:
                part.fillets.append(i)
                part.corners[i] = corner
            continue
        w = e.direction(False)
        perpendicular = abs(u[0] * v[0] + u[1] * v[1]) < 1e-6
        at_45 = all(abs(abs(w[0] * x[0] + w[1] * x[1]) - math.sqrt(0.5)) < 1e-6 for x in (u, v))
        if perpendicular and at_45:
            part.chamfers.append((i, e.length() * math.sqrt(0.5)))
            part.corners[i] = corner


def _threads(toolpath: Toolpath, tools: ToolTable, part: TurnedPart) -> None:
    """The thread passes of one block: its zone on the part, nominal diameter and pitch."""
    by_line: dict[int, list[Move]] = {}
    for m in toolpath.moves:
        if m.thread and m.kind != "rapid" and abs(m.end[2] - m.start[2]) > EPS:
            by_line.setdefault(m.span.line, []).append(m)
    for line, moves in sorted(by_line.items()):
        zs = [z for m in moves for z in (m.start[2], m.end[2])]
        z_lo, z_hi = max(min(zs), -part.blank.length), min(max(zs), 0.0)
        pitch = next((m.pitch for m in moves if m.pitch), None)
        if z_hi - z_lo < SAME or pitch is None:
            continue
        radii = [r for m in moves for r in (m.start[0], m.end[0])]
        mid = (z_lo + z_hi) / 2
        tool = tools.get(moves[0].tool) if moves[0].tool is not None else None
        if max(abs(r) for r in radii) < EPS:  # a tap on the axis: its diameter is the thread's
            if tool is None:
                continue
            part.threads.append(Thread(z_lo, z_hi, tool.diameter, pitch, tool.diameter / 2, True, line))
            continue
        outer, inner = part.radius_at(mid), part.radius_at(mid, True)
        inside = abs(min(radii) - inner) < abs(min(radii) - outer)
        if inside:
            part.threads.append(Thread(z_lo, z_hi, 2 * max(radii), pitch, max(radii), True, line))
        else:
            nominal = _programmed_radius(part, mid, outer)
            part.threads.append(Thread(z_lo, z_hi, 2 * nominal, pitch, min(radii), False, line))


def _programmed_radius(part: TurnedPart, z: float, measured: float) -> float:
    """The programmed radius of the cylinder at z (a turned diameter, else the blank's) the profile shows."""
    for e, inside in zip(part.surface, part.inside, strict=True):
        if (
            e.cylinder
            and not inside
            and min(e.a[0], e.b[0]) - SAME <= z <= max(e.a[0], e.b[0]) + SAME
            and abs(e.a[1] - measured) < 0.05
        ):
            return e.a[1]
    if abs(measured - part.blank.diameter / 2) < 0.05:
        return part.blank.diameter / 2
    return round(measured, 2)


def _grooves(toolpath: Toolpath, tools: ToolTable, part: TurnedPart, dz: float) -> None:
    """Recesses in the outside whose walls are programmed Z values (or one of them and the grooving insert's
    width from it) and whose bottom is a programmed radius."""
    ends = [(m.programmed_end or m.end, m.tool) for m in toolpath.moves if m.kind != "rapid" and not m.thread]
    radii = [p[0] for p, _ in ends]
    walls: dict[float, bool] = {}  # candidate z → a programmed one (not one the insert's width gives)
    for p, number in ends:
        walls.setdefault(round(p[2], 6), True)
        tool = tools.get(number) if number is not None else None
        if tool is not None and tool.insert == "groove" and tool.width > 0:
            for z in (p[2] - tool.width, p[2] + tool.width):
                walls.setdefault(round(z, 6), False)
    o = part.outer
    tol = max(0.06, 1.5 * dz)
    for m in range(len(o) - 1):
        top = o[m + 1]
        if top < o[m] + 0.1:
            continue  # not a wall rising towards +Z
        k = m
        while k > 0 and o[k - 1] < top - 0.1:
            k -= 1
        if k == 0:
            continue
        depth = float(o[k : m + 1].min())
        # both walls steep (faces, not tapers): half the depth or more within one sample
        if o[k - 1] - o[k] < 0.5 * (top - depth) or o[m + 1] - o[m] < 0.5 * (top - depth):
            continue
        lo, hi = part.zs[k] - dz / 2, part.zs[m] + dz / 2
        a = min(walls, key=lambda z: abs(z - lo))
        b = min(walls, key=lambda z: abs(z - hi))
        bottom = min(radii, key=lambda r: abs(r - depth), default=math.nan)
        if depth < 0.5 or not (abs(bottom - depth) <= tol):  # cut off, not grooved
            continue
        if abs(a - lo) <= tol and abs(b - hi) <= tol and (walls[a] or walls[b]):
            part.grooves.append((a, b, bottom))
            part.groove_walls |= {z for z in (a, b) if walls[z]}


def points(part: TurnedPart) -> list[tuple[P, bool]]:
    """The part's programmed points (on the bore or not): element ends, and the corner instead of the ends
    of a radius or chamfer between two lines (its radius −1 where the program does not give it)."""
    s, corners = part.surface, part.corners
    out: list[tuple[P, bool]] = []
    for i, e in enumerate(s):
        if i in corners:
            # a corner the program gives (G1 X60 R2), not one made from directions (A…): Z or Ø not printed
            z, r = corners[i]
            if round(z, 3) in part.known_z:
                out.append(((z, r if round(r, 3) in part.known_r else -1.0), part.inside[i]))
            continue
        after = i - 1 in corners and math.dist(s[i - 1].b, e.a) < SAME
        before = i + 1 in corners and math.dist(e.b, s[i + 1].a) < SAME
        if e.dims[0] and not after:
            out.append((e.a, part.inside[i]))
        if e.dims[1] and not before:
            out.append((e.b, part.inside[i]))
    return out


def _z_values(part: TurnedPart) -> None:
    # the points' Z, and a face's even where the blank cuts its ends off (its Z is programmed all along it)
    zs = [0.0] + [p[0] for p, _ in points(part)] + [e.a[0] for e in part.surface if e.face]
    zs += [t.z_lo for t in part.threads] + sorted(part.groove_walls)
    out: list[float] = []
    for z in sorted((z for z in zs if -part.blank.length - SAME <= z <= SAME), reverse=True):
        if not out or out[-1] - z > SAME:
            out.append(z)
    part.z_values = out


def turned_part(exercise: Exercise) -> TurnedPart:
    """The exercise's reference turned on its blank, and what its drawing dimensions."""
    assert exercise.blank is not None, "a turning exercise has a blank"
    setup, tools = _setup(exercise)
    toolpath = run(exercise.reference, exercise.dialect, setup)
    blank = exercise.blank.blank()
    result = simulate_turning(_without_threads(toolpath), blank, tools, exercise.resolution)
    profile = result.profile
    part = TurnedPart(
        blank,
        loops(profile.outer, profile.inner, profile.z0, profile.dz),
        np.clip(profile.outer, 0, None),
        np.clip(profile.inner, 0, None),
        profile.zs,
        profile.dz,
    )
    for m in toolpath.moves:
        for p in (m.programmed_end or m.end, m.start) + ((m.center,) if m.center is not None else ()):
            part.known_r.add(round(p[0], 3))
            part.known_z.add(round(p[2], 3))
    _on_surface(part, _elements(toolpath, tools), tools, profile.dz)
    _transitions(part)
    _threads(toolpath, tools, part)
    _grooves(toolpath, tools, part, profile.dz)
    _z_values(part)
    return part
