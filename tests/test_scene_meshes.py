"""The 3D view's geometry (core/scene): what a trainee sees of the bar, the chuck, the tools and the camera,
checked on the meshes themselves — sizes, volumes, where things are — without a viser scene."""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt
import pytest

from core.scene.camera import VIEW_MARGIN, camera_for
from core.scene.meshes import (
    DASH,
    GAP,
    HOLDER_THICKNESS,
    INSERT_THICKNESS,
    MAX_DASHES,
    SECTIONS,
    InsertShape,
    Mesh,
    ToolShape,
    dashed,
    footprint,
    insert_mesh,
    insert_meshes,
    insert_shape,
    merge,
    prism,
    revolve,
    spindle_axis,
    stock_outline,
    tool_mesh,
)
from core.scene.turned import (
    BAND_LIFT,
    CUT_OFFSET,
    TurnedProfile,
    ViewBlank,
    chuck_meshes,
    deviation_band,
    turned_chunks,
    view_blank,
)
from core.sim.insert import convex_hull, insert_of, lower_hull
from core.sim.turning import RevolvedProfile
from core.tools import DEFAULT_TOOLS, Tool

# an inscribed regular polygon of SECTIONS sides has this much of its circle's area
POLYGON = SECTIONS / (2 * math.pi) * math.sin(2 * math.pi / SECTIONS)


def signed_volume(mesh: Mesh) -> float:
    """The volume a closed, consistently wound mesh encloses (divergence theorem; outward normals: positive)."""
    v, t = mesh
    a, b, c = (v[t[:, k]].astype(np.float64) for k in range(3))
    return float(np.einsum("ij,ij->i", a, np.cross(b, c)).sum()) / 6


def is_closed(mesh: Mesh) -> bool:
    """Every edge (between vertices at the same place) is shared by exactly two triangles."""
    v, t = mesh
    _, ids = np.unique(np.round(v.astype(np.float64), 6), axis=0, return_inverse=True)
    tris = ids.reshape(-1)[t]
    tris = tris[(tris[:, 0] != tris[:, 1]) & (tris[:, 1] != tris[:, 2]) & (tris[:, 0] != tris[:, 2])]
    edges = np.sort(np.concatenate([tris[:, [0, 1]], tris[:, [1, 2]], tris[:, [2, 0]]]), axis=1)
    _, counts = np.unique(edges, axis=0, return_counts=True)
    return bool(np.all(counts == 2))


def bar_profile(diameter: float, length: float, dz: float = 0.1) -> TurnedProfile:
    n = round(length / dz)
    return TurnedProfile(-length, dz, np.full(n, diameter / 2, np.float32), np.zeros(n, np.float32))


def chunk_vertices(
    chunks: dict[str, tuple[str, npt.NDArray[np.float32], npt.NDArray[np.uint32]]],
) -> npt.NDArray[np.float64]:
    return np.vstack([v for _, v, _ in chunks.values()]).astype(np.float64)


# -- the turned part ----------------------------------------------------------------------------------------
def test_a_revolved_bar_is_closed_and_has_the_bars_size_and_volume() -> None:
    """A Ø40 × 30 bar's outline (the front face, the cylinder, the back face) revolved: ±20 across, 30 long,
    and the volume of the cylinder within the tessellation (an inscribed 48-gon)."""
    outline = np.array([[0.0, 0.0], [0.0, 20.0], [30.0, 20.0], [30.0, 0.0]])
    mesh = revolve(outline, half=False)
    v = mesh[0]
    assert np.allclose(v.min(axis=0), [0, -20, -20], atol=1e-5) and np.allclose(v.max(axis=0), [30, 20, 20])
    assert is_closed(mesh)
    volume = abs(signed_volume(mesh))
    exact = math.pi * 20**2 * 30
    assert volume == pytest.approx(exact * POLYGON, rel=1e-5)
    assert 0.995 * exact < volume < exact


def test_the_turned_bar_shows_its_diameter_and_length_in_chunks() -> None:
    """A Ø40 bar 30 long in front of the chuck: the chunks together reach from Z-30 to Z0 and ±20 around the
    axis; turned to Ø30 over its first 10 mm, the surface there has radius 15."""
    profile = bar_profile(40, 30)
    chunks = turned_chunks(profile, half=False)
    assert set(chunks) == {"z0", "z1", "z2"}  # 10 mm chunks
    v = chunk_vertices(chunks)
    assert np.allclose([v[:, 0].min(), v[:, 0].max()], [-30, 0], atol=1e-4)
    radius = np.hypot(v[:, 1], v[:, 2])
    assert radius.max() == pytest.approx(20, abs=1e-4) and np.allclose(v[:, 1:].min(axis=0), -20, atol=1e-4)
    outer = profile.outer.copy()
    outer[-100:] = 15.0  # the last 10 mm before Z0
    turned = turned_chunks(TurnedProfile(profile.z0, profile.dz, outer, profile.inner), half=False)
    front = chunk_vertices({"z2": turned["z2"]})
    on_surface = front[:, 0] > -9.99  # the shoulder's face at Z-10 reaches from R15 to R20
    assert np.allclose(np.hypot(front[on_surface, 1], front[on_surface, 2]).max(), 15, atol=1e-4)
    # only the chunk that changed has a new digest: playback resends nothing else
    assert [turned[k][0] == chunks[k][0] for k in ("z0", "z1", "z2")] == [True, True, False]


@pytest.mark.parametrize("shoulder", [-10.0, -15.0])  # on the border of two chunks, inside one
def test_the_turned_part_is_one_closed_surface_also_at_a_shoulder(shoulder: float) -> None:
    """A Ø40 bar turned to Ø30 from Z0 to the shoulder, with a Ø10 bore 5 mm deep: the chunks together are one
    closed surface, the shoulder's face from R15 to R20 and the bore's bottom there too (no hole to look
    into, wherever the shoulder falls)."""
    profile = bar_profile(40, 30)
    outer, inner = profile.outer.copy(), profile.inner.copy()
    outer[round((shoulder + 30) / 0.1) :] = 15.0
    inner[-50:] = 5.0
    chunks = turned_chunks(TurnedProfile(profile.z0, profile.dz, outer, inner), half=False)
    whole = merge([(v, t.astype(np.uint32)) for _, v, t in chunks.values()])
    assert is_closed(whole)
    v = whole[0].astype(np.float64)
    radius = np.hypot(v[:, 1], v[:, 2])
    step = radius[np.isclose(v[:, 0], shoulder, atol=0.06) & (radius > 1e-6)]  # within half a sample
    assert step.min() == pytest.approx(15, abs=1e-4) and step.max() == pytest.approx(20, abs=1e-4)


def test_a_half_section_keeps_the_back_half_and_shows_the_wall_of_a_tube() -> None:
    tube = TurnedProfile(-30.0, 0.1, np.full(300, 20.0, np.float32), np.full(300, 10.0, np.float32))
    chunks = turned_chunks(tube, half=True)
    surface = chunk_vertices({k: c for k, c in chunks.items() if not k.endswith("_cut")})
    assert surface[:, 1].min() > -1e-4  # the camera looks from −y: the front half is cut away
    cut = chunk_vertices({k: c for k, c in chunks.items() if k.endswith("_cut")})
    assert np.allclose(cut[:, 1], CUT_OFFSET)
    assert np.allclose(sorted({round(abs(float(r)), 3) for r in cut[:, 2]}), [10, 20])  # the wall R10 … R20


def test_the_chuck_holds_the_bar_from_outside_behind_the_part() -> None:
    """The chuck's body lies behind the bar's back end; its jaws grip the last `clamp` mm from outside: no part
    of the chuck reaches into the stock, nor in front of the clamped length."""
    blank = ViewBlank(diameter=40.0, inner_diameter=0.0, length=60.0, clamp=20.0, jaw_radius=40.0)
    for half in (False, True):
        body, jaws = chuck_meshes(blank, half)
        assert body[0][:, 0].max() == pytest.approx(-60)  # its face at the bar's back end
        jv = jaws[0].astype(np.float64)
        assert jv[:, 0].min() == pytest.approx(-60) and jv[:, 0].max() == pytest.approx(-40)
        assert np.hypot(jv[:, 1], jv[:, 2]).min() >= 20 - 1e-4  # outside the Ø40 bar
        # three jaws; in a half section the one in front of the cut is left out, and the chuck's front half
        assert len(jaws[1]) == (24 if half else 36)
        if half:
            assert body[0][:, 1].min() > -1e-4


def test_deviation_bands_lie_just_outside_the_surface_and_inside_the_bore() -> None:
    n = 300
    outer, inner = np.full(n, 19.0), np.full(n, 8.0)
    part = RevolvedProfile(
        -30.0,
        0.1,
        outer,
        inner,
        np.full(n, np.nan),
        np.full(n, np.nan),
        np.zeros(n, np.int64),
        np.zeros(n, np.int64),
    )
    marked = np.zeros(n, bool)
    marked[100:200] = True  # Z-20 … Z-10
    v, t = deviation_band(part, marked, marked, half=False)
    assert len(t)
    radius = np.hypot(v[:, 1], v[:, 2])
    assert np.allclose(sorted({round(float(r), 3) for r in radius}), [8 - BAND_LIFT, 19 + BAND_LIFT])
    assert v[:, 0].min() == pytest.approx(-20, abs=1e-4) and v[:, 0].max() == pytest.approx(-10, abs=1e-4)


def test_a_bar_around_the_program_leaves_the_chuck_clear_of_the_cutting_moves() -> None:
    from core.pipeline import run

    toolpath = run(
        "%\nO1\nN10 G95 G97 S1000 M4\nN20 T0101\nN30 G0 X30 Z2\nN40 G1 Z-25 F0.2\nN50 M30\n", "traub-tx8d"
    )
    blank = view_blank(None, toolpath)
    assert blank.diameter >= 30 and blank.length - blank.clamp >= 25
    given = view_blank({"diameter": 50, "length": 80, "chuck_length": 25}, toolpath)
    assert (given.diameter, given.length, given.clamp) == (50, 80, 25)


# -- the tools --------------------------------------------------------------------------------------------------
def test_the_tool_stands_upright_on_its_tip_with_the_tool_tables_size() -> None:
    t1 = DEFAULT_TOOLS.get(1)  # Schaftfräser Ø25
    t2 = DEFAULT_TOOLS.get(2)  # Langlochfräser Ø6
    assert t1 is not None and t2 is not None and t1.kind == "end_mill" and t2.kind == "slot_drill"
    for tool in (t1, t2):
        meshes = tool_mesh(ToolShape.of(tool))
        assert meshes.shank is not None
        cut_v, shank_v = meshes.cutter[0], meshes.shank[0]
        z = np.concatenate([cut_v[:, 2], shank_v[:, 2]])
        assert z.min() == 0 and z.max() == pytest.approx(tool.length)  # the tip at the bottom, along +Z
        assert np.hypot(cut_v[:, 0], cut_v[:, 1]).max() == pytest.approx(tool.diameter / 2, rel=1e-3)
        # the shank: a closed cylinder of the shank's diameter from the flutes' end up to the tool's length
        r, height = tool.shank / 2, tool.length - tool.flute_length
        assert is_closed(meshes.shank) and is_closed(meshes.cutter)
        assert signed_volume(meshes.shank) == pytest.approx(math.pi * r * r * height * POLYGON, rel=1e-4)
    # an end mill has four cutting edges, a slot drill two: they look different
    edges = [len(tool_mesh(ToolShape.of(t)).edges) for t in (t1, t2)]
    assert edges[0] == 2 * edges[1]


@pytest.mark.parametrize("kind", ["ball_nose", "twist_drill"])
def test_a_ball_nose_is_round_and_a_drill_pointed_at_the_tip(kind: str) -> None:
    shape = ToolShape.of(Tool(1, kind, 10.0, point_angle=118.0 if kind == "twist_drill" else 0.0))
    v = tool_mesh(shape).cutter[0].astype(np.float64)
    low = v[(v[:, 2] > 0) & (v[:, 2] < 1.0)]
    r = np.hypot(low[:, 0], low[:, 1]).max()
    expected = math.sqrt(25 - (5 - 1.0) ** 2) if kind == "ball_nose" else math.tan(math.radians(59))
    assert r <= expected + 1e-3  # within 1 mm of the tip the tool is narrower than its Ø10


def test_a_tool_without_a_table_entry_is_a_cylinder_of_its_radius() -> None:
    shape = ToolShape.cylinder(3.0)
    assert (shape.kind, shape.diameter, shape.shank) == ("end_mill", 6.0, 6.0)
    ring = footprint(3.0)
    assert ring.shape == (64, 2, 3) and np.allclose(np.hypot(ring[..., 0], ring[..., 1]), 3.0, atol=1e-5)


def test_a_turning_insert_is_drawn_around_its_theoretical_tip() -> None:
    """A C insert R0.8 of an outside tool (P3 on the lathe's drawing, P1 here): its outline is convex and stays
    0.8 mm and more from the sharp tip it is placed by, the holder lies behind the insert, both plates are
    closed solids of the outline's area times their thickness."""
    tool = Tool(1, "turning", 0.0, nose_radius=0.8, quadrant=1, insert="C")
    shape = insert_shape(insert_of(tool, 1))
    outline = np.asarray(shape.outline)
    area = 0.5 * (
        np.dot(outline[:, 0], np.roll(outline[:, 1], -1)) - np.dot(outline[:, 1], np.roll(outline[:, 0], -1))
    )
    assert area > 0 and len(convex_hull(list(shape.outline))) == len(outline)  # convex, counter-clockwise
    assert np.hypot(outline[:, 0], outline[:, 1]).min() > 0.3
    meshes = insert_meshes(shape)
    assert meshes.shank is not None
    assert is_closed(meshes.cutter)
    assert signed_volume(meshes.cutter) == pytest.approx(area * INSERT_THICKNESS, rel=1e-3)
    assert np.ptp(meshes.shank[0][:, 1]) == pytest.approx(HOLDER_THICKNESS)
    assert meshes.shank[0][:, 2].max() > outline[:, 1].max()  # the holder reaches up, away from the part
    # under SRK the path is the nose centre's: the mesh moves by the tip's offset
    assert shape.position((10.0, 0.0, 5.0), centre=True) == (10.0 + shape.tip[0], 0.0, 5.0 + shape.tip[1])
    assert shape.position((10.0, 0.0, 5.0), centre=False) == (10.0, 0.0, 5.0)


def test_every_insert_of_every_quadrant_has_a_convex_outline() -> None:
    for quadrant in (1, 2, 3, 4):
        for kind in ("C", "D", "V", "thread", "groove"):
            tool = Tool(5, "turning", 0.0, nose_radius=0.4, quadrant=quadrant, insert=kind, width=3.0)
            shape = insert_shape(insert_of(tool, 5))
            assert isinstance(shape, InsertShape) and shape.insert == kind
            assert len(convex_hull(list(shape.outline))) == len(shape.outline), (quadrant, kind)


def test_a_turning_tool_without_an_entry_is_a_generic_insert_at_its_point() -> None:
    meshes = insert_mesh()
    v = meshes.cutter[0]
    assert np.allclose(v[:, [0, 2]].min(axis=0), 0, atol=1e-6)  # its cutting point at the origin, reaching up
    assert meshes.shank is not None and meshes.shank[0][:, 2].min() > 0


# -- primitives, lines, camera ----------------------------------------------------------------------------------
def test_a_prism_is_the_outline_times_its_thickness() -> None:
    square = np.array([[0.0, 0.0], [4.0, 0.0], [4.0, 3.0], [0.0, 3.0]])
    mesh = prism(square, 2.0)
    assert is_closed(mesh) and signed_volume(mesh) == pytest.approx(24.0)  # wound outwards
    assert np.allclose(mesh[0].min(axis=0), [0, -1, 0]) and np.allclose(mesh[0].max(axis=0), [4, 1, 3])
    both = merge([mesh, prism(square + 10, 2.0)])
    assert len(both[0]) == 16 and signed_volume(both) == pytest.approx(48.0)


def test_rapid_moves_are_dashed_and_the_dashes_are_bounded() -> None:
    move = np.array([[[0, 0, 0], [10, 0, 0]]], np.float32)
    dashes = dashed(move)
    assert len(dashes) == 3  # 0–2, 3.5–5.5, 7–9
    assert np.allclose(np.linalg.norm(dashes[:, 1] - dashes[:, 0], axis=1), DASH)
    assert np.allclose(dashes[1:, 0, 0] - dashes[:-1, 0, 0], DASH + GAP)
    many = np.random.default_rng(1).uniform(0, 500, (4000, 2, 3)).astype(np.float32)
    assert len(dashed(many)) <= MAX_DASHES + len(many)


def test_the_spindle_axis_reaches_beyond_the_part_along_the_axis() -> None:
    axis = spindle_axis(-60.0, 0.0)
    assert np.allclose(axis[..., 1:], 0)
    assert axis[..., 0].min() == pytest.approx(-65) and 0 < axis[..., 0].max() <= 5


def test_the_stock_box_is_outlined() -> None:
    lo, hi = np.array([0.0, 0.0, -30.0]), np.array([80.0, 70.0, 0.0])
    edges = stock_outline(lo, hi)
    assert edges.shape == (12, 2, 3)
    lengths = sorted(np.round(np.linalg.norm(edges[:, 1] - edges[:, 0], axis=1)).tolist())
    assert lengths == [30] * 4 + [70] * 4 + [80] * 4


@pytest.mark.parametrize("view", ["iso", "top", "front"])
@pytest.mark.parametrize("aspect", [0.75, 1.3, 1.8])
def test_the_camera_centres_the_stock_and_fills_the_view(view: str, aspect: float) -> None:
    lo, hi = np.array([0.0, 0.0, -30.0]), np.array([80.0, 70.0, 0.0])
    fov = np.radians(50)
    eye, target = camera_for((lo, hi), view, aspect, fov)
    forward = (target - eye) / np.linalg.norm(target - eye)
    right = np.cross(forward, (0, 0, 1)) if abs(forward[2]) < 0.99 else np.array([1.0, 0, 0])
    right /= np.linalg.norm(right)
    up = np.cross(right, forward)
    corners = np.array(np.meshgrid(*zip(lo, hi, strict=True))).T.reshape(-1, 3)
    depth = (corners - eye) @ forward
    x = np.abs((corners - eye) @ right / depth) / (np.tan(fov / 2) * aspect)
    y = np.abs((corners - eye) @ up / depth) / np.tan(fov / 2)
    used = max(x.max(), y.max())
    # every corner in sight, the part filling the view but for the margin on every side (issue 28: framed)
    assert abs(used - (1 - 2 * VIEW_MARGIN)) < 0.01 and VIEW_MARGIN >= 0.05
    u = (corners - eye) @ right / depth
    v = (corners - eye) @ up / depth
    assert abs(u.max() + u.min()) < 0.02 * (u.max() - u.min())  # centred: as much room left as right
    assert abs(v.max() + v.min()) < 0.02 * (v.max() - v.min())  # and above as below


# -- the one convex hull ----------------------------------------------------------------------------------------
def test_the_convex_hull_is_counter_clockwise_without_inner_or_collinear_points() -> None:
    points = [(0.0, 0.0), (2.0, 0.0), (4.0, 0.0), (4.0, 4.0), (0.0, 4.0), (1.0, 1.0), (2.0, 3.0), (0.0, 4.0)]
    assert convex_hull(points) == [(0.0, 0.0), (4.0, 0.0), (4.0, 4.0), (0.0, 4.0)]
    assert convex_hull([(1.0, 1.0), (0.0, 0.0), (1.0, 1.0)]) == [(0.0, 0.0), (1.0, 1.0)]


def test_the_lower_hull_is_the_convex_hulls_lower_chain() -> None:
    rng = np.random.default_rng(7)
    for _ in range(50):
        points = [(float(a), float(b)) for a, b in rng.normal(size=(int(rng.integers(3, 40)), 2))]
        hull, lower = convex_hull(points), lower_hull(points)
        right = hull.index(max(hull))
        assert lower == hull[: right + 1]
