"""What a part drawing dimensions, read from the reference's toolpath: the programmed contours by depth.

A feature is a run of cutting moves in the XY plane at one height below the stock top (a contour, a slot's
centre line, a pocket wall). Its elements are the *programmed* geometry (`programmed_end`, the arc centres
and radii), never the tool-centre path, so every number the drawing prints is the program's own. Which of
them a drawing shows is decided here too: the corner points, arc end points and centres that lie on the
blank, the radii, chamfers and line angles.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass, field

from core.sim.engine import Stock
from core.toolpath import Move, Vec3
from core.tools import ToolTable

EPS = 1e-6


def start_and_sweep(
    start: tuple[float, float], end: tuple[float, float], centre: tuple[float, float], cw: bool
) -> tuple[float, float]:
    """An arc's start angle and signed sweep (radians, counter-clockwise positive); end = start is a full circle.
    Milled (x, y) and turned (z, r) drawings both use it."""
    a0 = math.atan2(start[1] - centre[1], start[0] - centre[0])
    sweep = math.atan2(end[1] - centre[1], end[0] - centre[0]) - a0
    if cw:
        while sweep >= -EPS:
            sweep -= 2 * math.pi
    else:
        while sweep <= EPS:
            sweep += 2 * math.pi
    return a0, sweep


POINT_TOLERANCE = 1e-3  # mm; values closer than this are one dimension


@dataclass(frozen=True, slots=True)
class Element:
    """A programmed line or arc in the XY plane (arc: centre, radius, direction seen from +Z)."""

    start: tuple[float, float]
    end: tuple[float, float]
    center: tuple[float, float] | None = None
    radius: float = 0.0
    direction: str | None = None
    line: int = 0
    centre_start: tuple[float, float] = (0.0, 0.0)  # where the tool centre ran (differs under G41/G42)
    centre_end: tuple[float, float] = (0.0, 0.0)

    @property
    def offset(self) -> bool:
        """Both ends of the tool-centre path are off the programmed element: a compensated contour element
        (not the approach or departure move, which starts or ends on the programmed point)."""
        return math.dist(self.start, self.centre_start) > EPS and math.dist(self.end, self.centre_end) > EPS

    @property
    def is_arc(self) -> bool:
        return self.center is not None

    def midpoint(self) -> tuple[float, float]:
        if self.center is None:
            return ((self.start[0] + self.end[0]) / 2, (self.start[1] + self.end[1]) / 2)
        a0, sweep = self.angles()
        a = a0 + sweep / 2
        return (self.center[0] + self.radius * math.cos(a), self.center[1] + self.radius * math.sin(a))

    def angles(self) -> tuple[float, float]:
        """Start angle and signed sweep (radians, counter-clockwise positive)."""
        assert self.center is not None
        return start_and_sweep(self.start, self.end, self.center, self.direction == "cw")

    def length(self) -> float:
        if self.center is None:
            return math.dist(self.start, self.end)
        return abs(self.angles()[1]) * self.radius


@dataclass
class Feature:
    """Cutting moves at one height: the programmed elements, their floor Z and the tool that cut them."""

    z: float
    tool: int | None
    tool_diameter: float
    compensated: bool  # programmed under G41/G42: the elements are the part's edge, not a centre line
    elements: list[Element] = field(default_factory=list)

    @property
    def lines(self) -> list[int]:
        return sorted({e.line for e in self.elements})


def _xy(p: Vec3) -> tuple[float, float]:
    return (p[0], p[1])


def _in_plane_cut(m: Move, top: float) -> bool:
    return (
        m.kind in ("feed", "arc")
        and m.plane == "G17"
        and abs(m.start[2] - m.end[2]) < EPS
        and m.end[2] < top - EPS
    )


def features(moves: list[Move], stock: Stock, tools: ToolTable) -> list[Feature]:
    """The runs of in-plane cutting moves below the stock top, in program order."""
    out: list[Feature] = []
    current: Feature | None = None
    previous_programmed: tuple[float, float] | None = None
    for m in moves:
        programmed = _xy(m.programmed_end if m.programmed_end is not None else m.end)
        start = previous_programmed if previous_programmed is not None else _xy(m.start)
        if _in_plane_cut(m, stock.z1):
            z = m.end[2]
            if current is None or abs(current.z - z) > EPS or current.tool != m.tool:
                tool = tools.get(m.tool) if m.tool is not None else None
                current = Feature(
                    z=z,
                    tool=m.tool,
                    tool_diameter=tool.diameter if tool is not None else 0.0,
                    compensated=False,
                )
                out.append(current)
            if m.programmed_end is not None and math.dist(_xy(m.programmed_end), _xy(m.end)) > EPS:
                current.compensated = True
            center = _xy(m.center) if m.kind == "arc" and m.center is not None else None
            radius = math.dist(start, center) if center is not None else 0.0
            # an arc the compensation inserts at an outside corner has no programmed length: not an element,
            # but the corner stays sharp (no tool radius is left there)
            if math.dist(start, programmed) > EPS or (center is not None and radius > EPS):
                current.elements.append(
                    Element(
                        start, programmed, center, radius, m.direction, m.span.line, _xy(m.start), _xy(m.end)
                    )
                )
        else:
            current = None
        previous_programmed = programmed
    return _contours([f for f in out if f.elements])


def _contours(found: list[Feature]) -> list[Feature]:
    """Compensated features without their approach and departure moves; clearing passes (uncompensated
    moves at the height of a compensated contour) left out, as a drawing shows only the contour."""
    contour_heights = {round(f.z, 6) for f in found if f.compensated}
    out = []
    for f in found:
        if f.compensated:
            f.elements = [e for e in f.elements if e.offset]
        elif round(f.z, 6) in contour_heights:
            continue
        if f.elements:
            out.append(f)
    return out


def machined_corners(f: Feature) -> list[tuple[tuple[float, float], tuple[float, float]]]:
    """Inside corners of a compensated contour, where the tool leaves its own radius: (programmed corner,
    tool-centre point) pairs. The tool-centre path has a sharp corner there (offset elements intersected)."""
    out = []
    for a, b in itertools.pairwise(f.elements):
        if math.dist(a.centre_end, b.centre_start) > EPS or math.dist(a.end, b.start) > EPS:
            continue
        if not _tangent(a, b):
            out.append((a.end, a.centre_end))
    return out


def _tangent(a: Element, b: Element) -> bool:
    u, v = heading(a, True), heading(b, False)
    return u[0] * v[0] + u[1] * v[1] > 1 - 1e-6


# ---- what is dimensioned -------------------------------------------------------------------------------


def on_stock(p: tuple[float, float], stock: Stock, margin: float = POINT_TOLERANCE) -> bool:
    return stock.x0 - margin <= p[0] <= stock.x1 + margin and stock.y0 - margin <= p[1] <= stock.y1 + margin


def clip_line(
    a: tuple[float, float], b: tuple[float, float], box: tuple[float, float, float, float]
) -> tuple[float, float] | None:
    """The part of the line a→b (as parameters 0…1) inside box = (u0, u1, v0, v1) (Liang–Barsky); None: outside.
    Milled (x, y) and turned (z, r) drawings both use it."""
    (x0, y0), (x1, y1) = a, b
    dx, dy = x1 - x0, y1 - y0
    t0, t1 = 0.0, 1.0
    for p, q in ((-dx, x0 - box[0]), (dx, box[1] - x0), (-dy, y0 - box[2]), (dy, box[3] - y0)):
        if abs(p) < EPS:
            if q < -POINT_TOLERANCE:
                return None
            continue
        t = q / p
        if p < 0:
            t0 = max(t0, t)
        else:
            t1 = min(t1, t)
    return (t0, t1) if t1 - t0 > EPS else None


def _clip_parameters(e: Element, stock: Stock) -> tuple[float, float] | None:
    """The part of a line (as parameters 0…1) inside the stock's rectangle; None: outside."""
    return clip_line(e.start, e.end, (stock.x0, stock.x1, stock.y0, stock.y1))


def visible(e: Element, stock: Stock) -> bool:
    """Whether any of the element shows on the blank."""
    if e.center is None:
        return _clip_parameters(e, stock) is not None
    a0, sweep = e.angles()
    n = max(8, int(abs(sweep) / math.radians(5)))
    return any(
        on_stock(
            (
                e.center[0] + e.radius * math.cos(a0 + sweep * k / n),
                e.center[1] + e.radius * math.sin(a0 + sweep * k / n),
            ),
            stock,
            -POINT_TOLERANCE,
        )
        for k in range(n + 1)
    )


def _cross(
    p: tuple[float, float], u: tuple[float, float], q: tuple[float, float], v: tuple[float, float]
) -> tuple[float, float] | None:
    """Where the lines p + s·u and q + t·v meet (None: parallel)."""
    den = u[0] * v[1] - u[1] * v[0]
    if abs(den) < 1e-9:
        return None
    s = ((q[0] - p[0]) * v[1] - (q[1] - p[1]) * v[0]) / den
    return (p[0] + s * u[0], p[1] + s * u[1])


def heading(e: Element, at_end: bool) -> tuple[float, float]:
    """The unit direction of travel at an element's start or end."""
    if e.center is None:
        d = (e.end[0] - e.start[0], e.end[1] - e.start[1])
    else:
        p = e.end if at_end else e.start
        r = (p[0] - e.center[0], p[1] - e.center[1])
        d = (r[1], -r[0]) if e.direction == "cw" else (-r[1], r[0])
    n = math.hypot(*d) or 1.0
    return (d[0] / n, d[1] / n)


def transitions(f: Feature) -> dict[int, tuple[float, float]]:
    """The rounded and chamfered corners a block makes with its transition word (PAL RN, Beckhoff #RND, #CHR,
    #CHF, Sinumerik RND, CHR): an arc tangent to the lines before and after it, or a 45° chamfer between two
    perpendicular lines, that comes from the same block as the line before it. They are dimensioned as drawings
    do (and as the block programs them): the sharp corner the two lines make, and the radius or chamfer.
    Index of the element → the corner."""
    out: dict[int, tuple[float, float]] = {}
    els = f.elements
    for k in range(1, len(els) - 1):
        prev, e, nxt = els[k - 1], els[k], els[k + 1]
        if prev.is_arc or nxt.is_arc or prev.line != e.line:
            continue
        if math.dist(prev.end, e.start) > EPS or math.dist(e.end, nxt.start) > EPS:
            continue
        u, v = heading(prev, True), heading(nxt, False)
        if e.is_arc:
            a, b = heading(e, False), heading(e, True)
            if u[0] * a[0] + u[1] * a[1] < 1 - 1e-6 or v[0] * b[0] + v[1] * b[1] < 1 - 1e-6:
                continue
        elif chamfer_leg(prev, e, nxt) is None:
            continue
        corner = _cross(prev.end, u, nxt.start, v)
        if corner is not None:
            out[k] = corner
    return out


def points(f: Feature, stock: Stock) -> list[tuple[float, float]]:
    """The corner points, arc end points and arc centres of a feature that lie on the blank; for a rounded or
    chamfered corner (`transitions`) the sharp corner instead of the ends and the centre of its radius or
    chamfer."""
    corners = transitions(f)
    pts: list[tuple[float, float]] = []
    for k, e in enumerate(f.elements):
        if k in corners:
            candidates = [corners[k]]
        else:
            candidates = [] if k - 1 in corners else [e.start]
            candidates += [] if k + 1 in corners else [e.end]
            candidates += [e.center] if e.center is not None and visible(e, stock) else []
        pts += [p for p in candidates if on_stock(p, stock)]
    return pts


@dataclass(frozen=True)
class Hole:
    """A plunge that is not the start of a cut in the plane: a hole or recess the tool's size (drilled, or sunk
    with a slot drill), at its centre (x, y) down to z."""

    x: float
    y: float
    z: float
    diameter: float
    tool: int | None
    line: int
    name: str = ""  # a tapped hole's thread ("M8"): printed instead of the diameter


def holes(moves: list[Move], stock: Stock, tools: ToolTable) -> list[Hole]:
    """The plunges below the stock top after which the tool goes up again (not on in the plane: that plunge
    starts a pocket or contour), the deepest per position and tool, in program order."""
    found: dict[tuple[float, float, int | None], Hole] = {}
    for i, m in enumerate(moves):
        if (
            m.kind != "feed"
            or math.dist(_xy(m.start), _xy(m.end)) > EPS
            or m.end[2] >= min(m.start[2], stock.z1) - EPS
        ):
            continue
        after = next((n for n in moves[i + 1 :] if math.dist(n.start, n.end) > EPS), None)
        if after is not None and _in_plane_cut(after, stock.z1):
            continue
        if after is not None and after.end[2] < m.end[2] - EPS:
            continue  # deeper still: the last plunge of the peck counts
        tool = tools.get(m.tool) if m.tool is not None else None
        if tool is None or tool.diameter <= 0 or not on_stock(_xy(m.end), stock):
            continue
        key = (round(m.end[0], 6), round(m.end[1], 6), m.tool)
        if key not in found or m.end[2] < found[key].z:
            found[key] = Hole(m.end[0], m.end[1], m.end[2], tool.diameter, m.tool, m.span.line)
    return list(found.values())


def chamfer_leg(prev: Element, e: Element, nxt: Element) -> float | None:
    """The leg of a 45° chamfer `e` between two perpendicular lines, or None if `e` is no such chamfer."""
    if prev.is_arc or e.is_arc or nxt.is_arc:
        return None

    def direction(x: Element) -> tuple[float, float]:
        length = x.length()
        return ((x.end[0] - x.start[0]) / length, (x.end[1] - x.start[1]) / length)

    if min(prev.length(), e.length(), nxt.length()) < EPS:
        return None
    a, b, c = direction(prev), direction(e), direction(nxt)
    perpendicular = abs(a[0] * c[0] + a[1] * c[1]) < 1e-6
    at_45 = abs(abs(a[0] * b[0] + a[1] * b[1]) - math.sqrt(0.5)) < 1e-6
    if perpendicular and at_45 and abs(abs(b[0] * c[0] + b[1] * c[1]) - math.sqrt(0.5)) < 1e-6:
        return e.length() * math.sqrt(0.5)
    return None


def line_angle(e: Element) -> float | None:
    """The angle of a slanted line against +X in degrees (0…180), None for lines parallel to an axis."""
    if e.is_arc or e.length() < EPS:
        return None
    a = math.degrees(math.atan2(e.end[1] - e.start[1], e.end[0] - e.start[0])) % 180
    if min(abs(a), abs(a - 90), abs(a - 180)) < 1e-6:
        return None
    return a


def distinct(values: list[float]) -> list[float]:
    """Sorted values with those closer than POINT_TOLERANCE merged (the first one kept)."""
    out: list[float] = []
    for v in sorted(values):
        if not out or v - out[-1] > POINT_TOLERANCE:
            out.append(v)
    return out
