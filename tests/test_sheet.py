"""Task sheets for paper practice (core/sheet): the PDF's text, its pages, a picture of page 1, and what
happens where WeasyPrint cannot be loaded.

A PNG of each task page is saved next to the browser tests' screenshots (PALTRAINER_SCREENSHOTS, else
tests/browser/screenshots/) to look at."""

from __future__ import annotations

import base64
import io
import os
import re
import shutil
import subprocess
from functools import cache
from pathlib import Path

import pytest

import core.sheet
from core.cli import main
from core.exercises import Exercise, builtin_exercises
from core.sheet import FORM_ROWS, SheetUnavailable, pdf_engine, task_sheet_html, task_sheet_pdf

LINE = r'<line x1="([-\d.]+)" y1="([-\d.]+)" x2="([-\d.]+)" y2="([-\d.]+)" stroke-width="([\d.]+)"/>'
SHOTS = Path(os.environ.get("PALTRAINER_SCREENSHOTS") or Path(__file__).parent / "browser" / "screenshots")


def _pdf_available() -> bool:
    try:
        pdf_engine()
    except SheetUnavailable:
        return False
    return True


needs_pdf = pytest.mark.skipif(
    not _pdf_available(), reason="WeasyPrint or Pango missing (bash .ci/run installs them)"
)


@cache
def exercise(eid: str) -> Exercise:
    return builtin_exercises()[eid]


def pages_text(pdf: bytes) -> list[str]:
    from pypdf import PdfReader

    return [page.extract_text() for page in PdfReader(io.BytesIO(pdf)).pages]


@cache
def pal13_pdf(lang: str) -> bytes:
    return task_sheet_pdf([exercise("pal-13-g41-aussenkontur")], lang)


def words(text: str) -> set[str]:
    return set(re.split(r"\s+", text))


@needs_pdf
def test_task_page_has_title_task_drawing_and_cutting_data() -> None:
    pdf = pal13_pdf("de")
    assert pdf.startswith(b"%PDF-")
    task, _ = pages_text(pdf)
    assert "G41 – Außenkontur (Bogenform)" in task
    assert "Fräsen Sie die Außenkontur eines bogenförmigen Zapfens 10 mm tief" in " ".join(task.split())
    # the drawing's dimensions: the arc, the X ordinates of the edges and the centre, the Y of the centre
    assert {"R20", "15", "35", "55", "75", "-10", "-20", "Draufsicht"} <= words(task)
    assert task.count("R20") >= 2  # the task text names it too: once more in the drawing
    assert "Tiefe 10" in task and "Schnitt A–A" in task
    # tools and cutting data: T1 end mill Ø25, S 2000 1/min, F 250 mm/min
    assert {"T1", "25", "2000", "250"} <= words(task) and "S (1/min)" in task and "F (mm/min)" in task
    assert "Schaftfräser 25 2000 250" in " ".join(task.split())
    assert "Bemerkung" not in task


@needs_pdf
def test_form_page_has_the_exam_columns() -> None:
    _, form = pages_text(pal13_pdf("de"))
    assert "Programmierblatt" in form and "G41 – Außenkontur (Bogenform)" in form
    headings = form.split()
    for column in ("N", "G", "X", "Y", "Z", "I", "J", "K", "R", "F", "S", "T", "M", "Bemerkung"):
        assert column in headings, column
    assert "Name:" in form and "Datum:" in form


@needs_pdf
def test_english_sheet() -> None:
    task, form = pages_text(pal13_pdf("en"))
    assert "G41 – outer contour (arch)" in task and "Top view" in task and "S (rpm)" in task
    assert "End mill 25 2000 250" in " ".join(task.split()) and "Schaftfräser" not in task
    assert "Programming form" in form and "Remark" in form and "Bemerkung" not in form
    assert "Page 2 of 2" in form


@needs_pdf
def test_several_exercises_make_one_document_each_with_its_form() -> None:
    fix, slots = exercise("fehler-02-spindel"), exercise("pal-09-g23-l-nuten")
    pages = pages_text(task_sheet_pdf([fix, slots], "de"))
    assert len(pages) == 4
    assert "Fehlersuche – Technologie" in pages[0] and "Programmierblatt" in pages[1]
    # the start program of a find-the-mistake exercise is printed with its task
    assert "Ausgangsprogramm" in pages[0] and "N10" in pages[0]
    assert slots.title.de in pages[2] and "Ausgangsprogramm" not in pages[2]
    assert "Programmierblatt 1 von 1" in pages[3] and "Seite 4 von 4" in pages[3]


@needs_pdf
@pytest.mark.skipif(shutil.which("pdftoppm") is None, reason="pdftoppm (poppler-utils) missing")
def test_picture_of_the_task_page(tmp_path: Path) -> None:
    from PIL import Image

    pdf = tmp_path / "sheet.pdf"
    pdf.write_bytes(pal13_pdf("de"))
    SHOTS.mkdir(parents=True, exist_ok=True)
    subprocess.run(
        ["pdftoppm", "-png", "-r", "100", "-f", "1", "-l", "2", str(pdf), str(tmp_path / "page")],
        check=True,
        timeout=60,
    )
    for k, name in ((1, "sheet-pal-13-task.png"), (2, "sheet-pal-13-form.png")):
        shot = next(tmp_path.glob(f"page-*{k}.png"))
        shutil.copy(shot, SHOTS / name)
        with Image.open(shot) as image:
            assert abs(image.width / image.height - 210 / 297) < 0.01  # A4 portrait
            grey = image.convert("L")
            dark = sum(grey.histogram()[:128]) / (image.width * image.height)
            assert 0.005 < dark < 0.25, dark  # lines and text on white: neither empty nor blotted


def test_form_has_25_rows_of_13_columns_and_the_task_is_escaped() -> None:
    ex = exercise("pal-13-g41-aussenkontur")
    task = {"de": "Erst <b>das</b>\nund & dies.\n\nZweiter Absatz."}
    odd = type(ex).model_validate({**ex.model_dump(), "task": task})
    page = task_sheet_html([odd], "de")
    assert "<p>Erst &lt;b&gt;das&lt;/b&gt;\nund &amp; dies.</p>" in page and "<p>Zweiter Absatz.</p>" in page
    form = page.split('class="pal"', 1)[1]
    columns = ["N", "G", "X", "Y", "Z", "I", "J", "K / R", "F", "S", "T", "M", "Bemerkung"]
    assert re.findall(r"<th>([^<]*)</th>", form) == columns
    widths = [float(w) for w in re.findall(r'<col style="width: ([\d.]+)mm">', form)]
    # the rows below: one drawn grid, its lines on the headings' column borders, a heavier one every fifth row
    grid = base64.b64decode(
        re.search(r'class="grid" src="data:image/svg\+xml;base64,([^"]+)"', form)[1]
    ).decode()
    lines = [tuple(map(float, m[:4])) + (float(m[4]),) for m in re.findall(LINE, grid)]
    across = sorted((y1, w) for x1, y1, x2, y2, w in lines if y1 == y2 and x1 == 0 and x2 == sum(widths))
    down = sorted(x1 for x1, y1, x2, y2, w in lines if x1 == x2)
    assert len(across) == FORM_ROWS + 1 and len(down) == 13 + 1
    assert down == pytest.approx([sum(widths[:k]) for k in range(14)])
    assert [w for _, w in across] == [0.4 if r % 5 == 0 else 0.25 for r in range(FORM_ROWS + 1)]
    assert across[-1][0] / FORM_ROWS >= 9.5  # mm a row: room for a handwritten block


def test_without_weasyprint_it_says_what_is_missing(
    monkeypatch: pytest.MonkeyPatch, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    def no_pango() -> None:
        raise OSError("cannot load library 'libpango-1.0-0': libpango-1.0-0: cannot open shared object file")

    monkeypatch.setattr(core.sheet, "_import_weasyprint", no_pango)
    with pytest.raises(SheetUnavailable) as err:
        task_sheet_pdf([exercise("pal-13-g41-aussenkontur")])
    assert "libpango-1.0-0" in err.value.message and "Systembibliotheken" in err.value.message
    assert "system libraries" in err.value.message_en
    out = tmp_path / "sheet.pdf"
    assert main(["sheet", "pal-13-g41-aussenkontur", "--out", str(out)]) == 2
    assert "WeasyPrint" in capsys.readouterr().err and not out.exists()

    def not_installed() -> None:
        raise ModuleNotFoundError("No module named 'weasyprint'")

    monkeypatch.setattr(core.sheet, "_import_weasyprint", not_installed)
    with pytest.raises(SheetUnavailable) as err:
        pdf_engine()
    assert "pip install weasyprint" in err.value.message


@needs_pdf
def test_cli_writes_the_pdf(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "sheet.pdf"
    both = ["pal-13-g41-aussenkontur", "pal-01-g1-gerade"]
    assert main(["sheet", *both, "--out", str(out), "--lang", "en"]) == 0
    pages = pages_text(out.read_bytes())
    assert len(pages) == 4 and "Programming form" in pages[1]
    assert main(["sheet", "no-such-exercise", "--out", str(out)]) == 2
    assert main(["sheet", "pal-13-g41-aussenkontur", "--out", str(tmp_path / "missing" / "x.pdf")]) == 2
    assert "kann nicht geschrieben werden" in capsys.readouterr().err
