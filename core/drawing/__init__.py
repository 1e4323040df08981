"""The dimensioned drawing of an exercise's part, as a PAL exam draws it: SVG on an A4 sheet.

The part is the reference program's: its toolpath gives the numbers (programmed contour points, arc
centres and radii, depths — core/drawing/features.py), the simulated stock gives the edges to draw (the
height map's outlines at each floor height). Coordinate dimensioning from the workpiece zero, as PAL
drawings do: X values below the top view, Y values to its left, Z values beside a section through the
deepest feature. Where a part has more points than ordinates can show, or floors that are not flat,
the drawing lists the points in a coordinate table instead: it never prints a number the program does
not give. A turning exercise's part is drawn by core/drawing/turned.py (a half section with Ø dimensions).
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

import contourpy
import numpy as np

from core.drawing.features import (
    POINT_TOLERANCE,
    Element,
    Feature,
    chamfer_leg,
    distinct,
    features,
    line_angle,
    machined_corners,
    on_stock,
    points,
    visible,
)
from core.drawing.frame import (
    KIND_NAMES_EN,
    LABELS,
    MARGIN,
    SCALES,
    SHEET,
    SPACING,
    TITLE_BLOCK,
    frame,
    scale_text,
    title_block,
    value,
)
from core.drawing.svg import THICK, THIN, Svg, num
from core.drawing.turned import turned_part_drawing
from core.exercises import Exercise
from core.grading import execute
from core.sim.engine import HeightMap, Stock

MAX_ORDINATES = 16  # more distinct X or Y values than this: a coordinate table instead
FLAT_SHARE = 0.01  # more cut cells than this off every programmed floor: the floors are free-form


@dataclass(frozen=True)
class Layout:
    """Where the views sit on the sheet (paper mm) and the scale."""

    s: float
    ox: float  # left edge of the blank in both views
    top_y: float  # top edge of the top view (the blank's Y max)
    section_y: float  # top edge of the section (the blank's Z max)
    stock: Stock

    def top(self, x: float, y: float) -> tuple[float, float]:
        return (self.ox + (x - self.stock.x0) * self.s, self.top_y + (self.stock.y1 - y) * self.s)

    def side(self, x: float, z: float) -> tuple[float, float]:
        return (self.ox + (x - self.stock.x0) * self.s, self.section_y + (self.stock.z1 - z) * self.s)


def _layout(stock: Stock) -> Layout:
    w, h, d = stock.x1 - stock.x0, stock.y1 - stock.y0, stock.z1 - stock.z0
    ox, top_y = MARGIN + 32.0, MARGIN + 12.0
    title_top = SHEET[1] - MARGIN - TITLE_BLOCK[1]
    title_left = SHEET[0] - MARGIN - TITLE_BLOCK[0]
    for s in SCALES:
        section_y = top_y + h * s + 28.0
        bottom = section_y + d * s + 10.0
        top_right = ox + w * s + 62.0  # the callout column
        section_right = ox + w * s + 26.0  # the Z ordinates
        if top_right > SHEET[0] - MARGIN or bottom > SHEET[1] - MARGIN:
            continue
        top_clear = top_right <= title_left or section_y - 20.0 <= title_top
        section_clear = section_right <= title_left or bottom <= title_top
        if top_clear and section_clear:
            return Layout(s, ox, top_y, section_y, stock)
    s = SCALES[-1]
    return Layout(s, ox, top_y, top_y + h * s + 28.0, stock)


# ---- the views -------------------------------------------------------------------------------------------

def _levels(hm: HeightMap, floors: list[float]) -> list[float]:
    """The heights the part's edges lie between: the base (outside), the programmed floors, the top."""
    heights = sorted({round(z, 6) for z in [hm.base - 1.0, hm.top] + floors})
    return [(a + b) / 2 for a, b in itertools.pairwise(heights)]


def _edges(hm: HeightMap, floors: list[float]) -> list[np.ndarray]:
    """The outlines of the machined part in the top view (workpiece mm): the height map's contour lines."""
    g = hm.grid
    z = np.full((g.ny + 2, g.nx + 2), hm.base - 1.0)
    z[1:-1, 1:-1] = hm.heights
    xs = g.x0 + (np.arange(-1, g.nx + 1) + 0.5) * g.dx
    ys = g.y0 + (np.arange(-1, g.ny + 1) + 0.5) * g.dy
    # cells of the border are the blank's edge, not half a cell inside it
    xs[0], xs[-1] = g.x0, g.x0 + g.nx * g.dx
    ys[0], ys[-1] = g.y0, g.y0 + g.ny * g.dy
    gen = contourpy.contour_generator(xs, ys, z, line_type=contourpy.LineType.Separate)
    out: list[np.ndarray] = []
    for level in _levels(hm, floors):
        out += [np.asarray(line) for line in gen.lines(level)]
    return out


def _simplify(pts: np.ndarray, tolerance: float) -> np.ndarray:
    """Drop the points of a polyline that lie on the straight line of their neighbours (grid steps)."""
    if len(pts) <= 2:
        return pts
    keep = [0]
    for i in range(1, len(pts) - 1):
        a, b, c = pts[keep[-1]], pts[i], pts[i + 1]
        ab, ac = b - a, c - a
        cross = abs(ab[0] * ac[1] - ab[1] * ac[0]) / (np.hypot(*ac) or 1.0)
        if cross > tolerance:
            keep.append(i)
    keep.append(len(pts) - 1)
    return pts[keep]


def _free_form(hm: HeightMap, floors: list[float]) -> bool:
    h = hm.heights
    cut = h < hm.top - 1e-6
    if not cut.any():
        return False
    on_floor = np.zeros_like(cut)
    for z in floors + [hm.base]:
        on_floor |= np.abs(h - z) < 0.01
    return bool(np.count_nonzero(cut & ~on_floor) > FLAT_SHARE * np.count_nonzero(cut))


def _zero_symbol(svg: Svg, c: tuple[float, float], r: float = 2.5) -> None:
    """The workpiece zero: a circle with two opposite quarters filled (DIN EN ISO 22768 style)."""
    svg.circle(c, r, width=THIN, fill="#fff")
    x, y = c
    svg.path(f"M{num(x)} {num(y)} L{num(x + r)} {num(y)} A{num(r)} {num(r)} 0 0 0 {num(x)} {num(y - r)} Z",
             width=0.1, fill="#000")
    svg.path(f"M{num(x)} {num(y)} L{num(x - r)} {num(y)} A{num(r)} {num(r)} 0 0 0 {num(x)} {num(y + r)} Z",
             width=0.1, fill="#000")


def _axes(svg: Svg, c: tuple[float, float]) -> None:
    x, y = c
    svg.line((x, y), (x + 12, y), width=THIN)
    svg.arrow((x + 12, y), (x, y))
    svg.text((x + 13, y + 1.2), "X", size=3.5)
    svg.line((x, y), (x, y - 12), width=THIN)
    svg.arrow((x, y - 12), (x, y))
    svg.text((x - 1.2, y - 13.5), "Y", size=3.5)


def _element_path(L: Layout, e: Element) -> str:
    sx, sy = L.top(*e.start)
    ex, ey = L.top(*e.end)
    if e.center is None:
        return f"M{num(sx)} {num(sy)} L{num(ex)} {num(ey)}"
    _, sweep = e.angles()
    large = 1 if abs(sweep) > math.pi else 0
    # y points down on paper: counter-clockwise in the part is clockwise on the sheet (sweep flag 0)
    flag = 0 if sweep > 0 else 1
    r = e.radius * L.s
    return f"M{num(sx)} {num(sy)} A{num(r)} {num(r)} 0 {large} {flag} {num(ex)} {num(ey)}"


def _ordinates(svg: Svg, L: Layout, pts: list[tuple[float, float]], lang: str) -> None:
    """Coordinate dimensions: every distinct X below the top view, every distinct Y to its left."""
    st = L.stock
    xs = distinct([p[0] for p in pts])
    ys = distinct([p[1] for p in pts])
    base_y = L.top(0, st.y0)[1] + 8.0  # the row the X texts hang from
    previous = -math.inf
    for x in xs:
        lowest = min((p for p in pts if abs(p[0] - x) <= POINT_TOLERANCE), key=lambda p: p[1])
        px, py = L.top(*lowest)
        tx = max(px, previous + SPACING)
        previous = tx
        svg.polyline([(px, py + 1.0), (px, base_y - 3.0), (tx, base_y), (tx, base_y + 0.5)], width=0.18)
        svg.text((tx + 1.2, base_y + 1.5), value(x, lang), anchor="end", rotate=-90, kind="x", value=value(x, "en"))
    base_x = L.top(st.x0, 0)[0] - 8.0
    previous = math.inf
    for y in ys:
        leftmost = min((p for p in pts if abs(p[1] - y) <= POINT_TOLERANCE), key=lambda p: p[0])
        px, py = L.top(*leftmost)
        ty = min(py, previous - SPACING)
        previous = ty
        svg.polyline([(px - 1.0, py), (base_x + 3.0, py), (base_x, ty), (base_x - 0.5, ty)], width=0.18)
        svg.text((base_x - 1.5, ty + 1.2), value(y, lang), anchor="end", kind="y", value=value(y, "en"))


def _leader(svg: Svg, at: tuple[float, float], direction: tuple[float, float], text: str, kind: str, raw: str,
            length: float = 7.0, zone: tuple[float, float] | None = None) -> None:
    """A leader from `at` (arrow on the element) outwards, the text at its end."""
    n = math.hypot(*direction) or 1.0
    ux, uy = direction[0] / n, direction[1] / n
    end = (at[0] + ux * length, at[1] + uy * length)
    if zone is not None and (end[0] < zone[0] + 2.0 or end[1] > zone[1] - 2.0):
        ux, uy = -ux, -uy  # the ordinates are left of and below the view: point the other way
        end = (at[0] + ux * length, at[1] + uy * length)
    shoulder = (end[0] + (4.0 if ux >= 0 else -4.0), end[1])
    svg.polyline([at, end, shoulder], width=THIN)
    svg.arrow(at, end)
    anchor = "start" if ux >= 0 else "end"
    svg.text((shoulder[0] + (0.8 if ux >= 0 else -0.8), shoulder[1] + 1.2), text, anchor=anchor, kind=kind, value=raw)


def _outward(L: Layout, p: tuple[float, float]) -> tuple[float, float]:
    """On paper: away from the blank's centre."""
    st = L.stock
    c = L.top((st.x0 + st.x1) / 2, (st.y0 + st.y1) / 2)
    d = (p[0] - c[0], p[1] - c[1])
    return d if math.hypot(*d) > 1e-9 else (1.0, -1.0)


def _annotations(svg: Svg, L: Layout, feats: list[Feature], lang: str) -> None:
    """Radii (programmed, and the tool's own radius in the inside corners of a contour), chamfers and line
    angles beside the elements; one depth callout per kind of feature in a column right of the view."""
    st = L.stock
    zone = (L.top(st.x0, 0)[0], L.top(0, st.y0)[1])  # left and bottom edge of the top view
    done_radii: set[tuple[float, float, float]] = set()
    for f in feats:
        for k, e in enumerate(f.elements):
            if not visible(e, st):
                continue
            mid = e.midpoint()
            if e.center is not None and on_stock(mid, st):
                key = (round(e.center[0], 3), round(e.center[1], 3), round(e.radius, 3))
                if key in done_radii:
                    continue
                done_radii.add(key)
                pm, pc = L.top(*mid), L.top(*e.center)
                _leader(svg, pm, (pm[0] - pc[0], pm[1] - pc[1]), f"R{value(e.radius, lang)}", "r",
                        value(e.radius, "en"), zone=zone)
                cx, cy = pc
                svg.line((cx - 2.5, cy), (cx + 2.5, cy), width=0.18)
                svg.line((cx, cy - 2.5), (cx, cy + 2.5), width=0.18)
                continue
            if 0 < k < len(f.elements) - 1:
                leg = chamfer_leg(f.elements[k - 1], e, f.elements[k + 1])
                if leg is not None and on_stock(mid, st):
                    pm = L.top(*mid)
                    _leader(svg, pm, _outward(L, pm), f"{value(leg, lang)}×45°", "chamfer", value(leg, "en"),
                            zone=zone)
                    continue
            angle = line_angle(e)
            if angle is not None and on_stock(mid, st):
                pm = L.top(*mid)
                # beside the line, on the side away from the blank's centre
                normal = (-(e.end[1] - e.start[1]), -(e.end[0] - e.start[0]))
                o = _outward(L, pm)
                if normal[0] * o[0] + normal[1] * o[1] < 0:
                    normal = (-normal[0], -normal[1])
                n = math.hypot(*normal) or 1.0
                svg.text((pm[0] + normal[0] / n * 4, pm[1] + normal[1] / n * 4 + 1.2), f"{value(angle, lang)}°",
                         anchor="middle", kind="angle", value=value(angle, "en"))
        r = f.tool_diameter / 2
        corners = [(c, p) for c, p in machined_corners(f) if on_stock(c, st)]
        if f.compensated and corners and r > 0:
            corner, centre = corners[0]
            d = (corner[0] - centre[0], corner[1] - centre[1])
            n = math.hypot(*d) or 1.0
            on_arc = L.top(centre[0] + d[0] / n * r, centre[1] + d[1] / n * r)
            pc = L.top(*centre)
            _leader(svg, on_arc, (pc[0] - on_arc[0], pc[1] - on_arc[1]) if n > r else (on_arc[0] - pc[0], on_arc[1] - pc[1]),
                    f"{len(corners)}× R{value(r, lang)}" if len(corners) > 1 else f"R{value(r, lang)}", "r",
                    value(r, "en"), length=5.0)
    _depth_callouts(svg, L, feats, lang)


def _depth_callouts(svg: Svg, L: Layout, feats: list[Feature], lang: str) -> None:
    """One callout per kind of feature (depth, and width for slots), in a column right of the top view."""
    st = L.stock
    labels = LABELS[lang]
    kinds: dict[tuple[float, float, bool], list[Feature]] = {}
    for f in feats:
        if any(visible(e, st) for e in f.elements):
            kinds.setdefault((round(st.z1 - f.z, 6), 0.0 if f.compensated else f.tool_diameter, f.compensated),
                             []).append(f)
    column = L.top(st.x1, 0)[0] + 12.0
    previous = -math.inf
    for (depth, width, _), group in sorted(kinds.items(), key=lambda kv: -max(
            e.midpoint()[1] for e in kv[1][0].elements if visible(e, st))):
        text = f"{labels['depth']} {value(depth, lang)}"
        if width > 0:
            text = labels["slot"].format(w=value(width, lang)) + f", {text}"
        if len(group) > 1:
            text = f"{len(group)}× {text}"
        shown = [e for e in group[0].elements if visible(e, st) and on_stock(e.midpoint(), st)]
        if not shown:
            continue
        e = max(shown, key=lambda x: (x.midpoint()[0], x.length()))
        pm = L.top(*e.midpoint())
        ty = max(pm[1], previous + SPACING + 1.0)
        previous = ty
        svg.polyline([pm, (column - 2.0, ty), (column, ty)], width=THIN)
        svg.circle(pm, 0.5, fill="#000")
        svg.text((column + 1.0, ty + 1.2), text, kind="depth", value=value(depth, "en"))


def _centre_lines(svg: Svg, L: Layout, feats: list[Feature]) -> None:
    """Slots milled without compensation: their centre line (the programmed path) as a thin dash-dot line."""
    for f in feats:
        if f.compensated:
            continue
        for e in f.elements:
            if visible(e, L.stock):
                svg.path(_element_path(L, e), width=0.18, dash="centre", clip_path="url(#blank)")


def _coordinate_table(svg: Svg, pts: list[tuple[float, float]], L: Layout, lang: str, at: tuple[float, float]) -> None:
    """The fallback: numbered points in the view and their X/Y in a table."""
    unique: list[tuple[float, float]] = []
    for p in pts:
        if all(math.dist(p, q) > POINT_TOLERANCE for q in unique):
            unique.append(p)
    x, y = at
    svg.text((x, y), LABELS[lang]["table"], size=3.5, weight="bold")
    rows = unique[:40]
    for i, p in enumerate(rows, start=1):
        px, py = L.top(*p)
        svg.circle((px, py), 0.6, fill="#000")
        svg.text((px + 1.2, py - 1.0), str(i), size=2.5)
        ry = y + 4.5 * i
        svg.text((x, ry), f"P{i}", size=3.0)
        svg.text((x + 22, ry), value(p[0], lang), size=3.0, anchor="end", kind="x", value=value(p[0], "en"))
        svg.text((x + 42, ry), value(p[1], lang), size=3.0, anchor="end", kind="y", value=value(p[1], "en"))


def _section(svg: Svg, L: Layout, hm: HeightMap, floors: list[float], lang: str) -> float:
    """Section A–A along X through the deepest cut; returns its Y (workpiece mm)."""
    st, g = L.stock, hm.grid
    h = hm.heights
    # the row that crosses the most edges (then the deepest, then the one nearest the middle)
    changes = (np.abs(np.diff(h, axis=1)) > 1e-6).sum(axis=1)
    deepest = h.min(axis=1)
    middle = np.abs(np.arange(g.ny) - g.ny / 2)
    j = int(np.lexsort((middle, deepest, -changes))[0])
    y = g.y0 + (j + 0.5) * g.dy
    row = h[j]
    profile = [L.side(st.x0, st.z0), L.side(st.x0, float(row[0]))]
    for i in range(1, g.nx):
        if abs(row[i] - row[i - 1]) > 1e-9:
            xb = g.x0 + i * g.dx
            profile += [L.side(xb, float(row[i - 1])), L.side(xb, float(row[i]))]
    profile += [L.side(st.x1, float(row[-1])), L.side(st.x1, st.z0)]
    svg.polyline(profile, width=THICK, closed=True, fill="url(#hatch)")
    x0, y0 = L.side(st.x0, st.z1)
    x1, y1 = L.side(st.x1, st.z0)
    svg.path(f"M{num(x0)} {num(y0)} H{num(x1)} V{num(y1)} H{num(x0)} Z", width=THIN, dash="phantom")
    svg.text(((x0 + x1) / 2, y0 - 4.0), f"{LABELS[lang]['section']} A–A", anchor="middle", size=3.5)
    # Z ordinates on the right: the top, every programmed floor the section meets, the base
    levels = [st.z1] + [z for z in floors if np.any(np.abs(row - z) < 0.01)] + [st.z0]
    base_x = x1 + 8.0
    previous = -math.inf
    for z in sorted({round(v, 6) for v in levels}, reverse=True):
        px, py = L.side(st.x1, z)
        ty = max(py, previous + SPACING)
        previous = ty
        svg.polyline([(px + 1.0, py), (base_x - 3.0, py), (base_x, ty), (base_x + 0.5, ty)], width=0.18)
        svg.text((base_x + 1.5, ty + 1.2), value(z, lang), kind="z", value=value(z, "en"))
    # the section line in the top view
    a, b = L.top(st.x0, y), L.top(st.x1, y)
    svg.line((a[0] - 6, a[1]), (b[0] + 6, b[1]), width=THIN, dash="centre")
    for end, sign in ((a[0] - 6, -1), (b[0] + 6, 1)):
        svg.line((end, a[1]), (end - sign * 3, a[1]), width=THICK)
        svg.line((end - sign * 1.5, a[1]), (end - sign * 1.5, a[1] + 4), width=THIN)
        svg.arrow((end - sign * 1.5, a[1] + 4), (end - sign * 1.5, a[1]))
        svg.text((end - sign * 1.5, a[1] - 1.5), "A", anchor="middle", size=3.5)
    return y


def part_drawing(exercise: Exercise, lang: str = "de") -> str:
    """The dimensioned drawing of the exercise's part as an SVG document (A4 landscape, mm)."""
    lang = "en" if lang == "en" else "de"
    if exercise.lathe:
        return turned_part_drawing(exercise, lang)
    stock = exercise.stock.stock()
    result = execute(exercise, exercise.reference)
    hm = result.sim.heightmap
    tools = exercise.tool_table()
    feats = features(result.toolpath.moves, stock, tools)
    floors = sorted({round(f.z, 6) for f in feats if f.z > stock.z0 - 1e-6})
    L = _layout(stock)
    svg = Svg(*SHEET)
    svg.defs.append('<pattern id="hatch" width="2" height="2" patternUnits="userSpaceOnUse" '
                    'patternTransform="rotate(45)"><line x1="0" y1="0" x2="0" y2="2" stroke="#000" '
                    'stroke-width="0.18"/></pattern>')
    bx0, by0 = L.top(stock.x0, stock.y1)
    bx1, by1 = L.top(stock.x1, stock.y0)
    svg.defs.append(f'<clipPath id="blank"><rect x="{num(bx0)}" y="{num(by0)}" width="{num(bx1 - bx0)}" '
                    f'height="{num(by1 - by0)}"/></clipPath>')
    frame(svg)
    svg.text((bx0, by0 - 5.0), LABELS[lang]["top"], size=3.5)
    # the machined part's edges, then the blank as a phantom line
    for edge in _edges(hm, floors):
        svg.polyline([L.top(float(x), float(y)) for x, y in _simplify(edge, hm.grid.dx * 0.3)], width=THICK)
    svg.path(f"M{num(bx0)} {num(by0)} H{num(bx1)} V{num(by1)} H{num(bx0)} Z", width=THIN, dash="phantom")
    _centre_lines(svg, L, feats)
    zero = L.top(0.0, 0.0)
    _zero_symbol(svg, zero)
    _axes(svg, zero)
    pts = [p for f in feats for p in points(f, stock)]
    if on_stock((0.0, 0.0), stock):
        pts.append((0.0, 0.0))
    free = _free_form(hm, floors)
    too_many = len(distinct([p[0] for p in pts])) > MAX_ORDINATES or len(distinct([p[1] for p in pts])) > MAX_ORDINATES
    if free or too_many:
        _coordinate_table(svg, pts, L, lang, (SHEET[0] - MARGIN - TITLE_BLOCK[0], MARGIN + 8.0))
    else:
        _ordinates(svg, L, pts, lang)
    _annotations(svg, L, feats, lang)
    _section(svg, L, hm, [] if free else floors, lang)
    title_block(svg, exercise, L.s, lang)
    return svg.document(f"{exercise.title.get(lang)} — {exercise.id}")


# what other packages take from here (core/sheet: the sheet's size and the number format)
__all__ = ["KIND_NAMES_EN", "MARGIN", "SHEET", "part_drawing", "scale_text", "turned_part_drawing", "value"]
