"""Modal state: the switch-on state, what is active at line N, and when words take effect in a block."""

from __future__ import annotations

import pytest

from core.pipeline import run


def test_switch_on_state() -> None:
    tp = run("M30")
    state, _ = tp.state_at(0)
    assert {
        g: state.active(g)
        for g in (
            "motion",
            "plane",
            "compensation",
            "zero_offset",
            "units",
            "dimensions",
            "feed_mode",
            "spindle_mode",
            "spindle",
            "coolant",
            "workpiece_change",
        )
    } == {
        "motion": "G1",
        "plane": "G17",
        "compensation": "G40",
        "zero_offset": "G54",
        "units": "G71",
        "dimensions": "G90",
        "feed_mode": "G94",
        "spindle_mode": "G97",
        "spindle": "M5",
        "coolant": "M9",
        "workpiece_change": "M60",
    }
    assert (state.feed, state.speed, state.tool) == (0, 0, None)


def test_what_is_active_at_line_n() -> None:
    tp = run("N10 T1 TC1 M6\nN20 S1200 F150 M3\nN30 G0 X0 Y0 Z2\nN40 G91\nN50 G1 Z-4\nN60 G90 M8\nN70 M30")
    s3, p3 = tp.state_at(3)
    assert (s3.active("motion"), s3.active("dimensions"), s3.active("spindle")) == ("G0", "G90", "M3")
    assert p3 == (0, 0, 2)
    s5, p5 = tp.state_at(5)
    assert (s5.active("motion"), s5.active("dimensions")) == ("G1", "G91")
    assert p5 == (0, 0, -2)
    s6, _ = tp.state_at(6)
    assert (s6.active("dimensions"), s6.active("coolant"), s6.feed, s6.speed, s6.tool) == (
        "G90",
        "M8",
        150,
        1200,
        1,
    )


def test_feed_and_speed_act_at_block_start() -> None:
    tp = run("T1 M6\nS1000 M3\nG1 X10 F80\nG1 X20 F120 S2000\nM30")
    assert [(m.feed, m.spindle) for m in tp.moves] == [(80, 1000), (120, 2000)]


def test_m5_and_m9_act_at_block_end() -> None:
    tp = run("T1 M6\nS1000 F100 M3 M8\nG1 X10 M5 M9\nG0 X20\nM30")
    first, second = tp.moves
    assert (first.spindle, first.coolant) == (1000, True)  # the move of the M5 block still cuts
    assert (second.spindle, second.coolant) == (0, False)
    assert tp.state_at(3)[0].active("spindle") == "M5"


def test_m3_acts_at_block_start() -> None:
    tp = run("T1 M6\nS1000 F100\nG1 X10 M3\nM30")
    assert tp.moves[0].spindle == 1000 and tp.diagnostics == []


def test_tool_change_stops_spindle_and_coolant_and_resets_offsets() -> None:
    tp = run("T1 TC3 TR0.1 M6\nS1000 F100 M13\nT4 M6\nM30")
    assert [(c.tool, c.tc, c.tr) for c in tp.tool_changes] == [(1, 3, 0.1), (4, 1, 0)]
    state, _ = tp.state_at(3)
    assert (state.active("spindle"), state.active("coolant"), state.tool) == ("M5", "M9", 4)
    assert tp.state_at(2)[0].active("coolant") == "M8"  # M13 = M3 + M8


def test_t0_empties_the_spindle() -> None:
    tp = run("T1 M6\nT0\nM30")
    assert tp.state_at(2)[0].tool is None


def test_incremental_spellings() -> None:
    tp = run("G0 X10 Y10 Z10\nG0 XI5 Y0\nG91\nG0 X1 YA3\nG90\nM30")
    assert [m.end for m in tp.moves] == [(10, 10, 10), (15, 0, 10), (16, 3, 10)]
    assert {d.code for d in tp.diagnostics} == set()


def test_unusual_spelling_is_a_hint_not_an_error() -> None:
    tp = run("G0 XA5\nM30")
    assert [(d.code, d.severity.value) for d in tp.diagnostics] == [("PAL-I101", "info")]
    assert tp.moves[0].end[0] == 5


def test_dwell() -> None:
    tp = run("T1 M6\nS600 M3\nG4 U2\nG4 U3 O2\nM30")
    assert [d.seconds for d in tp.dwells] == pytest.approx([2, 0.3])


def test_skip_blocks_switch() -> None:
    from core.interpreter.state import RunSetup

    program = "G0 X1\n/G0 X2\nM30"
    assert run(program).final_position[0] == 2
    assert run(program, setup=RunSetup(skip_blocks=True)).final_position[0] == 1


def test_helix_and_full_circle() -> None:
    tp = run("T1 M6\nS1000 F100 M3\nG0 X10 Y0 Z0\nG3 I-10 J0 Z-5\nG2 X0 Y10 R10 Z-6\nG2 X10 Y0 R-10\nM30")
    full, short, long = [m for m in tp.moves if m.kind == "arc"]
    assert (full.angle, full.center, full.end) == (360, (0, 0, 0), (10, 0, -5))
    # R+ : the shorter of the two arcs, clockwise from (10,0) to (0,10) about (10,10)
    assert short.center == pytest.approx((10, 10, -5)) and short.angle == pytest.approx(90)
    assert short.end == (0, 10, -6)
    # R- : the longer one, 270° about (10,10)... back from (0,10) to (10,0) clockwise
    assert long.angle == pytest.approx(270) and long.radius == 10
