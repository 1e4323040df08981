"""The task sheet's tools and cutting data as the PAL paper prints them: every entry the task gives (the roughing
feed F 0,35 beside the reduced feed E 0,12, not only the last entry), a turning tool's insert, nose radius and
quadrant, V under G96 or S under G97, F and E in mm/U and the spindle direction; the task as formatted text (the
page's HTML), the blank named once; and no placeholder ("null", "None", "NaN", "{") on any built-in sheet."""

from __future__ import annotations

import html
import re
import shutil
import subprocess
from functools import cache
from pathlib import Path

import pytest

from core.exercises import Exercise, builtin_exercises
from core.sheet import SheetUnavailable, pdf_engine, task_sheet_html, task_sheet_pdf

PLACEHOLDERS = ("null", "None", "undefined", "NaN", "nan", "{", "}")


@cache
def exercise(eid: str) -> Exercise:
    return builtin_exercises()[eid]


def tool_table(page: str) -> list[list[str]]:
    """The rows of the tools table (header first) as the reader sees them."""
    table = page.split('<table class="tools">', 1)[1].split("</table>", 1)[0]
    rows = re.findall(r"<tr>(.*?)</tr>", table, flags=re.DOTALL)
    return [[html.unescape(c) for c in re.findall(r"<t[hd][^>]*>(.*?)</t[hd]>", row)] for row in rows]


def visible_text(page: str) -> str:
    """The sheet's text without its stylesheet, tags and the drawing's data URI."""
    body = page.split("<body>", 1)[1]
    body = re.sub(r'src="data:[^"]*"', "", body)
    return html.unescape(re.sub(r"<[^>]+>", " ", body))


def test_every_cutting_data_entry_of_a_turning_tool_is_printed() -> None:
    header, t4, t5 = tool_table(task_sheet_html([exercise("traub-10-schruppen-g71-g88")], "de"))
    assert header == [
        "Werkzeug",
        "Art",
        "Schneidplatte",
        "Ø / R (mm)",
        "V / S",
        "F (mm/U)",
        "E (mm/U)",
        "Drehrichtung",
    ]
    assert t4 == [
        "T4",
        "Schruppmeißel D R0,8",
        "D (55°)",
        "R0,8, Lage P1",
        "V 160 m/min (G96)",
        "0,35",
        "0,12",
        "M4",
    ]
    # the finishing tool: F 0,15 and F 0,1 on the cone, E 0,1 at the chamfer
    assert t5 == [
        "T5",
        "Schlichtmeißel V R0,4",
        "V (35°)",
        "R0,4, Lage P1",
        "V 200 m/min (G96)",
        "0,15 / 0,1",
        "0,1",
        "M4",
    ]


def test_speed_under_g97_drills_and_english() -> None:
    _, t1 = tool_table(task_sheet_html([exercise("traub-01-srk-fase")], "de"))
    assert t1[4:] == ["S 1000 1/min (G97)", "0,2", "0,1", "M4"]
    rows = tool_table(task_sheet_html([exercise("traub-08-bohren-unterprogramm")], "de"))
    assert [r[3] for r in rows[1:]] == ["Ø12", "Ø11", "Ø12"] and {r[2] for r in rows[1:]} == {"–"}
    assert [r[7] for r in rows[1:]] == ["M3", "M3", "M3"]
    header, t4, _ = tool_table(task_sheet_html([exercise("traub-10-schruppen-g71-g88")], "en"))
    assert header[5:] == ["F (mm/rev)", "E (mm/rev)", "Spindle"] and t4[1] == "Turning tool"
    assert t4[3:7] == ["R0.8, quadrant P1", "V 160 m/min (G96)", "0.35", "0.12"]


def test_milling_tools_with_speed_feed_and_direction() -> None:
    header, t1 = tool_table(task_sheet_html([exercise("pal-13-g41-aussenkontur")], "de"))
    assert header == ["Werkzeug", "Art", "Ø (mm)", "S (1/min)", "F (mm/min)", "Drehrichtung"]
    assert t1 == ["T1", "Schaftfräser", "25", "2000", "250", "M3"]
    # no cutting data in the task: the direction the reference turns the spindle in, no placeholder
    _, t4 = tool_table(task_sheet_html([exercise("beckhoff-fasen-radien")], "de"))
    assert t4 == ["T4", "Schaftfräser", "20", "–", "–", "M3"]


def test_the_task_is_formatted_and_the_blank_printed_once() -> None:
    page = task_sheet_html([exercise("traub-10-schruppen-g71-g88")], "de")
    text = visible_text(page)
    assert "<strong>G88</strong>" in page and page.count("<li>") >= 6 and "**" not in text
    assert text.count("Ø100 × 160") == 1 and "Werkstücknullpunkt: Drehmitte auf der Stirnfläche (Z0)" in text
    assert "Werkzeuge und Schnittdaten" in text


@pytest.mark.parametrize("eid", sorted(builtin_exercises()))
def test_no_placeholder_on_any_sheet(eid: str) -> None:
    for lang in ("de", "en"):
        text = visible_text(task_sheet_html([exercise(eid)], lang))
        found = [p for p in PLACEHOLDERS if re.search(rf"(?<![\w]){re.escape(p)}(?![\w])", text)]
        assert not found, (eid, lang, found)


def _pdf() -> bool:
    try:
        pdf_engine()
    except SheetUnavailable:
        return False
    return shutil.which("pdftotext") is not None


@pytest.mark.skipif(
    not _pdf(), reason="WeasyPrint, Pango or poppler-utils missing (bash .ci/run installs them)"
)
def test_the_printed_pdf_has_both_feeds(tmp_path: Path) -> None:
    pdf = tmp_path / "tx30.pdf"
    pdf.write_bytes(task_sheet_pdf([exercise("traub-10-schruppen-g71-g88")], "de"))
    text = subprocess.run(
        ["pdftotext", "-layout", "-f", "1", "-l", "1", str(pdf), "-"],
        capture_output=True,
        text=True,
        check=True,
        timeout=60,
    ).stdout
    row = next(line for line in text.splitlines() if line.strip().startswith("T4"))
    assert re.search(r"0,35\s+0,12\s+M4", row), row
    assert "V 160 m/min (G96)" in row and "D (55°)" in row
