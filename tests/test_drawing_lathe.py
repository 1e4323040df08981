"""The drawing of a turned part (core/drawing/turned.py): the numbers read back from the SVG's dimension texts
against the reference programs', the callouts (chamfer, radius, groove, thread), no two texts on top of each
other, the task sheet's PDF, and the half-section picture the page shows while the 3D view is off.

A PNG of one drawing and of one picture are saved next to the browser tests' screenshots
(PALTRAINER_SCREENSHOTS, else tests/browser/screenshots/) to look at."""

from __future__ import annotations

import base64
import math
import os
import re
import shutil
import subprocess
import xml.etree.ElementTree as ET
from functools import cache
from pathlib import Path

import numpy as np
import pytest

from core.cli import main
from core.drawing import part_drawing
from core.drawing import turned_picture as tp
from core.exercises import Exercise, builtin_exercises, parse_exercise
from core.grading.turning import execute_turning

SVG = "{http://www.w3.org/2000/svg}"
SHOTS = Path(os.environ.get("PALTRAINER_SCREENSHOTS") or Path(__file__).parent / "browser" / "screenshots")
TURNING = sorted(eid for eid, ex in builtin_exercises().items() if ex.lathe)

# a pin Ø36 with a chamfer at the face and a groove 3 wide on Ø30 at Z-20 (a grooving insert B3 from Z-20 on)
GROOVE = """format: 1
id: drehen-einstich
title: {de: Zapfen mit Einstich und Fase, en: pin with groove and chamfer}
task: {de: "Stange Ø40 × 60, Zapfen Ø36 × 40 mit Fase 1 × 45° und Einstich 3 breit auf Ø30 bei Z-20"}
dialect: traub-tx8d
blank: {diameter: 40, length: 60, chuck_length: 20}
tools:
  - {number: 1, kind: turning, diameter: 0.8, nose_radius: 0.4, quadrant: 1, insert: C}
  - {number: 2, kind: turning, diameter: 0.4, nose_radius: 0.2, quadrant: 1, insert: groove, width: 3}
cutting_data: [{tool: 1, speed: 1000, feed: 0.2}, {tool: 2, speed: 600, feed: 0.05}]
resolution: 0.05
reference: |
  G95
  G97 S1000 T0101 M4
  G46
  G0 X30 Z2 M8
  G1 Z0 F0.2
  G1 X36 D1
  G1 Z-40
  G1 X42
  G40
  G0 X100 Z50
  G97 S600 T0202 M4
  G0 X38 Z-20
  G1 X30 F0.05
  G0 X38
  G0 X100 Z50 M9
  M30
"""


@cache
def exercise(eid: str) -> Exercise:
    return parse_exercise(GROOVE) if eid == "drehen-einstich" else builtin_exercises()[eid]


@cache
def drawing(eid: str, lang: str = "de") -> str:
    return part_drawing(exercise(eid), lang)


def dims(eid: str, lang: str = "de") -> dict[str, list[tuple[str, str]]]:
    """The dimension texts by kind (d, z, r, chamfer, angle, groove, thread): (as printed, data-value)."""
    out: dict[str, list[tuple[str, str]]] = {}
    for t in ET.fromstring(drawing(eid, lang)).iter(f"{SVG}text"):
        if t.get("class") == "dim":
            out.setdefault(t.get("data-kind", ""), []).append((t.text or "", t.get("data-value", "")))
    return out


def printed(eid: str, kind: str, lang: str = "de") -> list[str]:
    return [text for text, _ in dims(eid, lang).get(kind, [])]


def test_overview_contour_tx17_diameters_lengths_and_radii() -> None:
    """TX-17: Ø20 to Z-15, G2 R10 to Ø40 at Z-25, Ø40 to Z-40, G3 R10 to Ø60 at Z-50, Ø60 to Z-75; the bar's Ø62
    beyond (the part's outer size, dimensioned in the view)."""
    eid = "traub-02-uebersichtskontur"
    assert sorted(printed(eid, "d")) == ["Ø20", "Ø40", "Ø60", "Ø62"]
    assert printed(eid, "z") == ["0", "15", "25", "40", "50", "75"]  # running from the face (Z0)
    assert [v for _, v in dims(eid)["z"]] == ["0", "-15", "-25", "-40", "-50", "-75"]  # the programmed Z
    assert printed(eid, "r") == ["R10", "R10"]
    assert "Zeichnung für Drehteile" not in drawing(eid)


def test_face_roughing_tx32_radius_and_chamfer_to_their_corners() -> None:
    """G1 X60 R2 and G1 Z-6 D1: the radius and chamfer are called out, the lengths go to the sharp corners
    (Z-15, Z-6), not to the tangent points (Z-13, Z-7)."""
    eid = "traub-05-planschruppen-g72"
    assert sorted(printed(eid, "d")) == ["Ø30", "Ø60", "Ø80"]
    assert printed(eid, "z") == ["0", "6", "15"]
    assert printed(eid, "r") == ["R2"] and printed(eid, "chamfer") == ["1×45°"]


def test_srk_shoulder_chamfer_and_english_numbers() -> None:
    eid = "traub-01-srk-fase"
    assert sorted(printed(eid, "d")) == ["Ø40", "Ø44"] and printed(eid, "chamfer") == ["2×45°"]
    assert printed(eid, "z") == ["0", "30"]
    assert "Half section" in drawing(eid, "en") and "Halbschnitt" in drawing(eid)


def test_contour_train_taper_and_decimal_comma() -> None:
    """TX-25: the taper A135 from Ø40 to Ø50 as its angle against the axis; TX-30's falling cone X38 A205: its
    angle 25°, and its end Z-73,951 (computed by the interpreter from the angle) only as an auxiliary dimension
    in brackets at the drawing's precision (DIN 406-10), with a decimal comma, a point in English."""
    assert printed("traub-04-geometriezug", "angle") == ["45°"]
    assert sorted(printed("traub-04-geometriezug", "d")) == ["Ø20", "Ø40", "Ø50", "Ø52"]
    assert printed("traub-10-schruppen-g71-g88", "angle") == ["25°"]
    lengths = printed("traub-10-schruppen-g71-g88", "z")
    assert "(73,95)" in lengths and "73,951" not in lengths and {"0", "15", "45", "120"} <= set(lengths)
    assert "(73.95)" in printed("traub-10-schruppen-g71-g88", "z", "en")


def test_threads_outside_and_tapped() -> None:
    """G76 X33.1 Z-29 F1.5 on the Ø35 bar: M35×1,5, 29 long; G82 Z-15 F1 with the tap Ø12 in the core hole
    Ø11 drilled to Z-25: M12×1, 15 deep, the core hole's Ø and its depth."""
    assert printed("traub-07-gewinde-g76", "thread") == ["M35×1,5"]
    assert printed("traub-07-gewinde-g76", "thread", "en") == ["M35×1.5"]
    assert printed("traub-07-gewinde-g76", "z") == ["0", "29"]
    assert printed("traub-08-bohren-unterprogramm", "thread") == ["M12×1"]
    assert sorted(printed("traub-08-bohren-unterprogramm", "d")) == ["Ø11", "Ø40"]  # the bar's Ø40 untouched
    assert printed("traub-08-bohren-unterprogramm", "z") == ["0", "15", "25"]


def test_groove_and_chamfer_callouts() -> None:
    """A plunge with a grooving insert B3 at Z-20 down to X30: "Einstich 3 breit", its bottom Ø30, its
    programmed wall Z-20 (not the insert's other side, Z-17, which the program does not give)."""
    eid = "drehen-einstich"
    assert printed(eid, "groove") == ["Einstich 3 breit"] and printed(eid, "groove", "en") == [
        "groove 3 wide"
    ]
    assert sorted(printed(eid, "d")) == ["Ø30", "Ø36", "Ø40"]
    assert printed(eid, "z") == ["0", "20", "40"]
    assert printed(eid, "chamfer") == ["1×45°"]


def _programmed(ex: Exercise) -> tuple[set[float], set[float]]:
    """The diameters and Z values a program gives: 2 × every programmed X (radius) and every Z of its moves
    and arc centres, the tools' diameters, the blank's diameters."""
    moves = execute_turning(ex, ex.reference).toolpath.moves
    points = [p for m in moves for p in (m.programmed_end or m.end, m.start, m.center or m.end)]
    diameters = {round(2 * p[0], 3) for p in points} | {
        round(t.diameter, 3) for t in ex.tool_table().tools.values()
    }
    assert ex.blank is not None
    diameters |= {ex.blank.diameter, ex.blank.inner_diameter}
    return diameters, {round(p[2], 3) for p in points} | {0.0}


@pytest.mark.parametrize("eid", TURNING)
def test_every_turning_drawing_is_real_and_prints_only_the_programs_numbers(eid: str) -> None:
    """Every built-in turning exercise (however many there are) gets a dimensioned drawing: Ø and lengths,
    each Ø twice a programmed radius (or a drill's or the blank's diameter), each length a programmed Z."""
    svg = drawing(eid)
    assert "Zeichnung für Drehteile" not in svg and "nan" not in svg.lower()
    found = dims(eid)
    assert found.get("d") or found.get("thread"), "no diameter"
    assert len(found.get("z", [])) >= 2, "no length"
    diameters, zs = _programmed(exercise(eid))
    for text, raw in found.get("d", []) + found.get("thread", []):
        assert round(float(raw), 3) in diameters, (text, sorted(diameters))
    # a length or Ø the program states as it is written, one it computes (from an angle) in brackets at two
    # decimals: an auxiliary dimension
    words = {abs(float(v)) for v in re.findall(r"(?<=Z)-?\d+(?:\.\d+)?", exercise(eid).reference)}
    for text, raw in found["z"]:
        assert round(float(raw), 3) in zs, (text, raw)
        if text.startswith("("):
            assert abs(float(raw)) not in words and text == f"({abs(float(raw)):.2f})".replace(".", ","), (
                text,
                raw,
            )
        else:
            assert text == f"{abs(float(raw)):g}".replace(".", ","), (text, raw)
    for text, raw in found.get("d", []):
        assert text == "Ø" + f"{float(raw):g}".replace(".", ",")


def _boxes(svg: str) -> list[tuple[str, float, float, float, float]]:
    """The dimension texts' boxes on the sheet (mm), from their position, size, anchor and rotation."""
    out = []
    for t in ET.fromstring(svg).iter(f"{SVG}text"):
        if t.get("class") != "dim":
            continue
        x, y, size = float(t.get("x", 0)), float(t.get("y", 0)), float(t.get("font-size", 3.5))
        width, height = len(t.text or "") * 0.58 * size, 0.72 * size
        start = {"start": 0.0, "middle": -width / 2, "end": -width}[t.get("text-anchor", "start")]
        if "rotate(-90" in (t.get("transform") or ""):  # reads upwards: along -y, glyphs left of x
            out.append((t.text or "", x - height, y - start - width, x, y - start))
        else:
            out.append((t.text or "", x + start, y - height, x + start + width, y))
    return out


@pytest.mark.parametrize("eid", TURNING + ["drehen-einstich"])
def test_no_dimension_text_lies_on_another(eid: str) -> None:
    boxes = _boxes(drawing(eid))
    for i, a in enumerate(boxes):
        for b in boxes[i + 1 :]:
            overlap = min(a[3], b[3]) - max(a[1], b[1]) > 0.2 and min(a[4], b[4]) - max(a[2], b[2]) > 0.2
            assert not overlap, (a, b)


def test_cli_writes_the_turned_parts_drawing(tmp_path: Path) -> None:
    out = tmp_path / "tx17.svg"
    assert main(["drawing", "traub-02-uebersichtskontur", "--out", str(out), "--lang", "en"]) == 0
    text = out.read_text(encoding="utf-8")
    assert ">Ø60</text>" in text and ">R10</text>" in text and "Half section" in text


def _pdf_engine() -> bool:
    from core.sheet import SheetUnavailable, pdf_engine

    try:
        pdf_engine()
    except SheetUnavailable:
        return False
    return True


needs_pdf = pytest.mark.skipif(
    not _pdf_engine(), reason="WeasyPrint or Pango missing (bash .ci/run installs them)"
)
needs_poppler = pytest.mark.skipif(
    shutil.which("pdftotext") is None or shutil.which("pdftoppm") is None, reason="poppler-utils missing"
)


@needs_pdf
@needs_poppler
def test_task_sheet_of_a_turning_exercise_has_the_diameters(tmp_path: Path) -> None:
    from core.sheet import task_sheet_pdf

    pdf = tmp_path / "tx17.pdf"
    pdf.write_bytes(task_sheet_pdf([exercise("traub-02-uebersichtskontur")], "de"))
    text = subprocess.run(
        ["pdftotext", "-layout", "-f", "1", "-l", "1", str(pdf), "-"],
        capture_output=True,
        text=True,
        check=True,
        timeout=60,
    ).stdout
    words = set(re.split(r"\s+", text))
    assert {"Ø20", "Ø40", "Ø60", "R10", "75", "Halbschnitt"} <= words
    # the task text names the bar (once: the data line gives the zero only); the tools with nose radius and V
    assert text.count("Stange Ø62 × 120 mm") == 1 and "Werkstücknullpunkt: Drehmitte" in text
    assert "F (mm/U)" in text and "R0,8, Lage P1" in text and "V 180 m/min (G96)" in text


@needs_pdf
@needs_poppler
def test_picture_of_the_drawing(tmp_path: Path) -> None:
    """The drawing of TX-17 printed on its own (A4 landscape, 150 dpi) for looking at: lines on white."""
    import weasyprint
    from PIL import Image

    uri = (
        "data:image/svg+xml;base64,"
        + base64.b64encode(drawing("traub-02-uebersichtskontur").encode()).decode()
    )
    page = (
        f"<html><head><style>@page {{ size: 297mm 210mm; margin: 0 }} body {{ margin: 0 }}</style></head>"
        f'<body><img src="{uri}" style="width: 297mm; height: 210mm; display: block"></body></html>'
    )
    pdf = tmp_path / "drawing.pdf"
    pdf.write_bytes(weasyprint.HTML(string=page).write_pdf())
    subprocess.run(
        ["pdftoppm", "-png", "-r", "150", "-singlefile", str(pdf), str(tmp_path / "drawing")],
        check=True,
        timeout=60,
    )
    SHOTS.mkdir(parents=True, exist_ok=True)
    shutil.copy(tmp_path / "drawing.png", SHOTS / "drawing-traub-02-lathe.png")
    with Image.open(tmp_path / "drawing.png") as image:
        assert abs(image.width / image.height - 297 / 210) < 0.01
        dark = sum(image.convert("L").histogram()[:128]) / (image.width * image.height)
        assert 0.01 < dark < 0.2, dark  # hatching, lines and text on white


def test_half_section_picture_of_the_turned_part() -> None:
    """TX-17's part: the upper half hatched, the lower half shaded, Ø60 at the chuck side higher than Ø20 at the
    face; saved as a PNG to look at."""
    from PIL import Image

    ex = exercise("traub-02-uebersichtskontur")
    assert ex.blank is not None
    turned = execute_turning(ex, ex.reference)
    p = turned.sim.profile
    image = tp.half_section_image(p.outer, p.inner, p.z0, p.dz, ex.blank.blank(), (480, 320))
    SHOTS.mkdir(parents=True, exist_ok=True)
    Image.fromarray(image).save(SHOTS / "picture-traub-02-lathe.png")
    hatch = np.all(image == tp.HATCH, axis=2)
    section = hatch | np.all(image == tp.SECTION, axis=2)
    axis = int(np.argmax(np.all(image == tp.AXIS, axis=2).sum(axis=1)))
    assert hatch.sum() > 300 and np.nonzero(section)[0].max() <= axis
    height = [axis - np.flatnonzero(section[:, c]).min() if section[:, c].any() else 0 for c in range(480)]
    columns = [c for c in range(480) if height[c]]
    face, chuck = height[columns[-1] - 3], height[columns[0] + 3]
    assert math.isclose(chuck / face, 31 / 10, rel_tol=0.08)  # the blank's Ø62 at the chuck, Ø20 at the face
    removed = np.all(image == tp.REMOVED, axis=2)
    assert removed.sum() > 1000  # what was turned away, inside the blank's outline


@pytest.mark.parametrize(
    "program,lengths",
    [
        ("M30\n", ["0"]),  # nothing turned: the bar and its face, no placeholder
        (
            "G95\nG97 S1000 T0101 M4\nG0 X10 Z-20\nG0 X100 Z50\nM30\n",
            ["0"],
        ),  # a rapid through the bar cuts nothing drawn
        (
            "G95\nG97 S1000 T0101 M4\nG0 X42 Z-2\nG1 X-1 F0.2\nG0 Z2\nG0 X100 Z50\nM30\n",
            ["0", "2"],
        ),  # faced to Z-2
        (
            "G95\nG97 S600 T0202 M4\nG0 X42 Z-30\nG1 X0 F0.05\nG0 X42\nG0 X100 Z50\nM30\n",
            ["0", "30"],
        ),  # parted off
        ("G95\nG97 S1000 T0101 M4\nG1 X30 Z-10 F\nM30\n", ["0"]),  # a syntax error
    ],
)
def test_any_program_gets_a_drawing(program: str, lengths: list[str]) -> None:
    ex = parse_exercise(
        GROOVE.split("reference: |")[0]
        + "reference: |\n"
        + "".join(f"  {line}\n" for line in program.splitlines())
    )
    svg = part_drawing(ex)
    texts = [t for t in ET.fromstring(svg).iter(f"{SVG}text") if t.get("class") == "dim"]
    assert [t.text for t in texts if t.get("data-kind") == "z"] == lengths
    assert all(t.get("data-kind") != "d" or float(t.get("data-value", "0")) > 0 for t in texts)
    assert "Zeichnung für Drehteile" not in svg and "nan" not in svg.lower()
