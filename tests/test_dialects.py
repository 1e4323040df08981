"""SINUMERIK 808D ISO and Beckhoff TwinCAT: the seeds' programs and the geometry they state."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from core.pipeline import run
from core.toolpath import Move
from tests.conftest import codes, errors

BECKHOFF = Path(__file__).with_name("seeds") / "beckhoff"
READY = "T1 M6\nS1000 F100 M3\nG0 X0 Y0 Z0\n"


def iso(program: str) -> list[Move]:
    tp = run(READY + program + "\nM30", "sinumerik-iso")
    assert errors(tp) == []
    return tp.moves[1:]


# -- SINUMERIK 808D ISO -------------------------------------------------------------------------------


def test_g18_arc_with_k_and_i() -> None:
    (arc,) = iso("G18 G02 Z10 X10 K10 I0")
    assert (arc.plane, arc.direction) == ("G18", "cw")
    assert arc.end == pytest.approx((10, 0, 10)) and arc.center == pytest.approx((0, 0, 10))
    assert arc.radius == pytest.approx(10) and arc.angle == pytest.approx(90)


def test_g19_arc_with_j_and_k() -> None:
    (arc,) = iso("G19 G03 Y10 Z10 J0 K10")
    # in the Y-Z plane seen from +X: from Y0 Z0 about Y0 Z10 counter-clockwise to Y10 Z10
    assert (arc.plane, arc.direction) == ("G19", "ccw")
    assert arc.end == pytest.approx((0, 10, 10)) and arc.center == pytest.approx((0, 0, 10))
    assert arc.angle == pytest.approx(90)


def test_g17_arc_with_r_plus_and_r_minus() -> None:
    short, long = iso("G17 G02 X20 Y0 R10\nG02 X0 Y0 R-10.5")
    assert short.center == pytest.approx((10, 0, 0)) and short.angle == pytest.approx(180)
    assert long.angle > 180 and long.radius == pytest.approx(10.5)


def test_arc_outside_the_selected_plane_takes_the_plane_of_its_centre_words() -> None:
    (arc,) = iso("G17 G02 Z10 X10 K10")  # K cannot belong to G17: the arc lies in Z-X (I omitted = 0)
    assert (
        arc.plane == "G18"
        and arc.end == pytest.approx((10, 0, 10))
        and arc.center == pytest.approx((0, 0, 10))
    )


def test_r_arc_leaves_the_selected_plane_only_where_r_is_impossible_in_it() -> None:
    (helix,) = iso("G17 G02 Z10 X10 R10")  # possible in X-Y: a helix in G17, Y omitted = current position
    assert (
        helix.plane == "G17" and helix.end == pytest.approx((10, 0, 10)) and helix.angle == pytest.approx(60)
    )
    (arc,) = iso("G17 G02 Z10 X0 R5")  # in X-Y the end equals the start: the arc lies in Z-X
    assert (
        arc.plane == "G18" and arc.end == pytest.approx((0, 0, 10)) and arc.center == pytest.approx((0, 0, 5))
    )


def test_full_circle_and_helix_in_g19() -> None:
    (arc,) = iso("G19 G02 J10 K0 X-5")
    assert arc.plane == "G19" and arc.angle == pytest.approx(360)
    assert arc.end == pytest.approx((-5, 0, 0)) and arc.center == pytest.approx((0, 10, 0))


def test_compensation_in_the_plane_g18() -> None:
    tp = run(
        "T1 M6\nS1000 F100 M3\nG0 X0 Y0 Z-20\nG18 G41 G1 Z0 X0\nG1 Z50\nG40 G0 X100\nM30", "sinumerik-iso"
    )
    assert errors(tp) == []
    line = next(m for m in tp.moves if m.line == 5)
    # along +Z in the Z-X plane (u = Z, v = X), the left side is +X: the Ø25 tool runs at X12.5
    assert line.start == pytest.approx((12.5, 0, 0)) and line.end == pytest.approx((12.5, 0, 50))


@pytest.mark.parametrize(
    "block,code",
    [
        ("G02 X10 Y0 I3 J0", "ISO-E1202"),  # centre and end point disagree
        ("G02 X10 Y0 R2", "ISO-E1201"),  # radius too small
        ("G18 G02 Z10 X10 J5 R5", "ISO-E1204"),  # J is not a centre address of Z-X
        ("G01 U10", "ISO-E1003"),  # no fifth axis on the trainer's machine
    ],
)
def test_iso_errors(block: str, code: str) -> None:
    assert (code, 4) in codes(run(READY + block + "\nM30", "sinumerik-iso"))


def test_iso_rejects_pal_only_addresses() -> None:
    assert ("ISO-E1003", 4) in codes(run(READY + "G01 XI10\nM30", "sinumerik-iso"))


# -- Beckhoff ----------------------------------------------------------------------------------------------


def beckhoff(name: str) -> list[Move]:
    tp = run((BECKHOFF / name).read_text(encoding="utf-8"), "beckhoff")
    assert errors(tp) == []
    return tp.moves


def path(moves: list[Move]) -> list[tuple[str, tuple[float, ...], float]]:
    return [(m.kind, tuple(round(v, 3) for v in m.end[:2]), m.feed) for m in moves]


def test_bk01_chamfer_20_at_a_right_angle() -> None:
    moves = beckhoff("bk-01-g301-fase.nc")
    chamfer = next(m for m in moves if m.line == 4)
    assert chamfer.start[:2] == pytest.approx((100, 80)) and chamfer.end[:2] == pytest.approx((80, 100))
    assert (chamfer.kind, chamfer.feed) == ("feed", 200)  # G01 before it: the programmed feed
    assert next(m for m in moves if m.line == 5).end[:2] == pytest.approx((40, 100))


def test_bk02_pocket_with_r20_corners_in_both_variants() -> None:
    standard = beckhoff("bk-02-g302-tasche.nc")
    alternative = beckhoff("bk-02-g302-tasche-frc.nc")
    assert path(standard) == path(alternative)
    arcs = [m for m in standard if m.kind == "arc"]
    assert [tuple(round(c, 3) for c in (m.center or ())[:2]) for m in arcs] == [
        (180, 20),
        (180, 80),
        (20, 80),
        (20, 20),
    ]
    assert {m.radius for m in arcs} == {20} and {m.feed for m in arcs} == {150}
    assert {m.feed for m in standard if m.kind == "feed"} == {200}
    assert standard[-1].end[:2] == pytest.approx((40, 0))


def test_bk03_plane_change_before_or_after_the_g301_block_gives_the_same_result() -> None:
    a, b = beckhoff("bk-03-ebene-a.nc"), beckhoff("bk-03-ebene-b.nc")
    assert [(m.start, m.end) for m in a] == [(m.start, m.end) for m in b]
    chamfer = a[2]
    assert math.dist(chamfer.start, (20, 0, 0)) == pytest.approx(5)  # 5 mm from the corner on each line
    assert math.dist(chamfer.end, (20, 0, 0)) == pytest.approx(5)


def test_bk04_valued_g301_g302() -> None:
    moves = beckhoff("bk-04-g301-g302-wert.nc")
    by_line = [(m.line, m.kind, tuple(round(v, 3) for v in m.end[:2]), m.feed) for m in moves[1:]]
    assert by_line == [
        (2, "feed", (80, 0), 2000),
        (2, "feed", (100, 20), 500),  # chamfer X80 Y0 → X100 Y20
        (3, "feed", (100, 80), 2000),
        (3, "arc", (80, 100), 1000),  # rounding about X80 Y80
        (4, "feed", (20, 100), 2000),
        (4, "feed", (0, 80), 500),
        (5, "feed", (0, 20), 2000),
        (5, "arc", (20, 0), 1000),
        (6, "feed", (40, 0), 2000),
    ]


def test_bk05_chamfer_by_width_and_by_length() -> None:
    moves = beckhoff("bk-05-chr-chf-rnd.nc")
    chamfer = next(m for m in moves if m.line == 4 and m.feed == 500)
    leg = 35 / math.sqrt(2)
    assert chamfer.start[:2] == pytest.approx((leg, 100), abs=1e-3)  # X24.749 Y100
    assert chamfer.end[:2] == pytest.approx((0, 100 - leg), abs=1e-3)  # X0 Y75.251
    assert math.dist(chamfer.start, chamfer.end) == pytest.approx(35)
    first = next(m for m in moves if m.line == 2 and m.feed == 500)
    assert first.start[:2] == pytest.approx((180, 0)) and first.end[:2] == pytest.approx((200, 20))


def test_first_g301_needs_a_size() -> None:
    tp = run("G0 X0 Y0\nG1 X10 F100\nG301\nG1 Y10\nM30", "beckhoff")
    assert ("BK-E1501", 3) in codes(tp)
    assert len(tp.moves) == 2  # decoding stops at the bad block


def test_beckhoff_blend_that_does_not_fit() -> None:
    tp = run("G0 X0 Y0\nG1 X10 F100\nG302 I50\nG1 Y10\nM30", "beckhoff")
    assert ("BK-E1208", 3) in codes(tp)


def test_cli_dialect_option(tmp_path: Path) -> None:
    from core.cli import main

    assert main(["check", str(BECKHOFF / "bk-04-g301-g302-wert.nc"), "--dialect", "beckhoff"]) == 0
    assert main(["check", str(BECKHOFF / "bk-04-g301-g302-wert.nc")]) == 1  # not PAL


def test_beckhoff_element_after_g00_is_run_at_rapid() -> None:
    tp = run("G00 X0 Y0 Z0\nG00 X50\nG301 I10\nG00 Y50\nM30", "beckhoff")
    assert errors(tp) == []
    chamfer = next(m for m in tp.moves if m.line == 3)
    assert chamfer.kind == "rapid"
    assert chamfer.start[:2] == pytest.approx((40, 0)) and chamfer.end[:2] == pytest.approx((50, 10))
