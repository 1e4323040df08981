"""The 2D picture of a program's result, as the classic CNC simulators draw it: what the page shows while the
3D view is off (a school PC without graphics acceleration).

Milling (`mill_picture`): the plan view (X right, Y up) — the stock's outline, the finished part's depths as
a calm colour ramp with its legend in mm, the tool-centre path (rapid moves dashed orange, feed moves solid
blue), the programmed contour where compensation moves the tool off it (green), plunges as rings, the axes
with coordinates, the workpiece zero, and the blocks an error kept from running (red, with their line).
Turning (`lathe_picture`): the drawing view (Z right, X up, the chuck on the left) — the upper half cut open
and hatched, the lower half the part as seen, the blank's outline, the tool's path above the axis, the same
axes, zero, colours and markers.

Pure functions of the pipeline's result (core.pipeline.run) and the simulation's (core.sim) → SVG text, with
presentation attributes only (no <style>, no script): it shows the same as an <img>, opened directly under a
strict Content-Security-Policy, or printed. The cost is bounded (PictureLimits): the depth raster's pixels,
the path's points, the markers; what a cap left out is said in the picture and in `Picture.info`.
"""

from __future__ import annotations

import base64
import itertools
import math
import struct
import zlib
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from typing import Any, Literal
from xml.sax.saxutils import escape, quoteattr

import numpy as np
import numpy.typing as npt

from core.diagnostics import Severity
from core.geometry.polyline import simplified
from core.toolpath import Move

Lang = Literal["de", "en"]
Point = tuple[float, float]
Array = npt.NDArray[np.float64]


@dataclass(frozen=True)
class PictureLimits:
    """What one picture may cost."""

    raster: int = 400  # pixels of the depth raster along its longer side (cells pooled beyond)
    points: int = (
        8000  # points of the drawn path: rapid, feed and contour together (the rest left out, said so)
    )
    markers: int = (
        20  # blocks with an error marked in the picture (all of them named in the legend, up to 40)
    )
    plunges: int = 400  # plunge rings


DEFAULT_LIMITS = PictureLimits()

# the colours of docs/UI.md (the 3D view and its legend use the same)
RAPID = "#ef6c00"  # rapid moves: dashed orange
FEED = "#1565c0"  # feed moves: solid blue
CONTOUR = "#2e7d32"  # the programmed contour: green
ERROR = "#c62828"  # a block an error kept from running
INK = "#262a31"  # outlines, the zero symbol
MUTED = "#59606b"  # axis texts (4.5:1 on white)
GRID = "#e3e6ea"
PAPER = "#ffffff"
TOP = (226, 229, 234)  # the stock's untouched top face (the 3D view's stock, lighter)
# the depth below the top face, shallow → deepest cut (warm: the blue feed path and the green contour stand out)
RAMP = ((250, 236, 200), (242, 205, 150), (226, 168, 112), (199, 130, 90))
SECTION = "#dec08a"  # the lathe's cut face, hatched (as the 3D view's half section)
HATCH = "#8a6238"
REMOVED = "#eef0f3"  # the blank's material the program removed
VIEW_LIGHT, VIEW_DARK = "#d5d9e0", "#9aa1ad"  # the turned part as seen: a cylinder's shading
JAW = "#a4abb6"

FONT = "system-ui, 'Segoe UI', 'DejaVu Sans', Arial, sans-serif"
WIDTH = 560  # the picture's width in its own units (pixels at 100 %)
LEFT, RIGHT, TOP_PAD, AXIS_PAD = 50.0, 16.0, 14.0, 34.0  # around the plot: tick labels left and below
MAX_PLOT_HEIGHT = 400.0
MIN_WIDTH = 440.0  # the legend needs this much
TICK_FONT, LEGEND_FONT = 12.5, 13.5

TEXTS: dict[str, dict[str, str]] = {
    "de": {
        "title_mill": "Draufsicht nach dem Programm",
        "title_lathe": "Drehteil nach dem Programm (Halbschnitt)",
        "depth": "Tiefe Z in mm",
        "top": "Oberseite",
        "through": "durchgefräst",
        "rapid": "Eilgang",
        "feed": "Vorschub (Werkzeugmitte)",
        "contour": "programmierte Kontur",
        "plunge": "Eintauchen",
        "zero": "Werkstücknullpunkt",
        "error": "Satz mit Fehler, nicht ausgeführt",
        "line": "Zeile",
        "lines": "Zeilen",
        "stock": "Rohteil",
        "section": "Schnitt",
        "view": "Ansicht",
        "removed": "abgespant",
        "cut_path": "Weg gekürzt: {shown} von {total} Wegpunkten gezeichnet.",
        "raster": "Raster {cell} mm",
        "more_errors": "und {n} weitere",
        "outside": "außerhalb",
        "x_diameter": "X (Ø)",
        "no_moves": "Noch keine Bewegung.",
    },
    "en": {
        "title_mill": "Plan view after the program",
        "title_lathe": "Turned part after the program (half section)",
        "depth": "Depth Z in mm",
        "top": "top face",
        "through": "cut through",
        "rapid": "Rapid",
        "feed": "Feed (tool centre)",
        "contour": "programmed contour",
        "plunge": "plunge",
        "zero": "Workpiece zero",
        "error": "Block with an error, not executed",
        "line": "line",
        "lines": "lines",
        "stock": "stock",
        "section": "section",
        "view": "view",
        "removed": "removed",
        "cut_path": "Path cut short: {shown} of {total} path points drawn.",
        "raster": "raster {cell} mm",
        "more_errors": "and {n} more",
        "outside": "outside",
        "x_diameter": "X (Ø)",
        "no_moves": "No moves yet.",
    },
}


@dataclass
class Picture:
    """The SVG and what it shows: `info` has the raster's size and cell (mm), the path's points drawn and in
    all, whether the path was cut short, the marked error lines."""

    svg: str
    info: dict[str, Any] = field(default_factory=dict)


def num(value: float, lang: Lang = "de", digits: int = 3) -> str:
    """A number as the trainee writes it: at most `digits` decimals, no trailing zeros, German decimal comma."""
    text = f"{value:.{digits}f}".rstrip("0").rstrip(".")
    if text in ("-0", ""):
        text = "0"
    return text.replace(".", ",") if lang == "de" else text


def _c(v: float) -> str:
    """A coordinate in the SVG source (2 decimals of a pixel)."""
    text = f"{v:.2f}".rstrip("0").rstrip(".")
    return "0" if text in ("-0", "") else text


def _attrs(**attrs: Any) -> str:
    return "".join(
        f" {k.rstrip('_').replace('_', '-')}={quoteattr(_c(v) if isinstance(v, float) else str(v))}"
        for k, v in attrs.items()
        if v is not None
    )


def _el(tag: str, text: str | None = None, **attrs: Any) -> str:
    if text is None:
        return f"<{tag}{_attrs(**attrs)}/>"
    return f"<{tag}{_attrs(**attrs)}>{escape(text)}</{tag}>"


def nice_step(span: float, count: int = 7) -> float:
    """A round tick step (1, 2, 2.5, 5 × 10^k) giving about `count` ticks over `span`."""
    raw = max(span, 1e-9) / max(count, 1)
    power = 10.0 ** math.floor(math.log10(raw))
    for m in (1.0, 2.0, 2.5, 5.0, 10.0):
        if m * power >= raw - 1e-12:
            return m * power
    return 10 * power


@dataclass
class _Frame:
    """The plot: `x0…x1` × `y0…y1` in mm, drawn at `scale` px per mm with its top-left corner at (left, top)."""

    x0: float
    x1: float
    y0: float
    y1: float
    scale: float
    left: float
    top: float

    def px(self, x: float, y: float) -> Point:
        return self.left + (x - self.x0) * self.scale, self.top + (self.y1 - y) * self.scale

    @property
    def width(self) -> float:
        return (self.x1 - self.x0) * self.scale

    @property
    def height(self) -> float:
        return (self.y1 - self.y0) * self.scale

    def inside(self, x: float, y: float) -> bool:
        return self.x0 - 1e-9 <= x <= self.x1 + 1e-9 and self.y0 - 1e-9 <= y <= self.y1 + 1e-9


def _fit(
    box: tuple[float, float, float, float], reach: tuple[float, float, float, float], points: Iterable[Point]
) -> tuple[float, float, float, float]:
    """The extent shown: the part's box and every path point within `reach` of it, with a margin."""
    x0, y0, x1, y1 = box
    rx0, ry0, rx1, ry1 = reach
    for x, y in points:
        if rx0 <= x <= rx1 and ry0 <= y <= ry1:
            x0, y0, x1, y1 = min(x0, x), min(y0, y), max(x1, x), max(y1, y)
    margin = max(0.05 * max(x1 - x0, y1 - y0), 2.0)
    return x0 - margin, y0 - margin, x1 + margin, y1 + margin


def _frame(extent: tuple[float, float, float, float]) -> tuple[_Frame, float]:
    """The plot for an extent, and the picture's width."""
    x0, y0, x1, y1 = extent
    w, h = max(x1 - x0, 1e-3), max(y1 - y0, 1e-3)
    scale = min((WIDTH - LEFT - RIGHT) / w, MAX_PLOT_HEIGHT / h)
    width = max(LEFT + w * scale + RIGHT, MIN_WIDTH)
    left = LEFT + (width - LEFT - RIGHT - w * scale) / 2
    return _Frame(x0, x1, y0, y1, scale, left, TOP_PAD), width


def _frame_info(frame: _Frame) -> str:
    """Where the plot is: "u0 v1 scale left top" (mm, px per mm, px): a point (u, v) in mm is drawn at
    (left + (u − u0)·scale, top + (v1 − v)·scale)."""
    return " ".join(f"{v:.5f}" for v in (frame.x0, frame.y1, frame.scale, frame.left, frame.top))


def _axes(frame: _Frame, lang: Lang, x_name: str, y_name: str, y_label: Any = None) -> list[str]:
    """Grid lines and ticks with their coordinates below (X, or Z on a lathe) and to the left; the axis names."""
    out: list[str] = []
    fx0, fy0 = frame.px(frame.x0, frame.y0)
    fx1, fy1 = frame.px(frame.x1, frame.y1)
    label_y = y_label or (lambda v: num(v, lang))
    ticks_x = _ticks(frame.x0, frame.x1, frame.width / 62)
    ticks_y = _ticks(frame.y0, frame.y1, frame.height / 34)
    for v in ticks_x:
        x, _ = frame.px(v, 0.0)
        out.append(_el("line", x1=x, y1=fy1, x2=x, y2=fy0, stroke=GRID, stroke_width="1"))
        out.append(_el("line", x1=x, y1=fy0, x2=x, y2=fy0 + 4, stroke=MUTED, stroke_width="1"))
        out.append(
            _el(
                "text",
                num(v, lang),
                x=x,
                y=fy0 + 16,
                font_size=_c(TICK_FONT),
                text_anchor="middle",
                fill=MUTED,
            )
        )
    for v in ticks_y:
        _, y = frame.px(0.0, v)
        out.append(_el("line", x1=fx0, y1=y, x2=fx1, y2=y, stroke=GRID, stroke_width="1"))
        out.append(_el("line", x1=fx0 - 4, y1=y, x2=fx0, y2=y, stroke=MUTED, stroke_width="1"))
        out.append(
            _el(
                "text", label_y(v), x=fx0 - 6, y=y + 4, font_size=_c(TICK_FONT), text_anchor="end", fill=MUTED
            )
        )
    out.append(
        _el(
            "rect",
            x=fx0,
            y=fy1,
            width=frame.width,
            height=frame.height,
            fill="none",
            stroke="#c9ced6",
            stroke_width="1",
        )
    )
    out.append(
        _el(
            "text",
            x_name,
            x=fx1,
            y=fy0 + 30,
            font_size=_c(TICK_FONT),
            text_anchor="end",
            fill=MUTED,
            font_weight="600",
        )
    )
    out.append(
        _el(
            "text",
            y_name,
            x=fx0 - 6,
            y=fy1 - 3,
            font_size=_c(TICK_FONT),
            text_anchor="end",
            fill=MUTED,
            font_weight="600",
        )
    )
    return out


def _ticks(lo: float, hi: float, count: float) -> list[float]:
    step = nice_step(hi - lo, max(2, int(count)))
    first = math.ceil(lo / step - 1e-9) * step
    return [round(first + k * step, 9) for k in range(int((hi - first) / step + 1e-9) + 1)]


def _zero_symbol(x: float, y: float, r: float = 6.5) -> list[str]:
    """The workpiece zero as drawings show it: a circle with two filled quarters."""
    return [
        _el("circle", cx=x, cy=y, r=r + 1.5, fill=PAPER, opacity="0.85"),
        _el("circle", cx=x, cy=y, r=r, fill=PAPER, stroke=INK, stroke_width="1.3"),
        _el(
            "path",
            d=f"M{_c(x)} {_c(y)}h{_c(r)}a{_c(r)} {_c(r)} 0 0 0 {_c(-r)} {_c(-r)}z"
            f"M{_c(x)} {_c(y)}h{_c(-r)}a{_c(r)} {_c(r)} 0 0 0 {_c(r)} {_c(r)}z",
            fill=INK,
        ),
    ]


def _zero_axes(frame: _Frame, names: tuple[str, str]) -> list[str]:
    """Short arrows from the workpiece zero along the two axes, with their names; the zero symbol over them."""
    if not frame.inside(0.0, 0.0):
        return []
    x, y = frame.px(0.0, 0.0)
    length = 34.0
    out = []
    for (dx, dy), name in zip(((1.0, 0.0), (0.0, -1.0)), names, strict=True):
        ex, ey = x + dx * length, y + dy * length
        wing = (-dy * 3.5, dx * 3.5)
        out.append(_el("line", x1=x, y1=y, x2=ex - dx * 6, y2=ey - dy * 6, stroke=INK, stroke_width="1.4"))
        out.append(
            _el(
                "path",
                d=f"M{_c(ex)} {_c(ey)}L{_c(ex - dx * 7 + wing[0])} {_c(ey - dy * 7 + wing[1])}"
                f"L{_c(ex - dx * 7 - wing[0])} {_c(ey - dy * 7 - wing[1])}z",
                fill=INK,
            )
        )
        out.append(
            _el(
                "text",
                name,
                x=ex + dx * 4 + (4 if dy else 0),
                y=ey + dy * 2 + (4 if dx else 0),
                font_size="12",
                font_weight="700",
                fill=INK,
            )
        )
    return out + _zero_symbol(x, y)


# -- the path --------------------------------------------------------------------------------------------
# A polyline as drawn: its start (u, v) and steps, each ("L", u, v) or an arc ("A", u, v, radius, large, sweep)
# in the picture's mm; arcs in the plane of the picture stay arcs (SVG's own), others become chords.
Step = tuple[Any, ...]


@dataclass
class _Path:
    """The path as drawn: rapid, feed and contour polylines (start, steps); the plunges."""

    rapid: list[tuple[Point, list[Step]]] = field(default_factory=list)
    feed: list[tuple[Point, list[Step]]] = field(default_factory=list)
    contour: list[tuple[Point, list[Step]]] = field(default_factory=list)
    plunges: list[Point] = field(default_factory=list)
    points: int = 0  # drawn
    total: int = 0  # would have been drawn without the cap
    cut: bool = False


def _uv(p: Sequence[float], axes: tuple[int, int]) -> Point:
    return float(p[axes[0]]), float(p[axes[1]])


def _arc_steps(
    start: Sequence[float],
    end: Sequence[float],
    centre: Sequence[float],
    direction: str | None,
    angle: float,
    axes: tuple[int, int],
) -> list[Step] | None:
    """An arc in the picture's plane as SVG arc steps (a full circle as two halves); None if its radius at the
    start and at the end differ (then it is drawn as chords)."""
    (su, sv), (eu, ev), (cu, cv) = _uv(start, axes), _uv(end, axes), _uv(centre, axes)
    r = math.hypot(su - cu, sv - cv)
    if r < 1e-6 or abs(math.hypot(eu - cu, ev - cv) - r) > max(1e-3, 1e-4 * r):
        return None
    sweep = 1 if direction == "ccw" else 0  # the picture's v axis points up, SVG's y down
    if angle >= 359.999:  # a full circle: through the point opposite the start
        mid = (2 * cu - su, 2 * cv - sv)
        return [("A", *mid, r, 0, sweep), ("A", eu, ev, r, 0, sweep)]
    return [("A", eu, ev, r, 1 if angle > 180 else 0, sweep)]


def _move_steps(m: Move, axes: tuple[int, int], tolerance: float) -> list[Step]:
    from core.geometry.planes import AXES

    if m.kind == "arc" and m.center is not None and m.angle is not None and AXES[m.plane][:2] == axes:
        steps = _arc_steps(m.start, m.end, m.center, m.direction, m.angle, axes)
        if steps is not None:
            return steps
    return [("L", *_uv(p, axes)) for p in m.points(tolerance, 256)[1:]]


def _contour_steps(m: Move, start: Sequence[float], axes: tuple[int, int], tolerance: float) -> list[Step]:
    """The programmed contour of a compensated move from `start` (the previous contour point): a line, or the
    arc about the same centre."""
    end = m.programmed_end or m.end
    if m.kind == "arc" and m.center is not None and m.angle is not None:
        from core.geometry.planes import AXES, from_plane, to_plane

        if AXES[m.plane][:2] == axes:
            su, sv = _uv(start, axes)
            eu, ev = _uv(end, axes)
            cu, cv = _uv(m.center, axes)
            a0, a1 = math.atan2(sv - cv, su - cu), math.atan2(ev - cv, eu - cu)
            sweep = (a1 - a0) % (2 * math.pi) if m.direction == "ccw" else (a0 - a1) % (2 * math.pi)
            if sweep < 1e-9 and m.angle > 180:
                sweep = 2 * math.pi
            steps = _arc_steps(start, end, m.center, m.direction, math.degrees(sweep), axes)
            if steps is not None:
                return steps
        s, e, c = (to_plane((float(p[0]), float(p[1]), float(p[2])), m.plane) for p in (start, end, m.center))
        r = math.hypot(s[0] - c[0], s[1] - c[1])
        if r > 1e-6:
            a0, a1 = math.atan2(s[1] - c[1], s[0] - c[0]), math.atan2(e[1] - c[1], e[0] - c[0])
            turn = (a1 - a0) % (2 * math.pi) if m.direction == "ccw" else -((a0 - a1) % (2 * math.pi))
            n = max(
                2, min(128, math.ceil(abs(turn) / max(2 * math.acos(max(-1.0, 1 - tolerance / r)), 1e-3)))
            )
            return [
                (
                    "L",
                    *_uv(
                        from_plane(
                            (
                                c[0] + r * math.cos(a0 + turn * k / n),
                                c[1] + r * math.sin(a0 + turn * k / n),
                                s[2] + (e[2] - s[2]) * k / n,
                            ),
                            m.plane,
                        ),
                        axes,
                    ),
                )
                for k in range(1, n + 1)
            ]
    return [("L", *_uv(end, axes))]


def _append(lines: list[tuple[Point, list[Step]]], start: Point, steps: list[Step], join: bool) -> None:
    if join and lines:
        last = lines[-1][1][-1][1:3] if lines[-1][1] else lines[-1][0]
        if abs(last[0] - start[0]) < 1e-9 and abs(last[1] - start[1]) < 1e-9:
            lines[-1][1].extend(steps)
            return
    lines.append((start, list(steps)))


def _path(moves: Sequence[Move], axes: tuple[int, int], tolerance: float, limits: PictureLimits) -> _Path:
    """The moves projected on the picture's plane (`axes`: the indices of its u and v), consecutive moves of
    one kind as one polyline, arcs as arcs (or chords within `tolerance` mm); at most `limits.points` points."""
    out = _Path()
    budget = limits.points
    last_kind: str | None = None
    previous_contour: Sequence[float] | None = None
    seen_plunges: set[tuple[int, int]] = set()
    for m in moves:
        if out.cut:  # past the cap: only counted, never drawn (and no point made)
            out.total += min(m.chords(tolerance), 256) + 1
            continue
        kind = "rapid" if m.kind == "rapid" else "feed"
        start = _uv(m.start, axes)
        steps = _move_steps(m, axes, tolerance)
        out.total += len(steps) + 1
        compensated = (
            m.programmed_end is not None
            and max(abs(a - b) for a, b in zip(m.programmed_end, m.end, strict=True)) > 1e-6
        )
        contour = None
        if compensated and kind == "feed":
            contour_start = previous_contour if previous_contour is not None else m.programmed_end
            contour = (_uv(contour_start, axes), _contour_steps(m, contour_start, axes, tolerance))  # type: ignore[arg-type]
            out.total += len(contour[1]) + 1
        previous_contour = m.programmed_end if m.programmed_end is not None else m.end
        cost = len(steps) + 1 + (len(contour[1]) + 1 if contour else 0)
        if cost > budget:
            out.cut = True
            continue
        end = steps[-1][1:3]
        if m.kind != "arc" and abs(start[0] - end[0]) < 1e-6 and abs(start[1] - end[1]) < 1e-6:
            # along the axis of view: a plunge (feed) shows as a ring, a rapid not at all
            if kind == "feed" and len(out.plunges) < limits.plunges:
                key = (round(start[0] / max(tolerance, 1e-6)), round(start[1] / max(tolerance, 1e-6)))
                if key not in seen_plunges:
                    seen_plunges.add(key)
                    out.plunges.append(start)
            last_kind = None
            continue
        _append(out.rapid if kind == "rapid" else out.feed, start, steps, last_kind == kind)
        budget -= cost
        out.points += cost
        last_kind = kind
        if contour:
            _append(out.contour, contour[0], contour[1], True)
    return out


def _polyline_d(frame: _Frame, line: tuple[Point, list[Step]]) -> str:
    (u, v), steps = line
    x, y = frame.px(u, v)
    parts = [f"M{_c(x)} {_c(y)}"]
    for step in steps:
        x, y = frame.px(step[1], step[2])
        if step[0] == "A":
            r = _c(step[3] * frame.scale)
            parts.append(f"A{r} {r} 0 {step[4]} {step[5]} {_c(x)} {_c(y)}")
        else:
            parts.append(f"L{_c(x)} {_c(y)}")
    return "".join(parts)


def _draw_path(frame: _Frame, path: _Path) -> list[str]:
    """Contour under the path, then feed, then rapid (dashed), each with a white halo: readable on any depth."""
    out: list[str] = []
    for lines, colour, width, dash in (
        (path.contour, CONTOUR, 2.2, None),
        (path.feed, FEED, 1.8, None),
        (path.rapid, RAPID, 1.5, "6 4"),
    ):
        if not lines:
            continue
        d = "".join(_polyline_d(frame, line) for line in lines)
        out.append(
            _el(
                "path",
                d=d,
                fill="none",
                stroke=PAPER,
                stroke_width=_c(width + 2.4),
                stroke_opacity="0.8",
                stroke_linejoin="round",
                stroke_linecap="round",
            )
        )
        out.append(
            _el(
                "path",
                d=d,
                fill="none",
                stroke=colour,
                stroke_width=_c(width),
                stroke_dasharray=dash,
                stroke_linejoin="round",
                stroke_linecap="butt" if dash else "round",
            )
        )
    for u, v in path.plunges:
        x, y = frame.px(u, v)
        out.append(_el("circle", cx=x, cy=y, r="3.2", fill=PAPER, stroke=FEED, stroke_width="1.6"))
    return out


class _Labels:
    """Labels placed so that they overlap neither each other nor the marks they belong to, inside the plot."""

    def __init__(self, frame: _Frame) -> None:
        self.frame = frame
        self.taken: list[tuple[float, float, float, float]] = []

    def block(self, x: float, y: float, r: float) -> None:
        self.taken.append((x - r, y - r, x + r, y + r))

    def place(
        self, x: float, y: float, width: float, height: float, prefer_left: bool
    ) -> tuple[float, float]:
        """The top left corner of a label beside the point (x, y): right or left of it, above or below."""
        f = self.frame
        sides = [
            (10.0, -height - 3),
            (10.0, 4.0),
            (-10 - width, -height - 3),
            (-10 - width, 4.0),
            (10.0, -height - 22),
            (-10 - width, 22.0),
        ]
        if prefer_left:
            sides = sides[2:4] + sides[:2] + sides[4:]
        first = None
        for dx, dy in sides:
            tx = min(max(x + dx, f.left + 2), f.left + f.width - width - 2)
            ty = min(max(y + dy, f.top + 2), f.top + f.height - height - 2)
            box = (tx, ty, tx + width, ty + height)
            first = first or box
            if not any(a < box[2] and box[0] < c and b < box[3] and box[1] < d for a, b, c, d in self.taken):
                self.taken.append(box)
                return tx, ty
        assert first is not None
        self.taken.append(first)
        return first[0], first[1]


def _leaving(
    frame: _Frame, moves: Sequence[Move], axes: tuple[int, int], lang: Lang, labels: _Labels, most: int = 3
) -> list[str]:
    """Where a move leaves the picture (the retract to the tool change point, say): a dot at the edge and the
    point it goes to."""
    out: list[str] = []
    count = 0
    for m in moves:
        if count >= most:
            break
        a, b = _uv(m.start, axes), _uv(m.end, axes)
        if not frame.inside(*a) or frame.inside(*b):
            continue
        t = _exit(frame, a, b)
        if t is None:
            continue
        count += 1
        x, y = frame.px(a[0] + (b[0] - a[0]) * t, a[1] + (b[1] - a[1]) * t)
        names = ("X", "Y", "Z")
        target = "→ " + " ".join(f"{names[i]}{num(m.end[i], lang)}" for i in range(3))
        width = 6.4 * len(target) + 8
        tx, ty = labels.place(x, y, width, 15.0, x > frame.left + frame.width / 2)
        out.append(_el("circle", cx=x, cy=y, r="3", fill=RAPID))
        out.append(_el("rect", x=tx, y=ty, width=width, height="15", rx="3", fill=PAPER, opacity="0.9"))
        out.append(_el("text", target, x=tx + 4, y=ty + 11.5, font_size="11.5", fill=MUTED))
    return out


def _exit(frame: _Frame, a: Point, b: Point) -> float | None:
    """The parameter t (0…1) where the segment a→b leaves the frame (Liang–Barsky)."""
    t_out = 1.0
    d = (b[0] - a[0], b[1] - a[1])
    for p, q in (
        (-d[0], a[0] - frame.x0),
        (d[0], frame.x1 - a[0]),
        (-d[1], a[1] - frame.y0),
        (d[1], frame.y1 - a[1]),
    ):
        if abs(p) < 1e-12:
            if q < 0:
                return None
            continue
        r = q / p
        if p > 0:
            t_out = min(t_out, r)
    return t_out


# -- blocks an error kept from running --------------------------------------------------------------------
def skipped_blocks(toolpath: Any) -> list[int]:
    """The lines of the program file whose block has an error and made no move: the interpreter did not run
    it (core/interpreter: a block with an error is not executed)."""
    moved = {m.line for m in toolpath.moves if m.source is None}
    lines = {
        d.span.line
        for d in toolpath.diagnostics
        if d.severity is Severity.ERROR and d.source is None and d.span.line >= 1
    }
    return sorted(line for line in lines if line not in moved)


def _markers(
    frame: _Frame, toolpath: Any, axes: tuple[int, int], lang: Lang, limits: PictureLimits, labels: _Labels
) -> tuple[list[str], list[int]]:
    """A red marker with its line(s) at the program's position when a block was skipped for an error (where
    the block would have started)."""
    lines = skipped_blocks(toolpath)
    groups: dict[tuple[int, int], list[int]] = {}
    where: dict[tuple[int, int], Point] = {}
    for line in lines:
        _, position = toolpath.state_at(line)
        u, v = float(position[axes[0]]), float(position[axes[1]])
        u, v = min(max(u, frame.x0), frame.x1), min(max(v, frame.y0), frame.y1)
        key = (round(u * 10), round(v * 10))
        groups.setdefault(key, []).append(line)
        where[key] = (u, v)
    out: list[str] = []
    t = TEXTS[lang]
    shown = list(groups.items())[: limits.markers]
    for key, _ in shown:
        labels.block(*frame.px(*where[key]), 9.0)
    for key, group in shown:
        x, y = frame.px(*where[key])
        label = f"{t['line'] if len(group) == 1 else t['lines']} {', '.join(map(str, group[:4]))}" + (
            "…" if len(group) > 4 else ""
        )
        out.append(_el("circle", cx=x, cy=y, r="7", fill=PAPER, stroke=ERROR, stroke_width="2"))
        out.append(
            _el(
                "path",
                d=f"M{_c(x - 3.5)} {_c(y - 3.5)}L{_c(x + 3.5)} {_c(y + 3.5)}"
                f"M{_c(x + 3.5)} {_c(y - 3.5)}L{_c(x - 3.5)} {_c(y + 3.5)}",
                stroke=ERROR,
                stroke_width="2",
            )
        )
        width = 7.0 * len(label) + 8
        bx, by = labels.place(x, y, width, 16.0, x > frame.left + frame.width * 0.7)
        out.append(
            _el(
                "rect",
                x=bx,
                y=by,
                width=width,
                height="16",
                rx="3",
                fill=PAPER,
                opacity="0.9",
                stroke=ERROR,
                stroke_width="1",
            )
        )
        out.append(_el("text", label, x=bx + 4, y=by + 12, font_size="12", font_weight="600", fill=ERROR))
    return out, lines


# -- the legend ---------------------------------------------------------------------------------------------
def _legend_rows(
    items: list[tuple[str, str]], width: float, left: float
) -> tuple[list[list[tuple[str, str, float]]], float]:
    """Legend items (symbol, text) flowed into rows within `width`."""
    rows: list[list[tuple[str, str, float]]] = [[]]
    x = 0.0
    for symbol, text in items:
        w = 30 + 0.56 * LEGEND_FONT * len(text) + 18
        if x + w > width and rows[-1]:
            rows.append([])
            x = 0.0
        rows[-1].append((symbol, text, left + x))
        x += w
    return rows, 20.0 * len(rows)


def _symbol(kind: str, x: float, y: float) -> list[str]:
    if kind == "rapid":
        return [
            _el("line", x1=x, y1=y, x2=x + 24, y2=y, stroke=RAPID, stroke_width="2", stroke_dasharray="6 4")
        ]
    if kind == "feed":
        return [_el("line", x1=x, y1=y, x2=x + 24, y2=y, stroke=FEED, stroke_width="2.2")]
    if kind == "contour":
        return [_el("line", x1=x, y1=y, x2=x + 24, y2=y, stroke=CONTOUR, stroke_width="2.4")]
    if kind == "plunge":
        return [_el("circle", cx=x + 12, cy=y, r="3.2", fill=PAPER, stroke=FEED, stroke_width="1.6")]
    if kind == "error":
        return [
            _el("circle", cx=x + 12, cy=y, r="6", fill=PAPER, stroke=ERROR, stroke_width="2"),
            _el(
                "path",
                d=f"M{_c(x + 9)} {_c(y - 3)}L{_c(x + 15)} {_c(y + 3)}M{_c(x + 15)} {_c(y - 3)}"
                f"L{_c(x + 9)} {_c(y + 3)}",
                stroke=ERROR,
                stroke_width="1.8",
            ),
        ]
    if kind == "zero":
        return _zero_symbol(x + 12, y, 5.5)
    if kind == "stock":
        return [
            _el(
                "rect",
                x=x + 2,
                y=y - 6,
                width="20",
                height="12",
                fill=_rgb(TOP),
                stroke=INK,
                stroke_width="1.4",
            )
        ]
    if kind == "section":
        return [
            _el(
                "rect",
                x=x + 2,
                y=y - 6,
                width="20",
                height="12",
                fill="url(#hatch)",
                stroke=INK,
                stroke_width="1",
            )
        ]
    if kind == "view":
        return [
            _el(
                "rect",
                x=x + 2,
                y=y - 6,
                width="20",
                height="12",
                fill="url(#cylinder)",
                stroke=INK,
                stroke_width="1",
            )
        ]
    if kind == "removed":
        return [
            _el(
                "rect",
                x=x + 2,
                y=y - 6,
                width="20",
                height="12",
                fill=REMOVED,
                stroke=MUTED,
                stroke_width="1",
                stroke_dasharray="3 2",
            )
        ]
    if kind == "through":
        return [
            _el("rect", x=x + 2, y=y - 6, width="20", height="12", fill=PAPER, stroke=MUTED, stroke_width="1")
        ]
    return []


def _legend(
    items: list[tuple[str, str]], notes: list[str], width: float, top: float
) -> tuple[list[str], float]:
    """The legend's rows (symbols and texts) and the notes below them; the height they take."""
    rows, height = _legend_rows(items, width - 2 * 16, 16)
    out: list[str] = []
    for r, row in enumerate(rows):
        y = top + 12 + 20 * r
        for symbol, text, x in row:
            out += _symbol(symbol, x, y)
            out.append(_el("text", text, x=x + 30, y=y + 4, font_size=_c(LEGEND_FONT), fill=INK))
    y = top + height + 4
    for note in notes:
        y += 16
        out.append(_el("text", note, x=16, y=y, font_size="11.5", fill=MUTED))
    return out, height + 4 + 16 * len(notes) + 8


def _error_note(lines: list[int], lang: Lang) -> str:
    t = TEXTS[lang]
    shown = ", ".join(map(str, lines[:40]))
    more = f" {t['more_errors'].format(n=len(lines) - 40)}" if len(lines) > 40 else ""
    return f"{t['error']}: {t['line'] if len(lines) == 1 else t['lines']} {shown}{more}"


def _document(
    width: float, height: float, title: str, body: list[str], defs: list[str], info: dict[str, Any]
) -> str:
    data = "".join(f" data-{k.replace('_', '-')}={quoteattr(str(v))}" for k, v in info.items())
    return (
        f'<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 {_c(width)} {_c(height)}" width="{_c(width)}" '
        f'height="{_c(height)}" font-family={quoteattr(FONT)} role="img"{data}>'
        f"<title>{escape(title)}</title>"
        + (f"<defs>{''.join(defs)}</defs>" if defs else "")
        + _el("rect", x="0", y="0", width=_c(width), height=_c(height), fill=PAPER)
        + "".join(body)
        + "</svg>"
    )


def _rgb(c: Sequence[float]) -> str:
    return f"#{int(c[0]):02x}{int(c[1]):02x}{int(c[2]):02x}"


def png_rgb(image: npt.NDArray[np.uint8]) -> bytes:
    """An RGB image (rows top down) as PNG bytes."""

    def chunk(kind: bytes, data: bytes) -> bytes:
        return (
            struct.pack(">I", len(data))
            + kind
            + data
            + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)
        )

    height, width, _ = image.shape
    rows = np.hstack([np.zeros((height, 1), dtype=np.uint8), image.reshape(height, -1)])
    header = struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)
    return (
        b"\x89PNG\r\n\x1a\n"
        + chunk(b"IHDR", header)
        + chunk(b"IDAT", zlib.compress(rows.tobytes(), 9))
        + chunk(b"IEND", b"")
    )


# -- milling ------------------------------------------------------------------------------------------------
def depth_levels(heights: Array, top: float, base: float, most: int = 5) -> list[float]:
    """The depths the part's floors lie at (Z, mm, deepest last): the heights below the top face that cover
    at least 1 % of the cut cells, at most `most` of them (the largest areas)."""
    cut = heights[heights < top - 1e-3]
    if not len(cut):
        return []
    values, counts = np.unique(np.round(cut, 2), return_counts=True)
    keep = counts >= max(1, 0.01 * len(cut))
    chosen = sorted(zip(counts[keep], values[keep], strict=True), reverse=True)[:most]
    levels = sorted((float(v) for _, v in chosen), reverse=True)
    deepest = float(cut.min())
    if not levels or deepest < levels[-1] - 0.05:
        levels.append(round(deepest, 2))
    return [max(v, base) for v in levels]


def _ramp(t: Array) -> npt.NDArray[np.float64]:
    """Colours along RAMP for t in 0…1 (shallow → deep)."""
    stops = np.asarray(RAMP, dtype=np.float64)
    pos = np.clip(t, 0.0, 1.0) * (len(stops) - 1)
    k = np.minimum(pos.astype(np.int64), len(stops) - 2)
    f = (pos - k)[..., None]
    out: npt.NDArray[np.float64] = stops[k] * (1 - f) + stops[k + 1] * f
    return out


def depth_raster(
    heights: Array, top: float, base: float, low: float, limit: int
) -> tuple[npt.NDArray[np.uint8], int]:
    """The height map (rows along +Y) as an RGB image (rows top down): the top face grey, cut cells along the
    ramp from just below the top to `low`, cut-through cells white, edges between levels darker; cells pooled
    k × k (the lowest of each) to stay within `limit` pixels. Returns the image and k."""
    ny, nx = heights.shape
    k = max(1, math.ceil(max(nx, ny) / max(limit, 1)))
    if k > 1:
        py, px = (-ny) % k, (-nx) % k
        padded = np.pad(heights, ((0, py), (0, px)), mode="edge")
        heights = padded.reshape(padded.shape[0] // k, k, padded.shape[1] // k, k).min(axis=(1, 3))
    h = heights[::-1]
    uncut = h >= top - 1e-3
    through = h <= base + 1e-3
    span = max(top - low, 1e-3)
    rgb = _ramp((top - h) / span)
    rgb[uncut] = TOP
    rgb[through] = (255, 255, 255)
    step = np.zeros(h.shape, dtype=bool)  # a wall: the level changes to a neighbour (drawn as a darker line)
    diff_x = np.abs(np.diff(h, axis=1)) > 0.02
    diff_y = np.abs(np.diff(h, axis=0)) > 0.02
    step[:, 1:] |= diff_x
    step[1:, :] |= diff_y
    rgb[step] *= 0.62
    return np.clip(np.rint(rgb), 0, 255).astype(np.uint8), k


def mill_picture(
    toolpath: Any, heightmap: Any, stock: Any, lang: Lang = "de", limits: PictureLimits = DEFAULT_LIMITS
) -> Picture:
    """The plan view of a milling program's result: `toolpath` from core.pipeline.run, `heightmap` the
    simulation's (core.sim.simulate(...).heightmap; None: the stock untouched), `stock` its box."""
    t = TEXTS[lang]
    box = (float(stock.x0), float(stock.y0), float(stock.x1), float(stock.y1))
    w, h = box[2] - box[0], box[3] - box[1]
    grow = max(0.6 * max(w, h), 20.0)
    reach = (box[0] - grow, box[1] - grow, box[2] + grow, box[3] + grow)
    ends = [(float(p[0]), float(p[1])) for m in toolpath.moves for p in (m.start, m.end)]
    extent = _fit(box, reach, ends[: 4 * limits.points])
    frame, width = _frame(extent)
    tolerance = 0.4 / frame.scale  # chords within half a pixel
    path = _path(toolpath.moves, (0, 1), tolerance, limits)

    body: list[str] = []
    body += _axes(frame, lang, "X", "Y")
    # the part: the depth raster inside the stock's outline
    top, base = float(stock.z1), float(stock.z0)
    info: dict[str, Any] = {
        "view": "mill",
        "points": path.points,
        "points_total": path.total,
        "path_cut": str(path.cut).lower(),
        "frame": _frame_info(frame),
    }
    levels: list[float] = []
    sx, sy = frame.px(box[0], box[3])
    sw, sh = w * frame.scale, h * frame.scale
    if heightmap is not None:
        heights = np.asarray(heightmap.heights, dtype=np.float64)
        levels = depth_levels(heights, top, base)
        low = min(levels) if levels else base
        image, k = depth_raster(heights, top, base, low, limits.raster)
        cell = float(heightmap.grid.dx) * k
        info.update(raster=f"{image.shape[1]}x{image.shape[0]}", cell=round(cell, 4))
        href = "data:image/png;base64," + base64.b64encode(png_rgb(image)).decode("ascii")
        body.append(_el("image", x=sx, y=sy, width=sw, height=sh, preserveAspectRatio="none", href=href))
    else:
        body.append(_el("rect", x=sx, y=sy, width=sw, height=sh, fill=_rgb(TOP)))
    body.append(_el("rect", x=sx, y=sy, width=sw, height=sh, fill="none", stroke=INK, stroke_width="1.6"))
    # the path, clipped to the plot
    body.append(f'<g clip-path="url(#plot)">{"".join(_draw_path(frame, path))}</g>')
    labels = _Labels(frame)
    if frame.inside(0.0, 0.0):
        labels.block(*frame.px(0.0, 0.0), 10.0)
    marks, errors = _markers(frame, toolpath, (0, 1), lang, limits, labels)
    body += _zero_axes(frame, ("X", "Y"))
    body += marks
    body += _leaving(frame, toolpath.moves, (0, 1), lang, labels)
    info["errors"] = ",".join(map(str, errors))

    # the legend: the depth ramp with its levels, then the path's symbols, then the notes
    legend_top = frame.top + frame.height + AXIS_PAD
    ramp_part, ramp_height = _depth_legend(levels, top, base, lang, legend_top, heightmap is not None)
    body += ramp_part
    items = [
        ("stock", f"{t['stock']} ({t['top']} Z{num(top, lang)})"),
        ("rapid", t["rapid"]),
        ("feed", t["feed"]),
    ]
    if path.contour:
        items.append(("contour", t["contour"]))
    if path.plunges:
        items.append(("plunge", t["plunge"]))
    items.append(("zero", t["zero"]))
    if errors:
        items.append(("error", t["error"]))
    notes = _notes(path, errors, info, lang)
    legend, legend_height = _legend(items, notes, width, legend_top + ramp_height)
    body += legend
    height = legend_top + ramp_height + legend_height
    defs = [
        (
            f'<clipPath id="plot"><rect x="{_c(frame.left)}" y="{_c(frame.top)}" width="{_c(frame.width)}" '
            f'height="{_c(frame.height)}"/></clipPath>'
        )
    ]
    return Picture(_document(width, height, t["title_mill"], body, defs, info), info)


def _depth_legend(
    levels: list[float], top: float, base: float, lang: Lang, y: float, simulated: bool
) -> tuple[list[str], float]:
    """The colour ramp as a bar from the top face to the deepest floor, the floors' Z marked on it."""
    if not simulated or not levels:
        return [], 0.0
    t = TEXTS[lang]
    out = [_el("text", t["depth"], x=16, y=y + 12, font_size=_c(LEGEND_FONT), fill=INK, font_weight="600")]
    x0, bar = 16.0 + 0.56 * LEGEND_FONT * len(t["depth"]) + 14, 220.0
    low = min(levels)
    stops = "".join(
        f'<stop offset="{k / (len(RAMP) - 1):.3f}" stop-color="{_rgb(c)}"/>' for k, c in enumerate(RAMP)
    )
    out.append(f'<defs><linearGradient id="ramp" x1="0" y1="0" x2="1" y2="0">{stops}</linearGradient></defs>')
    out.append(
        _el("rect", x=x0, y=y + 2, width="14", height="12", fill=_rgb(TOP), stroke=MUTED, stroke_width="0.8")
    )
    out.append(
        _el(
            "rect",
            x=x0 + 14,
            y=y + 2,
            width=_c(bar),
            height="12",
            fill="url(#ramp)",
            stroke=MUTED,
            stroke_width="0.8",
        )
    )
    marks = [(x0 + 7, top)] + [(x0 + 14 + bar * (top - v) / max(top - low, 1e-3), v) for v in levels]
    last = -1e9
    for x, v in marks:
        out.append(_el("line", x1=x, y1=y + 14, x2=x, y2=y + 19, stroke=INK, stroke_width="1"))
        if x - last >= 30:
            out.append(
                _el("text", num(v, lang, 2), x=x, y=y + 30, font_size="11", text_anchor="middle", fill=INK)
            )
            last = x
    if any(v <= base + 1e-3 for v in levels):
        out += _symbol("through", x0 + bar + 30, y + 8)
        out.append(_el("text", t["through"], x=x0 + bar + 60, y=y + 12, font_size=_c(LEGEND_FONT), fill=INK))
    return out, 38.0


def _notes(path: _Path, errors: list[int], info: dict[str, Any], lang: Lang) -> list[str]:
    t = TEXTS[lang]
    notes = []
    if errors:
        notes.append(_error_note(errors, lang))
    if path.cut:
        notes.append(t["cut_path"].format(shown=path.points, total=path.total))
    if "cell" in info:
        notes.append(t["raster"].format(cell=num(float(info["cell"]), lang)))
    if not path.points and not path.plunges:
        notes.append(t["no_moves"])
    return notes


# -- turning ------------------------------------------------------------------------------------------------
def _runs(solid: npt.NDArray[np.bool_]) -> list[tuple[int, int]]:
    edges = np.flatnonzero(np.diff(np.concatenate([[0], solid.astype(np.int8), [0]])))
    return list(zip(edges[::2].tolist(), edges[1::2].tolist(), strict=True))


def _stepped(z0: float, dz: float, values: Array, i: int, j: int) -> tuple[Array, Array]:
    """Samples i…j−1 as a polyline over their cells: the ends at the cells' edges, the middle at their centres."""
    zs = z0 + (np.arange(i, j) + 0.5) * dz
    z = np.concatenate([[z0 + i * dz], zs, [z0 + j * dz]])
    v = np.concatenate([[values[i]], values[i:j], [values[j - 1]]])
    return z, v


def lathe_picture(
    toolpath: Any, profile: Any, blank: Any, lang: Lang = "de", limits: PictureLimits = DEFAULT_LIMITS
) -> Picture:
    """The drawing view of a turning program's result: `toolpath` from core.pipeline.run (x the radius),
    `profile` the turning simulation's (core.sim.simulate_turning(...).profile), `blank` the bar or tube."""
    t = TEXTS[lang]
    radius, length = float(blank.diameter) / 2, float(blank.length)
    jaw = float(blank.jaw_radius)
    box = (-length, -jaw, 0.0, jaw)  # (z, signed radius): the part and the chuck's jaws around it
    grow = max(0.5 * max(length, 2 * radius), 15.0)
    reach = (box[0] - grow, -jaw, box[2] + grow, jaw + grow)
    ends = [(float(p[2]), float(p[0])) for m in toolpath.moves for p in (m.start, m.end)]
    extent = _fit(box, reach, ends[: 4 * limits.points])
    frame, width = _frame(extent)
    tolerance = 0.4 / frame.scale
    path = _path(toolpath.moves, (2, 0), tolerance, limits)
    info: dict[str, Any] = {
        "view": "lathe",
        "points": path.points,
        "points_total": path.total,
        "path_cut": str(path.cut).lower(),
        "frame": _frame_info(frame),
    }

    body: list[str] = []
    body += _axes(frame, lang, "Z", t["x_diameter"], lambda v: num(abs(2 * v), lang))
    body.append('<g clip-path="url(#plot)">')
    # the blank: what the program removed, faint, with its outline dashed
    bore = float(blank.bore) / 2
    for lo, hi in ((bore, radius), (-radius, -bore)):
        x, y = frame.px(-length, hi)
        body.append(
            _el(
                "rect",
                x=x,
                y=y,
                width=length * frame.scale,
                height=(hi - lo) * frame.scale,
                fill=REMOVED,
                stroke=MUTED,
                stroke_width="1",
                stroke_dasharray="4 3",
            )
        )
    # the chuck's jaws holding the bar's last `clamp` mm
    clamp = float(blank.clamp)
    for lo, hi in ((radius, jaw), (-jaw, -radius)):
        x, y = frame.px(-length, hi)
        body.append(
            _el(
                "rect",
                x=x,
                y=y,
                width=clamp * frame.scale,
                height=(hi - lo) * frame.scale,
                fill=JAW,
                stroke=INK,
                stroke_width="1",
            )
        )
    outer = np.clip(np.asarray(profile.outer, dtype=np.float64), 0.0, None)
    inner = np.clip(np.asarray(profile.inner, dtype=np.float64), 0.0, None)
    z0, dz = float(profile.z0), float(profile.dz)
    tol = 0.3 / frame.scale
    section, view, edges = [], [], []
    for i, j in _runs(outer - inner > 1e-6):
        z, o = _stepped(z0, dz, outer, i, j)
        _, m = _stepped(z0, dz, inner, i, j)
        ko, ki = simplified(z, o, tol), simplified(z, m, tol)
        upper = [(z[k], o[k]) for k in ko] + [(z[k], m[k]) for k in ki[::-1]]
        section.append("M" + "L".join(f"{_c(a)} {_c(b)}" for a, b in (frame.px(*p) for p in upper)) + "Z")
        lower = [(z[k], -o[k]) for k in ko] + [(z[ko[-1]], 0.0), (z[ko[0]], 0.0)]
        view.append("M" + "L".join(f"{_c(a)} {_c(b)}" for a, b in (frame.px(*p) for p in lower)) + "Z")
        for a, b in itertools.pairwise(ko):  # a shoulder: its edge seen across the lower half
            if abs(z[b] - z[a]) < 1.5 * dz and abs(o[b] - o[a]) > tol:
                x, _ = frame.px(z[a], 0.0)
                edges.append(f"M{_c(x)} {_c(frame.px(0.0, 0.0)[1])}V{_c(frame.px(0.0, -min(o[a], o[b]))[1])}")
    if view:
        body.append(
            _el(
                "path",
                d="".join(view),
                fill="url(#cylinder)",
                stroke=INK,
                stroke_width="1.5",
                stroke_linejoin="round",
            )
        )
    if edges:
        body.append(_el("path", d="".join(edges), stroke=INK, stroke_width="1"))
    if section:
        body.append(
            _el(
                "path",
                d="".join(section),
                fill="url(#hatch)",
                stroke=INK,
                stroke_width="1.5",
                stroke_linejoin="round",
                fill_rule="evenodd",
            )
        )
    # the spindle axis, dash-dotted
    ax0, ay = frame.px(frame.x0, 0.0)
    ax1, _ = frame.px(frame.x1, 0.0)
    body.append(
        _el("line", x1=ax0, y1=ay, x2=ax1, y2=ay, stroke=INK, stroke_width="0.9", stroke_dasharray="14 3 2 3")
    )
    body += _draw_path(frame, path)
    body.append("</g>")
    labels = _Labels(frame)
    if frame.inside(0.0, 0.0):
        labels.block(*frame.px(0.0, 0.0), 10.0)
    marks, errors = _markers(frame, toolpath, (2, 0), lang, limits, labels)
    body += _zero_axes(frame, ("Z", "X"))
    body += marks
    body += _leaving(frame, toolpath.moves, (2, 0), lang, labels)
    info["errors"] = ",".join(map(str, errors))

    legend_top = frame.top + frame.height + AXIS_PAD
    items = [
        ("section", t["section"]),
        ("view", t["view"]),
        ("removed", f"{t['stock']}, {t['removed']}"),
        ("rapid", t["rapid"]),
        ("feed", t["feed"]),
    ]
    if path.contour:
        items.append(("contour", t["contour"]))
    items.append(("zero", t["zero"]))
    if errors:
        items.append(("error", t["error"]))
    legend, legend_height = _legend(items, _notes(path, errors, info, lang), width, legend_top)
    body += legend
    height = legend_top + legend_height
    defs = [
        (
            f'<clipPath id="plot"><rect x="{_c(frame.left)}" y="{_c(frame.top)}" width="{_c(frame.width)}" '
            f'height="{_c(frame.height)}"/></clipPath>'
        ),
        (
            '<pattern id="hatch" width="7" height="7" patternUnits="userSpaceOnUse" patternTransform="rotate(45)">'
            f'<rect width="7" height="7" fill="{SECTION}"/><line x1="0" y1="0" x2="0" y2="7" stroke="{HATCH}" '
            'stroke-width="1.1"/></pattern>'
        ),
        (
            f'<linearGradient id="cylinder" x1="0" y1="0" x2="0" y2="1"><stop offset="0" stop-color="{VIEW_LIGHT}"/>'
            f'<stop offset="1" stop-color="{VIEW_DARK}"/></linearGradient>'
        ),
    ]
    return Picture(_document(width, height, t["title_lathe"], body, defs, info), info)
