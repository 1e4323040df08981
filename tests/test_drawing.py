"""The dimensioned drawing: the numbers of the seed drawings, read back from the SVG's text elements."""

from __future__ import annotations

import re
import xml.etree.ElementTree as ET
from functools import cache
from pathlib import Path

import pytest

from core.cli import main
from core.drawing import part_drawing
from core.exercises import Exercise, builtin_exercises
from core.grading import execute

SVG = "{http://www.w3.org/2000/svg}"


@cache
def _exercises() -> dict[str, Exercise]:
    return builtin_exercises()


@cache
def _dims(exercise_id: str, lang: str = "de") -> dict[str, list[str]]:
    """The dimension texts of a drawing by kind (x, y, z, r, chamfer, angle, depth), as printed."""
    root = ET.fromstring(part_drawing(_exercises()[exercise_id], lang))
    out: dict[str, list[str]] = {}
    for t in root.iter(f"{SVG}text"):
        if t.get("class") == "dim":
            out.setdefault(t.get("data-kind", ""), []).append(t.text or "")
    return out


def _values(exercise_id: str, kind: str) -> set[float]:
    root = ET.fromstring(part_drawing(_exercises()[exercise_id]))
    return {
        round(float(t.get("data-value", "nan")), 3)
        for t in root.iter(f"{SVG}text")
        if t.get("class") == "dim" and t.get("data-kind") == kind
    }


def test_outer_contour_with_arc_pal13() -> None:
    d = _dims("pal-13-g41-aussenkontur")
    assert {"15", "35", "55"} <= set(d["x"])
    assert "75" in d["y"]
    assert "R20" in d["r"]
    assert any("Tiefe 10" in t for t in d["depth"])
    assert "-10" in d["z"] and "0" in d["z"] and "-20" in d["z"]
    # the approach point below the blank (Y-15) is no dimension of the part
    assert "-15" not in d["y"]


def test_inner_pocket_pal14_has_its_corners_and_no_plunge_point() -> None:
    d = _dims("pal-14-g42-innenkontur")
    assert {"20", "60"} <= set(d["x"]) and {"20", "50"} <= set(d["y"])
    assert "35" not in d["y"]  # the plunge point in the middle of the pocket is not dimensioned
    assert any(t.endswith("R10") for t in d["r"])  # the cutter leaves its radius in the four corners
    assert any("Tiefe 5" in t for t in d["depth"])
    assert "-5" in d["z"]


def test_g23_slots_pal09() -> None:
    d = _dims("pal-09-g23-l-nuten")
    assert {"15", "30", "45", "60"} <= set(d["x"])
    assert {"10", "20", "30", "40", "50", "60"} <= set(d["y"])
    assert d["depth"] == ["3× Nut 6 breit, Tiefe 2"]
    assert "-2" in d["z"]


def test_chamfer_and_decimal_comma() -> None:
    assert "15×45°" in _dims("pal-03-g1-rn-fase")["chamfer"]
    d = _dims("pal-05-g2-kreisbogen")
    assert "23,6" in d["y"] and "56,4" in d["x"]
    assert "23.6" in _dims("pal-05-g2-kreisbogen", "en")["y"]


def test_english_labels() -> None:
    d = _dims("pal-13-g41-aussenkontur", "en")
    assert any("depth 10" in t for t in d["depth"])
    assert "Draufsicht" not in part_drawing(_exercises()["pal-13-g41-aussenkontur"], "en")


@pytest.mark.parametrize("exercise_id", sorted(builtin_exercises()))
def test_every_number_is_the_programs_own(exercise_id: str) -> None:
    """Every X and Y the drawing prints is a programmed coordinate (contour point or arc centre) of the
    reference or the workpiece zero — never a number read off pixels."""
    exercise = _exercises()[exercise_id]
    moves = execute(exercise, exercise.reference).toolpath.moves
    # the numbers written in the program (the corner X50 Y10 of G1 X50 RN10 is no move's end) and the moves'
    written = {round(float(v), 3) for v in re.findall(r"(?<=[XY])-?\d+(?:\.\d+)?", exercise.reference)}
    programmed: dict[int, set[float]] = {0: {0.0} | written, 1: {0.0} | written}
    for m in moves:
        for p in (m.programmed_end or m.end, m.start, m.center or m.end):
            programmed[0].add(round(p[0], 3))
            programmed[1].add(round(p[1], 3))
    assert _values(exercise_id, "x") <= programmed[0]
    assert _values(exercise_id, "y") <= programmed[1]
    root = ET.fromstring(part_drawing(exercise))
    assert root.tag == f"{SVG}svg" and "nan" not in part_drawing(exercise).lower()


def test_cli_writes_the_svg(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "part.svg"
    assert main(["drawing", "pal-13-g41-aussenkontur", "--out", str(out)]) == 0
    assert "R20" in out.read_text(encoding="utf-8")
    assert main(["drawing", "no-such-exercise"]) == 2
    assert "Unbekannte Aufgabe" in capsys.readouterr().err
