"""How fast runaway programs end, and how large their answers get: the budgets of core/limits.py.

For each program: the CPU time (best of 3) until its diagnostic for parse + interpret, the size of its
JSON answer (POST /api/v1/run) and the time of the 3D view's drawing. Targets (issue 13): under a
second each with the default limits (the server's), answers under 5 MB.
Run from the repository root: python bench/limits.py
"""

from __future__ import annotations

import json
import sys
import time
from collections.abc import Callable
from functools import partial
from pathlib import Path
from typing import TypeVar

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from core.exercises import builtin_exercises
from core.grading import grade
from core.limits import DEFAULT_LIMITS
from core.pipeline import drawing, run, toolpath_json

CONTOUR = "N10 T1 TC1 M6\nN20 F250 S2000 M3\nN30 G0 X-10 Y-50 Z2\nN40 G41 G1 X15 Y-15\n"
PROGRAMS: dict[str, str | tuple[str, str]] = {  # name: program (PAL) or (dialect, program)
    "self-calling subprogram": "N10 G22 L1\nN20 M30\n%L1\nN10 G22 L1\nN20 M17\n",
    "endless G29 loop (1 block)": "N10 G29 N10\nN20 M30\n",
    "endless G29 loop with a counter": "N10 P1=0\nN20 P1=P1+1\nN30 G29 N20\nN40 M30\n",
    "endless G29 loop with moves": "N10 T1 M6\nN15 S100 F100 M3\nN20 G1 X10\nN30 G1 X0\nN40 G29 N20\nN50 M30\n",
    "loop of 50 m full circles": "N10 T1 M6\nN20 S1000 F100 M3\nN30 G0 X0 Y0 Z2\nN40 G2 X0 Y0 I50000 J0\n"
    "N50 G29 N40\nN60 M30\n",
    "compensated contour with RN in a loop": CONTOUR + "N60 G1 X15 Y75 RN5\nN70 G1 X55 Y75 RN-2\n"
    "N80 G1 X55 Y-15 RN3\nN85 G1 X15 Y-15\nN90 G29 N60\nN100 M30\n",
    "G41/G42 switched in a loop": CONTOUR
    + "N50 G1 X20 Y20\nN60 G42 G1 X1 Y1\nN70 G1 X5 Y9\nN80 G41 G1 X15 Y-15\n"
    "N90 G29 N50\nN100 M30\n",
    "arithmetic block in a loop": "N10 P1=" + "+".join(["P1*2"] * 40) + "\nN20 G29 N10\nN30 M30\n",
    "unassigned parameters in a loop": "N10 P1="
    + "+".join(f"P{900 + i}" for i in range(40))
    + "\nN20 G29 N10\nN30 M30\n",
    "subprogram called 9999 times": "N10 T1 M6\nN20 S100 F100 M3\nN30 G22 L1 H9999\nN40 M30\n"
    "%L1\nN10 G1 XI1\nN20 G1 YI1\nN30 M17\n",
    "7-line loop of moves (21 MB before)": "N10 T1 M6\nN20 S1000 F100 M3\nN30 G0 X0 Y0 Z2\nN40 G1 X10\nN50 G1 X0\n"
    "N60 G29 N40\nN70 M30\n",
    "200,000 characters of bad lines": "T1 M6\nS100 F100 M3\n" + "X1,5\n" * 39_990,
    "TRAUB: endless section repeat": (
        "traub-tx8d",
        ("G97 S500 T0101 M3\nN10 G0 X40 Z2\nN20 G1 Z-5 F0.1\nG22 P10 Q20 H9999\nM30"),
    ),
    "TRAUB: nested macros": (
        "traub-tx8d",
        (
            "G22 A8000 H9999\nM30\n%\nO8000\nG22 A8001 H9999\nM99\n%\n%\nO8001\n"
            "G201 \nM99\n%\n%\nO9801\nG0 X40 Z2\nG0 X50\nM99\n%"
        ),
    ),
}
# grading a loop of 50 m circles: the grader looks at a bounded number of chords per arc
GRADED = (
    "pal-01-g1-gerade",
    "N10 T1 M6\nN20 S1000 F100 M3\nN30 G0 X0 Y0 Z2\nN40 G2 X0 Y0 I50000 J0\nN50 G29 N40\nN60 M30\n",
)
TARGET_SECONDS = 1.0
TARGET_BYTES = 5_000_000
T = TypeVar("T")


def best_cpu(fn: Callable[[], T], repeats: int = 3) -> tuple[float, T]:
    """The least CPU time of this thread over `repeats` calls (other processes on the machine count less)."""
    best = float("inf")
    for _ in range(repeats):
        t = time.thread_time()
        result = fn()
        best = min(best, time.thread_time() - t)
    return best, result


def main() -> None:
    print(f"limits: {DEFAULT_LIMITS}\n")
    print(f"{'program':40s} {'run ms':>8s} {'answer MB':>10s} {'draw ms':>8s}  diagnostics")
    worst, largest = 0.0, 0
    for name, entry in PROGRAMS.items():
        dialect, program = entry if isinstance(entry, tuple) else ("pal-mill", entry)
        seconds, tp = best_cpu(partial(run, program, dialect))
        size = len(json.dumps(toolpath_json(tp)).encode())
        draw, _ = best_cpu(partial(drawing, tp, 0.05))
        codes = sorted({d.code for d in tp.diagnostics})
        worst, largest = max(worst, seconds, draw), max(largest, size)
        print(f"{name:40s} {seconds * 1000:8.1f} {size / 1e6:10.2f} {draw * 1000:8.1f}  {', '.join(codes)}")
    slug, graded = GRADED
    exercise = builtin_exercises()[slug]
    seconds, _ = best_cpu(partial(grade, exercise, graded), repeats=1)
    worst = max(worst, seconds)
    print(f"{'grading the loop of 50 m circles':40s} {seconds * 1000:8.1f}")
    ok = worst < TARGET_SECONDS and largest < TARGET_BYTES
    print(
        f"\nslowest: {worst * 1000:.1f} ms (target < {TARGET_SECONDS * 1000:.0f} ms), largest answer "
        f"{largest / 1e6:.2f} MB (target < {TARGET_BYTES / 1e6:.0f} MB) {'PASS' if ok else 'FAIL'}"
    )


if __name__ == "__main__":
    main()
