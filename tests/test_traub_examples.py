"""The TRAUB TX 8 D examples of the manual (spec examples.md TX-02…TX-49, without the contour trains and SRK):
each runs with exactly the diagnostics it should give, and the printed coordinates come out to 0.001 mm.

Moves are [x radius, 0, z] in the workpiece frame (DECISIONS §15).
"""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from core.interpreter.state import RunSetup
from core.pipeline import run
from core.toolpath import Toolpath
from tests.conftest import codes

SEEDS = Path(__file__).with_name("seeds") / "traub"
TOL = 1e-3


def traub(name: str, setup: RunSetup | None = None) -> Toolpath:
    return run((SEEDS / name).read_text(encoding="utf-8"), "traub-tx8d", setup)


def ends(tp: Toolpath) -> list[tuple[float, float]]:
    """(X diameter, Z) of every move's end."""
    return [(round(m.end[0] * 2, 3), round(m.end[2], 3)) for m in tp.moves]


NO_TOOL, NO_END = "TX-W106", "TX-W1102"

# every example with the diagnostics it must give (code, line) — nothing else
EXPECTED: dict[str, list[tuple[str, int]]] = {
    "tx-02-hauptprogramm.nc": [],
    "tx-03-unterprogramm.nc": [],
    "tx-04-makro.nc": [],
    "tx-05-m-woerter.nc": [],
    "tx-06-b-wort.nc": [],
    "tx-07-ausblendsaetze.nc": [],
    "tx-08-nullpunkt.nc": [],
    "tx-09-absolut-inkremental.nc": [],
    "tx-10-t-woerter.nc": [],
    "tx-11-ersatzwerkzeuge.nc": [],
    "tx-12-g94.nc": [],
    "tx-13-g95.nc": [],
    "tx-14-g97-s.nc": [],
    "tx-15-g97-v-x.nc": [],
    "tx-16-g96-g92.nc": [],
    "tx-18-g0.nc": [(NO_END, 1)],  # a fragment: no T, no M30
    "tx-19-g1.nc": [(NO_TOOL, 2), (NO_TOOL, 3), (NO_TOOL, 5), (NO_TOOL, 6), (NO_END, 6)],
    "tx-20-winkel-a.nc": [(NO_TOOL, n) for n in (3, 4, 5, 6, 9, 10, 11, 12)] + [(NO_END, 12)],
    "tx-26-verweilzeit.nc": [],
    "tx-43-g22-unterprogramm.nc": [],
    "tx-44-g22-abschnitt.nc": [],
    "tx-45-wertfreies-unterprogramm.nc": [],
    "tx-47-ausblendsatz.nc": [(NO_TOOL, 3), (NO_END, 3)],
    "tx-49-l-parameter.nc": [],
}


@pytest.mark.parametrize("name", sorted(EXPECTED))
def test_example_gives_exactly_its_diagnostics(name: str) -> None:
    assert codes(traub(name)) == EXPECTED[name]


def test_every_traub_seed_file_is_covered() -> None:
    mine = {p.name for p in SEEDS.glob("tx-*.nc")} - set(EXPECTED)
    theirs = {
        p
        for p in mine
        if p[:5]
        in {"tx-17", "tx-21", "tx-22", "tx-23", "tx-24", "tx-25", "tx-27", "tx-28", "tx-48"}
        | {f"tx-{n}" for n in range(29, 43)}
    }  # cycles: test_traub_cycles
    assert mine == theirs


def test_tx02_program_head_calls_tool_2_with_offset_2_at_constant_cutting_speed() -> None:
    tp = traub("tx-02-hauptprogramm.nc")
    (change,) = tp.tool_changes
    assert (change.tool, change.tc) == (2, 2)
    state, _ = tp.state_at(4)
    assert state.codes["spindle_mode"] == "G96" and state.codes["spindle"] == "M4"


def test_tx03_subprogram_o8001_runs_from_the_main_program() -> None:
    tp = traub("tx-03-unterprogramm.nc")
    assert ends(tp) == [(40.0, 2.0), (20.0, 2.0)]
    assert [m.line for m in tp.moves] == [11, 12]
    assert tp.moves[0].call_stack == ((None, 6),)


def test_tx04_macro_g201_calls_o9801() -> None:
    tp = traub("tx-04-makro.nc")
    assert ends(tp) == [(30.0, 2.0), (30.0, -10.0)]
    assert all(m.spindle == 800 for m in tp.moves)


def test_tx05_three_m_words_in_one_block_all_act() -> None:
    tp = traub("tx-05-m-woerter.nc")
    state, _ = tp.state_at(5)
    assert state.codes["spindle"] == "M4" and state.codes["coolant"] == "M8"
    assert tp.moves[0].coolant and tp.moves[0].spindle_direction == "ccw"


def test_tx05_a_fourth_m_word_is_an_error() -> None:
    tp = run("G 96 V 200 T 0303 M 04 M 08 M 41 M 48\nM30", "traub-tx8d")
    assert ("TX-E104", 1) in codes(tp)


def test_tx06_b06_before_the_driven_tool_is_switched_on_is_an_error() -> None:
    assert codes(run("B 06 3500\nM30", "traub-tx8d")) == [("TX-E107", 1)]
    assert codes(run("T 101 M 22 M 24 B 062150\nB 06 3500\nM30", "traub-tx8d")) == []


def test_tx07_skip_blocks_are_not_executed_by_default() -> None:
    tp = traub("tx-07-ausblendsaetze.nc")
    assert ends(tp)[:2] == [(28.02, 1.0), (28.02, -30.0)]
    assert tp.moves[1].feed == pytest.approx(0.15)


def test_tx07_with_the_skip_key_on_the_measuring_cut_runs_first() -> None:
    tp = traub("tx-07-ausblendsaetze.nc", RunSetup(skip_blocks=False))
    assert ends(tp)[:3] == [(28.5, 1.0), (28.5, -30.0), (42.0, -30.0)]
    assert (28.02, -30.0) in ends(tp)
    assert [c.tool for c in tp.tool_changes] == [6, 6]  # the T0606 after G26 calls the tool again
    # M00 includes M05: the fit is cut with the spindle at rest unless the operator restarts it
    assert ("TX-E1302", 13) in codes(tp)


def test_tx08_g59_added_to_g54_gives_the_same_workpiece_zero() -> None:
    """Bild b: G54 Z0 + G59 Z231; Bild c: G54 Z110 + G59 Z121. The tool-change point (Z585 machine) is then
    the same 354 mm in front of the workpiece zero in both."""
    b = traub("tx-08-nullpunkt.nc")
    text = (SEEDS / "tx-08-nullpunkt.nc").read_text(encoding="utf-8").replace("Z 231", "Z 121")
    c = run(text, "traub-tx8d", RunSetup(zero_offsets=(("G54", (0.0, 0.0, 110.0)),)))
    assert ends(b) == ends(c)
    assert ends(b)[-1] == (460.0, 354.0)


def test_tx08_g59_replaces_the_previous_shift() -> None:
    tp = run("G59 Z100\nT0101 G97 S500 M3\nG0 X40 Z0\nG59 Z50\nG0 X40 Z0\nM30", "traub-tx8d")
    assert ends(tp) == [(40.0, 0.0), (40.0, -50.0)]


def test_tx09_absolute_incremental_and_mixed_reach_the_same_point() -> None:
    """X30 Z-15 → X60 Z-55 is U15 W-40: U is a radius value (DECISIONS §12)."""
    tp = traub("tx-09-absolut-inkremental.nc")
    e = ends(tp)
    assert e[2] == e[5] == e[8] == (60.0, -55.0)
    assert e[1] == e[4] == e[7] == (30.0, -15.0)


def test_tx09_first_motion_after_a_tool_call_must_be_absolute() -> None:
    tp = run("G97 S500 T0101 M3\nG0 U10 Z2\nM30", "traub-tx8d")
    assert codes(tp) == [("TX-E101", 2)]
    assert tp.moves == []


def test_tx10_t_words_give_station_and_offset() -> None:
    tp = traub("tx-10-t-woerter.nc")
    assert [(c.tool, c.tc) for c in tp.tool_changes] == [(2, 2), (3, 3), (4, 4), (16, 16), (2, 2)]


def test_tx11_m06_needs_a_tool_call_in_its_block() -> None:
    assert [(c.tool) for c in traub("tx-11-ersatzwerkzeuge.nc").tool_changes] == [3, 4, 5]
    assert codes(run("M06\nM30", "traub-tx8d")) == [("TX-E105", 1)] or ("TX-E106", 1) in codes(
        run("M06\nM30", "traub-tx8d")
    )
    assert ("TX-E106", 1) in codes(run("G96 V200 M4 M13\nM30", "traub-tx8d"))


def test_tx12_g94_feed_per_minute_with_the_driven_tool() -> None:
    tp = traub("tx-12-g94.nc")
    drill = next(m for m in tp.moves if m.kind == "feed")
    assert (drill.feed, drill.feed_unit) == (80, "mm/min")
    assert ends(tp)[:3] == [(460.0, -20.0), (50.0, -20.0), (20.0, -20.0)]


def test_tx13_g95_feed_per_revolution() -> None:
    tp = traub("tx-13-g95.nc")
    cut = tp.moves[-1]
    assert (cut.feed, cut.feed_unit) == (0.2, "mm/rev")
    assert ends(tp)[-1] == (40.0, -30.0)


def test_tx14_g97_fixed_speed() -> None:
    tp = traub("tx-14-g97-s.nc")
    assert [m.spindle for m in tp.moves] == [800, 800]
    assert ends(tp) == [(0.0, 2.0), (0.0, -20.0)]


def test_tx15_g97_speed_from_v_and_x_is_computed_once() -> None:
    tp = traub("tx-15-g97-v-x.nc")
    assert [m.spindle for m in tp.moves] == pytest.approx([795.775, 795.775], abs=TOL)


def test_tx16_g96_speed_follows_the_diameter_and_g92_limits_it() -> None:
    tp = traub("tx-16-g96-g92.nc")
    by_line = {m.line: m.spindle for m in tp.moves}
    assert by_line[7] == pytest.approx(250_000 / (math.pi * 40), abs=TOL)  # 1989.437 at Ø40
    assert by_line[8] == pytest.approx(1989.437, abs=TOL)
    assert by_line[9] == 3000  # Ø20 would need 3978.9 1/min
    assert by_line[10] == 3000


def test_tx18_rapid_with_coolant() -> None:
    tp = traub("tx-18-g0.nc")
    (m,) = tp.moves
    assert m.kind == "rapid" and m.coolant
    assert [round(v, 3) for v in m.end] == [10.0, 0.0, 2.0]


def test_tx19_axis_parallel_and_conical_moves_feed_modal() -> None:
    tp = traub("tx-19-g1.nc")
    assert ends(tp) == [(20.0, 2.0), (20.0, -15.0), (40.0, -25.0), (20.0, 2.0), (20.0, -15.0), (40.0, -25.0)]
    assert tp.moves[-1].feed == 0.2 and tp.moves[-1].kind == "feed"


def test_tx20_lines_given_by_angle_a() -> None:
    tp = traub("tx-20-winkel-a.nc")
    e = [(m.end[0] * 2, m.end[2]) for m in tp.moves]
    assert e[2] == pytest.approx((20.0, -42.321), abs=TOL)  # X20 A210 from X40 Z-25
    assert e[4] == pytest.approx((60.0, -85.0), abs=TOL)  # X60 A135 from X20 Z-65
    assert e[8] == pytest.approx((40.0, -20.0), abs=TOL)  # X40 A30 from X20 Z-37.32 (= 20 + 10/tan 30°)


def test_tx26_dwell_half_a_second_where_the_tool_stands() -> None:
    tp = traub("tx-26-verweilzeit.nc")
    assert [d.seconds for d in tp.dwells] == [0.5, 0.5]
    assert [(round(d.position[0] * 2, 3), round(d.position[2], 3)) for d in tp.dwells] == [
        (0.0, -30.0),
        (40.0, -15.0),
    ]


def test_tx26_dwell_out_of_range() -> None:
    assert codes(run("G4 X1000\nM30", "traub-tx8d")) == [("TX-E108", 1)]


def _geometry(tp: Toolpath) -> list[tuple[str, tuple[float, ...], tuple[float, ...]]]:
    return [
        (m.kind, tuple(round(v, 6) for v in m.start), tuple(round(v, 6) for v in m.end)) for m in tp.moves
    ]


def test_tx43_subprogram_centres_and_drills() -> None:
    tp = traub("tx-43-g22-unterprogramm.nc")
    feeds = [
        (e, m.spindle) for e, m in zip(ends(tp), tp.moves, strict=True) if m.kind == "feed" and not m.thread
    ]
    assert feeds == [((0.0, -6.0), 1000), ((0.0, -25.0), 1000)]
    taps = [(e, m.pitch, m.spindle_direction) for e, m in zip(ends(tp), tp.moves, strict=True) if m.thread]
    assert [t[0][1] for t in taps] == [-15.0, taps[1][0][1]] and taps[0][
        1
    ] == 0.9  # G82: in, and out reversed
    assert taps[0][2] != taps[1][2]
    assert [c.tool for c in tp.tool_changes] == [3, 4, 5]
    assert ends(tp)[-1] == (460.0, 435.0)  # G27: Z first, then X to the change point X460 Z585 (G59 Z150)


def test_tx45_value_free_subprogram_gives_the_toolpath_of_tx43() -> None:
    a, b = traub("tx-43-g22-unterprogramm.nc"), traub("tx-45-wertfreies-unterprogramm.nc")
    assert _geometry(a) == _geometry(b)
    speeds = [m.spindle for m in b.moves if m.kind == "feed" and not m.thread]
    assert speeds == pytest.approx([795.775, 868.118], abs=TOL)  # 30·1000/(12π), 30·1000/(11π)
    assert b.params == {1: 11, 2: 12, 3: 15, 4: 25, 5: 1}
    assert [d.seconds for d in b.dwells] == [0.5]


def test_tx44_section_runs_once_inline_and_three_times_by_g22() -> None:
    tp = traub("tx-44-g22-abschnitt.nc")
    holes = [m for m in tp.moves if m.kind == "feed"]
    assert len(holes) == 4
    assert {(round(m.end[0] * 2, 3), round(m.end[2], 3)) for m in holes} == {(10.0, -10.0)}


def test_tx47_skip_block_runs_only_with_the_skip_key_on() -> None:
    assert ends(traub("tx-47-ausblendsatz.nc")) == [(40.0, 2.0), (40.0, -50.0)]
    tp = traub("tx-47-ausblendsatz.nc", RunSetup(skip_blocks=False))
    assert ends(tp) == [(40.0, 2.0), (40.0, -106.0), (40.0, -50.0)]
    assert tp.moves[1].feed == pytest.approx(0.2)


def test_tx49_parameters_assigned_before_the_call_and_computed_in_brackets() -> None:
    tp = traub("tx-49-l-parameter.nc")
    assert ends(tp)[:3] == [(25.0, 2.0), (25.0, -20.0), (35.0, -20.0)]
    assert tp.params == {1: 20, 2: 25}


def test_tool_table_yaml_carries_the_nose_data() -> None:
    from core.sim.tooltable import parse_tool_table, tool_table_yaml

    table = parse_tool_table(
        "tools:\n  - {number: 3, kind: turning, diameter: 0.8, nose_radius: 0.4, quadrant: 3}\n"
    )
    tool = table.tools[3]
    assert (tool.nose_radius, tool.quadrant, tool.name) == (0.4, 3, "Drehmeißel Ø0.8")
    assert parse_tool_table(tool_table_yaml(table)) == table


def test_the_benchmark_turning_program_runs_clean() -> None:
    import importlib.util

    spec = importlib.util.spec_from_file_location(
        "bench_interpreter", Path(__file__).parents[1] / "bench" / "interpreter.py"
    )
    assert spec is not None and spec.loader is not None
    bench = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(bench)
    text = bench.generate_turning()
    tp = run(text, "traub-tx8d")
    assert len(text.splitlines()) == 300
    assert codes(tp) == [] and len(tp.moves) > 250


def test_state_after_each_line_carries_position_and_speed() -> None:
    tp = traub("tx-16-g96-g92.nc")
    state, position = tp.state_at(7)  # G00 X40 Z2
    assert position == pytest.approx((20.0, 0.0, 2.0))
    assert state.speed == pytest.approx(1989.437, abs=TOL) and state.codes["spindle_mode"] == "G96"
    _, before = tp.state_at(1)
    assert before == pytest.approx((230.0, 0.0, 375.0))  # the tool-change point X460 Z585, G59 Z210
    state, _ = tp.state_at(9)
    assert state.speed == 3000
