"""Issue 12, part 2: a G23 section ends whatever its last block does (a call, a repeat, a failed call)."""

from __future__ import annotations

import pytest

from core.pipeline import run
from core.toolpath import Toolpath
from tests.conftest import codes

READY = "N10 T1 TC1 M6\nN20 S1000 F200 M3\n"


def xs(tp: Toolpath, line: int) -> list[tuple[float, float]]:
    """(start X, end X) of the moves line `line` made, in order."""
    return [(m.start[0], m.end[0]) for m in tp.moves if m.line == line]


def test_examiner_section_ending_with_a_call_runs_twice_then_m30() -> None:
    text = "N30 G0 X0 Y0 Z2\nN40 G22 L400\nN50 G23 N40 N40 H1\nN60 M30\n%L400\nN1 G91\nN2 G1 X5\nN3 G90\nN4 M17\n"
    tp = run(text)
    found = [c for c, _ in codes(tp)]
    assert "PAL-E013" not in found and "PAL-W102" not in found  # it ends, at M30
    assert xs(tp, 7) == [(0, 5), (5, 10)]  # L400 once, plus one repetition
    assert tp.final_position == pytest.approx((10, 0, 2))


def test_section_ending_with_a_call_run_twice_by_h() -> None:
    text = (
        READY + "N30 G0 X0 Y0 Z2\nN40 G22 L400 H2\nN50 G23 N40 N40 H1\nN60 M30\n"
        "%L400\nN1 G91\nN2 G1 X5\nN3 G90\nN4 M17\n"
    )
    tp = run(text)
    assert codes(tp) == []
    assert xs(tp, 9) == [(0, 5), (5, 10), (10, 15), (15, 20)]  # (1 + 1 repetition) × H2


def test_section_ending_with_a_call_of_a_subprogram_without_m17() -> None:
    text = (
        READY + "N30 G0 X0 Y0 Z2\nN40 G22 L400\nN50 G23 N40 N40 H2\nN60 M30\n"
        "%L400\nN1 G91\nN2 G1 X5\nN3 G90\n"
    )
    tp = run(text)
    assert [c for c, _ in codes(tp)] == ["PAL-E409"]  # once, though it happens three times
    assert xs(tp, 9) == [(0, 5), (5, 10), (10, 15)]  # once plus two repetitions


def test_section_ending_with_a_call_inside_the_section() -> None:
    # the call in the middle already worked; it must keep working
    text = (
        READY + "N30 G0 X0 Y0 Z2\nN40 G22 L400\nN45 G1 Y10\nN46 G0 Y0\nN50 G23 N40 N46 H1\nN60 M30\n"
        "%L400\nN1 G91\nN2 G1 X5\nN3 G90\nN4 M17\n"
    )
    tp = run(text)
    assert codes(tp) == []
    assert xs(tp, 11) == [(0, 5), (5, 10)]


def test_section_ending_with_a_g23_repeat() -> None:
    # N40 runs twice by the inner G23 in each of the two runs of the outer section N40–N50
    text = READY + "N30 G0 X0 Y0 Z2\nN40 G91 G1 X5\nN50 G23 N40 N40 H1\nN60 G23 N40 N50 H1\nN70 G90 M30\n"
    tp = run(text)
    assert codes(tp) == []
    assert xs(tp, 4) == [(0, 5), (5, 10), (10, 15), (15, 20)]


def test_section_ending_with_a_call_of_a_missing_subprogram_still_ends() -> None:
    text = READY + "N30 G0 X0 Y0 Z2\nN40 G91 G1 X5\nN50 G22 L999\nN60 G23 N40 N50 H1\nN70 G90 M30\n"
    tp = run(text)
    assert codes(tp) == [("PAL-E401", 5)]
    assert xs(tp, 4) == [(0, 5), (5, 10)]


def test_section_in_a_subprogram_ending_with_a_call() -> None:
    text = (
        READY + "N30 G0 X0 Y0 Z2\nN40 G22 L300\nN60 M30\n"
        "%L300\nN1 G22 L400\nN2 G23 N1 N1 H1\nN3 M17\n"
        "%L400\nN1 G91\nN2 G1 X5\nN3 G90\nN4 M17\n"
    )
    tp = run(text)
    assert codes(tp) == []
    assert xs(tp, 12) == [(0, 5), (5, 10)]
