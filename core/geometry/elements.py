"""Contour elements in the plane — lines and arcs — and what the control computes from them.

Offsets (equidistants), intersections, tangents, roundings (RN+) and chamfers (RN−). Pure
functions on immutable values; points are (x, y) tuples in mm. "Left" is seen in the direction
of travel. One offset-and-intersect routine serves both the rounding of a corner and the inside
corner of cutter radius compensation.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from core.geometry.arcs import sweep
from core.values import value

Point = tuple[float, float]
EPS = 1e-9
ON_TOL = 1e-6  # mm: a point this close to an element lies on it


@value
class Line:
    a: Point
    b: Point

    @property
    def length(self) -> float:
        return math.dist(self.a, self.b)


@value
class Arc:
    a: Point
    b: Point
    c: Point
    cw: bool
    full: bool = False  # a == b means a full circle when True, a point otherwise

    @property
    def radius(self) -> float:
        return math.dist(self.a, self.c)

    @property
    def angle(self) -> float:
        """Swept angle in degrees (0, 360]."""
        if self.full:
            return 360.0
        return sweep(self.a, self.b, self.c, self.cw)

    @property
    def length(self) -> float:
        return math.radians(self.angle) * self.radius


Element = Line | Arc


def unit(v: Point) -> Point:
    n = math.hypot(v[0], v[1])
    return (v[0] / n, v[1] / n) if n > EPS else (0.0, 0.0)


def left(v: Point) -> Point:
    return (-v[1], v[0])


def cross(u: Point, v: Point) -> float:
    return u[0] * v[1] - u[1] * v[0]


def dot(u: Point, v: Point) -> float:
    return u[0] * v[0] + u[1] * v[1]


def add(p: Point, v: Point, k: float = 1.0) -> Point:
    return (p[0] + k * v[0], p[1] + k * v[1])


def tangent_at(e: Element, p: Point) -> Point:
    """Unit direction of travel of `e` at its point `p`."""
    if isinstance(e, Line):
        return unit((e.b[0] - e.a[0], e.b[1] - e.a[1]))
    radial = unit((p[0] - e.c[0], p[1] - e.c[1]))
    return (radial[1], -radial[0]) if e.cw else left(radial)


def start_tangent(e: Element) -> Point:
    return tangent_at(e, e.a)


def end_tangent(e: Element) -> Point:
    return tangent_at(e, e.b)


def angle_of(v: Point) -> float:
    """Direction angle in degrees, counter-clockwise from +X, in [0, 360)."""
    return math.degrees(math.atan2(v[1], v[0])) % 360.0


def offset(e: Element, d: float) -> Element | None:
    """The equidistant of `e` at distance d to the left (d < 0: right); None if an arc vanishes or reverses."""
    if isinstance(e, Line):
        n = left(unit((e.b[0] - e.a[0], e.b[1] - e.a[1])))
        return Line(add(e.a, n, d), add(e.b, n, d))
    # left of a counter-clockwise arc is towards the centre
    r = e.radius
    new_r = r + d if e.cw else r - d
    if new_r <= ON_TOL:
        return None
    ua, ub = unit((e.a[0] - e.c[0], e.a[1] - e.c[1])), unit((e.b[0] - e.c[0], e.b[1] - e.c[1]))
    return Arc(add(e.c, ua, new_r), add(e.c, ub, new_r), e.c, e.cw, e.full)


def intersections(e1: Element, e2: Element) -> list[Point]:
    """Intersection points of the carriers of two elements (infinite line, full circle)."""
    if isinstance(e1, Line) and isinstance(e2, Line):
        d1 = (e1.b[0] - e1.a[0], e1.b[1] - e1.a[1])
        d2 = (e2.b[0] - e2.a[0], e2.b[1] - e2.a[1])
        den = cross(d1, d2)
        if abs(den) < EPS * max(1.0, math.hypot(*d1) * math.hypot(*d2)):
            return []
        t = cross((e2.a[0] - e1.a[0], e2.a[1] - e1.a[1]), d2) / den
        return [add(e1.a, d1, t)]
    if isinstance(e1, Arc) and isinstance(e2, Line):
        return intersections(e2, e1)
    if isinstance(e1, Line) and isinstance(e2, Arc):
        return line_circle(e1.a, e1.b, e2.c, e2.radius)
    assert isinstance(e1, Arc) and isinstance(e2, Arc)
    return circle_circle(e1.c, e1.radius, e2.c, e2.radius)


def line_circle(a: Point, b: Point, c: Point, r: float) -> list[Point]:
    d = unit((b[0] - a[0], b[1] - a[1]))
    f = (a[0] - c[0], a[1] - c[1])
    t0 = -dot(f, d)
    foot = add(a, d, t0)
    h2 = r * r - math.dist(foot, c) ** 2
    if h2 < -1e-9:
        return []
    h = math.sqrt(max(h2, 0.0))
    if h < 1e-9:
        return [foot]
    return [add(foot, d, -h), add(foot, d, h)]


def circle_circle(c1: Point, r1: float, c2: Point, r2: float) -> list[Point]:
    dd = math.dist(c1, c2)
    if dd < EPS or dd > r1 + r2 + 1e-9 or dd < abs(r1 - r2) - 1e-9:
        return []
    a = (r1 * r1 - r2 * r2 + dd * dd) / (2 * dd)
    h = math.sqrt(max(r1 * r1 - a * a, 0.0))
    u = unit((c2[0] - c1[0], c2[1] - c1[1]))
    m = add(c1, u, a)
    if h < 1e-9:
        return [m]
    n = left(u)
    return [add(m, n, h), add(m, n, -h)]


def param(e: Element, p: Point) -> float:
    """Where `p` lies along `e`: 0 at the start, 1 at the end (projected; arcs by angle)."""
    if isinstance(e, Line):
        d = (e.b[0] - e.a[0], e.b[1] - e.a[1])
        n2 = dot(d, d)
        return dot((p[0] - e.a[0], p[1] - e.a[1]), d) / n2 if n2 > EPS else 0.0
    total = e.angle
    part = sweep(e.a, p, e.c, e.cw) % 360.0
    if part > total + 1e-7 and 360.0 - part < 1e-7:
        part = 0.0
    return part / total if total > EPS else 0.0


def on_element(e: Element, p: Point, tol: float = ON_TOL) -> bool:
    if math.dist(p, e.a) <= tol or math.dist(p, e.b) <= tol:
        return True
    t = param(e, p)
    return -1e-9 <= t <= 1 + 1e-9


def with_start(e: Element, p: Point) -> Element:
    return Line(p, e.b) if isinstance(e, Line) else Arc(p, e.b, e.c, e.cw, False)


def with_end(e: Element, p: Point) -> Element:
    return Line(e.a, p) if isinstance(e, Line) else Arc(e.a, p, e.c, e.cw, False)


def nearest(points: list[Point], to: Point) -> Point | None:
    return min(points, key=lambda q: math.dist(q, to)) if points else None


def turn(e1: Element, e2: Element) -> float:
    """Sign of the turn at the joint e1 → e2: > 0 left, < 0 right, 0 tangent or reversing."""
    c = cross(end_tangent(e1), start_tangent(e2))
    return 0.0 if abs(c) < 1e-9 else c


@dataclass(frozen=True, slots=True)
class Transition:
    """An element inserted at a corner, with the trimmed neighbours."""

    first: Element
    inserted: Element
    second: Element


def rounding(e1: Element, e2: Element, r: float) -> Transition | None:
    """RN+: an arc of radius r tangent to both elements; None if it does not fit."""
    side = turn(e1, e2)
    if side == 0.0 or r <= 0:
        return None
    d = r if side > 0 else -r  # the centre lies on the inside of the turn
    o1, o2 = offset(e1, d), offset(e2, d)
    if o1 is None or o2 is None:
        return None
    centre = nearest(intersections(o1, o2), e1.b)
    if centre is None:
        return None
    t1, t2 = foot(e1, centre), foot(e2, centre)
    if not (on_element(e1, t1) and on_element(e2, t2)):
        return None
    if math.dist(t1, e1.a) <= ON_TOL or math.dist(t2, e2.b) <= ON_TOL:
        return None  # the rounding would eat a whole element
    return Transition(with_end(e1, t1), Arc(t1, t2, centre, cw=side < 0), with_start(e2, t2))


def chamfer(e1: Element, e2: Element, width: float) -> Transition | None:
    """RN−: a straight chamfer whose ends lie at chord distance `width` from the corner; None if it does not fit."""
    if width <= 0 or turn(e1, e2) == 0.0:
        return None
    corner = e1.b
    p1 = _at_chord(e1, corner, width, from_end=True)
    p2 = _at_chord(e2, corner, width, from_end=False)
    if p1 is None or p2 is None:
        return None
    return Transition(with_end(e1, p1), Line(p1, p2), with_start(e2, p2))


def _at_chord(e: Element, corner: Point, width: float, from_end: bool) -> Point | None:
    """The point of `e` at straight-line distance `width` from `corner` (one of its end points)."""
    if isinstance(e, Line):
        if width >= e.length - ON_TOL:
            return None
        t = unit((e.b[0] - e.a[0], e.b[1] - e.a[1]))
        return add(corner, t, -width if from_end else width)
    candidates = [p for p in circle_circle(corner, width, e.c, e.radius) if on_element(e, p)]
    if not candidates:
        return None
    far_end = e.a if from_end else e.b
    if math.dist(far_end, corner) <= width + ON_TOL and not e.full:
        return None
    # the candidate nearer to the corner along the arc
    return min(candidates, key=lambda p: abs(param(e, p) - (1.0 if from_end else 0.0)))


def foot(e: Element, p: Point) -> Point:
    """The point of the carrier of `e` nearest to `p`."""
    if isinstance(e, Line):
        d = unit((e.b[0] - e.a[0], e.b[1] - e.a[1]))
        return add(e.a, d, dot((p[0] - e.a[0], p[1] - e.a[1]), d))
    u = unit((p[0] - e.c[0], p[1] - e.c[1]))
    return add(e.c, u, e.radius)
