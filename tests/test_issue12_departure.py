"""Issue 12, part 1: where the tool is after a departure G40 G46/G48 (numbers computed by hand).

After the departure the tool centre stands at the departure's end, at the height Z/W of that block;
the next block starts there, in every form of the departure and whatever follows it.
"""

from __future__ import annotations

import pytest

from core.interpreter.state import RunSetup
from core.pipeline import run, toolpath_json
from core.toolpath import Toolpath
from core.tools import DEFAULT_TOOLS, Tool
from tests.conftest import SeedReader, errors

TOL = 0.001
SETUP = RunSetup(tools=DEFAULT_TOOLS.with_tool(Tool(1, "end_mill", 10.0, "Schaftfräser Ø10")))  # --tool 1=10
HEAD = "N10 T1 TC1 M6\nN20 S1000 F200 M3\nN30 G0 X-20 Y-20 Z-3\nN40 G41 G45 X0 Y0 D8\nN50 G1 Y30\n"


def go(departure: str, rest: str = "N70 G0 X100\nN80 M30\n") -> Toolpath:
    tp = run(HEAD + departure + "\n" + rest, setup=SETUP)
    assert errors(tp) == []
    return tp


def on_line(
    tp: Toolpath, line: int
) -> list[tuple[str, tuple[float, float, float], tuple[float, float, float]]]:
    return [(m.kind, m.start, m.end) for m in tp.moves if m.line == line]


def test_examiner_g46_next_move_starts_at_departure_end_and_height() -> None:
    tp = go("N60 G40 G46 D10 Z2 W50")
    dep = on_line(tp, 6)
    assert dep[0][1:] == (pytest.approx((-5, 30, -3)), pytest.approx((-5, 40, -3)))  # tangential, length 10
    assert dep[-1][2] == pytest.approx((-5, 40, 50))  # feed to Z2, rapid to W50
    assert on_line(tp, 7) == [("rapid", pytest.approx((-5, 40, 50)), pytest.approx((100, 40, 50)))]
    assert tp.final_position == pytest.approx((100, 40, 50))


def test_examiner_g48_next_move_starts_at_quarter_circle_end() -> None:
    # G41, tool r5 left of the line X0 Y0→Y30: centre (−5, 30); quarter circle R10 about (−15, 30) to (−15, 40)
    tp = go("N60 G40 G48 R10 Z2 W50")
    arc = next(m for m in tp.moves if m.line == 6)
    assert arc.kind == "arc" and arc.direction == "ccw" and arc.angle == pytest.approx(90)
    assert arc.center is not None and arc.center[:2] == pytest.approx((-15, 30))
    assert arc.end == pytest.approx((-15, 40, -3))
    assert on_line(tp, 7) == [("rapid", pytest.approx((-15, 40, 50)), pytest.approx((100, 40, 50)))]


@pytest.mark.parametrize(
    "departure,end",
    [
        ("N60 G40 G46 D10", (-5, 40, -3)),  # neither Z nor W: stays at the contour's height
        ("N60 G40 G46 D10 Z2", (-5, 40, 2)),  # Z only
        ("N60 G40 G46 D10 W50", (-5, 40, 50)),  # W only
        ("N60 G40 G48 R10", (-15, 40, -3)),
        ("N60 G40 G48 R10 Z5", (-15, 40, 5)),
        ("N60 G40 G48 R10 W40", (-15, 40, 40)),
    ],
)
def test_final_position_is_the_departure_end(departure: str, end: tuple[float, float, float]) -> None:
    tp = go(departure, "N70 M30\n")
    assert tp.final_position == pytest.approx(end)
    assert toolpath_json(tp)["final"]["position"] == pytest.approx(list(end))
    assert tp.state_at(6)[1] == pytest.approx(end)


@pytest.mark.parametrize("departure,x,y", [("N60 G40 G46 D10 Z2", -5, 40), ("N60 G40 G48 R10 Z2", -15, 40)])
def test_plain_z_after_departure_rises_straight_up(departure: str, x: float, y: float) -> None:
    tp = go(departure, "N70 G0 Z50\nN80 M30\n")
    assert on_line(tp, 7) == [("rapid", pytest.approx((x, y, 2)), pytest.approx((x, y, 50)))]


def test_incremental_move_after_departure_counts_from_its_end() -> None:
    tp = go("N60 G40 G46 D10 W50", "N70 G91 G0 X10 Y-5\nN80 G90 M30\n")
    assert on_line(tp, 7) == [("rapid", pytest.approx((-5, 40, 50)), pytest.approx((5, 35, 50)))]


def test_departure_after_an_arc_leaves_along_the_arc_tangent() -> None:
    # G42 on the arc from (0, 0) to (10, 10) about (10, 0), clockwise: end tangent (1, 0) at (10, 10);
    # the tool (r5) is right of it, centre (10, 5); G46 D10 ends at (20, 5)
    text = (
        "N10 T1 TC1 M6\nN20 S1000 F200 M3\nN30 G0 X-20 Y-20 Z-3\nN40 G42 G45 X0 Y0 D8\n"
        "N50 G2 X10 Y10 I10 J0\nN60 G40 G46 D10 W20\nN70 G0 X50\nN80 M30\n"
    )
    tp = run(text, setup=SETUP)
    assert errors(tp) == []
    assert on_line(tp, 7) == [("rapid", pytest.approx((20, 5, 20)), pytest.approx((50, 5, 20)))]


def test_departure_under_a_zero_shift() -> None:
    # the same contour shifted by G59 XA100 YA50: every point moves by (100, 50)
    text = (
        "N10 T1 TC1 M6\nN20 S1000 F200 M3\nN25 G59 XA100 YA50\nN30 G0 X-20 Y-20 Z-3\nN40 G41 G45 X0 Y0 D8\n"
        "N50 G1 Y30\nN60 G40 G46 D10 Z2 W50\nN70 G0 X10\nN80 M30\n"
    )
    tp = run(text, setup=SETUP)
    assert errors(tp) == []
    assert on_line(tp, 8) == [("rapid", pytest.approx((95, 90, 50)), pytest.approx((110, 90, 50)))]


def test_seed_linear_departure_programmed_end_and_tool_centre() -> None:
    # DECISIONS.md ruling 2: contour end X53.4995 Y50, departure G40 G46 D12.5 (T4 Ø20, G42)
    tp = SeedReader.run("pal-15-g45-g46.nc")
    assert errors(tp) == []
    dep = next(m for m in tp.moves if m.line == 9)
    assert dep.end[:2] == pytest.approx((64.551, 61.581), abs=TOL)
    assert dep.programmed_end is not None and dep.programmed_end[:2] == pytest.approx(
        (54.589, 62.452), abs=TOL
    )
    data = next(m for m in toolpath_json(tp)["moves"] if m["line"] == 9)
    assert data["programmed_end"][:2] == pytest.approx([54.589, 62.452], abs=TOL)
    # N90 goes from the departure's end, not from the last contour point
    last = next(m for m in tp.moves if m.line == 10)
    assert last.start == pytest.approx((64.551, 61.581, -3), abs=TOL)


def test_seed_quarter_circle_departure_programmed_end() -> None:
    # G48 R12.5 about the centre 22.5 (R + tool radius) right of the contour end: the programmed
    # departure is the concentric quarter circle through the contour point, ending at X77.875 Y70.453
    tp = SeedReader.run("pal-16-g47-g48.nc")
    assert errors(tp) == []
    dep = next(m for m in tp.moves if m.line == 9)
    assert dep.end[:2] == pytest.approx((77.003, 60.491), abs=TOL)  # DECISIONS.md ruling 1
    assert dep.programmed_end is not None and dep.programmed_end[:2] == pytest.approx(
        (77.875, 70.453), abs=TOL
    )
    last = next(m for m in tp.moves if m.line == 10)
    assert last.start == pytest.approx((77.003, 60.491, -3), abs=TOL)


def test_approach_with_w_and_no_z_continues_at_w() -> None:
    # G45 rises to W2 and has no Z: the contour that follows runs at Z2, not down a slope to Z-3
    text = (
        "N10 T1 TC1 M6\nN20 S1000 F200 M3\nN30 G0 X-20 Y-20 Z-3\nN40 G41 G45 X0 Y0 D8 W2\n"
        "N50 G1 Y30\nN60 G40 G46 D10\nN70 M30\n"
    )
    tp = run(text, setup=SETUP)
    assert errors(tp) == []
    contour = next(m for m in tp.moves if m.line == 5)
    assert contour.start == pytest.approx((-5, 0, 2)) and contour.end == pytest.approx((-5, 30, 2))
    assert tp.final_position == pytest.approx((-5, 40, 2))


def test_departure_without_active_compensation_still_goes_to_z_and_w() -> None:
    text = "N10 T1 TC1 M6\nN20 S1000 F200 M3\nN30 G0 X0 Y0 Z-3\nN40 G1 Y30\nN50 G40 G46 D10 Z2 W50\nN60 M30\n"
    tp = run(text, setup=SETUP)
    assert [(m.kind, m.end) for m in tp.moves if m.line == 5] == [
        ("feed", pytest.approx((0, 30, 2))),
        ("rapid", pytest.approx((0, 30, 50))),
    ]
    assert tp.final_position == pytest.approx((0, 30, 50))


@pytest.mark.parametrize("dialect", ["sinumerik-iso", "beckhoff"])
def test_iso_dialects_after_g40_start_from_the_programmed_point(dialect: str) -> None:
    # the same executor: after G40 the tool centre goes to the programmed point and the next block starts there
    text = "T1 M6\nS1000 F200 M3\nG0 X-20 Y-20 Z-3\nG41 G1 X0 Y0\nG1 Y30\nG40 G1 X-10 Y40\nG0 X100\nM30\n"
    tp = run(text, dialect, setup=SETUP)
    assert errors(tp) == []
    assert on_line(tp, 7) == [("rapid", pytest.approx((-10, 40, -3)), pytest.approx((100, 40, -3)))]
    assert tp.final_position == pytest.approx((100, 40, -3))


@pytest.mark.parametrize(
    "frame,arc_end,next_end",
    [
        ("N25 G66 Y\n", (15, 40, -3), (-100, 40, 50)),  # X mirrored: the quarter circle turns the other way
        ("N25 G58 AR90\n", (-40, -15, -3), (-40, 100, 50)),  # rotated by 90°: (x, y) → (−y, x)
    ],
)
def test_quarter_circle_departure_under_mirroring_and_rotation(
    frame: str, arc_end: tuple[float, float, float], next_end: tuple[float, float, float]
) -> None:
    text = HEAD.replace("N30 ", frame + "N30 ") + "N60 G40 G48 R10 Z2 W50\nN70 G0 X100\nN80 M30\n"
    tp = run(text, setup=SETUP)
    assert errors(tp) == []
    arc = next(m for m in tp.moves if m.kind == "arc" and m.line == 7)
    assert arc.end == pytest.approx(arc_end)
    up = (arc_end[0], arc_end[1], 50)
    assert on_line(tp, 8) == [("rapid", pytest.approx(up), pytest.approx(next_end))]
