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
from collections.abc import Mapping, Sequence
from functools import cache
from importlib import resources
from string import Template
from typing import Any

from core.drawing import KIND_NAMES_EN, MARGIN, SHEET, part_drawing, value
from core.exercises import CuttingData, Exercise
from core.interpreter.state import RunSetup
from core.pipeline import parse, run
from core.sheet.tasktext import blank_text, states_blank, task_html, zero_text
from core.tools import KIND_NAMES_DE, LATHE_KIND_NAMES_DE, Tool

FORM_ROWS = 25  # rows of one programming-form page
MAX_FORM_PAGES = 4
# the drawing's A4 landscape sheet (mm) without its outer white margin: its frame and the line under it
DRAWING_CROP = (MARGIN - 0.5, MARGIN - 0.5, SHEET[0] - 2 * MARGIN + 1.0, SHEET[1] - 2 * MARGIN + 6.5)
DEBIAN_PACKAGES = "libpango-1.0-0 libpangoft2-1.0-0 libharfbuzz-subset0 fonts-dejavu-core"

# the programming form's columns: heading (the same in both languages but the last), width in mm (190 in all)
FORM_COLUMNS = (
    ("N", 10),
    ("G", 10),
    ("X", 14),
    ("Y", 14),
    ("Z", 13),
    ("I", 12),
    ("J", 12),
    ("K / R", 12),
    ("F", 11),
    ("S", 11),
    ("T", 8),
    ("M", 9),
    ("", 54),
)

LABELS = {
    "de": {
        "sheet": "Aufgabenblatt",
        "form": "Programmierblatt",
        "name": "Name:",
        "date": "Datum:",
        "exercise": "Aufgabe",
        "data": "Rohteil, Werkzeuge und Schnittdaten",
        "tools_only": "Werkzeuge und Schnittdaten",
        "tool": "Werkzeug",
        "kind": "Art",
        "diameter": "Ø (mm)",
        "speed": "S (1/min)",
        "feed": "F (mm/min)",
        "insert": "Schneidplatte",
        "size": "Ø / R (mm)",
        "cut": "V / S",
        "feed_rev": "F (mm/U)",
        "reduced": "E (mm/U)",
        "spindle": "Drehrichtung",
        "position": "Lage",
        "groove": "Einstechplatte",
        "thread": "Gewindeplatte",
        "v": "V {v} m/min (G96)",
        "s": "S {s} 1/min (G97)",
        "remark": "Bemerkung",
        "start": "Ausgangsprogramm",
        "drawing": "Bemaßte Zeichnung des Fertigteils",
        "caption": "Zeichnung verkleinert gedruckt (etwa {p} %); es gelten die eingetragenen Maße in mm.",
        "form_page": "Programmierblatt {k} von {n}",
        "page": "Seite",
        "of": "von",
        "write": "Programm schreiben",
        "complete": "Programm ergänzen",
        "fix": "Fehler finden",
    },
    "en": {
        "sheet": "Task sheet",
        "form": "Programming form",
        "name": "Name:",
        "date": "Date:",
        "exercise": "Exercise",
        "data": "Blank, tools and cutting data",
        "tools_only": "Tools and cutting data",
        "tool": "Tool",
        "kind": "Kind",
        "diameter": "Ø (mm)",
        "speed": "S (rpm)",
        "feed": "F (mm/min)",
        "insert": "Insert",
        "size": "Ø / R (mm)",
        "cut": "V / S",
        "feed_rev": "F (mm/rev)",
        "reduced": "E (mm/rev)",
        "spindle": "Spindle",
        "position": "quadrant",
        "groove": "grooving insert",
        "thread": "threading insert",
        "v": "V {v} m/min (G96)",
        "s": "S {s} rpm (G97)",
        "remark": "Remark",
        "start": "Start program",
        "drawing": "Dimensioned drawing of the finished part",
        "caption": "Drawing printed reduced (about {p} %); the dimensions given in mm apply.",
        "form_page": "programming form {k} of {n}",
        "page": "Page",
        "of": "of",
        "write": "Write the program",
        "complete": "Complete the program",
        "fix": "Find the mistake",
    },
}
INSERT_ANGLES = {"C": 80, "D": 55, "V": 35}  # the rhombic inserts' corner angle (docs/tools.md)


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
        raise SheetUnavailable(
            "WeasyPrint ist nicht installiert (pip install weasyprint).",
            "WeasyPrint is not installed (pip install weasyprint).",
        ) from None
    except OSError as err:  # cffi could not load Pango, GObject or HarfBuzz
        reason = str(err).strip().splitlines()[0] if str(err).strip() else type(err).__name__
        install = f"Debian: apt-get install {DEBIAN_PACKAGES}"
        raise SheetUnavailable(
            f"WeasyPrint findet seine Systembibliotheken nicht ({install}): {reason}",
            f"WeasyPrint cannot load its system libraries ({install}): {reason}",
        ) from None


@cache
def _template(name: str) -> Template:
    return Template(resources.files(__package__).joinpath(name).read_text(encoding="utf-8"))


def _e(text: str) -> str:
    return html.escape(text, quote=True)


def _cropped(svg: str) -> str:
    """The drawing without the white margin around its frame (the page has its own)."""
    x, y, w, h = DRAWING_CROP
    return re.sub(
        r'width="[^"]*mm" height="[^"]*mm" viewBox="[^"]*"',
        f'width="{w:g}mm" height="{h:g}mm" viewBox="{x:g} {y:g} {w:g} {h:g}"',
        svg,
        count=1,
    )


def _svg_uri(svg: str) -> str:
    return "data:image/svg+xml;base64," + base64.b64encode(svg.encode("utf-8")).decode("ascii")


def _joined(values: list[str]) -> str:
    """Several allowed values side by side ("0,35 / 0,12"), each once; "–" where there is none."""
    seen = list(dict.fromkeys(v for v in values if v))
    return " / ".join(seen) if seen else "–"


def _programmed_feeds(
    exercise: Exercise,
) -> tuple[dict[int, set[float]], dict[int, set[float]], dict[int, str]]:
    """Per tool, the feeds the reference writes as F and as E (the reduced feed of a transition or a falling
    contour), and the spindle direction it turns the tool in (M3/M4): what tells an E from an F in the cutting
    data and fills in a direction the data leave open."""
    setup = RunSetup(
        tools=exercise.tool_table(),
        zero_offsets=tuple(exercise.zero_offsets.items()),
        subprograms=tuple(exercise.subprograms.items()),
    )
    toolpath = run(exercise.reference, exercise.dialect, setup)
    program, _ = parse(exercise.reference, exercise.dialect, setup)
    f_words: dict[int, set[float]] = {}
    e_words: dict[int, set[float]] = {}
    for block in program.blocks:
        if not block.ok or not block.words:
            continue
        tool = toolpath.state_at(block.line)[0].tool
        if tool is None:
            continue
        for word in block.words:
            if word.value is not None and word.address in ("F", "E"):
                (f_words if word.address == "F" else e_words).setdefault(tool, set()).add(
                    round(word.value, 6)
                )
    spindle: dict[int, str] = {}
    for m in toolpath.moves:
        if m.tool is not None and m.spindle_direction is not None and m.tool not in spindle:
            spindle[m.tool] = "M3" if m.spindle_direction == "cw" else "M4"
    return f_words, e_words, spindle


def tool_feeds(exercise: Exercise) -> dict[int, dict[str, Any]]:
    """Per tool of the cutting data, what its entries prescribe as the sheet prints it: "feed" (F), "reduced"
    (the feeds the reference writes as E: a turning tool's reduced feed; an entry written both ways is both), each
    in the entries' order and once, and "spindle" (M3/M4: the data's, else the direction the reference turns the
    tool in; None where neither says). The exercise page shows the same (server/tasktext.py)."""
    f_words, e_words, turning = _programmed_feeds(exercise)
    out: dict[int, dict[str, Any]] = {}
    for c in exercise.cutting_data:
        entry = out.setdefault(c.tool, {"feed": [], "reduced": [], "spindle": None})
        fs, es = f_words.get(c.tool, set()), e_words.get(c.tool, set())
        key = round(c.feed, 6)
        roles = (["reduced"] if key in es else []) + (["feed"] if key not in es or key in fs else [])
        for role in roles:
            if c.feed not in entry[role]:
                entry[role].append(c.feed)
        entry["spindle"] = entry["spindle"] or c.spindle or turning.get(c.tool)
    return out


def _insert(tool: Tool, lang: str) -> str:
    labels = LABELS[lang]
    if tool.kind != "turning":
        return "–"
    if tool.insert == "groove":
        return f"{labels['groove']} B{value(tool.width, lang)}" if tool.width else labels["groove"]
    if tool.insert == "thread":
        return f"{labels['thread']} (60°)"
    letter = tool.insert or "C"
    angle = tool.insert_angle or INSERT_ANGLES.get(letter)
    return f"{letter} ({value(angle, lang)}°)" if angle else letter


def _tool_rows(exercise: Exercise, lang: str) -> tuple[list[str], list[list[str]]]:
    """The columns and rows of the tool table: every tool of the exercise with every cutting-data entry the task
    gives for it (several allowed values side by side). Turning: the insert, its nose radius and quadrant,
    V (G96) or S (G97), F and the reduced feed E in mm/U, the spindle direction."""
    labels = LABELS[lang]
    kinds = (
        KIND_NAMES_DE | LATHE_KIND_NAMES_DE if lang == "de" else KIND_NAMES_EN | {"turning": "turning tool"}
    )
    table = exercise.tool_table()
    entries: dict[int, list[CuttingData]] = {}
    for c in exercise.cutting_data:
        entries.setdefault(c.tool, []).append(c)
    numbers = sorted(set(table.tools) | set(entries))
    _, _, turning = _programmed_feeds(exercise)
    feeds_of = tool_feeds(exercise) if exercise.lathe else {}
    rows = []
    for number in numbers:
        tool = table.get(number)
        cuts = entries.get(number, [])
        # the kind (a milling tool's name repeats its Ø, which has its own column); a lathe tool's own name in
        # German ("Schruppmeißel D R0,8": the names are German)
        kind = kinds.get(tool.kind, tool.name or tool.kind) if tool is not None else "–"
        if tool is not None and exercise.lathe and lang == "de" and tool.name:
            kind = tool.name
        if exercise.lathe:
            roles = feeds_of.get(number, {"feed": [], "reduced": []})
            feeds = [value(f, lang) for f in roles["feed"]]
            reduced = [value(f, lang) for f in roles["reduced"]]
            if tool is not None and tool.kind == "turning":
                size = f"R{value(tool.nose_radius, lang)}"
                if tool.quadrant:
                    size += f", {labels['position']} P{tool.quadrant}"
            else:
                size = f"Ø{value(tool.diameter, lang)}" if tool is not None and tool.diameter else "–"
            speeds = [
                labels["v"].format(v=value(c.cutting_speed, lang))
                if c.cutting_speed
                else labels["s"].format(s=value(c.speed, lang))
                if c.speed
                else ""
                for c in cuts
            ]
            spindle = [c.spindle or turning.get(number, "") for c in cuts] or [turning.get(number, "")]
            rows.append(
                [
                    f"T{number}",
                    kind[:1].upper() + kind[1:],
                    _insert(tool, lang) if tool is not None else "–",
                    size,
                    _joined(speeds),
                    _joined(feeds),
                    _joined(reduced),
                    _joined(spindle),
                ]
            )
        else:
            size = value(tool.diameter, lang) if tool is not None and tool.diameter else "–"
            spindle = [c.spindle or turning.get(number, "") for c in cuts] or [turning.get(number, "")]
            rows.append(
                [
                    f"T{number}",
                    kind[:1].upper() + kind[1:],
                    size,
                    _joined([value(c.speed, lang) for c in cuts if c.speed]),
                    _joined([value(c.feed, lang) for c in cuts]),
                    _joined(spindle),
                ]
            )
    columns = (
        ["tool", "kind", "insert", "size", "cut", "feed_rev", "reduced", "spindle"]
        if exercise.lathe
        else ["tool", "kind", "diameter", "speed", "feed", "spindle"]
    )
    return [labels[c] for c in columns], rows


def _task_page(exercise: Exercise, lang: str, drawing: str | None = None) -> str:
    """The task page; `drawing`: an image (data URI) the author gave instead of the generated drawing."""
    labels = LABELS[lang]
    headings, rows = _tool_rows(exercise, lang)
    left = 2  # the tool and its kind are text; the other columns are values
    head = "".join(
        f'<th class="num">{_e(h)}</th>' if n >= left else f"<th>{_e(h)}</th>" for n, h in enumerate(headings)
    )
    body = [
        "      <tr>"
        + "".join(
            f'<td class="num">{_e(c)}</td>' if k >= left else f"<td>{_e(c)}</td>" for k, c in enumerate(row)
        )
        + "</tr>"
        for row in rows
    ]
    start = ""
    if exercise.kind != "write" and exercise.start_program:
        start = (
            f'  <div class="start">\n    <h2>{_e(labels["start"])}</h2>\n'
            f"    <pre>{_e(exercise.start_program.rstrip())}</pre>\n  </div>"
        )
    percent = round(190.0 * (0.78 if start else 1.0) / DRAWING_CROP[2] * 100)
    stock = exercise.stock.model_dump(mode="json")
    blank = exercise.blank.model_dump(mode="json") if exercise.blank is not None else None
    task = exercise.task.get(lang)
    stated = states_blank(task, stock, blank)  # the text says it already: the data line gives only the zero
    data_line = (
        zero_text(stock, blank, lang)
        if stated
        else f"{blank_text(stock, blank, lang)} · {zero_text(stock, blank, lang)}"
    )
    return _template("task.html").substitute(
        sheet_label=_e(labels["sheet"]),
        name_label=_e(labels["name"]),
        date_label=_e(labels["date"]),
        title=_e(exercise.title.get(lang)),
        meta=_e(f"{labels['exercise']} {exercise.id} · {labels[exercise.kind]}"),
        task=task_html(task),  # safe HTML (core/sheet/tasktext.py): what the exercise page shows
        drawing=drawing or _svg_uri(_cropped(part_drawing(exercise, lang))),
        drawing_alt=_e(labels["drawing"]),
        caption=_e(labels["caption"].format(p=percent)),
        data_label=_e(labels["tools_only" if stated else "data"]),
        blank=_e(data_line),
        tool_headings=head,
        tool_rows="\n".join(body),
        start=start,
        variant=" with-start" if start else "",
        lathe=" lathe" if exercise.lathe else "",
    )


def form_pages(exercise: Exercise) -> int:
    """Programming-form pages for an exercise: room for its reference program's blocks, at least one page."""
    blocks = sum(1 for line in exercise.reference.splitlines() if line.strip())
    return max(1, min(MAX_FORM_PAGES, math.ceil(blocks / FORM_ROWS)))


FORM_ROW_HEIGHT = 9.75  # mm: room for a handwritten block
FORM_LINES = (0.25, 0.4)  # mm: the lines between cells; the outline and every fifth row's


@cache
def form_grid() -> str:
    """The rows of a form page below its headings as one SVG: FORM_ROWS rows of the FORM_COLUMNS, a heavier line
    round it and under every fifth row. A drawn grid, not table cells: the PDF engine lays out and draws each
    cell on its own, a table of 25 × 13 cells took four fifths of a sheet's time."""
    thin, heavy = FORM_LINES
    edges = [0]
    for _, w in FORM_COLUMNS:
        edges.append(edges[-1] + w)
    width, height = edges[-1], FORM_ROWS * FORM_ROW_HEIGHT
    lines = [
        (0, r * FORM_ROW_HEIGHT, width, r * FORM_ROW_HEIGHT, heavy if r % 5 == 0 else thin)
        for r in range(FORM_ROWS + 1)
    ]
    lines += [(x, 0, x, height, heavy if x in (0, width) else thin) for x in edges]
    body = "".join(
        f'<line x1="{x1:g}" y1="{y1:g}" x2="{x2:g}" y2="{y2:g}" stroke-width="{w:g}"/>'
        for x1, y1, x2, y2, w in lines
    )
    pad = heavy / 2  # the outline's lines whole, half of them outside the rows
    return (
        f'<svg xmlns="http://www.w3.org/2000/svg" width="{width + heavy:g}mm" height="{height + heavy:g}mm" '
        f'viewBox="{-pad:g} {-pad:g} {width + heavy:g} {height + heavy:g}" stroke="#000" stroke-linecap="square">'
        f"{body}</svg>"
    )


def _form_page(exercise: Exercise, lang: str, k: int, n: int) -> str:
    labels = LABELS[lang]
    columns = "".join(f'<col style="width: {w}mm">' for _, w in FORM_COLUMNS)
    headings = "".join(f"<th>{_e(h or labels['remark'])}</th>" for h, _ in FORM_COLUMNS)
    return _template("form.html").substitute(
        form_label=_e(labels["form"]),
        name_label=_e(labels["name"]),
        date_label=_e(labels["date"]),
        title=_e(exercise.title.get(lang)),
        exercise_label=_e(labels["exercise"]),
        id=_e(exercise.id),
        form_page=_e(labels["form_page"].format(k=k, n=n)),
        columns=columns,
        headings=headings,
        grid=_svg_uri(form_grid()),
    )


def task_sheet_html(
    exercises: Sequence[Exercise], lang: str = "de", drawings: Mapping[str, str] | None = None
) -> str:
    """The task sheets of the exercises as one HTML document with its print stylesheet (the PDF's source);
    `drawings`: per exercise id an author's own drawing (an image as data URI) printed instead of the generated one."""
    lang = "en" if lang == "en" else "de"
    if not exercises:
        raise ValueError("no exercises")
    labels = LABELS[lang]
    sheets: list[str] = []
    for exercise in exercises:
        sheets.append(_task_page(exercise, lang, (drawings or {}).get(exercise.id)))
        n = form_pages(exercise)
        sheets += [_form_page(exercise, lang, k, n) for k in range(1, n + 1)]
    first = exercises[0]
    title = first.title.get(lang) if len(exercises) == 1 else f"{labels['sheet']} ({len(exercises)})"
    footer = f"PAL Trainer · {labels['exercise']} {first.id}" if len(exercises) == 1 else "PAL Trainer"
    css = _template("sheet.css").substitute(
        footer=footer.replace('"', "'"), page_word=labels["page"], of_word=labels["of"]
    )
    return _template("sheet.html").substitute(lang=lang, title=_e(title), css=css, sheets="\n".join(sheets))


def task_sheet_pdf(
    exercises: Sequence[Exercise], lang: str = "de", drawings: Mapping[str, str] | None = None
) -> bytes:
    """The task sheets of the exercises as one PDF (A4): per exercise its task page, then its form pages."""
    engine = pdf_engine()
    document = task_sheet_html(exercises, lang, drawings)
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
        raise SheetUnavailable(
            "pypdf ist nicht installiert (pip install pypdf).", "pypdf is not installed (pip install pypdf)."
        ) from None
    writer = PdfWriter()
    for part in parts:
        writer.append(PdfReader(io.BytesIO(part)))
    out = io.BytesIO()
    writer.write(out)
    return out.getvalue()
