"""A corpus of graded submissions on the built-in exercises, milling and turning, each with the marking a teacher
gives it: equivalent solutions score 100; each typical mistake loses the criterion it concerns and only that (the
geometry in part: the share of the part's features it spoils), and the message names the cause with its line.

The programs are the exercises' references with a few words changed, so that every case states its mistake."""

from __future__ import annotations

import math
from dataclasses import dataclass

import pytest

from core.exercises import Exercise, builtin_exercises
from core.grading import CriterionResult, GradeResult, grade
from core.interpreter.state import RunSetup
from core.pipeline import run
from tests.conftest import codes

EXERCISES = builtin_exercises()


def edited(eid: str, *edits: tuple[str, str]) -> str:
    program = EXERCISES[eid].reference
    for old, new in edits:
        assert program.count(old) == 1, (eid, old)
        program = program.replace(old, new)
    return program


def line_of(program: str, start: str) -> int:
    """The number of the first line of `program` that starts with `start`."""
    return next(n for n, text in enumerate(program.splitlines(), 1) if text.strip().startswith(start))


def criterion(result: GradeResult, cid: str) -> CriterionResult:
    return next(c for c in result.criteria if c.id == cid)


def lost(result: GradeResult) -> set[str]:
    return {c.id for c in result.criteria if c.points < c.max_points}


# -- equivalent solutions: the same part, written another way -----------------------------------------------------

EQUIVALENT = [
    (
        "pal-05-g2-kreisbogen",
        "arc by R instead of I/J",
        (("N70 G2 X56.4 Y10 I-20 J6.4", "N70 G2 X56.4 Y10 R21"),),
    ),
    (
        "pal-05-g2-kreisbogen",
        "centre absolute IA/JA",
        (("N70 G2 X56.4 Y10 I-20 J6.4", "N70 G2 X56.4 Y10 IA50 JA30"),),
    ),
    ("pal-06-g3-kreisbogen", "arc by R", (("N70 G3 X70 Y23.6 I-6.4 J20", "N70 G3 X70 Y23.6 R21"),)),
    (
        "pal-02-g1-rn-radius",
        "the rounding written out",
        (("N60 G1 X70 Y10 RN20", "N60 G1 X50 Y10\nN65 G3 X70 Y30 R20"),),
    ),
    (
        "pal-03-g1-rn-fase",
        "the chamfer's points instead of RN-",
        (("N60 G1 X70 Y10 RN-15", "N60 G1 X55 Y10\nN65 G1 X70 Y25"),),
    ),
    (
        "pal-01-g1-gerade",
        "incremental",
        (("N60 G1 X70\nN70 G1 Y84", "N55 G91\nN60 G1 X84\nN70 G1 Y74\nN75 G90"),),
    ),
    (
        "pal-09-g23-l-nuten",
        "G29 loop instead of G23",
        (
            ("N110 G23 N40 N100 H2", "N105 P1=P1+1\nN110 G29 P1 O4 P2 N40"),
            ("N30 G0 X15 Y10 Z2", "N30 G0 X15 Y10 Z2\nN35 P1=0 P2=3"),
        ),
    ),
    (
        "pal-11-g29-schleife",
        "the loop written out",
        (
            (
                "N40 P12=0 P2=5\nN50 P12=P12+1\nN60 G29 P12 O3 P2 N200\nN70 G0 XI10\nN80 G1 Z-2\nN90 G0 Z2\nN190 G29 N50\n",
                "".join(
                    f"N{70 + 3 * i} G0 X{20 + 10 * i}\nN{71 + 3 * i} G1 Z-2\nN{72 + 3 * i} G0 Z2\n"
                    for i in range(5)
                ),
            ),
        ),
    ),
    ("iso-kreisboegen", "the first arc by I/J", (("N60 G03 X60 Y30 R20", "N60 G03 X60 Y30 I0 J20"),)),
    (
        "traub-01-srk-fase",
        "the chamfer's points instead of D",
        (("G1 X40 D2 E0.1", "G1 X36 E0.1\nG1 X40 Z-2"),),
    ),
    (
        "traub-02-uebersichtskontur",
        "the arc's centre by I, K instead of R",
        (("G2 X40 Z-25 R10", "G2 X40 Z-25 I10 K0"),),
    ),
    ("traub-04-geometriezug", "the cylinder incremental", (("G1 Z-60", "G1 W-25"),)),
]


@pytest.mark.parametrize("eid,what,edits", EQUIVALENT, ids=[f"{e}: {w}" for e, w, _ in EQUIVALENT])
def test_equivalent_solutions_score_100(eid: str, what: str, edits: tuple[tuple[str, str], ...]) -> None:
    result = grade(EXERCISES[eid], edited(eid, *edits))
    assert result.score == 100, [(c.id, c.message) for c in result.criteria if not c.passed]
    geometry = criterion(result, "geometry")
    assert geometry.status == "passed" and geometry.features and all(f.ok for f in geometry.features)


# -- typical mistakes ------------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Mistake:
    name: str
    exercise: str
    edits: tuple[tuple[str, str], ...]
    lost: frozenset[str]  # the criteria that lose points, and only these
    cause: str  # the code of the cause the first lost criterion names
    line: str  # the start of the submission's line that cause points to
    kept: tuple[int, int] | None = None  # geometry: features kept of all
    words: tuple[str, ...] = ()  # what the German message of that criterion says


MISTAKES = [
    Mistake(
        "G42 forgotten",
        "pal-01-g1-gerade",
        (("N40 G42 G0", "N40 G0"),),
        frozenset({"geometry", "compensation_off"}),
        "compensation_missing",
        "N40 G0 X-14 Y10",
        (1, 3),
        (
            "Die Fräserradiuskorrektur fehlt",
            "12,5 mm zu weit ins Werkstück",
            "seitlich 12,55 mm neben der Kontur",
        ),
    ),
    Mistake(
        "G41 forgotten and G3 for G2",
        "pal-05-g2-kreisbogen",
        (("N40 G41 G0", "N40 G0"), ("N70 G2", "N70 G3")),
        frozenset({"geometry", "compensation_off"}),
        "compensation_missing",
        "N40 G0 X70 Y84",
        (1, 4),
        (
            "(G41 in Zeile 5)",
            "Außerdem: Zeile 8: Der Kreisbogen läuft in die falsche Richtung – G3 statt G2",
            "Zu viel Material abgetragen: 5.088,4 mm³; Material stehen gelassen: 299,1 mm³",
        ),
    ),
    Mistake(
        "G41 for G42",
        "pal-01-g1-gerade",
        (("N40 G42 G0", "N40 G41 G0"),),
        frozenset({"geometry"}),
        "compensation_side",
        "N40 G41 G0",
        (1, 3),
        ("auf der falschen Seite der Kontur (G41 statt G42)",),
    ),
    Mistake(
        "G42 for G41",
        "pal-05-g2-kreisbogen",
        (("N40 G41 G0", "N40 G42 G0"),),
        frozenset({"geometry"}),
        "compensation_side",
        "N40 G42 G0",
        (1, 4),
        ("G42 statt G41",),
    ),
    Mistake(
        "G3 for G2",
        "pal-13-g41-aussenkontur",
        (("N70 G2", "N70 G3"),),
        frozenset({"geometry"}),
        "arc_direction",
        "N70 G3",
        (2, 4),
        ("G3 statt G2 (im Uhrzeigersinn)",),
    ),
    Mistake(
        "G02 for G03",
        "iso-kreisboegen",
        (("N60 G03", "N60 G02"),),
        frozenset({"geometry"}),
        "arc_direction",
        "N60 G02",
        (5, 6),
        ("G2 statt G3 (gegen den Uhrzeigersinn)",),
    ),
    Mistake(
        "arc end point off",
        "pal-05-g2-kreisbogen",
        (("N70 G2 X56.4 Y10 I-20 J6.4", "N70 G2 X56.4 Y11 R21"),),
        frozenset({"geometry"}),
        "arc_end",
        "N70 G2",
        (2, 4),
        ("Der Kreisbogen endet bei X56.4 Y11 statt bei X56.4 Y10",),
    ),
    Mistake(
        "arc radius off",
        "pal-05-g2-kreisbogen",
        (("N70 G2 X56.4 Y10 I-20 J6.4", "N70 G2 X56.4 Y10 R25"),),
        frozenset({"geometry"}),
        "arc_radius",
        "N70 G2",
        (3, 4),
        ("Radius R25 statt R21",),
    ),
    Mistake(
        "rounding RN5 for RN10",
        "pal-16-g47-g48",
        (("N60 G1 X50 RN10", "N60 G1 X50 RN5"),),
        frozenset({"geometry"}),
        "arc_radius",
        "N60 G1 X50 RN5",
        (5, 6),
        ("Rundung R5 statt R10",),
    ),
    Mistake(
        "depth 1 mm too deep",
        "pal-01-g1-gerade",
        (("N50 G0 Z-2", "N50 G0 Z-3"),),
        frozenset({"geometry"}),
        "depth",
        "N50 G0 Z-3",
        (2, 3),
        ("Tiefe Z-3 statt Z-2 – 1 mm zu tief", "Boden Z-2: 1 mm zu tief"),
    ),
    Mistake(
        "rounding RN20 left out",
        "pal-02-g1-rn-radius",
        (("N60 G1 X70 Y10 RN20", "N60 G1 X70 Y10"),),
        frozenset({"geometry"}),
        "element_missing",
        "N60 G1 X70 Y10",
        (3, 4),
        ("Es fehlt das Übergangselement Rundung R20",),
    ),
    Mistake(
        "one slot too few (G23 H1)",
        "pal-09-g23-l-nuten",
        (("H2", "H1"),),
        frozenset({"geometry"}),
        "element_missing",
        "N110 G23",
        (5, 7),
        ("Es fehlen 3 Konturelemente", "die Wiederholung in Zeile 12"),
    ),
    Mistake(
        "one plunge too few (G29)",
        "pal-11-g29-schleife",
        (("P2=5", "P2=4"),),
        frozenset({"geometry"}),
        "element_missing",
        "N60 G29",
        (5, 6),
        ("Es fehlt das Konturelement Eintauchen X60 Y35 Z-2",),
    ),
    Mistake(
        "one plunge too many (G29)",
        "pal-11-g29-schleife",
        (("P2=5", "P2=6"),),
        frozenset({"geometry"}),
        "element_extra",
        "N60 G29",
        (5, 6),
        ("Die Wiederholung läuft zu oft", "Eintauchen X70 Y35 Z-2 gehört nicht zur Kontur der Zeichnung"),
    ),
    Mistake(
        "G42 selected on the first contour element",
        "pal-01-g1-gerade",
        (
            ("N30 G0 X-25 Y-15 Z2\nN40 G42 G0 X-14 Y10", "N30 G0 X-14 Y10 Z2\nN40 G0 X-14 Y10"),
            ("N60 G1 X70", "N60 G42 G1 X70"),
        ),
        frozenset({"geometry"}),
        "approach",
        "N60 G42 G1 X70",
        (2, 3),
        ("Die Fräserradiuskorrektur wird ohne Anfahrbewegung angewählt",),
    ),
    Mistake(
        "G41 selected on the first contour element",
        "pal-05-g2-kreisbogen",
        (("N40 G41 G0 X70 Y84", "N40 G0 X70 Y84"), ("N60 G1 Y23.6", "N60 G41 G1 Y23.6")),
        frozenset({"geometry"}),
        "approach",
        "N60 G41 G1 Y23.6",
        (3, 4),
        ("ohne Anfahrbewegung",),
    ),
    Mistake(
        "M4 for a milling cutter",
        "pal-05-g2-kreisbogen",
        (("S1200 F150 M3", "S1200 F150 M4"),),
        frozenset({"technology"}),
        "spindle_direction",
        "N60 G1 Y23.6",
        None,
        ("Spindel M4 (Linkslauf) (gesetzt in Zeile 3) statt M3 (Rechtslauf) für T1",),
    ),
    Mistake(
        "feed F300 for F150",
        "pal-05-g2-kreisbogen",
        (("S1200 F150", "S1200 F300"),),
        frozenset({"technology"}),
        "feed",
        "N60 G1 Y23.6",
        None,
        ("F300 (gesetzt in Zeile 3) statt F150 für T1",),
    ),
    Mistake(
        "M30 missing",
        "pal-05-g2-kreisbogen",
        ((" M30", ""),),
        frozenset({"program_end"}),
        "program_end_missing",
        "N100 G0",
        None,
        ("M30 (Programmende) fehlt: das Programm endet in Zeile 11.",),
    ),
    Mistake(
        "Ø39 for Ø40",
        "traub-01-srk-fase",
        (("G1 X40 D2", "G1 X39 D2"),),
        frozenset({"geometry"}),
        "end_point",
        "G1 X39 D2",
        (1, 3),
        ("Ø39 statt Ø40", "Zu viel Material abgetragen: 1.898,8 mm³"),
    ),
    Mistake(
        "shoulder 1 mm short",
        "traub-01-srk-fase",
        (("G1 Z-30", "G1 Z-29"),),
        frozenset({"geometry"}),
        "end_point",
        "G1 Z-29",
        (2, 3),
        ("endet bei Z-29 statt bei Z-30", "liegt bei Z-29.75 statt Z-30.75"),
    ),
    Mistake(
        "chamfer D2 left out",
        "traub-01-srk-fase",
        (("G1 X40 D2 E0.1", "G1 X40"),),
        frozenset({"geometry"}),
        "element_missing",
        "G1 X40",
        (2, 3),
        ("Es fehlt das Übergangselement Fase X36 Z0 → X40 Z-2",),
    ),
    Mistake(
        "SRK forgotten",
        "traub-01-srk-fase",
        (("G46\n", ""),),
        frozenset({"geometry", "compensation_off"}),
        "compensation_missing",
        "G0 X30 Z3",
        (1, 3),
        ("ohne G46 fährt die theoretische Schneidenspitze",),
    ),
    Mistake(
        "G3 for G2",
        "traub-02-uebersichtskontur",
        (("G2 X40 Z-25 R10", "G3 X40 Z-25 R10"),),
        frozenset({"geometry"}),
        "arc_direction",
        "G3 X40 Z-25 R10",
        (5, 6),
        ("G3 statt G2",),
    ),
    Mistake(
        "arc R12 for R10",
        "traub-02-uebersichtskontur",
        (("G2 X40 Z-25 R10", "G2 X40 Z-25 R12"),),
        frozenset({"geometry"}),
        "arc_radius",
        "G2 X40 Z-25 R12",
        (5, 6),
        ("Radius R12 statt R10",),
    ),
    Mistake(
        "finishing with the roughing tool",
        "traub-02-uebersichtskontur",
        (("G96 V220 T0202", "G96 V220 T0101"),),
        frozenset({"geometry", "technology"}),
        "tool",
        "G96 V220 T0101",
        (4, 6),
        ("Werkzeug T1 (Schneidenradius 0,8 mm) statt T2 (Schneidenradius 0,4 mm)",),
    ),
    Mistake(
        "M3 for M4",
        "traub-01-srk-fase",
        (("T0101 M4", "T0101 M3"),),
        frozenset({"technology"}),
        "spindle_direction",
        "G1 Z0",
        None,
        ("Spindel M3 (Rechtslauf) (gesetzt in Zeile 3) statt M4 (Linkslauf)",),
    ),
    Mistake(
        "feed F0.3 for F0.2",
        "traub-01-srk-fase",
        (("F0.2", "F0.3"),),
        frozenset({"technology"}),
        "feed",
        "G1 Z0 F0.3",
        None,
        ("F0.3 statt F0.2 oder F0.1 mm pro Umdrehung für T1",),
    ),
    Mistake(
        "E0.1 left out: the G71's E0.12 cuts the chamfer",
        "traub-10-schruppen-g71-g88",
        (("G1 X30 D1.5 F0.15 E0.1", "G1 X30 D1.5 F0.15"),),
        frozenset({"technology"}),
        "feed",
        "G1 X30 D1.5 F0.15",
        None,
        ("Vorschub 0,12 mm/U statt F0.15 oder F0.1 für T5 – hier gilt E0.12 aus Zeile 7",),
    ),
    Mistake(
        "M30 missing",
        "traub-01-srk-fase",
        (("M30", ""),),
        frozenset({"program_end"}),
        "program_end_missing",
        "G0 X100 Z50",
        None,
    ),
]


@pytest.mark.parametrize("m", MISTAKES, ids=[f"{m.exercise}: {m.name}" for m in MISTAKES])
def test_a_typical_mistake_loses_its_criterion_and_names_its_cause(m: Mistake) -> None:
    program = edited(m.exercise, *m.edits)
    result = grade(EXERCISES[m.exercise], program)
    assert lost(result) == m.lost, [(c.id, c.message) for c in result.criteria if c.points < c.max_points]
    first = next(c for c in result.criteria if c.id in m.lost)
    assert first.cause is not None and first.cause.code == m.cause, [x.code for x in first.causes]
    assert first.cause.line == line_of(program, m.line), first.cause.message
    assert first.cause.line in first.lines
    for words in m.words:
        assert words in first.message, first.message
    assert f"Zeile {first.cause.line}" in first.message
    geometry = criterion(result, "geometry")
    if m.kept is not None:
        kept, total = m.kept
        assert geometry.features is not None and sum(f.ok for f in geometry.features) == kept
        assert len(geometry.features) == total
        assert geometry.points == math.floor(50 * kept / total + 0.5) and 0 < geometry.points < 50
        assert geometry.status == "partial" and geometry.to_json()["status"] == "partial"
        assert geometry.message.startswith(f"{kept} von {total} Formelementen maßhaltig.")
        assert geometry.message_en.startswith(f"{kept} of {total} features made to size.")
        assert "zu tief" not in geometry.message or m.cause == "depth"  # "zu tief" only for a depth
    else:
        assert geometry.passed


def test_the_messages_use_one_number_format() -> None:
    program = edited("pal-05-g2-kreisbogen", ("N40 G41 G0", "N40 G0"), ("N70 G2", "N70 G3"))
    geometry = criterion(grade(EXERCISES["pal-05-g2-kreisbogen"], program), "geometry")
    assert "5.088,4 mm³" in geometry.message and "5,088.4 mm³" in geometry.message_en
    assert "12,5 mm zu weit" in geometry.message and "12.5 mm too far" in geometry.message_en
    assert "2803.5" not in geometry.message and "5088.4" not in geometry.message


def test_one_number_format_for_quantities() -> None:
    from core.grading.numbers import mm, volume, word

    assert (volume(2803.5), volume(2803.5, "en")) == ("2.803,5 mm³", "2,803.5 mm³")
    assert (mm(1.95), mm(12.5), mm(2.0), mm(1.95, "en")) == ("1,95 mm", "12,5 mm", "2 mm", "1.95 mm")
    assert (word(56.4), word(-2.0), word(0.15)) == (
        "56.4",
        "-2",
        "0.15",
    )  # addresses as a program writes them


def test_the_docs_worked_example_of_a_lathe_diameter() -> None:
    # docs/exercises.md: traub-10 with Ø64 for Ø65 keeps 7 of its 10 features, 35 of 50 points
    geometry = criterion(
        grade(
            EXERCISES["traub-10-schruppen-g71-g88"],
            edited("traub-10-schruppen-g71-g88", ("G1 X65 R5", "G1 X64 R5")),
        ),
        "geometry",
    )
    assert geometry.features is not None and (
        sum(f.ok for f in geometry.features),
        len(geometry.features),
    ) == (7, 10)
    assert geometry.points == 35 and geometry.cause is not None and "Ø64 statt Ø65" in geometry.cause.message


def test_a_part_wrong_everywhere_scores_no_geometry_point() -> None:
    # the tool runs the contour 5 mm above the stock: nothing is machined
    program = edited("pal-01-g1-gerade", ("N50 G0 Z-2", "N50 G0 Z5"))
    geometry = criterion(grade(EXERCISES["pal-01-g1-gerade"], program), "geometry")
    assert (geometry.points, geometry.status) == (0, "failed")
    assert geometry.features is not None and not any(f.ok for f in geometry.features)
    assert geometry.to_json()["status"] == "failed"


def test_a_wrong_tool_from_the_magazine_costs_technology_and_the_slots_width() -> None:
    # the machine also holds T3, a Ø8 slot drill; the task prescribes T2 (Ø6) for the 6 mm slots
    ex = EXERCISES["pal-09-g23-l-nuten"]
    magazine = ex.model_copy(
        update={
            "tools": [
                *ex.tools,
                {
                    "number": 3,
                    "kind": "slot_drill",
                    "diameter": 8,
                    "cutting_length": 13,
                    "overall_length": 57,
                },
            ]
        }
    )
    assert isinstance(magazine, Exercise)
    program = ex.reference.replace("N10 T2 TC2 M6", "N10 T3 TC2 M6")
    result = grade(magazine, program)
    assert lost(result) == {"geometry", "technology"}
    technology = criterion(result, "technology")
    assert technology.cause is not None and technology.cause.code == "tool"
    assert "Werkzeug T3 ist in der Aufgabe nicht vorgesehen" in technology.message
    geometry = criterion(result, "geometry")
    assert geometry.cause is not None and (geometry.cause.code, geometry.cause.line) == ("tool", 2)
    assert "Werkzeug T3 (Ø8 mm) statt T2 (Ø6 mm)" in geometry.message


def test_the_syntax_criterion_speaks_of_syntax_and_program_errors() -> None:
    ex = EXERCISES["pal-05-g2-kreisbogen"]
    assert criterion(grade(ex, ex.reference), "syntax").message == "Keine Syntax- und Programmfehler."
    broken = criterion(grade(ex, ex.reference.replace("N70 G2 X56.4", "N70 G2 X56,4")), "syntax")
    assert broken.message.startswith("1 Syntax- oder Programmfehler, der in Zeile 8:")
    assert broken.cause is not None and broken.cause.code == "PAL-E010"


@pytest.mark.parametrize(
    "eid",
    [
        "pal-09-g23-l-nuten",
        "pal-11-g29-schleife",
        "pal-18-g66-spiegeln",
        "iso-kreisboegen",
        "beckhoff-fasen-radien",
        "traub-07-gewinde-g76",
    ],
)
def test_without_compensation_in_the_reference_the_criterion_passes_neutrally(eid: str) -> None:
    ex = EXERCISES[eid]
    c = criterion(grade(ex, ex.reference), "compensation_off")
    assert c.passed and c.message.startswith("Die Aufgabe verlangt keine")


def test_compensation_off_needs_the_compensation_selected_where_the_reference_uses_it() -> None:
    ex = EXERCISES["pal-13-g41-aussenkontur"]
    assert (
        criterion(grade(ex, ex.reference), "compensation_off").message
        == "Die Fräserradiuskorrektur ist angewählt und am Ende abgewählt (G40)."
    )
    never = criterion(grade(ex, ex.reference.replace("N40 G41 G1", "N40 G1")), "compensation_off")
    assert not never.passed and "nie angewählt (G41/G42 fehlt)" in never.message
    assert never.cause is not None and never.cause.code == "compensation_never_selected"
    left_on = criterion(grade(ex, ex.reference.replace("N90 G40 G1", "N90 G1")), "compensation_off")
    assert not left_on.passed and "G40 fehlt" in left_on.message


def test_spindle_direction_of_the_cutting_data_and_its_default() -> None:
    # the built-in exercises state it; an exercise without it takes the reference's direction
    assert all(d.spindle is not None for ex in EXERCISES.values() for d in ex.cutting_data)
    assert {d.spindle for d in EXERCISES["traub-01-srk-fase"].cutting_data} == {"M4"}
    assert {d.spindle for d in EXERCISES["traub-07-gewinde-g76"].cutting_data} == {"M3"}
    ex = EXERCISES["traub-01-srk-fase"]
    unstated = ex.model_copy(
        update={"cutting_data": [d.model_copy(update={"spindle": None}) for d in ex.cutting_data]}
    )
    assert not criterion(grade(unstated, ex.reference.replace("T0101 M4", "T0101 M3")), "technology").passed
    assert criterion(grade(unstated, ex.reference), "technology").passed


# -- the approach warning PAL-W222 -----------------------------------------------------------------------------------

MILLING = sorted(eid for eid, ex in EXERCISES.items() if not ex.lathe)
# the spec's figure programs for G41 and G42 (PAL-13, PAL-14 of the source document, M30 added)
FIGURES = {
    "PAL-13": "N10 T1 TC1 M6\nN20 F250 S2000 M3\nN30 G0 X-10 Y-50 Z2\nN40 G41 G1 X15 Y15\nN50 G1 Z-10\n"
    "N60 G1 X15 Y75\nN70 G2 X55 Y75 I20 J0\nN80 G1 X55 Y-15\nN90 G40 G1 X-10 Y-50 Z5\nN100 M30\n",
    "PAL-14": "N10 T1 TC1 M6\nN20 F250 S2000 M3\nN30 G0 X-10 Y-50 Z2\nN40 G42 G1 X15 Y-15\nN50 G1 Z-10\n"
    "N60 G1 X15 Y75\nN70 G2 X55 Y75 I20 J0\nN80 G1 X55 Y-15\nN90 G40 G1 X-10 Y-50 Z5\nN100 M30\n",
}


def warnings_of(eid: str, program: str) -> list[int]:
    ex = EXERCISES[eid]
    tp = run(program, ex.dialect, RunSetup(tools=ex.tool_table(), subprograms=tuple(ex.subprograms.items())))
    return [line for code, line in codes(tp) if code == "PAL-W222"]


@pytest.mark.parametrize("eid", MILLING)
def test_no_reference_warns_of_a_missing_approach(eid: str) -> None:
    assert warnings_of(eid, EXERCISES[eid].reference) == []


def test_no_seed_program_or_figure_warns_of_a_missing_approach() -> None:
    from pathlib import Path

    seeds = sorted((Path(__file__).parent / "seeds").glob("*.nc"))
    beckhoff = sorted((Path(__file__).parent / "seeds" / "beckhoff").glob("*.nc"))
    assert len(seeds) >= 10 and len(beckhoff) >= 5
    for path in seeds:
        assert not [d for d in run(path.read_text(encoding="utf-8")).diagnostics if d.code == "PAL-W222"], (
            path
        )
    for path in beckhoff:
        tp = run(path.read_text(encoding="utf-8"), "beckhoff")
        assert not [d for d in tp.diagnostics if d.code == "PAL-W222"], path
    for name, program in FIGURES.items():
        assert not [d for d in run(program).diagnostics if d.code == "PAL-W222"], name


APPROACH_MISSING = [
    (
        "G42 on the first element, the tool on the contour's line",
        "pal-01-g1-gerade",
        (("N40 G42 G0 X-14 Y10", "N40 G0 X-14 Y10"), ("N60 G1 X70", "N60 G42 G1 X70")),
        "N60",
    ),
    (
        "G42 alone in a block, then the contour",
        "pal-01-g1-gerade",
        (("N40 G42 G0 X-14 Y10", "N40 G0 X-14 Y10\nN45 G42"),),
        "N60",
    ),
    (
        "G42 with the infeed",
        "pal-01-g1-gerade",
        (("N40 G42 G0 X-14 Y10", "N40 G0 X-14 Y10"), ("N50 G0 Z-2", "N50 G42 G1 Z-2")),
        "N60",
    ),
    (
        "G41 on the first element, along the contour",
        "pal-05-g2-kreisbogen",
        (("N40 G41 G0 X70 Y84", "N40 G0 X70 Y84"), ("N60 G1 Y23.6", "N60 G41 G1 Y23.6")),
        "N60",
    ),
    (
        "G41 on the first element, collinear with the next",
        "pal-13-g41-aussenkontur",
        (("N40 G41 G1 X15 Y-15", "N40 G1 X15 Y-15"), ("N60 G1 X15 Y75", "N60 G41 G1 X15 Y75")),
        "N60",
    ),
    (
        "G41 on an arc",
        "pal-05-g2-kreisbogen",
        (("N40 G41 G0 X70 Y84", "N40 G0 X70 Y84"), ("N70 G2", "N70 G41 G2")),
        "N70",
    ),
]


@pytest.mark.parametrize("what,eid,edits,block", APPROACH_MISSING, ids=[w for w, _, _, _ in APPROACH_MISSING])
def test_the_compensation_selected_without_an_approach_warns_on_that_block(
    what: str, eid: str, edits: tuple[tuple[str, str], ...], block: str
) -> None:
    program = edited(eid, *edits)
    assert warnings_of(eid, program) == [line_of(program, block)]
    ex = EXERCISES[eid]
    tp = run(program, ex.dialect, RunSetup(tools=ex.tool_table()))
    d = next(x for x in tp.diagnostics if x.code == "PAL-W222")
    assert d.severity.value == "warning"
    assert d.message.startswith("Die Fräserradiuskorrektur wird ohne Anfahrbewegung angewählt: ")
    assert d.message_en.startswith("Cutter radius compensation is selected without an approach move: ")


@pytest.mark.parametrize(
    "edits",
    [
        (
            ("N40 G42 G0 X-14 Y10", "N40 G41 G0 X-14 Y10"),
        ),  # the wrong side is its own cause, not a missing approach
        (
            ("N30 G0 X-25 Y-15 Z2", "N30 G0 X-25 Y-2.5 Z2"),
        ),  # starting a cutter radius clear on the compensation side
        (("N40 G42 G0 X-14 Y10", "N40 G42 G45 X-14 Y10 D10"),),  # G45 approaches by itself
    ],
)
def test_approaches_that_do_not_warn(edits: tuple[tuple[str, str], ...]) -> None:
    assert warnings_of("pal-01-g1-gerade", edited("pal-01-g1-gerade", *edits)) == []
