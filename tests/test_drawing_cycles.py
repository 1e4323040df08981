"""Drawings of parts made with PAL cycles (issue 30, point 4): the drawing dimensions what the cycle makes, read
from the cycle's own words — a pocket's LP × BP, its corner radius and depth, a circular pocket's Ø, a slot's
length, width and round ends, an arc slot's radius and angles, holes by count, diameter and depth, a pitch circle
with its diameter and angles, threads as M8 — not the tool centre's rings as slots, and the title block names a
tool as the exercise does."""

from __future__ import annotations

import re
import xml.etree.ElementTree as ET
from functools import cache

from core.drawing import part_drawing
from core.drawing.cycles import thread_name
from core.exercises import Exercise, builtin_exercises

SVG = "{http://www.w3.org/2000/svg}"


@cache
def _exercise(eid: str) -> Exercise:
    return builtin_exercises()[eid]


@cache
def _texts(eid: str, lang: str = "de") -> list[str]:
    return [t.text or "" for t in ET.fromstring(part_drawing(_exercise(eid), lang)).iter(f"{SVG}text")]


def _svg_texts(exercise: Exercise, lang: str = "de") -> list[str]:
    return [t.text or "" for t in ET.fromstring(part_drawing(exercise, lang)).iter(f"{SVG}text")]


def _kind(eid: str, kind: str) -> list[str]:
    return [
        t.text or ""
        for t in ET.fromstring(part_drawing(_exercise(eid))).iter(f"{SVG}text")
        if t.get("data-kind") == kind
    ]


def test_rectangular_pocket_is_dimensioned_by_its_words_not_as_slots() -> None:
    texts = _texts("pal-30-g72-rechtecktasche")
    assert "60 × 40, Tiefe 6" in texts
    assert "R8" in texts
    assert not [t for t in texts if "Nut" in t], texts
    # the pocket's centre X50 Y40 (the call's position) is dimensioned like any other point
    assert "50" in _kind("pal-30-g72-rechtecktasche", "x")
    assert "40" in _kind("pal-30-g72-rechtecktasche", "y")


def test_circular_pocket_has_its_diameter_and_depth() -> None:
    texts = _texts("pal-31-g73-kreistasche")
    assert "Ø40, Tiefe 8" in texts
    assert not [t for t in texts if "Nut" in t or re.fullmatch(r"R[\d,]+", t)], texts


def test_slot_and_arc_slot() -> None:
    texts = _texts("pal-32-g74-g75-nuten")
    assert "50 × 10, Tiefe 5" in texts  # G74 LP50 BP10 ZI-5
    assert "R5" in texts  # its round ends
    assert "R30" in texts  # G75: the centre line's radius RP30
    assert "Nut 10 breit, Tiefe 4" in texts
    assert {"30°", "120°"} <= set(_kind("pal-32-g74-g75-nuten", "angle"))  # AN30, AO120
    # the arc slot's centre X60 Y30
    assert "60" in _kind("pal-32-g74-g75-nuten", "x") and "30" in _kind("pal-32-g74-g75-nuten", "y")


def test_hole_pattern_pitch_circle_and_threads() -> None:
    eid = "pal-33-g76-g77-bohrungen"
    texts = _texts(eid)
    assert "TK Ø40" in texts
    assert "6× M8, Gewindetiefe 12" in texts
    assert "4× Ø6,8, Tiefe 15" in texts
    assert {"30°", "60°"} <= set(_kind(eid, "angle"))  # the first hole at AN30, then every AI60
    assert "25" in _kind(eid, "spacing")  # G76 D25
    # the centring (spot drill Ø10) is not dimensioned apart, the threads are not "6× Ø8, Tiefe 12"
    assert sorted(_kind(eid, "depth")) == ["4× Ø6,8, Tiefe 15", "6× M8, Gewindetiefe 12"]
    # ordinates, not a coordinate table, and no computed hole position in brackets
    assert "Koordinaten" not in texts
    assert not [t for t in _kind(eid, "x") + _kind(eid, "y") if t.startswith("(")]
    assert "60" in _kind(eid, "x") and "50" in _kind(eid, "y")  # the pitch circle's centre


def test_title_block_names_the_tool_as_the_exercise_does() -> None:
    joined = " ".join(_texts("pal-33-g76-g77-bohrungen"))
    assert "Gewindebohrer M8 × 1,25" in joined
    assert "Spiralbohrer Ø8" not in joined
    assert "Spiralbohrer Ø6,8" in joined  # a tool without its own name: kind and diameter, German comma


def test_english_drawing() -> None:
    texts = _texts("pal-33-g76-g77-bohrungen", "en")
    assert "6× M8, thread depth 12" in texts
    assert "4× Ø6.8, depth 15" in texts
    assert "PCD Ø40" in texts


def test_combined_part_pocket_and_holes() -> None:
    texts = _texts("pal-34-kontur-tasche-bohrungen")
    assert "40 × 20, Tiefe 8" in texts and "R5" in texts
    assert "4× Ø8, Tiefe 12" in texts
    assert not [t for t in texts if "Nut" in t], texts


def test_rotated_pocket_says_its_angle() -> None:
    base = _exercise("pal-30-g72-rechtecktasche")
    turned = base.model_copy(
        update={"reference": base.reference.replace("G79 X50 Y40 Z0", "G79 X50 Y40 Z0 AR30")}
    )
    texts = _svg_texts(turned)
    assert "60 × 40, 30°, Tiefe 6" in texts
    assert not [t for t in texts if "Nut" in t], texts


def test_pocket_of_another_size_is_drawn_as_programmed() -> None:
    """The numbers come from the program's words: change LP, BP and RN and the drawing follows (a drawing that
    printed the exercise's fixed numbers would fail here)."""
    base = _exercise("pal-30-g72-rechtecktasche")
    other = base.model_copy(update={"reference": base.reference.replace("LP60 BP40 RN8", "LP50 BP30 RN6")})
    texts = _svg_texts(other)
    assert "50 × 30, Tiefe 6" in texts and "R6" in texts and "R8" not in texts


def test_thread_size() -> None:
    assert thread_name("Gewindebohrer M8 × 1,25", 8.0) == "M8"
    assert thread_name("", 10.0) == "M10"
    assert thread_name("", 8.0, 1.25) == "M8"
    assert thread_name("", 8.0, 1.0) == "M8 × 1"  # a fine thread
    assert thread_name("Gewindebohrer M6", 5.0, 1.0, "en") == "M6"


def test_section_shows_the_pockets_and_holes_depths() -> None:
    """The section runs where it meets the most depths: through the pockets, not only beside them through the
    holes; a drilled hole it cuts has its depth (the drill's tip) as a Z ordinate."""
    assert {"-5", "-6"} <= set(_kind("pal-35-zyklen-fehler", "z"))  # G72 ZI-5 and G73 ZI-6
    assert {"-5", "-8"} <= set(_kind("pal-34-kontur-tasche-bohrungen", "z"))  # the contour and the pocket
    assert "-15" in _kind("pal-33-g76-g77-bohrungen", "z")  # G83 ZI-15


def test_pocket_from_its_corner_and_a_call_without_position() -> None:
    """EP1: the call's point is the pocket's corner, the drawing dimensions its centre; a call without X and Y
    runs where the tool stood."""
    base = _exercise("pal-30-g72-rechtecktasche")
    corner = base.model_copy(
        update={
            "reference": base.reference.replace("LP60", "EP1 LP60").replace(
                "G79 X50 Y40 Z0", "G79 X10 Y10 Z0"
            )
        }
    )
    texts = _svg_texts(corner)
    assert "60 × 40, Tiefe 6" in texts
    root = ET.fromstring(part_drawing(corner))
    xs = [t.text for t in root.iter(f"{SVG}text") if t.get("data-kind") == "x"]
    ys = [t.text for t in root.iter(f"{SVG}text") if t.get("data-kind") == "y"]
    assert "40" in xs and "30" in ys  # the centre: X10 + 60 / 2, Y10 + 40 / 2
    here = base.model_copy(update={"reference": base.reference.replace("G79 X50 Y40 Z0", "G79 Z0")})
    assert "60 × 40, Tiefe 6" in _svg_texts(here)


def test_bore_milled_on_a_helix_has_the_bore_diameter() -> None:
    """G87 mills a bore with a smaller cutter: the drawing gives the bore's Ø (2 × R), not the cutter's."""
    base = _exercise("pal-31-g73-kreistasche")
    bore = base.model_copy(
        update={"reference": base.reference.replace("G73 ZI-8 R20 D4 V2 W5", "G87 ZI-8 R15 D2 V2 W5")}
    )
    texts = _svg_texts(bore)
    assert "Ø30, Tiefe 8" in texts
    assert not [t for t in texts if "Ø12," in t or "Nut" in t], texts
