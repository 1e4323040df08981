"""The TRAUB errors the manual names (spec §18) and the trainee mistakes a lathe teacher expects:
each minimal program gives its code on its line, and the block with an error does not run."""

from __future__ import annotations

import pytest

from core.diagnostics import CATALOGUE, catalogue_code
from core.pipeline import run
from tests.conftest import codes

READY = "G59 Z200\nG96 V200 T0101 M4\nG92 S3000\nF0.2\n"  # lines 1–4: zero, tool, speed, feed

CASES = [
    # (what, program, expected (code, line))
    ("T10 first motion after T incremental", READY + "G0 U5 Z2\nM30", ("TX-E101", 5)),
    ("T10 also W", READY + "G0 X40 W-2\nM30", ("TX-E101", 5)),
    ("T9 motion after G26 without T", READY + "G0 X40 Z2\nG26\nG0 X40 Z2\nM30", ("TX-E102", 7)),
    ("T9 after G53", READY + "G0 X40 Z2\nG53 X400 Z500\nG1 X30\nM30", ("TX-E102", 7)),
    ("T8 G26 while SRK is on", READY + "G46\nG0 X40 Z2\nG26\nM30", ("TX-E103", 7)),
    ("T1 other G function while G46 is on", READY + "G46\nG0 X40 Z2\nG59 Z10\nM30", ("TX-E103", 7)),
    (
        "T6 fewer than 3 motions in 5 blocks under SRK",
        READY + "G46\nG0 X40 Z2\nG1 Z-10\nM8\nF0.1\nS200\nG1 Z-20\nG40\nM30",
        ("TX-E113", 10),
    ),
    ("T17 four M words", "G96 V200 T0101 M4 M8 M41 M48\nM30", ("TX-E104", 1)),
    ("T18 M30 not alone", READY + "G0 X40 Z2 M30", ("TX-E105", 5)),
    ("T18 M00 not alone", READY + "M0 M8\nM30", ("TX-E105", 5)),
    ("T19 M06 without T", READY + "M6\nM30", ("TX-E106", 5)),
    ("T19 M17 while the spindle turns", READY + "M17\nM30", ("TX-E109", 5)),
    ("T25 B06 without the driven tool on", "B060800\nM30", ("TX-E107", 1)),
    ("dwell out of range", "G4 U0\nM30", ("TX-E108", 1)),
    ("no such L parameter", "L49 = 3\nM30", ("TX-E110", 1)),
    ("L parameter read before assigned", READY + "G0 X L7 Z2\nM30", ("TX-W101", 5)),
    ("no such turret station", "T1717\nM30", ("TX-E111", 1)),
    ("G97 V without X", "G97 V30 T0101 M3\nM30", ("TX-E112", 1)),
    ("G92 X has no meaning", "G92 S2000 X50\nM30", ("TX-W102", 1)),
    ("G9 with a chamfer", READY + "G0 X40 Z2\nG9 X60 D1\nG1 Z-20\nM30", ("TX-W104", 6)),
    ("G96 at diameter 0 without G92", "G96 V200 T0101 M4\nG0 X0 Z2\nG1 Z-5 F0.1\nM30", ("TX-W105", 2)),
    ("feed move without a tool", "G0 X40 Z2\nG1 Z-5 F0.1\nM30", ("TX-W106", 2)),
    ("feed 0", "G96 V200 T0101 M4\nG0 X40 Z2\nG1 Z-5\nM30", ("TX-E1301", 3)),
    ("spindle at rest", "T0101\nF0.1\nG0 X40 Z2\nG1 Z-5\nM30", ("TX-E1302", 4)),
    ("unknown M function", "M47\nM30", ("TX-W1103", 1)),
    ("unknown G code", "G5 X1\nM30", ("TX-E1105", 1)),
    ("unknown address", "G1 Y5\nM30", ("TX-E1003", 1)),
    ("word not allowed with G4", "G4 X1 Z3\nM30", ("TX-E1101", 1)),
    ("word not allowed with the modal G0", "G0 X40 Z2\nZ-5 R3\nM30", ("TX-E1101", 2)),
    ("G22 without A, P or Q", "G22 H2\nM30", ("TX-E1102", 1)),
    ("cycle not supported yet", READY + "G73 P10 Q20 I0.5 U-2 W-1 D2\nM30", ("TX-E1901", 5)),
    ("thread not supported yet", READY + "G0 X20 Z5\nG34 Z-20 F1.5 K0.1\nM30", ("TX-E1901", 6)),
    ("subprogram missing", "G22 A8123\nM30", ("TX-E301", 1)),
    ("macro missing", "G250\nM30", ("TX-E301", 1)),
    ("recursion", "G22 A8000\nM30\n%\nO8000\nG22 A8000\nM99\n%", ("TX-E303", 5)),
    ("section block missing", "N10 G0 X40 Z2\nG22 P10 Q99\nM30", ("TX-E304", 2)),
    ("section reversed", "N10 G0 X40 Z2\nN20 G0 X30\nG22 P20 Q10\nM30", ("TX-E305", 3)),
    ("M30 in a subprogram", "G22 A8000\nM30\n%\nO8000\nG0 X40 Z2\nM30\n%", ("TX-E306", 6)),
    ("M99 in the main program", "G0 X40 Z2\nM99", ("TX-W301", 2)),
    ("subprogram without M99", "G22 A8000\nM30\n%\nO8000\nG0 X40 Z2\n%", ("TX-W302", 5)),
    ("subprogram number range", "G22 A520\nM30\n%\nO520\nG0 X40 Z2\nM99\n%", ("TX-W103", 4)),
    ("missing M30", "G0 X40 Z2", ("TX-W1102", 1)),
    ("T indexing to another station in G00", READY + "G0 X40 Z2\nG0 X80 Z50 T0404\nM30", ("TX-W108", 6)),
    (
        "T27 L assigned after the call",
        "L1 = 50\nG22 A8000\nL1 = 70\nM30\n%\nO8000\nG0 X L1 Z2\nM99\n%",
        ("TX-W107", 3),
    ),
    ("decimal point and comma mixed up", "G1 X1,2.3\nM30", ("TX-E1002", 1)),
]


@pytest.mark.parametrize(("what", "program", "expected"), CASES, ids=[c[0] for c in CASES])
def test_diagnostic(what: str, program: str, expected: tuple[str, int]) -> None:
    assert expected in codes(run(program, "traub-tx8d"))


def test_every_code_is_in_the_catalogue_with_both_languages() -> None:
    for _, _, (code, _) in CASES:
        assert catalogue_code(code) in CATALOGUE
        assert CATALOGUE[catalogue_code(code)].de and CATALOGUE[catalogue_code(code)].en


def test_a_block_with_an_error_does_not_move() -> None:
    tp = run(READY + "G0 X40 Z2\nG26\nG0 X40 Z2\nM30", "traub-tx8d")
    assert [m.line for m in tp.moves] == [5, 6, 6]  # the approach and G26 (X, then Z); not line 7


def test_a_new_t_after_g26_allows_motion_again() -> None:
    tp = run(READY + "G0 X40 Z2\nG26\nT0202\nG0 X40 Z2\nM30", "traub-tx8d")
    assert codes(tp) == []
    assert tp.moves[-1].line == 8


def test_nesting_deeper_than_eight_levels() -> None:
    subs = "".join(f"%\nO{8000 + i}\nG22 A{8001 + i}\nM99\n%\n" for i in range(9))
    tp = run("G22 A8000\nM30\n" + subs + "%\nO8009\nG0 X40 Z2\nM99\n%\n", "traub-tx8d")
    assert [c for c, _ in codes(tp)] == ["TX-E302"]
    assert tp.moves == []


def test_diagnostic_in_a_subprogram_points_at_its_line() -> None:
    tp = run("G22 A8000\nM30\n%\nO8000\nG0 X40 Z2\nG1 Y3\nM99\n%", "traub-tx8d")
    (d,) = [d for d in tp.diagnostics if d.code == "TX-E1003"]
    assert (d.span.line, d.span.column) == (6, 4)


def test_section_of_another_program_with_a_p_q() -> None:
    text = (
        "G97 S500 T0101 M3\nG22 A8000 P20 Q30\nM30\n%\nO8000\nN10 G0 X90 Z2\nN20 G0 X40 Z2\n"
        "N30 G1 Z-10 F0.2\nN40 G0 X80\nM99\n%"
    )
    tp = run(text, "traub-tx8d")
    assert codes(tp) == []
    assert [(round(m.end[0] * 2, 3), round(m.end[2], 3)) for m in tp.moves] == [(40.0, 2.0), (40.0, -10.0)]


def test_section_repeated_h_times() -> None:
    text = "G97 S500 T0101 M3\nG0 X40 Z2\nN10 G1 W-1 F0.1\nN20 G1 W-1\nG22 P10 Q20 H2\nM30"
    tp = run(text, "traub-tx8d")
    assert codes(tp) == []
    assert round(tp.moves[-1].end[2], 3) == -4.0
    assert len(tp.moves) == 1 + 2 + 4


def test_a_new_value_for_the_next_call_is_no_late_assignment() -> None:
    text = "L1 = 50\nG22 A8000\nL1 = 70\nG22 A8000\nM30\n%\nO8000\nG0 X L1 Z2\nM99\n%"
    tp = run(text, "traub-tx8d")
    assert codes(tp) == []
    assert [round(m.end[0] * 2, 3) for m in tp.moves] == [50.0, 70.0]


def test_t_in_g00_for_the_second_edge_is_fine() -> None:
    assert codes(run(READY + "G0 X40 Z2\nG0 X80 Z50 T2121\nM30", "traub-tx8d")) == []


def test_a_t_word_in_the_g26_block_calls_the_tool_at_the_change_point() -> None:
    tp = run(READY + "G0 X40 Z2\nG26 T0202\nG0 X40 Z2\nM30", "traub-tx8d")
    assert codes(tp) == []
    assert [c.tool for c in tp.tool_changes] == [1, 2]
    assert tp.tool_changes[1].position == (230.0, 0.0, 385.0)  # X460 Z585 with G59 Z200
