"""Circular arcs in a plane: centres from radius or partial centre data, swept angles.

Pure functions on 2D points (tuples). Angles in degrees; clockwise as seen looking from the
positive third axis towards the plane (DIN 66025).
"""

from __future__ import annotations

import math

Point = tuple[float, float]

EPS = 1e-9


def sweep(start: Point, end: Point, centre: Point, clockwise: bool) -> float:
    """Swept angle in degrees, in (0, 360], going from start to end in the given sense.

    An end equal to the start (within 1e-6 mm) is a full circle: 360°.
    """
    a0 = math.atan2(start[1] - centre[1], start[0] - centre[0])
    a1 = math.atan2(end[1] - centre[1], end[0] - centre[0])
    delta = (a0 - a1) if clockwise else (a1 - a0)
    delta %= 2 * math.pi
    if delta < 1e-12 or math.dist(start, end) < 1e-6:
        return 360.0
    return math.degrees(delta)


def centres_from_radius(start: Point, end: Point, radius: float) -> list[Point]:
    """The centres of the circles of `radius` through start and end: 0, 1 (half circle) or 2."""
    dx, dy = end[0] - start[0], end[1] - start[1]
    chord = math.hypot(dx, dy)
    if chord < EPS or radius < EPS:
        return []
    half = chord / 2
    if half > radius + 1e-7:
        return []
    h = math.sqrt(max(radius * radius - half * half, 0.0))
    mx, my = start[0] + dx / 2, start[1] + dy / 2
    if h < 1e-7:
        return [(mx, my)]
    ux, uy = -dy / chord, dx / chord  # unit normal, left of start → end
    return [(mx + h * ux, my + h * uy), (mx - h * ux, my - h * uy)]


def centre_by_radius(start: Point, end: Point, radius: float, clockwise: bool, longer: bool) -> Point | None:
    """The centre for an arc of `radius` from start to end: the shorter (≤ 180°) or the longer one."""
    candidates = centres_from_radius(start, end, radius)
    if not candidates:
        return None
    return (max if longer else min)(candidates, key=lambda c: sweep(start, end, c, clockwise))


def centre_on_bisector(start: Point, end: Point, cx: float | None, cy: float | None) -> Point | None:
    """The centre equidistant from start and end with one coordinate given; None if there is none or many."""
    dx, dy = end[0] - start[0], end[1] - start[1]
    k = (end[0] ** 2 + end[1] ** 2 - start[0] ** 2 - start[1] ** 2) / 2  # dx·cx + dy·cy = k
    if cx is not None:
        return None if abs(dy) < EPS else (cx, (k - dx * cx) / dy)
    if cy is not None:
        return None if abs(dx) < EPS else ((k - dy * cy) / dx, cy)
    return None


def rotate(p: Point, centre: Point, degrees: float) -> Point:
    a = math.radians(degrees)
    dx, dy = p[0] - centre[0], p[1] - centre[1]
    return (centre[0] + dx * math.cos(a) - dy * math.sin(a), centre[1] + dx * math.sin(a) + dy * math.cos(a))


def _root(v: float) -> list[float]:
    """±√v as a list: empty when v < 0, one value when v ≈ 0."""
    if v < -1e-9:
        return []
    s = math.sqrt(max(v, 0.0))
    return [s] if s < 1e-9 else [s, -s]


def arc_solutions(  # noqa: C901
    start: Point,
    clockwise: bool,
    ex: float | None = None,
    ey: float | None = None,
    cx: float | None = None,
    cy: float | None = None,
    r: float | None = None,
    ao: float | None = None,
    tol: float = 0.01,
) -> list[tuple[Point, Point]]:
    """All arcs from `start` in the given sense that meet every given address: (centre, end) pairs.

    Given addresses may be any combination of end X/Y, centre X/Y, radius R and opening angle
    AO (degrees). With three of them there are 0 to 4 solutions; a fourth must agree within `tol`.
    """
    sx, sy = start
    phi = -ao if (ao is not None and clockwise) else ao  # signed rotation start → end
    centres: list[Point] = []
    if cx is not None and cy is not None:
        centres = [(cx, cy)]
    elif r is not None and (cx is not None or cy is not None):
        if cx is not None:
            centres = [(cx, sy + h) for h in _root(r * r - (sx - cx) ** 2)]
        elif cy is not None:
            centres = [(sx + h, cy) for h in _root(r * r - (sy - cy) ** 2)]
    elif ex is not None and ey is not None and (cx is not None or cy is not None):
        c = centre_on_bisector(start, (ex, ey), cx, cy)
        centres = [c] if c is not None else []
    elif ex is not None and ey is not None and r is not None:
        centres = centres_from_radius(start, (ex, ey), r)
    elif ex is not None and ey is not None and phi is not None:
        chord = math.dist(start, (ex, ey))
        s = math.sin(math.radians(ao or 0) / 2)
        centres = (
            centres_from_radius(start, (ex, ey), chord / (2 * s)) if abs(s) > EPS and chord > EPS else []
        )
    elif phi is not None and (cx is not None or cy is not None) and (ex is not None or ey is not None):
        c_phi, s_phi = math.cos(math.radians(phi)), math.sin(math.radians(phi))
        if cx is not None and ex is not None and abs(s_phi) > EPS:
            centres = [(cx, sy + (ex - cx - (sx - cx) * c_phi) / s_phi)]
        elif cy is not None and ey is not None and abs(s_phi) > EPS:
            centres = [(sx + (ey - cy - (sy - cy) * c_phi) / -s_phi, cy)]
        elif cx is not None and ey is not None and abs(1 - c_phi) > EPS:
            # ey = cy + (sx-cx)·sin φ + (sy-cy)·cos φ  →  cy(1 - cos φ) = ey - (sx-cx)·sin φ - sy·cos φ
            centres = [(cx, (ey - (sx - cx) * s_phi - sy * c_phi) / (1 - c_phi))]
        elif cy is not None and ex is not None and abs(1 - c_phi) > EPS:
            centres = [((ex + (sy - cy) * s_phi - sx * c_phi) / (1 - c_phi), cy)]
    elif phi is not None and r is not None and (ex is not None or ey is not None):
        chord = 2 * r * abs(math.sin(math.radians(ao or 0) / 2))
        ends: list[Point] = []
        if ex is not None:
            ends = [(ex, sy + h) for h in _root(chord * chord - (ex - sx) ** 2)]
        elif ey is not None:
            ends = [(sx + h, ey) for h in _root(chord * chord - (ey - sy) ** 2)]
        for e in ends:
            centres += centres_from_radius(start, e, r)

    solutions: list[tuple[Point, Point]] = []
    for c in centres:
        radius = math.dist(start, c)
        if radius < 1e-6:
            continue
        if phi is not None:
            ends = [rotate(start, c, phi)]
        elif ex is not None and ey is not None:
            ends = [(ex, ey)]
        elif ex is not None:
            ends = [(ex, c[1] + h) for h in _root(radius * radius - (ex - c[0]) ** 2)]
        elif ey is not None:
            ends = [(c[0] + h, ey) for h in _root(radius * radius - (ey - c[1]) ** 2)]
        else:
            ends = [start]  # full circle
        for e in ends:
            ok = abs(math.dist(e, c) - radius) <= tol
            ok = ok and (ex is None or abs(e[0] - ex) <= tol) and (ey is None or abs(e[1] - ey) <= tol)
            ok = ok and (cx is None or abs(c[0] - cx) <= tol) and (cy is None or abs(c[1] - cy) <= tol)
            ok = ok and (r is None or abs(radius - r) <= tol)
            if ok and ao is not None:
                ok = abs(sweep(start, e, c, clockwise) - ao) <= 1e-4 or (
                    ao >= 360 - 1e-9 and math.dist(start, e) < 1e-6
                )
            if ok and all(math.dist(c, c2) > 1e-7 or math.dist(e, e2) > 1e-7 for c2, e2 in solutions):
                solutions.append((c, e))
    return solutions


def choose_arc(
    start: Point, clockwise: bool, solutions: list[tuple[Point, Point]], longer: bool, h2: bool
) -> tuple[Point, Point] | None:
    """The PAL selection among arc solutions: by arc length (shorter unless `longer`), then by start tangent angle.

    The start tangent angle is the direction of motion at the start, counter-clockwise from +X,
    normalised to [0°, 360°); H1 takes the smaller, H2 the larger (DECISIONS.md §4).
    """
    if not solutions:
        return None

    def length(sol: tuple[Point, Point]) -> float:
        c, e = sol
        return math.radians(sweep(start, e, c, clockwise)) * math.dist(start, c)

    lengths = [length(s) for s in solutions]
    best = max(lengths) if longer else min(lengths)
    pool = [s for s, ln in zip(solutions, lengths, strict=True) if abs(ln - best) <= 1e-6]

    def start_angle(sol: tuple[Point, Point]) -> float:
        c = sol[0]
        rx, ry = start[0] - c[0], start[1] - c[1]
        t = (ry, -rx) if clockwise else (-ry, rx)
        return math.degrees(math.atan2(t[1], t[0])) % 360.0

    return (max if h2 else min)(pool, key=start_angle)
