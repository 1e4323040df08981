"""Speed of the stock simulations: milling (core.sim.simulate) on the seed examples and a generated pocket,
turning (core.sim.simulate_turning) on the TRAUB examples.

Run from the repository root:

    python bench/simulate.py            # seeds at 0.1 mm, pocket at 0.1 mm and 0.05 mm
    python bench/simulate.py --quick    # fewer repeats

For each case it prints the best wall time of `simulate` alone (the program is interpreted once,
before timing), the cells visited (every cell of every window under a move) and cells per second.
Targets: every seed example under 100 ms at 0.1 mm; the 2,000-move pocket under 1.5 s at 0.1 mm;
every TRAUB example, among them TX-30 (G71 roughing and the SRK finishing of a whole shaft, the most
complete turning program of the manual; TX-01's Musterprogramm 4711 is not printed in it), under 300 ms at
the turning default of 0.05 mm along Z, and so the reference of every built-in turning exercise on its own
blank with its own tools.
This is a benchmark that prints figures, not a test.
"""

from __future__ import annotations

import argparse
import datetime
import gc
import math
import os
import platform
import sys
import time
from pathlib import Path

try:
    import core  # noqa: F401
except ImportError:  # run as `python bench/simulate.py` without an installed package
    sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

from core.interpreter.state import RunSetup
from core.pipeline import run
from core.sim import Blank, SimResult, Stock, TurningResult, parse_tool_table, simulate, simulate_turning
from core.toolpath import Toolpath
from core.tools import Tool, ToolTable

ROOT = Path(__file__).resolve().parents[1]
SEEDS = ROOT / "tests" / "seeds"
PAL_STOCK = Stock(0, 0, -30, 80, 70, 0)  # 80 × 70 × 30, origin at the lower left corner of the top face
SEED_STOCK = {
    "pal-15-g45-g46.nc": Stock(0, 0, -20, 60, 50, 0),
    "pal-16-g47-g48.nc": Stock(0, 0, -20, 60, 50, 0),
}
POCKET_STOCK = Stock(0, 0, -30, 100, 100, 0)
POCKET_TOOLS = ToolTable(
    {1: Tool(1, "end_mill", 10.0, "Schaftfräser Ø10", cutting_length=30.0, overall_length=80.0)}
)
TRAUB_SEEDS = SEEDS / "traub"
TURN_BLANK = Blank(100, 160)  # Ø100 × 160, 30 mm in the chuck: room for every TRAUB example
TURN_TOOLS = parse_tool_table("""tools:
- {number: 4, kind: turning, diameter: 1.6, nose_radius: 0.8, quadrant: 1, insert: C, name: Schruppen C 80°}
- {number: 5, kind: turning, diameter: 0.8, nose_radius: 0.4, quadrant: 1, insert: D, name: Schlichten D 55°}
""")
TARGET_TURN_S = 0.300
TARGET_SEED_S = 0.100
TARGET_POCKET_S = 1.5


def _n(v: float) -> str:
    s = f"{v:.3f}".rstrip("0").rstrip(".")
    return "0" if s in ("-0", "") else s


def pocket_program(moves: int = 2000, angle: float = 0.0) -> str:
    """An 80 × 80 mm pocket in the 100 × 100 block with a Ø10 end mill: per 0.5 mm level a ramp,
    zig-zag passes 4 mm apart and a finishing pass round the wall; exactly `moves` motion blocks.
    With `angle` ≠ 0 the pocket is shrunk to 64 × 64 and turned by `angle` degrees about its centre,
    so that every move is diagonal."""
    lo, hi, step = 15.0, 85.0, 4.0
    c, s = math.cos(math.radians(angle)), math.sin(math.radians(angle))
    scale = 0.8 if angle else 1.0

    def at(x: float, y: float) -> str:
        dx, dy = (x - 50) * scale, (y - 50) * scale
        return f"X{_n(50 + dx * c - dy * s)} Y{_n(50 + dx * s + dy * c)}"

    lines = ["T1 TC1 M6", "S3000 F600 M3", f"G0 {at(lo, lo)} Z2"]
    count = 1
    level = 0
    while count < moves - 2:
        level += 1
        z = -0.5 * level
        body = [f"G1 {at(lo + 10, lo)} Z{_n(z)}", f"G1 {at(lo, lo)}"]  # ramp down, back to the corner
        y, forward = lo, True
        while True:
            body.append(f"G1 {at(hi if forward else lo, y)}")
            if y + step > hi + 1e-9:
                break
            y += step
            body.append(f"G1 {at(hi if forward else lo, y)}")
            forward = not forward
        body += [
            f"G1 {at(lo, hi)}",
            f"G1 {at(lo, lo)}",
            f"G1 {at(hi, lo)}",
            f"G1 {at(hi, hi)}",
            "G0 Z2",
            f"G0 {at(lo, lo)}",
        ]
        for b in body:
            if count >= moves - 2:
                break
            lines.append(b)
            count += 1
    lines += ["G0 Z2", "G0 X250 Y150 Z250 M30"]
    return "\n".join(lines) + "\n"


def best_of(
    toolpath: Toolpath, stock: Stock, resolution: float, repeats: int, tools: ToolTable | None = None
) -> tuple[float, SimResult]:
    best, result = float("inf"), None
    for _ in range(repeats):
        gc.collect()
        gc.disable()
        try:
            t0 = time.perf_counter()
            result = (
                simulate(toolpath, stock, tools, resolution)
                if tools
                else simulate(toolpath, stock, resolution=resolution)
            )
            best = min(best, time.perf_counter() - t0)
        finally:
            gc.enable()
    assert result is not None
    return best, result


def best_turning(toolpath: Toolpath, repeats: int) -> tuple[float, TurningResult]:
    best, result = float("inf"), None
    for _ in range(repeats):
        gc.collect()
        gc.disable()
        try:
            t0 = time.perf_counter()
            result = simulate_turning(toolpath, TURN_BLANK, TURN_TOOLS)
            best = min(best, time.perf_counter() - t0)
        finally:
            gc.enable()
    assert result is not None
    return best, result


def turning_lines(repeats: int) -> bool:
    ok = True
    for path in sorted(TRAUB_SEEDS.glob("*.nc")):
        tp = run(path.read_text(encoding="utf-8"), "traub-tx8d", RunSetup(tools=TURN_TOOLS))
        t, r = best_turning(tp, repeats)
        passed = t < TARGET_TURN_S
        ok &= passed
        print(
            f"| {path.stem} (turning) | 0.05 | Ø100×160 | {len(tp.moves)} | {t * 1000:.1f} ms | {r.cell_updates:,} "
            f"| {r.cell_updates / max(t, 1e-9) / 1e6:.0f} M | {r.removed_volume:,.1f} | < 300 ms "
            f"| {'PASS' if passed else 'FAIL'} |"
        )
    return ok


def exercise_lines(repeats: int) -> bool:
    from core.exercises import builtin_exercises
    from core.sim import DEFAULT_LATHE_TOOLS

    ok = True
    for eid, ex in sorted(builtin_exercises().items()):
        if ex.blank is None:
            continue
        tools = ex.tool_table() if ex.tools else DEFAULT_LATHE_TOOLS
        setup = RunSetup(
            tools=tools,
            zero_offsets=tuple(ex.zero_offsets.items()),
            subprograms=tuple(ex.subprograms.items()),
        )
        tp = run(ex.reference, ex.dialect, setup)
        blank = ex.blank.blank()
        best, r = float("inf"), None
        for _ in range(repeats):
            t0 = time.perf_counter()
            r = simulate_turning(tp, blank, tools, ex.resolution)
            best = min(best, time.perf_counter() - t0)
        assert r is not None
        passed = best < TARGET_TURN_S
        ok &= passed
        print(
            f"| {eid} (exercise) | {ex.resolution:g} | Ø{_n(blank.diameter)}×{_n(blank.length)} | {len(tp.moves)} "
            f"| {best * 1000:.1f} ms | {r.cell_updates:,} | {r.cell_updates / max(best, 1e-9) / 1e6:.0f} M "
            f"| {r.removed_volume:,.1f} | < 300 ms | {'PASS' if passed else 'FAIL'} |"
        )
    return ok


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="fewer repeats")
    args = ap.parse_args()
    seed_repeats, pocket_repeats = (3, 1) if args.quick else (10, 3)
    print(
        f"# core.sim.simulate — {datetime.date.today()} — Python {platform.python_version()} "
        f"on {platform.system()} {platform.machine()}, {os.cpu_count()} cores"
    )
    print()
    print("| Case | Cell | Stock | Moves | Time | Cells visited | Cells/s | Removed mm³ | Target | Result |")
    print("|---|---:|---|---:|---:|---:|---:|---:|---:|---|")
    ok = True
    for path in sorted(SEEDS.glob("*.nc")):
        stock = SEED_STOCK.get(path.name, PAL_STOCK)
        tp = run(path.read_text(encoding="utf-8"))
        t, r = best_of(tp, stock, 0.1, seed_repeats)
        passed = t < TARGET_SEED_S
        ok &= passed
        print(
            f"| {path.stem} | 0.1 | {_n(stock.x1 - stock.x0)}×{_n(stock.y1 - stock.y0)}×{_n(stock.z1 - stock.z0)} "
            f"| {len(tp.moves)} | {t * 1000:.1f} ms | {r.cell_updates:,} | {r.cell_updates / t / 1e6:.0f} M "
            f"| {r.removed_volume:,.1f} | < 100 ms | {'PASS' if passed else 'FAIL'} |"
        )
    for angle, res in ((0.0, 0.1), (0.0, 0.05), (30.0, 0.1)):
        tp = run(pocket_program(angle=angle), setup=RunSetup(tools=POCKET_TOOLS))
        errors = [d for d in tp.diagnostics if d.severity.value == "error"]
        assert not errors, errors
        t, r = best_of(tp, POCKET_STOCK, res, pocket_repeats, POCKET_TOOLS)
        timed = res == 0.1 and angle == 0
        target = f"< {TARGET_POCKET_S} s" if timed else "—"
        verdict = ("PASS" if t < TARGET_POCKET_S else "FAIL") if timed else "—"
        ok &= verdict != "FAIL"
        name = "pocket 2,000 moves" + (f", turned {angle:g}°" if angle else "")
        print(
            f"| {name} | {res} | 100×100×30 | {len(tp.moves)} | {t:.3f} s | {r.cell_updates:,} "
            f"| {r.cell_updates / t / 1e6:.0f} M | {r.removed_volume:,.1f} | {target} | {verdict} |"
        )
        if r.events:
            print(f"  events: {[(e.code, e.span.line) for e in r.events]}")
    ok &= turning_lines(seed_repeats)
    ok &= exercise_lines(seed_repeats)
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
