"""The built-in exercises with PAL cycles (issue 30): each reference scores 100, mills its part to the nominal
volume within 0,5 %, has its drawing and task sheet; a typical mistake loses the criterion a teacher would take
points off for, and the find-the-mistakes program shows its four planted cycle errors at their lines."""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET

import numpy as np
import pytest

from core.drawing import part_drawing
from core.exercises import Exercise, builtin_exercises
from core.grading import GradeResult, execute, grade
from core.sheet import task_sheet_html

EXERCISES = builtin_exercises()
TAN59 = math.tan(math.radians(59))  # half the point angle of a 118° twist drill


def _exercise(eid: str) -> Exercise:
    return EXERCISES[eid]


def hole(*cones: tuple[float, float, float]) -> float:
    """The volume of one drilled hole made by several tools on one axis: each (radius, depth of the tip, tangent
    of half the point angle); at each radius the deepest tool counts."""
    r = np.linspace(0, max(c[0] for c in cones), 200_001)
    depth = np.zeros_like(r)
    for radius, tip, tan_half in cones:
        depth = np.maximum(depth, np.where(r <= radius, tip - r / tan_half, 0.0))
    return float(np.trapezoid(2 * math.pi * r * depth, r))


def rounded_rectangle(lp: float, bp: float, rn: float) -> float:
    return lp * bp - (4 - math.pi) * rn**2


def drill(diameter: float, tip: float) -> tuple[float, float, float]:
    return (diameter / 2, tip, TAN59)


def spot(diameter: float, tip: float) -> tuple[float, float, float]:
    return (diameter / 2, tip, 1.0)  # 90°: the cone's radius grows as fast as it rises


NOMINAL = {
    # G72 60 × 40 R8, 6 deep
    "pal-30-g72-rechtecktasche": rounded_rectangle(60, 40, 8) * 6,
    # G73 R20, 8 deep
    "pal-31-g73-kreistasche": math.pi * 20**2 * 8,
    # G74 50 × 10 (round ends included), 5 deep; G75 width 10 on R30 over 120°, 4 deep
    "pal-32-g74-g75-nuten": (40 * 10 + math.pi * 5**2) * 5 + (2 * math.pi / 3 * 30 * 10 + math.pi * 5**2) * 4,
    # 10 holes centred 4 deep and drilled Ø6,8 15 deep; 6 of them tapped M8 12 deep (the tap a Ø8 118° tool)
    "pal-33-g76-g77-bohrungen": 4 * hole(spot(10, 4), drill(6.8, 15))
    + 6 * hole(spot(10, 4), drill(6.8, 15), drill(8, 12)),
    # 100 × 80 stock less the spigot 90 × 70 R10, 5 deep; pocket 40 × 20 R5 8 deep; 4 holes Ø8 12 deep
    "pal-34-kontur-tasche-bohrungen": (100 * 80 - rounded_rectangle(90, 70, 10)) * 5
    + rounded_rectangle(40, 20, 5) * 8
    + 4 * hole(drill(8, 12)),
    # G72 40 × 30 R8 5 deep; G73 R12 6 deep; 2 holes centred 3 deep and drilled Ø8 12 deep
    "pal-35-zyklen-fehler": rounded_rectangle(40, 30, 8) * 5
    + math.pi * 12**2 * 6
    + 2 * hole(spot(10, 3), drill(8, 12)),
}
CYCLE_EXERCISES = sorted(NOMINAL)

# what each exercise teaches: the cycles and calls its reference uses
CYCLES = {
    "pal-30-g72-rechtecktasche": ("G72", "G79"),
    "pal-31-g73-kreistasche": ("G73", "G79"),
    "pal-32-g74-g75-nuten": ("G74", "G75", "G79"),
    "pal-33-g76-g77-bohrungen": ("G81", "G83", "G84", "G76", "G77"),
    "pal-34-kontur-tasche-bohrungen": ("G41", "G45", "G40", "G46", "G72", "G79", "G81", "G76"),
    "pal-35-zyklen-fehler": ("G72", "G73", "G79", "G81", "G82", "G76"),
}


def lost(result: GradeResult) -> dict[str, str | None]:
    """The criteria that lost points, with the code of their likeliest cause."""
    return {c.id: (c.cause.code if c.cause else None) for c in result.criteria if c.points < c.max_points}


def test_there_are_six_cycle_exercises_one_to_find_mistakes_in() -> None:
    assert set(CYCLE_EXERCISES) <= set(EXERCISES)
    assert [_exercise(e).kind for e in CYCLE_EXERCISES].count("fix") == 1
    for eid, codes in CYCLES.items():
        words = _exercise(eid).reference.split()
        assert all(code in words for code in codes), (eid, [c for c in codes if c not in words])


@pytest.mark.parametrize("eid", CYCLE_EXERCISES)
def test_reference_scores_100_without_any_diagnostic(eid: str) -> None:
    ex = _exercise(eid)
    result = grade(ex, ex.reference)
    assert (result.score, result.max_score) == (100, 100), lost(result)
    assert list(result.diagnostics) == []


@pytest.mark.parametrize("eid", CYCLE_EXERCISES)
def test_the_reference_removes_its_nominal_volume(eid: str) -> None:
    machined = execute(_exercise(eid), _exercise(eid).reference)
    assert machined.sim.events == []
    assert machined.sim.removed_volume == pytest.approx(NOMINAL[eid], rel=0.005)


@pytest.mark.parametrize("eid", CYCLE_EXERCISES)
@pytest.mark.parametrize("lang", ["de", "en"])
def test_drawing_and_task_sheet_render(eid: str, lang: str) -> None:
    ex = _exercise(eid)
    svg = ET.fromstring(part_drawing(ex, lang))
    texts = " ".join(t.text or "" for t in svg.iter("{http://www.w3.org/2000/svg}text"))
    size = " × ".join(f"{hi - lo:g}" for lo, hi in zip(ex.stock.min, ex.stock.max, strict=True))
    assert size in texts  # the blank in the title block
    assert "Schnitt A–A" in texts or "Section A–A" in texts  # the depths are shown in a section
    sheet = task_sheet_html([ex], lang)
    assert ex.title.get(lang) in sheet
    assert "<svg" in sheet or "data:image/svg" in sheet  # the drawing on the sheet


# -- typical mistakes ------------------------------------------------------------------------------------------------

MISTAKES = [
    # (exercise, reference text, mistake, criteria lost with their cause)
    (
        "pal-30-g72-rechtecktasche",
        "ZI-6",
        "ZI6",  # the depth's sign: the pocket is not milled at all
        {"geometry": "element_missing", "syntax": "PAL-E603"},
    ),
    ("pal-30-g72-rechtecktasche", "LP60 BP40", "LP50 BP30", {"geometry": "end_point"}),  # pocket too small
    ("pal-30-g72-rechtecktasche", "RN8", "RN5", {"geometry": "end_point"}),  # corner radius too small
    ("pal-31-g73-kreistasche", "R20", "R15", {"geometry": "arc_radius"}),  # pocket too small
    ("pal-31-g73-kreistasche", "ZI-8", "ZI-10", {"geometry": "depth"}),  # 2 mm too deep
    ("pal-32-g74-g75-nuten", "LP50", "LP40", {"geometry": "end_point"}),  # slot too short
    ("pal-32-g74-g75-nuten", "AO120", "AO90", {"geometry": "arc_end"}),  # arc slot ends too early
    (
        "pal-33-g76-g77-bohrungen",
        "N190 G77 IA60 JA50 R20",
        "N190 G77 IA60 JA50 R25",  # threads on Ø50 for Ø40
        {"geometry": "end_point"},
    ),
    (
        "pal-33-g76-g77-bohrungen",
        "N130 G77 IA60 JA50 R20",
        "N130 G77 IA60 JA50 R40",  # diameter for radius
        {"geometry": "end_point"},
    ),
    (
        "pal-33-g76-g77-bohrungen",
        "G84 ZI-12 F1.25 M3",
        "G84 ZI-12 F1.25",  # no spindle for the tap: the
        {"geometry": "element_missing", "syntax": "PAL-E102"},
    ),  # definition is refused, its calls tap nothing
    (
        "pal-33-g76-g77-bohrungen",
        "N160 S400 M3",
        "N160 M3",  # the drill's speed left on for the tap
        {"technology": "speed"},
    ),
    (
        "pal-33-g76-g77-bohrungen",
        "G84 ZI-12 F1.25 M3",
        "G84 ZI-12 F1.25 M4",  # a left-hand thread
        {"technology": "spindle_direction"},
    ),
    (
        "pal-34-kontur-tasche-bohrungen",
        "G41 G45",
        "G42 G45",  # compensation on the wrong side
        {"geometry": "compensation_side", "syntax": "PAL-E214"},
    ),
    (
        "pal-34-kontur-tasche-bohrungen",
        "G72 ZI-8",
        "G72 ZI-4",
        {"geometry": "element_missing"},
    ),  # pocket too shallow
    ("pal-34-kontur-tasche-bohrungen", "N240 G76 X20 Y60", "N240 G76 X20 Y50", {"geometry": "end_point"}),
    (
        "pal-35-zyklen-fehler",
        "N10 T2",
        "N10 T1",  # one of the four mistakes left: the cutter too large
        {"geometry": "tool", "technology": "tool", "syntax": "PAL-E602"},
    ),
    (
        "pal-35-zyklen-fehler",
        "G82 ZI-12",
        "G82 ZI12",  # another one left: the depth's sign, the holes not drilled
        {"geometry": "element_missing", "syntax": "PAL-E603"},
    ),
]


@pytest.mark.parametrize("eid,old,new,expected", MISTAKES, ids=[f"{e}-{n}" for e, _, n, _ in MISTAKES])
def test_a_typical_mistake_loses_the_right_criterion(
    eid: str, old: str, new: str, expected: dict[str, str | None]
) -> None:
    ex = _exercise(eid)
    assert ex.reference.count(old) == 1
    result = grade(ex, ex.reference.replace(old, new))
    assert result.score < 100
    assert lost(result) == expected


def test_the_pocket_is_one_feature_of_the_part() -> None:
    # its rings and levels are the cycle's path, not features of their own: a pocket too small or with too small
    # corners loses the pocket, a pocket 2 mm too deep its pocket and its floor
    ex = _exercise("pal-30-g72-rechtecktasche")
    for mistake in (ex.reference.replace("LP60 BP40", "LP50 BP30"), ex.reference.replace("RN8", "RN5")):
        geometry = next(c for c in grade(ex, mistake).criteria if c.id == "geometry")
        assert geometry.status == "partial" and "Rechtecktasche (Zeile" in geometry.message
        assert "Fase" not in geometry.message and "Bahn" not in geometry.message
    deeper = grade(
        _exercise("pal-31-g73-kreistasche"),
        _exercise("pal-31-g73-kreistasche").reference.replace("ZI-8", "ZI-10"),
    )
    assert deeper.score <= 90


def test_a_hole_pattern_on_the_wrong_pitch_circle_loses_those_holes() -> None:
    ex = _exercise("pal-33-g76-g77-bohrungen")
    result = grade(ex, ex.reference.replace("N190 G77 IA60 JA50 R20", "N190 G77 IA60 JA50 R25"))
    geometry = next(c for c in result.criteria if c.id == "geometry")
    assert geometry.status == "partial" and "Bohrung" in geometry.message


def test_the_tap_reverses_out_of_the_thread_and_keeps_the_technology_points() -> None:
    ex = _exercise("pal-33-g76-g77-bohrungen")
    machined = execute(ex, ex.reference)
    taps = [
        m for m in machined.toolpath.moves if m.cycle is not None and m.cycle[0] == "G84" and m.kind == "feed"
    ]
    assert {(m.end[2] > m.start[2], m.spindle_direction) for m in taps} == {(False, "cw"), (True, "ccw")}
    assert taps and all(m.feed == pytest.approx(500) for m in taps)  # n × P = 400 × 1,25
    technology = next(c for c in grade(ex, ex.reference).criteria if c.id == "technology")
    assert technology.passed


# -- the find-the-mistakes exercise ----------------------------------------------------------------------------------


def test_the_start_program_shows_the_four_planted_cycle_errors_at_their_lines() -> None:
    ex = _exercise("pal-35-zyklen-fehler")
    result = grade(ex, ex.start_program)
    found = {(d.code, d.span.line) for d in result.diagnostics}
    assert found == {
        ("PAL-E601", 5),  # the pocket called before it is defined
        ("PAL-E602", 8),  # the Ø25 cutter in the Ø24 circular pocket
        ("PAL-E102", 13),  # V forgotten in the centring cycle
        ("PAL-E601", 14),  # … so its call finds no cycle (a follow-up of line 13)
        ("PAL-E603", 19),  # ZI12 for ZI-12
        ("PAL-E601", 20),  # … a follow-up of line 19
    }
    assert {d.span.line: d.follows_from for d in result.diagnostics if d.code == "PAL-E601"} == {
        5: None,
        14: 13,
        20: 19,
    }
    assert result.score < 70
    assert lost(result).keys() == {"geometry", "syntax"}
    assert len(ex.start_program.splitlines()) == len(ex.reference.splitlines())
