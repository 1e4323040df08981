"""No input crashes or hangs the pipeline: every limit is explicit and reported."""

from __future__ import annotations

import random
from pathlib import Path

from core.interpreter.state import RunSetup
from core.limits import DEFAULT_LIMITS, Limits
from core.pipeline import run
from tests.conftest import codes


def test_empty_program() -> None:
    assert codes(run("")) == []  # nothing written yet: no "M30 fehlt" in an empty editor


def test_binary_garbage() -> None:
    rnd = random.Random(7)
    data = bytes(rnd.randrange(256) for _ in range(20_000)).decode("cp1252", errors="replace")
    tp = run(data)
    assert tp.diagnostics and all(d.span.line >= 1 for d in tp.diagnostics)


def test_ten_megabyte_line_is_rejected_with_a_diagnostic() -> None:
    assert codes(run("G1 X" + "1" * 10_000_000)) == [("PAL-E005", 1)]


def test_overlong_block_is_reported_and_skipped() -> None:
    tp = run("G0 X1\nG1 X" + "1" * 5000 + "\nM30")
    assert ("PAL-E004", 2) in codes(tp)


def test_a_million_blocks_end_in_limit_diagnostics() -> None:
    tp = run("Y1\n" * 1_000_000, setup=RunSetup(limits=Limits(max_blocks=20_000, max_executed_blocks=10_000)))
    found = dict(codes(tp))
    assert found["PAL-E006"] == 20_001 and found["PAL-E013"] == 10_001


def test_too_many_diagnostics_are_capped() -> None:
    tp = run("Q1\n" * 5000, setup=RunSetup(limits=Limits(max_diagnostics=100)))
    assert len(tp.diagnostics) == 100 and tp.diagnostics[-1].code == "PAL-E012"


def test_deeply_nested_expressions() -> None:
    assert ("PAL-E014", 1) in codes(run("P1=" + "-" * 900 + "1\nM30"))
    assert codes(run("P1=" + "(" * 400 + "1" + ")" * 400 + "\nM30")) == []


def test_infinite_and_huge_numbers() -> None:
    assert ("PAL-E015", 1) in codes(run("G0 X" + "9" * 400 + "\nM30"))


def test_a_million_blocks_with_the_default_limits() -> None:
    found = dict(codes(run("X1\n" * 1_000_000)))
    assert found["PAL-E006"] == DEFAULT_LIMITS.max_blocks + 1
    assert "PAL-W102" not in found  # the lines not read may hold the M30


def test_an_endless_loop_with_the_default_limits() -> None:
    assert dict(codes(run("N10 X1\nN20 G29 N10\n")))["PAL-E013"] == 1  # the 100,001st block


def test_a_memo_gives_the_same_result_as_a_fresh_run() -> None:
    """The live editor re-runs a document with its memo; every edit must give exactly a fresh run's result."""
    from core.pipeline import Memo
    from core.toolpath import Move

    base = (Path(__file__).with_name("seeds") / "pal-15-g45-g46.nc").read_text(encoding="utf-8").splitlines()
    memo = Memo()
    edits = [
        base,
        base[:6] + ["N55 G1 X20 RN3"] + base[6:],
        [*base[:3], "N35 G91 G0 X1", *base[3:]],
        [line.replace("RN10", "RN12") for line in base],
        base[:-1],
        base,
    ]
    for lines in edits:
        text = "\n".join(lines)
        fresh, memoised = run(text), run(text, memo=memo)
        assert [m.to_json() for m in memoised.moves if isinstance(m, Move)] == [
            m.to_json() for m in fresh.moves
        ]
        assert [d.to_json() for d in memoised.diagnostics] == [d.to_json() for d in fresh.diagnostics]
    assert len(memo.lines.lines) == len(base)  # the memo holds this program's lines, no more
