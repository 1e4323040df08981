"""Issue 12, part 4: follow-up errors are named as such; a missing F is reported once where it matters."""

from __future__ import annotations

from pathlib import Path

import pytest

from core.diagnostics import CATALOGUE, FOLLOW_UPS, REPEATED, Severity
from core.pipeline import diagnostics_json, run
from core.toolpath import Toolpath
from tests.conftest import SeedReader, codes

READY = "N10 T1 TC1 M6\nN20 S1200 F150 M3\n"


def follows(tp: Toolpath) -> list[tuple[str, int, int | None]]:
    """(code, line, follows_from) of every diagnostic."""
    return [(d.code, d.span.line, d.follows_from) for d in tp.diagnostics]


def test_examiner_decimal_comma_then_arc_error_is_named_a_follow_up() -> None:
    tp = SeedReader.run("pal-05-g2-kreisbogen.nc", {"N60": "N60 G1 Y23,6"})
    assert follows(tp) == [("PAL-E010", 7, None), ("PAL-E202", 8, 7)]
    arc = tp.diagnostics[1]
    assert arc.message.endswith("(Folgefehler von Zeile 7).")
    assert arc.message_en.endswith("(follows from the error in line 7).")
    data = diagnostics_json(tp.diagnostics)["diagnostics"]
    assert "follows_from" not in data[0] and data[1]["follows_from"] == 7


def test_examiner_missing_feed_reported_once_then_one_note() -> None:
    tp = SeedReader.run("pal-05-g2-kreisbogen.nc", {"N20": "N20 S1200 M3"})
    assert follows(tp) == [("PAL-E301", 7, None), ("PAL-I301", 8, 7)]
    first, note = tp.diagnostics
    assert first.severity is Severity.ERROR and note.severity is Severity.INFO
    assert note.message == (
        "Vorschubbewegung mit Vorschub F0 auch in 2 weiteren Sätzen: Zeile 8, 9 (Folgefehler von Zeile 7)."
    )
    assert (
        note.message_en
        == "Feed move with feed F0 also in 2 more blocks: line 8, 9 (follows from the error in line 7)."
    )


def test_a_dropped_technology_block_names_the_missing_feed_and_spindle_as_follow_ups() -> None:
    tp = SeedReader.run("pal-05-g2-kreisbogen.nc", {"N20": "N20 S1200 F1,5 M3"})
    assert follows(tp) == [
        ("PAL-E010", 3, None),
        ("PAL-E301", 7, 3),
        ("PAL-E302", 7, 3),
        ("PAL-I301", 8, 3),
        ("PAL-I301", 8, 3),
    ]


def test_an_error_after_the_position_is_known_again_is_its_own() -> None:
    # N65 moves to an absolute X and Y: the wrong arc in N70 is the program's own error, not a follow-up
    tp = SeedReader.run(
        "pal-05-g2-kreisbogen.nc",
        {"N60": "N60 G1 Y23,6\nN65 G1 X70 Y23.6", "N70": "N70 G2 X56.4 Y10 I-20 J9"},
    )
    assert [(c, n, f) for c, n, f in follows(tp) if c == "PAL-E202"] == [("PAL-E202", 9, None)]


def test_an_incremental_move_does_not_make_the_position_known() -> None:
    text = READY + "N30 G0 X0 Y0 Z2\nN40 G1 X10,5\nN50 G91 G1 X10\nN60 G90 G2 X30 Y0 I5 J0\nN70 M30\n"
    tp = run(text)
    assert follows(tp) == [("PAL-E010", 4, None), ("PAL-E202", 6, 4)]


def test_an_arc_dropped_by_its_own_error_makes_the_next_arc_error_a_follow_up() -> None:
    text = READY + "N30 G0 X0 Y0 Z2\nN40 G2 X20 Y0 I5 J0\nN50 G2 X40 Y0 I10 J0\nN60 M30\n"
    tp = run(text)
    assert follows(tp) == [("PAL-E202", 4, None), ("PAL-E202", 5, 4)]


def test_a_repeat_of_a_dropped_block_number_is_a_follow_up() -> None:
    tp = run(READY + "N30 G0 X0 Y0 Z2\nN40 G1 X5,5\nN50 G23 N40 N40 H1\nN60 M30\n")
    assert follows(tp) == [("PAL-E010", 4, None), ("PAL-E406", 5, 4)]


def test_one_missing_feed_in_a_loop_is_one_error() -> None:
    tp = run("N10 T1 TC1 M6\nN20 S1200 M3\nN30 G0 X0 Y0 Z2\nN40 G91 G1 X5\nN50 G23 N40 N40 H3\nN60 G90 M30\n")
    assert codes(tp) == [("PAL-E301", 4)]


def test_no_tool_and_stopped_spindle_fold_the_same_way() -> None:
    tp = run("N20 F100\nN30 G0 X0 Y0 Z2\nN40 G1 X5\nN50 G1 Y5\nN60 G1 X0\nN70 M30\n")
    assert follows(tp) == [("PAL-E303", 3, None), ("PAL-I301", 4, 3)]
    assert tp.diagnostics[1].message.startswith(
        "Vorschubbewegung ohne Werkzeug auch in 2 weiteren Sätzen: Zeile 4, 5"
    )


def test_a_correct_program_has_no_follow_ups() -> None:
    tp = SeedReader.run("pal-05-g2-kreisbogen.nc")
    assert codes(tp) == []


@pytest.mark.parametrize("dialect", ["sinumerik-iso", "beckhoff"])
def test_other_dialects_fold_the_missing_feed(dialect: str) -> None:
    tp = run("T1 M6\nS1000 M3\nG0 X0 Y0 Z2\nG1 X5\nG1 Y5\nG1 X0\nM30\n", dialect)
    prefix = {"sinumerik-iso": "ISO", "beckhoff": "BK"}[dialect]
    assert follows(tp) == [(f"{prefix}-E1301", 4, None), (f"{prefix}-I1301", 5, 4)]


def test_iso_decimal_comma_then_arc_error_is_a_follow_up() -> None:
    tp = run("T1 M6\nS1000 F100 M3\nG0 X0 Y0 Z2\nG1 X10 Y5,5\nG2 X20 Y0 I5 J0\nM30\n", "sinumerik-iso")
    assert [(c, n, f) for c, n, f in follows(tp)][-1] == ("ISO-E1202", 5, 4)


def test_every_follow_up_rule_names_a_catalogued_code_and_is_documented() -> None:
    assert set(FOLLOW_UPS) <= set(CATALOGUE) and set(FOLLOW_UPS) >= REPEATED
    doc = (Path(__file__).parents[1] / "docs" / "diagnostics.md").read_text(encoding="utf-8")
    section = doc.split("## Follow-up errors", 1)[1]
    for code in FOLLOW_UPS:
        assert f"| {code} |" in section
