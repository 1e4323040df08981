"""PAL milling cycles (issue 30): the definition/call model and the drilling cycles G81–G87, with positions
computed by hand. Pockets and slots: tests/test_pal_cycles_pockets.py."""

from __future__ import annotations

import math

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from core.interpreter.state import RunSetup
from core.pipeline import DIALECTS, run
from core.toolpath import Move, Toolpath
from core.tools import Tool, ToolTable
from tests.conftest import codes

# T1: an end mill Ø10 (tool radius 5); the tool stands at X0 Y0 Z50
TOOLS = ToolTable({1: Tool(1, "end_mill", 10.0, cutting_length=40.0), 2: Tool(2, "twist_drill", 8.5)})
SETUP = RunSetup(tools=TOOLS)
READY = "N10 T1 TC1 M6\nN20 S1000 F100 M3\nN30 G0 X0 Y0 Z50\n"


def go(program: str) -> Toolpath:
    return run(READY + program + "\nN999 M30\n", setup=SETUP)


def cycle_moves(tp: Toolpath) -> list[Move]:
    return [m for m in tp.moves if m.cycle is not None]


def ends(moves: list[Move], kind: str | None = None) -> list[tuple[float, float, float]]:
    return [tuple(round(v, 3) for v in m.end) for m in moves if kind is None or m.kind == kind]  # type: ignore[misc]


def plunges(moves: list[Move]) -> list[tuple[float, float]]:
    """(x, y) of each feed move straight down: where the holes are."""
    return [
        (round(m.end[0], 3), round(m.end[1], 3))
        for m in moves
        if m.kind == "feed" and m.end[2] < m.start[2] and m.start[:2] == m.end[:2]
    ]


# -- the definition/call model ------------------------------------------------------------------------------------


def test_a_definition_moves_nothing_and_the_call_drills_there() -> None:
    tp = go("N40 G81 ZI-10 V2")
    assert codes(tp) == [] and cycle_moves(tp) == []
    tp = go("N40 G81 ZI-10 V2\nN50 G79 X10 Y20 Z0")
    assert codes(tp) == []
    moves = cycle_moves(tp)
    # rapid in the plane at Z50, down to the safety height Z2, feed to Z-10, rapid out to Z2 (no W: surface + V)
    assert ends(moves) == [(10, 20, 50), (10, 20, 2), (10, 20, -10), (10, 20, 2)]
    assert [m.kind for m in moves] == ["rapid", "rapid", "feed", "rapid"]
    assert {m.line for m in moves} == {5}  # the calling block
    assert {m.cycle_definition for m in moves} == {4}  # the defining block
    assert {m.cycle for m in moves} == {("G81", 1, 1)}
    assert moves[2].to_json()["cycle"] == {
        "code": "G81",
        "pass": 1,
        "of": 1,
        "defined_in_line": 4,
        "point": 1,
        "points": 1,
    }


def test_a_call_without_a_definition_is_an_error_and_moves_nothing() -> None:
    tp = go("N40 G79 X10 Y20 Z0")
    assert codes(tp) == [("PAL-E601", 4)]
    assert "kein Bearbeitungszyklus definiert" in tp.diagnostics[0].message
    assert cycle_moves(tp) == []


def test_retraction_to_w_between_points_and_up_first_when_below() -> None:
    # the tool stands in the material at Z-1: first up to the retraction height W20, then across
    tp = go("N40 G0 Z2\nN41 G1 Z-1\nN50 G81 ZI-10 V2 W20\nN60 G79 X10 Y0 Z0\nN70 G79 X30 Y0 Z-5")
    moves = cycle_moves(tp)
    assert ends(moves) == [
        (0, 0, 20),
        (10, 0, 20),
        (10, 0, 2),
        (10, 0, -10),
        (10, 0, 2),
        (10, 0, 20),
        (30, 0, 20),
        (30, 0, -3),
        (30, 0, -15),
        (30, 0, -3),
        (30, 0, 20),
    ]


def test_a_call_without_z_takes_the_surface_z0_and_za_is_absolute() -> None:
    moves = cycle_moves(go("N40 G81 ZA-7 V3\nN50 G79 X5 Y5"))
    assert ends(moves) == [(5, 5, 50), (5, 5, 3), (5, 5, -7), (5, 5, 3)]


def test_the_definition_stays_until_replaced() -> None:
    tp = go("N40 G81 ZI-5 V2\nN50 G79 X10 Y0 Z0\nN60 G85 ZI-8 V2 E50\nN70 G79 X20 Y0 Z0\nN80 G79 X30 Y0 Z0")
    assert [(m.cycle[0] if m.cycle else None, m.line) for m in tp.moves if m.kind == "feed"] == [
        ("G81", 5),
        ("G85", 7),
        ("G85", 7),
        ("G85", 8),
        ("G85", 8),
    ]


def test_g76_points_on_a_line() -> None:
    moves = cycle_moves(go("N40 G81 ZI-5 V2\nN50 G76 X10 Y20 Z0 AS30 D10 O3"))
    assert plunges(moves) == [(10, 20), (18.66, 25), (27.321, 30)]


@pytest.mark.parametrize(
    "words,points",
    [
        ("IA50 JA40 R20 AN45 AI90 O3", [(64.142, 54.142), (35.858, 54.142), (35.858, 25.858)]),
        ("IA50 JA40 R20 AN0 AP180 O3", [(70, 40), (50, 60), (30, 40)]),  # evenly to the last at AP
        (
            "IA50 JA40 R20 AN0 O4",
            [(70, 40), (50, 60), (30, 40), (50, 20)],
        ),  # neither AI nor AP: the full circle
        ("I10 J0 R5 AN90 AI180 O2", [(10, 5), (10, -5)]),  # I/J: the centre relative to the current point
    ],
)
def test_g77_points_on_a_pitch_circle(words: str, points: list[tuple[float, float]]) -> None:
    moves = cycle_moves(go(f"N40 G81 ZI-5 V2\nN50 G77 {words} Z0"))
    assert plunges(moves) == [(pytest.approx(x, abs=1e-3), pytest.approx(y, abs=1e-3)) for x, y in points]


def test_g78_a_point_in_polar_coordinates() -> None:
    assert plunges(cycle_moves(go("N40 G81 ZI-5 V2\nN50 G78 IA10 JA10 RP20 AP90 Z0"))) == [(10, 30)]
    assert plunges(cycle_moves(go("N40 G81 ZI-5 V2\nN50 G78 IA10 JA10 RP20 AP0 Z0"))) == [(30, 10)]


def test_calls_in_a_shifted_frame_land_in_workpiece_coordinates() -> None:
    moves = cycle_moves(go("N35 G59 XA100 YA50\nN40 G81 ZI-5 V2\nN50 G79 X10 Y5 Z0"))
    assert plunges(moves) == [(110, 55)]


# -- drilling cycles ------------------------------------------------------------------------------------------------


def test_g82_steps_with_da_dr_dm() -> None:
    # first step DA6, then D5 less 1 per step but not below DM2: 6, 4, 3, 2, 2, 2, then the last 1 mm to Z-20;
    # after each step back VB1 at rapid
    moves = cycle_moves(go("N40 G82 ZI-20 D5 DA6 DR1 DM2 V2\nN50 G79 X0 Y0 Z0"))
    feeds = [m.end[2] for m in moves if m.kind == "feed"]
    assert feeds == pytest.approx([-6, -10, -13, -15, -17, -19, -20])
    backs = [m.end[2] for m in moves if m.kind == "rapid" and m.end[2] < 0]
    assert backs == pytest.approx([-5, -9, -12, -14, -16, -18])
    assert {m.cycle[2] for m in moves if m.cycle} == {7}
    assert [m.cycle[1] for m in moves if m.kind == "feed" and m.cycle] == [1, 2, 3, 4, 5, 6, 7]


def test_g83_swarf_removal_goes_out_to_the_safety_height_after_each_step() -> None:
    moves = cycle_moves(go("N40 G83 ZI-12 D5 V2 VB0.5\nN50 G79 X0 Y0 Z0"))
    zs = [round(m.end[2], 3) for m in moves]
    # (already above the hole) down to 2, feed -5, out 2, back to -4.5, feed -10, out 2, back -9.5, feed -12, out 2
    assert zs == [2, -5, 2, -4.5, -10, 2, -9.5, -12, 2]


def test_g82_dwell_at_the_bottom() -> None:
    tp = go("N40 G82 ZI-10 D5 V2 U1.5\nN50 G79 X0 Y0 Z0")
    assert [(d.seconds, d.position[2]) for d in tp.dwells] == [(1.5, -10)]


def test_g84_feed_is_speed_times_pitch_and_the_spindle_reverses() -> None:
    tp = go("N40 G84 ZI-15 F1.5 M3 S800 V3\nN50 G79 X0 Y0 Z0\nN60 G1 X20")
    assert codes(tp) == []
    moves = cycle_moves(tp)
    down, up = [m for m in moves if m.kind == "feed"]
    assert down.feed == pytest.approx(1200) and down.feed_unit == "mm/min"
    assert (down.spindle_direction, up.spindle_direction) == ("cw", "ccw")
    assert down.end[2] == pytest.approx(-15) and up.end[2] == pytest.approx(3)
    assert tp.moves[-1].feed == 100  # the pitch F1.5 did not replace the modal feed


def test_g84_left_hand_and_its_warnings() -> None:
    tp = go("N40 G84 ZI-15 F1.5 M4 S500 V3\nN50 G79 X0 Y0 Z0")
    down, up = [m for m in cycle_moves(tp) if m.kind == "feed"]
    assert (down.spindle_direction, up.spindle_direction, down.feed) == ("ccw", "cw", pytest.approx(750))
    assert ("PAL-W607", 4) in codes(go("N40 G84 ZI-15 F1.3 M3 V3\nN50 G79 X0 Y0 Z0"))
    stopped = run(
        "N10 T1 TC1 M6\nN20 S500 F100\nN30 G84 ZI-10 F1 M3 V2\nN35 M5\nN40 G79 X0 Y0 Z0\nM30", setup=SETUP
    )
    assert ("PAL-W606", 5) in codes(stopped)
    assert ("PAL-E102", 4) in codes(go("N40 G84 ZI-15 F1.5 V3"))  # M3/M4 missing


def test_g85_out_at_e_and_g86_spindle_stop_and_retraction() -> None:
    moves = cycle_moves(go("N40 G85 ZI-10 V2 E40\nN50 G79 X0 Y0 Z0"))
    assert [(m.kind, round(m.end[2], 3), m.feed) for m in moves[1:]] == [("feed", -10, 100), ("feed", 2, 40)]
    moves = cycle_moves(go("N40 G86 ZI-10 V2 DR0.3\nN50 G79 X0 Y0 Z0"))
    assert ends(moves) == [(0, 0, 2), (0, 0, -10), (-0.3, 0, -10), (-0.3, 0, 2), (0, 0, 2)]
    assert [m.spindle for m in moves[1:]] == [1000, 0, 0, 0]


@pytest.mark.parametrize(
    "v,arcs,last",
    [
        # hole R10, tool radius 5: the centre on radius 5 about X0 Y0; helix from the safety height V down to Z-10
        (2, [(5, 0, -2), (5, 0, -6), (5, 0, -10)], (5, 0, -10)),  # 12 mm at pitch 4: three whole turns
        (1, [(5, 0, -3), (5, 0, -7), (0, -5, -10)], (0, -5, -10)),  # 11 mm: two turns and three quarters
    ],
)
def test_g87_helix_end_points(
    v: float, arcs: list[tuple[float, float, float]], last: tuple[float, float, float]
) -> None:
    moves = cycle_moves(go(f"N40 G87 ZI-10 R10 D4 V{v}\nN50 G79 X0 Y0 Z0"))
    helix = [m for m in moves if m.kind == "arc"]
    assert [tuple(round(c, 3) + 0.0 for c in m.end) for m in helix[:-1]] == arcs
    assert all(m.direction == "ccw" and m.radius == pytest.approx(5) for m in helix)
    final = helix[-1]  # the full circle at the bottom
    assert final.angle == 360 and final.start == final.end and final.end[2] == pytest.approx(-10)
    assert tuple(round(c, 3) + 0.0 for c in final.end) == last
    assert ends(moves)[-2:] == [(0, 0, -10), (0, 0, 1 * v)]


def test_g87_tool_not_smaller_than_the_hole_is_an_error() -> None:
    tp = go("N40 G87 ZI-10 R5 D2 V2\nN50 G79 X0 Y0 Z0")
    assert codes(tp) == [("PAL-E602", 5)]
    assert (
        tp.diagnostics[0].message == "G87: das Werkzeug T1 (Ø10 mm) ist zu groß für die Bohrung Ø10 mm."
        and cycle_moves(tp) == []
    )


# -- diagnostics of definitions and calls ---------------------------------------------------------------------------


@pytest.mark.parametrize(
    "program,expected",
    [
        ("N40 G81 ZI-10", ("PAL-E102", 4)),  # V missing
        ("N40 G81 V2", ("PAL-E102", 4)),  # ZA/ZI missing
        ("N40 G81 ZA-10 ZI-10 V2", ("PAL-E107", 4)),  # both
        ("N40 G82 ZI-10 D0 V2", ("PAL-E213", 4)),  # D ≤ 0
        ("N40 G81 ZI5 V2", ("PAL-E603", 4)),  # the bottom above the surface
        ("N40 G81 ZA5 V2\nN50 G79 X0 Y0 Z0", ("PAL-E603", 5)),  # ZA above the call's surface
        ("N40 G41 G0 X10 Y10\nN50 G81 ZI-5 V2", ("PAL-E608", 5)),  # a definition under compensation
        (
            "N40 G81 ZI-5 V2\nN45 G41 G0 X10 Y10\nN50 G79 X0 Y0 Z0",
            ("PAL-E608", 6),
        ),  # a call under compensation
        ("N40 G81 ZI-5 V2\nN50 G77 IA0 JA0 R10 O0", ("PAL-E611", 5)),  # no points
        ("N40 G81 ZI-5 V2\nN50 G76 X0 Y0 D0.001 O100000", ("PAL-E610", 5)),  # beyond the run's limits
        ("N40 G82 ZI-100 D5 DM0.0001 DR5 V2\nN50 G79 X0 Y0 Z0", ("PAL-E610", 5)),
    ],
)
def test_cycle_diagnostics(program: str, expected: tuple[str, int]) -> None:
    tp = go(program)
    assert expected in codes(tp)
    assert cycle_moves(tp) == []


def test_every_cycle_diagnostic_has_both_languages_and_sie() -> None:
    from core.diagnostics import CATALOGUE

    cycle_codes = [c for c in CATALOGUE if c[5] == "6" and c.startswith("PAL-")]
    assert len(cycle_codes) >= 10
    for c in cycle_codes:
        entry = CATALOGUE[c]
        assert entry.de and entry.en and entry.de != entry.en
        assert not any(w in f" {entry.de} " for w in (" du ", " Du ", " dein", " Dein"))


def test_the_still_unsupported_forms_say_so_once() -> None:
    tp = go("N40 G73 ZI-5 R20 RZ8 D2 V2")
    assert codes(tp) == [("PAL-E901", 4)]
    assert tp.diagnostics[0].message.startswith("Zapfenfräsen mit G73 (RZ) wird noch nicht unterstützt")
    for code in ("G34", "G39", "G80", "G88", "G89"):
        assert codes(go(f"N40 {code} ZI-5 V2")) == [("PAL-E901", 4)]


def test_bad_words_never_crash() -> None:
    for block in (
        "G72 ZI-5 LP-4 BP3 D1 V2",
        "G73 ZI-5 R0 D1 V2",
        "G87 ZI-5 R8 D0.00001 V2",
        "G75 ZI-2 BP8 RP2 AN0 AO0 D1 V2",
        "G74 ZI-2 LP5 BP10 D1 V2",
        "G72 ZI-5 LP40 BP30 D1 V2 H3",
        "G72 ZI-5 LP40 BP30 D1 V2 DB0",
    ):
        tp = go(f"N40 {block}\nN50 G79 X0 Y0 Z0")
        assert tp.diagnostics, block
        assert math.isfinite(sum(m.end[2] for m in tp.moves))


# -- help and docs ----------------------------------------------------------------------------------------------------


def test_hover_help_of_every_cycle_says_reconstructed_and_its_example_runs() -> None:
    from core.dialects.pal_mill import TABLE
    from core.interpreter.pal_cycles import CALLS, DEFINITIONS

    for name in sorted(DEFINITIONS | CALLS):
        code = TABLE.codes[name]
        assert "nach der PAL-Syntax rekonstruiert (nicht aus der Vorlage)" in code.rule_de, name
        assert "reconstructed" in code.rule_en, name
        for group in code.help_mandatory():
            for a in group:
                assert TABLE.addresses[a].help_de and TABLE.addresses[a].help_en
        assert all(TABLE.addresses[a].unit == "mm" for a in ("V", "LP", "BP", "AK", "AL", "DA", "DM", "VB"))
        definition = code.example if name in DEFINITIONS else "N40 G81 ZI-5 V2"
        call = code.example if name in CALLS else "N60 G79 X50 Y40 Z0"
        tp = run(
            "N10 T1 TC1 M6\nN20 S500 F100 M3\nN30 G0 X0 Y0 Z50\n" + definition + "\n" + call + "\nN99 M30",
            setup=RunSetup(tools=ToolTable({1: Tool(1, "end_mill", 6.0, cutting_length=40.0)})),
        )
        assert codes(tp) == [], name
        assert cycle_moves(tp), name


def test_docs_list_every_reconstructed_choice() -> None:
    from pathlib import Path

    from core.interpreter.pal_cycles import reconstructed_markdown

    doc = (Path(__file__).parents[1] / "docs" / "pal-milling.md").read_text(encoding="utf-8")
    assert "## Zyklen" in doc and "Nach der PAL-Syntax rekonstruiert (nicht aus der Vorlage)" in doc
    assert reconstructed_markdown() in doc, (
        "docs/pal-milling.md: paste core.interpreter.pal_cycles.reconstructed_markdown()"
    )


def test_a_call_after_a_rejected_definition_is_its_follow_up() -> None:
    tp = go("N40 G81 ZI-10 ZA-3 V2\nN50 G79 X10 Y0 Z0")
    assert codes(tp) == [("PAL-E107", 4), ("PAL-E601", 5)]
    assert tp.diagnostics[1].follows_from == 4
    assert tp.diagnostics[1].message.endswith("(Folgefehler von Zeile 4).")
    # a call with no definition at all is an error of its own
    assert go("N50 G79 X10 Y0 Z0").diagnostics[0].follows_from is None


def test_a_rejected_definition_replaces_the_earlier_one() -> None:
    # the pocket of line 4 is not milled again at line 7: the drilling cycle of line 6 (V missing) replaced it
    tp = go("N40 G73 ZI-6 R12 D3 V2 W5\nN50 G79 X75 Y40 Z0\nN60 G81 ZI-3 W5\nN70 G79 X30 Y70 Z0")
    assert codes(tp) == [("PAL-E102", 6), ("PAL-E601", 7)] and tp.diagnostics[1].follows_from == 6
    assert [m for m in tp.moves if m.line == 7] == [] and any(m.line == 5 for m in tp.moves)


@pytest.mark.parametrize(
    "program,expected",
    [
        (
            "N40 G72 ZI-90000 LP40 BP30 D0.001 V2\nN50 G79 X0 Y0 Z0",
            "PAL-E610",
        ),  # levels, refused before they are made
        ("N40 G72 ZI-2 LP90000 BP90000 DB1 D2 V2\nN50 G79 X0 Y0 Z0", "PAL-E610"),  # rings
        ("N40 G83 ZI-90000 D0.001 V2\nN50 G79 X0 Y0 Z0", "PAL-E610"),  # steps
        (
            "N40 G82 ZI-40 D0.2 V2\nN50 G77 IA0 JA0 R50 O400",
            "PAL-E017",
        ),  # 400 holes of 200 steps: too many moves
    ],
)
def test_huge_cycles_are_refused_quickly(program: str, expected: str) -> None:
    # refused before any of their moves is made: the work is bounded by counting, not by the clock
    tp = go(program)
    assert expected in [c for c, _ in codes(tp)]
    assert cycle_moves(tp) == []


def _words() -> dict[str, tuple[list[str], list[tuple[str, ...]]]]:
    from core.dialects.pal_mill import TABLE
    from core.interpreter.pal_cycles import CALLS, DEFINITIONS

    return {
        name: (sorted(TABLE.codes[name].words), list(TABLE.codes[name].help_mandatory()))
        for name in sorted(DEFINITIONS | CALLS)
    }


WORDS = _words()


ran: list[bool] = []


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.data())
def test_any_cycle_and_call_with_any_values_never_crashes(data: st.DataObject) -> None:
    defs = [n for n in WORDS if n not in ("G76", "G77", "G78", "G79")]
    code = data.draw(st.sampled_from(defs))
    call = data.draw(st.sampled_from(["G76", "G77", "G78", "G79"]))
    value = st.one_of(
        st.integers(1, 60), st.integers(-60, 60), st.sampled_from([0, 0.001, 1, 2, 4, 14, 90, 100, 360])
    )
    def_words, call_words = (
        [data.draw(st.sampled_from(group)) for group in WORDS[name][1]]
        + data.draw(st.lists(st.sampled_from(WORDS[name][0]), max_size=5, unique=True))
        for name in (code, call)
    )
    def_words, call_words = list(dict.fromkeys(def_words)), list(dict.fromkeys(call_words))
    depth = st.integers(-30, 0)
    block = " ".join(f"{w}{data.draw(depth if w in ('ZI', 'ZA') else value)}" for w in def_words)
    calling = " ".join(f"{w}{data.draw(value)}" for w in call_words)
    extra = " M3" if code == "G84" else ""
    tp = go(f"N40 {code} {block}{extra}\nN50 {call} {calling}")
    ran.append(any(m.cycle for m in tp.moves))
    for m in tp.moves:
        assert all(math.isfinite(v) for v in (*m.start, *m.end))


def test_the_random_cycles_above_did_run_some_moves() -> None:
    assert not ran or sum(ran) >= 5, sum(ran)  # (about 20 of the 300 make moves; the rest are refused)


def test_hover_help_of_the_cycle_words_says_reconstructed() -> None:
    from core.dialects.pal_mill import TABLE

    for a in ("V", "LP", "BP", "AK", "AL", "EP", "DB", "Q", "DA", "DR", "DM", "VB", "AN"):
        address = TABLE.addresses[a]
        assert "nach der PAL-Syntax rekonstruiert (nicht aus der Vorlage)" in address.rule_de, a
        assert address.help_en and "reconstructed" in address.rule_en, a
    assert (TABLE.addresses["DB"].unit, TABLE.addresses["AN"].unit, TABLE.addresses["LP"].unit) == (
        "%",
        "°",
        "mm",
    )


def test_the_help_of_a_cycle_word_says_how_certain_its_meaning_is() -> None:
    addresses = DIALECTS["pal-mill"].table.addresses
    assert addresses["LP"].rule_de.startswith(
        "Zyklenwort, Bedeutung sicher (H); nach der PAL-Syntax rekonstruiert"
    )
    assert addresses["DR"].rule_de.startswith("Zyklenwort, Bedeutung unsicher (L)")
    assert addresses["VB"].rule_en.startswith(
        "cycle word, meaning likely (M); reconstructed from the PAL syntax"
    )
    assert addresses["LP"].unit == "mm" and addresses["DB"].unit == "%"
