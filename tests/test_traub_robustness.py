"""TRAUB: no input crashes or hangs the run; limits end endless sections and deep calls with a diagnostic."""

from __future__ import annotations

import random

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from core.interpreter.state import RunSetup
from core.limits import DEFAULT_LIMITS, Limits, work_ceiling
from core.pipeline import run
from tests.conftest import codes

TOKENS = [
    "G0",
    "G1",
    "G2",
    "G3",
    "G4",
    "G9",
    "G22",
    "G24",
    "G26",
    "G28",
    "G40",
    "G41",
    "G46",
    "G53",
    "G59",
    "G71",
    "G92",
    "G96",
    "G97",
    "G201",
    "M3",
    "M4",
    "M8",
    "M30",
    "M99",
    "M6",
    "M13",
    "M31",
    "X",
    "U",
    "Z",
    "W",
    "A",
    "R",
    "P",
    "Q",
    "I",
    "K",
    "D",
    "C",
    "H",
    "F",
    "E",
    "S",
    "V",
    "T",
    "B",
    "L1",
    "L2",
    "N10",
    "N20",
    "O8000",
    "%",
    "/",
    "(",
    ")",
    "[",
    "]",
    "=",
    "-",
    "+",
    "*",
    "0",
    "5",
    "12,5",
    "-30",
    "0.4",
    "1000",
    " ",
    " ",
    "\n",
    "\n",
    "\n",
]


@settings(max_examples=200, deadline=None)
@given(st.lists(st.sampled_from(TOKENS), max_size=80))
def test_any_sequence_of_traub_words_runs_without_raising(tokens: list[str]) -> None:
    tp = run("".join(tokens), "traub-tx8d", RunSetup(limits=Limits(max_executed_blocks=2000)))
    assert all(d.span.line >= 1 and d.message and d.message_en for d in tp.diagnostics)
    assert len(tp.line_states) == len(tp.line_positions)


def test_binary_garbage_in_traub() -> None:
    rnd = random.Random(16)
    data = bytes(rnd.randrange(256) for _ in range(20_000)).decode("cp1252", errors="replace")
    tp = run(data, "traub-tx8d")
    assert tp.diagnostics


def test_a_section_that_calls_itself_stops_at_the_nesting_limit() -> None:
    tp = run("N10 G0 X40 Z2\nN20 G22 P10 Q20\nM30", "traub-tx8d")
    assert ("TX-E302", 2) in codes(tp)


def test_endless_repeats_end_at_the_executed_block_limit() -> None:
    subs = "%\nO8000\nG22 A8001 H9999\nM99\n%\n%\nO8001\nG0 X40 Z2\nG0 X50\nM99\n%\n"
    tp = run("G22 A8000 H9999\nM30\n" + subs, "traub-tx8d", RunSetup(limits=Limits(max_executed_blocks=5000)))
    assert any(c == "TX-E1013" for c, _ in codes(tp))


def test_huge_values_are_reported_not_computed() -> None:
    tp = run("G96 V200 T0101 M4\nG0 X" + "9" * 400 + " Z2\nM30", "traub-tx8d")
    assert codes(tp) == [("TX-E1015", 2)]
    tp = run("L1 = 99999999999999999999\nG0 X L1 Z2\nM30", "traub-tx8d")
    assert any(c == "TX-E1015" for c, _ in codes(tp))


@pytest.mark.parametrize(
    "program",
    [
        "G97 S500 T0101 M3\nN10 G0 X40 Z2\nN20 G1 Z-5 F0.1\nG22 P10 Q20 H9999\nM30",
        "G22 A8000 H9999\nM30\n%\nO8000\nG22 A8001 H9999\nM99\n%\n%\nO8001\nG201 \nM99\n%\n%\nO9801\nG0 X40 Z2\nG0 X50\nM99\n%",
        "L1 = 1\nN10 L1 = [" + "+".join(["L1*2"] * 40) + "]\nN20 G22 P10 Q10 H9999\nM30",
        "N10 F0.1\nN20 G22 P10 Q10 H9999\nN30 G22 P10 Q20 H9999\nM30",
    ],
    ids=["section-moves", "nested-macros", "arithmetic", "blocks-without-motion"],
)
def test_small_programs_finish_within_the_work_budget(program: str) -> None:
    assert len(program) < 300
    tp = run(program, "traub-tx8d")
    assert all(w <= c for w, c in zip(tp.work, work_ceiling(DEFAULT_LIMITS), strict=True))
    assert any(c in ("TX-E1013", "TX-E1016", "TX-E1017") for c, _ in codes(tp))
