"""The dimensioned drawing of an exercise's part, as a PAL exam draws it: SVG on an A4 sheet.

The part is the reference program's: its toolpath gives the numbers (programmed contour points, arc
centres and radii, depths — core/drawing/features.py), the simulated stock gives the edges to draw (the
height map's outlines at each floor height). Coordinate dimensioning from the workpiece zero, as PAL
drawings do: X values below the top view, Y values to its left, Z values beside a section through the
deepest feature; the blank's size by dimension lines above and right of the top view. A rounded or chamfered
corner the program makes with a transition word (RN, #RND, #CHF, …) is dimensioned to its sharp corner, with
its radius or chamfer; a hole or recess (a plunge) by its centre and a callout "5× Ø6, Tiefe 2". Where a part
has more points than ordinates can show, or floors that are not flat, the drawing lists the points in a
coordinate table instead: it never prints a number the program does not give, and a coordinate it computes
(the end of a line given by its angle) only in brackets (core/drawing/frame.py: Numbers). No text is placed on
another (Svg.free). A turning exercise's part is drawn by core/drawing/turned.py (a half section with Ø
dimensions). What PAL cycles made (pockets, slots, hole patterns, threads) is dimensioned from the cycles' own
words (core/drawing/cycles.py), not from the tool centre's rings.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

import contourpy
import numpy as np

from core.drawing.cycles import Cycles, Pocket, cycles
from core.drawing.features import (
    POINT_TOLERANCE,
    Element,
    Feature,
    Hole,
    chamfer_leg,
    distinct,
    features,
    holes,
    line_angle,
    machined_corners,
    on_stock,
    points,
    transitions,
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
    Numbers,
    exercise_tool_names,
    frame,
    mark_views,
    scale_text,
    title_block,
    value,
)
from core.drawing.svg import CHAR, THICK, THIN, Svg, num, text_box
from core.drawing.turned import turned_part_drawing
from core.exercises import Exercise
from core.grading import execute
from core.sim.engine import HeightMap, Stock

MAX_ORDINATES = 16  # more distinct X or Y values than this: a coordinate table instead
FLAT_SHARE = 0.01  # more cut cells than this off every programmed floor: the floors are free-form


MAX_ORDINATES = 16  # more distinct X or Y values than this: a coordinate table instead
FLAT_SHARE = 0.01  # more cut cells than this off every programmed floor: the floors are free-form
TEXT = 3.5  # mm, the dimension texts' height
VIEW_TITLE = 12.0  # mm above the top view: the view's name (the blank's width is dimensioned between)
SIZE_GAP = 6.0  # mm from the blank's top edge to its width's dimension line
HEIGHT_GAP = 11.0  # mm from the blank's right edge to its height's (beyond the section line's arrows)
COLUMN = 20.0  # mm right of the top view: the callouts' column


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


def _length(text: str, size: float = TEXT) -> float:
    return len(text) * CHAR * size


def _layout(stock: Stock, below: float, left: float) -> Layout:
    """The largest standard scale at which the top view (its X ordinates `below` mm long under it, its Y
    ordinates `left` mm long left of it, the size and callouts right of it) and the section fit the sheet
    beside or above the title block."""
    w, h, d = stock.x1 - stock.x0, stock.y1 - stock.y0, stock.z1 - stock.z0
    ox, top_y = MARGIN + max(32.0, left + 14.0), MARGIN + VIEW_TITLE + 6.0
    gap = max(28.0, below + 19.0)  # the X ordinates, then the section's title
    title_top = SHEET[1] - MARGIN - TITLE_BLOCK[1]
    title_left = SHEET[0] - MARGIN - TITLE_BLOCK[0]
    for s in SCALES:
        section_y = top_y + h * s + gap
        bottom = section_y + d * s + 10.0
        top_right = ox + w * s + COLUMN + 50.0  # the callout column
        section_right = ox + w * s + 26.0  # the Z ordinates
        if top_right > SHEET[0] - MARGIN or bottom > SHEET[1] - MARGIN:
            continue
        top_clear = top_right <= title_left or section_y - 20.0 <= title_top
        section_clear = section_right <= title_left or bottom <= title_top
        if top_clear and section_clear:
            return Layout(s, ox, top_y, section_y, stock)
    s = SCALES[-1]
    return Layout(s, ox, top_y, top_y + h * s + gap, stock)


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
    xy = pts[:, :2].tolist()  # Python floats: a walk point by point, where numpy's scalars cost 10x
    keep = [0]
    ax, ay = xy[0]
    for i in range(1, len(xy) - 1):
        bx, by = xy[i]
        cx, cy = xy[i + 1]
        acx, acy = cx - ax, cy - ay
        cross = abs((bx - ax) * acy - (by - ay) * acx) / (math.hypot(acx, acy) or 1.0)
        if cross > tolerance:
            keep.append(i)
            ax, ay = bx, by
    keep.append(len(xy) - 1)
    return pts[keep]


def _free_form(hm: HeightMap, floors: list[float], bores: list[Hole]) -> bool:
    """Whether more of the cut than FLAT_SHARE is off every programmed floor (not counting the holes: a drill's
    point is no floor)."""
    h = hm.heights
    cut = h < hm.top - 1e-6
    if not cut.any():
        return False
    on_floor = np.zeros_like(cut)
    for z in floors + [hm.base]:
        on_floor |= np.abs(h - z) < 0.01
    g = hm.grid
    xs = g.x0 + (np.arange(g.nx) + 0.5) * g.dx
    ys = g.y0 + (np.arange(g.ny) + 0.5) * g.dy
    for b in bores:
        on_floor |= np.hypot(xs[None, :] - b.x, ys[:, None] - b.y) <= b.diameter / 2 + 1.5 * max(g.dx, g.dy)
    return bool(np.count_nonzero(cut & ~on_floor) > FLAT_SHARE * np.count_nonzero(cut))


def _zero_symbol(svg: Svg, c: tuple[float, float], r: float = 2.5) -> None:
    """The workpiece zero: a circle with two opposite quarters filled (DIN EN ISO 22768 style)."""
    svg.circle(c, r, width=THIN, fill="#fff")
    x, y = c
    svg.path(
        f"M{num(x)} {num(y)} L{num(x + r)} {num(y)} A{num(r)} {num(r)} 0 0 0 {num(x)} {num(y - r)} Z",
        width=0.1,
        fill="#000",
    )
    svg.path(
        f"M{num(x)} {num(y)} L{num(x - r)} {num(y)} A{num(r)} {num(r)} 0 0 0 {num(x)} {num(y + r)} Z",
        width=0.1,
        fill="#000",
    )
    svg.take((x - r, y - r, x + r, y + r))


def _axes(svg: Svg, c: tuple[float, float]) -> None:
    x, y = c
    svg.line((x, y), (x + 12, y), width=THIN)
    svg.arrow((x + 12, y), (x, y))
    svg.text((x + 13, y + 1.2), "X", size=3.5)
    svg.line((x, y), (x, y - 12), width=THIN)
    svg.arrow((x, y - 12), (x, y))
    svg.text((x - 1.2, y - 13.5), "Y", size=3.5, anchor="end")


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


def _ordinate_texts(pts: list[tuple[float, float]], numbers: Numbers) -> tuple[float, float]:
    """How long the longest X and Y ordinate texts are (paper mm): the room the layout keeps for them."""
    xs = distinct([p[0] for p in pts])
    ys = distinct([p[1] for p in pts])
    return (
        max((_length(numbers.dimension(x)) for x in xs), default=0.0),
        max((_length(numbers.dimension(y)) for y in ys), default=0.0),
    )


def _ordinates(svg: Svg, L: Layout, pts: list[tuple[float, float]], numbers: Numbers) -> None:
    """Coordinate dimensions: every distinct X below the top view, every distinct Y to its left; a text moves
    along its row where it would cover another."""
    st = L.stock
    xs = distinct([p[0] for p in pts])
    ys = distinct([p[1] for p in pts])
    base_y = L.top(0, st.y0)[1] + 8.0  # the row the X texts hang from
    previous = -math.inf
    for x in xs:
        lowest = min((p for p in pts if abs(p[0] - x) <= POINT_TOLERANCE), key=lambda p: p[1])
        px, py = L.top(*lowest)
        text = numbers.dimension(x)
        tx = max(px, previous + SPACING)
        for _ in range(40):
            if svg.free(text_box((tx + 1.2, base_y + 1.5), text, anchor="end", rotate=-90)):
                break
            tx += 0.5
        previous = tx
        svg.polyline([(px, py + 1.0), (px, base_y - 3.0), (tx, base_y), (tx, base_y + 0.5)], width=0.18)
        svg.keep((px, py + 1.0), (px, base_y - 3.0))
        svg.text((tx + 1.2, base_y + 1.5), text, anchor="end", rotate=-90, kind="x", value=numbers.raw(x))
    base_x = L.top(st.x0, 0)[0] - 8.0
    previous = math.inf
    for y in ys:
        leftmost = min((p for p in pts if abs(p[1] - y) <= POINT_TOLERANCE), key=lambda p: p[0])
        px, py = L.top(*leftmost)
        text = numbers.dimension(y)
        ty = min(py, previous - SPACING)
        for _ in range(40):
            if svg.free(text_box((base_x - 1.5, ty + 1.2), text, anchor="end")):
                break
            ty -= 0.5
        previous = ty
        svg.polyline([(px - 1.0, py), (base_x + 3.0, py), (base_x, ty), (base_x - 0.5, ty)], width=0.18)
        svg.keep((px - 1.0, py), (base_x + 3.0, py))
        svg.text((base_x - 1.5, ty + 1.2), text, anchor="end", kind="y", value=numbers.raw(y))


def _size(svg: Svg, L: Layout, numbers: Numbers) -> None:
    """The blank's size in the view (not only in the title block): its width on a dimension line above the top
    view, its height on one right of it, each text in the middle of its line (or moved along it to where it
    covers no other text)."""
    st = L.stock
    x0, y0 = L.top(st.x0, st.y1)
    x1, y1 = L.top(st.x1, st.y0)
    row = y0 - SIZE_GAP
    for x in (x0, x1):
        svg.line((x, y0 - 1.0), (x, row - 1.5), width=THIN)
        svg.keep((x, y0 - 1.0), (x, row - 1.5))
    svg.line((x0, row), (x1, row), width=THIN)
    svg.keep((x0, row), (x1, row))
    svg.arrow((x0, row), (x1, row))
    svg.arrow((x1, row), (x0, row))
    width = numbers.text(st.x1 - st.x0)
    svg.text(
        ((x0 + x1) / 2, row - 1.0), width, anchor="middle", kind="size", value=numbers.nominal(st.x1 - st.x0)
    )
    column = x1 + HEIGHT_GAP
    for y in (y0, y1):
        svg.line((x1 + 1.0, y), (column + 1.5, y), width=THIN)
        svg.keep((x1 + 1.0, y), (column + 1.5, y))
    svg.line((column, y0), (column, y1), width=THIN)
    svg.keep((column, y0), (column, y1))
    svg.arrow((column, y0), (column, y1))
    svg.arrow((column, y1), (column, y0))
    height = numbers.text(st.y1 - st.y0)
    mid = (y0 + y1) / 2
    at = (column - 1.0, mid)
    for shift in (0.0, -6.0, 6.0, -12.0, 12.0):
        candidate = (column - 1.0, mid + shift)
        if svg.free(text_box(candidate, height, anchor="middle", rotate=-90)):
            at = candidate
            break
    svg.text(at, height, anchor="middle", rotate=-90, kind="size", value=numbers.nominal(st.y1 - st.y0))


def _rotate(d: tuple[float, float], degrees: float) -> tuple[float, float]:
    a = math.radians(degrees)
    return (d[0] * math.cos(a) - d[1] * math.sin(a), d[0] * math.sin(a) + d[1] * math.cos(a))


def _leader(
    svg: Svg,
    at: tuple[float, float],
    direction: tuple[float, float],
    text: str,
    kind: str,
    raw: str,
    length: float = 7.0,
    zone: tuple[float, float] | None = None,
) -> None:
    """A leader from `at` (arrow on the element) outwards, the text at its end: the first of the directions
    near `direction` and lengths where the text covers no other text and the leader crosses none (not into the
    ordinates left of and below the view, `zone`)."""
    n = math.hypot(*direction) or 1.0
    d = (direction[0] / n, direction[1] / n)
    if zone is not None:
        end = (at[0] + d[0] * length, at[1] + d[1] * length)
        if end[0] < zone[0] + 2.0 or end[1] > zone[1] - 2.0:
            d = (-d[0], -d[1])  # the ordinates are left of and below the view: point the other way
    options = []
    for turn in (0.0, 30.0, -30.0, 60.0, -60.0, 180.0, 150.0, -150.0, 90.0, -90.0):
        u = _rotate(d, turn)
        for reach in (length, length + 4.0, length + 9.0, length + 15.0):
            options.append((u, reach))
    choices: list[tuple[bool, int, tuple[float, float], tuple[float, float], str, tuple[float, float]]] = []
    for u, reach in options:
        end = (at[0] + u[0] * reach, at[1] + u[1] * reach)
        right = u[0] >= 0
        shoulder = (end[0] + (4.0 if right else -4.0), end[1])
        anchor = "start" if right else "end"
        place = (shoulder[0] + (0.8 if right else -0.8), shoulder[1] + 1.2)
        box = text_box(place, text, anchor=anchor)
        good = (
            svg.free(box)
            and svg.clear(at, end)
            and svg.clear(end, shoulder)
            and (zone is None or not (box[0] < zone[0] or box[3] > zone[1]))
        )
        choices.append((not good, len(choices), end, shoulder, anchor, place))
        if good:
            break
    _, _, end, shoulder, anchor, place = min(choices)  # the first good one, else the first
    svg.polyline([at, end, shoulder], width=THIN)
    svg.arrow(at, end)
    svg.text(place, text, anchor=anchor, kind=kind, value=raw)


def _outward(L: Layout, p: tuple[float, float]) -> tuple[float, float]:
    """On paper: away from the blank's centre."""
    st = L.stock
    c = L.top((st.x0 + st.x1) / 2, (st.y0 + st.y1) / 2)
    d = (p[0] - c[0], p[1] - c[1])
    return d if math.hypot(*d) > 1e-9 else (1.0, -1.0)


def _aligned(
    svg: Svg, L: Layout, a: tuple[float, float], b: tuple[float, float], text: str, kind: str, raw: str
) -> None:
    """A length along an inclined edge a–b (paper mm): a dimension line parallel to it on the side away from
    the blank's centre, its text parallel to the line (reading from below or from the right)."""
    mid = ((a[0] + b[0]) / 2, (a[1] + b[1]) / 2)
    d = (b[0] - a[0], b[1] - a[1])
    n = math.hypot(*d) or 1.0
    normal = (-d[1] / n, d[0] / n)
    o = _outward(L, mid)
    if normal[0] * o[0] + normal[1] * o[1] < 0:
        normal = (-normal[0], -normal[1])
    angle = math.degrees(math.atan2(d[1], d[0]))
    if angle > 90:
        angle -= 180
    elif angle <= -90:
        angle += 180
    for offset in (5.0, 8.0, 11.0):
        pa = (a[0] + normal[0] * offset, a[1] + normal[1] * offset)
        pb = (b[0] + normal[0] * offset, b[1] + normal[1] * offset)
        at = ((pa[0] + pb[0]) / 2 + normal[0] * 1.0, (pa[1] + pb[1]) / 2 + normal[1] * 1.0)
        # the baseline 1 mm off the line, on its outer side: for a text above the line that is the baseline
        if normal[1] > 0:  # the outer side is below the line on paper: the text hangs under it
            at = (at[0] + normal[0] * TEXT * 0.76, at[1] + normal[1] * TEXT * 0.76)
        if svg.free(text_box(at, text, anchor="middle", rotate=angle)):
            break
    for p, q in ((a, pa), (b, pb)):
        svg.line(
            (p[0] + normal[0] * 1.0, p[1] + normal[1] * 1.0),
            (q[0] + normal[0] * 1.5, q[1] + normal[1] * 1.5),
            width=THIN,
        )
    svg.line(pa, pb, width=THIN)
    svg.arrow(pa, pb)
    svg.arrow(pb, pa)
    svg.text(at, text, anchor="middle", rotate=angle, kind=kind, value=raw)


def _angle_text(svg: Svg, L: Layout, e: Element, text: str, raw: str) -> None:
    """A line's angle beside it, on the side away from the blank's centre, where it covers no other text."""
    pm = L.top(*e.midpoint())
    normal = (-(e.end[1] - e.start[1]), -(e.end[0] - e.start[0]))
    o = _outward(L, pm)
    if normal[0] * o[0] + normal[1] * o[1] < 0:
        normal = (-normal[0], -normal[1])
    n = math.hypot(*normal) or 1.0
    u = (normal[0] / n, normal[1] / n)
    a, b = L.top(*e.start), L.top(*e.end)
    t = ((b[0] - a[0]) / (math.dist(a, b) or 1.0), (b[1] - a[1]) / (math.dist(a, b) or 1.0))
    first = None
    for side in (1.0, -1.0):
        for along in (0.0, 5.0, -5.0, 10.0, -10.0):
            for off in (4.0, 7.0):
                at = (
                    pm[0] + side * u[0] * off + t[0] * along,
                    pm[1] + side * u[1] * off + t[1] * along + 1.2,
                )
                first = first or at
                if svg.free(text_box(at, text, anchor="middle")):
                    svg.text(at, text, anchor="middle", kind="angle", value=raw)
                    return
    assert first is not None
    svg.text(first, text, anchor="middle", kind="angle", value=raw)


def _corner_lines(svg: Svg, L: Layout, feats: list[Feature]) -> None:
    """The sharp corner of a rounded or chamfered corner: the two edges drawn on to it in thin lines, where its
    coordinates are dimensioned (DIN ISO 129-1)."""
    for f in feats:
        for k, corner in transitions(f).items():
            if not on_stock(corner, L.stock):
                continue
            e = f.elements[k]
            c = L.top(*corner)
            for p in (e.start, e.end):
                svg.line(L.top(*p), c, width=0.18)
            svg.circle(c, 0.35, width=0.1, fill="#000")


def _annotations(svg: Svg, L: Layout, feats: list[Feature], numbers: Numbers) -> None:
    """Radii (programmed, and the tool's own radius in the inside corners of a contour), chamfers and line
    angles beside the elements."""
    st = L.stock
    zone = (L.top(st.x0, 0)[0], L.top(0, st.y0)[1])  # left and bottom edge of the top view
    done_radii: set[tuple[float, float, float]] = set()
    for f in feats:
        corners = transitions(f)
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
                _leader(
                    svg,
                    pm,
                    (pm[0] - pc[0], pm[1] - pc[1]),
                    f"R{numbers.text(e.radius)}",
                    "r",
                    numbers.nominal(e.radius),
                    zone=zone,
                )
                if k not in corners:  # a rounded corner is dimensioned to the corner, not to the centre
                    cx, cy = pc
                    svg.line((cx - 2.5, cy), (cx + 2.5, cy), width=0.18)
                    svg.line((cx, cy - 2.5), (cx, cy + 2.5), width=0.18)
                continue
            if 0 < k < len(f.elements) - 1:
                leg = chamfer_leg(f.elements[k - 1], e, f.elements[k + 1])
                if leg is not None and on_stock(mid, st):
                    if numbers.stated(leg) or not numbers.stated(e.length()):
                        _leader(
                            svg,
                            L.top(*mid),
                            _outward(L, L.top(*mid)),
                            f"{numbers.text(leg)}×45°",
                            "chamfer",
                            numbers.nominal(leg),
                            zone=zone,
                        )
                    else:  # the program gives the chamfer's length (#CHF), not its leg: that length and 45°
                        _aligned(
                            svg,
                            L,
                            L.top(*e.start),
                            L.top(*e.end),
                            numbers.text(e.length()),
                            "chamfer",
                            numbers.nominal(e.length()),
                        )
                        _angle_text(svg, L, e, "45°", "45")
                    continue
            angle = line_angle(e)
            if angle is not None and on_stock(mid, st):
                _angle_text(svg, L, e, f"{numbers.text(angle)}°", numbers.nominal(angle))
        r = f.tool_diameter / 2
        inside = [(c, p) for c, p in machined_corners(f) if on_stock(c, st)]
        if f.compensated and inside and r > 0:
            corner, centre = inside[0]
            d = (corner[0] - centre[0], corner[1] - centre[1])
            n = math.hypot(*d) or 1.0
            on_arc = L.top(centre[0] + d[0] / n * r, centre[1] + d[1] / n * r)
            pc = L.top(*centre)
            _leader(
                svg,
                on_arc,
                (pc[0] - on_arc[0], pc[1] - on_arc[1]) if n > r else (on_arc[0] - pc[0], on_arc[1] - pc[1]),
                f"{len(inside)}× R{numbers.text(r)}" if len(inside) > 1 else f"R{numbers.text(r)}",
                "r",
                numbers.nominal(r),
                length=5.0,
            )


def _callouts(
    svg: Svg,
    L: Layout,
    feats: list[Feature],
    bores: list[Hole],
    numbers: Numbers,
    extra: list[tuple[float, str, str, tuple[float, float]]] | None = None,
) -> None:
    """One callout per kind of feature (depth, and width for slots; diameter and depth for holes), in a column
    right of the top view, each at the height of what it names or below, where its leader crosses no text."""
    st = L.stock
    labels = LABELS[numbers.lang]
    items: list[
        tuple[float, str, str, tuple[float, float]]
    ] = []  # (workpiece y, text, raw depth, paper point)
    kinds: dict[tuple[float, float, bool], list[Feature]] = {}
    for f in feats:
        if any(visible(e, st) for e in f.elements):
            kinds.setdefault(
                (round(st.z1 - f.z, 6), 0.0 if f.compensated else f.tool_diameter, f.compensated), []
            ).append(f)
    for (depth, width, _), group in kinds.items():
        text = f"{labels['depth']} {numbers.text(depth)}"
        if width > 0:
            text = labels["slot"].format(w=numbers.text(width)) + f", {text}"
        if len(group) > 1:
            text = f"{len(group)}× {text}"
        shown = [e for e in group[0].elements if visible(e, st) and on_stock(e.midpoint(), st)]
        if not shown:
            continue
        e = max(shown, key=lambda x: (x.midpoint()[0], x.length()))
        # a line's point a third along it (its middle may carry its angle), an arc's middle
        at = (
            e.midpoint()
            if e.is_arc
            else (e.start[0] + (e.end[0] - e.start[0]) / 3, e.start[1] + (e.end[1] - e.start[1]) / 3)
        )
        if not on_stock(at, st):
            at = e.midpoint()
        items.append((at[1], text, numbers.nominal(depth), L.top(*at)))
    sizes: dict[tuple[float, float, str], list[Hole]] = {}
    for bore in bores:
        sizes.setdefault((round(bore.diameter, 6), round(st.z1 - bore.z, 6), bore.name), []).append(bore)
    for (diameter, depth, name), alike in sizes.items():
        text = f"Ø{numbers.text(diameter)}, {labels['depth']} {numbers.text(depth)}"
        if name:
            text = f"{name}, " + labels["thread_depth"].format(d=numbers.text(depth))
        if len(alike) > 1:
            text = f"{len(alike)}× {text}"
        hole = max(alike, key=lambda h: (h.x, h.y))
        px, py = L.top(hole.x, hole.y)
        items.append(
            (
                hole.y,
                text,
                numbers.nominal(depth),
                (px + diameter / 2 * L.s * math.sqrt(0.5), py - diameter / 2 * L.s * math.sqrt(0.5)),
            )
        )
    items += extra or []
    column = L.top(st.x1, 0)[0] + COLUMN
    previous = -math.inf
    for _, text, raw, pm in sorted(items, key=lambda i: -i[0]):
        ty = max(pm[1], previous + SPACING + 1.0)
        for _ in range(60):
            if svg.free(text_box((column + 1.0, ty + 1.2), text)) and svg.clear(pm, (column - 2.0, ty)):
                break
            ty += 1.0
        previous = ty
        svg.polyline([pm, (column - 2.0, ty), (column, ty)], width=THIN)
        svg.circle(pm, 0.5, fill="#000")
        svg.text((column + 1.0, ty + 1.2), text, kind="depth", value=raw)


def _centre_lines(svg: Svg, L: Layout, feats: list[Feature], bores: list[Hole]) -> None:
    """Slots milled without compensation: their centre line (the programmed path) as a thin dash-dot line; a
    hole's centre lines across it."""
    for f in feats:
        if f.compensated:
            continue
        for e in f.elements:
            if visible(e, L.stock):
                svg.path(_element_path(L, e), width=0.18, dash="centre", clip_path="url(#blank)")
    for b in bores:
        cx, cy = L.top(b.x, b.y)
        reach = b.diameter / 2 * L.s + 2.0
        svg.line((cx - reach, cy), (cx + reach, cy), width=0.18, dash="centre")
        svg.line((cx, cy - reach), (cx, cy + reach), width=0.18, dash="centre")


# ---- what the PAL cycles made (core/drawing/cycles.py) ------------------------------------------------------


def _on(p: Pocket, u: float, v: float) -> tuple[float, float]:
    """A point of the pocket's own frame (u along LP, v along BP, from its centre) in the part, turned by AR."""
    a = math.radians(p.angle)
    return (p.x + u * math.cos(a) - v * math.sin(a), p.y + u * math.sin(a) + v * math.cos(a))


def _polar(c: tuple[float, float], r: float, degrees: float) -> tuple[float, float]:
    return (c[0] + r * math.cos(math.radians(degrees)), c[1] + r * math.sin(math.radians(degrees)))


def _cross_lines(
    svg: Svg,
    L: Layout,
    a: tuple[float, float],
    b: tuple[float, float],
    c: tuple[float, float],
    d: tuple[float, float],
) -> None:
    """Two centre lines (dash-dot) a–b and c–d (part coordinates), reaching 2 mm beyond on paper."""
    for p, q in ((a, b), (c, d)):
        pa, pb = L.top(*p), L.top(*q)
        n = math.dist(pa, pb) or 1.0
        u = ((pb[0] - pa[0]) / n * 2.0, (pb[1] - pa[1]) / n * 2.0)
        svg.line((pa[0] - u[0], pa[1] - u[1]), (pb[0] + u[0], pb[1] + u[1]), width=0.18, dash="centre")


def _cycle_lines(svg: Svg, L: Layout, made: Cycles) -> None:
    """The centre lines of the pockets and slots, the arc slot's centre line, the pitch circles and the
    threads' outer diameter (a thin three-quarter circle, DIN ISO 6410)."""
    for p in made.pockets:
        if p.code == "G75":
            c = (p.x, p.y)
            s0, s1 = _polar(c, p.arc_radius, p.start), _polar(c, p.arc_radius, p.start + p.sweep)
            r = p.arc_radius * L.s
            e0, e1 = L.top(*s0), L.top(*s1)
            flag = 0 if p.sweep > 0 else 1
            large = 1 if abs(p.sweep) > 180 else 0
            svg.path(
                f"M{num(e0[0])} {num(e0[1])} A{num(r)} {num(r)} 0 {large} {flag} {num(e1[0])} {num(e1[1])}",
                width=0.18,
                dash="centre",
            )
            for q in (s0, s1):
                svg.line(L.top(*c), L.top(*q), width=0.18, dash="centre")
            continue
        half_u = p.length / 2 if p.code != "G73" else p.radius
        half_v = p.width / 2 if p.code != "G73" else p.radius
        _cross_lines(svg, L, _on(p, -half_u, 0), _on(p, half_u, 0), _on(p, 0, -half_v), _on(p, 0, half_v))
    for t in made.patterns:
        if t.code != "G77":
            continue
        c = L.top(*t.centre)
        r = t.radius * L.s
        svg.path(
            f"M{num(c[0] + r)} {num(c[1])} A{num(r)} {num(r)} 0 1 1 {num(c[0] - r)} {num(c[1])} "
            f"A{num(r)} {num(r)} 0 1 1 {num(c[0] + r)} {num(c[1])}",
            width=0.18,
            dash="centre",
        )
        reach = 2.5
        svg.line((c[0] - reach, c[1]), (c[0] + reach, c[1]), width=0.18)
        svg.line((c[0], c[1] - reach), (c[0], c[1] + reach), width=0.18)
    for b in made.holes:
        if b.name:
            cx, cy = L.top(b.x, b.y)
            r = b.diameter / 2 * L.s
            svg.path(f"M{num(cx + r)} {num(cy)} A{num(r)} {num(r)} 0 1 0 {num(cx)} {num(cy + r)}", width=THIN)


def _cycle_marks(
    svg: Svg, L: Layout, made: Cycles, numbers: Numbers
) -> list[tuple[float, str, str, tuple[float, float]]]:
    """The radii, angles and spacings of what the cycles made; their callouts (size and depth) for the column
    right of the view."""
    st = L.stock
    labels = LABELS[numbers.lang]
    zone = (L.top(st.x0, 0)[0], L.top(0, st.y0)[1])
    items: list[tuple[float, str, str, tuple[float, float]]] = []
    t = numbers.text
    for p in made.pockets:
        depth = st.z1 - p.z
        tail = f"{labels['depth']} {t(depth)}"
        turned = f", {t(p.angle)}°" if abs(p.angle) > 1e-9 and p.code != "G75" else ""
        if p.code == "G72":
            text = f"{t(p.length)} × {t(p.width)}{turned}, {tail}"
            spots = [
                _on(p, p.length / 2, 0),
                _on(p, 0, p.width / 2),
                _on(p, -p.length / 2, 0),
                _on(p, 0, -p.width / 2),
            ]
            if p.radius > 0:
                k = p.radius * (1 - math.sqrt(0.5))
                corner, pc = L.top(*_on(p, p.length / 2 - k, p.width / 2 - k)), L.top(p.x, p.y)
                _leader(
                    svg,
                    corner,
                    (corner[0] - pc[0], corner[1] - pc[1]),
                    f"R{t(p.radius)}",
                    "r",
                    numbers.nominal(p.radius),
                    zone=zone,
                )
        elif p.code == "G73":
            text = f"Ø{t(p.length)}, {tail}"
            spots = [
                _on(p, p.radius * math.sqrt(0.5), p.radius * math.sqrt(0.5)),
                _on(p, -p.radius, 0),
                _on(p, 0, -p.radius),
            ]
        elif p.code == "G74":
            text = f"{t(p.length)} × {t(p.width)}{turned}, {tail}"
            spots = [_on(p, 0, p.width / 2), _on(p, 0, -p.width / 2)]
            end = L.top(*_on(p, p.length / 2, 0))
            _leader(
                svg,
                end,
                (end[0] - L.top(p.x, p.y)[0], end[1] - L.top(p.x, p.y)[1]),
                f"R{t(p.radius)}",
                "r",
                numbers.nominal(p.radius),
                zone=zone,
            )
        else:
            c = (p.x, p.y)
            mid = p.start + p.sweep / 2
            text = labels["slot"].format(w=t(p.width)) + f", {tail}"
            spots = [_polar(c, p.arc_radius + p.width / 2, mid), _polar(c, p.arc_radius - p.width / 2, mid)]
            on_line = L.top(*_polar(c, p.arc_radius, p.start + p.sweep / 3))
            pc = L.top(*c)
            _leader(
                svg,
                on_line,
                (on_line[0] - pc[0], on_line[1] - pc[1]),
                f"R{t(p.arc_radius)}",
                "r",
                numbers.nominal(p.arc_radius),
                zone=zone,
            )
            _angle_label(
                svg, L, c, p.arc_radius * 0.45, p.start / 2, f"{t(p.start)}°", numbers.nominal(p.start)
            )
            _angle_label(svg, L, c, p.arc_radius * 0.45, mid, f"{t(p.sweep)}°", numbers.nominal(p.sweep))
            if abs(p.start) > 1e-9:  # the angle's other leg: the X direction through the centre
                svg.line(L.top(*c), L.top(*_polar(c, p.arc_radius, 0.0)), width=0.18, dash="centre")
        at = next((q for q in spots if on_stock(q, st)), None)  # a point of its edge that lies on the blank
        if at is not None:
            items.append((at[1], text, numbers.nominal(depth), L.top(*at)))
    for pattern in made.patterns:
        if pattern.code == "G77":
            c = pattern.centre
            pc = L.top(*c)
            mid = pattern.start + pattern.step / 2
            on_circle = L.top(*_polar(c, pattern.radius, mid + pattern.step))
            _leader(
                svg,
                on_circle,
                (on_circle[0] - pc[0], on_circle[1] - pc[1]),
                labels["pitch_circle"].format(d=t(2 * pattern.radius)),
                "diameter",
                numbers.nominal(2 * pattern.radius),
                zone=zone,
            )
            first, second = (
                pattern.points[0],
                pattern.points[1] if len(pattern.points) > 1 else pattern.points[0],
            )
            for q in (first, second):
                svg.line(pc, L.top(*q), width=0.18, dash="centre")
            svg.line(pc, L.top(*_polar(c, pattern.radius, 0.0)), width=0.18, dash="centre")
            _angle_label(
                svg,
                L,
                c,
                pattern.radius * 0.55,
                pattern.start / 2,
                f"{t(pattern.start)}°",
                numbers.nominal(pattern.start),
            )
            _angle_label(
                svg, L, c, pattern.radius * 0.55, mid, f"{t(pattern.step)}°", numbers.nominal(pattern.step)
            )
        elif pattern.code == "G76" and len(pattern.points) > 2:  # two holes: their ordinates say it
            a, b = L.top(*pattern.points[0]), L.top(*pattern.points[1])
            _aligned(svg, L, a, b, t(pattern.step), "spacing", numbers.nominal(pattern.step))
    return items


def _angle_label(
    svg: Svg, L: Layout, c: tuple[float, float], r: float, degrees: float, text: str, raw: str
) -> None:
    """An angle's text inside its legs at the centre c, a little further out where it would cover a text."""
    spots = [
        (px, py + 1.2) for px, py in (L.top(*_polar(c, r * k, degrees)) for k in (1.0, 1.3, 0.75, 1.6, 0.5))
    ]
    at = next((q for q in spots if svg.free(text_box(q, text, anchor="middle"))), spots[0])
    svg.text(at, text, anchor="middle", kind="angle", value=raw)


def _coordinate_table(
    svg: Svg, pts: list[tuple[float, float]], L: Layout, numbers: Numbers, at: tuple[float, float]
) -> None:
    """The fallback: numbered points in the view and their X/Y in a table."""
    unique: list[tuple[float, float]] = []
    for p in pts:
        if all(math.dist(p, q) > POINT_TOLERANCE for q in unique):
            unique.append(p)
    x, y = at
    svg.text((x, y), LABELS[numbers.lang]["table"], size=3.5, weight="bold")
    rows = unique[:40]
    for i, p in enumerate(rows, start=1):
        px, py = L.top(*p)
        svg.circle((px, py), 0.6, fill="#000")
        for dx, dy in ((1.2, -1.0), (1.2, 3.0), (-1.2, -1.0), (-1.2, 3.0)):
            spot = (px + dx, py + dy)
            anchor = "start" if dx > 0 else "end"
            if svg.free(text_box(spot, str(i), size=2.5, anchor=anchor), gap=0.2):
                break
        svg.text(spot, str(i), size=2.5, anchor=anchor)
        ry = y + 4.5 * i
        svg.text((x, ry), f"P{i}", size=3.0)
        svg.text(
            (x + 22, ry), numbers.dimension(p[0]), size=3.0, anchor="end", kind="x", value=numbers.raw(p[0])
        )
        svg.text(
            (x + 42, ry), numbers.dimension(p[1]), size=3.0, anchor="end", kind="y", value=numbers.raw(p[1])
        )


def _section_row(hm: HeightMap, floors: list[float]) -> int:
    """The row of the height map the section runs along: the one that meets the most programmed floors (a
    pocket's depth is shown, not only the holes beside it), then crosses the most edges (then the deepest, then
    the one nearest the middle)."""
    h, g = hm.heights, hm.grid
    met = np.zeros(g.ny, dtype=int)
    for z in floors:
        met += np.any(np.abs(h - z) < 0.01, axis=1)
    changes = (np.abs(np.diff(h, axis=1)) > 1e-6).sum(axis=1)
    deepest = h.min(axis=1)
    middle = np.abs(np.arange(g.ny) - g.ny / 2)
    return int(np.lexsort((middle, deepest, -changes, -met))[0])


def _cut_line(svg: Svg, L: Layout, y: float) -> None:
    """The section line A–A in the top view."""
    st = L.stock
    a, b = L.top(st.x0, y), L.top(st.x1, y)
    svg.line((a[0] - 6, a[1]), (b[0] + 6, b[1]), width=THIN, dash="centre")
    svg.keep((a[0] - 6, a[1]), (b[0] + 6, b[1]))
    for end, sign in ((a[0] - 6, -1), (b[0] + 6, 1)):
        svg.line((end, a[1]), (end - sign * 3, a[1]), width=THICK)
        svg.line((end - sign * 1.5, a[1]), (end - sign * 1.5, a[1] + 4), width=THIN)
        svg.arrow((end - sign * 1.5, a[1] + 4), (end - sign * 1.5, a[1]))
        svg.text((end - sign * 1.5, a[1] - 1.5), "A", anchor="middle", size=3.5)


def _section(
    svg: Svg,
    L: Layout,
    hm: HeightMap,
    j: int,
    floors: list[float],
    numbers: Numbers,
    bores: list[Hole] | None = None,
) -> None:
    """Section A–A along X through row j of the height map, its Z ordinates right of it (with the depth of the
    holes the section cuts through: a drill's tip lies between the cells)."""
    st, g = L.stock, hm.grid
    row = hm.heights[j]
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
    svg.text(((x0 + x1) / 2, y0 - 4.0), f"{LABELS[numbers.lang]['section']} A–A", anchor="middle", size=3.5)
    # Z ordinates on the right: the top, every programmed floor the section meets, the base
    levels = [st.z1] + [z for z in floors if np.any(np.abs(row - z) < 0.01)] + [st.z0]
    y = g.y0 + (j + 0.5) * g.dy
    levels += [b.z for b in bores or [] if abs(b.y - y) <= b.diameter / 4 and b.z > st.z0]
    base_x = x1 + 8.0
    previous = -math.inf
    for z in sorted({round(v, 6) for v in levels}, reverse=True):
        px, py = L.side(st.x1, z)
        text = numbers.text(z)
        ty = max(py, previous + SPACING)
        for _ in range(40):
            if svg.free(text_box((base_x + 1.5, ty + 1.2), text)):
                break
            ty += 0.5
        previous = ty
        svg.polyline([(px + 1.0, py), (base_x - 3.0, py), (base_x, ty), (base_x + 0.5, ty)], width=0.18)
        svg.text((base_x + 1.5, ty + 1.2), text, kind="z", value=numbers.raw(z))


def part_drawing(exercise: Exercise, lang: str = "de") -> str:
    """The dimensioned drawing of the exercise's part as an SVG document (A4 landscape, mm)."""
    lang = "en" if lang == "en" else "de"
    if exercise.lathe:
        return turned_part_drawing(exercise, lang)
    numbers = Numbers.of(lang, exercise.reference, *exercise.subprograms.values())
    stock = exercise.stock.stock()
    result = execute(exercise, exercise.reference)
    hm = result.sim.heightmap
    tools = exercise.tool_table()
    made = cycles(
        exercise.reference,
        exercise.dialect,
        result.toolpath.moves,
        tools,
        exercise_tool_names(exercise),
        lang,
    )
    moves = [m for m in result.toolpath.moves if id(m) not in made.handled]
    feats = features(moves, stock, tools)
    bores = holes(moves, stock, tools) + [b for b in made.holes if on_stock((b.x, b.y), stock)]
    floors = sorted(
        {round(f.z, 6) for f in feats if f.z > stock.z0 - 1e-6}
        | {round(b.z, 6) for b in bores if b.z > stock.z0 - 1e-6}
        | {round(p.z, 6) for p in made.pockets if p.z > stock.z0 - 1e-6}
    )
    on_circle = {(round(x, 6), round(y, 6)) for t in made.patterns if t.code == "G77" for x, y in t.points}
    pts = (
        [p for f in feats for p in points(f, stock)]
        + [(b.x, b.y) for b in bores if (round(b.x, 6), round(b.y, 6)) not in on_circle]
        + [(p.x, p.y) for p in made.pockets if on_stock((p.x, p.y), stock)]
        + [t.centre for t in made.patterns if t.code == "G77" and on_stock(t.centre, stock)]
    )
    if on_stock((0.0, 0.0), stock):
        pts.append((0.0, 0.0))
    free = _free_form(hm, floors, bores + made.drilled)
    too_many = (
        len(distinct([p[0] for p in pts])) > MAX_ORDINATES
        or len(distinct([p[1] for p in pts])) > MAX_ORDINATES
    )
    table = free or too_many
    L = _layout(stock, *((0.0, 0.0) if table else _ordinate_texts(pts, numbers)))
    svg = Svg(*SHEET)
    svg.defs.append(
        '<pattern id="hatch" width="2" height="2" patternUnits="userSpaceOnUse" '
        'patternTransform="rotate(45)"><line x1="0" y1="0" x2="0" y2="2" stroke="#000" '
        'stroke-width="0.18"/></pattern>'
    )
    bx0, by0 = L.top(stock.x0, stock.y1)
    bx1, by1 = L.top(stock.x1, stock.y0)
    svg.defs.append(
        f'<clipPath id="blank"><rect x="{num(bx0)}" y="{num(by0)}" width="{num(bx1 - bx0)}" '
        f'height="{num(by1 - by0)}"/></clipPath>'
    )
    frame(svg)
    title_block(svg, exercise, L.s, lang)
    svg.take((SHEET[0] - MARGIN - TITLE_BLOCK[0], SHEET[1] - MARGIN - TITLE_BLOCK[1], SHEET[0], SHEET[1]))
    svg.text((bx0, by0 - VIEW_TITLE), LABELS[lang]["top"], size=3.5)
    # the machined part's edges, then the blank as a phantom line
    for edge in _edges(hm, floors):
        svg.polyline([L.top(float(x), float(y)) for x, y in _simplify(edge, hm.grid.dx * 0.3)], width=THICK)
    svg.path(f"M{num(bx0)} {num(by0)} H{num(bx1)} V{num(by1)} H{num(bx0)} Z", width=THIN, dash="phantom")
    _centre_lines(svg, L, feats, bores)
    _cycle_lines(svg, L, made)
    _corner_lines(svg, L, feats)
    zero = L.top(0.0, 0.0)
    _zero_symbol(svg, zero)
    _axes(svg, zero)
    j = _section_row(hm, [] if free else floors)
    _cut_line(svg, L, hm.grid.y0 + (j + 0.5) * hm.grid.dy)
    if table:
        _coordinate_table(svg, pts, L, numbers, (SHEET[0] - MARGIN - TITLE_BLOCK[0], MARGIN + 8.0))
    else:
        _ordinates(svg, L, pts, numbers)
    _size(svg, L, numbers)
    _annotations(svg, L, feats, numbers)
    marked = _cycle_marks(svg, L, made, numbers)
    _callouts(svg, L, feats, bores, numbers, marked)
    _section(svg, L, hm, j, [] if free else floors, numbers, bores)
    mark_views(svg, (bx0, by0, bx1, by1), (*L.side(stock.x0, stock.z1), *L.side(stock.x1, stock.z0)))
    return svg.document(f"{exercise.title.get(lang)} — {exercise.id}")


# what other packages take from here (core/sheet: the sheet's size and the number format)
__all__ = ["KIND_NAMES_EN", "MARGIN", "SHEET", "part_drawing", "scale_text", "turned_part_drawing", "value"]
