"""Plane geometry on its own: roundings and chamfers between lines and arcs, offsets, arc solutions.

Expected numbers are worked out by hand (circle intersections written out in the comments).
"""

from __future__ import annotations

import math

import pytest

from core.geometry.arcs import arc_solutions, choose_arc
from core.geometry.elements import Arc, Line, chamfer, offset, rounding


def test_rounding_line_line() -> None:
    t = rounding(Line((-14, 10), (70, 10)), Line((70, 10), (70, 84)), 20)
    assert t is not None and isinstance(t.inserted, Arc)
    assert t.inserted.a == pytest.approx((50, 10)) and t.inserted.b == pytest.approx((70, 30))
    assert t.inserted.c == pytest.approx((50, 30)) and not t.inserted.cw


def test_rounding_arc_line() -> None:
    # arc about X0 Y0, R10, ccw to X0 Y10, then up along X0: a right turn. Fillet R2 on the right:
    # its centre lies on the circle R12 and on the line X2 → Y = √(144 − 4)
    cy = math.sqrt(140)
    t = rounding(Arc((10, 0), (0, 10), (0, 0), cw=False), Line((0, 10), (0, 30)), 2)
    assert t is not None and isinstance(t.inserted, Arc)
    assert t.inserted.c == pytest.approx((2, cy))
    assert t.inserted.a == pytest.approx((10 * 2 / 12, 10 * cy / 12))
    assert t.inserted.b == pytest.approx((0, cy)) and t.inserted.cw


def test_rounding_arc_arc() -> None:
    # second arc cw about X10 Y10 from X0 Y10; fillet R2: centre on circles R12 about X0 Y0 and R8
    # about X10 Y10: d = √200, a = (144 − 64 + 200)/(2d), h = √(144 − a²), nearer the corner X0 Y10
    d = math.sqrt(200)
    a = 280 / (2 * d)
    h = math.sqrt(144 - a * a)
    centre = (a / d * 10 - h * 10 / d, a / d * 10 + h * 10 / d)
    t = rounding(Arc((10, 0), (0, 10), (0, 0), cw=False), Arc((0, 10), (10, 20), (10, 10), cw=True), 2)
    assert t is not None and isinstance(t.inserted, Arc)
    assert t.inserted.c == pytest.approx(centre)
    assert t.inserted.a == pytest.approx((centre[0] * 10 / 12, centre[1] * 10 / 12))
    assert t.inserted.b == pytest.approx((10 + (centre[0] - 10) * 10 / 8, 10 + (centre[1] - 10) * 10 / 8))


def test_chamfer_on_an_arc_uses_the_secant() -> None:
    # arc cw about X20 Y0 from X10 Y0 (heading +Y): the chamfer end lies on the circle R5 about the
    # corner and on the arc: d = 10, a = (25 − 100 + 100)/20 = 1.25, h = √(25 − 1.25²)
    t = chamfer(Line((0, 0), (10, 0)), Arc((10, 0), (20, 10), (20, 0), cw=True), 5)
    assert t is not None
    assert t.inserted.a == pytest.approx((5, 0))
    assert t.inserted.b == pytest.approx((11.25, math.sqrt(25 - 1.25**2)))


def test_rounding_that_does_not_fit() -> None:
    assert rounding(Line((0, 0), (5, 0)), Line((5, 0), (5, 5)), 10) is None
    assert rounding(Line((0, 0), (5, 0)), Line((5, 0), (10, 0)), 1) is None  # tangent: nothing to round


def test_offset_of_arcs() -> None:
    ccw = Arc((10, 0), (0, 10), (0, 0), cw=False)
    left = offset(ccw, 2)
    assert isinstance(left, Arc) and left.radius == pytest.approx(8)
    right = offset(ccw, -2)
    assert isinstance(right, Arc) and right.radius == pytest.approx(12)
    assert offset(ccw, 10) is None  # vanishes


def test_arc_with_two_solutions_of_different_length() -> None:
    sols = arc_solutions((0, 0), True, ex=10, ey=0, r=5)
    assert len(sols) == 1  # a half circle: the only centre is the midpoint
    sols = arc_solutions((0, 0), True, ex=10, ey=0, r=10)
    assert len(sols) == 2
    short = choose_arc((0, 0), True, sols, longer=False, h2=False)
    long = choose_arc((0, 0), True, sols, longer=True, h2=False)
    assert short is not None and long is not None
    # clockwise from X0 to X10 the shorter arc bulges up: its centre is below
    assert short[0][1] < 0 < long[0][1]
