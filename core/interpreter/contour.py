"""From programmed contour to tool-centre path: RN transitions, cutter radius compensation, G45–G48.

The block executor emits `Planned` moves: the programmed geometry plus what the contour needs
(RN at the end, the compensation side and radius, approach/departure requests). This stage runs
over them in order, with the look-ahead the PAL control has (an element is final only once its
successor is known): first the transition elements are put into the programmed contour, then
the contour is offset by the tool radius. Errors name the block(s) concerned.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

from core.diagnostics import Diagnostic, diag
from core.geometry.elements import (
    Arc,
    Element,
    Line,
    Transition,
    add,
    chamfer,
    end_tangent,
    intersections,
    left,
    nearest,
    offset,
    rounding,
    start_tangent,
    turn,
    with_end,
    with_start,
)
from core.toolpath import Dwell, Move, MoveKind, ToolChange, Vec3


@dataclass(frozen=True, slots=True)
class Approach:
    """G45 (line of length `size`) or G47 (quarter circle of tool-centre radius `size`)."""

    code: str
    size: float
    w: float | None  # rapid infeed plane
    plunge_feed: float | None  # E
    z: float | None  # infeed depth at the approach point


@dataclass(frozen=True, slots=True)
class Departure:
    """G46 (line of length `size`) or G48 (quarter circle of tool-centre radius `size`)."""

    code: str
    size: float
    w: float | None
    z: float | None


@dataclass(slots=True)
class Planned:
    """A programmed move and what the contour stage needs to know about it."""

    move: Move
    rn: float = 0.0  # RN at the end: > 0 rounding radius, < 0 chamfer width
    rn_raw: str = ""
    rn_feed: float | None = None  # E: feed on the inserted element
    side: int = 0  # +1 tool left of the contour (G41), -1 right (G42), 0 off (G40)
    radius: float = 0.0  # effective tool radius (table + TR)
    approach: Approach | None = None
    departure: Departure | None = None

    @property
    def in_plane(self) -> bool:
        m = self.move
        return m.kind == "arc" or (m.start[0], m.start[1]) != (m.end[0], m.end[1])

    @property
    def is_contour(self) -> bool:
        """A feed move in the plane (G1, G2, G3, G11, G12, G13): an element RN may follow."""
        return self.move.kind != "rapid" and self.in_plane


Command = Move | Dwell | ToolChange


def element_of(m: Move) -> Element:
    if m.kind == "arc" and m.center is not None:
        return Arc((m.start[0], m.start[1]), (m.end[0], m.end[1]), (m.center[0], m.center[1]), m.direction == "cw",
                   full=(m.angle or 0) >= 360 - 1e-9)
    return Line((m.start[0], m.start[1]), (m.end[0], m.end[1]))


def move_of(template: Move, e: Element, z0: float, z1: float, programmed: Vec3 | None = None,
            kind: str | None = None, feed: float | None = None) -> Move:
    """`template`'s technology and block with the geometry of `e` from Z `z0` to `z1`."""
    start, end = (e.a[0], e.a[1], z0), (e.b[0], e.b[1], z1)
    fields: dict[str, object] = {"start": start, "end": end, "programmed_end": programmed}
    if isinstance(e, Arc):
        fields.update(kind="arc", center=(e.c[0], e.c[1], z0), direction="cw" if e.cw else "ccw",
                      radius=e.radius, angle=e.angle)
    else:
        fields.update(kind=kind if kind is not None else ("rapid" if template.kind == "rapid" else "feed"),
                      center=None, direction=None, radius=None, angle=None)
    if feed is not None:
        fields["feed"] = feed
    return dataclasses.replace(template, **fields)  # type: ignore[arg-type]


def _z_at(m: Move) -> tuple[float, float]:
    return m.start[2], m.end[2]


# -- stage 1: transition elements RN ---------------------------------------------------------

def insert_transitions(items: list[Planned | Dwell | ToolChange], d: list[Diagnostic]) -> list[Planned | Dwell | ToolChange]:
    """Put RN roundings and chamfers into the programmed contour."""
    out: list[Planned | Dwell | ToolChange] = list(items)
    i = 0
    while i < len(out):
        p = out[i]
        if not isinstance(p, Planned) or p.rn == 0 or not p.in_plane:
            i += 1
            continue
        j = i + 1
        while j < len(out) and not isinstance(out[j], Planned):
            j += 1
        nxt = out[j] if j < len(out) else None
        if not isinstance(nxt, Planned) or not nxt.is_contour or nxt.side != p.side:
            d.append(diag("PAL-E209", p.move.span, line=p.move.span.line))
            i += 1
            continue
        e1, e2 = element_of(p.move), element_of(nxt.move)
        t: Transition | None = rounding(e1, e2, p.rn) if p.rn > 0 else chamfer(e1, e2, -p.rn)
        if t is None:
            if turn(e1, e2) == 0.0:
                why, why_en = "die Elemente gehen tangential ineinander über", "the elements meet tangentially"
            else:
                why, why_en = "es ist zu groß für die Nachbarelemente", "it is too large for its neighbours"
            d.append(diag("PAL-E208", p.move.span, raw=p.rn_raw, first=p.move.span.line,
                          second=nxt.move.span.line, reason=why, reason_en=why_en))
            i += 1
            continue
        z0, z1 = _z_at(p.move)
        first = dataclasses.replace(p, move=move_of(p.move, t.first, z0, z1), rn=0.0)
        inserted = dataclasses.replace(
            p, rn=0.0, move=move_of(p.move, t.inserted, z1, z1,
                                    feed=p.rn_feed if p.rn_feed is not None else p.move.feed))
        nz0, nz1 = _z_at(nxt.move)
        second = dataclasses.replace(nxt, move=move_of(nxt.move, t.second, nz0, nz1))
        out[i] = first
        out[j] = second
        out.insert(i + 1, inserted)
        i += 1
    return out


# -- stage 2: cutter radius compensation -----------------------------------------------------

def compensate(items: list[Planned | Dwell | ToolChange], d: list[Diagnostic]) -> list[Command]:
    """Turn the programmed contour into the tool-centre path (G41/G42, G45–G48, G40)."""
    out: list[Command] = []
    pos: Vec3 | None = None  # where the tool centre is
    active = 0  # side of the running compensation
    planned = [(k, p) for k, p in enumerate(items) if isinstance(p, Planned)]
    order = {k: n for n, (k, _) in enumerate(planned)}

    def next_in_plane(k: int, side: int) -> Planned | None:
        for _, q in planned[order[k] + 1:]:
            if q.side != side:
                return None
            if q.in_plane:
                return q
        return None

    for k, item in enumerate(items):
        if not isinstance(item, Planned):
            out.append(item)
            continue
        p, m = item, item.move
        start = pos if pos is not None else m.start
        if p.side == 0:
            if p.departure is not None:
                if active:
                    pos = _depart(p, start, active, out)
                active = 0
                continue
            active = 0
            moved = dataclasses.replace(m, start=start, programmed_end=m.end)
            if start != m.end or m.kind == "arc":
                out.append(moved if m.kind != "arc" else _arc_from(m, start))
            pos = m.end
            continue
        if p.radius <= 0:
            d.append(diag("PAL-E220", m.span))
            out.append(dataclasses.replace(m, start=start))
            pos = m.end
            continue
        r = p.side * p.radius
        if not p.in_plane:  # an infeed move keeps the tool where it is in the plane
            end = (start[0], start[1], m.end[2])
            if end != start:
                out.append(dataclasses.replace(m, start=start, end=end, programmed_end=m.end))
            pos = end
            continue
        if not active or active != p.side:
            # the first move after G41/G42: to the point beside the next element's start
            nxt = next_in_plane(k, p.side)
            if nxt is None:
                d.append(diag("PAL-E218", m.span, command="G41" if p.side > 0 else "G42"))
                out.append(dataclasses.replace(m, start=start))
                pos = m.end
                continue
            active = p.side
            first = element_of(nxt.move)
            t = start_tangent(first)
            if p.approach is not None:
                pos = _approach(p, start, first, r, out)
            else:
                target = add((m.end[0], m.end[1]), left(t), r)
                end = (target[0], target[1], m.end[2])
                out.append(dataclasses.replace(m, kind="rapid" if m.kind == "rapid" else "feed", start=start, end=end,
                                               center=None, direction=None, radius=None, angle=None,
                                               programmed_end=m.end))
                pos = end
            continue
        # a contour element under compensation
        e = element_of(m)
        o = offset(e, r)
        if o is None:
            if isinstance(e, Arc):
                d.append(diag("PAL-E214", m.span, radius=round(e.radius, 4), tool_radius=p.radius))
            else:
                d.append(diag("PAL-E215", m.span, tool_radius=p.radius))
            pos = m.end
            continue
        o = with_start(o, (start[0], start[1]))  # where the previous corner left the tool
        corner_arc: Element | None = None
        nxt = next_in_plane(k, p.side)
        if nxt is not None:
            e2 = element_of(nxt.move)
            o2 = offset(e2, r)
            side_turn = turn(e, e2)
            if o2 is not None:
                if side_turn * p.side > 0:  # inside corner: end where the two offsets meet
                    x = nearest([q for q in intersections(o, o2)], e.b)
                    if x is None or math.dist(x, e.b) > 10 * abs(r) + 1e-6:
                        d.append(diag("PAL-E217", m.span, tool_radius=p.radius, first=m.span.line,
                                      second=nxt.move.span.line))
                    else:
                        o = with_end(o, x)
                elif side_turn != 0.0 or _reverses(e, e2):  # outside corner: an arc about the corner
                    corner_arc = Arc(o.b, o2.a, e.b, cw=side_turn < 0 if side_turn != 0.0 else p.side > 0)
        if _reversed(e, o):
            d.append(diag("PAL-E215", m.span, tool_radius=p.radius))
        z1 = m.end[2]
        out.append(move_of(m, o, start[2], z1, programmed=m.end))
        pos = (o.b[0], o.b[1], z1)
        if corner_arc is not None:
            out.append(move_of(m, corner_arc, z1, z1, programmed=m.end))
            pos = (corner_arc.b[0], corner_arc.b[1], z1)
    return out


def _reverses(e1: Element, e2: Element) -> bool:
    t1, t2 = end_tangent(e1), start_tangent(e2)
    return t1[0] * t2[0] + t1[1] * t2[1] < 0


def _reversed(e: Element, o: Element) -> bool:
    """True if the trimmed offset element runs against its contour element (it vanished)."""
    if isinstance(e, Line) and isinstance(o, Line):
        de = (e.b[0] - e.a[0], e.b[1] - e.a[1])
        do = (o.b[0] - o.a[0], o.b[1] - o.a[1])
        return de[0] * do[0] + de[1] * do[1] < -1e-9
    return False


def _arc_from(m: Move, start: Vec3) -> Move:
    """The programmed arc `m`, started from the actual tool position (after G40 the path returns to it)."""
    return dataclasses.replace(m, start=start, programmed_end=m.end)


def _approach(p: Planned, start: Vec3, first: Element, r: float, out: list[Command]) -> Vec3:
    """G45/G47: position beside the approach start, infeed (rapid to W, feed E to Z), then approach."""
    m = p.move
    a = p.approach
    assert a is not None
    p1 = first.a
    t = start_tangent(first)
    n = left(t)
    side = 1 if r > 0 else -1
    target = add(p1, n, r)  # tool centre at the first contour point
    if a.code == "G45":
        approach_start = add(target, t, -a.size)
        element: Element = Line(approach_start, target)
    else:
        centre = add(target, n, side * a.size)
        approach_start = add(centre, t, -a.size)
        element = Arc(approach_start, target, centre, cw=side < 0)
    z = start[2]
    pos: Vec3 = (approach_start[0], approach_start[1], z)
    kind: MoveKind = "rapid" if m.kind == "rapid" else "feed"
    if pos != start:
        out.append(dataclasses.replace(m, kind=kind, start=start, end=pos, center=None, direction=None,
                                       radius=None, angle=None, programmed_end=None))
    if a.w is not None and a.w != z:
        out.append(dataclasses.replace(m, kind="rapid", start=pos, end=(pos[0], pos[1], a.w), center=None,
                                       direction=None, radius=None, angle=None, programmed_end=None))
        pos = (pos[0], pos[1], a.w)
    if a.z is not None and a.z != pos[2]:
        feed = a.plunge_feed if a.plunge_feed is not None else m.feed
        out.append(dataclasses.replace(m, kind="feed", start=pos, end=(pos[0], pos[1], a.z), center=None,
                                       direction=None, radius=None, angle=None, feed=feed, programmed_end=None))
        pos = (pos[0], pos[1], a.z)
    feed_move = dataclasses.replace(m, kind="feed")
    out.append(move_of(feed_move, element, pos[2], pos[2], programmed=(p1[0], p1[1], pos[2])))
    return (target[0], target[1], pos[2])


def _depart(p: Planned, start: Vec3, side: int, out: list[Command]) -> Vec3:
    """G46/G48: leave the last contour point tangentially, then feed to Z and rapid to W."""
    m = p.move
    dep = p.departure
    assert dep is not None
    last = next((c for c in reversed(out) if isinstance(c, Move) and (c.kind == "arc" or c.start[:2] != c.end[:2])),
                None)
    if last is None:
        return start
    e = element_of(last)
    t = end_tangent(e)
    here = (start[0], start[1])
    if dep.code == "G46":
        element: Element = Line(here, add(here, t, dep.size))
    else:  # a quarter circle on the compensation side, tangent at the last point
        centre = add(here, left(t), side * dep.size)
        element = Arc(here, add(centre, t, dep.size), centre, cw=side < 0)
    feed_move = dataclasses.replace(m, kind="feed")
    out.append(move_of(feed_move, element, start[2], start[2], programmed=None))
    pos: Vec3 = (element.b[0], element.b[1], start[2])
    if dep.z is not None and dep.z != pos[2]:
        out.append(dataclasses.replace(m, kind="feed", start=pos, end=(pos[0], pos[1], dep.z), center=None,
                                       direction=None, radius=None, angle=None, programmed_end=None))
        pos = (pos[0], pos[1], dep.z)
    if dep.w is not None and dep.w != pos[2]:
        out.append(dataclasses.replace(m, kind="rapid", start=pos, end=(pos[0], pos[1], dep.w), center=None,
                                       direction=None, radius=None, angle=None, programmed_end=None))
        pos = (pos[0], pos[1], dep.w)
    return pos


def finish(items: list[Planned | Dwell | ToolChange], d: list[Diagnostic]) -> list[Command]:
    """Both stages in order: transitions on the programmed contour, then compensation."""
    if not any(isinstance(p, Planned) and (p.rn or p.side) for p in items):
        return [p.move if isinstance(p, Planned) else p for p in items]
    return compensate(insert_transitions(items, d), d)


