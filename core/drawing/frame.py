"""What every drawing sheet has, milled or turned: the A4 frame, the scales, the title block, and how a number
is printed (at most 3 decimals, the decimal comma in German). core/drawing (milled parts) and
core/drawing/turned.py (turned parts) both draw their sheet with these."""

from __future__ import annotations

from core.drawing.svg import THICK, THIN, Svg, num
from core.exercises import Exercise
from core.tools import KIND_NAMES_DE

SHEET = (297.0, 210.0)  # A4 landscape, mm
MARGIN = 10.0
TITLE_BLOCK = (112.0, 34.0)
SCALES = (10.0, 5.0, 2.0, 1.0, 0.5, 0.2, 0.1, 0.05, 0.02, 0.01)
TEXT = 3.5  # mm, dimension text height
SPACING = 4.5  # mm between neighbouring ordinate texts

KIND_NAMES_EN = {"end_mill": "end mill", "slot_drill": "slot drill", "ball_nose": "ball-nose mill",
                 "torus": "torus mill", "twist_drill": "twist drill", "spot_drill": "spot drill"}

LABELS = {
    "de": {"blank": "Rohteil", "scale": "Maßstab", "tools": "Werkzeuge", "zero": "Nullpunkt", "section": "Schnitt",
           "depth": "Tiefe", "slot": "Nut {w} breit", "table": "Koordinaten", "point": "Punkt", "units": "Maße in mm",
           "top": "Draufsicht", "exercise": "Aufgabe", "title": "Benennung", "centre": "M",
           "half": "Halbschnitt", "groove": "Einstich {w} breit", "thread_depth": "Gewindetiefe {d}"},
    "en": {"blank": "Blank", "scale": "Scale", "tools": "Tools", "zero": "Zero", "section": "Section",
           "depth": "depth", "slot": "slot {w} wide", "table": "Coordinates", "point": "Point", "units": "Dimensions in mm",
           "top": "Top view", "exercise": "Exercise", "title": "Title", "centre": "C",
           "half": "Half section", "groove": "groove {w} wide", "thread_depth": "thread depth {d}"},
}


def value(v: float, lang: str) -> str:
    """A dimension value as the drawing prints it: at most 3 decimals, a decimal comma in German."""
    s = f"{round(v, 3):.3f}".rstrip("0").rstrip(".")
    if s in ("-0", ""):
        s = "0"
    return s.replace(".", ",") if lang == "de" else s


def scale_text(s: float) -> str:
    return f"{num(s)}:1" if s >= 1 else f"1:{num(1 / s)}"


def fit(text: str, chars: int) -> str:
    return text if len(text) <= chars else text[: chars - 1] + "…"


def frame(svg: Svg) -> None:
    """The sheet's border, MARGIN inside the paper's edge."""
    svg.path(f"M{num(MARGIN)} {num(MARGIN)} H{num(SHEET[0] - MARGIN)} V{num(SHEET[1] - MARGIN)} H{num(MARGIN)} Z",
             width=THICK)


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
    for t in sorted(exercise.tool_table().tools.values(), key=lambda t: t.number):
        names = KIND_NAMES_DE if lang == "de" else KIND_NAMES_EN
        if t.kind == "turning":  # a lathe tool: its insert's nose radius, not a diameter
            tools.append(f"T{t.number} R{value(t.nose_radius, lang)}")
        else:
            tools.append(f"T{t.number} {names.get(t.kind, t.kind)} Ø{value(t.diameter, lang)}")
    if exercise.blank is not None:  # a bar or tube: diameters and length
        b = exercise.blank
        bore = f"/Ø{value(b.inner_diameter, lang)}" if b.inner_diameter else ""
        blank = f"Ø{value(b.diameter, lang)}{bore} × {value(b.length, lang)}"
    else:
        blank = f"{value(st.x1 - st.x0, lang)} × {value(st.y1 - st.y0, lang)} × {value(st.z1 - st.z0, lang)}"
    blank += f" · {labels['scale']} {scale_text(scale)} · {labels['units']}"
    rows = [(labels["title"], exercise.title.get(lang)), (labels["blank"], blank),
            (labels["tools"], ", ".join(tools)), (labels["zero"], exercise.stock.zero.get(lang))]
    for k, (label, text) in enumerate(rows):
        ty = y + k * h / 4 + 5.6
        svg.text((x + 1.5, ty), label, size=2.5)
        big = k == 0 and len(text) <= 34  # what fits the 80 mm column: bold 3.5 mm or regular 3 mm text
        svg.text((x + 30, ty), fit(text, 34 if big else 43), size=3.5 if big else 3.0,
                 weight="bold" if k == 0 else None)
    svg.text((x + w, y + h + 4.0), f"PAL Trainer · {labels['exercise']} {exercise.id}", size=2.5, anchor="end")
