"""A small SVG writer in paper millimetres: the line types and text styles of a technical drawing.

Only presentation attributes (no <style> element, no script), so the file shows the same as an image, opened
directly under a strict Content-Security-Policy, and printed. Line widths follow DIN ISO 128 group 0.5:
visible edges 0.5 mm, dimension, centre and phantom lines 0.25 mm.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from xml.sax.saxutils import escape, quoteattr

THICK = 0.5
THIN = 0.25
CHAR = 0.62  # a character's width in text heights (DejaVu Sans: digits 0.64, lower case about 0.55)
BOLD = 0.7  # … in bold
ASCENT, DESCENT = 0.76, 0.22  # how far a line of text reaches above and below its baseline, in text heights
Box = tuple[float, float, float, float]  # x0, y0, x1, y1 on paper
FONT = "'DejaVu Sans', 'Liberation Sans', Arial, sans-serif"
DASH = {"solid": None, "centre": "6 1 0.5 1", "phantom": "6 1 0.5 1 0.5 1", "hidden": "2 1"}


def num(v: float) -> str:
    """A coordinate for the SVG source (paper mm, 3 decimals)."""
    s = f"{v:.3f}".rstrip("0").rstrip(".")
    return "0" if s in ("-0", "") else s


def text_box(
    at: tuple[float, float],
    content: str,
    size: float = 3.5,
    anchor: str = "start",
    rotate: float = 0.0,
    weight: str | None = None,
) -> Box:
    """The paper box a text takes (estimated from its length and height), turned as the text is."""
    width = len(content) * (BOLD if weight == "bold" else CHAR) * size
    x0 = {"start": 0.0, "middle": -width / 2, "end": -width}[anchor]
    corners = [
        (x0, -ASCENT * size),
        (x0 + width, -ASCENT * size),
        (x0, DESCENT * size),
        (x0 + width, DESCENT * size),
    ]
    a = math.radians(rotate)
    c, s = math.cos(a), math.sin(a)
    xs = [at[0] + u * c - v * s for u, v in corners]
    ys = [at[1] + u * s + v * c for u, v in corners]
    return (min(xs), min(ys), max(xs), max(ys))


def overlaps(a: Box, b: Box, gap: float = 0.0) -> bool:
    return a[0] < b[2] + gap and b[0] < a[2] + gap and a[1] < b[3] + gap and b[1] < a[3] + gap


def _crosses(a: tuple[float, float], b: tuple[float, float], box: Box, shrink: float = 0.2) -> bool:
    """Whether the segment a–b passes through the box (Liang–Barsky), the box a little smaller than it is."""
    x0, y0, x1, y1 = box[0] + shrink, box[1] + shrink, box[2] - shrink, box[3] - shrink
    if x0 >= x1 or y0 >= y1:
        return False
    dx, dy = b[0] - a[0], b[1] - a[1]
    t0, t1 = 0.0, 1.0
    for p, q in ((-dx, a[0] - x0), (dx, x1 - a[0]), (-dy, a[1] - y0), (dy, y1 - a[1])):
        if abs(p) < 1e-12:
            if q < 0:
                return False
            continue
        t = q / p
        if p < 0:
            t0 = max(t0, t)
        else:
            t1 = min(t1, t)
        if t0 > t1:
            return False
    return True


class Svg:
    """Elements collected in order; `document()` wraps them in an A4 sheet. The boxes of the texts (and of
    what else a caller marks as taken) are kept, so that a text can be placed where it covers no other."""

    def __init__(self, width: float, height: float) -> None:
        self.width = width
        self.height = height
        self.defs: list[str] = []
        self.items: list[str] = []
        self.views: Box | None = None  # where the views and their dimensions are (the viewer's "fit")
        self.taken: list[Box] = []  # texts and what else no text nor leader may cover
        self.kept: list[Box] = []  # lines no text may cover (a leader may cross them)

    def free(self, box: Box, gap: float = 0.6) -> bool:
        """Whether `box` covers no text (nor anything marked taken or kept) and stays on the sheet."""
        inside = box[0] >= 0 and box[1] >= 0 and box[2] <= self.width and box[3] <= self.height
        return (
            inside
            and not any(overlaps(box, b, gap) for b in self.taken)
            and not any(overlaps(box, b, 0.3) for b in self.kept)
        )

    def keep(self, a: tuple[float, float], b: tuple[float, float]) -> None:
        """A line no text may lie on (a dimension or extension line; a leader may cross it)."""
        self.kept.append((min(a[0], b[0]), min(a[1], b[1]), max(a[0], b[0]), max(a[1], b[1])))

    def clear(self, a: tuple[float, float], b: tuple[float, float]) -> bool:
        """Whether the line a–b crosses no text (nor anything marked taken)."""
        return not any(_crosses(a, b, box) for box in self.taken)

    def take(self, box: Box) -> None:
        self.taken.append(box)

    @staticmethod
    def _attrs(attrs: dict[str, str | float | None]) -> str:
        out = []
        for k, v in attrs.items():
            if v is None:
                continue
            out.append(f"{k.replace('_', '-')}={quoteattr(num(v) if isinstance(v, float | int) else v)}")
        return " ".join(out)

    def _stroke(self, width: float, dash: str, colour: str = "#000") -> dict[str, str | float | None]:
        return {
            "stroke": colour,
            "stroke_width": width,
            "fill": "none",
            "stroke_dasharray": DASH[dash],
            "stroke_linecap": "round",
            "stroke_linejoin": "round",
        }

    def line(
        self,
        a: tuple[float, float],
        b: tuple[float, float],
        width: float = THIN,
        dash: str = "solid",
        **extra: str,
    ) -> None:
        attrs = {"x1": a[0], "y1": a[1], "x2": b[0], "y2": b[1], **self._stroke(width, dash), **extra}
        self.items.append(f"<line {self._attrs(attrs)}/>")

    def path(
        self, d: str, width: float = THIN, dash: str = "solid", fill: str | None = None, **extra: str
    ) -> None:
        attrs = {"d": d, **self._stroke(width, dash), **extra}
        if fill is not None:
            attrs["fill"] = fill
        self.items.append(f"<path {self._attrs(attrs)}/>")

    def polyline(
        self,
        pts: Iterable[tuple[float, float]],
        width: float = THICK,
        dash: str = "solid",
        closed: bool = False,
        fill: str | None = None,
        **extra: str,
    ) -> None:
        pts = list(pts)
        if len(pts) < 2:
            return
        d = "M" + " L".join(f"{num(x)} {num(y)}" for x, y in pts) + (" Z" if closed else "")
        self.path(d, width, dash, fill, **extra)

    def circle(self, c: tuple[float, float], r: float, width: float = THIN, fill: str = "none") -> None:
        self.items.append(
            f"<circle {self._attrs({'cx': c[0], 'cy': c[1], 'r': r, 'stroke': '#000', 'stroke_width': width, 'fill': fill})}/>"
        )

    def text(
        self,
        at: tuple[float, float],
        content: str,
        size: float = 3.5,
        anchor: str = "start",
        rotate: float = 0.0,
        weight: str | None = None,
        kind: str | None = None,
        value: str | None = None,
        baseline: str | None = None,
    ) -> None:
        attrs: dict[str, str | float | None] = {
            "x": at[0],
            "y": at[1],
            "font_size": size,
            "font_family": FONT,
            "text_anchor": anchor,
            "font_weight": weight,
            "dominant_baseline": baseline,
            "transform": f"rotate({num(rotate)} {num(at[0])} {num(at[1])})" if rotate else None,
        }
        if kind is not None:
            attrs["class"] = "dim"
            attrs["data_kind"] = kind
            attrs["data_value"] = value
        self.items.append(f"<text {self._attrs(attrs)}>{escape(content)}</text>")
        self.taken.append(text_box(at, content, size, anchor, rotate, weight))

    def arrow(self, tip: tuple[float, float], toward: tuple[float, float], length: float = 2.5) -> None:
        """A filled arrowhead at `tip`, its shaft pointing to `toward` (15° half angle)."""
        dx, dy = toward[0] - tip[0], toward[1] - tip[1]
        n = (dx * dx + dy * dy) ** 0.5 or 1.0
        ux, uy = dx / n, dy / n
        w = length * 0.27
        a = (tip[0] + ux * length - uy * w, tip[1] + uy * length + ux * w)
        b = (tip[0] + ux * length + uy * w, tip[1] + uy * length - ux * w)
        self.polyline([tip, a, b], width=0.1, closed=True, fill="#000")

    def group(self, elements: list[str], **attrs: str) -> None:
        self.items.append(f"<g {self._attrs(dict(attrs))}>" + "".join(elements) + "</g>")

    def document(self, title: str) -> str:
        views = f' data-views="{" ".join(num(v) for v in self.views)}"' if self.views is not None else ""
        head = (
            f'<svg xmlns="http://www.w3.org/2000/svg" width="{num(self.width)}mm" height="{num(self.height)}mm" '
            f'viewBox="0 0 {num(self.width)} {num(self.height)}"{views}>'
        )
        defs = f"<defs>{''.join(self.defs)}</defs>" if self.defs else ""
        background = f'<rect x="0" y="0" width="{num(self.width)}" height="{num(self.height)}" fill="#fff"/>'
        return (
            f'<?xml version="1.0" encoding="UTF-8"?>\n{head}<title>{escape(title)}</title>{defs}{background}'
            + "\n".join(self.items)
            + "</svg>\n"
        )
