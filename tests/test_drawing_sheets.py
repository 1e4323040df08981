"""Every built-in exercise's drawing as a sheet a trainee reads (issue 28, "Drawings"): milling and turning, German
and English. No text lies on another (the boxes of all SVG texts, estimated from font size and text length), no
"null"/"undefined"/"NaN", no number with more decimals than the drawing's precision (a computed one only in
brackets, as an auxiliary dimension), the part's outer size in the view, every chamfer labelled, a long title
wrapped in the title block instead of cut; and the numbers the issue names: R21 (not R20,999), the 25° cone with
its computed end in brackets, the front chamfer of the turned shaft, 80 × 70 in the view."""

from __future__ import annotations

import math
import re
import xml.etree.ElementTree as ET
from functools import cache

import pytest

from core.drawing import part_drawing
from core.drawing.frame import Numbers, written_decimals
from core.exercises import Exercise, builtin_exercises

SVG = "{http://www.w3.org/2000/svg}"
BUILTIN = builtin_exercises()  # (read once: each reading parses every exercise file)
EXERCISES = sorted(BUILTIN)
MILLING = [e for e in EXERCISES if not BUILTIN[e].lathe]
TURNING = [e for e in EXERCISES if BUILTIN[e].lathe]
NUMBER = re.compile(r"\d+(?:[.,]\d+)?")


def _exercise(eid: str) -> Exercise:
    return BUILTIN[eid]


@cache
def _svg(eid: str, lang: str = "de") -> str:
    return part_drawing(_exercise(eid), lang)


def _texts(eid: str, lang: str = "de") -> list[ET.Element]:
    return list(ET.fromstring(_svg(eid, lang)).iter(f"{SVG}text"))


def _printed(eid: str, kind: str, lang: str = "de") -> list[str]:
    return [t.text or "" for t in _texts(eid, lang) if t.get("data-kind") == kind]


def _box(t: ET.Element) -> tuple[float, float, float, float]:
    """A text's box on the sheet (mm): its length from the font size (DejaVu Sans: about 0.58 of the height per
    character, bold 0.66), from 0.72 of the height above the baseline to 0.1 below, turned as the text is."""
    x, y, size = float(t.get("x", 0)), float(t.get("y", 0)), float(t.get("font-size", 3.5))
    width = len(t.text or "") * (0.66 if t.get("font-weight") == "bold" else 0.58) * size
    x0 = {"start": 0.0, "middle": -width / 2, "end": -width}[t.get("text-anchor", "start")]
    turn = re.match(r"rotate\(([-\d.]+)", t.get("transform") or "")
    a = math.radians(float(turn.group(1))) if turn else 0.0
    c, s = math.cos(a), math.sin(a)
    corners = [(x0, -0.72 * size), (x0 + width, -0.72 * size), (x0, 0.1 * size), (x0 + width, 0.1 * size)]
    xs = [x + u * c - v * s for u, v in corners]
    ys = [y + u * s + v * c for u, v in corners]
    return (min(xs), min(ys), max(xs), max(ys))


@pytest.mark.parametrize("lang", ["de", "en"])
@pytest.mark.parametrize("eid", EXERCISES)
def test_no_text_lies_on_another(eid: str, lang: str) -> None:
    texts = [(t.text or "", _box(t)) for t in _texts(eid, lang)]
    for i, (a, p) in enumerate(texts):
        for b, q in texts[i + 1 :]:
            overlap = min(p[2], q[2]) - max(p[0], q[0]) > 0.1 and min(p[3], q[3]) - max(p[1], q[1]) > 0.1
            assert not overlap, (a, p, b, q)


@pytest.mark.parametrize("lang", ["de", "en"])
@pytest.mark.parametrize("eid", EXERCISES)
def test_no_placeholder_and_no_number_beyond_the_drawings_precision(eid: str, lang: str) -> None:
    """No "null", "undefined", "NaN" or "None" anywhere; every dimension's number has at most the drawing's
    decimals (two, three where the program writes three): a value computed from the program's words is rounded
    (R20,999 → R21), and a length the program does not state is in brackets."""
    svg = _svg(eid, lang)
    assert not re.search(r"\b(null|undefined|NaN|None|nan|inf)\b", svg), eid
    ex = _exercise(eid)
    numbers = Numbers.of(lang, ex.reference, *ex.subprograms.values())
    assert numbers.decimals == 2  # no built-in program writes three decimals
    for t in _texts(eid, lang):
        if t.get("class") != "dim":
            continue
        text = t.text or ""
        for found in NUMBER.findall(text):
            decimals = found.replace(",", ".").split(".")[1] if re.search(r"[.,]", found) else ""
            assert len(decimals) <= numbers.decimals, (text, t.get("data-kind"))
        assert not re.search(r"\d\.\d" if lang == "de" else r"\d,\d", text), (
            text
        )  # the decimal comma in German
        if text.startswith(
            "("
        ):  # an auxiliary dimension: a coordinate the program computes, not one it states
            assert not numbers.stated(float(t.get("data-value", "nan"))), text


@pytest.mark.parametrize("eid", MILLING)
def test_the_blanks_size_is_dimensioned_in_the_view(eid: str) -> None:
    """The width above the top view and the height beside it, as the blank's: not only in the title block."""
    st = _exercise(eid).stock.stock()
    size = [t for t in _texts(eid) if t.get("data-kind") == "size"]
    assert sorted(float(t.get("data-value", "nan")) for t in size) == sorted([st.x1 - st.x0, st.y1 - st.y0])
    assert [t.text for t in size] == [f"{st.x1 - st.x0:g}", f"{st.y1 - st.y0:g}"]
    assert "rotate(-90" in (size[1].get("transform") or "")  # the height reads along its line


@pytest.mark.parametrize("eid", TURNING)
def test_the_turned_parts_outer_diameter_is_dimensioned(eid: str) -> None:
    """The largest diameter (a thread's nominal one, or the bar's where it stays as it was) is in the view."""
    ex = _exercise(eid)
    assert ex.blank is not None
    shown = {float(t.get("data-value", "nan")) for t in _texts(eid) if t.get("data-kind") in ("d", "thread")}
    assert ex.blank.diameter in shown


@pytest.mark.parametrize("eid", EXERCISES)
def test_the_title_block_wraps_a_long_title(eid: str) -> None:
    """The title is in the title block word for word, in one to three lines, never cut with "…"."""
    ex = _exercise(eid)
    for lang in ("de", "en"):
        texts = [t.text or "" for t in _texts(eid, lang)]
        start = texts.index(LABELS_TITLE[lang]) + 1
        lines = texts[start : start + 3]
        title = ex.title.get(lang)
        assert not any("…" in line for line in lines)
        joined = ""
        for line in lines:
            joined = f"{joined} {line}".strip()
            if joined == title:
                break
        assert joined == title, (lines, title)


LABELS_TITLE = {"de": "Benennung", "en": "Title"}


# ---- the numbers of the issue ---------------------------------------------------------------------------------


@pytest.mark.parametrize(
    "eid",
    ["pal-05-g2-kreisbogen", "pal-06-g3-kreisbogen", "ergaenzen-01-kreisbogen", "fehler-01-kreisendpunkt"],
)
def test_the_arc_is_R21_as_the_task_says(eid: str) -> None:
    """G2 X56.4 Y10 I-20 J6.4 from X70 Y23.6: the interpreter's radius is 20.999 (the program's end point is
    rounded); the task and the seed say R21, and so does the drawing, at its precision."""
    assert "R21" in _exercise(eid).task.get("de") or eid.startswith(("ergaenzen", "fehler"))
    assert _printed(eid, "r") == ["R21"]
    assert "20,999" not in _svg(eid) and "20.999" not in _svg(eid, "en")
    assert {"50", "56,4", "70"} <= set(_printed(eid, "x")) and {"10", "23,6", "30"} <= set(_printed(eid, "y"))


def test_the_falling_cone_by_its_angle_with_its_end_as_an_auxiliary_dimension() -> None:
    """TX-30: G1 X38 A205 from Ø65 at Z-45. The drawing gives the cone's angle (25°) and its diameters; its end
    Z-73,951 is computed from the angle: only in brackets, at the drawing's precision (DIN 406-10)."""
    eid = "traub-10-schruppen-g71-g88"
    assert _printed(eid, "angle") == ["25°"]
    assert {"Ø65", "Ø38"} <= set(_printed(eid, "d"))
    lengths = _printed(eid, "z")
    assert "(73,95)" in lengths and not any("73,951" in t for t in _printed(eid, "z"))
    assert "45" in lengths and "120" in lengths


def test_the_front_chamfer_of_the_turned_shaft_is_labelled() -> None:
    """TX-30 starts the finishing contour in front of the face (G0 X26 Z0.5) and programs the chamfer D1.5 onto
    Ø30 from there: on the part (faced at Z0) it is the chamfer 1 × 45° from the face to Z-1. It is labelled and
    dimensioned to its corner at the face, so the running dimensions have no "1" next to the "0" at Z0; the
    chamfer D2 at Ø100 is labelled too."""
    eid = "traub-10-schruppen-g71-g88"
    assert sorted(_printed(eid, "chamfer")) == ["1×45°", "2×45°"]
    assert "1" not in _printed(eid, "z")
    front = [t for t in _texts(eid) if t.get("data-kind") == "chamfer" and t.text == "1×45°"]
    zero = next(t for t in _texts(eid) if t.get("data-kind") == "z" and t.text == "0")
    assert abs(float(front[0].get("x", 0)) - float(zero.get("x", 0))) < 15  # at the face, not somewhere else


@pytest.mark.parametrize("eid", TURNING)
def test_every_chamfer_of_a_turned_part_is_labelled(eid: str) -> None:
    """Every 45° chamfer on the part (between a face, or the front face, and a cylinder) has its callout."""
    from core.drawing.turned_features import turned_part

    part = turned_part(_exercise(eid))
    legs = sorted(f"{leg:g}×45°".replace(".", ",") for _, leg in part.chamfers)
    assert sorted(_printed(eid, "chamfer")) == legs


def test_80_by_70_in_the_view_of_the_arc_exercise() -> None:
    eid = "pal-05-g2-kreisbogen"
    assert _printed(eid, "size") == ["80", "70"]
    root = ET.fromstring(_svg(eid))
    width = next(t for t in root.iter(f"{SVG}text") if t.get("data-kind") == "size")
    title_block_top = 210 - 10 - 34
    assert float(width.get("y", 0)) < title_block_top - 50  # above the top view, far from the title block


def test_a_rounded_corner_is_dimensioned_to_its_corner() -> None:
    """G1 X50 RN10 then G1 Y50 AS85 (PAL-15): the corner X50 Y10 and R10, not the tangent points X40,837 and
    Y19,128; the line's angle 85°; where it leaves the blank (X53,4995, computed from the angle) only in brackets."""
    eid = "pal-15-g45-g46"
    assert _printed(eid, "x") == ["0", "50", "(53,5)"] and _printed(eid, "y") == ["0", "10", "50"]
    assert _printed(eid, "r") == ["R10"] and _printed(eid, "angle") == ["85°"]
    assert _printed("pal-02-g1-rn-radius", "x") == ["0", "70"]  # G1 X70 Y10 RN20: the corner, and R20
    assert _printed("pal-03-g1-rn-fase", "x") == ["0", "70"] and _printed("pal-03-g1-rn-fase", "chamfer") == [
        "15×45°"
    ]


def test_beckhoff_chamfers_by_their_programmed_words() -> None:
    """#CHR=20 is the chamfer's leg: "20×45°"; #CHF=35 its length along the chamfer: the length 35 on a
    dimension line parallel to it and 45° (not the leg 24,749 the interpreter computes)."""
    eid = "beckhoff-fasen-radien"
    chamfers = _printed(eid, "chamfer")
    assert sorted(chamfers) == ["20×45°", "35"]
    assert "24,749" not in _svg(eid) and "75,251" not in _svg(eid)
    assert set(_printed(eid, "x")) == {"-10", "0", "40", "200"} and set(_printed(eid, "y")) == {
        "-10",
        "0",
        "100",
    }


def test_holes_by_their_centres_and_a_callout() -> None:
    """PAL-11 sinks five recesses with the slot drill Ø6 (a loop of plunges): their centres X20…X60 on Y35 and
    "5× Ø6, Tiefe 2", not a coordinate table of the workpiece zero alone."""
    eid = "pal-11-g29-schleife"
    assert _printed(eid, "x") == ["0", "20", "30", "40", "50", "60"] and _printed(eid, "y") == ["0", "35"]
    assert _printed(eid, "depth") == ["5× Ø6, Tiefe 2"] and _printed(eid, "depth", "en") == ["5× Ø6, depth 2"]
    assert "Koordinaten" not in _svg(eid)
    assert "-2" in _printed(eid, "z")


def test_the_drawings_precision_comes_from_the_programs_words() -> None:
    assert written_decimals("N10 G1 X23.6 Y10 F0.15 ; X1.2345\n(Z0.125)") == 1  # feeds and comments not
    assert written_decimals("G1 X12.345 Z-3") == 3 and written_decimals("G71 P50 Q60 I0.5 K0.05 D4") == 2
    numbers = Numbers.of("de", "G1 X12.5 Z-3")
    assert numbers.decimals == 2 and numbers.text(20.999) == "21" and numbers.text(73.951) == "73,95"
    assert (
        numbers.dimension(45.0) == "45" and numbers.dimension(73.9511) == "(73,95)" and numbers.stated(12.5)
    )
    assert Numbers.of("en", "G1 X1.125").text(1.12549) == "1.125"
