"""TRAUB contour trains and nose-radius compensation (core.interpreter.turn_contour), unit by unit.

The blocks are written as in the manual and turned into `TurnItem`s by a small reader below that
does what the block executor does (X halved, U/W resolved against a known start, start None after
an unknown point), so these tests do not depend on the executor. Oracles: the coordinates the
manual prints or that follow from its drawings (spec examples.md TX-17…TX-28, TX-48), worked by
hand in the comments; points are [x radius, 0, z].
"""

from __future__ import annotations

import math
import re
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from core.diagnostics import Diagnostic
from core.interpreter.state import RunSetup
from core.interpreter.turn_contour import (
    XZ,
    Nose,
    SrkSwitch,
    TransitionSpec,
    TurnItem,
    known_end,
    resolve,
)
from core.pipeline import run as pipeline_run
from core.pipeline import toolpath_json
from core.syntax.blocks import Span
from core.toolpath import Move
from core.tools import DEFAULT_TOOLS, turning_tool

TOL = 0.001
WORD = re.compile(r"([A-Z])\s*(-?\s*[\d.,]+)")


def _template(line: int, feed: float) -> Move:
    return Move(
        kind="feed",
        start=(0.0, 0.0, 0.0),
        end=(0.0, 0.0, 0.0),
        feed=feed,
        feed_unit="mm/rev",
        spindle=1000.0,
        spindle_direction="cw",
        coolant=True,
        tool=1,
        span=Span(line, 1, line, 40),
    )


def items_of(
    program: str,
    start: XZ = (50.0, 10.0),
    radius: float = 0.4,
    quadrant: int = 1,
) -> list[TurnItem | SrkSwitch]:
    """The items the executor hands over for `program` (one block a line), from tool tip `start`."""
    out: list[TurnItem | SrkSwitch] = []
    pos: XZ | None = start
    motion, feed, efeed, mode = "G0", 0.2, None, "G40"
    for n, text in enumerate(program.strip().splitlines(), 1):
        words = {k: float(v.replace(" ", "").replace(",", ".")) for k, v in WORD.findall(text.upper())}
        gs = [int(g) for g in re.findall(r"G\s*(\d+)", text.upper())]
        words.pop("G", None)
        for g in gs:
            if g in (40, 41, 42, 46):
                mode = f"G{g}"
                out.append(SrkSwitch(mode, Span(n, 1, n, 40), Nose(mode, radius, quadrant)))  # type: ignore[arg-type]
            elif g in (0, 1, 2, 3, 9):
                motion = f"G{g}"
        feed = words.get("F", feed)
        efeed = words.get("E", efeed)
        if not set(words) & set("XZUWARDCPQIKH"):
            continue  # G40 / G46 alone, F alone
        arc = motion in ("G2", "G3")
        transition = None
        if "D" in words:
            d = words["D"]
            transition = TransitionSpec("chamfer" if d > 0 else "chamfer_length", abs(d), f"D{d:g}", efeed)
        rr = words.get("C") if arc else words.get("R")
        if rr is not None:
            transition = TransitionSpec("rounding", rr, f"R{rr:g}", efeed)
        x = words["X"] / 2 if "X" in words else None
        z = words.get("Z")
        dx, dz = words.get("U"), words.get("W")
        if pos is not None:
            x = pos[0] + dx if dx is not None else x
            z = pos[1] + dz if dz is not None else z
            dx = dz = None
        item = TurnItem(
            template=_template(n, feed),
            code=motion,
            start=pos,
            x=x,
            z=z,
            dx=dx,
            dz=dz,  # type: ignore[arg-type]
            a=words.get("A"),
            radius=words.get("R") if arc else None,
            centre=(words["P"] / 2, words["Q"]) if "P" in words and "Q" in words else None,
            centre_offset=(words.get("I", 0.0), words.get("K", 0.0))
            if "I" in words or "K" in words
            else None,
            h=int(words["H"]) if "H" in words else None,
            transition=transition,
            nose=Nose(mode, radius, quadrant),
        )  # type: ignore[arg-type]
        out.append(item)
        pos = known_end(pos, item)
    return out


def run(program: str, **kw: object) -> tuple[list[Move], list[Diagnostic]]:
    d: list[Diagnostic] = []
    cmds = resolve(items_of(program, **kw), d)  # type: ignore[arg-type]
    moves = [c for c in cmds if isinstance(c, Move)]
    return moves, d


def codes(d: list[Diagnostic]) -> list[tuple[str, int]]:
    return [(x.code, x.span.line) for x in d]


def ends(moves: list[Move]) -> list[tuple[float, float]]:
    """(X diameter, Z) of each end, as the drawing dimensions them."""
    return [(round(2 * m.end[0], 3), round(m.end[2], 3)) for m in moves]


def approx(*pts: tuple[float, float]) -> list[object]:
    return [pytest.approx(p, abs=TOL) for p in pts]


# -- TX-17…TX-20: single blocks -----------------------------------------------------------------


def test_tx17_overview_contour_arcs_seen_from_plus_y() -> None:
    moves, d = run("G0 X20 Z2 M8\nG1 Z-15 F0.2\nG2 X40 Z-25 R10\nG1 Z-40\nG3 X60 Z-50 R10\nG1 Z-75")
    assert d == []
    assert ends(moves) == approx((20, 2), (20, -15), (40, -25), (40, -40), (60, -50), (60, -75))
    g2, g3 = moves[2], moves[4]
    # G2: concave quarter circle about X40 Z-15, clockwise in the drawing view (Z right, X up)
    assert (g2.kind, g2.direction, g2.plane) == ("arc", "cw", "G18")
    assert g2.center == pytest.approx((20, 0, -15)) and g2.radius == pytest.approx(10)
    assert g2.angle == pytest.approx(90)
    # G3: convex quarter circle about X40 Z-50
    assert (g3.direction, g3.center) == ("ccw", pytest.approx((20, 0, -50)))
    assert all(m.programmed_end == m.end for m in moves)  # no SRK: the tool tip is programmed


def test_tx18_tx19_rapid_and_feed_lines() -> None:
    moves, d = run("G0 X20 Z2 M8\nG1 Z-15 F0.2\nG1 X40 Z-25 F0.2\nG0 X20 Z2\nG1 Z-15 F0.2\nG1 X40 Z-25")
    assert d == []
    assert [m.kind for m in moves] == ["rapid", "feed", "feed", "rapid", "feed", "feed"]
    assert moves[0].end == pytest.approx((10, 0, 2))  # x is the radius X/2
    assert ends(moves) == approx((20, 2), (20, -15), (40, -25), (20, 2), (20, -15), (40, -25))


def test_tx20_angle_a_first_example() -> None:
    moves, d = run("G0 X40 Z0\nG1 Z-25 F0.2\nG1 X20 A 210 F0.1\nG1 Z-65 F0.2\nG1 X60 A135")
    assert d == []
    # X20 A210 from X40 Z-25: 10 mm down on the radius at 30° → 17.321 along −Z
    assert ends(moves)[2:] == approx((20, -42.321), (20, -65), (60, -85))


def test_tx20_angle_a_second_example() -> None:
    moves, d = run("G0 X20 Z-37.32\nG1 X40 A30")
    assert d == []
    assert ends(moves)[-1] == pytest.approx((40, -20.0), abs=0.002)  # 37.32 = 20 + 10 / tan 30°


def test_angle_a_with_z_and_known_start() -> None:
    moves, d = run("G0 X20 Z0\nG1 Z-10 A135 F0.2")
    assert d == []
    assert ends(moves)[-1] == pytest.approx((40, -10))  # 45° rise: 10 mm along −Z is 10 mm on the radius


# -- TX-21: contour trains of lines -------------------------------------------------------------


def test_tx21_second_example_unknown_point_from_the_closing_block() -> None:
    moves, d = run("G0 X40 Z1 M8\nG1 Z-25 F0.2\nG1 X20 A210 F0.1\nG1 A180 F0.2\nG1 X60 Z-85 A-45")
    assert d == []
    assert ends(moves) == approx((40, 1), (40, -25), (20, -42.321), (20, -65), (60, -85))
    # the closing element runs from the intersection to the known point: travel direction 135°
    last = moves[-1]
    assert last.start == pytest.approx((10, 0, -65)) and last.line == 5
    assert moves[3].line == 4 and moves[3].feed == 0.2


def test_tx21_rounding_at_the_unknown_point() -> None:
    # the manual's margin note "R2 E 0.08" is not NC text (DECISIONS 22), but the combination is legal by the
    # template L2281–2285; from an assumed start X40 Z0 the rounding must touch both lines
    moves, d = run("G0 X40 Z0\nG1 A105 R2 E0.08 F0.2\nG1 X100 Z-50 A-30")
    assert d == []
    first, rounding, last = moves[1:]
    assert rounding.kind == "arc" and rounding.radius == pytest.approx(2) and rounding.feed == 0.08
    assert rounding.line == 2 and last.line == 3
    c = (rounding.center[2], rounding.center[0])  # type: ignore[index]
    # the corner without rounding: the line from X40 Z0 at 105° meets the line through X100 Z-50 at −30°
    for start, angle in (((0.0, 20.0), 105.0), ((-50.0, 50.0), -30.0)):
        u = (math.cos(math.radians(angle)), math.sin(math.radians(angle)))
        dist = abs((c[0] - start[0]) * u[1] - (c[1] - start[1]) * u[0])
        assert dist == pytest.approx(2, abs=1e-6)  # tangent to both lines
    assert ends(moves)[-1] == pytest.approx((100, -50))
    assert first.end == rounding.start and rounding.end == last.start


def test_train_closing_a_may_be_given_either_way_round() -> None:
    # DECISIONS 12: A of the closing block points back; A+180 names the same line
    a, _ = run("G0 X40 Z1\nG1 Z-25 F0.2\nG1 A180\nG1 X60 Z-85 A-45")
    b, _ = run("G0 X40 Z1\nG1 Z-25 F0.2\nG1 A180\nG1 X60 Z-85 A135")
    assert ends(a) == ends(b) == approx((40, 1), (40, -25), (40, -75), (60, -85))


# -- TX-22: transition elements -----------------------------------------------------------------


def test_tx22_face_chamfer_d_is_the_width_along_z() -> None:
    moves, d = run("G0 X0 Z1 M8\nG1 Z0 F0.2\nG1 X40 D0.5 E0.1\nG1 Z-30")
    assert d == []
    assert ends(moves) == approx((0, 1), (0, 0), (39, 0), (40, -0.5), (40, -30))
    chamfer = moves[3]
    assert (chamfer.line, chamfer.feed, chamfer.kind) == (3, 0.1, "feed")  # E, on the block that programs it
    assert moves[4].feed == 0.2


def test_tx22_face_rounding() -> None:
    moves, d = run("G0 X0 Z1 M8\nG1 Z0 F0.2\nG1 X40 R0.5 E0.1\nG1 Z-30")
    assert d == []
    assert ends(moves) == approx((0, 1), (0, 0), (39, 0), (40, -0.5), (40, -30))
    r = moves[3]
    assert (r.kind, r.direction, r.radius, r.feed) == ("arc", "ccw", pytest.approx(0.5), 0.1)  # a left turn
    assert r.center == pytest.approx((19.5, 0, -0.5))  # centre X39 Z-0.5


def test_tx22_train_corner_and_chamfer_length() -> None:
    plain, d0 = run("G0 X0 Z1 M8\nG1 Z0 F0.2\nG1 A100\nG1 X86 Z-35 A-30")
    assert d0 == []
    assert ends(plain)[2] == pytest.approx((50.752, -4.474), abs=TOL)  # the corner of the train
    moves, d = run("G0 X0 Z1 M8\nG1 Z0 F0.2\nG1 A100 D-2\nG1 X86 Z-35 A-30")
    assert d == []
    chamfer = moves[3]
    p1 = (chamfer.start[0], chamfer.start[2])
    p2 = (chamfer.end[0], chamfer.end[2])
    corner = (50.752 / 2, -4.474)
    assert math.dist(p1, p2) == pytest.approx(2, abs=1e-6)  # D− is the chamfer's own length
    assert math.dist(p1, corner) == pytest.approx(math.dist(p2, corner), abs=TOL)  # equal legs
    assert ends(moves)[-1] == pytest.approx((86, -35))


def test_tx22_train_corner_with_rounding() -> None:
    moves, d = run("G0 X0 Z1 M8\nG1 Z0 F0.2\nG1 A100 R2\nG1 X86 Z-35 A-30")
    assert d == []
    r = moves[3]
    assert r.kind == "arc" and r.radius == pytest.approx(2)
    corner = (-4.474, 50.752 / 2)
    c = (r.center[2], r.center[0])  # type: ignore[index]
    # the centre lies on the bisector, 2 / sin(half the corner angle) from the corner
    half = math.radians((180 - (100 - (-30 + 180))) / 2)
    assert math.dist(c, corner) == pytest.approx(2 / math.sin(half), abs=TOL)


def test_tx22_line_to_arc_with_rounding() -> None:
    moves, d = run("G0 X40 Z2\nG1 Z-20 R6 F0.2\nG3 X96 Z-48 R28")
    assert d == []
    _, rounding, arc = moves[1:]
    assert rounding.radius == pytest.approx(6) and rounding.line == 2
    assert arc.center is not None and arc.radius == pytest.approx(28)
    c6 = (rounding.center[2], rounding.center[0])  # type: ignore[index]
    c28 = (arc.center[2], arc.center[0])
    assert c6[1] == pytest.approx(20 + 6)  # tangent to the line X40 …
    assert math.dist(c6, c28) == pytest.approx(28 + 6, abs=1e-6)  # … and to the arc R28 (about X40 Z-48)


def test_tx22_w_min_is_transition_plus_0_1_plus_nose_radius() -> None:
    # D0.2 with nose radius 0.4: W_min = 0.7 mm (stated in the manual)
    _, d = run("G0 X0 Z1\nG1 Z0 F0.2\nG1 X40 D0.2 E0.08\nG1 Z-0.69\nG1 X50", radius=0.4)
    assert codes(d) == [("TX-E223", 4)]
    assert "0.7" in d[0].message_en
    _, ok = run("G0 X0 Z1\nG1 Z0 F0.2\nG1 X40 D0.2 E0.08\nG1 Z-0.71\nG1 X50", radius=0.4)
    assert ok == []


def test_transition_without_partner_is_an_error_on_its_block() -> None:
    _, d = run("G0 X0 Z1\nG1 Z0 F0.2\nG1 X40 D0.5\nG0 X60")
    assert codes(d) == [("TX-E210", 3)]
    _, d2 = run("G0 X0 Z1\nG1 Z0 F0.2\nG1 X40 R0.5")
    assert codes(d2) == [("TX-E210", 3)]


def test_transition_too_large_for_its_neighbours() -> None:
    _, d = run("G0 X0 Z1\nG1 Z0 F0.2\nG1 X40 R30\nG1 Z-30")
    assert codes(d) == [("TX-E211", 3)]


# -- TX-23 / TX-48: three ways to give an arc ---------------------------------------------------


@pytest.mark.parametrize("arc", ["G2 X50 Z-35 R10", "G2 X50 Z-35 P50 Q-25", "G2 X50 Z-35 I10 K0"])
def test_tx23_g2_three_equivalent_forms(arc: str) -> None:
    moves, d = run(f"G0 X30 Z1 M8\nG1 Z-25 F0.2\n{arc}\nG1 Z-55")
    assert d == []
    m = moves[2]
    assert (m.direction, m.center, m.radius, m.angle) == (
        "cw",
        pytest.approx((25, 0, -25)),
        pytest.approx(10),
        pytest.approx(90),
    )
    assert ends(moves)[2:] == approx((50, -35), (50, -55))


@pytest.mark.parametrize("arc", ["G3 X50 Z-35 R10", "G3 X50 Z-35 P30 Q-35", "G3 X50 Z-35 I0 K-10"])
def test_tx23_g3_three_equivalent_forms(arc: str) -> None:
    moves, d = run(f"G0 X30 Z1 M8\nG1 Z-25 F0.2\n{arc}\nG1 Z-55")
    assert d == []
    m = moves[2]
    assert (m.direction, m.center, m.angle) == ("ccw", pytest.approx((15, 0, -35)), pytest.approx(90))


def test_arc_radius_too_small_for_its_end_point() -> None:
    _, d = run("G0 X30 Z1\nG1 Z-25 F0.2\nG2 X50 Z-35 R5")
    assert codes(d) == [("TX-E202", 3)]


def test_arc_with_r_of_180_degrees_needs_the_centre() -> None:
    _, d = run("G0 X30 Z1\nG1 Z-25 F0.2\nG3 X30 Z-45 R10")
    assert codes(d) == [("TX-E203", 3)]
    moves, ok = run("G0 X30 Z1\nG1 Z-25 F0.2\nG3 X30 Z-45 P30 Q-35")
    assert ok == [] and moves[2].angle == pytest.approx(180)


def test_arc_end_point_not_on_the_circle_of_its_centre() -> None:
    _, d = run("G0 X30 Z1\nG1 Z-25 F0.2\nG2 X50 Z-35 P52 Q-25")
    assert codes(d) == [("TX-E205", 3)]


# -- TX-24 / TX-25 / TX-48: trains with arcs ----------------------------------------------------


def test_tx24_h0_h1_rank_by_distance_from_the_known_point() -> None:
    # assumption (DECISIONS 22): the arc starts at X0 Z0, so it has radius 28 about X0 Z-28;
    # the line X40 (radius 20) meets that circle at Z = −28 ± √(28² − 20²) = −8.404 and −47.596
    h0, d0 = run("G0 X0 Z0\nG3 P0 Q-28 H0 F0.2\nG1 X40 Z-10 A0")
    h1, d1 = run("G0 X0 Z0\nG3 P0 Q-28 H1 F0.2\nG1 X40 Z-27 A0")
    assert d0 == [] and d1 == []
    assert ends(h0)[1:] == approx((40, -8.404), (40, -10))  # nearer to Z-10
    assert ends(h1)[1:] == approx((40, -47.596), (40, -27))  # the farther from Z-27
    assert h0[1].direction == h1[1].direction == "ccw"


def test_h_missing_where_line_and_circle_meet_twice() -> None:
    _, d = run("G0 X0 Z0\nG3 P0 Q-28 F0.2\nG1 X40 Z-10 A0")
    assert codes(d) == [("TX-E207", 2)]


def test_train_line_line_without_intersection_is_an_error_on_the_closing_block() -> None:
    moves, d = run("G0 X40 Z1\nG1 Z-25 F0.2\nG1 A180\nG1 X60 Z-85 A0")
    assert codes(d) == [("TX-E201", 4)]
    assert ends(moves)[-1] == pytest.approx((60, -85))  # the known point is still reached


def test_unknown_point_must_be_followed_by_a_known_point() -> None:
    _, d = run("G0 X40 Z1\nG1 Z-25 F0.2\nG1 A180\nG1 A135\nG1 X60 Z-85 A-45")
    assert ("TX-E206", 4) in codes(d)
    _, d2 = run("G0 X40 Z1\nG1 Z-25 F0.2\nG1 A180")
    assert codes(d2) == [("TX-E206", 3)]


def test_tx25_line_arc_tangential() -> None:
    # G1 A180 from X20 Z0, then G2 to X40 Z-20 R10: the arc is a quarter circle about X40 Z-10
    moves, d = run("G0 X20 Z0\nG1 A180 F0.2\nG2 X40 Z-20 R10")
    assert d == []
    assert ends(moves)[1:] == approx((20, -10), (40, -20))
    assert moves[2].center == pytest.approx((20, 0, -10))


def test_tx25_tx27_arc_line_tangential() -> None:
    # TX-27 example 3: G3 R30 from X0 Z0 runs tangentially into the line X30 → tangent point X30 Z-25.981,
    # centre X-30 Z-25.981, 60° counter-clockwise
    moves, d = run("G0 X0 Z0\nG3 R30 F0.2\nG1 X30 Z-30 A0")
    assert d == []
    arc = moves[1]
    assert ends(moves)[1:] == approx((30, -25.981), (30, -30))
    assert arc.center == pytest.approx((-15, 0, -25.981), abs=TOL)
    assert (arc.direction, arc.angle) == ("ccw", pytest.approx(60))


def test_tx25_line_arc_with_centre_h0_h1() -> None:
    # G1 A180 from X40 Z0 (radius 20) meets the circle about X0 Z-30 through X40 Z-30+… : radius 25 via the
    # end point X50 Z-30 → intersections at Z = −30 ± √(25² − 20²) = −15 and −45; H0 nearer to the start
    h0, d0 = run("G0 X40 Z0\nG1 A180 F0.2\nG2 X50 Z-30 P0 Q-30 H0")
    h1, d1 = run("G0 X40 Z0\nG1 A180 F0.2\nG2 X50 Z-30 P0 Q-30 H1")
    assert d0 == [] and d1 == []
    assert ends(h0)[1:] == approx((40, -15), (50, -30))
    assert ends(h1)[1:] == approx((40, -45), (50, -30))


def test_tx25_arc_chamfer_and_rounding_to_line() -> None:
    # arc about X0 Z-28 (radius 28) from X0 Z0, H1 with the line X40 from Z-27: corner X40 Z-47.596
    plain, _ = run("G0 X0 Z0\nG3 P0 Q-28 H1 F0.2\nG1 X40 Z-27 A0")
    corner = (plain[1].end[0], plain[1].end[2])
    ch, d = run("G0 X0 Z0\nG3 P0 Q-28 D-2 H1 F0.2\nG1 X40 Z-27 A0")
    assert d == []
    a, b = (ch[2].start[0], ch[2].start[2]), (ch[2].end[0], ch[2].end[2])
    assert math.dist(a, b) == pytest.approx(2, abs=1e-6)
    assert math.dist(a, corner) == pytest.approx(math.dist(b, corner), abs=1e-6)
    rd, d2 = run("G0 X0 Z0\nG3 P0 Q-28 C3 H1 F0.2\nG1 X40 Z-27 A0")
    assert d2 == []
    assert rd[2].kind == "arc" and rd[2].radius == pytest.approx(3) and rd[2].line == 2
    assert rd[2].center is not None and rd[2].center[0] == pytest.approx(
        20 + 3
    )  # left of the line X40, tangent


def test_tx25_arc_arc_tangential() -> None:
    # G3 about X0 Z-10 (radius 10) from X0 Z0, then G2 R10 to X40 Z-30: the second centre lies 20 from the
    # first and 10 from the end point (Z-30, radius 20)
    moves, d = run("G0 X0 Z0\nG3 P0 Q-10 F0.2\nG2 X40 Z-30 R10")
    assert d == []
    a1, a2 = moves[1], moves[2]
    c1 = (a1.center[2], a1.center[0])  # type: ignore[index]
    c2 = (a2.center[2], a2.center[0])  # type: ignore[index]
    assert math.dist(c1, c2) == pytest.approx(20, abs=1e-6)
    assert math.dist(c2, (-30, 20)) == pytest.approx(10, abs=1e-6)
    assert a1.end == a2.start and (a1.direction, a2.direction) == ("ccw", "cw")


def test_arc_arc_with_equal_senses_is_an_error() -> None:
    _, d = run("G0 X0 Z0\nG3 P0 Q-10 F0.2\nG3 X40 Z-30 R10")
    assert codes(d) == [("TX-E209", 3)]


# -- TX-27 / TX-28: nose-radius compensation ----------------------------------------------------


def test_tx27_selection_rapid_ends_on_the_equidistant() -> None:
    moves, d = run("G46\nG0 X40 Z1\nG1 Z-30 F0.2", radius=0.4, quadrant=1)
    assert d == []
    assert [m.end for m in moves] == [pytest.approx((20.4, 0, 1)), pytest.approx((20.4, 0, -30))]
    assert [m.programmed_end for m in moves] == [pytest.approx((20, 0, 1)), pytest.approx((20, 0, -30))]


def test_tx27_selection_with_chamfer() -> None:
    moves, d = run("G46\nG0 X30 Z1\nG1 Z0\nG1 X40 D2 F0,2 E0,1\nG1 Z-30", radius=0.4, quadrant=1)
    assert d == []
    s = math.sqrt(0.08)  # 0.4 / √2
    assert [m.end for m in moves] == [
        pytest.approx((15.4, 0, 1)),  # the rapid ends beside the face Z0 … Z1 line
        pytest.approx((15.4, 0, 0.4)),  # inside corner: the equidistants of Z-face and X-face meet
        pytest.approx((18, 0, 0.4)),  # up to the chamfer's start X36, on its perpendicular
        pytest.approx((18 + s, 0, s)),  # outside corner: arc about X36 Z0
        pytest.approx((20 + s, 0, -2 + s)),  # the chamfer, 0.4 away
        pytest.approx((20.4, 0, -2)),  # arc about X40 Z-2
        pytest.approx((20.4, 0, -30)),
    ]
    assert [m.kind for m in moves] == ["rapid", "feed", "feed", "arc", "feed", "arc", "feed"]
    assert moves[3].center == pytest.approx((18, 0, 0)) and moves[3].direction == "ccw"
    assert moves[4].programmed_end == pytest.approx((20, 0, -2)) and moves[4].feed == 0.1


def test_tx27_selection_below_the_axis_and_tangential_arc() -> None:
    moves, d = run(
        "G 46\nG 0 X - 1,6 Z 1\nG 1 Z 0 F 0,2\nG 1 X 0\nG 3 R 30\nG 1 X 30 Z - 30 A 0", radius=0.4, quadrant=1
    )
    assert d == []
    s = (0.4 * math.sin(math.radians(30)), 0.4 * math.cos(math.radians(30)))
    assert [m.end for m in moves] == [
        pytest.approx((-0.4, 0, 1)),
        pytest.approx((-0.4, 0, 0.4)),
        pytest.approx((0, 0, 0.4)),
        pytest.approx((s[0], 0, s[1])),  # outside corner at X0 Z0: arc to the arc's normal at 30°
        pytest.approx((15.4, 0, -25.981), abs=TOL),  # the arc R30 + 0.4 to the tangent point
        pytest.approx((15.4, 0, -30)),
    ]
    assert moves[4].radius == pytest.approx(30.4) and moves[4].programmed_end == pytest.approx(
        (15, 0, -25.981), abs=TOL
    )


def test_tx27_first_feed_shorter_than_the_nose_radius() -> None:
    # compensated length of G1 Z0.5: from Z1 to the inside corner at Z0.9 → 0.1 mm < 0.4 mm
    _, d = run("G46\nG0 X30 Z1\nG1 Z0.5 F0.2\nG1 X40\nG1 Z-30", radius=0.4, quadrant=1)
    assert codes(d) == [("TX-E219", 3)]


def test_first_motion_after_g46_must_not_be_an_arc() -> None:
    _, d = run("G0 X30 Z1\nG46\nG2 X50 Z-9 R10 F0.2\nG1 Z-30", radius=0.4, quadrant=1)
    assert ("TX-E213", 3) in codes(d)


def test_g46_needs_the_quadrant() -> None:
    _, d = run("G46\nG0 X40 Z1\nG1 Z-30 F0.2", radius=0.4, quadrant=0)
    assert codes(d) == [("TX-E212", 1)]


@pytest.mark.parametrize(
    ("quadrant", "code", "x"), [(1, "G46", 20.4), (4, "G46", 19.6), (0, "G42", 20.4), (0, "G41", 19.6)]
)
def test_side_from_quadrant_or_g41_g42(quadrant: int, code: str, x: float) -> None:
    # travel −Z: an outside tool (P1) and G42 (tool right of the travel) stay above, a boring bar (P4) and G41 below
    moves, d = run(f"{code}\nG0 X40 Z1\nG1 Z-30 F0.2", radius=0.4, quadrant=quadrant)
    assert d == []
    assert moves[-1].end == pytest.approx((x, 0, -30))


TX28 = "G46\nG0 X60 Z1\nG1 Z-30 F0.2\nG1 X90 A135\n"


def test_tx28_case3_g0_with_a_ends_the_last_block_on_its_perpendicular() -> None:
    moves, d = run(TX28 + "G0 X91 A135\nG40\nG0 X120 Z10", radius=0.4, quadrant=1)
    assert d == []
    k = 0.4 / math.sqrt(2)
    assert moves[2].end == pytest.approx((45 + k, 0, -45 + k))  # beside X90 Z-45 on the 135° line's normal
    assert moves[2].programmed_end == pytest.approx((45, 0, -45))
    assert moves[3].end == pytest.approx((45.5, 0, -45))  # the G0 deselects: tool tip at X91


def test_tx28_case2_g0_without_a_cuts_the_last_block_short() -> None:
    moves, d = run(TX28 + "G0 X91\nG40\nG0 X120 Z10", radius=0.4, quadrant=1)
    assert codes(d) == [("TX-W217", 4)]
    # the 90° vector of the G0: the G1's equidistant meets the G0's equidistant Z-45+0.4
    k = 0.4 / math.sqrt(2)
    z = -44.6
    x = 45 + k - (z - (-45 + k))  # along the 135° line: Δx = −Δz
    assert moves[2].end == pytest.approx((x, 0, z))


def test_tx28_case1_g40_after_a_feed_block_falsifies_it() -> None:
    moves, d = run(TX28 + "G40\nG0 X120 Z10", radius=0.4, quadrant=1)
    assert codes(d) == [("TX-W218", 4)]
    assert moves[2].end == pytest.approx((45, 0, -45))  # the block ends on the tool tip


def test_a_in_g0_against_the_last_direction_is_a_warning() -> None:
    _, d = run(TX28 + "G0 X91 A90\nG40\nG0 X120 Z10", radius=0.4, quadrant=1)
    assert ("TX-W216", 5) in codes(d)


def test_deselection_after_transition_needs_element_plus_nose_plus_0_01() -> None:
    _, d = run("G46\nG0 X30 Z1\nG1 Z0 F0.2\nG1 X40 D2\nG1 Z-2.4\nG0 X50 A180\nG40", radius=0.4, quadrant=1)
    assert codes(d) == [("TX-E222", 5)]
    _, ok = run("G46\nG0 X30 Z1\nG1 Z0 F0.2\nG1 X40 D2\nG1 Z-2.42\nG0 X50 A180\nG40", radius=0.4, quadrant=1)
    assert ok == []


def test_inside_arc_smaller_than_the_nose_radius() -> None:
    # the last element cannot be suppressed: an error
    _, d = run("G46\nG0 X30 Z1\nG1 Z-10 F0.2\nG2 X30.6 Z-10.3 R0.3", radius=0.4, quadrant=1)
    assert ("TX-E214", 4) in codes(d)


def test_inside_fillet_smaller_than_the_nose_radius_is_suppressed() -> None:
    # a fillet R0.2 at a shoulder with nose R0.4: the nose leaves its own radius in the corner
    moves, d = run(
        "G46\nG0 X40 Z1\nG1 Z-10 F0.2\nG2 X40.4 Z-10.2 R0.2\nG1 X50\nG1 Z-30\nG0 X54 A180\nG40",
        radius=0.4,
        quadrant=1,
    )
    assert codes(d) == [("TX-W220", 4)]
    assert [m.end for m in moves if m.line == 3] == [pytest.approx((20.4, 0, -9.8))]  # equidistants meet
    assert all(m.line != 4 for m in moves)


def test_groove_narrower_than_the_nose_is_suppressed() -> None:
    # a groove 0.5 mm wide and 1 mm deep: the nose R0.4 (Ø0.8) cannot enter; its three blocks are
    # suppressed (Satzausblendung, a warning) and the nose passes over at X40 + 2 × 0.4
    moves, d = run(
        "G46\nG0 X40 Z1\nG1 Z-10 F0.2\nG1 X38\nG1 Z-10.5\nG1 X40\nG1 Z-30\nG0 X44 A180\nG40",
        radius=0.4,
        quadrant=1,
    )
    assert sorted(codes(d)) == [("TX-W220", 4), ("TX-W220", 5), ("TX-W220", 6)]
    assert [(m.line, m.end) for m in moves[1:3]] == [
        (3, pytest.approx((20.4, 0, -10))),
        (7, pytest.approx((20.4, 0, -30))),
    ]


def test_groove_wider_than_the_nose_is_machined() -> None:
    moves, d = run(
        "G46\nG0 X40 Z1\nG1 Z-10 F0.2\nG1 X38\nG1 Z-12\nG1 X40\nG1 Z-30\nG0 X44 A180\nG40",
        radius=0.4,
        quadrant=1,
    )
    # the plunge down the groove's right wall is outside the 180° cutting range of P1 (the back of the nose)
    assert codes(d) == [("TX-W225", 4)]
    assert [m.end for m in moves if m.line == 5] == [
        pytest.approx((19.4, 0, -11.6))
    ]  # floor between the walls


@pytest.mark.parametrize(
    ("step", "corner", "end"),
    [
        ("X40.2", (20.1, -10), (20.5, 0, -10)),  # up 0.1: the nose rolls over the step's outer corner
        ("X39.8", (20.0, -10), (20.3, 0, -10 - math.sqrt(0.4**2 - 0.3**2))),  # down 0.1: round the edge
    ],
)
def test_step_smaller_than_the_nose_radius(
    step: str, corner: tuple[float, float], end: tuple[float, float, float]
) -> None:
    moves, d = run(
        f"G46\nG0 X40 Z1\nG1 Z-10 F0.2\nG1 {step}\nG1 Z-20\nG0 X54 A180\nG40", radius=0.4, quadrant=1
    )
    assert codes(d) == [("TX-W220", 4)]
    roll = [m for m in moves if m.kind == "arc"]
    assert len(roll) == 1 and roll[0].center == pytest.approx((corner[0], 0, corner[1]))
    assert roll[0].radius == pytest.approx(0.4) and roll[0].angle < 90
    assert roll[0].end == pytest.approx(end)
    assert all(m.line != 4 for m in moves)


def test_g46_watches_the_cutting_range_of_the_quadrant() -> None:
    # facing down (−X) and then turning (−Z) with an outside tool P1: the face needs the nose on the other
    # side, a change of machining direction without G40
    _, d = run("G46\nG0 X42 Z0\nG1 X0 F0.2\nG1 Z-1\nG1 X40", radius=0.4, quadrant=1)
    assert codes(d) == [("TX-W225", 4)]  # the side comes from the face (nose at +Z), Z-1 needs the other
    _, d2 = run("G42\nG0 X42 Z0\nG1 X20 F0.2\nG1 Z-30", radius=0.4, quadrant=1)
    assert "TX-W225" not in {x.code for x in d2}  # G41/G42: no monitoring


def test_deselection_in_x_needs_twice_the_nose_radius() -> None:
    _, d = run("G46\nG0 X40 Z1\nG1 Z-30 F0.2\nG1 X41\nG40\nG0 X60", radius=0.4, quadrant=1)
    assert codes(d) == [("TX-W218", 4), ("TX-E224", 4)]
    _, ok = run("G46\nG0 X40 Z1\nG1 Z-30 F0.2\nG1 X42\nG40\nG0 X60", radius=0.4, quadrant=1)
    assert codes(ok) == [("TX-W218", 4)]


def test_g40_at_the_end_after_a_feed_block_is_case_1() -> None:
    moves, d = run("G46\nG0 X40 Z1\nG1 Z-30 F0.2\nG40", radius=0.4, quadrant=1)
    assert codes(d) == [("TX-W218", 3)]
    assert moves[-1].end == pytest.approx((20, 0, -30))


def test_srk_switched_inside_a_train_or_a_transition() -> None:
    _, d = run("G0 X40 Z1\nG1 Z-25 F0.2\nG1 A180\nG46\nG1 X60 Z-85 A-45", radius=0.4, quadrant=1)
    assert ("TX-E226", 4) in codes(d)
    _, d2 = run("G46\nG0 X30 Z1\nG1 Z0 F0.2\nG1 X40 D2\nG40\nG1 Z-30", radius=0.4, quadrant=1)
    assert ("TX-E226", 5) in codes(d2)


def test_a_that_contradicts_x_and_z_after_a_known_point() -> None:
    moves, d = run("G0 X20 Z0\nG1 X40 Z-10 A135 F0.2\nG1 X60 Z-20 A120")
    assert codes(d) == [("TX-W227", 3)]  # 135° fits (as does −45°); 120° does not
    assert ends(moves)[-1] == pytest.approx((60, -20))


def test_arc_without_radius_or_centre() -> None:
    _, d = run("G0 X30 Z1\nG1 Z-25 F0.2\nG2 X50 Z-35")
    assert codes(d) == [("TX-E204", 3)]


def test_arc_in_a_train_needs_r_or_p_q() -> None:
    # I, K are relative to the start, and the start is the unknown point
    _, d = run("G0 X20 Z0\nG1 A180 F0.2\nG2 X40 Z-20 I10 K0")
    assert codes(d) == [("TX-E208", 3)]


def test_suppression_right_before_deselection_is_an_error() -> None:
    # the last feed block, a step of 0.1 mm, cannot be followed by the nose R0.4 and G40 comes next
    _, d = run("G46\nG0 X40 Z1\nG1 Z-10 F0.2\nG1 X40.2\nG0 X50 A90\nG40", radius=0.4, quadrant=1)
    assert codes(d) == [("TX-W220", 4), ("TX-E221", 4)]


def test_no_srk_without_nose_radius_keeps_the_tip_path() -> None:
    moves, d = run("G46\nG0 X40 Z1\nG1 Z-30 F0.2", radius=0.0, quadrant=1)
    assert d == []
    assert moves[-1].end == pytest.approx((20, 0, -30))


# -- properties -----------------------------------------------------------------------------------


def _dist_to(m: Move, p: tuple[float, float]) -> float:
    """Distance from plane point p (z, x) to the programmed element of the tip path move m."""
    a, b = (m.start[2], m.start[0]), (m.end[2], m.end[0])
    if m.kind == "arc" and m.center is not None and m.radius is not None and m.angle is not None:
        c = (m.center[2], m.center[0])
        a0 = math.degrees(math.atan2(a[1] - c[1], a[0] - c[0]))
        ap = math.degrees(math.atan2(p[1] - c[1], p[0] - c[0]))
        part = ((a0 - ap) if m.direction == "cw" else (ap - a0)) % 360  # how far along the arc p's ray lies
        if part <= m.angle + 1e-9:
            return abs(math.dist(p, c) - m.radius)
        return min(math.dist(p, a), math.dist(p, b))
    dz, dx = b[0] - a[0], b[1] - a[1]
    n2 = dz * dz + dx * dx
    t = 0.0 if n2 == 0 else max(0.0, min(1.0, ((p[0] - a[0]) * dz + (p[1] - a[1]) * dx) / n2))
    return math.dist(p, (a[0] + t * dz, a[1] + t * dx))


@st.composite
def outside_profiles(draw: st.DrawFn) -> str:
    """A rising outside contour (travel −Z and +X, optional tapers, concave fillets and convex roundings)."""
    x, z = draw(st.floats(5, 30)), 0.0
    blocks = [f"G0 X{2 * x:.9f} Z2", "G1 Z0 F0.2"]
    for _ in range(draw(st.integers(1, 4))):
        length = draw(st.floats(5, 20))
        rise = draw(st.floats(2, 10))
        fillet = draw(st.one_of(st.none(), st.floats(1, 1.9)))
        taper = draw(st.floats(0, 1.5))
        z -= length
        if fillet is not None:
            blocks.append(f"G1 Z{z + fillet:.9f}")
            blocks.append(f"G2 X{2 * (x + fillet):.9f} Z{z:.9f} R{fillet:.9f}")
            x += fillet
        else:
            blocks.append(f"G1 Z{z:.9f}")
        x += rise
        z -= taper
        rounding = draw(st.one_of(st.none(), st.floats(0.5, 1)))  # a convex edge R at the top of the rise
        blocks.append(f"G1 X{2 * x:.9f} Z{z:.9f}" + ("" if rounding is None else f" R{rounding:.9f}"))
    blocks.append(f"G1 Z{z - draw(st.floats(3, 10)):.9f}")
    return "\n".join(blocks)


@settings(max_examples=60, deadline=None)
@given(outside_profiles(), st.floats(0.2, 0.8))
def test_property_nose_centre_stays_at_nose_radius_from_the_contour(program: str, radius: float) -> None:
    contour, d0 = run(program)
    assert d0 == []
    path, d = run("G46\n" + program, radius=radius, quadrant=1)
    assert d == []
    elements = [m for m in contour if m.kind != "rapid"]
    for m in path[1:]:
        for q in m.points(0.001):
            p = (q[2], q[0])
            gap = min(_dist_to(e, p) for e in elements)
            assert gap == pytest.approx(radius, abs=2e-3), (program, radius, m.line, q)
        assert m.programmed_end is not None


@settings(max_examples=40, deadline=None)
@given(outside_profiles(), st.floats(0.2, 0.45))
def test_property_nose_centre_on_the_other_side_with_g41(program: str, radius: float) -> None:
    # G41: the nose left of the travel, below the contour — the corners swap inside and outside
    contour, _ = run(program)
    path, d = run("G41\n" + program, radius=radius, quadrant=0)
    assert d == []
    elements = [m for m in contour if m.kind != "rapid"]
    for m in path[1:]:
        for q in m.points(0.001):
            gap = min(_dist_to(e, (q[2], q[0])) for e in elements)
            assert gap == pytest.approx(radius, abs=2e-3), (program, radius, m.line, q)
    assert path[-1].end[0] == pytest.approx(path[-1].programmed_end[0] - radius)  # type: ignore[index]


def _xz(z: float, x: float) -> str:
    return f"X{2 * x:.9f} Z{z:.9f}"


@settings(max_examples=80, deadline=None)
@given(
    st.tuples(st.floats(-20, 20), st.floats(0, 40)),
    st.floats(5, 30),
    st.floats(0, 360),
    st.floats(5, 30),
    st.floats(0, 360),
    st.sampled_from(["", "D", "D-", "R"]),
    st.floats(0.05, 0.3),
)
def test_property_train_equals_its_explicit_coordinates(
    s: tuple[float, float], l1: float, a1: float, l2: float, a2: float, kind: str, frac: float
) -> None:
    turn = abs(math.sin(math.radians(a2 - a1)))
    if turn < 0.2:
        return  # nearly parallel lines: the train is ill-conditioned
    p = (s[0] + l1 * math.cos(math.radians(a1)), s[1] + l1 * math.sin(math.radians(a1)))
    e = (p[0] + l2 * math.cos(math.radians(a2)), p[1] + l2 * math.sin(math.radians(a2)))
    size = frac * min(l1, l2) * turn
    extra = {"": "", "D": f" D{size:.9f}", "D-": f" D-{size:.9f}", "R": f" R{size:.9f}"}[kind]
    back = (a2 + 180) % 360  # the closing A points back from the known point
    start = f"G0 {_xz(*s)}\n"
    train, d1 = run(start + f"G1 A{a1:.9f}{extra} F0.2\nG1 {_xz(*e)} A{back:.9f}", start=(0, 0))
    explicit, d2 = run(start + f"G1 {_xz(*p)}{extra} F0.2\nG1 {_xz(*e)}", start=(0, 0))
    assert d1 == d2 == []
    assert len(train) == len(explicit)
    for m1, m2 in zip(train, explicit, strict=True):
        assert (m1.kind, m1.line) == (m2.kind, m2.line)
        assert m1.end == pytest.approx(m2.end, abs=1e-6)
        assert (m1.center is None) == (m2.center is None)
        if m1.center is not None:
            assert m1.center == pytest.approx(m2.center, abs=1e-6)


# -- the examples through the pipeline (core.pipeline.run, dialect traub-tx8d) --------------------

SEEDS = Path(__file__).with_name("seeds") / "traub"
NOSE = RunSetup(tools=DEFAULT_TOOLS.with_tool(turning_tool(1, 0.4, 1)))  # T0101: R0.4, quadrant P1

# the files of the contour trains and SRK, with the diagnostics each must give (code, line) under T0101 R0.4 P1
PIPELINE: dict[str, list[tuple[str, int]]] = {
    "tx-17-g0-g1-g2-g3.nc": [],
    "tx-21-geometriezug.nc": [],
    "tx-22-uebergangselemente.nc": [],
    "tx-23-kreise.nc": [],
    "tx-24-h0-h1.nc": [],
    "tx-25-vorlagen.nc": [],
    "tx-27-srk-anwahl.nc": [],
    "tx-28-srk-abwahl-1.nc": [("TX-W218", 7)],
    "tx-28-srk-abwahl-2.nc": [("TX-W217", 7)],
    "tx-28-srk-abwahl-3.nc": [],
    "tx-48-kreis-eingaben.nc": [],
}


def traub(name: str, setup: RunSetup = NOSE) -> list[Move]:
    tp = pipeline_run((SEEDS / name).read_text(encoding="utf-8"), "traub-tx8d", setup)
    assert [(x.code, x.span.line) for x in tp.diagnostics] == PIPELINE[name]
    return tp.moves


def by_line(moves: list[Move], line: int) -> list[Move]:
    return [m for m in moves if m.line == line]


@pytest.mark.parametrize("name", sorted(PIPELINE))
def test_pipeline_example_gives_exactly_its_diagnostics(name: str) -> None:
    traub(name)


@pytest.mark.parametrize("name", sorted(n for n, expected in PIPELINE.items() if not expected))
def test_pipeline_example_without_nose_data_runs_on_the_tool_tip(name: str) -> None:
    # without a nose radius in the set-up G46 changes nothing: every move ends on its programmed point
    tp = pipeline_run((SEEDS / name).read_text(encoding="utf-8"), "traub-tx8d", RunSetup())
    assert [(x.code, x.span.line) for x in tp.diagnostics] == []
    assert all(m.programmed_end == m.end for m in tp.moves)


def test_pipeline_tx17_arcs() -> None:
    moves = traub("tx-17-g0-g1-g2-g3.nc")
    g2, g3 = by_line(moves, 6)[0], by_line(moves, 8)[0]
    assert (g2.direction, g2.center, g2.end) == (
        "cw",
        pytest.approx((20, 0, -15)),
        pytest.approx((20, 0, -25)),
    )
    assert (g3.direction, g3.center, g3.end) == (
        "ccw",
        pytest.approx((20, 0, -50)),
        pytest.approx((30, 0, -50)),
    )


def test_pipeline_tx21_train() -> None:
    moves = traub("tx-21-geometriezug.nc")
    assert [ends([m])[0] for m in moves if 13 <= m.line <= 15] == approx((20, -42.321), (20, -65), (60, -85))
    # first example from the assumed start X40 Z0: the line at 105° meets the line through X100 Z-50 at −30°
    assert ends(by_line(moves, 7)) == approx((42.679, -0.359))


def test_pipeline_tx22_transitions() -> None:
    moves = traub("tx-22-uebergangselemente.nc")
    assert ends(by_line(moves, 7)) == approx((39, 0), (40, -0.5))  # D0.5: X39 Z0 → X40 Z-0.5
    assert by_line(moves, 7)[1].feed == 0.1
    r05 = by_line(moves, 14)[1]
    assert (r05.kind, r05.center, r05.radius) == ("arc", pytest.approx((19.5, 0, -0.5)), pytest.approx(0.5))
    corner_d = by_line(moves, 21)
    p1, p2 = corner_d[1].start, corner_d[1].end
    assert math.dist(p1, p2) == pytest.approx(2)  # D-2: the chamfer's length
    assert ends(by_line(moves, 22)) == approx((86, -35))


def test_pipeline_tx23_three_forms_give_the_same_arc() -> None:
    moves = traub("tx-23-kreise.nc")
    arcs = [m for m in moves if m.kind == "arc"]
    assert len(arcs) == 6
    for arc in arcs[:3]:
        assert (arc.direction, arc.center, arc.end) == (
            "cw",
            pytest.approx((25, 0, -25)),
            pytest.approx((25, 0, -35)),
        )
    for arc in arcs[3:]:
        assert (arc.direction, arc.center) == ("ccw", pytest.approx((15, 0, -35)))


def test_pipeline_tx24_h0_h1() -> None:
    moves = traub("tx-24-h0-h1.nc")
    assert ends(by_line(moves, 6)) == approx((40, -8.404))
    assert ends(by_line(moves, 11)) == approx((40, -47.596))


def test_pipeline_tx25_templates() -> None:
    moves = traub("tx-25-vorlagen.nc")
    assert ends(by_line(moves, 7)) == approx((20, -10))  # line – arc tangential
    assert ends(by_line(moves, 13)) == approx((30, -25.981))  # arc – line tangential
    assert ends(by_line(moves, 19)) == approx((40, -15))  # H0
    assert ends(by_line(moves, 24)) == approx((40, -45))  # H1
    arc_arc = [m for m in moves if m.line in (41, 42)]
    assert [m.direction for m in arc_arc] == ["ccw", "cw"] and arc_arc[0].end == arc_arc[1].start


def test_pipeline_tx27_nose_centre_path() -> None:
    moves = traub("tx-27-srk-anwahl.nc")
    assert by_line(moves, 5)[0].end == pytest.approx((20.4, 0, 1))
    assert by_line(moves, 6)[0].end == pytest.approx((20.4, 0, -30))
    assert by_line(moves, 6)[0].programmed_end == pytest.approx((20, 0, -30))
    chamfer_block = by_line(moves, 13)
    assert [m.kind for m in chamfer_block] == ["feed", "arc", "feed", "arc"]
    assert chamfer_block[2].programmed_end == pytest.approx((20, 0, -2)) and chamfer_block[2].feed == 0.1
    arc = by_line(moves, 22)[0]
    assert arc.end == pytest.approx((15.4, 0, -25.981), abs=TOL) and arc.radius == pytest.approx(30.4)
    assert arc.center == pytest.approx((-15, 0, -25.981), abs=TOL)


def test_pipeline_tx28_deselection_cases() -> None:
    k = 0.4 / math.sqrt(2)
    case1 = by_line(traub("tx-28-srk-abwahl-1.nc"), 7)[-1]
    case2 = by_line(traub("tx-28-srk-abwahl-2.nc"), 7)[-1]
    case3 = by_line(traub("tx-28-srk-abwahl-3.nc"), 7)[-1]
    assert case1.end == pytest.approx((45, 0, -45))  # falsified: the block ends on the tool tip
    assert case2.end == pytest.approx((45 + k - 0.1172, 0, -44.6), abs=TOL)  # cut short by the 90° vector
    assert case3.end == pytest.approx((45 + k, 0, -45 + k))  # complete, on its perpendicular


def test_pipeline_tx48_input_forms() -> None:
    moves = traub("tx-48-kreis-eingaben.nc")
    arcs = [m for m in moves if m.kind == "arc" and m.line <= 21]
    assert [m.direction for m in arcs] == ["cw", "ccw"] * 3
    assert [m.center for m in arcs] == [pytest.approx((25, 0, -25)), pytest.approx((15, 0, -35))] * 3
    assert ends(by_line(moves, 27)) == approx((40, -20))
    assert ends(by_line(moves, 31)) == approx((30, -25.981))
    assert ends(by_line(moves, 37)) == approx((40, -8.404))
    assert ends(by_line(moves, 42)) == approx((40, -47.596))


@st.composite
def any_blocks(draw: st.DrawFn) -> str:
    """Random blocks of every form the stage accepts, sensible or not."""
    num = st.integers(-60, 60).map(float)
    blocks = []
    for _ in range(draw(st.integers(1, 9))):
        code = draw(st.sampled_from(["G0", "G1", "G2", "G3", "G46", "G40", "G41", "G42"]))
        words = [code]
        for address in draw(st.lists(st.sampled_from("XZAURDCPQIKHW"), max_size=5, unique=True)):
            value = draw(num)
            if address == "H":
                value = float(draw(st.integers(0, 1)))
            words.append(f"{address}{value:g}")
        blocks.append(" ".join(words))
    return "\n".join(blocks)


@settings(max_examples=300, deadline=None)
@given(any_blocks(), st.sampled_from([0.0, 0.4, 2.0]), st.integers(0, 4))
def test_property_any_blocks_give_moves_or_diagnostics_never_an_exception(
    program: str, radius: float, quadrant: int
) -> None:
    moves, _ = run(program, radius=radius, quadrant=quadrant)
    for m in moves:
        assert all(math.isfinite(v) for v in m.start + m.end)
        assert m.kind != "arc" or (m.radius is not None and m.radius > 0)


@st.composite
def stepped_profiles(draw: st.DrawFn) -> str:
    """An outside contour of axial lines and radial steps, some steps smaller than the nose."""
    x, z = 20.0, 0.0
    blocks = [f"G0 X{2 * x:.6f} Z2", "G1 Z0 F0.2"]
    for _ in range(draw(st.integers(1, 5))):
        z -= draw(st.floats(2, 10))
        blocks.append(f"G1 Z{z:.6f}")
        x += draw(st.one_of(st.floats(0.02, 0.35), st.floats(-0.35, -0.02), st.floats(1, 5)))
        blocks.append(f"G1 X{2 * x:.6f}")
    blocks.append(f"G1 Z{z - 5:.6f}\nG0 X{2 * x + 10:.6f} A180\nG40")
    return "\n".join(blocks)


@settings(max_examples=60, deadline=None)
@given(stepped_profiles())
def test_property_suppressed_steps_never_gouge(program: str) -> None:
    contour, _ = run(program)
    path, d = run("G46\n" + program, radius=0.4, quadrant=1)
    assert {x.code for x in d} <= {"TX-W220", "TX-W225"}  # a step down is a plunge with the back of P1
    elements = [m for m in contour if m.kind != "rapid"][1:-1]
    for m in path[1:]:
        if m.kind == "rapid":
            continue
        for q in m.points(0.001):
            gap = min(_dist_to(e, (q[2], q[0])) for e in elements)
            assert gap >= 0.4 - 2e-3, (program, m.line, q)


def test_pipeline_json_of_a_compensated_arc() -> None:
    # the contract of `run --json` / POST /api/v1/run: x radius, y 0, z; end = nose centre, programmed_end = contour
    tp = pipeline_run((SEEDS / "tx-27-srk-anwahl.nc").read_text(encoding="utf-8"), "traub-tx8d", NOSE)
    arc = next(m for m in toolpath_json(tp)["moves"] if m["line"] == 22)
    assert arc["kind"] == "arc" and arc["direction"] == "ccw" and arc["plane"] == "G18"
    assert arc["end"] == pytest.approx([15.4, 0, -25.980762], abs=1e-6)
    assert arc["programmed_end"] == pytest.approx([15, 0, -25.980762], abs=1e-6)
    assert arc["center"] == pytest.approx([-15, 0, -25.980762], abs=1e-6) and arc["radius"] == pytest.approx(
        30.4
    )
