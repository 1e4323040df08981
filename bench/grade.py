"""Speed of the grader: `core.grading.grade` of built-in exercises, the reference and typical wrong submissions.

Run from the repository root:

    python bench/grade.py            # best of 5
    python bench/grade.py --quick    # best of 2

For each case it prints the best wall time of one whole grade (both programs interpreted and simulated on the
exercise's stock or blank, every criterion judged, the cause of a lost criterion searched). The exercise objects
are loaded once, before timing. This is a benchmark that prints figures, not a test.
"""

from __future__ import annotations

import argparse
import datetime
import gc
import os
import platform
import sys
import time

try:
    import core  # noqa: F401
except ImportError:  # run as `python bench/grade.py` without an installed package
    sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

from core.exercises import builtin_exercises
from core.grading import grade

# (exercise, what, edits of the reference: (old text, new text) …); no edits: the reference itself
CASES: list[tuple[str, str, tuple[tuple[str, str], ...]]] = [
    ("pal-05-g2-kreisbogen", "reference", ()),
    (
        "pal-05-g2-kreisbogen",
        "G41 forgotten, G3 for G2",
        (("N40 G41 G0 X70 Y84", "N40 G0 X70 Y84"), ("N70 G2 X56.4", "N70 G3 X56.4")),
    ),
    ("pal-16-g47-g48", "reference", ()),
    ("traub-01-srk-fase", "reference", ()),
    ("traub-01-srk-fase", "Ø39 for Ø40", (("G1 X40 D2", "G1 X39 D2"),)),
    ("traub-10-schruppen-g71-g88", "reference", ()),
]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="best of 2 instead of 5")
    args = parser.parse_args()
    repeats = 2 if args.quick else 5
    exercises = builtin_exercises()
    print(
        f"# grade, {datetime.date.today()}, CPython {platform.python_version()}, {platform.machine()}, "
        f"{os.cpu_count()} cores, best of {repeats}"
    )
    print("| Exercise | Submission | Score | Grade |")
    print("|---|---|---:|---:|")
    for eid, what, edits in CASES:
        ex = exercises[eid]
        program = ex.reference
        for old, new in edits:
            program = program.replace(old, new)
        best = float("inf")
        score = 0.0
        for _ in range(repeats):
            gc.disable()
            t0 = time.perf_counter()
            result = grade(ex, program)
            best = min(best, time.perf_counter() - t0)
            gc.enable()
            score = result.score
        print(f"| {eid} | {what} | {score:g} | {best * 1000:.0f} ms |")


if __name__ == "__main__":
    main()
