"""The seed's G2 and G3 examples: the three printed forms of N70 describe one arc (oracle: examples.md PAL-05/06)."""

from __future__ import annotations

import pytest

from tests.conftest import SeedReader, errors

TOL = 0.001

G2_FORMS = ["N70 G2 X56.4 Y10 I-20 J6.4", "N70 G2 X56.4 Y10 IA50 JA30", "N70 G2 X56.4 Y10 R21"]
G3_FORMS = ["N70 G3 X70 Y23.6 I-6.4 J20", "N70 G3 X70 Y23.6 IA50 JA30", "N70 G3 X70 Y23.6 R21"]


def _arc(name: str, n70: str, compensation: str) -> object:
    # Radius compensation is a later stage: drop G41/G42 to run the programmed contour itself.
    text = SeedReader.text(name).replace(compensation + " ", "")
    lines = [n70 if ln.startswith("N70 ") else ln for ln in text.splitlines()]
    from core.pipeline import run

    tp = run("\n".join(lines))
    assert errors(tp) == []
    (arc,) = [m for m in tp.moves if m.kind == "arc"]
    assert arc.line == 8
    return arc


@pytest.mark.parametrize("n70", G2_FORMS)
def test_g2_example_forms_give_the_same_arc(n70: str) -> None:
    arc = _arc("pal-05-g2-kreisbogen.nc", n70, "G41")
    assert arc.direction == "cw"
    assert arc.start == pytest.approx((70, 23.6, -2), abs=TOL)
    assert arc.end == pytest.approx((56.4, 10, -2), abs=TOL)
    assert arc.center == pytest.approx((50, 30, -2), abs=TOL)
    assert arc.radius == pytest.approx(21, abs=TOL)
    assert arc.angle == pytest.approx(54.511, abs=0.005)


@pytest.mark.parametrize("n70", G3_FORMS)
def test_g3_example_forms_give_the_same_arc(n70: str) -> None:
    arc = _arc("pal-06-g3-kreisbogen.nc", n70, "G42")
    assert arc.direction == "ccw"
    assert arc.start == pytest.approx((56.4, 10, -2), abs=TOL)
    assert arc.end == pytest.approx((70, 23.6, -2), abs=TOL)
    assert arc.center == pytest.approx((50, 30, -2), abs=TOL)
    assert arc.radius == pytest.approx(21, abs=TOL)
    assert arc.angle == pytest.approx(54.511, abs=0.005)


def test_r21_variant_centre_matches_the_spec_derivation() -> None:
    arc = _arc("pal-05-g2-kreisbogen.nc", G2_FORMS[2], "G41")
    assert arc.center[0] == pytest.approx(49.99924, abs=1e-5)
    assert arc.center[1] == pytest.approx(30.00076, abs=1e-5)


def test_g2_example_as_printed_runs_with_compensation(seed: type[SeedReader]) -> None:
    tp = seed.run("pal-05-g2-kreisbogen.nc")
    assert errors(tp) == []
    arcs = [m for m in tp.moves if m.kind == "arc"]
    # the contour arc R21 becomes R21 + 12.5 about the same centre (tool left, outside of the arc)
    (contour,) = [
        a for a in arcs if a.line == 8 and a.center is not None and a.center[:2] == pytest.approx((50, 30))
    ]
    assert contour.radius == pytest.approx(33.499, abs=TOL)
    assert contour.programmed_end == pytest.approx((56.4, 10, -2), abs=TOL)
    assert tp.final_position == (250, 150, 250)


def test_g40_figure_runs_without_error_and_mills_the_programmed_contour(seed: type[SeedReader]) -> None:
    tp = seed.run("pal-12-g40.nc")
    assert errors(tp) == []
    feeds = [(m.kind, m.end) for m in tp.moves if m.kind != "rapid"]
    assert feeds[0] == ("feed", (15, 15, 2))
    arc = next(m for m in tp.moves if m.kind == "arc")
    assert arc.direction == "cw"
    assert arc.center == pytest.approx((35, 75, -10))
    assert arc.radius == pytest.approx(20)
    assert arc.angle == pytest.approx(180)
    assert tp.final_position == (-10, 50, 5)
