"""The cutting shape of a lathe tool in the drawing view (Z right, X up), for the turning simulation.

An insert is a convex polygon (its "core", with a corner at the nose-radius centre) grown by the nose
radius R: rhombic inserts C (80°), D (55°) and V (35°) as two cutting edges leaving the nose, a grooving
insert as a rectangle of width B, a thread insert as a 60° point. The shape is built for quadrant P1
(nose centre at +Z/+X of the theoretical tip, an outside tool cutting towards the chuck, DECISIONS §16)
and mirrored for P2–P4. Quadrants P3/P4 are inside tools: they remove material from the bore.
A milling kind (drill, end mill) on the lathe is an axial tool that bores from the face.

`lower_envelope` gives, on sample positions z, the lowest point of a convex polygon grown by a radius:
the shape swept along a straight piece is the convex hull of its two end positions, so a move's cut on
the revolved profile is the minimum of these envelopes (upper envelopes by mirroring X). `convex_hull` is the
one convex hull of the project (the 3D view's insert outlines, core/scene/meshes.py, use it too).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from core.sim.shapes import Array
from core.tools import Tool

QUADRANT: dict[int, tuple[float, float]] = {
    1: (1.0, 1.0),
    2: (-1.0, 1.0),
    3: (-1.0, -1.0),
    4: (1.0, -1.0),
}  # (z, x)
INSERT_ANGLE = {"C": 80.0, "D": 55.0, "V": 35.0, "thread": 60.0}
EDGE_LENGTH = {
    "C": 12.9,
    "D": 15.5,
    "V": 16.6,
    "thread": 5.0,
}  # mm: ISO 12/15/16 inserts, a 16 mm thread insert
CUTTING_LENGTH = {"C": 8.0, "D": 6.0, "V": 4.0, "thread": 3.0, "groove": 10.0}  # mm: usable depth of cut
INSIDE_EDGE = 6.4  # mm: the small inserts (CCMT 06) of a boring bar
APPROACH = 93.0  # degrees: the approach angle κ of a copying holder (SDJCR, SVJBR, …)
HOLDER_SETBACK = 1.0  # mm: the holder's side behind the theoretical tip along Z
HOLDER_WIDTH = 25.0  # mm: a 25 × 25 shank; a boring bar's default diameter is 16 mm
BAR_DIAMETER = 16.0
BAR_CLEARANCE = 1.0  # mm: a boring bar's top below the theoretical tip
FAR = 500.0  # mm: "to the end of the machine" for holders


@dataclass(frozen=True, slots=True)
class Insert:
    """A tool's cutting shape relative to its nose-radius centre; `tip` is the theoretical tip relative to it."""

    number: int
    kind: str  # "C" | "D" | "V" | "groove" | "thread" | "axial"
    radius: float  # nose radius R
    core: tuple[tuple[float, float], ...]  # convex polygon (z, x), nose centre at (0, 0)
    holder: tuple[tuple[float, float], ...]  # convex polygon (z, x) of the holder; () none
    inside: bool  # removes from the bore (P3, P4, axial tools)
    tip: tuple[float, float]  # theoretical tip − nose centre (z, x)
    cutting_length: float  # mm: the usable depth of cut
    direction: int  # −1 cuts towards −Z, +1 towards +Z (the quadrant's side of the body, mirrored)


def _mirror(points: list[tuple[float, float]], sz: float, sx: float) -> tuple[tuple[float, float], ...]:
    return tuple((sz * z, sx * x) for z, x in points)


def insert_of(tool: Tool | None, number: int) -> Insert:
    """The cutting shape of `tool` (a generic outside tool, C 80° R0.4 P1, when the table has no lathe tool)."""
    if tool is not None and tool.kind != "turning":
        return _axial(tool)
    r = tool.nose_radius if tool is not None else 0.4
    quadrant = tool.quadrant if tool is not None and tool.quadrant in QUADRANT else 1
    kind = (tool.insert if tool is not None else "") or "C"
    inside = quadrant in (3, 4)
    qz, qx = QUADRANT[quadrant]
    cutting = (
        tool.cutting_length if tool is not None and tool.cutting_length is not None else CUTTING_LENGTH[kind]
    )
    if kind == "groove":
        assert tool is not None
        b = max(tool.width, 2 * r + 0.01)
        core = [(0.0, 0.0), (b - 2 * r, 0.0), (b - 2 * r, cutting), (0.0, cutting)]
        height = cutting + r
        hz = (-2.0, b + (tool.holder or HOLDER_WIDTH))
    else:
        eps = tool.insert_angle if tool is not None and tool.insert_angle else INSERT_ANGLE[kind]
        edge = INSIDE_EDGE if inside else EDGE_LENGTH[kind]
        if kind == "thread":
            t1, t2 = math.radians(90 + eps / 2), math.radians(90 - eps / 2)
        else:
            t1 = math.radians(180 - APPROACH)
            t2 = t1 - math.radians(eps)
        u1 = (edge * math.cos(t1), edge * math.sin(t1))
        u2 = (edge * math.cos(t2), edge * math.sin(t2))
        core = (
            [(0.0, 0.0), u2, (u1[0] + u2[0], u1[1] + u2[1]), u1] if kind != "thread" else [(0.0, 0.0), u2, u1]
        )
        height = max(x for _, x in core) + r
        width = tool.holder if tool is not None and tool.holder else HOLDER_WIDTH
        hz = (-r + HOLDER_SETBACK, -r + HOLDER_SETBACK + width)
    if inside:
        core_m = _mirror(core, qz, -1.0)
        bar = tool.holder if tool is not None and tool.holder else BAR_DIAMETER
        top = r - BAR_CLEARANCE  # the tip is R above the nose centre of an inside tool
        zs = max(z for z, _ in core_m) + r  # the bar leaves the bore towards the turret (+Z)
        holder_m: tuple[tuple[float, float], ...] = ((zs, top - bar), (FAR, top - bar), (FAR, top), (zs, top))
    else:
        core_m = _mirror(core, qz, 1.0)
        holder_m = _mirror([(hz[0], height), (hz[1], height), (hz[1], FAR), (hz[0], FAR)], qz, 1.0)
    return Insert(number, kind, r, core_m, holder_m, inside, (-qz * r, -qx * r), cutting, -1 if qz > 0 else 1)


def _axial(tool: Tool) -> Insert:
    """A drill or end mill on the spindle axis: a point (cone) and its body towards +Z, boring from the face."""
    d = tool.diameter / 2
    angle = tool.point_angle or (
        118.0 if tool.kind == "twist_drill" else 90.0 if tool.kind == "spot_drill" else 180.0
    )
    h = d / math.tan(math.radians(angle / 2)) if angle < 179.9 else 0.0
    length = max(tool.flute_length, h + 1.0)
    core = (
        ((0.0, 0.0), (h, -d), (length, -d), (length, d), (h, d))
        if h > 0
        else ((0.0, -d), (length, -d), (length, d), (0.0, d))
    )
    return Insert(tool.number, "axial", 0.0, core, (), True, (0.0, 0.0), tool.flute_length, -1)


Point = tuple[float, float]


def _chain(points: list[Point]) -> list[Point]:
    """One chain of Andrew's monotone chain over `points` in sorted order: every turn is to the left, collinear
    points are dropped."""
    out: list[Point] = []
    for p in points:
        while (
            len(out) >= 2
            and (
                (out[-1][0] - out[-2][0]) * (p[1] - out[-2][1])
                - (out[-1][1] - out[-2][1]) * (p[0] - out[-2][0])
            )
            <= 0
        ):
            out.pop()
        out.append(p)
    return out


def lower_hull(points: list[Point]) -> list[Point]:
    """The lower chain of the convex hull, sorted by z (Andrew's monotone chain)."""
    return _chain(sorted(set(points)))


def convex_hull(points: list[Point]) -> list[Point]:
    """The convex hull of 2-D points, counter-clockwise from the lowest z (then x); fewer than three distinct
    points come back sorted."""
    pts = sorted(set(points))
    if len(pts) < 3:
        return pts
    lower, upper = _chain(pts), _chain(pts[::-1])
    return lower[:-1] + upper[:-1]


def lower_envelope(zs: Array, chain: list[tuple[float, float]], radius: float) -> Array:
    """On samples `zs`, the lowest x of the region above `chain` (a lower hull) grown by `radius`; +inf
    where the region does not reach."""
    env = np.full(zs.shape, np.inf)
    pts = np.asarray(chain, dtype=np.float64)
    if radius > 0:
        for pz, px in pts:
            d = zs - pz
            inside = np.abs(d) <= radius
            if inside.any():
                env[inside] = np.minimum(env[inside], px - np.sqrt(radius * radius - d[inside] ** 2))
    if len(pts) == 1:
        if radius == 0:
            env[np.abs(zs - pts[0, 0]) <= 1e-9] = pts[0, 1]
        return env
    a, b = pts[:-1], pts[1:]
    dz, dx = b[:, 0] - a[:, 0], b[:, 1] - a[:, 1]
    length = np.hypot(dz, dx)
    ok = dz > 1e-12
    a, dz, dx, length = a[ok], dz[ok], dx[ok], length[ok]
    nz, nx = dx / length * radius, -dz / length * radius  # the outward normal of a lower edge (nx ≤ 0)
    z0 = a[:, 0] + nz
    x0 = a[:, 1] + nx
    z1 = z0 + dz
    for k in range(len(z0)):
        i0, i1 = np.searchsorted(zs, (z0[k], z1[k]), side="left")
        if i1 > i0:
            seg = x0[k] + (zs[i0:i1] - z0[k]) * (dx[k] / dz[k])
            np.minimum(env[i0:i1], seg, out=env[i0:i1])
    return env
