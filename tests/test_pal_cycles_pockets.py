"""PAL milling cycles (issue 30): the pockets and slots G72–G75, their levels and paths, the simulated volume of
the part they make, and a property test of the rectangular pocket."""

from __future__ import annotations

import math

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from core.interpreter.state import RunSetup
from core.pipeline import run
from core.sim import Stock, simulate
from core.toolpath import Move, Toolpath
from core.tools import Tool, ToolTable
from tests.conftest import codes

STOCK = Stock(0, 0, -20, 100, 80, 0)  # 100 × 80 × 20, the pockets centred at X50 Y40
RESOLUTION = 0.2


def tools(diameter: float = 10.0) -> ToolTable:
    return ToolTable({1: Tool(1, "end_mill", diameter, cutting_length=40.0)})


def go(program: str, diameter: float = 10.0) -> Toolpath:
    ready = "N10 T1 TC1 M6\nN20 S1000 F100 M3\nN30 G0 X0 Y0 Z50\n"
    return run(ready + program + "\nN999 G0 Z100 M30\n", setup=RunSetup(tools=tools(diameter)))


def removed(tp: Toolpath, diameter: float = 10.0) -> float:
    result = simulate(tp, STOCK, tools(diameter), RESOLUTION)
    assert result.events == []
    return result.removed_volume


def cutting(tp: Toolpath) -> list[Move]:
    return [m for m in tp.moves if m.cycle is not None and m.kind != "rapid"]


def extent(moves: list[Move]) -> tuple[float, float, float, float]:
    pts = [p for m in moves for p in m.points(0.001)]
    return (min(p[0] for p in pts), max(p[0] for p in pts), min(p[1] for p in pts), max(p[1] for p in pts))


# -- G72 rectangular pocket -----------------------------------------------------------------------------------------


def test_g72_levels_spread_evenly_when_d_does_not_divide_the_depth() -> None:
    tp = go("N40 G72 ZI-5 LP40 BP30 RN8 D2 V2\nN50 G79 X50 Y40 Z0")
    assert codes(tp) == []
    moves = cutting(tp)
    # 5 mm at most 2 mm a level: three levels of 5/3 mm
    levels = sorted({round(m.end[2], 4) for m in moves}, reverse=True)
    assert levels == [-1.6667, -3.3333, -5.0]
    assert [m.cycle for m in moves if m.end[2] < m.start[2]] == [("G72", 1, 3), ("G72", 2, 3), ("G72", 3, 3)]
    # the tool centre reaches the wall less the tool radius: X50 ± (20 − 5), Y40 ± (15 − 5)
    assert extent(moves) == pytest.approx((35, 65, 30, 50), abs=1e-6)
    # the walls' corners: arcs of radius RN − tool radius = 3 counter-clockwise (climb milling)
    corners = [m for m in moves if m.kind == "arc" and m.radius == pytest.approx(3)]
    assert len(corners) == 4 * 3 and {m.direction for m in corners} == {"ccw"}
    assert removed(tp) == pytest.approx((40 * 30 - (4 - math.pi) * 8**2) * 5, rel=0.005)


def test_g72_rotated_by_ar_and_referred_to_its_corner_by_ep1() -> None:
    moves = cutting(go("N40 G72 ZI-2 LP40 BP20 D2 V2\nN50 G79 X50 Y40 Z0 AR90"))
    assert extent(moves) == pytest.approx((50 - 5, 50 + 5, 40 - 15, 40 + 15), abs=1e-6)
    moves = cutting(go("N40 G72 ZI-2 LP40 BP20 D2 V2 EP1\nN50 G79 X10 Y10 Z0"))
    assert extent(moves) == pytest.approx((10 + 5, 10 + 35, 10 + 5, 10 + 15), abs=1e-6)


def test_g72_taller_than_wide() -> None:
    tp = go("N40 G72 ZI-3 LP20 BP50 RN6 D3 V2\nN50 G79 X50 Y40 Z0")
    assert extent(cutting(tp)) == pytest.approx((45, 55, 20, 60), abs=1e-6)
    assert removed(tp) == pytest.approx((20 * 50 - (4 - math.pi) * 36) * 3, rel=0.005)


def test_g72_allowances_roughing_and_finishing() -> None:
    rough = cutting(go("N40 G72 ZI-4 LP40 BP30 D2 V2 AK1 AL0.5 H1\nN50 G79 X50 Y40 Z0"))
    assert min(m.end[2] for m in rough) == pytest.approx(-3.5)
    assert extent(rough) == pytest.approx((36, 64, 31, 49), abs=1e-6)
    both = go("N40 G72 ZI-4 LP40 BP30 D2 V2 AK1 AL0.5 H14\nN50 G79 X50 Y40 Z0")
    moves = cutting(both)
    finish = [m for m in moves if m.cycle and m.cycle[1] > 2]
    assert min(m.end[2] for m in finish) == pytest.approx(-4)
    assert extent(finish) == pytest.approx((35, 65, 30, 50), abs=1e-6)
    # roughing 2 levels, then the wall at -2 and the bottom at -4: four steps
    assert {m.cycle[2] for m in moves if m.cycle} == {4}
    assert removed(both) == pytest.approx((40 * 30 - (4 - math.pi) * 25) * 4, rel=0.005)


def test_g72_conventional_milling_and_helical_plunge() -> None:
    moves = cutting(go("N40 G72 ZI-2 LP40 BP30 RN8 D2 V2 Q2 O2\nN50 G79 X50 Y40 Z0"))
    corners = [m for m in moves if m.kind == "arc" and m.radius == pytest.approx(3)]
    assert corners and {m.direction for m in corners} == {"cw"}
    helix = [m for m in moves if m.kind == "arc" and m.end[2] < m.start[2]]
    assert len(helix) == 1 and helix[0].angle == 360 and helix[0].radius == pytest.approx(2.5)


def test_g72_diagnostics() -> None:
    tp = go("N40 G72 ZI-2 LP40 BP8 D2 V2\nN50 G79 X50 Y40 Z0")
    assert codes(tp) == [("PAL-E602", 5)]
    assert tp.diagnostics[0].message.endswith(
        "(Ø10 mm) ist zu groß für die Tasche mit der kleineren Seite 8 mm."
    )
    assert codes(go("N40 G72 ZI-2 LP40 BP30 RN3 D2 V2\nN50 G79 X50 Y40 Z0")) == [("PAL-W609", 5)]
    assert codes(go("N40 G72 ZI-2 LP40 BP30 AK11 D2 V2\nN50 G79 X50 Y40 Z0")) == [("PAL-E605", 5)]
    assert codes(go("N40 G72 ZI-2 LP40 BP30 AL2 D2 V2\nN50 G79 X50 Y40 Z0")) == [("PAL-E605", 5)]
    assert codes(go("N40 G72 ZI-2 LP40 BP30 AK-1 D2 V2")) == [("PAL-E604", 4)]
    assert codes(go("N40 G72 ZI-2 LP40 BP30 D2 V2 H2")) == [("PAL-E611", 4)]
    assert codes(go("N40 G72 ZI-2 LP40 BP30 RN16 D2 V2\nN50 G79 X50 Y40 Z0")) == [("PAL-E612", 5)]


# -- G73, G74, G75 --------------------------------------------------------------------------------------------------


def test_g73_circular_pocket() -> None:
    tp = go("N40 G73 ZI-3 R18 D1.5 V2\nN50 G79 X50 Y40 Z0")
    assert codes(tp) == []
    moves = cutting(tp)
    assert extent(moves) == pytest.approx((37, 63, 27, 53), abs=1e-3)
    assert removed(tp) == pytest.approx(math.pi * 18**2 * 3, rel=0.005)
    assert codes(go("N40 G73 ZI-3 R4 D1.5 V2\nN50 G79 X50 Y40 Z0")) == [("PAL-E602", 5)]


def test_g74_slot_with_the_round_ends_in_its_length() -> None:
    tp = go("N40 G74 ZI-4 LP50 BP16 D2 V2\nN50 G79 X50 Y40 Z0")
    assert codes(tp) == []
    assert extent(cutting(tp)) == pytest.approx((30, 70, 37, 43), abs=1e-3)
    assert removed(tp) == pytest.approx((50 * 16 - (4 - math.pi) * 64) * 4, rel=0.005)
    # a slot as wide as the tool: one pass along its centre line per level
    narrow = cutting(go("N40 G74 ZI-2 LP40 BP10 D2 V2 EP1\nN50 G79 X20 Y40 Z0"))
    assert extent(narrow) == pytest.approx((20, 50, 40, 40), abs=1e-6)


def test_g75_arc_slot() -> None:
    tp = go("N40 G75 ZI-2 BP12 RP25 AN0 AO90 D2 V2\nN50 G79 X30 Y20 Z0")
    assert codes(tp) == []
    moves = cutting(tp)
    for m in moves:  # every tool centre point within 1 mm (the width less the tool, halved) of the centre arc
        for p in m.points(0.001):
            a = math.atan2(p[1] - 20, p[0] - 30)
            r = math.hypot(p[0] - 30, p[1] - 20)
            if 0 <= a <= math.pi / 2:
                assert abs(r - 25) <= 1 + 1e-6
            else:
                ends = [(55, 20), (30, 45)]
                assert min(math.dist((p[0], p[1]), e) for e in ends) <= 1 + 1e-6
    area = math.pi / 2 * 25 * 12 + math.pi * 36
    assert removed(tp) == pytest.approx(area * 2, rel=0.005)
    assert codes(go("N40 G75 ZI-2 BP12 RP5 AN0 AO90 D2 V2\nN50 G79 X30 Y20 Z0")) == [("PAL-E612", 5)]


# -- the property: any G72 that fits stays in its outline and removes the nominal pocket --------------------------


@st.composite
def pockets(draw: st.DrawFn) -> tuple[float, float, float, float, float, float]:
    lp = draw(st.integers(24, 160)) / 4  # 6 … 40 mm
    bp = draw(st.integers(24, 120)) / 4
    diameter = (
        draw(st.integers(6, min(int(min(lp, bp) * 4), 64))) / 4
    )  # 1.5 … 16 mm, no wider than the pocket
    rn = draw(st.floats(diameter / 2, min(lp, bp) / 2))
    depth = draw(st.integers(2, 40)) / 4
    d = draw(st.integers(2, 24)) / 4
    return lp, bp, round(rn, 3), depth, d, diameter


@settings(max_examples=30, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(pockets())
def test_g72_stays_in_its_outline_and_removes_the_nominal_volume(case: tuple[float, ...]) -> None:
    lp, bp, rn, depth, d, diameter = case
    rt = diameter / 2
    tp = go(
        f"N40 G72 ZI-{depth:g} LP{lp:g} BP{bp:g} RN{max(rn, rt):g} D{d:g} V2\nN50 G79 X50 Y40 Z0", diameter
    )
    assert [c for c, _ in codes(tp)] == []
    rn = max(rn, rt)
    a, b, rc = lp / 2 - rt, bp / 2 - rt, rn - rt  # the outline shrunk by the tool radius
    tol = 1e-6
    for m in cutting(tp):
        for p in m.points(0.0005):
            dx, dy = abs(p[0] - 50), abs(p[1] - 40)
            assert dx <= a + tol and dy <= b + tol
            if dx > a - rc and dy > b - rc:
                assert math.hypot(dx - (a - rc), dy - (b - rc)) <= rc + 1e-3
            assert p[2] >= -depth - tol
    nominal = (lp * bp - (4 - math.pi) * rn**2) * depth
    # within the grid's accuracy: a band of one cell along the outline, over the depth
    assert abs(removed(tp, diameter) - nominal) <= 2 * (lp + bp) * RESOLUTION * depth + 0.001 * nominal


# -- the drilled part ---------------------------------------------------------------------------------------------


def test_holes_on_a_pitch_circle_remove_their_nominal_volume() -> None:
    drill = ToolTable({1: Tool(1, "twist_drill", 8.0, point_angle=118.0, cutting_length=40.0)})
    text = (
        "N10 T1 TC1 M6\nN20 S1000 F100 M3\nN30 G0 X0 Y0 Z50\nN40 G83 ZI-12 D5 V2\n"
        "N50 G77 IA50 JA40 R25 AN45 O4 Z0\nN60 G0 Z100 M30\n"
    )
    tp = run(text, setup=RunSetup(tools=drill))
    assert codes(tp) == []
    cone = 4 / math.tan(math.radians(59))
    hole = math.pi * 16 * (12 - cone) + math.pi * 16 * cone / 3
    result = simulate(tp, STOCK, drill, 0.1)
    assert result.events == []
    assert result.removed_volume == pytest.approx(4 * hole, rel=0.01)


def test_g87_bore_milled_hole_is_a_full_cylinder() -> None:
    tp = go("N40 G87 ZI-6 R9 D2 V1\nN50 G79 X50 Y40 Z0")
    assert codes(tp) == []
    assert removed(tp) == pytest.approx(math.pi * 81 * 6, rel=0.005)
