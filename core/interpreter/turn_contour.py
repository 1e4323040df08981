"""TRAUB TX 8 D turning: contour trains (Geometriezüge) and nose-radius compensation (SRK).

The turning sibling of `core.interpreter.contour`. The TRAUB block executor does not compute the
geometry of a motion block itself: it hands one `TurnItem` per motion block (and passes other
commands through) to `resolve`, which runs over them in order with the control's one-block
look-ahead:

1. contour trains: end points given only by angle A, or not at all, are found by intersecting
   with the next element (DECISIONS 12, 17); arcs by R, P/Q (centre), I/K (centre from the start);
   H0/H1 pick an intersection of a line and a circle; tangential line–arc, arc–line, arc–arc;
2. transition elements D (chamfer width along Z), D− (chamfer length), R / C (rounding) are put
   into the programmed contour as moves of the block that programs them;
3. SRK (G46, G41, G42; G40 off) turns the contour into the path of the nose-radius centre:
   intersections of the equidistants at inside corners, an inserted arc at outside corners
   (DECISIONS 16); the first motion after switching on ends on the equidistant of the next
   element, a rapid (with A: the last element's direction) or G40 ends it as TX-28 describes;
   blocks the nose cannot follow are suppressed ("Satzausblendung", a warning).

Frame (DECISIONS 15): points are given and returned as (x, z) with x = radius (X/2) and z = Z;
moves are `[x, 0, z]` in plane G18 (Z-X): an arc's `direction` is seen from +Y, i.e. in the
drawing view with Z to the right and X up, so G2 = "cw". Internally the plane point is (z, x),
which keeps that sense for the 2-D geometry of `core.geometry.elements`.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Literal

from core.diagnostics import Diagnostic, diag
from core.geometry.arcs import centre_by_radius
from core.geometry.elements import (
    Arc,
    Element,
    Line,
    Transition,
    add,
    angle_of,
    chamfer,
    circle_circle,
    cross,
    dot,
    end_tangent,
    intersections,
    left,
    line_circle,
    nearest,
    offset,
    rounding,
    start_tangent,
    tangent_at,
    turn,
    unit,
    with_end,
    with_start,
)
from core.syntax.blocks import Span
from core.toolpath import Dwell, Move, MoveKind, ToolChange, Vec3
from core.values import value

XZ = tuple[float, float]  # (x radius, z) in the workpiece frame
Command = Move | Dwell | ToolChange


@dataclass(frozen=True, slots=True)
class Nose:
    """The SRK state of a block and the set-up data of the tool's cutting edge.

    `mode`: "G40" off, "G46" on (side from the quadrant and the travel direction), "G41" tool left
    of the travel direction, "G42" right (drawing view Z right, X up). `radius`: nose radius R_s in
    mm (0 when the tool has none). `quadrant`: P1…P4 as DECISIONS 16 counts them (0: not set).
    """

    mode: Literal["G40", "G41", "G42", "G46"] = "G40"
    radius: float = 0.0
    quadrant: int = 0

    @property
    def active(self) -> bool:
        return self.mode != "G40"


@dataclass(frozen=True, slots=True)
class TransitionSpec:
    """A transition element at the end of the block, into the next motion block.

    kind "chamfer": D+ = chamfer width measured along Z (equal legs); "chamfer_length": D− = the
    chamfer's own length (the chord); "rounding": R in G1 or C in G2/G3. `size` > 0 in mm.
    `feed` is E (modal; the executor resolves it, None = the block's feed). `raw` is the text for
    messages ("D0.5", "D-2", "R2", "C3").
    """

    kind: Literal["chamfer", "chamfer_length", "rounding"]
    size: float
    raw: str
    feed: float | None = None


@value
class TurnItem:
    """One motion block as programmed, in the output frame (x radius, z); unknown values are None.

    template: the block's Move carrying technology and origin (feed, feed_unit, spindle,
        spindle_direction, coolant, tool, span, exact_stop, source, call_stack). Its geometry
        (start, end, center, kind, …) is ignored and replaced.
    code: "G0" rapid line, "G1" / "G9" feed line (G9 = exact stop), "G2" / "G3" arc (G2 = cw).
    start: where the block starts, if the executor knows it (authoritative: it accounts for tool
        changes, G26, G53 …); None after a block whose end the executor could not compute (an
        unknown train point) — then the resolved end of the previous item is the start.
    x, z: absolute end point (X already halved); None where not programmed.
    dx, dz: incremental end (U radius, W) *only* when `start` is None (the executor resolves U/W
        itself when it knows the start). They are added to the resolved start.
    a: angle A in degrees as programmed (0° = +Z, counter-clockwise positive). For a line with a
        known start A is the travel direction; in the closing block of a train (after an unknown
        point) A points back from the known end point (DECISIONS 12). On a G0 while SRK is active
        A is the direction of the last contour element for the deselection (TX-28 case 3).
    radius: R of G2/G3 (the arc radius; a rounding of G1 is `transition`).
    centre: absolute arc centre from P/Q (x = P/2, z = Q).
    centre_offset: arc centre relative to the start from I/K (I radius, K), start may be unknown.
    h: H0 / H1 — which intersection of line and circle (0: nearer to the known point of the line).
    transition: D / D− / R / C at the end of the block.
    nose: SRK state while the block runs.
    spindle_at: optional; the spindle speed (1/min) for a move ending at radius x (G96 with the
        G92 limit). When given, every output move of the block carries spindle_at(end x).
    """

    template: Move
    code: Literal["G0", "G1", "G9", "G2", "G3"]
    start: XZ | None = None
    x: float | None = None
    z: float | None = None
    dx: float | None = None
    dz: float | None = None
    a: float | None = None
    radius: float | None = None
    centre: XZ | None = None
    centre_offset: XZ | None = None
    h: int | None = None
    transition: TransitionSpec | None = None
    nose: Nose = Nose()
    spindle_at: Callable[[float], float] | None = None

    @property
    def span(self) -> Span:
        return self.template.span

    @property
    def is_arc(self) -> bool:
        return self.code in ("G2", "G3")


@dataclass(frozen=True, slots=True)
class SrkSwitch:
    """Where G40 / G41 / G42 / G46 is programmed (for the selection and deselection rules and their
    messages); the motion blocks that follow carry the new state in `TurnItem.nose`."""

    code: Literal["G40", "G41", "G42", "G46"]
    span: Span
    nose: Nose = Nose()


Item = TurnItem | SrkSwitch | Command


Point = tuple[float, float]  # a point of the plane: (z, x radius) — Z right, X up as in the drawing
ON_CIRCLE = 0.01  # mm: an arc's end may miss the circle of its programmed centre by this much
W_MIN_TRANSITION = 0.1  # mm: travel after a transition element beyond its size and the nose radius (L1978)
W_MIN_DESELECT = 0.01  # mm: the same before SRK deselection (L2673)
SHORT = 10.0  # a line longer than this many nose radii is not checked for Satzausblendung (it cannot vanish
# unless its corners are sharper than about 11°)


def known_end(start: XZ | None, item: TurnItem) -> XZ | None:
    """The end point of `item` if the block alone fixes it from `start` (no look-ahead needed).

    The executor uses this to keep its position: None means the point is an unknown train point
    (found by `resolve` from the next block); blocks after it get `start=None` and U/W as dx/dz.
    """
    s = _pt(start) if start is not None else None
    if _open_end(item):
        return None
    end = _end_point(item, s, [])
    return None if end is None else (end[1], end[0])


def resolve(items: Sequence[Item], diagnostics: list[Diagnostic]) -> list[Command]:
    """Turn the planned items into the toolpath, in order.

    Every `TurnItem` becomes one or more `Move`s with plane "G18", start/end `[x, 0, z]`
    (x = radius), arcs with center/direction/radius/angle; transition elements become moves of
    their block (feed = the transition's E). Without SRK `end` is the tool tip and equals
    `programmed_end`; with SRK `end` is the nose-radius centre and `programmed_end` the contour
    point (inserted corner arcs carry the corner as `programmed_end`). Dwell, ToolChange and
    already finished Moves (G24–G28, G53) pass through unchanged; a passed-through Move ends SRK
    like a rapid. `SrkSwitch` items produce no command.

    Errors never raise: a train without a solution is reported on its closing (known-point) block,
    a missing transition partner on the block with the transition; the affected block then runs
    as a straight move to whatever end point is known (or is dropped when none is) so that the
    rest of the program still gives a toolpath. Codes: TX-E2xx / TX-W2xx (core/diagnostics.py).
    """
    seq = _geometry(items, diagnostics)
    seq = _transitions(seq, diagnostics)
    return _compensate(seq, diagnostics)


# -- small helpers ------------------------------------------------------------------------------


def _pt(xz: XZ) -> Point:
    return (xz[1], xz[0])


def _vec(p: Point) -> Vec3:
    return (p[1], 0.0, p[0])


def _dir(a: float) -> Point:
    rad = math.radians(a)
    return (math.cos(rad), math.sin(rad))


def _num(v: float) -> str:
    text = f"{v:.3f}".rstrip("0").rstrip(".")
    return "0" if text in ("-0", "") else text


def _open_end(item: TurnItem) -> bool:
    """Whether the block leaves its end point to the next block (an unknown train point)."""
    no_x = item.x is None and item.dx is None
    no_z = item.z is None and item.dz is None
    if item.is_arc:
        return no_x and no_z
    return item.code != "G0" and item.a is not None and no_x and no_z


def _end_point(item: TurnItem, s: Point | None, d: list[Diagnostic]) -> Point | None:
    """The end of a block that fixes it alone; None (with an error in `d`) if it cannot be found."""
    z = item.z if item.z is not None else (s[0] + item.dz if s is not None and item.dz is not None else None)
    x = item.x if item.x is not None else (s[1] + item.dx if s is not None and item.dx is not None else None)
    programmed_x = item.x is not None or item.dx is not None
    programmed_z = item.z is not None or item.dz is not None
    if item.a is not None and item.code in ("G1", "G9") and programmed_x != programmed_z and s is not None:
        # a line by angle A and one coordinate from a known start
        u = _dir(item.a)
        if programmed_x:
            assert x is not None
            if abs(u[1]) < 1e-9:
                d.append(
                    diag(
                        "TX-E201",
                        item.span,
                        reason=f"die Gerade mit A{_num(item.a)} erreicht X{_num(2 * x)} nie",
                        reason_en=f"the line at A{_num(item.a)} never reaches X{_num(2 * x)}",
                    )
                )
                return None
            return (s[0] + (x - s[1]) * u[0] / u[1], x)
        assert z is not None
        if abs(u[0]) < 1e-9:
            d.append(
                diag(
                    "TX-E201",
                    item.span,
                    reason=f"die Gerade mit A{_num(item.a)} erreicht Z{_num(z)} nie",
                    reason_en=f"the line at A{_num(item.a)} never reaches Z{_num(z)}",
                )
            )
            return None
        return (z, s[1] + (z - s[0]) * u[1] / u[0])
    if s is not None:
        return (z if z is not None else s[0], x if x is not None else s[1])
    if z is None or x is None:
        return None
    return (z, x)


def _centre(item: TurnItem, s: Point | None) -> Point | None:
    if item.centre is not None:
        return _pt(item.centre)
    if item.centre_offset is not None and s is not None:
        return (s[0] + item.centre_offset[1], s[1] + item.centre_offset[0])
    return None


def _arc_known(item: TurnItem, s: Point, e: Point, d: list[Diagnostic]) -> Arc | None:
    """An arc with known start and end from R (the shorter arc), P/Q or I/K; None with an error."""
    cw = item.code == "G2"
    c = _centre(item, s)
    if c is None and item.radius is not None:
        r = item.radius
        chord = math.dist(s, e)
        if chord < 1e-9 or r <= 0 or chord > 2 * r + 1e-4:
            d.append(diag("TX-E202", item.span, radius=r, chord=chord / 2))
            return None
        if chord >= 2 * r - 1e-6:
            d.append(diag("TX-E203", item.span))
            return None
        c = centre_by_radius(s, e, r, cw, longer=False)
        if c is None:
            d.append(diag("TX-E202", item.span, radius=r, chord=chord / 2))
            return None
        return Arc(s, e, c, cw)
    if c is None:
        d.append(diag("TX-E204", item.span))
        return None
    r0, r1 = math.dist(s, c), math.dist(e, c)
    if r0 < 1e-6:
        d.append(diag("TX-E205", item.span, difference=0.0, start_radius=0.0, end_radius=r1))
        return None
    if abs(r0 - r1) > ON_CIRCLE:
        d.append(diag("TX-E205", item.span, difference=abs(r0 - r1), start_radius=r0, end_radius=r1))
        return None
    return Arc(s, e, c, cw, full=math.dist(s, e) < 1e-6)


# -- stage 1: the programmed contour, with the trains solved ------------------------------------


@dataclass(slots=True)
class _Seg:
    """One element of the programmed contour (plane points) and the block it belongs to."""

    item: TurnItem
    e: Element
    inserted: bool = False  # a chamfer or rounding put in at the end of the block
    full: Element | None = None  # the element before a transition trimmed it (for the travel checks)
    after_transition: TransitionSpec | None = None  # the transition that trimmed this element's start

    @property
    def rapid(self) -> bool:
        return self.item.code == "G0" and not self.inserted

    @property
    def moves(self) -> bool:
        return isinstance(self.e, Arc) or math.dist(self.e.a, self.e.b) > 1e-9


Seq = list[_Seg | Command | SrkSwitch]


def _geometry(items: Sequence[Item], d: list[Diagnostic]) -> Seq:
    out: Seq = []
    pos: Point | None = None  # the programmed end of the block before
    i = 0
    while i < len(items):
        it = items[i]
        if not isinstance(it, TurnItem):
            out.append(it)
            if isinstance(it, Move):
                pos = (it.end[2], it.end[0])
            i += 1
            continue
        s = _pt(it.start) if it.start is not None else pos
        if not _open_end(it):
            e = _end_point(it, s, d)
            if e is None or s is None:
                pos = e
                i += 1
                continue
            elem: Element | None = Line(s, e)
            if it.is_arc:
                elem = _arc_known(it, s, e, d)
            elif it.code != "G0" and it.a is not None and math.dist(s, e) > 1e-6:
                # X, Z and A after a known point: A says nothing new, but it must agree (either way round)
                off = _angle_diff(angle_of((e[0] - s[0], e[1] - s[1])), it.a)
                if min(abs(off), 180 - abs(off)) > 0.01:
                    d.append(
                        diag("TX-W227", it.span, angle=it.a, direction=angle_of((e[0] - s[0], e[1] - s[1])))
                    )
            out.append(_Seg(it, elem if elem is not None else Line(s, e)))
            pos = e
            i += 1
            continue
        # an unknown point: the next motion block must close the train
        j = i + 1
        between: list[_Seg | Command | SrkSwitch] = []
        while j < len(items) and isinstance(items[j], (SrkSwitch, Dwell)):
            between.append(items[j])  # type: ignore[arg-type]
            j += 1
        nxt = items[j] if j < len(items) else None
        if not isinstance(nxt, TurnItem):
            d.append(diag("TX-E206", it.span))
            pos = None
            i += 1
            continue
        if s is None:  # the block before already failed
            out += between
            pos = _pt_or_none(nxt)
            i = j + 1
            continue
        for q in between:
            if isinstance(q, SrkSwitch):  # the open point would be compensated with two different states
                d.append(
                    diag(
                        "TX-E226",
                        q.span,
                        code=q.code,
                        where="im Geometriezug",
                        where_en="inside a contour train",
                    )
                )
        pair = _solve_pair(it, s, nxt, d)
        e_end = _pt_or_none(nxt)
        if pair is not None:
            out.append(_Seg(it, pair[0]))
            out += between
            out.append(_Seg(nxt, pair[1]))
        else:
            out += between
            if e_end is not None:
                out.append(_Seg(nxt, Line(s, e_end)))
        pos = e_end
        i = j + 1
    return out


def _pt_or_none(item: TurnItem) -> Point | None:
    return (item.z, item.x) if item.x is not None and item.z is not None else None


def _solve_pair(k: TurnItem, s: Point, n: TurnItem, d: list[Diagnostic]) -> tuple[Element, Element] | None:
    """The unknown point between block k (known start s) and block n (known end): both elements."""
    e = _pt_or_none(n)
    if e is None or (not n.is_arc and n.a is None):
        d.append(diag("TX-E206", n.span))
        return None
    if not k.is_arc and not n.is_arc:
        assert k.a is not None and n.a is not None
        pts = intersections(Line(s, add(s, _dir(k.a))), Line(e, add(e, _dir(n.a))))
        if not pts:
            _no_solution(n, d, "die beiden Geraden sind parallel", "the two lines are parallel")
            return None
        return Line(s, pts[0]), Line(pts[0], e)
    if not k.is_arc:
        return _line_arc(k, s, n, e, d)
    if not n.is_arc:
        return _arc_line(k, s, n, e, d)
    return _arc_arc(k, s, n, e, d)


def _no_solution(n: TurnItem, d: list[Diagnostic], why: str, why_en: str) -> None:
    d.append(diag("TX-E201", n.span, reason=why, reason_en=why_en))


def _pick(points: list[Point], known: Point, arc: TurnItem, n: TurnItem, d: list[Diagnostic]) -> Point | None:
    """H0 = the intersection nearer to the known point of the line, H1 the other (DECISIONS 17);
    `arc` is the block that must say which, `n` the closing block."""
    if not points:
        _no_solution(n, d, "die Gerade schneidet den Kreis nicht", "the line does not meet the circle")
        return None
    ranked = sorted(points, key=lambda q: math.dist(q, known))
    h = arc.h
    if len(ranked) == 2 and h is None:
        d.append(diag("TX-E207", arc.span))
        return None
    return ranked[min(h or 0, len(ranked) - 1)]


def _line_arc(
    k: TurnItem, s: Point, n: TurnItem, e: Point, d: list[Diagnostic]
) -> tuple[Element, Element] | None:
    assert k.a is not None
    u = _dir(k.a)
    cw = n.code == "G2"
    if n.centre is not None:
        c = _pt(n.centre)
        p = _pick(line_circle(s, add(s, u), c, math.dist(c, e)), s, n, n, d)
        return None if p is None else (Line(s, p), Arc(p, e, c, cw))
    if n.radius is None or n.radius <= 0:
        d.append(diag("TX-E208", n.span))
        return None
    r = n.radius
    nrm = left(u) if not cw else (-left(u)[0], -left(u)[1])  # towards the centre at the joint
    f = add(s, nrm, r)
    f = (f[0] - e[0], f[1] - e[1])
    b, c0 = dot(f, u), dot(f, f) - r * r
    disc = b * b - c0
    best: tuple[float, Line, Arc] | None = None
    if disc >= -1e-9:
        for t in {-b + math.sqrt(max(disc, 0.0)), -b - math.sqrt(max(disc, 0.0))}:
            if t < -1e-7:
                continue
            p = add(s, u, t)
            arc = Arc(p, e, add(p, nrm, r), cw)
            if best is None or arc.angle < best[0]:
                best = (arc.angle, Line(s, p), arc)
    if best is None:
        _no_solution(
            n,
            d,
            f"kein Kreisbogen R{_num(r)} schließt tangential an die Gerade an",
            f"no arc R{_num(r)} joins the line tangentially",
        )
        return None
    if best[0] >= 180 - 1e-6:
        d.append(diag("TX-E203", n.span))
        return None
    return best[1], best[2]


def _arc_line(
    k: TurnItem, s: Point, n: TurnItem, e: Point, d: list[Diagnostic]
) -> tuple[Element, Element] | None:
    assert n.a is not None
    u = _dir(n.a)
    cw = k.code == "G2"
    c = _centre(k, s)
    if c is not None:
        p = _pick(line_circle(e, add(e, u), c, math.dist(c, s)), e, k, n, d)
        return None if p is None else (Arc(s, p, c, cw), Line(p, e))
    if k.radius is None or k.radius <= 0:
        d.append(diag("TX-E208", k.span))
        return None
    r = k.radius
    best: tuple[float, Arc, Line] | None = None
    for sign in (1.0, -1.0):
        base = add(e, left(u), sign * r)
        for centre in line_circle(base, add(base, u), s, r):
            p = add(centre, left(u), -sign * r)
            if math.dist(p, e) < 1e-9:
                continue
            arc = Arc(s, p, centre, cw)
            travel = unit((e[0] - p[0], e[1] - p[1]))
            if dot(tangent_at(arc, p), travel) < 1 - 1e-6:
                continue
            if best is None or arc.angle < best[0]:
                best = (arc.angle, arc, Line(p, e))
    if best is None:
        _no_solution(
            n,
            d,
            f"kein Kreisbogen R{_num(r)} geht tangential in die Gerade über",
            f"no arc R{_num(r)} runs tangentially into the line",
        )
        return None
    if best[0] >= 180 - 1e-6:
        d.append(diag("TX-E203", k.span))
        return None
    return best[1], best[2]


def _arc_arc(
    k: TurnItem, s: Point, n: TurnItem, e: Point, d: list[Diagnostic]
) -> tuple[Element, Element] | None:
    cw1, cw2 = k.code == "G2", n.code == "G2"
    if cw1 == cw2:
        d.append(diag("TX-E209", n.span))
        return None
    c1 = _centre(k, s)
    c2 = _pt(n.centre) if n.centre is not None else None
    candidates: list[tuple[Point, Point, Point]] = []  # (c1, p, c2)
    if c1 is not None and c2 is not None:
        r1, r2 = math.dist(c1, s), math.dist(c2, e)
        p = _pick(circle_circle(c1, r1, c2, r2), e, n if n.h is not None or k.h is None else k, n, d)
        if p is None:
            return None
        candidates = [(c1, p, c2)]
    elif c1 is not None and n.radius is not None and n.radius > 0:
        r1 = math.dist(c1, s)
        for q in circle_circle(e, n.radius, c1, r1 + n.radius):
            candidates.append((c1, add(c1, unit((q[0] - c1[0], q[1] - c1[1])), r1), q))
    elif c2 is not None and k.radius is not None and k.radius > 0:
        r2 = math.dist(c2, e)
        for q in circle_circle(s, k.radius, c2, r2 + k.radius):
            candidates.append((q, add(c2, unit((q[0] - c2[0], q[1] - c2[1])), r2), c2))
    else:
        d.append(diag("TX-E209", n.span))
        return None
    arcs = [(Arc(s, p, a, cw1), Arc(p, e, b, cw2)) for a, p, b in candidates]
    if not arcs:
        _no_solution(n, d, "die beiden Kreisbögen berühren sich nicht", "the two arcs do not touch")
        return None
    return min(arcs, key=lambda pair: pair[0].angle + pair[1].angle)


# -- stage 2: transition elements D, D-, R, C ---------------------------------------------------


def _next_motion(seq: Seq, i: int, skip: tuple[type, ...] = (SrkSwitch,)) -> int | None:
    """Index of the next contour segment after i that moves, skipping `skip` items; None if another
    command comes first or the sequence ends."""
    j = i + 1
    while j < len(seq):
        q = seq[j]
        if isinstance(q, _Seg):
            if q.moves:
                return j
        elif not isinstance(q, skip):
            return None
        j += 1
    return None


def _transitions(seq: Seq, d: list[Diagnostic]) -> Seq:
    out = list(seq)
    i = 0
    while i < len(out):
        seg = out[i]
        spec = seg.item.transition if isinstance(seg, _Seg) and not seg.inserted else None
        if not isinstance(seg, _Seg) or spec is None or not _last_of_block(out, i):
            i += 1
            continue
        j = _next_motion(out, i)
        nxt = out[j] if j is not None else None
        if not isinstance(nxt, _Seg) or nxt.rapid or seg.rapid:
            d.append(diag("TX-E210", seg.item.span, element=spec.raw))
            i += 1
            continue
        assert j is not None
        for q in out[i + 1 : j]:
            if isinstance(q, SrkSwitch):
                d.append(
                    diag(
                        "TX-E226",
                        q.span,
                        code=q.code,
                        where=f"zwischen dem Übergangselement {spec.raw} und seinem Folgesatz",
                        where_en=f"between the transition element {spec.raw} and its next block",
                    )
                )
        if spec.kind == "rounding":
            t = rounding(seg.e, nxt.e, spec.size)
        else:
            width = spec.size
            t = (
                _chamfer_by_length(seg.e, nxt.e, width)
                if spec.kind == "chamfer_length"
                else chamfer(seg.e, nxt.e, width)
            )
        if t is None:
            if turn(seg.e, nxt.e) == 0.0:
                why, why_en = (
                    "die Elemente gehen tangential ineinander über",
                    "the elements meet tangentially",
                )
            else:
                why, why_en = "es ist zu groß für die Nachbarelemente", "it is too large for its neighbours"
            d.append(
                diag(
                    "TX-E211",
                    seg.item.span,
                    element=spec.raw,
                    second=nxt.item.span.line,
                    reason=why,
                    reason_en=why_en,
                )
            )
            i += 1
            continue
        k = _next_motion(out, j, (SrkSwitch, Dwell))
        after = out[k] if k is not None else None
        deselects = nxt.item.nose.active and not (
            isinstance(after, _Seg) and not after.rapid and after.item.nose.mode == nxt.item.nose.mode
        )
        need = spec.size + W_MIN_TRANSITION + seg.item.nose.radius
        if not deselects and nxt.e.length < need - 1e-9:  # before deselection L2673 applies instead
            d.append(diag("TX-E223", nxt.item.span, length=nxt.e.length, need=need, element=spec.raw))
        out[i] = _Seg(seg.item, t.first, full=seg.full, after_transition=seg.after_transition)
        out[j] = _Seg(nxt.item, t.second, full=nxt.full or nxt.e, after_transition=spec)
        out.insert(i + 1, _Seg(seg.item, t.inserted, inserted=True))
        i += 1
    return out


def _chamfer_by_length(e1: Element, e2: Element, length: float) -> Transition | None:
    """D−: the chamfer with equal legs whose own length is `length` (legs found by bisection, since
    on an arc a leg is a chord)."""

    def chord(w: float) -> float | None:
        t = chamfer(e1, e2, w)
        return None if t is None else t.inserted.length

    lo, hi = 0.0, length
    while (c := chord(hi)) is not None and c < length:
        lo, hi = hi, 2 * hi
        if hi > 1e6:
            return None
    if chord(hi) is None:  # the legs for this length may still fit below hi
        top = hi
        for _ in range(60):
            mid = (lo + top) / 2
            c = chord(mid)
            if c is None:
                top = mid
            elif c < length:
                lo = mid
            else:
                hi = mid
                break
        else:
            return None
    for _ in range(80):
        mid = (lo + hi) / 2
        c = chord(mid)
        if c is None or c >= length:
            hi = mid
        else:
            lo = mid
    return chamfer(e1, e2, hi)


def _last_of_block(seq: Seq, i: int) -> bool:
    seg = seq[i]
    assert isinstance(seg, _Seg)
    return not any(isinstance(q, _Seg) and q.item is seg.item for q in seq[i + 1 : i + 3])


# -- stage 3: nose-radius compensation ----------------------------------------------------------

QUADRANT: dict[int, Point] = {1: (1.0, 1.0), 2: (-1.0, 1.0), 3: (-1.0, -1.0), 4: (1.0, -1.0)}  # (z, x)


def _move(seg: _Seg, e: Element, programmed: Point, feed: float | None = None) -> Move:
    """The block's template with the geometry of `e` (plane points) and the contour point `programmed`."""
    item = seg.item
    t = item.template
    if seg.inserted:
        spec = item.transition
        feed = spec.feed if spec is not None and spec.feed is not None else t.feed
    spindle = t.spindle if item.spindle_at is None else item.spindle_at(programmed[1])
    if isinstance(e, Arc):
        return t.with_path(
            "arc",
            _vec(e.a),
            _vec(e.b),
            _vec(e.c),
            "cw" if e.cw else "ccw",
            e.radius,
            e.angle,
            "G18",
            _vec(programmed),
            t.feed if feed is None else feed,
            spindle,
        )
    kind: MoveKind = "rapid" if seg.rapid else "feed"
    return t.with_path(
        kind,
        _vec(e.a),
        _vec(e.b),
        None,
        None,
        None,
        None,
        "G18",
        _vec(programmed),
        t.feed if feed is None else feed,
        spindle,
    )


def _session_side(seq: Seq, i: int, nose: Nose, span: Span, d: list[Diagnostic]) -> int:
    """+1 nose centre left of the travel direction, −1 right: G41/G42 say it, G46 takes it from the
    quadrant and the direction of the first feed blocks that decide it (L2552)."""
    if nose.mode == "G41":
        return 1
    if nose.mode == "G42":
        return -1
    q = QUADRANT.get(nose.quadrant)
    if q is None:
        d.append(diag("TX-E212", span, quadrant=nose.quadrant))
        return -1
    for seg in seq[i:]:
        if not isinstance(seg, _Seg) or not seg.item.nose.active:
            if isinstance(seg, _Seg):
                break
            continue
        if seg.rapid or not seg.moves:
            continue
        for tangent in (start_tangent(seg.e), end_tangent(seg.e)):
            k = dot(left(tangent), q)
            if abs(k) > 1e-6:
                return 1 if k > 0 else -1
    return -1


def _element_end(
    seq: Seq,
    i: int,
    j: int | None,
    seg: _Seg,
    nxt: object,
    start: Point,
    o: Element,
    side: int,
    nose: Nose,
    follows: bool,
    skipped: set[int],
    d: list[Diagnostic],
) -> tuple[Element, Element | None, Element | None]:
    """How the equidistant `o` of `seg` under SRK ends: a small step rolled round, an inside corner where the
    next equidistant starts, an arc about an outside corner, the end of the compensation (a rapid or G40
    next); (the equidistant, a corner arc, a tail to the contour point)."""
    r = side * nose.radius
    corner: Element | None = None
    tail: Element | None = None
    step = _small_step(seq, seg, j, o, r, nose.mode) if j is not None and follows else None
    if step is not None:
        # a step smaller than the nose radius: the nose rolls round its outer corner instead (Satzausblendung)
        assert isinstance(nxt, _Seg)
        o, corner = step
        d.append(diag("TX-W220", nxt.item.span, nose=nose.radius))
        skipped.add(id(nxt))
    elif isinstance(nxt, _Seg) and follows and not nxt.rapid:
        o2 = offset(nxt.e, r)
        bend = turn(seg.e, nxt.e)
        if o2 is not None and math.dist(seg.e.b, nxt.e.a) > 1e-6:  # blocks between were suppressed
            x = _gap_joint(o, o2, seg.e.b, nxt.e.a, nose.radius)
            if x is not None:
                o = with_end(o, x)
        elif o2 is not None and bend * side > 0:  # inside corner: where the equidistants meet
            x = nearest(intersections(o, o2), seg.e.b)
            if x is None or math.dist(x, seg.e.b) > 10 * nose.radius + 1e-6:
                d.append(diag("TX-E215", seg.item.span, nose=nose.radius, second=nxt.item.span.line))
            else:
                o = with_end(o, x)
        elif (
            o2 is not None
            and math.dist(o.b, o2.a) > 1e-6
            and (bend != 0.0 or dot(end_tangent(seg.e), start_tangent(nxt.e)) < 0)
        ):
            corner = Arc(o.b, o2.a, seg.e.b, cw=bend < 0 if bend != 0.0 else side > 0)
    elif isinstance(nxt, _Seg) and follows:
        # a rapid under SRK ends the compensation on this block: A there names the direction of
        # the last element (TX-28 case 3); without A the rapid's own direction makes the corner
        a = nxt.item.a
        v = _dir(a) if a is not None else start_tangent(nxt.e)
        if a is not None and abs(_angle_diff(angle_of(end_tangent(seg.e)), a)) > 0.01:
            d.append(diag("TX-W216", nxt.item.span, angle=a, direction=angle_of(end_tangent(seg.e))))
        bend = cross(end_tangent(seg.e), v)
        if abs(bend) > 1e-9 and bend * side > 0:
            virtual = offset(Line(seg.e.b, add(seg.e.b, v)), r)
            x = nearest(intersections(o, virtual), seg.e.b) if virtual is not None else None
            if x is not None:
                o = with_end(o, x)
                if a is None:
                    d.append(
                        diag(
                            "TX-W217",
                            seg.item.span,
                            length=math.dist(x, add(seg.e.b, left(end_tangent(seg.e)), r)),
                            second=nxt.item.span.line,
                        )
                    )
        _check_deselect(seg, nose, d)
    elif nxt is not None or _switch_follows(seq, i):
        # G40 straight after a feed block: the block itself deselects (TX-28 case 1)
        d.append(diag("TX-W218", seg.item.span))
        _check_deselect(seg, nose, d)
        if (
            isinstance(seg.e, Line)
            and abs(seg.e.a[0] - seg.e.b[0]) < 1e-9
            and seg.e.length < 2 * nose.radius - 1e-9
        ):  # deselection in X needs 2 × R (L2676)
            d.append(diag("TX-E224", seg.item.span, length=seg.e.length, need=2 * nose.radius))
        if isinstance(o, Line):
            o = Line(start, seg.e.b)
        else:
            tail = Line(o.b, seg.e.b)
    return o, corner, tail


def _compensate(seq: Seq, d: list[Diagnostic]) -> list[Command]:
    out: list[Command] = []
    pos: Point | None = None  # where the output path is (tool tip, or nose centre under SRK)
    session: tuple[int, Nose] | None = None  # (side, nose) of the running compensation
    selecting = False  # the next motion is the selection move
    first_feed = False  # the next feed is the first after a selection move (contour protection)
    switch_span: Span | None = None
    skipped: set[int] = set()  # segments taken out by Satzausblendung while compensating
    range_warned = False  # the session's cutting-range warning was given
    for i, seg in enumerate(seq):
        if id(seg) in skipped:
            continue
        if isinstance(seg, SrkSwitch):
            switch_span = seg.span
            if session is not None and (seg.code == "G40" or seg.code != session[1].mode):
                session = None
            continue
        if not isinstance(seg, _Seg):
            out.append(seg)
            if isinstance(seg, Move):
                pos, session = (seg.end[2], seg.end[0]), None
            continue
        nose = seg.item.nose
        start = pos if pos is not None else seg.e.a
        if not nose.active or nose.radius <= 0:
            session = None
            out += _plain(seg, start)
            pos = seg.e.b
            continue
        if session is None or session[1].mode != nose.mode:
            side = _session_side(seq, i, nose, switch_span or seg.item.span, d)
            session = (side, nose)
            selecting = True
            range_warned = False
            _suppress(seq, i, side * nose.radius, d)
            if isinstance(seg.e, Arc):
                d.append(diag("TX-E213", seg.item.span, command=nose.mode))
        side, r = session[0], session[0] * nose.radius
        j = _next_motion(seq, i, (SrkSwitch, Dwell))
        nxt = seq[j] if j is not None else None
        follows = isinstance(nxt, _Seg) and nxt.item.nose.active and nxt.item.nose.mode == nose.mode
        if not seg.moves:
            continue
        if seg.rapid or (selecting and not isinstance(seg.e, Arc)):
            # selection: end on the equidistant of the next element; a rapid before G40 deselects
            if isinstance(nxt, _Seg) and follows and not nxt.rapid:
                end = add(seg.e.b, left(start_tangent(nxt.e)), r)
                first_feed = True
            else:
                end = seg.e.b
            out.append(_move(seg, Line(start, end), seg.e.b))
            pos, selecting = end, False
            continue
        selecting = False
        o = offset(seg.e, r)
        if o is None:
            d.append(
                diag(
                    "TX-E214",
                    seg.item.span,
                    radius=seg.e.radius if isinstance(seg.e, Arc) else 0.0,
                    nose=nose.radius,
                )
            )
            out += _plain(seg, start)
            pos = seg.e.b
            continue
        o = with_start(o, start)
        o, corner, tail = _element_end(seq, i, j, seg, nxt, start, o, side, nose, follows, skipped, d)
        if nose.mode == "G46" and not range_warned and _against_quadrant(seg.e, side, nose.quadrant):
            d.append(diag("TX-W225", seg.item.span, quadrant=nose.quadrant))
            range_warned = True
        if first_feed:
            first_feed = False
            if o.length < nose.radius - 1e-9:
                d.append(diag("TX-E219", seg.item.span, length=o.length, nose=nose.radius))
        if isinstance(o, Line) and isinstance(seg.e, Line) and _against(seg.e, o):
            d.append(diag("TX-W220", seg.item.span, nose=nose.radius))
            if not (follows and isinstance(nxt, _Seg) and not nxt.rapid):  # deselection comes next
                d.append(diag("TX-E221", seg.item.span))
        out.append(_move(seg, o, seg.e.b))
        pos = o.b
        for extra in (corner, tail):
            if extra is not None:
                out.append(_move(seg, extra, seg.e.b))
                pos = extra.b
    return out


def _session_runs(seq: Seq, i: int) -> list[list[_Seg]]:
    """The runs of consecutive feed segments of the compensation session that starts at seq[i]."""
    first = seq[i]
    assert isinstance(first, _Seg)
    mode = first.item.nose.mode
    runs: list[list[_Seg]] = [[]]
    for q in seq[i:]:
        if isinstance(q, SrkSwitch):
            if q.code != mode:
                break
            continue
        if isinstance(q, Dwell):
            continue
        if not isinstance(q, _Seg) or q.item.nose.mode != mode or q.item.nose.radius <= 0:
            break
        if q.rapid:
            runs.append([])
        elif q.moves:
            runs[-1].append(q)
    return [run for run in runs if len(run) >= 3]


def _suppress(seq: Seq, i: int, r: float, d: list[Diagnostic]) -> None:
    """Satzausblendung (L2652): inner blocks of the session starting at seq[i] whose equidistant vanishes
    between its neighbours' are taken out of `seq`; the neighbours' equidistants are intersected instead."""
    for run in _session_runs(seq, i):
        m = 1
        while 1 <= m < len(run) - 1:
            e = run[m].e
            if isinstance(e, Arc):
                gone = offset(e, r) is None  # an inside arc smaller than the nose radius
            else:
                gone = e.length <= SHORT * abs(r) and _vanishes(run[m - 1], run[m], run[m + 1], r)
            if not gone:
                m += 1
                continue
            before, after = run[m - 1].e, run[m + 1].e
            o1, o2 = offset(before, r), offset(after, r)
            facing = dot(end_tangent(before), start_tangent(after)) < -1e-9  # the walls of a narrow groove
            if (
                o1 is None
                or o2 is None
                or (not facing and _gap_joint(o1, o2, before.b, after.a, abs(r)) is None)
            ):
                m += 1  # the neighbours' equidistants do not meet either: the block stays (TX-W220 below)
                continue
            seg = run.pop(m)
            del seq[_index(seq, seg, i)]
            d.append(diag("TX-W220", seg.item.span, nose=abs(r)))
            m = max(1, m - 1)  # the neighbour before may vanish now


def _switch_follows(seq: Seq, i: int) -> bool:
    """Whether G40 (or another SRK code) is programmed after seq[i] before any further motion."""
    for q in seq[i + 1 :]:
        if isinstance(q, SrkSwitch):
            return True
        if not isinstance(q, Dwell):
            return False
    return False


def _against_quadrant(e: Element, side: int, quadrant: int) -> bool:
    """G46 watches a cutting range of 180° (L2544): a travel direction that would need the nose centre on
    the other side for this quadrant is outside it."""
    q = QUADRANT.get(quadrant)
    if q is None:
        return False
    return any(dot(left(t), q) * side < -1e-6 for t in (start_tangent(e), end_tangent(e)))


def _small_step(
    seq: Seq,
    seg: _Seg,
    j: int,
    o: Element,
    r: float,
    mode: str,
) -> tuple[Element, Element] | None:
    """A line `nxt` too short for the nose between an inside and an outside corner (or the reverse): the
    equidistant `o` of `seg` and an arc about the step's outer corner that reaches the equidistant of the
    element after the step. None when `nxt` (= seq[j]) is no such step."""
    nxt = seq[j]
    if not isinstance(nxt, _Seg) or not isinstance(nxt.e, Line) or nxt.rapid or nxt.e.length > SHORT * abs(r):
        return None
    k = _next_motion(seq, j, (SrkSwitch, Dwell))
    after = seq[k] if k is not None else None
    if not isinstance(after, _Seg) or after.rapid or after.item.nose.mode != mode:
        return None
    if math.dist(seg.e.b, nxt.e.a) > 1e-6 or math.dist(nxt.e.b, after.e.a) > 1e-6:
        return None
    if not _vanishes(seg, nxt, after, r):
        return None
    o3 = offset(after.e, r)
    if o3 is None:
        return None
    first, second = turn(seg.e, nxt.e) * r, turn(nxt.e, after.e) * r
    radius = abs(r)
    if first > 0 and second < 0:  # inside, then outside: roll round the step's end
        c = nxt.e.b
        hits = [p for p in _circle_hits(o, c, radius)]
        if not hits:
            return None
        x = min(hits, key=lambda p: math.dist(p, o.a))
        return with_end(o, x), Arc(x, o3.a, c, cw=r > 0)
    if (
        first < 0 and second > 0
    ):  # outside, then inside: roll round the step's start onto the next equidistant
        c = nxt.e.a
        hits = _circle_hits(o3, c, radius)
        if not hits:
            return None
        x = min(hits, key=lambda p: math.dist(p, o3.b))
        return o, Arc(o.b, x, c, cw=r > 0)
    return None


def _circle_hits(e: Element, c: Point, radius: float) -> list[Point]:
    """Points of the carrier of `e` at distance `radius` from `c`."""
    if isinstance(e, Line):
        return line_circle(e.a, e.b, c, radius)
    return circle_circle(e.c, e.radius, c, radius)


def _index(seq: Seq, seg: _Seg, start: int = 0) -> int:
    return next(k for k in range(start, len(seq)) if seq[k] is seg)


def _joint(e1: Element, e2: Element, o1: Element, o2: Element, r: float) -> Point | None:
    """Where the nose centre passes from the equidistant o1 of e1 to o2 of e2 (one side of the joint);
    None if an inside corner or a gap has no intersection near the contour."""
    if math.dist(e1.b, e2.a) > 1e-6:
        return _gap_joint(o1, o2, e1.b, e2.a, abs(r))
    bend = turn(e1, e2)
    if bend * r > 0:
        x = nearest(intersections(o1, o2), e1.b)
        return x if x is not None and math.dist(x, e1.b) <= 10 * abs(r) + 1e-6 else None
    return o1.b


def _gap_joint(o1: Element, o2: Element, a: Point, b: Point, radius: float) -> Point | None:
    """The joint of two equidistants whose contour elements no longer meet (blocks suppressed between):
    their intersection near the gap, or o1's end when they are one line."""
    mid = ((a[0] + b[0]) / 2, (a[1] + b[1]) / 2)
    x = nearest(intersections(o1, o2), mid)
    if x is not None and math.dist(x, mid) <= 10 * radius + math.dist(a, b) + 1e-6:
        return x
    if (
        isinstance(o1, Line)
        and isinstance(o2, Line)
        and abs(cross(unit((o1.b[0] - o1.a[0], o1.b[1] - o1.a[1])), (o2.a[0] - o1.a[0], o2.a[1] - o1.a[1])))
        < 1e-6
    ):
        return o1.b  # collinear: the path runs straight on
    return None


def _vanishes(prev: _Seg, seg: _Seg, nxt: _Seg, r: float) -> bool:
    """Whether the equidistant of the line `seg`, cut by its neighbours', is empty or runs backwards.

    r > 0: the nose centre is left of the travel direction, r < 0 right."""
    joined = math.dist(prev.e.b, seg.e.a) <= 1e-6 and math.dist(seg.e.b, nxt.e.a) <= 1e-6
    if joined and turn(prev.e, seg.e) * r <= 0 and turn(seg.e, nxt.e) * r <= 0:
        return False  # outside corners at both ends: perpendicular to perpendicular, never empty
    o0, o, o2 = offset(prev.e, r), offset(seg.e, r), offset(nxt.e, r)
    if o0 is None or o is None or o2 is None:
        return False
    start = _joint(prev.e, seg.e, o0, o, r)
    end = _joint(seg.e, nxt.e, o, o2, r)
    if start is None or end is None:
        return True
    if math.dist(prev.e.b, seg.e.a) <= 1e-6 and turn(prev.e, seg.e) * r <= 0:
        start = o.a  # an outside corner: the equidistant starts on the perpendicular
    e = seg.e
    return dot((end[0] - start[0], end[1] - start[1]), (e.b[0] - e.a[0], e.b[1] - e.a[1])) <= 1e-9


def _plain(seg: _Seg, start: Point) -> list[Move]:
    """The programmed element, from where the tool is (a line joins first if an arc starts elsewhere)."""
    if isinstance(seg.e, Line):
        return [_move(seg, Line(start, seg.e.b), seg.e.b)]
    moves = []
    if math.dist(start, seg.e.a) > 1e-9:
        moves.append(dataclasses.replace(_move(seg, Line(start, seg.e.a), seg.e.a), kind="feed"))
    return moves + [_move(seg, seg.e, seg.e.b)]


def _check_deselect(seg: _Seg, nose: Nose, d: list[Diagnostic]) -> None:
    """The last feed block after a transition must travel transition + nose radius + 0.01 mm (L2673)."""
    spec = seg.after_transition
    if spec is None or seg.full is None:
        return
    need = spec.size + nose.radius + W_MIN_DESELECT
    if seg.full.length < need - 1e-9:
        d.append(diag("TX-E222", seg.item.span, length=seg.full.length, need=need, element=spec.raw))


def _against(e: Line, o: Line) -> bool:
    de = (e.b[0] - e.a[0], e.b[1] - e.a[1])
    do = (o.b[0] - o.a[0], o.b[1] - o.a[1])
    return dot(de, do) < -1e-9


def _angle_diff(a: float, b: float) -> float:
    return (a - b + 180.0) % 360.0 - 180.0
