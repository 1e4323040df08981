"""How fast runaway programs end: a self-calling subprogram and endless G29 loops.

Prints the time each program needs until its diagnostic (best of 5). Target (issue "Program flow"):
under a second each, with the default limit of 100,000 executed blocks.
Run from the repository root: python bench/limits.py
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from core.pipeline import run

PROGRAMS = {
    "self-calling subprogram": "N10 G22 L1\nN20 M30\n%L1\nN10 G22 L1\nN20 M17\n",
    "endless G29 loop (1 block)": "N10 G29 N10\nN20 M30\n",
    "endless G29 loop with a counter": "N10 P1=0\nN20 P1=P1+1\nN30 G29 N20\nN40 M30\n",
    "endless G29 loop with moves": "N10 T1 M6\nN15 S100 F100 M3\nN20 G1 X10\nN30 G1 X0\nN40 G29 N20\nN50 M30\n",
}


def main() -> None:
    worst = 0.0
    for name, program in PROGRAMS.items():
        best = float("inf")
        for _ in range(5):
            t = time.perf_counter()
            tp = run(program)
            best = min(best, time.perf_counter() - t)
        codes = sorted({d.code for d in tp.diagnostics})
        worst = max(worst, best)
        print(f"{name:34s} {best * 1000:8.1f} ms   {', '.join(codes)}")
    print(f"slowest: {worst * 1000:.1f} ms (target < 1000 ms) {'PASS' if worst < 1.0 else 'FAIL'}")


if __name__ == "__main__":
    main()
