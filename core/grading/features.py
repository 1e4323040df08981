"""The geometry criterion's partial credit: the finished part judged feature by feature of the reference.

A milled part's features are the reference's contour elements that cut the stock (each wall of a compensated
contour, each path milled with the tool centre – a slot –, each transition element RN, each arc), the plunges
that stand alone (holes), and one floor per depth. Every cell where the submitted part leaves the tolerance band
(core.grading._outside_band) is put down to one feature:

- in depth – both parts are cut at that cell, to different heights: the floor of the reference's depth there;
- sideways – one part is cut there and the other is not: a cell cut too much belongs to the reference feature
  that the submission's element cutting it stands for (core.grading.causes aligns the two contours), else to the
  element whose machined edge (tool-centre path ± tool radius) is nearest; a cell left standing belongs to the
  element whose cut should have taken it.

A feature is kept ("maßhaltig") when what is put down to it stays within the allowance of a few cells at the
band's edge; a floor is also lost when the submission machines (almost) no cell at its depth.
The criterion's points are its share of kept features, rounded half up (all points only with every feature
kept): one wrong element costs its share, a part wrong everywhere scores 0, an equivalent program keeps every
feature. A deviation of more than SAMPLED_CELLS cells is put down on a regular sample of its cells.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from core.grading.causes import Element, describe, elements
from core.grading.numbers import mm, word
from core.sim import HeightMap
from core.toolpath import Toolpath

Array = npt.NDArray[np.float64]
LEVEL = 0.01  # mm: depths this close are one floor
SAMPLED_CELLS = 20_000  # deviating cells put down one by one; beyond, a regular sample of them


@dataclass(frozen=True, slots=True)
class Feature:
    """One feature of the reference part and how the submission made it."""

    kind: str  # milling: contour, path, rounding, chamfer, hole, pocket, floor; turning: diameter, taper, radius, face
    name: str
    name_en: str
    ok: bool = True
    deviation: float = 0.0  # mm: the largest deviation put down to it
    sideways: bool = False  # the deviation lies beside the contour (milling) rather than in depth
    too_much: bool = True  # the largest deviation is material removed (else material left standing)
    where: str = ""  # the place of the largest deviation, as address words ("X61.2 Y19.8", "Z-30.5")
    line: int | None = None  # the submission's line there
    detail: str = (
        ""  # turning: what deviates, said for the feature ("Ø39 statt Ø40"); empty: from the fields above
    )
    detail_en: str = ""

    def to_json(self) -> dict[str, Any]:
        return {
            "kind": self.kind,
            "name": self.name,
            "name_en": self.name_en,
            "ok": self.ok,
            "deviation": round(self.deviation, 3),
            "line": self.line,
        }


def share(points: int, kept: int, total: int) -> int:
    """The points of `kept` of `total` features, rounded half up (all kept: all points, none: 0)."""
    if total <= 0 or kept >= total:
        return points
    return min(points - 1, math.floor(points * kept / total + 0.5)) if kept else 0


@dataclass(frozen=True, slots=True)
class Shape:
    """A reference feature's place: the tool-centre path and the tool radius around it."""

    feature: Feature
    path: CentrePath  # the tool centre's
    radius: float
    depth: float
    element: int | None  # index into the reference's elements


def milled_features(
    tp: Toolpath, cutting: list[int], radius: dict[int | None, float]
) -> tuple[list[Shape], list[float]]:
    """The reference's features (contour elements, and plunges no element's cut covers: holes) and its floor
    depths. A shape's `element` is its index in the reference's elements (core.grading.causes.elements)."""
    elems = elements(tp, cutting, lathe=False)
    shapes: list[Shape] = []
    # a milling cycle's pocket or slot is one feature: its rings and levels are the cycle's path, not the part's
    # elements (a pocket 2 mm too deep would else cost one ring of many)
    pockets: dict[tuple[int, str], list[int]] = {}
    for n, e in enumerate(elems):
        code = _pocket_cycle(tp, e) if e.kind != "plunge" else None
        if code is not None:
            pockets.setdefault((e.line, code), []).append(n)
    for n, e in enumerate(elems):
        if e.kind == "plunge":
            continue
        code = _pocket_cycle(tp, e)
        if code is not None:
            members = pockets[(e.line, code)]
            if members[0] == n:
                de, en = POCKETS[code]
                moves = tuple(k for m in members for k in elems[m].moves)
                shapes.append(
                    Shape(
                        Feature("pocket", f"{de} (Zeile {e.line})", f"{en} (line {e.line})"),
                        _path(tp, moves),
                        radius.get(e.tool, 0.0),
                        min(elems[m].depth for m in members),
                        n,
                    )
                )
            continue
        r = radius.get(e.tool, 0.0)
        before = [x for x in elems[:n] if x.kind != "plunge"]
        joint = bool(before) and before[-1].line == e.line and before[-1].moves[-1] + 1 == e.moves[0]
        compensated = abs(e.offset) > 0.5 * max(r, 0.01)
        if joint and compensated:
            kind = "rounding" if e.kind == "arc" else "chamfer"
        else:
            kind = "contour" if compensated else "path"
        name, name_en = _names(kind, e)
        shapes.append(Shape(Feature(kind, name, name_en), _path(tp, e.moves), r, e.depth, n))
    for n, e in enumerate(elems):
        if e.kind != "plunge":
            continue
        p = np.array([[e.end[0], e.end[1]]])
        if any(s.depth <= e.depth + LEVEL and float(_distance(p, s.path)[0]) <= s.radius for s in shapes):
            continue  # the plunge at the start of a slot: the slot's feature
        at = f"X{word(e.end[0])} Y{word(e.end[1])}"
        shapes.append(
            Shape(
                Feature("hole", f"Bohrung/Eintauchstelle {at}", f"hole/plunge {at}"),
                _point_path(e.end[0], e.end[1]),
                radius.get(e.tool, 0.0),
                e.depth,
                n,
            )
        )
    levels = sorted({round(s.depth / LEVEL) * LEVEL for s in shapes})
    return shapes, levels


POCKETS = {
    "G72": ("Rechtecktasche", "rectangular pocket"),
    "G73": ("Kreistasche", "circular pocket"),
    "G74": ("Nut", "slot"),
    "G75": ("Kreisbogennut", "arc slot"),
}


def _pocket_cycle(tp: Toolpath, e: Element) -> str | None:
    """The PAL milling cycle (G72–G75) whose call made every move of `e`, if one did."""
    cycles = [tp.moves[k].cycle for k in e.moves]
    codes = {c[0] if c is not None else None for c in cycles}
    code = codes.pop() if len(codes) == 1 else None
    return code if code in POCKETS else None


def _names(kind: str, e: Element) -> tuple[str, str]:
    text, text_en = describe(e, False), describe(e, False, "en")
    if e.joint:  # "Rundung R20 X50 Y10 → X70 Y30" says it already
        return text, text_en
    return {
        "contour": (f"Kontur {text}", f"contour {text_en}"),
        "path": (f"Bahn {text}", f"path {text_en}"),
        "rounding": (f"Rundung {text}", f"rounding {text_en}"),
        "chamfer": (f"Fase {text}", f"chamfer {text_en}"),
    }[kind]


@dataclass(frozen=True, slots=True)
class CentrePath:
    """A tool-centre path in the plane: straight pieces (a → b) and arcs (centre, radius, start angle, signed
    sweep in radians), each measured exactly (no chords)."""

    lines: tuple[tuple[float, float, float, float], ...]
    arcs: tuple[tuple[float, float, float, float, float], ...]


def _path(tp: Toolpath, moves: tuple[int, ...]) -> CentrePath:
    lines: list[tuple[float, float, float, float]] = []
    arcs: list[tuple[float, float, float, float, float]] = []
    for k in moves:
        m = tp.moves[k]
        if m.kind == "arc" and m.center is not None and m.plane == "G17" and m.radius and m.angle:
            c = m.center
            a0 = math.atan2(m.start[1] - c[1], m.start[0] - c[0])
            sweep = math.radians(m.angle) * (-1 if m.direction == "cw" else 1)
            arcs.append((c[0], c[1], m.radius, a0, sweep))
            continue
        pts = m.points(0.02, max_chords=64)
        lines += [(u[0], u[1], v[0], v[1]) for u, v in itertools.pairwise(pts)]
    return CentrePath(tuple(lines), tuple(arcs))


def _point_path(x: float, y: float) -> CentrePath:
    return CentrePath(((x, y, x, y),), ())


def _distance(p: Array, path: CentrePath) -> Array:
    """Distance of each point of `p` (n, 2) from the path."""
    best = np.full(len(p), np.inf)
    for ax, ay, bx, by in path.lines:
        dx, dy = bx - ax, by - ay
        n2 = dx * dx + dy * dy
        rx, ry = p[:, 0] - ax, p[:, 1] - ay
        t = np.zeros(len(p)) if n2 < 1e-18 else np.clip((rx * dx + ry * dy) / n2, 0.0, 1.0)
        np.minimum(best, np.hypot(rx - t * dx, ry - t * dy), out=best)
    for cx, cy, r, a0, sweep in path.arcs:
        rx, ry = p[:, 0] - cx, p[:, 1] - cy
        d = np.hypot(rx, ry)
        turn = (np.arctan2(ry, rx) - a0) * (1.0 if sweep > 0 else -1.0)
        inside = np.mod(turn, 2 * math.pi) <= abs(sweep) + 1e-9
        ends = np.minimum(
            np.hypot(rx - r * math.cos(a0), ry - r * math.sin(a0)),
            np.hypot(rx - r * math.cos(a0 + sweep), ry - r * math.sin(a0 + sweep)),
        )
        np.minimum(best, np.where(inside, np.abs(d - r), ends), out=best)
    return best


@dataclass(frozen=True, slots=True)
class Judged:
    features: list[Feature]
    kept: int


@dataclass(frozen=True, slots=True)
class Cutter:
    """A submission's contour element as it cut: its tool-centre path, radius and depth, and the reference
    feature made in its place (None: no counterpart)."""

    path: CentrePath
    radius: float
    depth: float
    feature: int | None


def cutters(
    tp: Toolpath, elems: list[Element], radius: dict[int | None, float], counterpart: dict[int, int]
) -> list[Cutter]:
    """The submission's elements as cutters; `counterpart` maps a submission element to a reference feature."""
    out = []
    for n, e in enumerate(elems):
        out.append(Cutter(_path(tp, e.moves), radius.get(e.tool, 0.0), e.depth, counterpart.get(n)))
    return out


def judge_milled(
    shapes: list[Shape],
    levels: list[float],
    ref: HeightMap,
    sub: HeightMap,
    over: Array,
    left: Array,
    tol: float,
    line_at: Any,
    cut_by: list[Cutter] | None = None,
) -> Judged:
    """Every deviating cell put down to one feature; each feature kept or lost (see the module's text).
    `line_at(x, y, over)` names the submission's block at a place (or None). A cell cut too much beside the
    contour belongs to the reference feature that the submission's element cutting it stands for (`cut_by`), if
    it has one."""
    grid = ref.grid
    area = grid.dx * grid.dy
    allowance = 4 * area * tol
    floors = [Feature("floor", f"Boden Z{word(z)}", f"floor Z{word(z)}") for z in levels]
    n_f = len(shapes)
    volume = np.zeros(n_f + len(floors))
    worst = np.zeros(n_f + len(floors))
    worst_at: list[tuple[float, float, bool, bool]] = [(0.0, 0.0, True, True)] * (n_f + len(floors))
    j, i = np.nonzero((over > 0) | (left > 0))
    # a large deviation is put down on every stride-th cell along X and Y (each standing for stride² cells): the
    # same features are lost, at a bounded cost
    stride = max(1, math.ceil(math.sqrt(len(j) / SAMPLED_CELLS)))
    if stride > 1:
        keep = (j % stride == 0) & (i % stride == 0)
        j, i = j[keep], i[keep]
    if len(j):
        x = grid.x0 + (i + 0.5) * grid.dx
        y = grid.y0 + (j + 0.5) * grid.dy
        hr, hs = ref.heights[j, i], sub.heights[j, i]
        amount = np.maximum(over[j, i], left[j, i])
        too_much = over[j, i] > 0
        top = ref.top - tol
        vertical = (hr < top) & (hs < top)
        owner = np.full(len(j), -1, dtype=np.int64)
        gap = np.zeros(len(j))
        if floors:
            lv = np.array(levels)
            owner[vertical] = n_f + np.argmin(np.abs(hr[vertical][:, None] - lv[None, :]), axis=1)
            gap[vertical] = np.abs(hs[vertical] - hr[vertical])
        side = ~vertical
        if shapes and side.any():
            p = np.stack([x[side], y[side]], 1)
            dist = np.stack([_distance(p, s.path) for s in shapes], 1)
            radii = np.array([s.radius for s in shapes])
            edge = np.abs(dist - radii[None, :])
            cover = np.clip(dist - radii[None, :], 0.0, None) + 1e-3 * dist
            key = np.where(too_much[side][:, None], edge, cover)
            pick = np.argmin(key, axis=1)
            if cut_by:
                made_by = _made_by(p, hs[side], cut_by, tol)
                pick = np.where(too_much[side] & (made_by >= 0), made_by, pick)
            owner[side] = pick
            gap[side] = edge[np.arange(len(pick)), pick]
        elif floors and side.any():
            lv = np.array(levels)
            owner[side] = n_f + np.argmin(
                np.abs(np.minimum(hr[side], hs[side])[:, None] - lv[None, :]), axis=1
            )
            gap[side] = amount[side]
        for f in range(n_f + len(floors)):
            mine = owner == f
            if not mine.any():
                continue
            volume[f] = float(amount[mine].sum()) * area * stride * stride
            k = int(np.argmax(np.where(mine, gap, -1.0)))
            worst[f] = float(gap[k])
            worst_at[f] = (float(x[k]), float(y[k]), bool(too_much[k]), bool(~vertical[k]))
    out: list[Feature] = []
    for f, feat in enumerate([s.feature for s in shapes] + floors):
        lost = bool(volume[f] > allowance)
        if f >= n_f and not lost:  # a floor the submission machines nowhere is lost as well
            z = levels[f - n_f]
            wanted = int(np.count_nonzero(np.abs(ref.heights - z) <= tol))
            made = int(np.count_nonzero(np.abs(sub.heights - z) <= tol))
            lost = bool(wanted > 0 and made < 0.01 * wanted)
        if not lost:
            out.append(feat)
            continue
        wx, wy, much, sideways = worst_at[f]
        line = line_at(wx, wy, much) if volume[f] > 0 else None
        out.append(
            Feature(
                feat.kind,
                feat.name,
                feat.name_en,
                False,
                worst[f],
                sideways,
                much,
                f"X{word(wx, 1)} Y{word(wy, 1)}",
                line,
            )
        )
    return Judged(out, sum(1 for f in out if f.ok))


def _made_by(p: Array, heights: Array, cut_by: list[Cutter], tol: float) -> npt.NDArray[np.int64]:
    """For each point, the reference feature of the submission's element that cut it (the deepest one whose tool
    reaches over it at the height it left), −1 where none."""
    best = np.full(len(p), np.inf)
    out = np.full(len(p), -1, dtype=np.int64)
    for c in cut_by:
        if c.feature is None:
            continue
        reach = _distance(p, c.path) <= c.radius + tol
        hit = reach & (np.abs(heights - c.depth) <= tol + 0.05) & (c.depth < best)
        out[hit] = c.feature
        best[hit] = c.depth
    return out


def deviation_text(f: Feature, lang: str = "de") -> str:
    """`Kontur …: seitlich 12,5 mm neben der Kontur bei X61.2 Y19.8 (Zeile 8)`; in depth: `… 1 mm zu tief …`."""
    where = "" if not f.where else f" bei {f.where}" if lang == "de" else f" at {f.where}"
    if f.line:
        where += f" (Zeile {f.line})" if lang == "de" else f" (line {f.line})"
    name = f.name if lang == "de" else f.name_en
    if f.detail:
        return f"{name}: {f.detail if lang == 'de' else f.detail_en}{where}"
    if f.deviation <= 0:
        return f"{name}: nirgends maßhaltig gefertigt" if lang == "de" else f"{name}: nowhere made to size"
    if f.sideways:
        if lang == "de":
            what = "zu viel abgetragen" if f.too_much else "Material stehen gelassen"
            return f"{name}: seitlich {mm(f.deviation)} neben der Kontur ({what}){where}"
        what = "too much removed" if f.too_much else "material left standing"
        return f"{name}: {mm(f.deviation, 'en')} sideways off the contour ({what}){where}"
    if lang == "de":
        return f"{name}: {mm(f.deviation)} zu {'tief' if f.too_much else 'hoch'}{where}"
    return f"{name}: {mm(f.deviation, 'en')} too {'deep' if f.too_much else 'high'}{where}"
