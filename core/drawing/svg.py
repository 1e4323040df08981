"""A small SVG writer in paper millimetres: the line types and text styles of a technical drawing.

Only presentation attributes (no <style> element, no script), so the file shows the same as an image, opened
directly under a strict Content-Security-Policy, and printed. Line widths follow DIN ISO 128 group 0.5:
visible edges 0.5 mm, dimension, centre and phantom lines 0.25 mm.
"""

from __future__ import annotations

from collections.abc import Iterable
from xml.sax.saxutils import escape, quoteattr

THICK = 0.5
THIN = 0.25
FONT = "'DejaVu Sans', 'Liberation Sans', Arial, sans-serif"
DASH = {"solid": None, "centre": "6 1 0.5 1", "phantom": "6 1 0.5 1 0.5 1", "hidden": "2 1"}


def num(v: float) -> str:
    """A coordinate for the SVG source (paper mm, 3 decimals)."""
    s = f"{v:.3f}".rstrip("0").rstrip(".")
    return "0" if s in ("-0", "") else s


class Svg:
    """Elements collected in order; `document()` wraps them in an A4 sheet."""

    def __init__(self, width: float, height: float) -> None:
        self.width = width
        self.height = height
        self.defs: list[str] = []
        self.items: list[str] = []

    @staticmethod
    def _attrs(attrs: dict[str, str | float | None]) -> str:
        out = []
        for k, v in attrs.items():
            if v is None:
                continue
            out.append(f"{k.replace('_', '-')}={quoteattr(num(v) if isinstance(v, float | int) else v)}")
        return " ".join(out)

    def _stroke(self, width: float, dash: str, colour: str = "#000") -> dict[str, str | float | None]:
        return {"stroke": colour, "stroke_width": width, "fill": "none", "stroke_dasharray": DASH[dash],
                "stroke_linecap": "round", "stroke_linejoin": "round"}

    def line(self, a: tuple[float, float], b: tuple[float, float], width: float = THIN, dash: str = "solid",
             **extra: str) -> None:
        attrs = {"x1": a[0], "y1": a[1], "x2": b[0], "y2": b[1], **self._stroke(width, dash), **extra}
        self.items.append(f"<line {self._attrs(attrs)}/>")

    def path(self, d: str, width: float = THIN, dash: str = "solid", fill: str | None = None, **extra: str) -> None:
        attrs = {"d": d, **self._stroke(width, dash), **extra}
        if fill is not None:
            attrs["fill"] = fill
        self.items.append(f"<path {self._attrs(attrs)}/>")

    def polyline(self, pts: Iterable[tuple[float, float]], width: float = THICK, dash: str = "solid",
                 closed: bool = False, fill: str | None = None, **extra: str) -> None:
        pts = list(pts)
        if len(pts) < 2:
            return
        d = "M" + " L".join(f"{num(x)} {num(y)}" for x, y in pts) + (" Z" if closed else "")
        self.path(d, width, dash, fill, **extra)

    def circle(self, c: tuple[float, float], r: float, width: float = THIN, fill: str = "none") -> None:
        self.items.append(f"<circle {self._attrs({'cx': c[0], 'cy': c[1], 'r': r, 'stroke': '#000', 'stroke_width': width, 'fill': fill})}/>")

    def text(self, at: tuple[float, float], content: str, size: float = 3.5, anchor: str = "start",
             rotate: float = 0.0, weight: str | None = None, kind: str | None = None, value: str | None = None,
             baseline: str | None = None) -> None:
        attrs: dict[str, str | float | None] = {
            "x": at[0], "y": at[1], "font_size": size, "font_family": FONT, "text_anchor": anchor,
            "font_weight": weight, "dominant_baseline": baseline,
            "transform": f"rotate({num(rotate)} {num(at[0])} {num(at[1])})" if rotate else None,
        }
        if kind is not None:
            attrs["class"] = "dim"
            attrs["data_kind"] = kind
            attrs["data_value"] = value
        self.items.append(f"<text {self._attrs(attrs)}>{escape(content)}</text>")

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
        head = (f'<svg xmlns="http://www.w3.org/2000/svg" width="{num(self.width)}mm" height="{num(self.height)}mm" '
                f'viewBox="0 0 {num(self.width)} {num(self.height)}">')
        defs = f"<defs>{''.join(self.defs)}</defs>" if self.defs else ""
        background = f'<rect x="0" y="0" width="{num(self.width)}" height="{num(self.height)}" fill="#fff"/>'
        return (f'<?xml version="1.0" encoding="UTF-8"?>\n{head}<title>{escape(title)}</title>{defs}{background}'
                + "\n".join(self.items) + "</svg>\n")
