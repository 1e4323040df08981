"""Issue 12, part 5: the grader judges the technology of the moves that cut, and says what it means."""

from __future__ import annotations

import pytest

from core.exercises import builtin_exercises
from core.grading import CriterionResult, grade
from core.pipeline import run
from tests.conftest import codes

EXERCISES = builtin_exercises()
READY = "N1 T1 TC1 M6\nN2 S1200 F150 M3\n"  # T1: end mill Ø25


def criterion(eid: str, program: str, cid: str) -> CriterionResult:
    result = grade(EXERCISES[eid], program)
    return next(c for c in result.criteria if c.id == cid)


def swap(eid: str, old: str, new: str) -> str:
    program = EXERCISES[eid].reference
    assert old in program
    return program.replace(old, new)


def test_examiner_plunge_feed_in_the_air_keeps_the_technology_points() -> None:
    program = swap("pal-16-g47-g48", "N50 G42 G47 X0 Y10 R12.5", "N50 G42 G47 X0 Y10 R12.5 Z-3 W2 E100")
    result = grade(EXERCISES["pal-16-g47-g48"], program)
    assert result.score == 100, [(c.id, c.message) for c in result.criteria if not c.passed]


def test_feed_move_in_the_air_with_another_feed_keeps_the_points() -> None:
    # N45 feeds at F500 beside the blank (tool Ø20 at X−30…−40, the blank starts at X0)
    program = swap(
        "pal-16-g47-g48", "N50 G42 G47 X0 Y10 R12.5", "N45 G1 X-40 Y-20 F500\nN50 G42 G47 X0 Y10 R12.5 F150"
    )
    assert criterion("pal-16-g47-g48", program, "technology").passed


def test_a_wrong_feed_that_cuts_still_costs_the_points() -> None:
    program = swap("pal-16-g47-g48", "N60 G1 X50 RN10", "N60 G1 X50 RN10 F100")
    tech = criterion("pal-16-g47-g48", program, "technology")
    assert not tech.passed and tech.points == 0
    assert "F100 statt F150" in tech.message and tech.lines == (7,)


def test_a_plunge_feed_into_the_blank_still_costs_the_points() -> None:
    # the approach starts inside the blank's outline: the plunge at E100 cuts
    program = swap(
        "pal-16-g47-g48",
        "N30 G0 X-30 Y-20 Z2\nN40 G0 Z-3\nN50 G42 G47 X0 Y10 R12.5",
        "N30 G0 X20 Y30 Z2\nN50 G1 Z-3 E100 F100\nN55 G1 X21 F150\nN56 G0 Z2\nN57 G0 X-30 Y-20\nN58 G0 Z-3\n"
        "N59 G42 G47 X0 Y10 R12.5",
    )
    tech = criterion("pal-16-g47-g48", program, "technology")
    assert not tech.passed and "F100 statt F150" in tech.message


def test_no_tool_loaded_is_said_in_words() -> None:
    program = swap("pal-16-g47-g48", "N10 T4 TC4 M6\n", "")
    tech = criterion("pal-16-g47-g48", program, "technology")
    assert not tech.passed
    assert "kein Werkzeug eingewechselt" in tech.message and "None" not in tech.message
    assert "no tool loaded" in tech.message_en and "None" not in tech.message_en


@pytest.mark.parametrize(
    "radius,de,en",
    [
        ("12.5", "nicht größer als der Fräserradius 12.5 mm", "not larger than the cutter radius 12.5 mm"),
        ("10", "kleiner als der Fräserradius 12.5 mm", "smaller than the cutter radius 12.5 mm"),
    ],
)
def test_inside_arc_message_equal_is_not_smaller(radius: str, de: str, en: str) -> None:
    tp = run(
        READY
        + f"G0 X0 Y-20 Z0\nG41 G1 X0 Y0\nG3 X{float(radius) * 2:g} Y0 R{radius}\nG1 Y-20\nG40 G0 X50\nM30"
    )
    assert ("PAL-E214", 5) in codes(tp)
    d = next(x for x in tp.diagnostics if x.code == "PAL-E214")
    assert de in d.message and en in d.message_en
    assert ("nicht größer" in d.message) == (radius == "12.5")
