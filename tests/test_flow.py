"""Program flow (G22, G23, G29, parameters) and coordinate transforms (G50, G53–G59, G66)."""

from __future__ import annotations

from pathlib import Path

import pytest

from core.interpreter.state import RunSetup
from core.limits import DEFAULT_LIMITS
from core.pipeline import run
from tests.conftest import SeedReader, codes, errors

READY = "N1 T1 TC1 M6\nN2 S1200 F150 M3\n"


def xy(p: tuple[float, float, float] | None) -> tuple[float, float]:
    assert p is not None
    return (round(p[0], 6), round(p[1], 6))


def test_g23_example_mills_three_l_slots() -> None:
    tp = SeedReader.run("pal-09-g23-l-nuten.nc")
    assert errors(tp) == []
    cuts = [(xy(m.start), xy(m.end)) for m in tp.moves if m.kind == "feed" and m.start[2] == m.end[2] == -2]
    assert cuts == [
        ((15, 10), (30, 10)),
        ((30, 10), (30, 20)),
        ((30, 30), (45, 30)),
        ((45, 30), (45, 40)),
        ((45, 50), (60, 50)),
        ((60, 50), (60, 60)),
    ]
    assert tp.moves[-1].start == (60, 70, 2)  # 10 mm above the last slot in Y
    assert tp.moves[-1].end == (250, 150, 250)


G29_PROGRAM = """N10 T1 TC1 M6
N20 F120 S955 M3
N30 G0 X20 Y15 Z2
N40 P12=0 P2=5
N50 P12=P12+1
N60 G29 P12 O3 P2 N200
N70 G0 XI10
N80 G1 Z-1
N90 G0 Z2
N190 G29 N50
N200 G0 X250 Y50 Z180 M30
"""


def test_g29_loop_runs_the_counted_number_of_times() -> None:
    tp = run(G29_PROGRAM)
    assert errors(tp) == []
    plunges = [m for m in tp.moves if m.kind == "feed"]
    assert len(plunges) == 5
    assert [xy(m.end)[0] for m in plunges] == [30, 40, 50, 60, 70]
    assert tp.params == {12: 6, 2: 5}


@pytest.mark.parametrize(
    "op,a,b,taken",
    [
        (1, 3, 3, True),
        (1, 3, 4, False),
        (2, 3, 4, True),
        (2, 4, 4, False),
        (3, 5, 4, True),
        (3, 4, 5, False),
        (4, 4, 5, True),
        (4, 5, 4, False),
    ],
)
def test_g29_comparisons(op: int, a: int, b: int, taken: bool) -> None:
    tp = run(f"P1={a} P2={b}\nG29 P1 O{op} P2 N30\nG0 X1\nN30 M30")
    assert (len(tp.moves) == 0) is taken


def test_endless_loop_ends_at_the_executed_block_limit() -> None:
    tp = run("N10 P1=P1+1\nN20 G29 N10\nM30")
    assert ("PAL-E013", 1) in codes(tp) or ("PAL-E013", 2) in codes(tp)
    assert tp.params[1] == pytest.approx(DEFAULT_LIMITS.max_executed_blocks / 2, abs=1)  # two blocks per pass


def test_parameters_as_address_values() -> None:
    tp = run(READY + "P1=12.5 P2=2\nG0 X=P1*P2 Y=-P1 Z=(P1+P2)/2\nM30")
    assert errors(tp) == [] and tp.moves[0].end == (25, -12.5, 7.25)


ARROW = """%L235 ; pfeilförmige Nut im 1. Quadranten
N1 G0 X10 Y10 Z2
N2 G1 Z-2
N3 G1 X30 Y30
N4 G1 X30 Y20
N5 G0 Z2
N6 G0 X20 Y30
N7 G1 Z-2
N8 G3 X10 Y20 IA20 JA20
N9 G0 Z2
N10 M17
"""

MIRROR_MAIN = """N10 T2 TC2 M6
N20 S1800 F50 M3
N30 G22 L235 H1
N40 G66 Y
N50 G22 L235 H1
N60 G66
N70 G66 X
N80 G22 L235 H1
N90 G66
N100 G66 X Y
N110 G22 L235 H1
N120 G66
N130 G0 X250 Y150 Z250 M30
"""


def test_g66_mirroring_with_subprogram_in_the_same_file() -> None:
    tp = run(MIRROR_MAIN + ARROW)
    assert errors(tp) == []
    arcs = [m for m in tp.moves if m.kind == "arc"]
    assert [(xy(a.center), a.direction) for a in arcs] == [
        ((20, 20), "ccw"),
        ((-20, 20), "cw"),
        ((20, -20), "cw"),
        ((-20, -20), "ccw"),
    ]
    assert [xy(a.end) for a in arcs] == [(10, 20), (-10, 20), (10, -20), (-10, -20)]
    shafts = [m for m in tp.moves if m.kind == "feed" and m.line == 17]  # N3 of L235, file line 17
    assert [xy(m.end) for m in shafts] == [(30, 30), (-30, 30), (30, -30), (-30, -30)]
    assert all(m.call_stack for m in arcs)
    assert [m.call_stack[0][1] for m in arcs] == [3, 5, 8, 11]  # the calling blocks N30, N50, N80, N110


def test_subprogram_from_a_library_folder(tmp_path: Path) -> None:
    (tmp_path / "L235.nc").write_text(ARROW.split("\n", 1)[1], encoding="utf-8")
    from core.cli import read_library

    tp = run(MIRROR_MAIN, setup=RunSetup(subprograms=read_library(str(tmp_path))))
    assert errors(tp) == []
    arc = next(m for m in tp.moves if m.kind == "arc")
    assert arc.source == "L235" and arc.line == 8 and arc.call_stack == ((None, 3),)


def test_g22_with_h3_runs_three_times() -> None:
    tp = run(READY + "G0 X0 Y0 Z0\nG22 L7 H3\nM30\n%L7\nG1 XI5\nM17\n")
    assert errors(tp) == []
    assert [xy(m.end)[0] for m in tp.moves[1:]] == [5, 10, 15]


def test_nested_subprograms_and_depth_limit() -> None:
    program = "G22 L1\nM30\n%L1\nG22 L2 H2\nM17\n%L2\nG0 XI1\nM17\n"
    tp = run(program)
    assert errors(tp) == [] and len(tp.moves) == 2
    assert tp.moves[0].call_stack == ((None, 1), (None, 4))
    deep = run(program, setup=RunSetup(max_call_depth=1))
    assert ("PAL-E405", 4) in codes(deep)


def test_recursion_is_reported_at_once() -> None:
    tp = run("G22 L1\nM30\n%L1\nG22 L2\nM17\n%L2\nG22 L1\nM17\n")
    assert ("PAL-E404", 7) in codes(tp)


# -- transforms ---------------------------------------------------------------------------------------


def test_g59_shift_and_rotation_and_g50() -> None:
    tp = run("G59 XA10 YA5\nG0 X0 Y0\nG59 AR90\nG0 X10 Y0\nG50\nG0 X1 Y1\nM30")
    assert errors(tp) == []
    assert [xy(m.end) for m in tp.moves] == [(10, 5), (10, 15), (1, 1)]


def test_g58_polar_shift() -> None:
    tp = run("G58 RP10 AP90 ZA-5\nG0 X0 Y0 Z0\nM30")
    assert tp.moves[0].end == pytest.approx((0, 10, -5))


def test_settable_zero_points_and_machine_coordinates() -> None:
    setup = RunSetup(zero_offsets=(("G54", (100.0, 100.0, 0.0)), ("G55", (200.0, 100.0, -10.0))))
    tp = run("G55\nG0 X0 Y0 Z0\nG53\nG0 X0 Y0 Z0\nG54\nG0 X0 Y0 Z0\nM30", setup=setup)
    assert errors(tp) == []
    assert [m.end for m in tp.moves] == [(100, 0, -10), (-100, -100, 0), (0, 0, 0)]


def test_arcs_are_rotated_with_the_frame() -> None:
    tp = run(READY + "G59 XA50 YA50 AR90\nG0 X0 Y0 Z0\nG2 X10 Y10 I10 J0\nM30")
    arc = tp.moves[-1]
    assert xy(arc.center) == (50, 60) and xy(arc.end) == (40, 60) and arc.direction == "cw"


def test_mirrored_pocket_keeps_the_tool_inside() -> None:
    # a square pocket X10…70 Y10…70 milled counter-clockwise with G41 (tool inside), mirrored about Y
    pocket = "%L5\nG0 X20 Y10 Z0\nG41 G1 X70 Y10\nG1 X70 Y70\nG1 X10 Y70\nG1 X10 Y10\nG40 G0 X40 Y40\nM17\n"
    tp = run(READY + "G66 Y\nG22 L5\nG66\nM30\n" + pocket)
    assert errors(tp) == []
    corners = [xy(m.end) for m in tp.moves if m.kind == "feed" and m.line in (10, 11, 12)]
    # the mirrored square spans X-70…-10; the Ø25 tool runs 12.5 mm inside its edges
    # (the last element, before G40, ends beside its programmed end point)
    assert corners == [pytest.approx((-57.5, 57.5)), pytest.approx((-22.5, 57.5)), pytest.approx((-22.5, 10))]


def test_m17_inside_a_g23_section_ends_the_subprogram_with_its_section() -> None:
    # L7 repeats N30…N40 five times, but N40 is its M17: each run of L7 ends there, the section with it
    program = (
        READY + "G0 X0 Y0 Z0\nG22 L7 H2\nM30\n%L7\nN10 G1 XI1\nN20 G23 N30 N40 H5\nN30 G1 YI1\nN40 M17\n"
    )
    tp = run(program)
    assert errors(tp) == []
    feeds = [(xy(m.start), xy(m.end)) for m in tp.moves if m.kind == "feed"]
    assert feeds == [((0, 0), (1, 0)), ((1, 0), (1, 1)), ((1, 1), (2, 1)), ((2, 1), (2, 2))]
    assert xy(tp.final_position) == (2, 2)


def test_a_g23_inside_its_own_section_is_skipped_where_it_would_repeat_itself() -> None:
    # N20 repeats N10…N30, itself among them: each pass would open a repeat of its own without end (a loop of
    # ever deeper repeats until a budget stops it). The first G23 runs; inside its passes it is skipped.
    program = READY + "G0 X0 Y0 Z0\nN10 G1 XI1\nN20 G23 N10 N30 H3\nN30 G1 YI1\nM30\n"
    tp = run(program)
    assert codes(tp) == [("PAL-E411", 5)]
    feeds = [xy(m.end) for m in tp.moves if m.kind == "feed"]
    assert feeds == [(1, 0), (2, 0), (2, 1), (3, 1), (3, 2), (4, 2), (4, 3), (4, 4)]
    executed, _, _ = tp.work
    assert executed == 16  # 5 up to N20, 3 passes of 3, N30 after the section and M30: no budget spent
