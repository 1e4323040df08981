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
from collections.abc import Callable
from dataclasses import dataclass

from core.diagnostics import Diagnostic, diag
from core.geometry.elements import (
    Arc,
    Element,
    Line,
    Transition,
    add,
    chamfer,
    cross,
    dot,
    end_tangent,
    intersections,
    left,
    nearest,
    offset,
    on_element,
    rounding,
    start_tangent,
    turn,
    with_end,
    with_start,
)
from core.geometry.planes import from_plane, to_plane
from core.syntax.blocks import Span
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
    tangent: tuple[float, float] | None = None  # end tangent of the last contour element; None: no departure
    programmed: Vec3 | None = (
        None  # the end of the programmed departure (the contour's, not the tool centre's)
    )


def departure_ends(
    code: str, last: tuple[float, float], tangent: tuple[float, float], side: int, radius: float, size: float
) -> tuple[tuple[float, float], tuple[float, float]]:
    """Where the tool centre and the programmed contour end after G46/G48 from the contour point `last`.

    The tool centre starts `radius` beside `last` on the compensation side (`side` +1 left, -1 right)
    and moves parallel to the programmed departure: G46 `size` along the tangent (DECISIONS.md
    ruling 2); G48 a quarter circle of tool-centre radius `size` (ruling 1), whose programmed
    counterpart is the concentric quarter circle of radius `size` + `radius` through `last`.
    """
    n = left(tangent)
    centre = add(last, n, side * radius)
    if code == "G46":
        return add(centre, tangent, size), add(last, tangent, size)
    middle = add(centre, n, side * size)
    return add(middle, tangent, size), add(middle, tangent, size + radius)


def end_tangent_of(m: Move) -> tuple[float, float]:
    """The unit tangent at the end of `m`, in the coordinates of its plane."""
    return end_tangent(element_of(to_plane_move(m, m.plane)))


@dataclass(slots=True)
class Planned:
    """A programmed move and what the contour stage needs to know about it."""

    move: Move
    rn: float = 0.0  # RN at the end: > 0 rounding radius, < 0 chamfer width
    rn_raw: str = ""  # as written, for messages: "RN-15", "G301 I20", "#CHF=35"
    rn_feed: float | None = None  # E: feed on the inserted element
    side: int = 0  # +1 tool left of the contour (G41), -1 right (G42), 0 off (G40)
    radius: float = 0.0  # effective tool radius (table + TR)
    approach: Approach | None = None
    departure: Departure | None = None
    chamfer_by_length: bool = False  # a negative rn is the chamfer's own length (Beckhoff #CHF)
    rapid_ok: bool = False  # the transition may join rapid moves (Beckhoff G301/G302)
    blend_span: Span | None = None  # the block that asked for the transition, when not this one

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
        return Arc(
            (m.start[0], m.start[1]),
            (m.end[0], m.end[1]),
            (m.center[0], m.center[1]),
            m.direction == "cw",
            full=(m.angle or 0) >= 360 - 1e-9,
        )
    return Line((m.start[0], m.start[1]), (m.end[0], m.end[1]))


def move_of(
    template: Move,
    e: Element,
    z0: float,
    z1: float,
    programmed: Vec3 | None = None,
    kind: str | None = None,
    feed: float | None = None,
) -> Move:
    """`template`'s technology and block with the geometry of `e` from Z `z0` to `z1`."""
    start, end = (e.a[0], e.a[1], z0), (e.b[0], e.b[1], z1)
    fields: dict[str, object] = {"start": start, "end": end, "programmed_end": programmed}
    if isinstance(e, Arc):
        fields.update(
            kind="arc",
            center=(e.c[0], e.c[1], z0),
            direction="cw" if e.cw else "ccw",
            radius=e.radius,
            angle=e.angle,
        )
    else:
        fields.update(
            kind=kind if kind is not None else ("rapid" if template.kind == "rapid" else "feed"),
            center=None,
            direction=None,
            radius=None,
            angle=None,
        )
    if feed is not None:
        fields["feed"] = feed
    return dataclasses.replace(template, **fields)  # type: ignore[arg-type]


def _z_at(m: Move) -> tuple[float, float]:
    return m.start[2], m.end[2]


# -- stage 1: transition elements RN ---------------------------------------------------------


@dataclass(frozen=True, slots=True)
class Blend:
    """A chamfer or rounding programmed in a block of its own (Beckhoff G301/G302) for the corner
    between the motion blocks before and after it."""

    size: float  # > 0 rounding radius, < 0 chamfer width
    raw: str
    feed: float | None
    span: Span


Item = Planned | Dwell | ToolChange | Blend


def insert_transitions(items: list[Item], d: list[Diagnostic]) -> list[Item]:
    """Put RN roundings and chamfers into the programmed contour, in the plane of the second element."""
    out: list[Item] = []
    for item in items:  # a Blend block applies to the end of the motion before it
        if isinstance(item, Blend):
            prev = next((k for k in range(len(out) - 1, -1, -1) if isinstance(out[k], Planned)), None)
            if prev is None:
                d.append(diag("BK-E502", item.span, element=item.raw, line=item.span.line))
                continue
            before = out[prev]
            assert isinstance(before, Planned)
            if before.blend_span is not None:  # Beckhoff's error 20701: no motion block since the last one
                d.append(
                    diag(
                        "BK-E504",
                        item.span,
                        element=item.raw,
                        line=item.span.line,
                        first=before.rn_raw,
                        first_line=before.blend_span.line,
                    )
                )
                continue
            out[prev] = dataclasses.replace(
                before, rn=item.size, rn_raw=item.raw, rn_feed=item.feed, rapid_ok=True, blend_span=item.span
            )
            continue
        out.append(item)
    i = 0
    while i < len(out):
        p = out[i]
        if not isinstance(p, Planned) or p.rn == 0:
            i += 1
            continue
        j = i + 1
        while j < len(out) and not isinstance(out[j], Planned):
            j += 1
        nxt = out[j] if j < len(out) else None
        where = p.blend_span or p.move.span
        if (
            not isinstance(nxt, Planned)
            or not nxt.in_plane
            or nxt.side != p.side
            or not (nxt.is_contour or p.rapid_ok)
        ):
            if p.rn_raw.startswith("RN"):
                d.append(diag("PAL-E209", where, line=where.line))
            else:  # Beckhoff's G301/G302, #CHR, #CHF, #RND
                d.append(diag("BK-E503", where, element=p.rn_raw, line=where.line))
            i += 1
            continue
        plane = nxt.move.plane
        first_move, next_move = to_plane_move(p.move, plane), to_plane_move(nxt.move, plane)
        e1, e2 = element_of(first_move), element_of(next_move)
        t: Transition | None = None
        if not _in_plane(first_move) and p.rn < 0 and p.move.kind != "arc" and nxt.move.kind != "arc":
            # the block before has no extent in the plane: a chamfer between two lines lies on the lines
            pair = _chamfer_in_space(p, nxt)
            if pair is not None:
                out[i], inserted3, out[j] = pair
                out.insert(i + 1, inserted3)
                i += 1
                continue
            why, why_en = "es ist zu groß für die Nachbarelemente", "it is too large for its neighbours"
        elif not _in_plane(first_move):
            why, why_en = (
                f"der Satz davor liegt nicht in der Ebene {plane}",
                f"the block before is not in plane {plane}",
            )
        elif p.rn > 0:
            t = rounding(e1, e2, p.rn)
        else:
            width = -p.rn
            if p.chamfer_by_length:  # the chamfer's own length → its legs along the elements
                cos_half = math.cos(
                    math.acos(max(-1.0, min(1.0, dot(end_tangent(e1), start_tangent(e2))))) / 2
                )
                width = width / (2 * cos_half) if cos_half > 1e-9 else math.inf
            t = chamfer(e1, e2, width)
        if t is None:
            if _in_plane(first_move) and turn(e1, e2) == 0.0:
                why, why_en = (
                    "die Elemente gehen tangential ineinander über",
                    "the elements meet tangentially",
                )
            elif _in_plane(first_move):
                why, why_en = "es ist zu groß für die Nachbarelemente", "it is too large for its neighbours"
            d.append(
                diag(
                    "PAL-E208",
                    where,
                    element=p.rn_raw,
                    first=p.move.span.line,
                    second=nxt.move.span.line,
                    reason=why,
                    reason_en=why_en,
                )
            )
            i += 1
            continue
        z0, z1 = _z_at(first_move)
        feed = p.rn_feed if p.rn_feed is not None else p.move.feed
        first = dataclasses.replace(
            p, move=from_plane_move(move_of(first_move, t.first, z0, z1), plane), rn=0.0
        )
        inserted_move = move_of(first_move, t.inserted, z1, z1, feed=feed)
        if p.blend_span is not None:
            inserted_move = dataclasses.replace(inserted_move, span=p.blend_span)
        inserted = dataclasses.replace(p, rn=0.0, move=from_plane_move(inserted_move, plane))
        nz0, nz1 = _z_at(next_move)
        second = dataclasses.replace(nxt, move=from_plane_move(move_of(next_move, t.second, nz0, nz1), plane))
        out[i] = first
        out[j] = second
        out.insert(i + 1, inserted)
        i += 1
    return out


def _chamfer_in_space(p: Planned, nxt: Planned) -> tuple[Planned, Planned, Planned] | None:
    """A chamfer between two straight moves in space: its ends lie `width` from the corner on each line."""
    a, corner, b = p.move.start, p.move.end, nxt.move.end
    len1, len2 = math.dist(a, corner), math.dist(corner, b)
    if len1 < 1e-9 or len2 < 1e-9:
        return None
    t1 = tuple((corner[k] - a[k]) / len1 for k in range(3))
    t2 = tuple((b[k] - corner[k]) / len2 for k in range(3))
    width = -p.rn
    if p.chamfer_by_length:
        cos_half = math.cos(
            math.acos(max(-1.0, min(1.0, sum(x * y for x, y in zip(t1, t2, strict=True))))) / 2
        )
        width = width / (2 * cos_half) if cos_half > 1e-9 else math.inf
    if width >= len1 - 1e-6 or width >= len2 - 1e-6:
        return None
    p1: Vec3 = (corner[0] - width * t1[0], corner[1] - width * t1[1], corner[2] - width * t1[2])
    p2: Vec3 = (corner[0] + width * t2[0], corner[1] + width * t2[1], corner[2] + width * t2[2])
    feed = p.rn_feed if p.rn_feed is not None else p.move.feed
    inserted = dataclasses.replace(p.move, start=p1, end=p2, feed=feed, span=p.blend_span or p.move.span)
    return (
        dataclasses.replace(p, move=dataclasses.replace(p.move, end=p1), rn=0.0),
        dataclasses.replace(p, move=inserted, rn=0.0),
        dataclasses.replace(nxt, move=dataclasses.replace(nxt.move, start=p2)),
    )


def _in_plane(m: Move) -> bool:
    """Whether a move, in plane coordinates, moves in the plane (u, v)."""
    return m.kind == "arc" or (m.start[0], m.start[1]) != (m.end[0], m.end[1])


def to_plane_move(m: Move, plane: str) -> Move:
    """`m` in the coordinates (u, v, w) of `plane` (identity for G17)."""
    return _map_move(m, plane, to_plane)


def from_plane_move(m: Move, plane: str) -> Move:
    """The inverse of to_plane_move: back to (x, y, z), the arc keeping its plane."""
    return _map_move(m, plane, from_plane)


def _map_move(m: Move, plane: str, f: Callable[[Vec3, str], Vec3]) -> Move:
    if plane == "G17":
        return m
    return dataclasses.replace(
        m,
        start=f(m.start, plane),
        end=f(m.end, plane),
        center=None if m.center is None else f(m.center, plane),
        programmed_end=None if m.programmed_end is None else f(m.programmed_end, plane),
        plane=plane,
    )


# -- stage 2: cutter radius compensation -----------------------------------------------------


def compensate(items: list[Planned | Dwell | ToolChange], d: list[Diagnostic]) -> list[Command]:
    """Turn the programmed contour into the tool-centre path (G41/G42, G45–G48, G40)."""
    out: list[Command] = []
    pos: Vec3 | None = None  # where the tool centre is
    active = 0  # side of the running compensation
    planned = [(k, p) for k, p in enumerate(items) if isinstance(p, Planned)]
    order = {k: n for n, (k, _) in enumerate(planned)}

    def next_in_plane(k: int, side: int) -> Planned | None:
        for _, q in planned[order[k] + 1 :]:
            if q.side != side:
                return None
            if q.in_plane:
                return q
        return None

    def following(k: int, side: int) -> list[Element]:
        """The programmed contour elements after item `k` while the compensation `side` lasts (the first few)."""
        found: list[Element] = []
        for n in range(order[k] + 1, len(planned)):
            q = planned[n][1]
            if q.side != side or q.approach is not None or q.departure is not None or len(found) >= FOLLOWING:
                break
            if q.in_plane and q.move.kind != "rapid":
                found.append(element_of(q.move))
        return found

    for k, item in enumerate(items):
        if not isinstance(item, Planned):
            out.append(item)
            continue
        p, m = item, item.move
        start = pos if pos is not None else m.start
        if p.side == 0:
            if p.departure is not None:
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
            follow = following(k, p.side) if p.approach is None else []
            pos = _first_beside(p, start, element_of(nxt.move), r, follow, out, d)
            continue
        pos = _contour_element(p, start, r, next_in_plane(k, p.side), out, d)
    return out


def _first_beside(
    p: Planned,
    start: Vec3,
    first: Element,
    r: float,
    follow: list[Element],
    out: list[Command],
    d: list[Diagnostic],
) -> Vec3:
    """The first move after G41/G42 (`p`): G45's approach, or straight to the point beside the start of the
    first contour element (a warning when it cuts into the contour); where the tool centre is then."""
    m = p.move
    if p.approach is not None:
        return _approach(p, start, first, r, out)
    t = start_tangent(first)
    target = add((m.end[0], m.end[1]), left(t), r)
    end = (target[0], target[1], m.end[2])
    if _without_approach(m, start, target, t, r, follow):
        d.append(
            diag(
                "PAL-W222",
                m.span,
                command="G41" if p.side > 0 else "G42",
                tool_radius=p.radius,
                tool_radius_de=_fmt_de(p.radius),
            )
        )
    out.append(
        dataclasses.replace(
            m,
            kind="rapid" if m.kind == "rapid" else "feed",
            start=start,
            end=end,
            center=None,
            direction=None,
            radius=None,
            angle=None,
            programmed_end=m.end,
        )
    )
    return end


def _contour_element(
    p: Planned, start: Vec3, r: float, nxt: Planned | None, out: list[Command], d: list[Diagnostic]
) -> Vec3:
    """A contour element under compensation: its offset by the tool radius, ending where the next element's
    offset starts (inside corner) or followed by an arc about the corner (outside); where the tool centre is."""
    m = p.move
    e = element_of(m)
    o = offset(e, r)
    if o is None:
        if isinstance(e, Arc):
            smaller = e.radius < p.radius - 1e-9  # equal is not smaller: the offset arc vanishes
            d.append(
                diag(
                    "PAL-E214",
                    m.span,
                    radius=round(e.radius, 4),
                    tool_radius=p.radius,
                    relation="kleiner als" if smaller else "nicht größer als",
                    relation_en="smaller than" if smaller else "not larger than",
                )
            )
        else:
            d.append(diag("PAL-E215", m.span, tool_radius=p.radius))
        return m.end
    o = with_start(o, (start[0], start[1]))  # where the previous corner left the tool
    corner_arc: Element | None = None
    if nxt is not None:
        e2 = element_of(nxt.move)
        o2 = offset(e2, r)
        side_turn = turn(e, e2)
        if o2 is not None:
            if side_turn * p.side > 0:  # inside corner: end where the two offsets meet
                x = nearest([q for q in intersections(o, o2)], e.b)
                if x is None or math.dist(x, e.b) > 10 * abs(r) + 1e-6:
                    d.append(
                        diag(
                            "PAL-E217",
                            m.span,
                            tool_radius=p.radius,
                            first=m.span.line,
                            second=nxt.move.span.line,
                        )
                    )
                else:
                    o = with_end(o, x)
            elif side_turn != 0.0 or _reverses(e, e2):  # outside corner: an arc about the corner
                corner_arc = Arc(o.b, o2.a, e.b, cw=side_turn < 0 if side_turn != 0.0 else p.side > 0)
    if _reversed(e, o):
        d.append(diag("PAL-E215", m.span, tool_radius=p.radius))
    z1 = m.end[2]
    out.append(move_of(m, o, start[2], z1, programmed=m.end))
    if corner_arc is None:
        return (o.b[0], o.b[1], z1)
    out.append(move_of(m, corner_arc, z1, z1, programmed=m.end))
    return (corner_arc.b[0], corner_arc.b[1], z1)


# the approach check (PAL-W222) looks at the first few contour elements after the compensation is selected
FOLLOWING = 4
ALONG = math.sin(math.radians(20))  # a first move this close to the contour's direction runs along it
CROSSING = 1 / 8  # a tool centre this close to the contour (in cutter radii) has the cutter across it


def _without_approach(
    m: Move,
    start: Vec3,
    target: tuple[float, float],
    t: tuple[float, float],
    r: float,
    contour: list[Element],
) -> bool:
    """Whether the first move after G41/G42 (from the tool centre `start` to `target`, beside the contour's first
    point; `r` the signed radius, > 0 left) is no approach but already lies on the contour (PAL-W222).

    PAL selects the compensation with a move to a point in front of the contour, which the control approaches
    equidistantly (`G42 G0 X-14 Y10`). The move is no such approach when
    - it is an arc: an arc is a contour element (a circular approach is G47);
    - it runs in the direction of the contour's first element (within 20°) and does not start clear of the contour
      on the compensation side (a cutter radius or more): the tool travels along the contour while the
      compensation builds up;
    - the tool centre passes within an eighth of the cutter radius of the contour that follows: the cutter runs
      across the contour (the tool stood on the contour, e.g. on the element before the first one).
    """
    if m.kind == "arc":
        return True
    s, p1 = (start[0], start[1]), (m.end[0], m.end[1])
    length = math.dist(s, p1)
    if length < 1e-9:
        return False
    u = ((p1[0] - s[0]) / length, (p1[1] - s[1]) / length)
    side = 1.0 if r > 0 else -1.0
    clear = side * dot((s[0] - p1[0], s[1] - p1[1]), left(t))  # > 0: S on the compensation side
    if dot(u, t) > 0 and abs(cross(u, t)) < ALONG and clear < abs(r) - 1e-6:
        return True
    reach = abs(r) * CROSSING
    steps = 32
    for i in range(steps + 1):
        q = (s[0] + (target[0] - s[0]) * i / steps, s[1] + (target[1] - s[1]) * i / steps)
        if any(_distance(e, q) < reach - 1e-6 for e in contour):
            return True
    return False


def _distance(e: Element, p: tuple[float, float]) -> float:
    """The distance of `p` from the element `e` (a segment or an arc, its ends included)."""
    if isinstance(e, Line):
        dx, dy = e.b[0] - e.a[0], e.b[1] - e.a[1]
        n2 = dx * dx + dy * dy
        k = 0.0 if n2 < 1e-18 else max(0.0, min(1.0, ((p[0] - e.a[0]) * dx + (p[1] - e.a[1]) * dy) / n2))
        return math.hypot(p[0] - e.a[0] - k * dx, p[1] - e.a[1] - k * dy)
    ends = min(math.dist(p, e.a), math.dist(p, e.b))
    if math.dist(p, e.c) < 1e-9:
        return ends
    on_circle = add(e.c, ((p[0] - e.c[0]) / math.dist(p, e.c), (p[1] - e.c[1]) / math.dist(p, e.c)), e.radius)
    if e.full or on_element(e, on_circle):
        return min(ends, abs(math.dist(p, e.c) - e.radius))
    return ends


def _fmt_de(v: float) -> str:
    text = f"{v:.4f}".rstrip("0").rstrip(".")
    return text.replace(".", ",")


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
        out.append(
            dataclasses.replace(
                m,
                kind=kind,
                start=start,
                end=pos,
                center=None,
                direction=None,
                radius=None,
                angle=None,
                programmed_end=None,
            )
        )
    if a.w is not None and a.w != z:
        out.append(
            dataclasses.replace(
                m,
                kind="rapid",
                start=pos,
                end=(pos[0], pos[1], a.w),
                center=None,
                direction=None,
                radius=None,
                angle=None,
                programmed_end=None,
            )
        )
        pos = (pos[0], pos[1], a.w)
    if a.z is not None and a.z != pos[2]:
        feed = a.plunge_feed if a.plunge_feed is not None else m.feed
        out.append(
            dataclasses.replace(
                m,
                kind="feed",
                start=pos,
                end=(pos[0], pos[1], a.z),
                center=None,
                direction=None,
                radius=None,
                angle=None,
                feed=feed,
                programmed_end=None,
            )
        )
        pos = (pos[0], pos[1], a.z)
    feed_move = dataclasses.replace(m, kind="feed")
    out.append(move_of(feed_move, element, pos[2], pos[2], programmed=(p1[0], p1[1], pos[2])))
    return (target[0], target[1], pos[2])


def _depart(p: Planned, start: Vec3, side: int, out: list[Command]) -> Vec3:
    """G46/G48: leave the last contour point tangentially (if compensation `side` was on), then feed to Z
    and rapid to W."""
    m = p.move
    dep = p.departure
    assert dep is not None
    pos = start
    if side and dep.tangent is not None:
        t = dep.tangent
        here = (start[0], start[1])
        if dep.code == "G46":
            element: Element = Line(here, add(here, t, dep.size))
        else:  # a quarter circle on the compensation side, tangent at the last point
            centre = add(here, left(t), side * dep.size)
            element = Arc(here, add(centre, t, dep.size), centre, cw=side < 0)
        programmed = None if dep.programmed is None else (dep.programmed[0], dep.programmed[1], start[2])
        out.append(
            move_of(dataclasses.replace(m, kind="feed"), element, start[2], start[2], programmed=programmed)
        )
        pos = (element.b[0], element.b[1], start[2])
    if dep.z is not None and dep.z != pos[2]:
        out.append(
            dataclasses.replace(
                m,
                kind="feed",
                start=pos,
                end=(pos[0], pos[1], dep.z),
                center=None,
                direction=None,
                radius=None,
                angle=None,
                programmed_end=None,
            )
        )
        pos = (pos[0], pos[1], dep.z)
    if dep.w is not None and dep.w != pos[2]:
        out.append(
            dataclasses.replace(
                m,
                kind="rapid",
                start=pos,
                end=(pos[0], pos[1], dep.w),
                center=None,
                direction=None,
                radius=None,
                angle=None,
                programmed_end=None,
            )
        )
        pos = (pos[0], pos[1], dep.w)
    return pos


def finish(items: list[Item], d: list[Diagnostic]) -> list[Command]:
    """Both stages in order: transitions on the programmed contour, then compensation in each plane."""
    # the common case, no transition and no compensation: the moves as programmed, found in one pass
    as_programmed: list[Command] = []
    for p in items:
        if isinstance(p, Planned):
            if p.rn or p.side or p.departure:
                break
            as_programmed.append(p.move)
        elif isinstance(p, Blend):
            break
        else:
            as_programmed.append(p)
    else:
        return as_programmed
    contour = insert_transitions(items, d)
    out: list[Command] = []
    segment: list[Planned | Dwell | ToolChange] = []
    plane = "G17"
    for item in contour + [None]:
        if item is None or (isinstance(item, Planned) and item.move.plane != plane):
            if segment:  # compensation runs in the plane of its moves; a plane change ends a segment
                mapped = [
                    dataclasses.replace(q, move=to_plane_move(q.move, plane)) if isinstance(q, Planned) else q
                    for q in segment
                ]
                out += [
                    from_plane_move(c, plane) if isinstance(c, Move) else c for c in compensate(mapped, d)
                ]
            segment = []
            if item is None:
                break
            plane = item.move.plane
        if not isinstance(item, Blend):
            segment.append(item)
    return out
