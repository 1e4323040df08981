"""Meshes and line sets of the 3D view (scene mm, Z up): primitives (revolve, prism, box), the toolpath's
dashes, the stock's outline, the milling tools, the turning tools' inserts and holders.

A mesh is (vertices float32 (n, 3), triangles uint32 (m, 3)); line sets are segments float32 (n, 2, 3).
Tool shapes are frozen values made from the tool table in a worker (they cross the process boundary and
say by equality whether the scene's tool must be rebuilt).
"""

from __future__ import annotations

import hashlib
import itertools
from dataclasses import dataclass
from typing import Any, NamedTuple

import numpy as np
import numpy.typing as npt

from core.sim.insert import Insert, convex_hull
from core.tools import Tool

Vertices = npt.NDArray[np.float32]
Triangles = npt.NDArray[np.uint32]
Mesh = tuple[Vertices, Triangles]
Segments = npt.NDArray[np.float32]  # (n, 2, 3)
Tiles = dict[str, tuple[str, Vertices, npt.NDArray[Any]]]  # key → (digest, vertices mm, triangles)
Vec3 = tuple[float, float, float]

SECTIONS = 48  # a revolved mesh's sections around the axis; a half section keeps the back 24
DASH, GAP = 2.0, 1.5  # mm: rapid moves are drawn dashed
MAX_DASHES = 30_000
FLUTES = {"end_mill": 4, "slot_drill": 2, "ball_nose": 2, "torus": 4, "twist_drill": 2, "spot_drill": 2}
HELIX = 0.55  # rad: the cutting edges' helix angle (about 30°)
INSERT_THICKNESS = 4.8  # mm: an ISO insert (…04…) seen from the side; the holder is drawn as a thicker plate
HOLDER_THICKNESS = 12.0
HOLDER_REACH = 35.0  # mm of the holder drawn beyond the insert (the turret is not drawn)


# -- primitives -----------------------------------------------------------------------------------------------
def merge(parts: list[Mesh]) -> Mesh:
    """Several meshes as one."""
    vertices, triangles, base = [], [], 0
    for v, t in parts:
        vertices.append(v)
        triangles.append(t + base)
        base += len(v)
    if not vertices:
        return np.zeros((0, 3), np.float32), np.zeros((0, 3), np.uint32)
    return np.vstack(vertices).astype(np.float32), np.vstack(triangles).astype(np.uint32)


def digest(vertices: npt.NDArray[Any], triangles: npt.NDArray[Any]) -> str:
    """A mesh's content digest: the scene resends a chunk only when it changes."""
    return hashlib.blake2b(vertices.tobytes() + triangles.tobytes(), digest_size=12).hexdigest()


def _angles(half: bool, sections: int) -> tuple[npt.NDArray[np.float64], bool]:
    """The angles of the rings from the top (θ = 0) over the back; whether the last column wraps to the first."""
    if half:
        return np.linspace(0.0, np.pi, sections // 2 + 1), False
    return np.linspace(0.0, 2 * np.pi, sections, endpoint=False), True


def revolve(points: npt.NDArray[Any], half: bool, sections: int = SECTIONS) -> Mesh:
    """A polyline (z, r) revolved about the scene's x axis (the lathe's Z; θ = 0 up, +y at the back); in a
    half section only the back half (the camera looks from −y)."""
    theta, wrap = _angles(half, sections)
    columns = len(theta)
    z, r = points[:, 0][:, None], points[:, 1][:, None]
    vertices = np.stack(
        [np.broadcast_to(z, (len(points), columns)), r * np.sin(theta), r * np.cos(theta)], -1
    )
    i, j = np.meshgrid(np.arange(len(points) - 1), np.arange(columns if wrap else columns - 1), indexing="ij")
    a = i * columns + j
    b = i * columns + (j + 1) % columns
    quads = np.stack([a, b, b + columns, a + columns], -1).reshape(-1, 4)
    triangles = np.concatenate([quads[:, [0, 1, 2]], quads[:, [0, 2, 3]]])
    return vertices.reshape(-1, 3).astype(np.float32), triangles.astype(np.uint32)


def prism(outline: npt.NDArray[Any], thickness: float) -> Mesh:
    """A convex outline (z, x; counter-clockwise) as a plate across y, `thickness` thick and centred on y = 0:
    a closed solid, its faces wound outwards."""
    n = len(outline)
    front = np.stack([outline[:, 0], np.full(n, -thickness / 2), outline[:, 1]], -1)
    back = front + [0.0, thickness, 0.0]
    k = np.arange(n)
    fan = [(0, i, i + 1) for i in range(1, n - 1)]
    tris = (
        fan
        + [(n + a, n + c, n + b) for a, b, c in fan]
        + [t for i in k for t in ((i, n + (i + 1) % n, (i + 1) % n), (i, n + i, n + (i + 1) % n))]
    )
    return np.vstack([front, back]).astype(np.float32), np.asarray(tris, dtype=np.uint32)


def box(corners: npt.NDArray[Any]) -> Mesh:
    """A hexahedron from its 8 corners (index bits: z, tangential, radial)."""
    faces = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    tris = [t for a, b, c, d in faces for t in ((a, b, c), (a, c, d))]
    return corners.astype(np.float32), np.asarray(tris, dtype=np.uint32)


# -- line sets ------------------------------------------------------------------------------------------------
def dashed(segments: Segments) -> Segments:
    """Segments cut into dashes (DASH mm drawn, GAP mm left out), so that rapid moves read as dashed lines;
    longer dashes where there would be more than MAX_DASHES."""
    if not len(segments):
        return segments
    a, b = segments[:, 0, :].astype(np.float64), segments[:, 1, :].astype(np.float64)
    length = np.linalg.norm(b - a, axis=1)
    period = DASH + GAP
    total = float(np.ceil(length / period).sum())
    if total > MAX_DASHES:
        period *= total / MAX_DASHES
    dash = period * DASH / (DASH + GAP)
    pieces = []
    for p, q, n in zip(a, b, length, strict=True):
        if n <= dash:
            pieces.append((p, q))
            continue
        starts = np.arange(0.0, n, period)
        ends = np.minimum(starts + dash, n)
        d = (q - p) / n
        pieces.extend(zip(p + starts[:, None] * d, p + ends[:, None] * d, strict=True))
    return np.asarray(pieces, dtype=np.float32).reshape(-1, 2, 3)


def spindle_axis(lo: float, hi: float) -> Segments:
    """A lathe's spindle axis along the scene's x, a little beyond a part from `lo` to `hi`, dash-dotted as
    the centre line of a drawing (6 mm line, 1.5 gap, 1 mm dot, 1.5 gap)."""
    margin = max(5.0, 0.08 * (hi - lo))
    start, end = lo - margin, hi + margin
    pieces = []
    for a in np.arange(start, end, 10.0):
        pieces += [(a, min(a + 6.0, end)), (a + 7.5, a + 8.5)]
    pieces = [(a, b) for a, b in pieces if a < end and b > a]
    return np.array([[[a, 0.0, 0.0], [min(b, end), 0.0, 0.0]] for a, b in pieces], dtype=np.float32)


def stock_outline(lo: npt.NDArray[Any], hi: npt.NDArray[Any]) -> Segments:
    """The twelve edges of the stock's box: the blank stays readable where the material is gone and where its
    lit faces are close to the background."""
    corners = np.array([[x, y, z] for z in (lo[2], hi[2]) for y in (lo[1], hi[1]) for x in (lo[0], hi[0])])
    edges = [(0, 1), (2, 3), (4, 5), (6, 7), (0, 2), (1, 3), (4, 6), (5, 7), (0, 4), (1, 5), (2, 6), (3, 7)]
    return np.array([[corners[a], corners[b]] for a, b in edges], dtype=np.float32)


def footprint(radius: float, count: int = 64) -> Segments:
    """The circle a milling tool of `radius` cuts, at its tip (around the tool's axis)."""
    a = np.linspace(0.0, 2 * np.pi, count + 1)
    ring = np.stack([radius * np.cos(a), radius * np.sin(a), np.full_like(a, 0.05)], -1)
    return np.stack([ring[:-1], ring[1:]], 1).astype(np.float32)


# -- tools ------------------------------------------------------------------------------------------------------
class ToolMeshes(NamedTuple):
    """A tool as the scene draws it: the cutting part, the shank or holder (None: not drawn), the cutting edges."""

    cutter: Mesh
    shank: Mesh | None
    edges: Segments


@dataclass(frozen=True, slots=True)
class ToolShape:
    """A milling tool as the view draws it (mm): kind, Ø, cutting length, overall length, shank Ø, corner radius
    (torus), point angle (drills)."""

    kind: str
    diameter: float
    flute: float
    length: float
    shank: float
    corner: float = 0.0
    angle: float = 0.0

    @classmethod
    def of(cls, tool: Tool) -> ToolShape:
        """A tool table entry's shape."""
        return cls(
            str(tool.kind),
            float(tool.diameter),
            float(tool.flute_length),
            float(tool.length),
            float(tool.shank),
            float(tool.corner_radius),
            float(tool.point_angle),
        )

    @classmethod
    def cylinder(cls, radius: float) -> ToolShape:
        """No tool table entry: a plain end mill of the tool's radius."""
        return cls("end_mill", 2 * radius, 4 * radius, 4 * radius + 40, 2 * radius)


def _envelope(shape: ToolShape, z: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
    """The tool's outer radius at height z above its tip: the tip's form, the cutting part, the shank."""
    r = shape.diameter / 2
    out = np.where(z <= shape.flute, r, shape.shank / 2)
    if shape.kind == "ball_nose":
        out = np.where(z < r, np.sqrt(np.clip(r * r - (r - z) ** 2, 0, None)), out)
    elif shape.kind == "torus" and shape.corner > 0:
        c = min(shape.corner, r)
        out = np.where(z < c, r - c + np.sqrt(np.clip(c * c - (c - z) ** 2, 0, None)), out)
    elif shape.kind in ("twist_drill", "spot_drill"):
        half = np.radians((shape.angle or 118.0) / 2)
        cone = r / np.tan(half)
        out = np.where(z < cone, z * np.tan(half), out)
    return np.asarray(out, dtype=np.float64)


def tool_mesh(shape: ToolShape, around: int = 48) -> ToolMeshes:
    """The milling tool standing on its tip at the origin: the cutting part with its gullets, the shank and
    the cutting edges as helical line segments. An end mill has four edges, a slot drill two; a ball-nose
    mill a round tip, a drill a point."""
    r, flute, length = shape.diameter / 2, shape.flute, max(shape.length, shape.flute)
    n = FLUTES.get(shape.kind, 2)
    tip = r if shape.kind == "ball_nose" else 0.0
    zs_cut = np.unique(
        np.concatenate([np.linspace(0, min(max(tip, r), flute), 9), np.linspace(0, flute, 17)])
    )
    theta = np.linspace(0, 2 * np.pi, around, endpoint=False)

    def rings(zs: npt.NDArray[np.float64], gullets: bool) -> Mesh:
        env = _envelope(shape, zs)[:, None]
        phase = theta[None, :] - (zs[:, None] / max(r, 1e-6)) * np.tan(HELIX)
        depth = 0.16 * np.clip(np.cos(n * phase), 0, None) ** 3 if gullets else 0.0
        radius = np.broadcast_to(env * (1 - depth), (len(zs), around))
        pts = np.stack(
            [radius * np.cos(theta), radius * np.sin(theta), np.broadcast_to(zs[:, None], radius.shape)], -1
        )
        vertices = np.vstack([pts.reshape(-1, 3), [[0, 0, zs[0]], [0, 0, zs[-1]]]])
        k, m = len(zs), around
        tris = []
        for i in range(k - 1):
            for j in range(m):
                a, b = i * m + j, i * m + (j + 1) % m
                tris += [(a, b, b + m), (a, b + m, a + m)]
        bottom, top = k * m, k * m + 1
        tris += [(bottom, (j + 1) % m, j) for j in range(m)]
        tris += [(top, (k - 1) * m + j, (k - 1) * m + (j + 1) % m) for j in range(m)]
        return vertices.astype(np.float32), np.asarray(tris, dtype=np.uint32)

    zs = np.linspace(0, flute, 25)
    env = _envelope(shape, zs) * 1.005
    edges = []
    for e in range(n):
        angle = 2 * np.pi * e / n + (zs / max(r, 1e-6)) * np.tan(HELIX)
        pts = np.stack([env * np.cos(angle), env * np.sin(angle), zs], -1)
        edges += list(itertools.pairwise(pts))
    return ToolMeshes(
        rings(zs_cut, True),
        rings(np.array([flute, length]), False),
        np.asarray(edges, dtype=np.float32).reshape(-1, 2, 3),
    )


@dataclass(frozen=True, slots=True)
class InsertShape:
    """A turning tool's insert as the view draws it (from core/sim/insert.py): its outline (the core grown by
    the nose radius) and its holder (cut off HOLDER_REACH beyond the insert), (z, x) mm relative to the
    theoretical tip, which is `tip` from the nose-radius centre."""

    insert: str  # "C", "D", "V", "groove", "thread", "axial"
    outline: tuple[tuple[float, float], ...]
    holder: tuple[tuple[float, float], ...]
    tip: tuple[float, float]

    def position(self, point: Vec3, centre: bool) -> Vec3:
        """Where the mesh (made around the theoretical tip) goes when the path's point is `point` (scene mm):
        under SRK (`centre`) the path is the nose centre's, and the tip is beside it."""
        tz, tx = self.tip if centre else (0.0, 0.0)
        return (point[0] + tz, point[1], point[2] + tx)


def insert_shape(insert: Insert) -> InsertShape:
    """A lathe tool's cutting shape as the view draws it."""
    r, (tz, tx) = float(insert.radius), insert.tip
    core = np.asarray(insert.core, dtype=np.float64)
    if r > 0:
        a = np.linspace(0, 2 * np.pi, 24, endpoint=False)
        core = (core[:, None, :] + r * np.stack([np.cos(a), np.sin(a)], -1)[None]).reshape(-1, 2)
    hull = convex_hull([(round(float(z), 6), round(float(x), 6)) for z, x in core])
    outline = np.asarray(hull, dtype=np.float64).reshape(-1, 2) - (tz, tx)
    holder = np.asarray(insert.holder, dtype=np.float64).reshape(-1, 2) - (tz, tx)
    if len(holder):
        lo, hi = outline.min(axis=0), outline.max(axis=0)
        holder[:, 0] = np.clip(holder[:, 0], lo[0] - HOLDER_REACH - 40, hi[0] + HOLDER_REACH + 40)
        holder[:, 1] = np.clip(holder[:, 1], lo[1] - HOLDER_REACH, hi[1] + HOLDER_REACH)

    def points(a: npt.NDArray[np.float64]) -> tuple[tuple[float, float], ...]:
        return tuple((float(z), float(x)) for z, x in a.round(4))

    return InsertShape(insert.kind, points(outline), points(holder), (float(tz), float(tx)))


def insert_meshes(shape: InsertShape) -> ToolMeshes:
    """A turning tool in the plane of the lathe's drawing view, its theoretical tip at the origin: the insert
    as a plate INSERT_THICKNESS thick, the holder as a thicker one, the insert's outline at its front."""
    outline = np.asarray(shape.outline, dtype=np.float64)
    holder = None
    if len(shape.holder) >= 3:
        holder = prism(np.asarray(convex_hull(list(shape.holder)), dtype=np.float64), HOLDER_THICKNESS)
    ring = np.stack([outline[:, 0], np.full(len(outline), -INSERT_THICKNESS / 2 - 0.05), outline[:, 1]], -1)
    edges = np.stack([ring, np.roll(ring, -1, axis=0)], 1).astype(np.float32)
    return ToolMeshes(prism(outline, INSERT_THICKNESS), holder, edges)


def insert_mesh(nose: float = 0.0) -> ToolMeshes:
    """A turning tool without a tool table entry, in the lathe's drawing view (the cutting point at the
    origin): an 80° rhombic insert reaching right and up from its point, the holder above it, the insert's
    outline. A nose radius rounds the point."""
    size = 10.0
    e1 = np.array([np.cos(np.radians(5)), np.sin(np.radians(5))])  # along Z (the side cutting edge) …
    e2 = np.array([np.cos(np.radians(85)), np.sin(np.radians(85))])  # … and along X: 80° between them
    r = min(max(nose, 0.0), 2.0)
    if r > 0:  # the nose: an arc tangent to both edges, from the Z edge round the corner to the X edge
        centre = (e1 + e2) / np.linalg.norm(e1 + e2) * r / np.sin(np.radians(40))
        angles = np.radians(np.linspace(275, 175, 7))
        nose_points = centre + r * np.stack([np.cos(angles), np.sin(angles)], -1)
    else:
        nose_points = np.zeros((1, 2))
    outline = np.vstack([nose_points, [size * e2, size * (e1 + e2), size * e1]])
    outline_3d = np.stack([outline[:, 0], np.full(len(outline), 1.0), outline[:, 1]], -1)
    insert_v = np.vstack([outline_3d, [[*outline_3d.mean(axis=0)]]]).astype(np.float32)
    middle = len(outline)
    insert_t = np.array([(middle, k, (k + 1) % middle) for k in range(middle)], dtype=np.uint32)
    edges = np.stack([outline_3d, np.roll(outline_3d, -1, axis=0)], 1).astype(np.float32)
    centre = size * (e1 + e2) / 2
    holder = np.array(
        [
            [centre[0] - 6, 2.0, centre[1]],
            [centre[0] + 6, 2.0, centre[1]],
            [centre[0] + 6, 2.0, centre[1] + 45],
            [centre[0] - 6, 2.0, centre[1] + 45],
        ],
        dtype=np.float32,
    )
    return ToolMeshes(
        (insert_v, insert_t), (holder, np.array([(0, 1, 2), (0, 2, 3)], dtype=np.uint32)), edges
    )
