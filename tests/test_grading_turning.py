"""Turning exercises and their grading: the lathe format (blank, insert tools, V or S, F per revolution), every
built-in turning reference scores 100, typical mistakes cost the geometry criterion with the line named, the
technology criterion on the feed per revolution, the volumes of a turned part, the drawing's title."""

from __future__ import annotations

import math
import re

import pytest

from core.drawing import part_drawing
from core.exercises import ExerciseError, builtin_exercises, parse_exercise
from core.grading import grade
from core.grading.turning import execute_turning, turned_deviation

EXERCISES = builtin_exercises()
TURNING = sorted(eid for eid, ex in EXERCISES.items() if ex.dialect == "traub-tx8d")


def lost(result: object) -> dict[str, str]:
    return {c.id: c.message for c in result.criteria if not c.passed}  # type: ignore[attr-defined]


def criterion(result: object, cid: str) -> object:
    return next(c for c in result.criteria if c.id == cid)  # type: ignore[attr-defined]


def test_the_built_in_set_has_the_turning_examples_of_every_kind() -> None:
    assert len(TURNING) >= 8
    assert {EXERCISES[e].kind for e in TURNING} == {"write", "complete", "fix"}
    sources = " ".join(EXERCISES[e].source for e in TURNING)
    for seed in ("TX-17", "TX-21", "TX-27", "TX-30", "TX-32", "TX-33", "TX-40", "TX-43"):
        assert seed in sources, seed
    for eid in TURNING:
        ex = EXERCISES[eid]
        assert ex.blank is not None and ex.task.de and ex.task.en and ex.title.en
        assert f"Ø{ex.blank.diameter:g}" in ex.task.de  # the task states the blank


# each example of the manual the issue names: the exercise that teaches it and the words its reference must use
MANUAL_EXAMPLES = {
    "TX-17": ("traub-02-uebersichtskontur", ("G2 ", "G3 ")),
    "TX-21/TX-25": ("traub-04-geometriezug", ("G1 A180", "A135")),
    "TX-27": ("traub-01-srk-fase", ("G46",)),
    "TX-30": ("traub-10-schruppen-g71-g88", ("G88", "G71 P50 Q60", "G1 X38 A205", "E0.12")),
    "TX-31": ("traub-11-innen-g71-g89", ("G89", "G71 P51 Q61", "U0.3 A150")),
    "TX-32": ("traub-05-planschruppen-g72", ("G88", "G72 P70 Q80")),
    "TX-33": ("traub-06-g72-unterprogramm", ("G72 A520", "G22 A520", "O520")),
    "TX-40": ("traub-07-gewinde-g76", ("G76",)),
    "TX-43/TX-45": ("traub-08-bohren-unterprogramm", ("G 22 A 8000", "O8000")),
}


@pytest.mark.parametrize("seed", MANUAL_EXAMPLES)
def test_every_named_example_of_the_manual_has_its_exercise(seed: str) -> None:
    eid, words = MANUAL_EXAMPLES[seed]
    ex = EXERCISES[eid]
    assert ex.dialect == "traub-tx8d" and seed.split("/")[0] in ex.source
    for word in words:
        assert word in ex.reference, word


def test_the_inner_contour_exercise_turns_a_tube_from_inside() -> None:
    # TX-31: the bore is widened by the inside tools (P4), the outside stays the blank's Ø140
    ex = EXERCISES["traub-11-innen-g71-g89"]
    assert ex.blank is not None and ex.blank.inner_diameter == 30
    part = execute_turning(ex, ex.reference).sim.profile
    k = int((-50.0 - part.z0) / part.dz)
    assert 2 * part.inner[k] == pytest.approx(60.0, abs=0.02) and 2 * part.outer[k] == pytest.approx(140.0)
    k = int((-63.5 - part.z0) / part.dz)  # the undercut under the Ø60 bore
    assert 2 * part.inner[k] == pytest.approx(60.6, abs=0.05)
    # without the undercut's block the bore keeps Ø60 there: material left in the undercut, named on the line before
    program = "\n".join(line for line in ex.reference.splitlines() if line != "G1 U0.3 A150 F0.08")
    geo = criterion(grade(ex, program), "geometry")
    assert geo.status == "partial" and "Material stehen gelassen" in geo.message  # type: ignore[attr-defined]
    assert "Bohrung Ø60.6 (Z-62.6 … Z-65): Ø60 statt Ø60.6 (0,3 mm zu wenig abgetragen)" in geo.message  # type: ignore[attr-defined]
    assert geo.cause.line == program.splitlines().index("G1 Z-62") + 1  # type: ignore[attr-defined]


def test_the_falling_cone_is_roughed_with_g88_and_left_with_g89() -> None:
    ex = EXERCISES["traub-10-schruppen-g71-g88"]
    head, contour = ex.reference.split("G0 X150 Z50\n", 1)
    roughing = head + "G0 X150 Z50\nM30\n" + contour  # the program ends before the finishing
    with_g88 = execute_turning(ex, roughing).sim.profile
    with_g89 = execute_turning(ex, roughing.replace("G88", "G89")).sim.profile
    k = int((-60.0 - with_g88.z0) / with_g88.dz)  # on the cone, between Ø65 at Z−45 and Ø38 at Z−73.95
    cone = 65 - 2 * (60 - 45) * math.tan(math.radians(25))
    assert 0 < 2 * with_g88.outer[k] - cone < 1.0  # within the allowance I0.5
    assert 2 * with_g89.outer[k] > 65  # G89: the cone is left at the level of the last pass above Ø65


@pytest.mark.parametrize("eid", TURNING)
def test_turning_reference_scores_100(eid: str) -> None:
    ex = EXERCISES[eid]
    result = grade(ex, ex.reference)
    assert (result.score, result.max_score) == (100, 100), lost(result)
    turned = execute_turning(ex, ex.reference)
    assert turned.sim.removed_volume > 10  # the reference really turns the blank


@pytest.mark.parametrize("eid", [e for e in TURNING if EXERCISES[e].kind != "write"])
def test_turning_start_programs_do_not_score_full_marks(eid: str) -> None:
    ex = EXERCISES[eid]
    assert grade(ex, ex.start_program).score < 100


def test_a_wrong_diameter_costs_its_features_and_names_the_block() -> None:
    ex = EXERCISES["traub-01-srk-fase"]
    program = ex.reference.replace("G1 X40 D2", "G1 X39 D2")
    result = grade(ex, program)
    geo = criterion(result, "geometry")
    # the part's features: the chamfer, the Ø40 and the shoulder; the Ø39 spoils the chamfer and the Ø40
    assert geo.status == "partial" and (geo.points, geo.max_points) == (17, 50)  # type: ignore[attr-defined]
    assert [(f.name, f.ok) for f in geo.features] == [  # type: ignore[attr-defined]
        ("Ø40 (Z-2 … Z-30.75)", False),
        ("Kegel/Fase Ø36 → Ø40 (Z0 … Z-2)", False),
        ("Planfläche Z-30.75 (Ø40.9 → Ø44)", True),
    ]
    line = program.splitlines().index("G1 X39 D2 E0.1") + 1
    assert geo.cause.code == "end_point" and geo.cause.line == line  # type: ignore[attr-defined]
    assert f"Ursache: Zeile {line}: Ø39 statt Ø40" in geo.message  # type: ignore[attr-defined]
    assert "Ø40 (Z-2 … Z-30.75): Ø39 statt Ø40 (0,5 mm zu viel abgetragen)" in geo.message  # type: ignore[attr-defined]
    assert "Zu viel Material abgetragen: 1.898,8 mm³" in geo.message  # type: ignore[attr-defined]
    assert "Too much material removed: 1,898.8 mm³" in geo.message_en  # type: ignore[attr-defined]
    cylinder = program.splitlines().index("G1 Z-30") + 1  # the cut along the too small diameter
    assert geo.lines == (line, cylinder)  # type: ignore[attr-defined]
    assert result.score == 67


# a diameter programmed 1 mm too small (0.6 mm for the thread's root) in each built-in exercise, and the block
# that then cuts the surface where the part deviates most
WRONG_DIAMETER = {
    "traub-01-srk-fase": ("G1 X40 D2", "G1 X39 D2", "G1 Z-30"),
    "traub-02-uebersichtskontur": ("G1 X20 Z0 F0.15", "G1 X19 Z0 F0.15", "G1 Z-15"),
    "traub-03-schruppen-g71-fehler": ("G1 X20 Z0 F0.15", "G1 X19 Z0 F0.15", "G1 Z-15"),
    "traub-04-geometriezug": ("G1 X50 A135", "G1 X49 A135", "G1 Z-60"),
    "traub-05-planschruppen-g72": ("G1 X60 R2 F0.15", "G1 X59 R2 F0.15", "G1 X59 R2 F0.15"),
    "traub-06-g72-unterprogramm": ("G1 X60 R2 F0.15", "G1 X59 R2 F0.15", "G1 X59 R2 F0.15"),
    "traub-07-gewinde-g76": ("G76 X33.1", "G76 X32.5", "G76 X32.5 Z-29 K0.92 H8 F1.5"),
    "traub-09-srk-fehler": ("G1 X40 D2", "G1 X39 D2", "G1 Z-30"),
    "traub-10-schruppen-g71-g88": ("G1 X65 R5", "G1 X64 R5", "G1 Z-45"),
    "traub-11-innen-g71-g89": ("G1 X60\n", "G1 X61\n", "G1 Z-65 R0.6"),
}


@pytest.mark.parametrize("eid", sorted(WRONG_DIAMETER))
def test_a_wrong_diameter_costs_the_geometry_of_every_exercise(eid: str) -> None:
    ex = EXERCISES[eid]
    was, wrong, cutter = WRONG_DIAMETER[eid]
    assert ex.reference.count(was) == 1
    program = ex.reference.replace(was, wrong)
    geo = criterion(grade(ex, program), "geometry")
    assert not geo.passed and geo.points < geo.max_points and "Zu viel Material abgetragen" in geo.message  # type: ignore[attr-defined]
    assert any(not f.ok for f in geo.features) and geo.points < 50  # type: ignore[attr-defined]
    lines = [program.splitlines()[n - 1] for n in geo.lines]  # type: ignore[attr-defined]
    assert (
        wrong.strip() in lines[0] and cutter in lines
    )  # the changed block first, and the block that cut there
    if geo.cause is not None:  # type: ignore[attr-defined]  (G76's thread is a cycle: no contour to compare)
        assert program.splitlines()[geo.cause.line - 1].startswith(wrong.strip())  # type: ignore[attr-defined]


@pytest.mark.parametrize("eid", [e for e in TURNING if "G46" in EXERCISES[e].reference])
def test_srk_off_costs_the_geometry_of_every_exercise(eid: str) -> None:
    ex = EXERCISES[eid]
    geo = criterion(grade(ex, re.sub(r"\bG46\b", "", ex.reference)), "geometry")
    assert not geo.passed and geo.lines  # type: ignore[attr-defined]


def test_srk_off_leaves_material_and_names_the_cause() -> None:
    ex = EXERCISES["traub-01-srk-fase"]
    program = "\n".join(line for line in ex.reference.splitlines() if line.strip() != "G46")
    result = grade(ex, program)
    geo = criterion(result, "geometry")
    assert geo.status == "partial" and "Material stehen gelassen" in geo.message  # type: ignore[attr-defined]
    assert geo.cause.code == "compensation_missing" and "ohne G46" in geo.cause.message  # type: ignore[attr-defined]
    # the cylinder Ø40 is right without SRK (the tip follows it); the chamfer and the shoulder are not
    assert [f.ok for f in geo.features] == [True, False, False]  # type: ignore[attr-defined]
    assert geo.lines and program.splitlines()[geo.lines[-1] - 1].startswith("G1")  # type: ignore[attr-defined]
    assert not criterion(result, "compensation_off").passed  # type: ignore[attr-defined]
    # the chamfer without compensation stays too small: material left on it as well
    chamfer = execute_turning(ex, program).sim.profile
    ref = execute_turning(ex, ex.reference).sim.profile
    k = int((-1.0 - ref.z0) / ref.dz)
    assert chamfer.outer[k] - ref.outer[k] > 0.2


def test_the_fix_exercise_of_the_srk_is_that_mistake() -> None:
    ex = EXERCISES["traub-09-srk-fehler"]
    result = grade(ex, ex.start_program)
    assert not criterion(result, "geometry").passed  # type: ignore[attr-defined]
    assert grade(ex, ex.start_program.replace("G0 X30 Z3 M8", "G46\nG0 X30 Z3 M8")).score == 100


def test_technology_checks_the_feed_per_revolution() -> None:
    ex = EXERCISES["traub-01-srk-fase"]
    per_minute = ex.reference.replace("G95", "G94").replace("F0.2", "F200").replace("E0.1", "E100")
    tech = criterion(grade(ex, per_minute), "technology")
    assert not tech.passed and "mm/min (G94)" in tech.message and "F0.2 mm pro Umdrehung" in tech.message  # type: ignore[attr-defined]
    line = per_minute.splitlines().index("G1 Z0 F200") + 1
    assert tech.lines == (line,)  # type: ignore[attr-defined]
    too_fast = criterion(grade(ex, ex.reference.replace("F0.2", "F0.3")), "technology")
    assert not too_fast.passed and "F0.3 statt F0.2 oder F0.1" in too_fast.message  # type: ignore[attr-defined]
    within = criterion(grade(ex, ex.reference.replace("F0.2", "F0.21")), "technology")
    assert within.passed  # type: ignore[attr-defined]


def test_technology_checks_the_cutting_speed_under_g96() -> None:
    ex = EXERCISES["traub-04-geometriezug"]
    result = grade(ex, ex.reference.replace("G96 V220", "G96 V300"))
    tech = criterion(result, "technology")
    assert not tech.passed and "V220" in tech.message and "T2" in tech.message  # type: ignore[attr-defined]
    assert criterion(result, "geometry").passed  # type: ignore[attr-defined]


SIMPLE = """format: 1
id: drehen-zylinder
title: {de: Zylinder}
task: {de: "Stange Ø40 × 60, Zapfen Ø30 × 20"}
dialect: traub-tx8d
blank: {diameter: 40, length: 60, chuck_length: 20}
tools: [{number: 1, kind: turning, diameter: 0.4, nose_radius: 0.2, quadrant: 1, insert: C}]
cutting_data: [{tool: 1, speed: 1000, feed: 0.2}]
resolution: 0.05
reference: |
  G95
  G97 S1000 T0101 M4
  G0 X35 Z2
  G1 Z-20 F0.2
  G0 X42 Z-19
  G0 Z2
  G0 X30
  G1 Z-20
  G0 X42 Z-19
  G0 X100 Z50
  M30
"""


def test_volumes_of_a_simple_turned_part_through_the_grader() -> None:
    ex = parse_exercise(SIMPLE)
    turned = execute_turning(ex, ex.reference)
    expected = math.pi * (20**2 - 15**2) * 20  # Ø40 → Ø30 over 20 mm
    assert turned.sim.removed_volume == pytest.approx(expected, rel=0.005)
    assert grade(ex, ex.reference).score == 100
    smaller = ex.reference.replace("G0 X30\n", "G0 X28\n")
    geo = criterion(grade(ex, smaller), "geometry")
    over = german(geo.message.split("abgetragen: ")[1].split(" mm³")[0])  # type: ignore[attr-defined]
    assert over == pytest.approx(math.pi * (15**2 - 14**2) * 20, rel=0.02)
    assert "2 mm" not in geo.message and "Ø28 statt Ø30 (1 mm zu viel abgetragen)" in geo.message  # radial  # type: ignore[attr-defined]
    bigger = ex.reference.replace("G0 X30\n", "G0 X32\n")
    geo = criterion(grade(ex, bigger), "geometry")
    left = german(geo.message.split("gelassen: ")[1].split(" mm³")[0])  # type: ignore[attr-defined]
    assert left == pytest.approx(math.pi * (16**2 - 15**2) * 20, rel=0.02)


def german(text: str) -> float:
    """A German number of the grader's texts ("1.808,5") as a float."""
    assert "," in text or "." not in text, text
    return float(text.replace(".", "").replace(",", "."))


def test_turned_deviation_marks_the_samples_for_the_view() -> None:
    ex = parse_exercise(SIMPLE)
    dev = turned_deviation(ex, ex.reference.replace("G0 X30\n", "G0 X28\n"))
    zs = dev.part.zs[dev.over_outer > 0]
    assert zs.min() == pytest.approx(-20, abs=0.2) and zs.max() == pytest.approx(0, abs=0.1)
    assert float(dev.over_outer.max()) == pytest.approx(0.95, abs=0.01)  # 1 mm radially, less the band
    assert not dev.left_outer.any() and not dev.over_inner.any()


def test_lathe_safety_criterion_names_the_rapid_into_the_bar() -> None:
    ex = parse_exercise(SIMPLE)
    program = ex.reference.replace("G1 Z-20 F0.2", "G0 Z-20")
    safety = criterion(grade(ex, program), "safety")
    assert not safety.passed and "Eilgang ins Material" in safety.message  # type: ignore[attr-defined]
    assert safety.lines[0] == 4 and safety.message.startswith("Zeile 4:")  # type: ignore[attr-defined]


def test_the_turning_format_and_its_mistakes() -> None:
    ex = parse_exercise(SIMPLE)
    assert ex.lathe and ex.stock.min == (-20.0, -20.0, -60.0) and ex.stock.max == (20.0, 20.0, 0.0)
    with pytest.raises(ExerciseError) as err:
        parse_exercise(SIMPLE.replace("blank: {diameter: 40, length: 60, chuck_length: 20}\n", ""))
    assert [p["field"] for p in err.value.problems] == ["blank"]
    with pytest.raises(ExerciseError) as err:
        parse_exercise(SIMPLE.replace("length: 60,", "length: 60, inner_diameter: 45,"))
    assert [p["field"] for p in err.value.problems] == ["blank"]
    with pytest.raises(ExerciseError) as err:
        parse_exercise(SIMPLE.replace("speed: 1000", "speed: 1000, cutting_speed: 200"))
    assert "genau eines" in err.value.message
    milling = EXERCISES["pal-01-g1-gerade"].model_dump(mode="json")
    with pytest.raises(Exception, match="blank"):
        type(EXERCISES["pal-01-g1-gerade"]).model_validate(
            {**milling, "blank": {"diameter": 40, "length": 60}}
        )


@pytest.mark.parametrize(
    "lang,note", [("de", "Zeichnung für Drehteile folgt"), ("en", "drawing of turned parts to follow")]
)
def test_the_drawing_of_a_turning_exercise_is_titled_and_no_placeholder(lang: str, note: str) -> None:
    ex = EXERCISES["traub-01-srk-fase"]
    svg = part_drawing(ex, lang)  # the drawing itself: tests/test_drawing_lathe.py
    assert svg.startswith("<") and note not in svg and "Ø44 × 80" in svg and ex.title.get(lang) in svg


def test_lathe_syntax_criterion_names_the_first_error() -> None:
    ex = parse_exercise(SIMPLE)
    program = ex.reference.replace("G1 Z-20 F0.2", "G1 Z-20 F0.2 Y5")  # a lathe has no Y
    syntax = criterion(grade(ex, program), "syntax")
    assert not syntax.passed and syntax.lines[0] == 4  # type: ignore[attr-defined]
    assert "Zeile 4" in syntax.message and "»Y«" in syntax.message and "line 4" in syntax.message_en  # type: ignore[attr-defined]
    assert criterion(grade(ex, ex.reference), "syntax").passed  # type: ignore[attr-defined]


def test_lathe_safety_criterion_counts_every_turning_event() -> None:
    # the spindle never switched on (no M4): the cuts run at zero speed, SIM-E006 on the first cutting line
    ex = parse_exercise(SIMPLE)
    safety = criterion(grade(ex, ex.reference.replace("T0101 M4", "T0101")), "safety")
    assert not safety.passed and safety.lines[0] == 4 and "stehender Spindel" in safety.message  # type: ignore[attr-defined]
    # a straight retract from the end of each pass is none of them (the reference lifts to X42 at Z−19)
    assert criterion(grade(ex, ex.reference), "safety").passed  # type: ignore[attr-defined]
