"""Contour geometry against numbers computed by hand from the drawings (oracles: examples.md, DECISIONS.md)."""

from __future__ import annotations

import math

import pytest

from core.pipeline import run
from tests.conftest import SeedReader, codes, errors

TOL = 0.001
READY = "N1 T1 TC1 M6\nN2 S1200 F150 M3\n"  # T1: end mill Ø25


def xy(p: tuple[float, float, float] | None) -> tuple[float, float]:
    assert p is not None
    return (p[0], p[1])


def feed_path(name: str) -> list[tuple[str, tuple[float, float], tuple[float, float]]]:
    tp = SeedReader.run(name)
    assert errors(tp) == []
    return [(m.kind, xy(m.start), xy(m.end)) for m in tp.moves if m.kind != "rapid"]


# -- G1 examples 1–4 ----------------------------------------------------------------------------


def test_example_1_tool_centre_path_with_g42() -> None:
    tp = SeedReader.run("pal-01-g1-gerade.nc")
    assert errors(tp) == []
    path = [(m.kind, xy(m.end)) for m in tp.moves[1:-1]]
    assert path == [
        ("rapid", pytest.approx((-14, -2.5))),  # equidistant start: 1.5 safety + 12.5 radius in front
        ("rapid", pytest.approx((-14, -2.5))),  # down to Z-2
        ("feed", pytest.approx((70, -2.5))),
        ("arc", pytest.approx((82.5, 10))),  # outside corner: arc about the contour corner X70 Y10
        ("feed", pytest.approx((82.5, 84))),
    ]
    corner = tp.moves[4]
    assert corner.center is not None and xy(corner.center) == pytest.approx((70, 10))
    assert (corner.radius, corner.direction) == (pytest.approx(12.5), "ccw")


def test_example_2_rounding_rn20_tangent_points() -> None:
    tp = SeedReader.run("pal-02-g1-rn-radius.nc")
    assert errors(tp) == []
    line, fillet, up = [m for m in tp.moves if m.kind != "rapid"]
    assert xy(line.programmed_end) == pytest.approx((50, 10), abs=TOL)
    assert fillet.kind == "arc" and xy(fillet.programmed_end) == pytest.approx((70, 30), abs=TOL)
    assert fillet.center is not None and xy(fillet.center) == pytest.approx((50, 30), abs=TOL)
    assert fillet.radius == pytest.approx(20 + 12.5)  # tool outside the rounding
    assert xy(up.end) == pytest.approx((82.5, 84))


def test_example_3_chamfer_rn_minus_15() -> None:
    tp = SeedReader.run("pal-03-g1-rn-fase.nc")
    assert errors(tp) == []
    programmed = [xy(m.programmed_end) for m in tp.moves if m.kind == "feed"]
    assert programmed[0] == pytest.approx((55, 10), abs=TOL)  # chamfer start
    assert programmed[1] == pytest.approx((70, 25), abs=TOL)  # chamfer end
    chamfer = [m for m in tp.moves if m.kind == "feed"][1]
    # the chamfer's tool-centre line is parallel to it, 12.5 mm outside
    assert xy(chamfer.start) == pytest.approx((55 + 12.5 / math.sqrt(2), 10 - 12.5 / math.sqrt(2)), abs=TOL)


def test_example_4_rise_angle_as85() -> None:
    tp = SeedReader.run("pal-04-g1-as-winkel.nc")
    assert errors(tp) == []
    last = [m for m in tp.moves if m.kind == "feed"][-1]
    assert xy(last.programmed_end) == pytest.approx((60 + 74 / math.tan(math.radians(85)), 84), abs=TOL)


def test_run_json_has_programmed_end() -> None:
    from core.pipeline import toolpath_json

    data = toolpath_json(SeedReader.run("pal-01-g1-gerade.nc"))
    feed = next(m for m in data["moves"] if m["kind"] == "feed")
    assert feed["end"] == [70, -2.5, -2] and feed["programmed_end"] == [70, 10, -2]
    rapid = data["moves"][0]
    assert rapid["programmed_end"] == rapid["end"]


# -- approach and departure -------------------------------------------------------------------


def test_linear_approach_and_departure_g45_g46() -> None:
    tp = SeedReader.run("pal-15-g45-g46.nc")
    assert errors(tp) == []
    moves = tp.moves
    approach = next(m for m in moves if m.line == 6 and m.kind == "feed")
    assert xy(approach.start) == pytest.approx((-12.5, 0), abs=TOL)  # programmed start Y10
    assert xy(approach.end) == pytest.approx((0, 0), abs=TOL)
    departure = next(m for m in moves if m.line == 9)
    assert xy(departure.start) == pytest.approx((63.461, 49.128), abs=TOL)
    assert xy(departure.end) == pytest.approx((64.551, 61.581), abs=TOL)  # programmed X54.589 Y62.452
    # the last contour point X53.4995 Y50 (50 + 40/tan 85°)
    assert xy(next(m for m in moves if m.line == 8).programmed_end) == pytest.approx((53.4995, 50), abs=TOL)
    # the RN10 rounding: tangent points X40.837 Y10 and X50.799 Y19.128, centre X40.837 Y20
    fillet = next(m for m in moves if m.kind == "arc" and m.line == 7)
    assert fillet.center is not None and xy(fillet.center) == pytest.approx((40.837, 20), abs=TOL)
    assert xy(fillet.programmed_end) == pytest.approx((50.799, 19.128), abs=TOL)


def test_quarter_circle_approach_and_departure_g47_g48() -> None:
    tp = SeedReader.run("pal-16-g47-g48.nc")
    assert errors(tp) == []
    approach = next(m for m in tp.moves if m.line == 6 and m.kind == "arc")
    assert xy(approach.start) == pytest.approx((-12.5, -12.5), abs=TOL)  # DECISIONS §1
    assert xy(approach.end) == pytest.approx((0, 0), abs=TOL)
    assert (approach.radius, approach.angle, approach.direction) == (
        pytest.approx(12.5),
        pytest.approx(90),
        "cw",
    )
    departure = next(m for m in tp.moves if m.line == 9)
    assert departure.kind == "arc" and departure.angle == pytest.approx(90)
    assert xy(departure.start) == pytest.approx((63.461, 49.128), abs=TOL)
    assert xy(departure.end) == pytest.approx((77.003, 60.491), abs=TOL)


def test_approach_with_w_and_plunge_feed() -> None:
    tp = run(READY + "G0 X-30 Y-20 Z50\nG42 G45 X0 Y10 D12.5 W2 Z-3 E40\nG1 X50\nG40 G46 D5 Z2 W50\nM30")
    assert errors(tp) == []
    moves = [(m.kind, m.end, m.feed) for m in tp.moves if m.line in (4, 6)]
    assert moves[0][:2] == ("rapid", pytest.approx((-12.5, -2.5, 50)))
    assert moves[1][:2] == ("rapid", pytest.approx((-12.5, -2.5, 2)))  # rapid to W
    assert moves[2] == ("feed", pytest.approx((-12.5, -2.5, -3)), 40)  # plunge at E
    assert moves[3][:2] == ("feed", pytest.approx((0, -2.5, -3)))
    assert [m[:2] for m in moves[4:]] == [
        ("feed", pytest.approx((55, -2.5, -3))),
        ("feed", pytest.approx((55, -2.5, 2))),
        ("rapid", pytest.approx((55, -2.5, 50))),
    ]


# -- G1 with D, AS, H ---------------------------------------------------------------------------


@pytest.mark.parametrize(
    "block,end",
    [
        ("G1 X10 D20", (10, 10 * math.sqrt(3))),  # H1: the smaller rise angle (60° rather than 300°)
        ("G1 X10 D20 H2", (10, -10 * math.sqrt(3))),
        ("G1 Y10 D20", (10 * math.sqrt(3), 10)),  # 30° rather than 150°
        ("G1 Y10 D20 H2", (-10 * math.sqrt(3), 10)),
        ("G1 D10 AS30", (10 * math.cos(math.radians(30)), 5)),
        ("G1 X20 AS45", (20, 20)),
        ("G1 Y-5 AS135", (5, -5)),
    ],
)
def test_line_from_two_of_x_y_d_as(block: str, end: tuple[float, float]) -> None:
    tp = run(READY + "G0 X0 Y0 Z0\n" + block + "\nM30")
    assert errors(tp) == []
    assert xy(tp.moves[-1].end) == pytest.approx(end, abs=1e-6)


@pytest.mark.parametrize(
    "block,code",
    [
        ("G1 X10 Y10 D5", "PAL-E211"),
        ("G1 D5", "PAL-E212"),
        ("G1 AS30", "PAL-E212"),
        ("G1 X30 D5", "PAL-E210"),
        ("G1 X5 AS90", "PAL-E210"),
        ("G1 D-5 AS10", "PAL-E213"),
    ],
)
def test_line_geometry_errors(block: str, code: str) -> None:
    assert (code, 4) in codes(run(READY + "G0 X0 Y0 Z0\n" + block + "\nM30"))


# -- G2/G3 with any three addresses ---------------------------------------------------------------


@pytest.mark.parametrize(
    "block",
    [
        "G2 X56.4 Y10 AO54.5107",
        "G2 X56.4 IA50 JA30",
        "G2 Y10 IA50 JA30",
        "G2 IA50 JA30 AO54.5107",
        "G2 X56.4 IA50 AO54.5107",
        "G2 Y10 JA30 AO54.5107",
        "G2 X56.4 R21 AO54.5107 H2",  # two arcs of equal length: H2, the larger start tangent angle
        "G2 X56.4 Y10 IA50 R21",
        "G2 X56.4 Y10 I-20 J6.4 R21",
    ],
)
def test_arc_forms_of_the_g2_example(block: str) -> None:
    tp = run(READY + "G0 X70 Y23.6 Z-2\n" + block + "\nM30")
    assert errors(tp) == []
    arc = tp.moves[-1]
    assert arc.kind == "arc" and arc.direction == "cw"
    # R21 is the drawing's rounded radius (the exact one is 20.99905): forms with R land within 5 µm
    assert xy(arc.end) == pytest.approx((56.4, 10), abs=5e-3)
    assert arc.center is not None and xy(arc.center) == pytest.approx((50, 30), abs=5e-3)


def test_arc_length_and_start_angle_choice() -> None:
    base = READY + "G0 X0 Y0 Z0\n"
    # X10 I5 J0 from X0 Y0: the circle about X5 Y0 meets X10 only at Y0 — unique
    assert xy(run(base + "G3 X10 I5 J0\nM30").moves[-1].end) == pytest.approx((10, 0))
    # X5 I5 J0: two end points Y±5; clockwise the shorter arc ends at Y5 (90°), O2 takes Y-5 (270°)
    short = run(base + "G2 X5 I5 J0\nM30").moves[-1]
    long = run(base + "G2 X5 I5 J0 O2\nM30").moves[-1]
    assert (xy(short.end), short.angle) == (pytest.approx((5, 5)), pytest.approx(90))
    assert (xy(long.end), long.angle) == (pytest.approx((5, -5)), pytest.approx(270))
    # R5 AO90 X5: two arcs of equal length; H1 starts at the smaller tangent angle, H2 at the larger
    h1 = run(base + "G3 X5 R5 AO90\nM30").moves[-1]
    h2 = run(base + "G3 X5 R5 AO90 H2\nM30").moves[-1]
    assert xy(h1.end) == pytest.approx((5, 5))  # centre X0 Y5: start tangent 0°
    assert xy(h2.end) == pytest.approx((5, -5))  # centre X5 Y0: start tangent 270°


@pytest.mark.parametrize(
    "block,code",
    [
        ("G2 X10 Y0 I3 J0", "PAL-E202"),  # Kreisendpunktfehler
        ("G2 X10 Y0 R5.1 I3", "PAL-E202"),
        ("G2 X10 Y0 R2", "PAL-E201"),
        ("G2 X10 AO0 R5", "PAL-E213"),
        ("G2 X10", "PAL-E203"),
    ],
)
def test_arc_errors(block: str, code: str) -> None:
    assert (code, 4) in codes(run(READY + "G0 X0 Y0 Z0\n" + block + "\nM30"))


# -- polar coordinates ------------------------------------------------------------------------------


def test_polar_moves() -> None:
    tp = run(
        READY + "G0 X0 Y0 Z0\nG11 IA10 JA10 RP5 AP90\nG11 RP5 AI-90\nG13 AP90\nG12 AI-90\nG10 RP0 AP0\nM30"
    )
    assert errors(tp) == []
    ends = [xy(m.end) for m in tp.moves[1:]]
    assert ends[0] == pytest.approx((10, 15))  # pole X10 Y10, 5 mm at 90°
    assert ends[1] == pytest.approx((15, 10))  # the pole stays; 90° less
    assert ends[2] == pytest.approx((10, 15))  # counter-clockwise about the pole to 90°
    assert (
        tp.moves[3].kind == "arc"
        and tp.moves[3].direction == "ccw"
        and tp.moves[3].angle == pytest.approx(90)
    )
    assert ends[3] == pytest.approx((15, 10)) and tp.moves[4].direction == "cw"
    assert ends[4] == pytest.approx((10, 10)) and tp.moves[5].kind == "rapid"


def test_polar_pole_defaults_to_workpiece_zero() -> None:
    tp = run(READY + "G0 X5 Y5 Z0\nG11 RP10 AP0\nM30")
    assert xy(tp.moves[-1].end) == pytest.approx((10, 0))


# -- compensation errors -----------------------------------------------------------------------------


def test_inside_arc_smaller_than_tool_radius() -> None:
    # tool left of a ccw arc is inside it: R10 < 12.5
    tp = run(READY + "G0 X0 Y-20 Z0\nG41 G1 X0 Y0\nG3 X20 Y0 R10\nG1 Y-20\nG40 G0 X50\nM30")
    assert ("PAL-E214", 5) in codes(tp)


def test_offsets_changed_while_compensating() -> None:
    assert ("PAL-E216", 4) in codes(run(READY + "G41 G1 X0 Y0\nG1 X10 TR0.5\nG40 G1 X20\nM30"))


def test_approach_needs_its_companion() -> None:
    assert ("PAL-E219", 3) in codes(run(READY + "G45 X0 Y10 D5\nM30"))
    assert ("PAL-E219", 5) in codes(run(READY + "G41 G1 X0 Y0\nG1 X10\nG46 D5\nM30"))


def test_compensation_without_following_element() -> None:
    assert ("PAL-E218", 3) in codes(run(READY + "G41 G1 X0 Y0\nG40\nM30"))


def test_rn_that_does_not_fit() -> None:
    tp = run(READY + "G0 X0 Y0 Z0\nG1 X10 RN20\nG1 Y10\nM30")
    assert ("PAL-E208", 4) in codes(tp)
    msg = next(d for d in tp.diagnostics if d.code == "PAL-E208").message
    assert "Zeile 4" in msg and "Zeile 5" in msg


def test_rn_without_following_contour_element() -> None:
    assert ("PAL-E209", 4) in codes(run(READY + "G0 X0 Y0 Z0\nG1 X10 RN2\nG0 Z10\nM30"))


def test_rn_feed_e_on_the_inserted_element() -> None:
    tp = run(READY + "G0 X0 Y0 Z0\nG1 X10 RN2 E50\nG1 Y10\nM30")
    assert [m.feed for m in tp.moves if m.kind != "rapid"] == [150, 50, 150]


def test_compensation_radius_is_offset_memory_plus_tr() -> None:
    from core.interpreter.state import RunSetup
    from core.tools import DEFAULT_TOOLS, Tool, ToolOffset

    tools = DEFAULT_TOOLS.with_tool(Tool(8, "end_mill", 10.0, offsets=(ToolOffset(2, 4.9, 80.0),)))
    program = "T8 TC{tc} TR{tr} M6\nS1000 F100 M3\nG0 X0 Y-20 Z0\nG41 G1 X0 Y0\nG1 X50\nG40 G0 Y50\nM30"
    for tc, tr, expected in ((1, 0, 5.0), (2, 0, 4.9), (2, 0.1, 5.0), (1, -0.2, 4.8)):
        tp = run(program.format(tc=tc, tr=tr), setup=RunSetup(tools=tools))
        assert errors(tp) == []
        contour = next(m for m in tp.moves if m.line == 5)
        assert contour.end[1] == pytest.approx(expected), (tc, tr)  # tool left of +X: Y = +radius
