"""What every drawing sheet has, milled or turned: the A4 frame, the scales, the title block, and how a number
is printed (the drawing's precision, the decimal comma in German). core/drawing (milled parts) and
core/drawing/turned.py (turned parts) both draw their sheet with these.

A drawing prints nominal values, as the task states them: the program's own words (X, Z, R, D, …) at the
precision the program writes them, never a float the interpreter computed from them ("R20,999" for an arc
given by I and J whose task says R21). The precision is two decimals, three where the program writes three
(`Numbers`). A length the program does not state but computes (the end of a taper given by its angle) is shown
only as an auxiliary dimension in brackets, rounded to that precision (DIN 406-10): "(73,95)".
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass

from core.drawing.svg import BOLD, CHAR, THICK, THIN, Box, Svg, num
from core.exercises import Exercise
from core.tools import KIND_NAMES_DE

SHEET = (297.0, 210.0)  # A4 landscape, mm
MARGIN = 10.0
TITLE_BLOCK = (112.0, 34.0)
SCALES = (10.0, 5.0, 2.0, 1.0, 0.5, 0.2, 0.1, 0.05, 0.02, 0.01)
TEXT = 3.5  # mm, dimension text height
SPACING = 4.5  # mm between neighbouring ordinate texts

KIND_NAMES_EN = {
    "end_mill": "end mill",
    "slot_drill": "slot drill",
    "ball_nose": "ball-nose mill",
    "torus": "torus mill",
    "twist_drill": "twist drill",
    "spot_drill": "spot drill",
}

LABELS = {
    "de": {
        "blank": "Rohteil",
        "scale": "Maßstab",
        "tools": "Werkzeuge",
        "zero": "Nullpunkt",
        "section": "Schnitt",
        "depth": "Tiefe",
        "slot": "Nut {w} breit",
        "table": "Koordinaten",
        "point": "Punkt",
        "units": "Maße in mm",
        "top": "Draufsicht",
        "exercise": "Aufgabe",
        "title": "Benennung",
        "centre": "M",
        "half": "Halbschnitt",
        "groove": "Einstich {w} breit",
        "thread_depth": "Gewindetiefe {d}",
        "pitch_circle": "TK Ø{d}",
    },
    "en": {
        "blank": "Blank",
        "scale": "Scale",
        "tools": "Tools",
        "zero": "Zero",
        "section": "Section",
        "depth": "depth",
        "slot": "slot {w} wide",
        "table": "Coordinates",
        "point": "Point",
        "units": "Dimensions in mm",
        "top": "Top view",
        "exercise": "Exercise",
        "title": "Title",
        "centre": "C",
        "half": "Half section",
        "groove": "groove {w} wide",
        "thread_depth": "thread depth {d}",
        "pitch_circle": "PCD Ø{d}",
    },
}


def value(v: float, lang: str, decimals: int = 3) -> str:
    """A dimension value as the drawing prints it: at most `decimals` decimals, a decimal comma in German."""
    s = f"{round(v, decimals):.{decimals}f}".rstrip("0").rstrip(".") if decimals > 0 else f"{round(v):d}"
    if s in ("-0", ""):
        s = "0"
    return s.replace(".", ",") if lang == "de" else s


# the addresses whose numbers are no geometry: block numbers, feeds, speeds, tools, functions, jumps, parameters
_NOT_GEOMETRY = frozenset(
    {"N", "F", "S", "T", "TC", "M", "G", "E", "H", "L", "O", "P", "Q", "V", "FRC", "#FRC"}
)
_WORD = re.compile(r"(?<![A-Za-z#_])(#?[A-Za-z]+)\s*=?\s*[-+]?(\d*)\.(\d+)")
_COMMENT = re.compile(r"\([^)\n]*\)|;[^\n]*")
MIN_DECIMALS, MAX_DECIMALS = 2, 3


def written_decimals(*programs: str) -> int:
    """The most decimals a geometry word of the programs is written with (X23.6: 1; K0.05: 2; comments not)."""
    most = 0
    for text in programs:
        for address, _, fraction in _WORD.findall(_COMMENT.sub(" ", text)):
            if address.upper() not in _NOT_GEOMETRY:
                most = max(most, len(fraction.rstrip("0")))
    return min(most, 4)


@dataclass(frozen=True)
class Numbers:
    """How a drawing prints its numbers: `decimals` (the drawing's precision), the decimal comma in German;
    `written` the decimals of the program's own words, which tell a stated value (23.6, 45 + 10.5) from one the
    interpreter computed (45 + 13.5 / tan 25° = 73.951…)."""

    lang: str = "de"
    decimals: int = MIN_DECIMALS
    written: int = MIN_DECIMALS

    @classmethod
    def of(cls, lang: str, *programs: str) -> Numbers:
        written = written_decimals(*programs)
        return cls(lang, min(MAX_DECIMALS, max(MIN_DECIMALS, written)), written)

    def text(self, v: float, lang: str | None = None) -> str:
        """The value at the drawing's precision: R20.999 → "21" (at two decimals)."""
        return value(v, self.lang if lang is None else lang, self.decimals)

    def raw(self, v: float) -> str:
        """A coordinate for the SVG's data-value (for machines: the point, to 6 decimals)."""
        return value(v, "en", 6)

    def nominal(self, v: float) -> str:
        """A size for the SVG's data-value (a radius, chamfer, angle, depth): the value as printed, in English."""
        return value(v, "en", self.decimals)

    def stated(self, v: float) -> bool:
        """Whether a coordinate is one the program can state: a number with no more decimals than the program's
        words have (a computed one, from an angle or a tangent, practically never is)."""
        return math.isclose(v, round(v, self.written), abs_tol=1e-6)

    def dimension(self, v: float, lang: str | None = None) -> str:
        """A coordinate as printed: the value, or in brackets as an auxiliary dimension where it is computed."""
        text = self.text(v, lang)
        return text if self.stated(v) else f"({text})"


def scale_text(s: float) -> str:
    return f"{num(s)}:1" if s >= 1 else f"1:{num(1 / s)}"


def fit(text: str, chars: int) -> str:
    return text if len(text) <= chars else text[: chars - 1] + "…"


def wrap(text: str, width: float, size: float, lines: int, char: float = CHAR) -> list[str] | None:
    """`text` in at most `lines` lines of `width` mm at the text height `size` (a character `char` text heights
    wide; broken between words, a word longer than a line where it must); None where it does not fit."""
    chars = max(1, int(width / (char * size)))
    out: list[str] = []
    for word in text.split():
        while len(word) > chars:
            if out and len(out[-1]) + 1 < chars:
                room = chars - len(out[-1]) - 1
                out[-1] += " " + word[:room]
                word = word[room:]
            else:
                out.append(word[:chars])
                word = word[chars:]
        if out and len(out[-1]) + 1 + len(word) <= chars:
            out[-1] += " " + word
        elif word:
            out.append(word)
    return out if len(out) <= lines else None


def _cell(svg: Svg, x: float, y: float, width: float, height: float, text: str, bold: bool) -> None:
    """A title block cell's text: one line at 3.5 mm (the title) or 3 mm, else wrapped into two or three lines
    at 3 or 2.5 mm, vertically centred; cut with "…" only where even three lines cannot hold it."""
    sizes = ((3.5, 1), (3.0, 2), (2.5, 3)) if bold else ((3.0, 1), (2.5, 2), (2.2, 3))
    char = BOLD if bold else CHAR
    for size, n in sizes:
        lines = wrap(text, width, size, n, char)
        if lines is not None:
            break
    else:
        size, n = sizes[-1]
        chars = int(width / (char * size))
        lines = (wrap(text, width, size, 99, char) or [text])[:n]
        lines[-1] = fit(lines[-1] + " …", chars)
    step = size * 1.15
    first = y + (height - step * (len(lines) - 1)) / 2 + 0.36 * size
    for k, line in enumerate(lines):
        svg.text((x, first + k * step), line, size=size, weight="bold" if bold else None)


def mark_views(svg: Svg, *parts: Box, margin: float = 4.0) -> None:
    """Note on the sheet where its views are: the parts' boxes and every text so far outside the title block, a
    margin around them (the SVG's data-views, which the page's viewer fits to the Zeichnung tab)."""
    tx, ty = SHEET[0] - MARGIN - TITLE_BLOCK[0], SHEET[1] - MARGIN - TITLE_BLOCK[1]
    boxes = [b for b in svg.taken if not (b[0] >= tx - 1.0 and b[1] >= ty - 1.0)] + list(parts)
    if not boxes:
        return
    svg.views = (
        max(0.0, min(b[0] for b in boxes) - margin),
        max(0.0, min(b[1] for b in boxes) - margin),
        min(SHEET[0], max(b[2] for b in boxes) + margin),
        min(SHEET[1], max(b[3] for b in boxes) + margin),
    )


def frame(svg: Svg) -> None:
    """The sheet's border, MARGIN inside the paper's edge."""
    svg.path(
        f"M{num(MARGIN)} {num(MARGIN)} H{num(SHEET[0] - MARGIN)} V{num(SHEET[1] - MARGIN)} H{num(MARGIN)} Z",
        width=THICK,
    )


def exercise_tool_names(exercise: Exercise) -> dict[int, str]:
    """The tools the exercise itself names (its `tools:` entries with a `name`), by number: what the title block
    and a tap's thread size read (the table makes up a name for every other tool)."""
    out: dict[int, str] = {}
    for entry in exercise.tools:
        name, number = entry.get("name"), entry.get("number")
        if isinstance(name, str) and name.strip() and isinstance(number, int):
            out[number] = name.strip()
    return out


def title_block(svg: Svg, exercise: Exercise, scale: float, lang: str) -> None:
    """The title block at the bottom right: title, blank (and scale), tools, workpiece zero; the exercise's id
    under it."""
    labels = LABELS[lang]
    w, h = TITLE_BLOCK
    x, y = SHEET[0] - MARGIN - w, SHEET[1] - MARGIN - h
    svg.path(f"M{num(x)} {num(y)} h{num(w)} v{num(h)} h{num(-w)} Z", width=THICK)
    for k in (1, 2, 3):
        svg.line((x, y + k * h / 4), (x + w, y + k * h / 4), width=THIN)
    svg.line((x + 28, y), (x + 28, y + h), width=THIN)
    st = exercise.stock.stock()
    tools = []
    named = exercise_tool_names(exercise)
    for t in sorted(exercise.tool_table().tools.values(), key=lambda t: t.number):
        names = KIND_NAMES_DE if lang == "de" else KIND_NAMES_EN
        if t.kind == "turning":  # a lathe tool: its insert's nose radius, not a diameter
            tools.append(f"T{t.number} R{value(t.nose_radius, lang)}")
        elif t.number in named:  # the exercise names the tool ("Gewindebohrer M8 × 1,25"): as it says
            tools.append(f"T{t.number} {named[t.number]}")
        else:
            tools.append(f"T{t.number} {names.get(t.kind, t.kind)} Ø{value(t.diameter, lang)}")
    if exercise.blank is not None:  # a bar or tube: diameters and length
        b = exercise.blank
        bore = f"/Ø{value(b.inner_diameter, lang)}" if b.inner_diameter else ""
        blank = f"Ø{value(b.diameter, lang)}{bore} × {value(b.length, lang)}"
    else:
        blank = f"{value(st.x1 - st.x0, lang)} × {value(st.y1 - st.y0, lang)} × {value(st.z1 - st.z0, lang)}"
    blank += f" · {labels['scale']} {scale_text(scale)} · {labels['units']}"
    rows = [
        (labels["title"], exercise.title.get(lang)),
        (labels["blank"], blank),
        (labels["tools"], ", ".join(tools)),
        (labels["zero"], exercise.stock.zero.get(lang)),
    ]
    for k, (label, text) in enumerate(rows):
        svg.text((x + 1.5, y + k * h / 4 + 5.2), label, size=2.5)
        _cell(svg, x + 30, y + k * h / 4, w - 31.5, h / 4, text, bold=k == 0)
    svg.text(
        (x + w, y + h + 4.0), f"PAL Trainer · {labels['exercise']} {exercise.id}", size=2.5, anchor="end"
    )
