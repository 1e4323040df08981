"""The dimensioned drawing of a turned part, as lathe drawings are dimensioned (DIN ISO 128 / 129): SVG, A4.

The part lies with the spindle axis horizontal, the front face (the workpiece zero Z0, as in the TRAUB manual)
on the right and the chuck side on the left. The upper half is cut open (half section, hatched: bores and
inside threads show), the lower half is the view. Diameters carry "Ø" on dimension lines across the axis,
their text in the view half; lengths are running dimensions from the front face in one row above the part
(DIN 406-11, the origin a small circle at Z0); radii, 45° chamfers, tapers and grooves are called out under the
part; a thread by its designation "M35×1,5" on its dimension line. The blank is a thin phantom outline.
The numbers come from core/drawing/turned_features.py: never one the program does not give.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from core.drawing.frame import (
    LABELS,
    MARGIN,
    SCALES,
    SHEET,
    SPACING,
    TITLE_BLOCK,
    Numbers,
    frame,
    mark_views,
    title_block,
)
from core.drawing.svg import CHAR, THICK, THIN, Svg, num
from core.drawing.turned_features import SAME, P, TurnedPart, loops, points, turned_part
from core.exercises import Exercise

CLEAR = 4.0  # mm on paper: a diameter's line this far from edges and other lines stands clear
ROW_HEIGHT = 5.5  # mm between the rows of callouts under the part
MAX_ROWS = 6
ROW_GAP = 9.0  # mm from the part's top to the running dimensions' line
TEXT = 3.5
EDGE_WINDOW, EDGE_STEP, EDGE_MERGE = 0.6, 0.05, 1.0  # mm: how an edge of the outline is found (_edges)
EDGE_ANGLE = math.radians(35)
HATCH = (
    '<pattern id="hatch" width="2.5" height="2.5" patternUnits="userSpaceOnUse" '
    'patternTransform="rotate(45)"><line x1="0" y1="0" x2="0" y2="2.5" stroke="#000" '
    'stroke-width="0.18"/></pattern>'
)


def _width(text: str, size: float = TEXT) -> float:
    return len(text) * CHAR * size


def _diameter(d: float, numbers: Numbers) -> str:
    """Ø and the diameter; in brackets (an auxiliary dimension) where the program computes it."""
    return f"Ø{numbers.text(d)}" if numbers.stated(d) else f"(Ø{numbers.text(d)})"


@dataclass(frozen=True)
class Layout:
    """Paper position of the part: Z to the right (Z0, the front face, at `right`), the radius up from `axis`."""

    s: float
    right: float
    axis: float
    row: float  # the running dimensions' line above the part
    radius: float  # the blank's radius (mm)
    length: float

    def at(self, z: float, r: float) -> tuple[float, float]:
        return (self.right + z * self.s, self.axis - r * self.s)

    @property
    def bottom(self) -> float:
        return self.axis + self.radius * self.s


def _drawn_length(part: TurnedPart) -> float:
    """How much of the bar is drawn from the face: all of it, or where the turning ends and a stub more
    (broken off there) when the rest up to the chuck is the plain blank."""
    turned = -part.machined_from()
    length = 5.0 * math.ceil((turned + max(8.0, 0.1 * turned)) / 5.0)
    return length if length < part.blank.length - 5.0 else part.blank.length


def _layout(part: TurnedPart, rows: int, length: float, numbers: Numbers) -> Layout:
    """The largest standard scale at which the part, its dimensions above and callouts below fit the sheet
    beside (or above) the title block; the whole in the middle of the room it has."""
    radius = part.blank.diameter / 2
    title_top = SHEET[1] - MARGIN - TITLE_BLOCK[1]
    title_left = SHEET[0] - MARGIN - TITLE_BLOCK[0]
    # above: the running dimensions' row ROW_GAP over the part, their texts over it; below: the callouts
    longest = max((_width(numbers.dimension(abs(z))) for z in part.z_values), default=0.0)
    above, below = ROW_GAP + 4.0 + longest, 10.0 + rows * ROW_HEIGHT
    left_room, right_room = MARGIN + 10.0, 14.0
    for s in SCALES:
        width, height = length * s, 2 * radius * s
        if width + left_room + right_room > SHEET[0] - MARGIN:
            continue
        centred = left_room + (SHEET[0] - MARGIN - right_room - left_room - width) / 2 + width
        for right, floor in (
            (centred, title_top - 2.0),
            (min(centred, title_left - right_room), SHEET[1] - MARGIN),
        ):
            if right - width < left_room or (floor > title_top and right > title_left - right_room):
                continue
            spare = floor - (MARGIN + 3.0) - above - height - below
            if spare >= 0:
                row = MARGIN + 3.0 + spare / 2 + above - ROW_GAP
                return Layout(s, right, row + ROW_GAP + radius * s, row, radius, length)
    s = SCALES[-1]
    row = MARGIN + above
    return Layout(s, left_room + length * s, row + ROW_GAP + radius * s, row, radius, length)


# ---- the part ---------------------------------------------------------------------------------------------


def _edges(outline: list[P]) -> list[float]:
    """The Z of the outline's edges: where its direction over EDGE_WINDOW mm before and after a point differs
    by more than EDGE_ANGLE (a sharp corner, or one the nose rounded; not a tangent arc sampled in steps).
    These are the circles seen edge-on in the view."""
    pts = np.asarray(outline, dtype=np.float64)
    if len(pts) < 3:
        return []
    steps = np.hypot(*np.diff(pts, axis=0).T)
    along = np.concatenate([[0.0], np.cumsum(steps)])
    if along[-1] < 2 * EDGE_WINDOW:
        return []
    t = np.arange(0.0, along[-1], EDGE_STEP)
    z, r = np.interp(t, along, pts[:, 0]), np.interp(t, along, pts[:, 1])
    k = max(1, round(EDGE_WINDOW / EDGE_STEP))
    before = np.stack([z[k:-k] - z[: -2 * k], r[k:-k] - r[: -2 * k]], axis=1)
    after = np.stack([z[2 * k :] - z[k:-k], r[2 * k :] - r[k:-k]], axis=1)
    cos = (before * after).sum(axis=1) / np.maximum(np.hypot(*before.T) * np.hypot(*after.T), 1e-12)
    turn = np.arccos(np.clip(cos, -1.0, 1.0))
    out: list[float] = []
    last = -np.inf
    for i in np.flatnonzero(turn > EDGE_ANGLE):
        peak = i
        if t[i + k] - last < EDGE_MERGE:
            continue
        j = i
        while j + 1 < len(turn) and turn[j + 1] > EDGE_ANGLE:
            j += 1
            if turn[j] > turn[peak]:
                peak = j
        last = t[j + k]
        out.append(float(z[peak + k]))
    return out


def _drawn_loops(part: TurnedPart, length: float) -> list[list[P]]:
    k = int(np.searchsorted(part.zs, -length))
    return (
        loops(part.outer[k:], part.inner[k:], float(part.zs[k]) - part.dz / 2, part.dz)
        if k < len(part.zs)
        else []
    )


def _break(svg: Svg, L: Layout, z: float, r: float) -> None:
    """A freehand break line (thin, DIN ISO 128-20 type 01.1) across the bar at z, from −r to r."""
    x, top, low = L.at(z, 0)[0], L.axis - r * L.s, L.axis + r * L.s
    waves = max(2, round((low - top) / 12.0))
    n = 8 * waves
    pts = [(x + 1.2 * math.sin(2 * math.pi * waves * i / n), top + (low - top) * i / n) for i in range(n + 1)]
    svg.polyline(pts, width=THIN)


def _part(svg: Svg, L: Layout, part: TurnedPart) -> list[tuple[float, float]]:
    """Upper half: the section, hatched, with the bore's edges behind it; lower half: the outside as seen;
    where the bar is drawn shorter than it is, a break line. Returns the view's vertical lines: (paper x,
    how far below the axis in paper mm)."""
    lines: list[tuple[float, float]] = []
    cut = -L.length if L.length < part.blank.length - 1e-6 else None
    for loop in _drawn_loops(part, L.length):
        svg.polyline([L.at(z, r) for z, r in loop], width=0.0, closed=True, fill="url(#hatch)")
        # the outline, not where it runs on the axis (there the section meets the view: the centre line)
        run: list[P] = []
        for p, q in zip(loop, loop[1:] + loop[:1], strict=True):
            broken = cut is not None and abs(p[0] - cut) < part.dz and abs(q[0] - cut) < part.dz
            if (p[1] < 1e-6 and q[1] < 1e-6) or broken:
                svg.polyline([L.at(*v) for v in run], width=THICK)
                run = []
                continue
            run = run + [p, q] if not run else run + [q]
        svg.polyline([L.at(*v) for v in run], width=THICK)
        n = len(loop)
        # the loop is: front face top, outside towards -Z, back face, bore towards +Z; split it where r is the
        # outside (first half of the points up to the minimum Z) and the bore
        k = min(range(n), key=lambda i: (loop[i][0], -loop[i][1]))
        outside = loop[: k + 1]
        bore = loop[k + 1 :]
        svg.polyline([L.at(z, -r) for z, r in outside], width=THICK)
        front, back = outside[0], outside[-1]
        ends = [(front[0], front[1])] + (
            [(back[0], back[1])] if cut is None or back[0] > cut + part.dz else []
        )
        for z, reach in ends + [(z, part.silhouette(z, 2 * SAME + 0.06)) for z in _edges(outside)]:
            svg.line(L.at(z, 0.0), L.at(z, -reach), width=THICK)
            lines.append((L.at(z, 0.0)[0], reach * L.s))
        for z in _edges(bore):
            near = [r for zz, r in bore if abs(zz - z) <= 0.1]
            low = min(near) if near else 0.0
            if low > 1e-6:
                svg.line(L.at(z, 0.0), L.at(z, low), width=THICK)
    if cut is not None:
        _break(svg, L, cut, part.radius_at(cut + part.dz))
    return lines


def _threads(svg: Svg, L: Layout, part: TurnedPart) -> None:
    """DIN ISO 6410: the thread's root (outside) or nominal diameter (inside) thin over its length, the end
    of the usable thread a thick line."""
    for t in part.threads:
        if t.inside:
            svg.line(L.at(t.z_lo, t.other), L.at(t.z_hi, t.other), width=THIN)
            core = part.radius_at(t.z_lo + SAME, True)
            svg.line(L.at(t.z_lo, core), L.at(t.z_lo, t.other), width=THICK)
        else:
            for sign in (1.0, -1.0):
                svg.line(L.at(t.z_lo, sign * t.other), L.at(t.z_hi, sign * t.other), width=THIN)
            svg.line(L.at(t.z_lo, -t.nominal / 2), L.at(t.z_lo, -t.other), width=THICK)


def _blank(svg: Svg, L: Layout, part: TurnedPart) -> None:
    """The blank as a thin phantom line (open at a break)."""
    b = part.blank
    x0, y0 = L.at(-L.length, b.diameter / 2)
    x1, y1 = L.at(0.0, -b.diameter / 2)
    close = f" H{num(x0)} Z" if L.length >= b.length - 1e-6 else f" H{num(x0)}"
    svg.path(f"M{num(x0)} {num(y0)} H{num(x1)} V{num(y1)}{close}", width=THIN, dash="phantom")
    if b.bore > 0:
        for sign in (1.0, -1.0):
            svg.line(
                L.at(-L.length, sign * b.bore / 2), L.at(0.0, sign * b.bore / 2), width=THIN, dash="phantom"
            )
    # the centre line, a little beyond the part
    svg.line((x0 - 5.0, L.axis), (x1 + 8.0, L.axis), width=THIN, dash="centre")


# ---- dimensions -------------------------------------------------------------------------------------------


@dataclass
class _Diameter:
    lo: float  # paper x range where the line may stand
    hi: float
    r: float  # mm: the arrows' radius
    text: str
    kind: str
    raw: str
    inside: bool


def _same_radius(part: TurnedPart, z: float, r: float, inside: bool, length: float) -> tuple[float, float]:
    """The Z range around z where the part keeps the radius r (a point's diameter may be dimensioned there)."""
    same = np.abs((part.inner if inside else part.outer) - r) < 0.02
    near = np.flatnonzero(same & (np.abs(part.zs - z) <= 1.0))  # the nose may round the corner at z itself
    if len(near):
        j = int(near[np.argmin(np.abs(part.zs[near] - z))])
        a = b = j
        while a > 0 and same[a - 1] and part.zs[a - 1] > -length:
            a -= 1
        while b + 1 < len(same) and same[b + 1]:
            b += 1
        return float(part.zs[a]), float(part.zs[b])
    return z, z


def _diameters(part: TurnedPart, L: Layout, numbers: Numbers) -> list[_Diameter]:
    """A dimension line per cylinder of the part (outside and bore) and per thread; a programmed point's
    diameter no cylinder gives (the end of a taper or arc, a groove's bottom) gets one where the part has it."""
    out: list[_Diameter] = []
    shown: dict[bool, list[float]] = {True: [], False: []}
    for t in part.threads:
        x0, x1 = L.at(t.z_lo, 0)[0], L.at(t.z_hi, 0)[0]
        text = f"M{numbers.text(t.nominal)}×{numbers.text(t.pitch)}"
        out.append(_Diameter(x0, x1, t.nominal / 2, text, "thread", numbers.nominal(t.nominal), t.inside))
        shown[t.inside].append(t.nominal / 2)
    for e, inside in zip(part.surface, part.inside, strict=True):
        if not e.cylinder or e.a[1] < SAME:
            continue
        za, zb = sorted((e.a[0], e.b[0]))
        za, zb = max(za, -part.blank.length), min(zb, 0.0)
        if any(
            abs(d.r - e.a[1]) < SAME
            and d.inside == inside
            and d.lo <= L.at(zb, 0)[0]
            and L.at(za, 0)[0] <= d.hi
            for d in out
        ):
            continue  # one line per cylinder (a thread on it has its own)
        out.append(
            _Diameter(
                L.at(za, 0)[0],
                L.at(zb, 0)[0],
                e.a[1],
                _diameter(2 * e.a[1], numbers),
                "d",
                numbers.raw(2 * e.a[1]),
                inside,
            )
        )
        shown[inside].append(e.a[1])
    for (z, r), inside in points(part):
        if r < SAME or any(abs(r - v) < SAME for v in shown[inside]):
            continue
        shown[inside].append(r)
        za, zb = _same_radius(part, z, r, inside, L.length)
        out.append(
            _Diameter(
                L.at(za, 0)[0], L.at(zb, 0)[0], r, _diameter(2 * r, numbers), "d", numbers.raw(2 * r), inside
            )
        )
    for z_lo, z_hi, r in part.grooves:
        if not any(abs(r - v) < SAME for v in shown[False]):
            shown[False].append(r)
            out.append(
                _Diameter(
                    L.at(z_lo, 0)[0],
                    L.at(z_hi, 0)[0],
                    r,
                    _diameter(2 * r, numbers),
                    "d",
                    numbers.raw(2 * r),
                    False,
                )
            )
    # the part's outer size (and a tube's bore) where the program leaves the blank's: its diameter from the blank
    for inside, r in ((False, part.blank.diameter / 2), (True, part.blank.bore / 2)):
        if r < SAME or any(abs(r - v) < SAME for v in shown[inside]):
            continue
        same = (np.abs((part.inner if inside else part.outer) - r) < 0.02) & (part.zs > -L.length)
        if not same.any():
            continue
        k = int(np.flatnonzero(same)[-1])  # the blank's surface nearest the face: its whole run from there
        za, zb = _same_radius(part, float(part.zs[k]), r, inside, L.length)
        out.append(
            _Diameter(
                L.at(za, 0)[0], L.at(zb, 0)[0], r, f"Ø{numbers.text(2 * r)}", "d", numbers.raw(2 * r), inside
            )
        )
    return out


Box = tuple[float, float, float, float]  # x0, y0, x1, y1 on paper


def _free(box: Box, taken: list[Box]) -> bool:
    return all(box[2] <= b[0] or box[0] >= b[2] or box[3] <= b[1] or box[1] >= b[3] for b in taken)


def _candidates(d: _Diameter) -> list[float]:
    """Where a diameter's line may stand: its range's middle first, then ever further from it."""
    margin = min(0.8, (d.hi - d.lo) / 2)
    lo, hi = d.lo + margin, d.hi - margin
    if hi - lo < 0.5:
        return [(d.lo + d.hi) / 2]
    mid = (lo + hi) / 2
    steps = np.arange(lo, hi + 1e-9, 0.25)
    return [mid] + sorted((float(x) for x in steps), key=lambda x: abs(x - mid))


def _touches(part: TurnedPart, d: _Diameter, z: float) -> bool:
    """Whether the part's outline at z is the diameter's (the line not standing in a groove, say)."""
    if d.kind == "thread":
        return True
    found = part.radius_at(z, d.inside)
    return abs(found - d.r) < 0.05 or (d.lo == d.hi)


def _diameter_lines(
    svg: Svg, L: Layout, part: TurnedPart, dims: list[_Diameter], view_lines: list[tuple[float, float]]
) -> list[Box]:
    """Each diameter across the axis with two arrows; its text along the line beside it, in the view half
    for the outside, in the bore for a bore (across the axis where the bore is narrow). Line and text go
    where they cross no edge of the view, no other dimension line and no other text (the line anywhere on
    its cylinder); where there is no such place, the text goes under the part and the line is drawn on to
    it. Returns the boxes the texts and the lines under the part take."""
    edges: list[Box] = [(x - 0.3, L.axis, x + 0.3, L.axis + depth) for x, depth in view_lines]
    lines: list[Box] = []
    texts: list[Box] = []
    under: list[Box] = []
    below = L.bottom + 2.0
    for d in sorted(dims, key=lambda d: ((d.lo + d.hi) / 2, -d.r)):
        top, low = L.axis - d.r * L.s, L.axis + d.r * L.s
        length = _width(d.text)
        place = None
        walls = [(b[0] + b[2]) / 2 for b in edges + lines]
        mid = _candidates(d)[0]
        # first where the line stands clear of the view's edges and other lines, nearest the middle
        for x in sorted(
            _candidates(d),
            key=lambda x: (min((abs(x - w) for w in walls), default=99.0) < CLEAR, abs(x - mid)),
        ):
            line = (x - 1.0, top, x + 1.0, low)
            if not _free(line, edges + lines + texts) or not _touches(part, d, (x - L.right) / L.s):
                continue
            z = (x - L.right) / L.s
            half = d.r * L.s - 2.0
            if d.inside:  # in the view half, in the bore, or across the axis
                centres = [
                    c
                    for c, room in (
                        (L.axis + d.r * L.s / 2, half),
                        (L.axis - d.r * L.s / 2, half),
                        (L.axis, 2 * half + 2.0),
                    )
                    if length <= room
                ]
            else:
                room = part.silhouette(z, 0.01) * L.s - 2.0
                centres = [L.axis + (room + 2.0) / 2] if length <= room else []
            for centre in centres:
                for base in (x - 0.9, x + 0.9 + 0.8 * TEXT):
                    box = (base - 0.8 * TEXT, centre - length / 2, base + 0.2, centre + length / 2)
                    if _free(box, edges + lines + texts):
                        place = (x, base, centre + length / 2, low)
                        break
                if place is not None:
                    break
            if place is not None:
                break
        if place is None:  # under the part, the line drawn on to its text
            x = next((x for x in _candidates(d) if _touches(part, d, (x - L.right) / L.s)), _candidates(d)[0])
            y = below + length
            while not _free((x - 0.9 - 0.8 * TEXT, y - length, x + 0.2, y), texts + under):
                y += 2.0
            place = (x, x - 0.9, y, y + 1.0)
            under.append((x - 0.3, low, x + 0.3, y))
        x, base, y_text, end = place
        lines.append((x - 0.3, top, x + 0.3, low))
        svg.line((x, top), (x, max(end, low)), width=THIN)
        svg.arrow((x, top), (x, top + 5.0))
        svg.arrow((x, low), (x, low - 5.0))
        svg.text((base, y_text), d.text, rotate=-90, kind=d.kind, value=d.raw)
        texts.append((base - 0.8 * TEXT, y_text - length, base + 0.2, y_text))
    return texts + under


def _running(svg: Svg, L: Layout, part: TurnedPart, numbers: Numbers) -> None:
    """Running dimensions from the front face (Z0): one line above the part, an arrow at each edge, the
    length written at its extension line."""
    zs = part.z_values
    if not zs:
        return
    x0 = L.at(0.0, 0)[0]
    xs = [L.at(z, 0)[0] for z in zs]
    svg.line((min(xs) - 2.0, L.row), (x0, L.row), width=THIN)
    svg.circle((x0, L.row), 1.2, width=THIN, fill="#fff")
    previous = math.inf
    for z, x in zip(zs, xs, strict=True):
        # from the outline (a bore's edge is seen in the section under its extension line)
        top = L.axis - part.silhouette(z, 0.1) * L.s
        svg.line((x, top - 1.0), (x, L.row - 2.0), width=THIN)
        if abs(z) > SAME:
            svg.arrow((x, L.row), (x + 5.0, L.row))
        tx = min(x, previous - SPACING)
        previous = tx
        text = numbers.dimension(abs(z))
        if tx < x - 0.01:
            svg.line((x, L.row - 1.0), (tx, L.row - 3.0), width=0.18)
        svg.text((tx - 0.8, L.row - 3.0), text, rotate=-90, kind="z", value=numbers.raw(z))


def _callouts(part: TurnedPart, numbers: Numbers) -> list[tuple[P, bool, str, str, str]]:
    """(point on the element, on the bore, text, kind, value) of the radii, chamfers, tapers and grooves."""
    out: list[tuple[P, bool, str, str, str]] = []
    chamfers = dict(part.chamfers)
    labels = LABELS[numbers.lang]
    for i, (e, whole, inside) in enumerate(zip(part.surface, part.whole, part.inside, strict=True)):
        mid = e.point(0.5)
        if e.centre is not None and whole:
            out.append((mid, inside, f"R{numbers.text(e.radius)}", "r", numbers.nominal(e.radius)))
        elif i in chamfers:
            out.append(
                (mid, inside, f"{numbers.text(chamfers[i])}×45°", "chamfer", numbers.nominal(chamfers[i]))
            )
        elif whole and not e.cylinder and not e.face and not e.drilled and e.centre is None:
            angle = math.degrees(math.atan2(abs(e.b[1] - e.a[1]), abs(e.b[0] - e.a[0])))
            out.append((mid, inside, f"{numbers.text(angle)}°", "angle", numbers.nominal(angle)))
    for z_lo, z_hi, r in part.grooves:
        w = z_hi - z_lo
        out.append(
            (
                ((z_lo + z_hi) / 2, r),
                False,
                labels["groove"].format(w=numbers.text(w)),
                "groove",
                numbers.nominal(w),
            )
        )
    return out


def _beside(
    svg: Svg, L: Layout, at: tuple[float, float], text: str, kind: str, raw: str, taken: list[Box]
) -> bool:
    """A bore's callout right of the face: the leader into the bore, then along it out of the part. False
    where there is no room there."""
    px, py = at
    width = _width(text) + 0.5
    x = L.right + 6.0
    y = py + 2.0 * 1.0 + 1.2
    for _ in range(8):
        box = (x - 0.5, y - TEXT, x + width, y + 1.2)
        if _free(box, taken):
            taken.append(box)
            bend = (px + 2.0, y - 1.2)
            svg.polyline([(px, py), bend, (x - 0.5, y - 1.2)], width=THIN)
            svg.arrow((px, py), bend)
            svg.text((x, y), text, kind=kind, value=raw)
            return True
        y += ROW_HEIGHT
    return False


def _draw_callouts(svg: Svg, L: Layout, part: TurnedPart, numbers: Numbers, taken: list[Box]) -> None:
    """Under the part in rows: a leader from the element (in the view half; a bore's in the section) to its
    text, right or left of it; no text overlaps another text or a diameter's."""
    items = sorted(_callouts(part, numbers), key=lambda c: L.at(*c[0])[0])
    first_row = L.bottom + 8.0
    tx, ty = SHEET[0] - MARGIN - TITLE_BLOCK[0], SHEET[1] - MARGIN - TITLE_BLOCK[1]
    taken = taken + [
        (tx - 2.0, ty - 2.0, SHEET[0], SHEET[1]),
        (0.0, SHEET[1] - MARGIN - 1.0, SHEET[0], SHEET[1]),
        (SHEET[0] - MARGIN - 1.0, 0.0, SHEET[0], SHEET[1]),
    ]
    for (z, r), inside, text, kind, raw in items:
        px, py = L.at(z, r if inside else -r)
        width = _width(text) + 0.5
        if inside and _beside(svg, L, (px, py), text, kind, raw, taken):
            continue
        choice = None
        for k in range(MAX_ROWS):
            y = first_row + k * ROW_HEIGHT
            for x, side in ((px + 3.0, 1.0), (px - 3.0 - width, -1.0)):
                box = (x - 0.5, y - TEXT, x + width, y + 1.2)
                if _free(box, taken):
                    choice = (x, y, side, box)
                    break
            if choice is not None:
                break
        if choice is None:
            y = first_row + MAX_ROWS * ROW_HEIGHT
            choice = (px + 3.0, y, 1.0, (px + 2.5, y - TEXT, px + 3.0 + width, y + 1.2))
        x, y, side, box = choice
        taken.append(box)
        bend = (px + 1.5 * side, y - 1.2)
        shoulder = (x - 0.5, y - 1.2) if side > 0 else (x + width, y - 1.2)
        svg.polyline([(px, py), bend, shoulder], width=THIN)
        svg.arrow((px, py), bend)
        svg.text((x, y), text, kind=kind, value=raw)


def _rows(part: TurnedPart, numbers: Numbers) -> int:
    n = len(_callouts(part, numbers))
    return 0 if n == 0 else 1 if n <= 3 else 2  # the room kept for them; more go where there is room


def turned_part_drawing(exercise: Exercise, lang: str = "de") -> str:
    """The dimensioned drawing of a turning exercise's part (SVG, A4 landscape, mm)."""
    part = turned_part(exercise)
    numbers = Numbers.of(lang, exercise.reference, *exercise.subprograms.values())
    L = _layout(part, _rows(part, numbers), _drawn_length(part), numbers)
    svg = Svg(*SHEET)
    svg.defs.append(HATCH)
    frame(svg)
    _blank(svg, L, part)
    dims = _diameters(part, L, numbers)
    view_lines = _part(svg, L, part)
    _threads(svg, L, part)
    boxes = _diameter_lines(svg, L, part, dims, view_lines)
    _running(svg, L, part, numbers)
    _draw_callouts(svg, L, part, numbers, boxes)
    top, bottom = L.at(-L.length, part.blank.diameter / 2), L.at(0.0, -part.blank.diameter / 2)
    mark_views(svg, (top[0] - 6.0, top[1], bottom[0] + 9.0, bottom[1]))
    svg.text((MARGIN + 4.0, SHEET[1] - MARGIN - 4.0), LABELS[lang]["half"], size=3.5)
    title_block(svg, exercise, L.s, lang)
    return svg.document(f"{exercise.title.get(lang)} — {exercise.id}")
