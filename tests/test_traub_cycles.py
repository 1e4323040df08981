"""TRAUB TX 8 D cycles (spec §11–§12, DECISIONS 20, examples TX-30…TX-42): number of passes, where the first and
the last cutting pass start and end, diagnostics for trainees' mistakes, and properties of the roughing passes.

Moves are [x radius, 0, z]; the helpers report X as a diameter as the program writes it.
"""

from __future__ import annotations

import itertools
import math
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from core.interpreter.state import RunSetup
from core.pipeline import run
from core.sim import parse_tool_table
from core.sim.turning import Blank, simulate_turning
from core.toolpath import Move, Toolpath
from core.tools import ToolTable, turning_tool
from tests.conftest import codes

SEEDS = Path(__file__).with_name("seeds") / "traub"
TOL = 1e-3
READY = "G97 S800 T101 M4\n"


def traub(text: str) -> Toolpath:
    return run(text, "traub-tx8d")


def seed_text(name: str) -> str:
    return (SEEDS / name).read_text(encoding="utf-8")


def seed(name: str) -> Toolpath:
    return traub(seed_text(name))


def xz(p: tuple[float, float, float]) -> tuple[float, float]:
    return (round(2 * p[0], 3), round(p[2], 3))


def cuts(tp: Toolpath, line: int) -> list[Move]:
    """The feed moves made by the cycle block in `line`."""
    return [m for m in tp.moves if m.line == line and m.kind == "feed"]


def passes(tp: Toolpath, line: int) -> int:
    tags = {m.cycle for m in tp.moves if m.line == line}
    assert len({t[2] for t in tags if t is not None}) == 1, tags
    return next(t[2] for t in tags if t is not None)


def first_of_pass(tp: Toolpath, line: int, n: int) -> list[Move]:
    return [m for m in cuts(tp, line) if m.cycle is not None and m.cycle[1] == n]


# -- the manual's examples --------------------------------------------------------------------------


EXPECTED: dict[str, list[tuple[str, int]]] = {
    "tx-29-g70.nc": [("TX-W419", 4), ("TX-W418", 4)],  # 0.05 mm left by the full D; J not in the text
    "tx-30-g71-g88.nc": [],
    "tx-31-g71-g89.nc": [],
    "tx-32-g72-g88.nc": [],
    "tx-33-g72-unterprogramm.nc": [("TX-W103", 26)],  # O520 as printed: below the usual 8000
    "tx-34-g73.nc": [("TX-E1901", 3)],  # G73: its format line and example page are lost
    "tx-35-g74.nc": [],
    "tx-36-g75.nc": [],
    "tx-37-g83.nc": [],
    "tx-38-g84.nc": [],
    "tx-39-g33.nc": [],
    "tx-40-g76.nc": [("TX-W421", 14)],  # M35: the run-out is set-up data, not drawn
    "tx-41-g78-g81.nc": [],
    "tx-42-g82.nc": [],
}


@pytest.mark.parametrize("name", sorted(EXPECTED))
def test_cycle_example_gives_exactly_its_diagnostics(name: str) -> None:
    assert codes(seed(name)) == EXPECTED[name]


def test_tx29_g70_cuts_with_the_full_depth() -> None:
    tp = seed("tx-29-g70.nc")
    # (90 − 25)/2 − I0.8 = 31.7 mm: five full cuts of 6.33 (DECISIONS 20: D and I radial), 0.05 mm left
    assert passes(tp, 4) == 5
    levels = [xz(m.end)[0] for m in cuts(tp, 4)]
    assert levels == [77.34, 64.68, 52.02, 39.36, 26.7]
    assert xz(cuts(tp, 4)[-1].end) == (26.7, -39.9)  # the undercut X24.4 at Z-36.52…-40 stays (G89)
    assert (24.4, -36.52) in {xz(m.end) for m in tp.moves if m.line == 11}  # the finishing contour as printed


def test_tx34_g73_finishing_contour_corners_and_not_supported_cycle() -> None:
    tp = seed("tx-34-g73.nc")
    assert not [m for m in tp.moves if m.line == 3]
    ends = {xz(m.end) for m in tp.moves}
    assert (25.0, -29.497) in ends


def test_g86_face_thread_infeeds_in_z() -> None:
    tp = traub(READY.replace("M4", "M3") + "G0 X50 Z5\nG86 X10 Z-2 K1 H3 F2\nM30")
    threads = [m for m in tp.moves if m.thread]
    assert len(threads) == 3 and passes(tp, 3) == 3
    assert (xz(threads[-1].start), xz(threads[-1].end)) == ((50.0, -2.0), (10.0, -2.0))
    assert xz(threads[0].end)[1] == pytest.approx(-2 + 1 - math.sqrt(1 / 2), abs=TOL)


def test_tx30_g71_passes_at_start_minus_depth_spread_evenly_and_g88_follows_the_falling_cone() -> None:
    tp = seed("tx-30-g71-g88.nc")
    # stock: radius 50 − (13 + I0.5) = 36.5 mm, D4 → ceil(9.125) = 10 passes of 3.65 mm
    assert passes(tp, 5) == 10
    first, last = first_of_pass(tp, 5, 1), first_of_pass(tp, 5, 10)
    assert (xz(first[0].start), xz(first[0].end)) == ((92.7, 2.0), (92.7, -119.95))  # Z-120 + K0.05
    assert (xz(last[0].start), xz(last[0].end)) == ((27.0, 2.0), (27.0, 0.55))  # X26 + 2·I, Z0.5 + K
    # … then on the contour + allowance: the chamfer, Ø30 + 2·I, up the shoulder to the level of pass 9
    assert [xz(m.end) for m in last[1:]] == [(28.0, 0.55), (31.0, -0.95), (31.0, -14.95), (34.3, -14.95)]
    for n in range(1, 11):  # every pass starts with one feed from the start Z
        assert xz(first_of_pass(tp, 5, n)[0].start)[1] == 2.0
    falling = [m for m in cuts(tp, 5) if m.feed == pytest.approx(0.12)]
    assert falling, "G88: the falling cone X65 → X38 is roughed with the reduced feed E0.12"
    assert min(xz(m.end)[1] for m in falling) < -45
    assert all(m.kind == "rapid" for m in tp.moves if m.line == 5 and m not in cuts(tp, 5))
    assert xz(tp.moves[[m.line for m in tp.moves].index(6) - 1].end) == (
        100.0,
        2.0,
    )  # back at the start point


def test_tx31_g71_inside_with_g89_skips_the_undercut() -> None:
    tp = seed("tx-31-g71-g89.nc")
    # inner: from the bore X30 out to X120 − 2·I0.5 = X119 → 44.5 mm radial at D3.5 → 13 passes
    assert passes(tp, 5) == 13
    first, last = first_of_pass(tp, 5, 1), first_of_pass(tp, 5, 13)
    assert xz(first[0].start) == (36.846, 2.0) and xz(first[0].end) == (36.846, -74.95)
    assert [xz(m.end) for m in first[1:]] == [(30.0, -74.95)]  # up the face Z-75 + K to the start X30
    assert (xz(last[0].start), xz(last[0].end)) == (
        (119.0, 2.0),
        (119.0, 0.05),
    )  # along X120 − 2·I to the face
    # the undercut U0.3 A150 at Z-62…-62.52 (X60…X60.6) is never entered
    assert not [m for m in cuts(tp, 5) if 2 * m.end[0] > 59.5 and m.end[2] < -62.0]


def test_tx32_g72_facing_levels_in_z() -> None:
    tp = seed("tx-32-g72-g88.nc")
    # Z1 − (Z-35 + K0.5) = 35.5 at D3.5 → 11 passes of 3.2273
    assert passes(tp, 5) == 11
    first, last = first_of_pass(tp, 5, 1), first_of_pass(tp, 5, 11)
    assert (xz(first[0].start), xz(first[0].end)) == ((145.0, -2.227), (25.2, -2.227))  # X25 + 2·I0.1
    assert (xz(last[0].start), xz(last[0].end)) == ((145.0, -34.5), (120.2, -34.5))  # in the R10 rounding
    assert [m for m in cuts(tp, 5) if m.feed == pytest.approx(0.1)], "G88: the cone Z-8 → Z-16 is followed"


O520_ALONE = """G0 X30 Z2
G22 A520
M30
%
O520
G46
G0 X33 Z-40
G1 X85.6 R0,6 F0.2
G1 A0
G1 X85 Z-37 A150
G1 Z-25
G1 A90
G1 X110 Z-12 A220
G1 X140
G1 Z0 R3
G1 X150
G40
M99
%
"""


def test_tx33_contour_in_a_subprogram_and_the_two_contours_coincide() -> None:
    tp = seed("tx-33-g72-unterprogramm.nc")
    # Z2 − (Z-40 + K0.05) = 41.95 at D3.5 → 12 passes
    assert passes(tp, 5) == 12
    first, last = first_of_pass(tp, 5, 1), first_of_pass(tp, 5, 12)
    assert (xz(first[0].start), xz(first[0].end)) == ((30.0, -1.496), (139.767, -1.496))  # in the R3 rounding
    assert (xz(last[0].start), xz(last[0].end)) == ((30.0, -39.95), (83.4, -39.95))  # along the face to R0.6
    finishing = {xz(m.end) for m in tp.moves if 10 <= m.line <= 20}
    rough = traub(O520_ALONE)
    corners = [xz(m.end) for m in rough.moves if m.kind != "rapid"][
        :-1
    ]  # without X150, where finishing starts
    assert (88.183, -25.0) in corners and (85.6, -37.52) in corners
    assert set(corners) <= finishing | {xz(m.start) for m in tp.moves if 10 <= m.line <= 20}


def test_tx35_g74_interrupted_uninterrupted_face_groove_and_drilling() -> None:
    tp = seed("tx-35-g74.nc")
    assert passes(tp, 4) == 4  # radial 20 mm, I5
    one = first_of_pass(tp, 4, 1)
    assert [xz(m.end) for m in one] == [(60.0, z) for z in (-7.0, -15.0, -23.0, -31.0, -39.0, -47.0, -50.0)]
    assert xz(one[1].start) == (60.0, -6.5)  # backed off 0.5 mm between the cuts
    assert [xz(m.end) for m in cuts(tp, 9)] == [(x, -50.0) for x in (60.0, 50.0, 40.0, 30.0)]  # K51: no break
    assert passes(tp, 14) == 3  # X62 → X40 with I3.7: 11 mm radial in 3 passes of 3.667
    assert [xz(m.end)[0] for m in cuts(tp, 14)] == [54.667, 47.333, 40.0]
    after = [m for m in tp.moves if m.line == 14 and m.kind == "rapid"]
    first_return = next(m for m in after if m.cycle is not None and m.cycle[1] == 1 and m.end[2] > m.start[2])
    assert xz(first_return.end)[0] == 54.667  # D-0.3: no lift on the first cut
    second_return = next(
        m for m in after if m.cycle is not None and m.cycle[1] == 2 and m.end[2] > m.start[2]
    )
    assert xz(second_return.end)[0] == pytest.approx(47.333 + 0.6, abs=TOL)
    assert [xz(m.end) for m in cuts(tp, 19)] == [(0.0, -8.0), (0.0, -18.0), (0.0, -28.0), (0.0, -38.0)]


def test_tx36_g75_uneven_depth_grooving_and_cross_drilling() -> None:
    tp = seed("tx-36-g75.nc")
    assert passes(tp, 4) == 6  # Z-3 → Z-20 with K3: 17 mm in 6 passes of 2.8333
    levels = sorted({xz(m.end)[1] for m in cuts(tp, 4)}, reverse=True)
    assert levels == [-5.833, -8.667, -11.5, -14.333, -17.167, -20.0]
    assert [xz(m.end)[0] for m in first_of_pass(tp, 4, 1)] == [56.0, 40.0, 25.0]  # I8 radial breaks
    assert len(first_of_pass(tp, 9, 1)) == 1  # I23.5 = (72 − 25)/2: no interruption
    assert passes(tp, 14) == 5 and xz(cuts(tp, 14)[0].end) == (40.0, -22.2)
    assert [xz(m.end) for m in cuts(tp, 20)] == [(32.0, -25.0), (20.0, -25.0)]  # U-21 from X62, I15


def test_tx37_g83_first_depth_then_h_equal_sections() -> None:
    tp = seed("tx-37-g83.nc")
    assert [xz(m.end)[1] for m in cuts(tp, 3)] == [-30.0, -50.0, -70.0, -90.0]
    assert passes(tp, 3) == 4
    rapids = [xz(m.end)[1] for m in tp.moves if m.line == 3 and m.kind == "rapid"]
    assert rapids[:2] == [5.0, -29.5]  # out to the start, back in to the safety distance


def test_tx38_g84_rapid_distance_first_and_further_depths() -> None:
    tp = seed("tx-38-g84.nc")
    cycle = [m for m in tp.moves if m.line == 9]
    assert cycle[0].kind == "rapid" and xz(cycle[0].end) == (0.0, -14.0)
    assert [xz(m.end)[1] for m in cuts(tp, 9)] == [-27.0, -37.0, -47.0, -52.0]
    assert (
        len([d for d in tp.dwells if d.span.line == 9]) == 4 + 3
    )  # Q after each depth, R after each retraction


def test_tx39_g33_pitch_is_modal() -> None:
    tp = seed("tx-39-g33.nc")
    threads = [m for m in tp.moves if m.thread]
    assert [xz(m.end) for m in threads] == [(29.2, -29.5), (28.8, -29.5), (28.16, -29.5)]
    assert [m.pitch for m in threads] == [1.5, 1.5, 1.5] and all(m.kind == "feed" for m in threads)


def test_tx40_g76_constant_chip_area_and_taper() -> None:
    tp = seed("tx-40-g76.nc")
    one = [m for m in tp.moves if m.line == 4 and m.thread]
    assert len(one) == 8 and passes(tp, 4) == 8
    k = 0.92
    assert 2 * one[0].end[0] == pytest.approx(33.1 + 2 * (k - k * math.sqrt(1 / 7)), abs=TOL)
    assert xz(one[-1].end) == (33.1, -29.0) and one[-1].pitch == 1.5
    two = [m for m in tp.moves if m.line == 9 and m.thread]  # start X20 < X24: an inner thread
    assert len(two) == 7 and xz(two[-1].end) == (24.0, -24.0) and two[0].end[0] < two[-1].end[0]
    three = [m for m in tp.moves if m.line == 14 and m.thread]
    assert len(three) == 10
    assert (xz(three[-1].start), xz(three[-1].end)) == ((29.268, 6.0), (30.836, -19.1))  # J1.789: 1:16 on X


def test_tx41_g78_with_g81_splits_the_last_infeed() -> None:
    tp = seed("tx-41-g78-g81.nc")
    threads = [m for m in tp.moves if m.thread]
    diameters = [xz(m.end)[0] for m in threads]
    assert diameters[0] == 19.5 and diameters[-1] == 15.5  # 19.5 − 2·10·0.2: core of Tr 20 × 4
    assert diameters[-5:] == [15.9, 15.7, 15.6, 15.55, 15.5]  # U/2, U/4, U/8, U/8
    assert all(m.pitch == 4 for m in threads)


def test_tx42_g82_taps_in_and_back_out_with_the_spindle_reversed() -> None:
    tp = seed("tx-42-g82.nc")
    taps = [m for m in tp.moves if m.line == 3]
    assert [(xz(m.end), m.thread, m.pitch) for m in taps] == [
        ((0.0, -10.0), True, 1.0),
        ((0.0, 3.0), True, 1.0),
    ]
    assert taps[0].spindle_direction == "cw" and taps[1].spindle_direction == "ccw"


def test_cycle_moves_carry_the_cycle_in_json() -> None:
    tp = seed("tx-42-g82.nc")
    data = next(m for m in tp.moves if m.line == 3).to_json()
    assert data["cycle"] == {"code": "G82", "pass": 1, "of": 1}
    assert data["thread"] is True and data["pitch"] == 1.0
    assert "cycle" not in tp.moves[0].to_json() and "thread" not in tp.moves[0].to_json()


# -- diagnostics ---------------------------------------------------------------------------------------


CONTOUR = """N10 G0 X20 Z0.5
G1 Z-20 F0.2
G1 X40
G1 Z-40
N20 G1 X60
"""


@pytest.mark.parametrize(
    ("case", "program", "expected"),
    [
        ("depth zero", READY + "G0 X60 Z2\nG71 P10 Q20 D0 F0.3\n" + CONTOUR + "M30", ("TX-E402", 3)),
        ("no contour blocks", READY + "G0 X60 Z2\nG71 P10 Q30 D2 F0.3\n" + CONTOUR + "M30", ("TX-E304", 3)),
        (
            "falling and undercut with G88",
            READY + "G0 X60 Z2\nG88\nG71 P10 Q20 D2 F0.3\n"
            "N10 G0 X20 Z0.5\nG1 Z-20 F0.2\nG1 X40\nG1 Z-10\nN20 G1 X60\nM30",
            ("TX-E404", 4),
        ),
        (
            "contour ends outside the blank",
            READY + "G0 X50 Z2\nG71 P10 Q20 D2 F0.3\n" + CONTOUR + "M30",
            ("TX-W405", 3),
        ),
        ("too many passes", READY + "G0 X60 Z2\nG71 P10 Q20 D0.01 F0.3\n" + CONTOUR + "M30", ("TX-E406", 3)),
        ("missing pitch", READY + "G0 X30 Z4\nG33 Z-20\nM30", ("TX-E407", 3)),
        (
            "thread deeper than the start allows",
            READY + "G0 X33.5 Z4\nG76 X33.1 Z-29 K0.92 H8 F1.5\nM30",
            ("TX-E408", 3),
        ),
        ("G74 drilling with I", READY + "G0 X0 Z2\nG74 Z-38 I2 K10 F0.1\nM30", ("TX-E411", 3)),
        ("G75 cross drilling with K", READY + "G0 X62 Z-25\nG75 U-21 I15 K2 F0.1\nM30", ("TX-E411", 3)),
        (
            "chip breaking beyond the move budget",
            READY + "G0 X60 Z1\nG74 X20 Z-400 I1 K0.001 F0.2\nM30",
            ("TX-E406", 3),
        ),
        (
            "start point unknown after an open train point",
            READY + "G0 X40 Z2\nG1 A180 F0.2\nG71 P10 Q20 D2\nM30",
            ("TX-E401", 4),
        ),
        ("no contour named", READY + "G0 X40 Z2\nG71 D2 F0.2\nM30", ("TX-E409", 3)),
        (
            "contour with an error",
            READY + "G0 X60 Z2\nG71 P10 Q20 D2 F0.3\nN10 G0 X20 Z0.5\nG2 X40 Z-20\nN20 G1 X60\nM30",
            ("TX-E410", 3),
        ),
        ("G81 without G77/G78/G79", READY + "G0 X30 Z2\nG81 U-0.2 H3\nM30", ("TX-E414", 3)),
        ("taper beyond 45°", READY + "G0 X40 Z4\nG76 X33.1 Z-29 J50 K0.9 H4 F1.5\nM30", ("TX-E416", 3)),
        ("G76 with I", READY + "G0 X40 Z4\nG76 X33.1 Z-29 I1 K0.9 H4 F1.5\nM30", ("TX-E412", 3)),
        ("tapping without the spindle", "G97 S300 T505 M5\nG0 X0 Z3\nG82 Z-10 F1\nM30", ("TX-E417", 3)),
    ],
)
def test_cycle_diagnostics(case: str, program: str, expected: tuple[str, int]) -> None:
    assert expected in codes(traub(program)), case


def test_stock_smaller_than_the_depth_is_one_pass_with_a_warning() -> None:
    tp = traub(READY + "G0 X44 Z2\nG71 P10 Q20 D15 F0.3\n" + CONTOUR.replace("X60", "X44") + "M30")
    assert ("TX-W403", 3) in codes(tp) and passes(tp, 3) == 1


def test_too_many_passes_reports_the_limit() -> None:
    tp = traub(READY + "G0 X60 Z2\nG71 P10 Q20 D0.01 F0.3\n" + CONTOUR + "M30")
    d = next(x for x in tp.diagnostics if x.code == "TX-E406")
    assert (
        "2000" in d.message and "500" in d.message
    )  # 20 mm radial at D0.01 and not [m for m in tp.moves if m.line == 3]


# -- properties of the roughing passes ---------------------------------------------------------------


def _boundary(points: list[tuple[float, float]], z: float) -> float:
    """The radius of the (z-monotone, falling z) outer contour at z; the lowest at a step."""
    best = math.inf
    for (x0, z0), (x1, z1) in itertools.pairwise(points):
        if min(z0, z1) - 1e-9 <= z <= max(z0, z1) + 1e-9:
            best = min(best, x0 if abs(z1 - z0) < 1e-12 else x0 + (x1 - x0) * (z - z0) / (z1 - z0))
    return best


@st.composite
def staircase(draw: st.DrawFn) -> list[tuple[float, float]]:
    """An outer turning contour as radius steps rising towards -Z (x radius, z)."""
    n = draw(st.integers(1, 4))
    x, z = draw(st.floats(3, 10)), draw(st.floats(-0.5, 0.5))
    pts = [(x, z)]
    for _ in range(n):
        z -= draw(st.floats(2, 15))
        pts.append((x, z))
        x += draw(st.floats(0.5, 8))
        if draw(st.booleans()):
            pts.append((x, z - draw(st.floats(0.5, 4))))  # a cone
        else:
            pts.append((x, z))
        z = pts[-1][1]
    return pts


def _program(
    code: str,
    pts: list[tuple[float, float]],
    start: tuple[float, float],
    depth: float,
    allowance: tuple[float, float],
) -> str:
    blocks = [f"N10 G0 X{2 * pts[0][0]:.4f} Z{pts[0][1]:.4f}"]
    blocks += [f"G1 X{2 * x:.4f} Z{z:.4f}" for x, z in pts[1:]]
    blocks[-1] = "N20 " + blocks[-1]
    return (
        READY + f"G0 X{2 * start[0]:.4f} Z{start[1]:.4f}\nG89\n{code} P10 Q20 I{allowance[0]:.3f} "
        f"K{allowance[1]:.3f} D{depth:.3f} F0.3\n" + "\n".join(blocks) + "\nM30\n"
    )


@settings(max_examples=40, deadline=None)
@given(staircase(), st.floats(0.5, 4), st.floats(0, 0.4), st.floats(0, 0.3))
def test_g71_passes_stay_outside_contour_plus_allowance_and_inside_the_blank(
    pts: list[tuple[float, float]], depth: float, ai: float, ak: float
) -> None:
    start = (pts[-1][0], pts[0][1] + 2)  # the blank: up to the highest step, in front of the face
    pts = [(round(x, 3), round(z, 3)) for x, z in pts]
    depth, ai, ak = round(depth, 3), round(ai, 3), round(ak, 3)
    start = (pts[-1][0], pts[0][1] + 2)
    tp = traub(_program("G71", pts, start, depth, (ai, ak)))
    assert not [d for d in tp.diagnostics if d.severity.value == "error"], tp.diagnostics
    shifted = [(x + ai, z + ak) for x, z in pts]
    feeds = cuts(tp, 4)
    assert feeds, _program("G71", pts, start, depth, (ai, ak))
    for m in feeds:
        for p in (m.start, m.end, tuple((a + b) / 2 for a, b in zip(m.start, m.end, strict=True))):
            x, z = p[0], p[2]
            assert x <= start[0] + 1e-6 and z <= start[1] + 1e-6  # never at feed outside the blank
            if z <= shifted[0][1]:
                assert x >= _boundary(shifted, z) - 1e-6 or z < shifted[-1][1] - 1e-6
    # the union of passes leaves at most the allowance plus one depth step radially
    step = max(m.cycle[2] for m in feeds if m.cycle is not None)
    assert step >= 1


@settings(max_examples=40, deadline=None)
@given(
    st.floats(20, 60),
    st.floats(5, 19),
    st.floats(-40, -5),
    st.floats(0.5, 6),
    st.floats(4, 30),
    st.sampled_from(["G74", "G75"]),
)
def test_g74_g75_passes_stay_in_the_rectangle(
    x0: float, x1: float, z1: float, depth: float, every: float, code: str
) -> None:
    words = f"I{depth:.3f} K{every:.3f}" if code == "G74" else f"I{every:.3f} K{depth:.3f}"
    tp = traub(READY + f"G0 X{2 * x0:.3f} Z1\n{code} X{2 * x1:.3f} Z{z1:.3f} {words} D0.5 F0.2\nM30")
    assert not [d for d in tp.diagnostics if d.severity.value == "error"], tp.diagnostics
    feeds = cuts(tp, 3)
    for m in feeds:
        for p in (m.start, m.end):
            assert x1 - 1e-3 <= p[0] <= x0 + 1e-3 and z1 - 1e-3 <= p[2] <= 1 + 1e-3
    depth_axis = 0 if code == "G74" else 2
    levels = sorted({round(m.end[depth_axis], 6) for m in feeds})
    gaps = [b - a for a, b in itertools.pairwise(levels)]
    assert all(g <= depth + 2e-3 for g in gaps)
    assert min(levels) == pytest.approx(x1 if code == "G74" else z1, abs=1e-3)


def test_a_cycle_as_the_first_motion_starts_at_the_tool_change_point() -> None:
    tp = traub(READY + "G74 X400 Z500 I50 K100 F0.3\nM30")
    assert passes(tp, 2) == 1 and xz(cuts(tp, 2)[0].start) == (400.0, 585.0)


def test_the_benchmark_cycles_program_runs_clean_and_quickly() -> None:
    import importlib.util

    spec = importlib.util.spec_from_file_location(
        "bench_interpreter", Path(__file__).parents[1] / "bench" / "interpreter.py"
    )
    assert spec is not None and spec.loader is not None
    bench = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(bench)
    text = bench.generate_turning_cycles()
    assert len(text.splitlines()) == 300
    tp = traub(text)  # bench/interpreter.py times it (target 20 ms)
    assert codes(tp) == []
    assert {m.cycle[0] for m in tp.moves if m.cycle is not None} == {"G71", "G72", "G74", "G75", "G76"}


# -- robustness and coverage -------------------------------------------------------------------------

_CONTOURS = (
    "N10 G0 X20 Z0.5\nG1 Z-20 F0.2\nG2 X40 Z-30 R10\nG1 Z-40\nG1 X30 Z-50\nN20 G1 X60\n",
    "N10 G0 X150 Z-40\nG1 X100 F0.2\nG1 Z-20\nG3 X60 Z0 R20\nN20 G1 X10\n",
)


@settings(max_examples=150, deadline=None)
@given(
    st.sampled_from(
        sorted(
            {
                "G70",
                "G71",
                "G72",
                "G74",
                "G75",
                "G76",
                "G77",
                "G78",
                "G79",
                "G81",
                "G82",
                "G83",
                "G84",
                "G86",
                "G33",
            }
        )
    ),
    st.dictionaries(
        st.sampled_from("XZUWIKDHPQAJFER"),
        st.sampled_from([0, -1, 1, 0.001, 2.5, 10, 20, 50, 1e4]),
        max_size=7,
    ),
    st.sampled_from(["", "G88\n", "G89\n", "G78 X19.5 Z-34 F4\n"]),
    st.sampled_from([(0, 2), (40, 2), (200, -10)]),
    st.sampled_from(_CONTOURS),
)
def test_any_cycle_words_give_diagnostics_never_an_exception(
    code: str, words: dict[str, float], before: str, start: tuple[int, int], contour: str
) -> None:
    text = " ".join(f"{a}{v:g}" for a, v in words.items())
    program = (
        f"G97 S800 T101 M3\nG0 X{start[0]} Z{start[1]}\n{before}{code} {text}\n{contour}M30\n%\nO520\n"
        "G0 X10 Z0\nG1 X50 Z-10 F0.2\nM99\n%\n"
    )
    tp = traub(program)
    for m in tp.moves:
        assert m.to_json()["line"] >= 1


def _removed(feeds: list[Move], x: float, z: float) -> bool:
    """Is (x radius, z) swept by a feed at or below its radius (the material above a cut level goes with it)?"""
    for m in feeds:
        if abs(m.start[0] - m.end[0]) < 1e-9 and m.end[0] <= x + 1e-6:
            lo, hi = sorted((m.start[2], m.end[2]))
            if lo - 1e-6 <= z <= hi + 1e-6:
                return True
    return False


@settings(max_examples=30, deadline=None)
@given(
    st.lists(st.tuples(st.floats(2, 15), st.floats(0.5, 8)), min_size=1, max_size=4),
    st.floats(0.7, 4),
    st.floats(0, 0.4),
    st.sampled_from(["G88", "G89"]),
)
def test_g71_on_a_shaft_leaves_no_more_than_the_allowance(
    steps: list[tuple[float, float]], depth: float, allowance: float, falling: str
) -> None:
    """A shaft of cylinders and shoulders: after roughing, every point of the blank above the contour plus the
    allowance has been under a cut (checked on a 0.25 mm grid): each pass runs on along a step that lies between
    its level and the one before, so no step of the staircase stays for the finishing tool (TX-30's Ø65)."""
    x, z = 5.0, 0.0
    pts = [(x, z)]
    for length, rise in steps:
        z = round(z - length, 3)
        pts.append((x, z))
        x = round(x + rise, 3)
        pts.append((x, z))
    depth, allowance = round(depth, 3), round(allowance, 3)
    blocks = [f"N10 G0 X{2 * pts[0][0]:g} Z{pts[0][1]:g}"] + [f"G1 X{2 * a:g} Z{b:g}" for a, b in pts[1:]]
    blocks[-1] = "N20 " + blocks[-1]
    start = (x, 1.0)
    tp = traub(
        READY
        + f"G0 X{2 * start[0]:g} Z1\n{falling}\nG71 P10 Q20 I{allowance:g} D{depth:g} F0.3\n"
        + "\n".join(blocks)
        + "\nM30\n"
    )
    assert not [d for d in tp.diagnostics if d.severity.value == "error"]
    feeds = cuts(tp, 4)
    gz = 1.0
    while gz > pts[-1][1] + 0.3:
        # the contour's radius at gz (in front of the face: its first point, where the passes end)
        wall = max(px for px, pz in pts if pz >= gz - 1e-9) if gz <= 0 else pts[0][0]
        surface = wall + allowance
        gx = surface + 0.05
        while gx < start[0] - 0.05:
            assert _removed(feeds, gx, gz), (gx, gz, blocks, depth, allowance, falling)
            gx += 0.25
        gz -= 0.25
    for m in feeds:  # and no cut below the surface
        wall = max((px for px, pz in pts if pz >= max(m.start[2], m.end[2]) - 1e-9), default=0.0)
        assert m.end[0] >= min(wall, pts[0][0]) + allowance - 1e-6 or max(m.start[2], m.end[2]) > 0


@settings(max_examples=30, deadline=None)
@given(
    st.lists(st.tuples(st.floats(2, 15), st.floats(0.5, 6)), min_size=1, max_size=4),
    st.floats(0.7, 4),
    st.floats(0, 0.4),
)
def test_g72_passes_never_cut_below_the_contour_plus_allowance(
    steps: list[tuple[float, float]], depth: float, allowance: float
) -> None:
    """A facing contour of shoulders stepping towards the axis: no pass ends beyond the contour + K, none feeds
    outside the blank."""
    x, z = 40.0, -30.0
    pts = [(x, z)]
    for width, rise in steps:
        x = round(max(1.0, x - width), 3)
        pts.append((x, z))
        z = round(min(0.0, z + rise), 3)
        pts.append((x, z))
    depth, allowance = round(depth, 3), round(allowance, 3)
    blocks = [f"N10 G0 X{2 * pts[0][0]:g} Z{pts[0][1]:g}"] + [f"G1 X{2 * a:g} Z{b:g}" for a, b in pts[1:]]
    blocks[-1] = "N20 " + blocks[-1]
    tp = traub(
        READY
        + f"G0 X{2 * 41:g} Z1\nG72 P10 Q20 K{allowance:g} D{depth:g} F0.3\n"
        + "\n".join(blocks)
        + "\nM30\n"
    )
    assert not [d for d in tp.diagnostics if d.severity.value == "error"]
    for m in cuts(tp, 3):
        level, end_x = m.end[2], m.end[0]
        assert level <= 1 + 1e-6 and max(m.start[0], m.end[0]) <= 41 + 1e-6
        # the face of the contour at this radius lies at most at level − allowance
        face = max((pz for px, pz in pts if px > end_x + 1e-6), default=-math.inf)
        assert level >= face + allowance - 1e-6


def test_cycle_moves_under_g96_turn_at_the_speed_of_their_diameter() -> None:
    tp = seed("tx-30-g71-g88.nc")  # G96 V160, no G92 limit
    first, last = first_of_pass(tp, 5, 1)[0], first_of_pass(tp, 5, 10)[0]
    assert first.spindle == pytest.approx(160_000 / (math.pi * 92.7), abs=TOL)
    assert last.spindle == pytest.approx(160_000 / (math.pi * 27.0), abs=TOL)


def test_many_roughing_cycles_meet_the_run_budget() -> None:
    steps = "\n".join(f"G1 X{20 + 0.01 * k:.2f} Z{-0.05 * (k + 1):.2f}" for k in range(1000))
    program = (
        READY
        + "G0 X80 Z2\n"
        + "G71 P10 Q20 I50 D1 F0.3\n" * 700
        + "M30\nN10 G0 X20 Z0\n"
        + steps
        + "\nN20 G1 X60\n"
    )
    tp = traub(program)
    assert "TX-E420" in {d.code for d in tp.diagnostics}


def test_g77_chamfer_pass_and_g81_repeats_shifted_by_u() -> None:
    tp = traub(READY + "G0 X40 Z2\nG77 X30 Z-20 I2 K15 F0.2\nG81 U-1 H2\nM30")
    assert [xz(m.end) for m in cuts(tp, 3)] == [(30.0, -13.0), (34.0, -20.0)]  # K15 along Z, then I2 out
    assert [xz(m.end) for m in cuts(tp, 4)] == [(28.0, -13.0), (32.0, -20.0), (26.0, -13.0), (30.0, -20.0)]
    assert passes(tp, 4) == 2 and xz(tp.moves[-1].end) == (40.0, 2.0)


def test_g79_facing_chamfer_pass() -> None:
    tp = traub(READY + "G0 X40 Z-30\nG79 X10 Z-40 I3 K2 F0.2\nM30")
    assert [xz(m.end) for m in cuts(tp, 3)] == [(34.0, -40.0), (10.0, -38.0)]  # I3 facing, then K2 out


@st.composite
def humps(draw: st.DrawFn) -> list[tuple[float, float]]:
    """An outer contour along -Z whose radius rises and falls (falling cones make pockets for G88)."""
    x, z = draw(st.floats(5, 10)), 0.0
    pts = [(round(x, 3), z)]
    for _ in range(draw(st.integers(2, 6))):
        z -= draw(st.floats(1, 10))
        x = max(1.0, x + draw(st.floats(-6, 8)))
        pts.append((round(x, 3), round(z, 3)))
    return pts


@settings(max_examples=40, deadline=None)
@given(humps(), st.floats(0.7, 4), st.floats(0, 0.4))
def test_g88_passes_never_feed_below_the_contour_plus_allowance(
    pts: list[tuple[float, float]], depth: float, allowance: float
) -> None:
    depth, allowance = round(depth, 3), round(allowance, 3)
    top = max(x for x, _ in pts) + 1
    blocks = [f"N10 G0 X{2 * pts[0][0]:g} Z{pts[0][1]:g}"] + [f"G1 X{2 * a:g} Z{b:g}" for a, b in pts[1:]]
    blocks.append(f"N20 G1 X{2 * top:g}")
    tp = traub(
        READY
        + f"G0 X{2 * top:g} Z1\nG88\nG71 P10 Q20 I{allowance:g} D{depth:g} F0.3 E0.1\n"
        + "\n".join(blocks)
        + "\nM30\n"
    )
    assert not [d for d in tp.diagnostics if d.severity.value == "error"], blocks
    shifted = [(x + allowance, z) for x, z in pts]
    for m in cuts(tp, 4):
        for p in (m.start, m.end, tuple((a + b) / 2 for a, b in zip(m.start, m.end, strict=True))):
            x, z = p[0], p[2]
            assert x <= top + 1e-6 and z <= 1 + 1e-6, blocks
            if (
                shifted[-1][1] - 1e-6 <= z < shifted[0][1] - 1e-6
            ):  # in front of the contour's start: the blank
                assert x >= _boundary(shifted, z) - 1e-5, (p, blocks)


# -- TX-30 with the manual's D4: the passes bring every step down to the allowance ----------------------------

TX30_TOOLS = parse_tool_table(
    "tools: [{number: 4, kind: turning, diameter: 1.6, nose_radius: 0.8, quadrant: 1, insert: D},"
    " {number: 5, kind: turning, diameter: 0.8, nose_radius: 0.4, quadrant: 1, insert: V}]"
)


def _tx30_part(z: float) -> float:
    """TX-30's finished radius at z (N50…N60): chamfer D1.5 on Ø30, R5 on the Ø65 shoulder, the cone A205 to Ø38,
    R6 into the Ø100 face, its chamfer D2."""
    cone_end = -45 - 13.5 / math.tan(math.radians(25))
    if z > 0.5:
        return 0.0
    if z > -1:
        return 13.5 + (0.5 - z)
    if z > -15:
        return 15.0
    if z > -20:
        return 27.5 + math.sqrt(max(0.0, 25 - (z + 20) ** 2))
    if z > -45:
        return 32.5
    if z > cone_end:
        return 32.5 - (-45 - z) * math.tan(math.radians(25))
    if z > -114:
        return 19.0
    if z > -120:
        return 25 - math.sqrt(max(0.0, 36 - (z + 114) ** 2))
    return 48 + (-120 - z) if z > -122 else 50.0


def _excess(tp: Toolpath, tools: ToolTable, zones: list[tuple[float, float]]) -> tuple[float, float]:
    """The largest radial excess over the allowance I0.5 after TX-30's cycle (line 5), and where (Z)."""
    rough = simulate_turning(
        tp.until_move(sum(1 for m in tp.moves if m.line <= 5)), Blank(100, 160, chuck_length=30), tools, 0.05
    )
    assert [(e.code, e.span.line) for e in rough.events if e.severity.value == "error"] == []
    worst = (-math.inf, 0.0)
    for z, r in zip(rough.profile.zs, rough.profile.outer, strict=True):
        if any(lo < z < hi for lo, hi in zones):
            # within a sample (0.05 mm) and the allowance K0.05 along Z of a wall the larger radius counts
            part = max(_tx30_part(z - dz) for dz in np.linspace(-0.05, 0.1, 7))
            worst = max(worst, (float(r) - part - 0.5, float(z)))
    return worst


def test_tx30_g71_g88_with_d4_roughs_every_step_down_to_the_allowance() -> None:
    """The manual's TX-30 (D4 from X100 on a Ø100 bar, T4 a D insert R0.8): no pass rapids into the Ø65 step, the
    finishing tool meets no more than the allowance, and after the cycle the part carries at most the allowance
    I0.5 (radial) / K0.05 (along Z) anywhere on the contour."""
    tp = run(seed_text("tx-30-g71-g88.nc"), "traub-tx8d", RunSetup(tools=TX30_TOOLS))
    assert [d.code for d in tp.diagnostics if d.severity.value == "error"] == []
    whole = simulate_turning(tp, Blank(100, 160, chuck_length=30), TX30_TOOLS, 0.05)
    assert [(e.code, e.span.line) for e in whole.events if e.severity.value == "error"] == []
    # the cylinders Ø30, Ø65 and Ø38 with the real insert
    worst = _excess(tp, TX30_TOOLS, [(-14, -2), (-44, -21), (-113, -75)])
    assert worst[0] <= 0.01, f"{worst[0]:.3f} mm more than the allowance at Z{worst[1]:.2f}"
    # the whole contour along the path itself (a sharp insert: the nose radius of the roughing tool leaves its
    # own small rest on chamfers and roundings, as any uncompensated path does)
    sharp = ToolTable({4: turning_tool(4, 0.0, 1)})
    worst = _excess(
        run(seed_text("tx-30-g71-g88.nc"), "traub-tx8d", RunSetup(tools=sharp)), sharp, [(-123, 0.5)]
    )
    assert worst[0] <= 0.01, f"{worst[0]:.3f} mm more than the allowance at Z{worst[1]:.2f}"


def test_g71_last_pass_below_an_approach_chamfer_runs_on_the_contour() -> None:
    """TX-17 (exercise traub-02): the contour starts in front of the face (X16 Z2, chamfer to X20 Z0), so the
    lowest level X17 meets it at the start point. That pass runs on the contour from there (the chamfer, Ø20 +
    2·I to the arc) instead of being dropped and leaving Ø20 at the level of the pass before (X23.05)."""
    tp = traub(
        READY + "G0 X64 Z2\nG71 P10 Q20 I0.5 K0.1 D3 F0.3\nM30\nN10 G46\nG0 X16 Z2\nG1 X20 Z0 F0.15\n"
        "G1 Z-15\nG2 X40 Z-25 R10\nG1 Z-40\nG3 X60 Z-50 R10\nG1 Z-75\nG1 X64 Z-77\nN20 G40\n"
    )
    assert passes(tp, 3) == 8
    last = first_of_pass(tp, 3, 8)
    assert [(xz(m.start), xz(m.end)) for m in last[:2]] == [
        ((17.2, 2.0), (21.0, 0.1)),
        ((21.0, 0.1), (21.0, -14.9)),
    ]
    assert xz(last[-1].end) == (23.05, -19.295)  # up the R10 arc to the level of pass 7
