"""Arcs the DIN 66025 / ISO way (SINUMERIK 808D ISO, Beckhoff TwinCAT), in the coordinates (u, v) of their plane.

PAL reads a missing arc word as unknown and solves for it (core/interpreter/pal_mill.py `_arc`). A DIN/ISO
control does not: an omitted end-point axis is the current position under G90 and 0 under G91 (the end point
arrives here complete), an omitted centre offset I/J/K is 0 (shared/spec/iso-808d-arcs.md §2; Beckhoff
"Circular interpolation (G02/G03)": "The I,J,K parameters are optional and have 0 value by default"). The end
point must then lie on the circle about the programmed centre, as the control checks:

- SINUMERIK: start and end radius may differ by max(RunSetup.arc_tolerance, 0.1 % of the radius) (machine data
  CIRCLE_ERROR_CONST 0.01 mm and CIRCLE_ERROR_FACTOR 0.001), else the circle end point error (PAL-E202);
- Beckhoff with G165 (centre point correction, the switch-on state): the centre moves onto the perpendicular
  bisector of start and end point, at most min(2 mm, 5 % of the radius) (P-CHAN-00059 = 20000 × 0.1 µm,
  P-CHAN-00060 = 50 × 0.1 %), a warning when it moves (BK-W202), an error beyond (BK-E203); with G164 the radii
  may differ by max(0.005 mm, 0.01 % of the radius) (P-CHAN-00171/00172), else PAL-E202.

R programs the radius (R+ at most 180°, R- the longer arc, DECISIONS §13); an end point equal to the start is a
full circle with a centre and impossible with R.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from core.diagnostics import Diagnostic, diag
from core.geometry.arcs import centres_from_radius, sweep
from core.syntax.blocks import Span, Word

Point = tuple[float, float]

BECKHOFF_SHIFT = 2.0  # mm, P-CHAN-00059 default 20000 × 0.1 µm
BECKHOFF_SHIFT_FACTOR = 0.05  # P-CHAN-00060 default 50 × 0.1 %
BECKHOFF_RADIUS_DIFF = 0.005  # mm, P-CHAN-00171 default 50 × 0.1 µm (G164)
BECKHOFF_RADIUS_FACTOR = 0.0001  # P-CHAN-00172 default 0.1 × 0.1 % (G164)


@dataclass(frozen=True, slots=True)
class ArcRules:
    """How a dialect checks an arc programmed with its centre."""

    tolerance: float  # mm: start and end radius may differ this much …
    factor: float = 0.0  # … or this fraction of the radius, whichever is larger
    correction: bool = False  # Beckhoff G165: move the centre onto the arc instead (within its limits)


def din_arc(
    start: Point,
    end: Point,
    centre: Point | None,
    radius_word: Word | None,
    radius: float | None,
    clockwise: bool,
    rules: ArcRules,
    span: Span,
    d: list[Diagnostic],
) -> tuple[Point, Point, float] | None:
    """Centre, end and radius of an arc from `start` to `end` (complete: omitted axes already filled in) about
    `centre` (omitted offsets already 0) or with `radius` (signed as written; `radius_word` the R word, None for
    Beckhoff's kept radius); None after an error diagnostic."""
    if centre is not None:
        r_s, r_e = math.dist(start, centre), math.dist(end, centre)
        if r_s < 1e-6:
            d.append(diag("PAL-E206", span))
            return None
        if math.dist(start, end) < 1e-6:
            return centre, end, r_s  # a full circle
        allowed = max(rules.tolerance, rules.factor * r_s)
        if abs(r_s - r_e) <= allowed:
            return centre, end, r_s
        if rules.correction:
            return _corrected(start, end, centre, r_s, r_e, span, d)
        d.append(
            diag("PAL-E202", span, r_start=round(r_s, 4), r_end=round(r_e, 4), tolerance=round(allowed, 4))
        )
        return None
    assert radius is not None
    where = radius_word.span if radius_word is not None else span
    chord = math.dist(start, end)
    if chord < 1e-6:
        d.append(diag("PAL-E205", where))
        return None
    size = abs(radius)
    if size < chord / 2 and chord / 2 - size <= max(rules.tolerance, rules.factor * size):
        size = chord / 2  # a radius rounded down by the program: the half circle
    candidates = centres_from_radius(start, end, size)
    if not candidates:
        d.append(
            diag(
                "PAL-E201",
                where,
                reason=f"Radius {size:g} mm ist kleiner als die halbe Sehne {chord / 2:.3f} mm",
                reason_en=f"radius {size:g} mm is less than half the chord {chord / 2:.3f} mm",
            )
        )
        return None
    longer = radius < 0
    c = (max if longer else min)(candidates, key=lambda p: sweep(start, end, p, clockwise))
    return c, end, size


def _corrected(
    start: Point, end: Point, centre: Point, r_s: float, r_e: float, span: Span, d: list[Diagnostic]
) -> tuple[Point, Point, float] | None:
    """Beckhoff G165: the nearest centre on the perpendicular bisector of start and end, if it moves little enough."""
    dx, dy = end[0] - start[0], end[1] - start[1]
    mid = ((start[0] + end[0]) / 2, (start[1] + end[1]) / 2)
    n2 = dx * dx + dy * dy
    k = ((centre[0] - mid[0]) * dx + (centre[1] - mid[1]) * dy) / n2  # along the chord: what must go
    moved = (centre[0] - k * dx, centre[1] - k * dy)
    shift = math.dist(centre, moved)
    radius = math.dist(start, moved)
    limit = min(BECKHOFF_SHIFT, BECKHOFF_SHIFT_FACTOR * radius)
    if shift > limit:
        d.append(
            diag(
                "BK-E203",
                span,
                shift=round(shift, 4),
                limit=round(limit, 4),
                r_start=round(r_s, 4),
                r_end=round(r_e, 4),
            )
        )
        return None
    d.append(diag("BK-W202", span, shift=round(shift, 4), r_start=round(r_s, 4), r_end=round(r_e, 4)))
    return moved, end, radius


def beckhoff_rules(correction_on: bool, tolerance: float) -> ArcRules:
    """Beckhoff's check: G165 corrects the centre (after the usual tolerance), G164 allows a small radius difference."""
    if correction_on:
        return ArcRules(tolerance, 0.0, True)
    return ArcRules(BECKHOFF_RADIUS_DIFF, BECKHOFF_RADIUS_FACTOR)
