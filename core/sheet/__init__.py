"""Paper practice: an exercise as a printed task sheet (PDF), as the PAL exam hands it out.

Per exercise, a task page — title, task text, the dimensioned drawing (core/drawing), blank, tools and
cutting data, and for kinds complete and fix the start program — then empty programming-form pages
("Programmierblatt": one column per address and a wide remark column, 25 rows a page). Several exercises
make one document. The HTML comes from the templates next to this file; WeasyPrint turns it into PDF.
`merge_pdfs` puts PDFs made one exercise at a time one after the other (pypdf).

WeasyPrint needs Pango and HarfBuzz from the system, so it is imported only when a PDF is made: without
it everything else works, and `task_sheet_pdf` raises `SheetUnavailable`, saying what is missing.
"""

from __future__ import annotations

import base64
import html
import importlib
import io
import math
import re
from collections.abc import Sequence
from functools import cache
from importlib import resources
from string import Template
from typing import Any

from core.drawing import KIND_NAMES_EN, MARGIN, SHEET, part_drawing, value
from core.exercises import CuttingData, Exercise
from core.tools import KIND_NAMES_DE

FORM_ROWS = 25  # rows of one programming-form page
MAX_FORM_PAGES = 4
# the drawing's A4 landscape sheet (mm) without its outer white margin: its frame and the line under it
DRAWING_CROP = (MARGIN - 0.5, MARGIN - 0.5, SHEET[0] - 2 * MARGIN + 1.0, SHEET[1] - 2 * MARGIN + 6.5)
DEBIAN_PACKAGES = "libpango-1.0-0 libpangoft2-1.0-0 libharfbuzz-subset0 fonts-dejavu-core"

# the programming form's columns: heading (the same in both languages but the last), width in mm (190 in all)
FORM_COLUMNS = (("N", 10), ("G", 10), ("X", 14), ("Y", 14), ("Z", 13), ("I", 12), ("J", 12), ("K / R", 12),
                ("F", 11), ("S", 11), ("T", 8), ("M", 9), ("", 54))

LABELS = {
    "de": {"sheet": "Aufgabenblatt", "form": "Programmierblatt", "name": "Name:", "date": "Datum:",
           "exercise": "Aufgabe", "data": "Rohteil, Werkzeuge und Schnittdaten",
           "blank": "Rohteil {x} × {y} × {z} mm, Werkstücknullpunkt: {zero}.",
           "bar": "Rohteil Stange Ø{d} × {l} mm, Werkstücknullpunkt: {zero}.",
           "tube": "Rohteil Rohr Ø{d} / Ø{i} × {l} mm, Werkstücknullpunkt: {zero}.",
           "feed_rev": "F (mm/U)", "nose": "Ø / R (mm)",
           "tool": "Werkzeug", "kind": "Art", "diameter": "Ø (mm)", "speed": "S (1/min)",
           "feed": "F (mm/min)",
           "remark": "Bemerkung", "start": "Ausgangsprogramm", "drawing": "Bemaßte Zeichnung des Fertigteils",
           "caption": "Zeichnung verkleinert gedruckt (etwa {p} %); es gelten die eingetragenen Maße in mm.",
           "form_page": "Programmierblatt {k} von {n}", "page": "Seite", "of": "von",
           "write": "Programm schreiben", "complete": "Programm ergänzen", "fix": "Fehler finden"},
    "en": {"sheet": "Task sheet", "form": "Programming form", "name": "Name:", "date": "Date:",
           "exercise": "Exercise", "data": "Blank, tools and cutting data",
           "blank": "Blank {x} × {y} × {z} mm, workpiece zero: {zero}.",
           "bar": "Blank: bar Ø{d} × {l} mm, workpiece zero: {zero}.",
           "tube": "Blank: tube Ø{d} / Ø{i} × {l} mm, workpiece zero: {zero}.",
           "feed_rev": "F (mm/rev)", "nose": "Ø / R (mm)",
           "tool": "Tool", "kind": "Kind", "diameter": "Ø (mm)", "speed": "S (rpm)", "feed": "F (mm/min)",
           "remark": "Remark", "start": "Start program",
           "drawing": "Dimensioned drawing of the finished part",
           "caption": "Drawing printed reduced (about {p} %); the dimensions given in mm apply.",
           "form_page": "programming form {k} of {n}", "page": "Page", "of": "of",
           "write": "Write the program", "complete": "Complete the program", "fix": "Find the mistake"},
}


class SheetUnavailable(RuntimeError):
    """PDF cannot be made on this machine: WeasyPrint or its system libraries are missing."""

    def __init__(self, message: str, message_en: str) -> None:
        super().__init__(message, message_en)  # both in args: the error crosses process boundaries by pickle
        self.message, self.message_en = message, message_en

    def __str__(self) -> str:
        return f"{self.message} / {self.message_en}"


def _import_weasyprint() -> Any:
    return importlib.import_module("weasyprint")


def pdf_engine() -> Any:
    """The weasyprint module, imported on first use; SheetUnavailable says what is missing."""
    try:
        return _import_weasyprint()
    except ImportError:
        raise SheetUnavailable("WeasyPrint ist nicht installiert (pip install weasyprint).",
                               "WeasyPrint is not installed (pip install weasyprint).") from None
    except OSError as err:  # cffi could not load Pango, GObject or HarfBuzz
        reason = str(err).strip().splitlines()[0] if str(err).strip() else type(err).__name__
        install = f"Debian: apt-get install {DEBIAN_PACKAGES}"
        raise SheetUnavailable(f"WeasyPrint findet seine Systembibliotheken nicht ({install}): {reason}",
                               f"WeasyPrint cannot load its system libraries ({install}): {reason}") from None


@cache
def _template(name: str) -> Template:
    return Template(resources.files(__package__).joinpath(name).read_text(encoding="utf-8"))


def _e(text: str) -> str:
    return html.escape(text, quote=True)


def _paragraphs(markdown: str) -> str:
    """Markdown paragraphs as the exercise page shows them: blank lines separate, single breaks are spaces."""
    paragraphs = [re.sub(r"\s*\n\s*", " ", p).strip() for p in re.split(r"\n\s*\n", markdown)]
    return "\n".join(f"    <p>{_e(p)}</p>" for p in paragraphs if p)


def _cropped(svg: str) -> str:
    """The drawing without the white margin around its frame (the page has its own)."""
    x, y, w, h = DRAWING_CROP
    return re.sub(r'width="[^"]*mm" height="[^"]*mm" viewBox="[^"]*"',
                  f'width="{w:g}mm" height="{h:g}mm" viewBox="{x:g} {y:g} {w:g} {h:g}"', svg, count=1)


def _svg_uri(svg: str) -> str:
    return "data:image/svg+xml;base64," + base64.b64encode(svg.encode("utf-8")).decode("ascii")


def _speed(cut: CuttingData | None, lang: str) -> str:
    """S in 1/min; where the task gives a cutting speed instead (turning under G96), V in m/min."""
    if cut is None:
        return "–"
    if cut.speed:
        return value(cut.speed, lang)
    v = getattr(cut, "cutting_speed", None)
    return f"V {value(float(v), lang)} m/min" if v else "–"


def _task_page(exercise: Exercise, lang: str) -> str:
    labels = LABELS[lang]
    kinds = KIND_NAMES_DE if lang == "de" else KIND_NAMES_EN
    st = exercise.stock.stock()
    cutting = {c.tool: c for c in exercise.cutting_data}
    rows = []
    for tool in sorted(exercise.tool_table().tools.values(), key=lambda t: t.number):
        cut = cutting.get(tool.number)
        # the kind only (the tool's name repeats its Ø, which has its own column)
        kind = kinds.get(tool.kind, tool.name or tool.kind)
        size = value(tool.diameter, lang) if tool.diameter else "–"
        if tool.kind == "turning":  # a lathe tool: its nose radius
            size = f"R{value(tool.nose_radius, lang)}"
        cells = [f"T{tool.number}", kind[:1].upper() + kind[1:], size, _speed(cut, lang),
                 value(cut.feed, lang) if cut else "–"]
        rows.append("      <tr>" + "".join(f'<td class="num">{_e(c)}</td>' if k >= 2 else f"<td>{_e(c)}</td>"
                                            for k, c in enumerate(cells)) + "</tr>")
    columns = ("tool", "kind", "nose", "speed", "feed_rev") if exercise.lathe else ("tool", "kind", "diameter", "speed",
                                                                                     "feed")
    headings = "".join(f'<th class="num">{_e(labels[k])}</th>' if n >= 2 else f"<th>{_e(labels[k])}</th>"
                       for n, k in enumerate(columns))
    start = ""
    if exercise.kind != "write" and exercise.start_program:
        start = (f'  <div class="start">\n    <h2>{_e(labels["start"])}</h2>\n'
                 f"    <pre>{_e(exercise.start_program.rstrip())}</pre>\n  </div>")
    percent = round(190.0 * (0.78 if start else 1.0) / DRAWING_CROP[2] * 100)
    blank = labels["blank"].format(x=value(st.x1 - st.x0, lang), y=value(st.y1 - st.y0, lang),
                                   z=value(st.z1 - st.z0, lang), zero=exercise.stock.zero.get(lang))
    if exercise.blank is not None:  # a lathe's bar or tube
        b = exercise.blank
        blank = labels["tube" if b.inner_diameter else "bar"].format(
            d=value(b.diameter, lang), i=value(b.inner_diameter, lang), l=value(b.length, lang),
            zero=exercise.stock.zero.get(lang))
    return _template("task.html").substitute(
        sheet_label=_e(labels["sheet"]), name_label=_e(labels["name"]), date_label=_e(labels["date"]),
        title=_e(exercise.title.get(lang)),
        meta=_e(f"{labels['exercise']} {exercise.id} · {labels[exercise.kind]}"),
        task=_paragraphs(exercise.task.get(lang)),
        drawing=_svg_uri(_cropped(part_drawing(exercise, lang))), drawing_alt=_e(labels["drawing"]),
        caption=_e(labels["caption"].format(p=percent)), data_label=_e(labels["data"]), blank=_e(blank),
        tool_headings=headings, tool_rows="\n".join(rows), start=start,
        variant=" with-start" if start else "")


def form_pages(exercise: Exercise) -> int:
    """Programming-form pages for an exercise: room for its reference program's blocks, at least one page."""
    blocks = sum(1 for line in exercise.reference.splitlines() if line.strip())
    return max(1, min(MAX_FORM_PAGES, math.ceil(blocks / FORM_ROWS)))


def _form_page(exercise: Exercise, lang: str, k: int, n: int) -> str:
    labels = LABELS[lang]
    columns = "".join(f'<col style="width: {w}mm">' for _, w in FORM_COLUMNS)
    headings = "".join(f"<th>{_e(h or labels['remark'])}</th>" for h, _ in FORM_COLUMNS)
    row = "      <tr>" + "<td></td>" * len(FORM_COLUMNS) + "</tr>"
    return _template("form.html").substitute(
        form_label=_e(labels["form"]), name_label=_e(labels["name"]), date_label=_e(labels["date"]),
        title=_e(exercise.title.get(lang)), exercise_label=_e(labels["exercise"]), id=_e(exercise.id),
        form_page=_e(labels["form_page"].format(k=k, n=n)), columns=columns, headings=headings,
        rows="\n".join([row] * FORM_ROWS))


def task_sheet_html(exercises: Sequence[Exercise], lang: str = "de") -> str:
    """The task sheets of the exercises as one HTML document with its print stylesheet (the PDF's source)."""
    lang = "en" if lang == "en" else "de"
    if not exercises:
        raise ValueError("no exercises")
    labels = LABELS[lang]
    sheets: list[str] = []
    for exercise in exercises:
        sheets.append(_task_page(exercise, lang))
        n = form_pages(exercise)
        sheets += [_form_page(exercise, lang, k, n) for k in range(1, n + 1)]
    first = exercises[0]
    title = first.title.get(lang) if len(exercises) == 1 else f"{labels['sheet']} ({len(exercises)})"
    footer = f"PAL Trainer · {labels['exercise']} {first.id}" if len(exercises) == 1 else "PAL Trainer"
    css = _template("sheet.css").substitute(footer=footer.replace('"', "'"), page_word=labels["page"],
                                            of_word=labels["of"])
    return _template("sheet.html").substitute(lang=lang, title=_e(title), css=css, sheets="\n".join(sheets))


def task_sheet_pdf(exercises: Sequence[Exercise], lang: str = "de") -> bytes:
    """The task sheets of the exercises as one PDF (A4): per exercise its task page, then its form pages."""
    engine = pdf_engine()
    document = task_sheet_html(exercises, lang)
    pdf: bytes = engine.HTML(string=document).write_pdf()
    return pdf


def merge_pdfs(parts: Sequence[bytes]) -> bytes:
    """PDFs one after the other as one PDF (pypdf): the server renders each exercise's sheet on its own (one
    exercise's pages are one short job, and cached) and hands out an assignment's sheets as one file. Each part
    keeps its own page numbers ("Seite 1 von 2": the pages of its exercise) and footer (its exercise)."""
    if not parts:
        raise ValueError("no PDFs")
    if len(parts) == 1:
        return parts[0]
    try:
        from pypdf import PdfReader, PdfWriter
    except ImportError:
        raise SheetUnavailable("pypdf ist nicht installiert (pip install pypdf).",
                               "pypdf is not installed (pip install pypdf).") from None
    writer = PdfWriter()
    for part in parts:
        writer.append(PdfReader(io.BytesIO(part)))
    out = io.BytesIO()
    writer.write(out)
    return out.getvalue()
