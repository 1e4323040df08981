"""Property: the tool centre of a G41/G42 path stays exactly one tool radius from the programmed contour.

Random star-shaped polygons (convex and not) and chains with arcs are milled around with G42 on a
counter-clockwise contour (tool outside). Distances are computed here independently of the
offset code, by exact point–segment and point–arc distances.
"""

from __future__ import annotations

import math

from hypothesis import assume, given, settings
from hypothesis import strategies as st

from core.pipeline import run

RADIUS = 3.0  # tool T7 of Ø6 below
Pt = tuple[float, float]


def seg_distance(p: Pt, a: Pt, b: Pt) -> float:
    dx, dy = b[0] - a[0], b[1] - a[1]
    t = max(0.0, min(1.0, ((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / (dx * dx + dy * dy)))
    return math.dist(p, (a[0] + t * dx, a[1] + t * dy))


def arc_distance(p: Pt, a: Pt, b: Pt, c: Pt, ccw: bool) -> float:
    r = math.dist(a, c)
    a0 = math.atan2(a[1] - c[1], a[0] - c[0])
    a1 = math.atan2(b[1] - c[1], b[0] - c[0])
    ap = math.atan2(p[1] - c[1], p[0] - c[0])
    span = (a1 - a0) % (2 * math.pi) if ccw else (a0 - a1) % (2 * math.pi)
    rel = (ap - a0) % (2 * math.pi) if ccw else (a0 - ap) % (2 * math.pi)
    if rel <= span:
        return abs(math.dist(p, c) - r)
    return min(math.dist(p, a), math.dist(p, b))


def inside(p: Pt, poly: list[Pt]) -> bool:
    hit = False
    for (x1, y1), (x2, y2) in zip(poly, poly[1:] + poly[:1], strict=True):
        if (y1 > p[1]) != (y2 > p[1]) and p[0] < x1 + (p[1] - y1) * (x2 - x1) / (y2 - y1):
            hit = not hit
    return hit


def samples(m: object) -> list[Pt]:
    """Points along a move: 25 per element, arcs by angle."""
    start, end = m.start, m.end  # type: ignore[attr-defined]
    if m.kind != "arc":  # type: ignore[attr-defined]
        return [
            (start[0] + (end[0] - start[0]) * k / 24, start[1] + (end[1] - start[1]) * k / 24)
            for k in range(25)
        ]
    c, r = m.center, m.radius  # type: ignore[attr-defined]
    a0 = math.atan2(start[1] - c[1], start[0] - c[0])
    sweep = math.radians(m.angle) * (-1 if m.direction == "cw" else 1)  # type: ignore[attr-defined]
    return [
        (c[0] + r * math.cos(a0 + sweep * k / 24), c[1] + r * math.sin(a0 + sweep * k / 24))
        for k in range(25)
    ]


@st.composite
def star_polygons(draw: st.DrawFn) -> list[Pt]:
    n = draw(st.integers(min_value=3, max_value=9))
    gaps = draw(st.lists(st.floats(min_value=1.0, max_value=3.0), min_size=n, max_size=n))
    radii = draw(st.lists(st.floats(min_value=25.0, max_value=60.0), min_size=n, max_size=n))
    total = sum(gaps)
    angle, pts = 0.0, []
    for g, r in zip(gaps, radii, strict=True):
        pts.append((r * math.cos(angle), r * math.sin(angle)))
        angle += 2 * math.pi * g / total
    return pts


def _program(body: list[str], start: Pt) -> str:
    head = ["T7 M6", "S2000 F300 M3", f"G0 X{start[0] + 40:.4f} Y{start[1] - 40:.4f} Z2", "G0 Z-2"]
    return "\n".join(head + body + ["G40 G0 X200 Y200", "M30"]) + "\n"


def _check(text: str, distance: object, poly: list[Pt]) -> None:
    from core.interpreter.state import RunSetup
    from core.tools import DEFAULT_TOOLS, Tool

    tp = run(text, setup=RunSetup(tools=DEFAULT_TOOLS.with_tool(Tool(7, "end_mill", 2 * RADIUS))))
    assume(not any(d.severity.value == "error" for d in tp.diagnostics))
    contour_moves = [m for m in tp.moves if m.kind != "rapid" and m.line > 5]  # after the G42 positioning
    assert contour_moves
    for m in contour_moves:
        for p in samples(m):
            assert abs(distance(p) - RADIUS) < 1e-6, (m, p, distance(p))  # type: ignore[operator]
            assert not inside(p, poly)


@settings(max_examples=60, deadline=None)
@given(star_polygons())
def test_polygon_offset_keeps_the_tool_radius(poly: list[Pt]) -> None:
    # start at the vertex with the largest X: always a convex corner
    k = max(range(len(poly)), key=lambda i: poly[i][0])
    ring = poly[k:] + poly[:k]
    body = [f"G42 G1 X{ring[0][0]:.4f} Y{ring[0][1]:.4f}"]
    body += [f"G1 X{x:.4f} Y{y:.4f}" for x, y in ring[1:] + ring[:1]]
    exact = [(round(x, 4), round(y, 4)) for x, y in ring]

    def distance(p: Pt) -> float:
        return min(seg_distance(p, a, b) for a, b in zip(exact, exact[1:] + exact[:1], strict=True))

    _check(_program(body, ring[0]), distance, exact)


@settings(max_examples=40, deadline=None)
@given(star_polygons(), st.lists(st.booleans(), min_size=9, max_size=9))
def test_chain_with_outward_arcs_keeps_the_tool_radius(poly: list[Pt], bulges: list[bool]) -> None:
    k = max(range(len(poly)), key=lambda i: poly[i][0])
    ring = [(round(x, 4), round(y, 4)) for x, y in poly[k:] + poly[:k]]
    body = [f"G42 G1 X{ring[0][0]} Y{ring[0][1]}"]
    pieces: list[tuple[Pt, Pt, Pt | None]] = []
    last = len(ring) - 1
    for i, (a, b) in enumerate(zip(ring, ring[1:] + ring[:1], strict=True)):
        if bulges[i] and 0 < i < last:  # the chain starts and ends with lines at the convex start vertex
            # an outward bulge: centred inside the polygon, run counter-clockwise like the polygon
            chord = math.dist(a, b)
            mx, my = (a[0] + b[0]) / 2, (a[1] + b[1]) / 2
            nx, ny = (b[1] - a[1]) / chord, -(b[0] - a[0]) / chord  # right normal = outward
            h = math.sqrt(chord**2 - (chord / 2) ** 2)
            c = (mx - nx * h, my - ny * h)  # centre inside: the arc bulges outward
            body.append(f"G3 X{b[0]} Y{b[1]} IA{c[0]:.9f} JA{c[1]:.9f}")
            pieces.append((a, b, c))
        else:
            body.append(f"G1 X{b[0]} Y{b[1]}")
            pieces.append((a, b, None))

    def distance(p: Pt) -> float:
        return min(
            seg_distance(p, a, b) if c is None else arc_distance(p, a, b, c, ccw=True) for a, b, c in pieces
        )

    outline = [q for a, b, c in pieces for q in ([a] if c is None else _arc_points(a, b, c))]
    _check(_program(body, ring[0]), distance, outline)


def _arc_points(a: Pt, b: Pt, c: Pt) -> list[Pt]:
    a0 = math.atan2(a[1] - c[1], a[0] - c[0])
    a1 = math.atan2(b[1] - c[1], b[0] - c[0])
    sweep = (a1 - a0) % (2 * math.pi)
    r = math.dist(a, c)
    return [
        (c[0] + r * math.cos(a0 + sweep * k / 16), c[1] + r * math.sin(a0 + sweep * k / 16))
        for k in range(16)
    ]
