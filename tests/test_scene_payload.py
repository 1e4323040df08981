"""The scene payload (core/scene/payload.py): what the 3D view shows of a run, built from the toolpath alone —
the path split into feed and rapid, the programmed contour under compensation, a turning program in the
lathe's drawing view with its part, the box the camera frames, and a payload that crosses to the server."""

from __future__ import annotations

import pickle

import numpy as np
import pytest

from core.pipeline import run
from core.scene.meshes import InsertShape, ToolShape
from core.scene.payload import MAX_SCENE_SEGMENTS, StockLevels, TurnedPart, lathe_scene, mill_scene, part_box
from core.scene.turned import TURNED_RESOLUTION, TurnedProfile, ViewBlank, turned_chunks, view_blank
from core.sim import DEFAULT_LATHE_TOOLS, Stock, simulate, simulate_turning, stock_tiles
from core.tools import DEFAULT_TOOLS

MILL = "N10 T1 TC1 M6\nN20 S1200 F150 M3\nN30 G0 X0 Y0 Z2\nN40 G1 Z-2\nN50 G1 X20\nN60 G0 Z50 M30\n"
CONTOUR = (
    "N10 T2 TC1 M6\nN20 S2000 F200 M3\nN30 G0 X-10 Y-10 Z2\nN40 G1 Z-2\nN50 G41 G1 X0 Y0\nN60 G1 X40\n"
    "N70 G1 Y30\nN80 G40 G1 X50 Y40\nN90 G0 Z50 M30\n"
)
TURNING = (
    "%\nO0001\nN10 G95 G97 S1200 M4\nN20 T0101\nN30 G0 X40 Z2\nN40 G1 Z0 F0.2\nN50 G1 Z-20\n"
    "N60 U5\nN70 G2 X60 Z-30 R10\nN80 G0 X100 Z100\nN90 M30\n"
)


def test_a_milling_program_is_feed_and_rapid_segments_with_a_line_each() -> None:
    toolpath = run(MILL)
    scene = mill_scene(toolpath, DEFAULT_TOOLS, None)
    p = scene.playback
    assert len(p.segments) == len(p.lines) == len(p.moves) == len(p.tools) == len(toolpath.moves)
    assert len(scene.feed) + len(scene.rapid) == len(p.segments)
    assert sorted(set(p.lines)) == [3, 4, 5, 6] and scene.errors == 0 and not scene.cut
    # N50 G1 X20 at Z-2: a feed segment from X0 to X20
    ((a, b),) = [s for s, line in zip(p.segments, p.lines, strict=True) if line == 5]
    assert np.allclose(a, [0, 0, -2]) and np.allclose(b, [20, 0, -2])
    assert scene.tool == toolpath.final_position and scene.states[5]["position"] == [20, 0, -2]
    assert isinstance(p.shapes[1], ToolShape) and p.shapes[1].diameter == DEFAULT_TOOLS.tools[1].diameter
    assert len(scene.contour) == 0  # no compensation: the tool-centre path is the contour
    assert part_box(scene) is not None and np.allclose(part_box(scene)[0], [0, 0, -2])  # type: ignore[index]


def test_under_compensation_the_programmed_contour_is_drawn_beside_the_path() -> None:
    scene = mill_scene(run(CONTOUR), DEFAULT_TOOLS, None)
    contour = scene.contour.reshape(-1, 3)
    assert len(contour)  # the programmed points: X0 Y0, X40 Y0, X40 Y30
    assert {(round(float(x), 3), round(float(y), 3)) for x, y, _ in contour} >= {(0, 0), (40, 0), (40, 30)}
    assert not np.allclose(scene.feed.reshape(-1, 3)[:, 1].min(), 0)  # the tool's centre runs beside it


def test_the_stock_frames_the_camera_and_is_kept_in_its_levels() -> None:
    toolpath = run(MILL)
    result = simulate(toolpath, Stock(0, 0, -30, 80, 70, 0), DEFAULT_TOOLS, 0.5)
    levels = StockLevels(stock_tiles(result.heightmap, 6_000), stock_tiles(result.heightmap, 40_000))
    scene = mill_scene(toolpath, DEFAULT_TOOLS, levels)
    box = part_box(scene)
    assert box is not None and np.allclose(box[0], [0, 0, -30]) and np.allclose(box[1], [80, 70, 0])


def test_a_turning_program_is_in_the_lathe_drawing_view_with_its_part() -> None:
    """Z to the right, the radius up: N50 G1 Z-20 at Ø40 is a segment at height 20 from 0 to -20; the modal
    states keep the program's coordinates and name G18; the tools are inserts; the stock is the part."""
    toolpath = run(TURNING, "traub-tx8d")
    blank = view_blank({"diameter": 70, "length": 60}, toolpath)
    profile = TurnedProfile.of(
        simulate_turning(toolpath, blank, DEFAULT_LATHE_TOOLS, TURNED_RESOLUTION).profile
    )
    part = TurnedPart(profile, ViewBlank.of(blank), turned_chunks(profile, False))
    scene = lathe_scene(toolpath, DEFAULT_TOOLS, DEFAULT_LATHE_TOOLS, part)
    p = scene.playback
    ((a, b),) = [s for s, line in zip(p.segments, p.lines, strict=True) if line == 7]
    assert np.allclose(a, [0, 0, 20]) and np.allclose(b, [-20, 0, 20])
    assert scene.lathe and scene.states[7]["plane"] == "G18" and scene.states[7]["position"][0] == 20
    assert all(isinstance(p.shapes[n], InsertShape) for n in p.tools if n is not None)
    assert scene.stock is not None and scene.stock.coarse is part.chunks and scene.stock.fine is None
    lo, hi = part_box(scene)  # type: ignore[misc]
    assert lo[2] <= 0 <= hi[2]  # the spindle axis in the picture
    assert lo[0] < -60  # and the chuck's jaws behind the bar's end
    assert p.move_at(10_000) == p.moves[-1] and p.move_at(0) == p.moves[0]


def test_a_long_path_is_cut_at_the_views_budget() -> None:
    circles = "N10 T1 TC1 M6\nN20 S1000 F200 M3\nN30 G0 X0 Y0 Z2\nN40 G1 Z-1\n" + "".join(
        f"N{50 + 10 * k} G2 X0 Y0 I100 J0\n" for k in range(300)
    )
    scene = mill_scene(run(circles + "N9999 M30\n"), DEFAULT_TOOLS, None)
    assert scene.cut and len(scene.playback.segments) <= MAX_SCENE_SEGMENTS


def test_a_payload_crosses_the_process_boundary() -> None:
    scene = mill_scene(run(MILL), DEFAULT_TOOLS, None)
    again = pickle.loads(pickle.dumps(scene))
    assert np.array_equal(again.playback.segments, scene.playback.segments) and again.states == scene.states
    assert again.playback.shapes == scene.playback.shapes


@pytest.mark.parametrize("program", [MILL, CONTOUR])
def test_the_cycles_of_a_plain_program_are_none(program: str) -> None:
    assert mill_scene(run(program), DEFAULT_TOOLS, None).playback.cycles == {}
