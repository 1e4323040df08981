"""Golden traces: every seed program's canonical commands and diagnostics, one line each.

The expected files were checked against the seeds' published numbers (see test_contour.py,
test_seed_arcs.py, test_flow.py); this test keeps every other coordinate from drifting.
Regenerate after an intended change with `UPDATE_GOLDEN=1 pytest tests/test_golden.py` and
review the diff.
"""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from core.pipeline import DIALECTS, run
from core.trace import trace_lines

ROOT = Path(__file__).parents[1]
# the exercises' references run with their exercise's set-up: tests/test_grading.py covers them
PROGRAMS = sorted((ROOT / "tests" / "seeds").rglob("*.nc")) + [
    ROOT / "exercises" / "pal-mill" / "nuten-demo.nc"
]
GOLDEN = Path(__file__).with_name("golden")


def render(path: Path) -> str:
    """The trace of a program, read in the dialect its folder is named after (PAL milling otherwise)."""
    folder = {"traub": "traub-tx8d"}.get(path.parent.name, path.parent.name)
    dialect = folder if folder in DIALECTS else "pal-mill"
    tp = run(path.read_text(encoding="utf-8"), dialect)
    lines = trace_lines(tp, DIALECTS[dialect].lathe) + [
        f"! {d.code} {d.span.line}:{d.span.column}" for d in tp.diagnostics
    ]
    return "\n".join(lines) + "\n"


@pytest.mark.parametrize("path", PROGRAMS, ids=[p.stem for p in PROGRAMS])
def test_golden_trace(path: Path) -> None:
    expected = GOLDEN / f"{path.parent.name}--{path.stem}.trace"
    actual = render(path)
    if os.environ.get("UPDATE_GOLDEN") == "1":
        expected.write_text(actual, encoding="utf-8")
    assert expected.exists(), f"no golden trace for {path.name}: run with UPDATE_GOLDEN=1"
    assert actual == expected.read_text(encoding="utf-8")
