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
