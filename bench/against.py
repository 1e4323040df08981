"""The interpreter's benchmark programs run by a past revision's code and by ours, side by side on this machine.

Run from the repository root (a git clone):

    python bench/against.py                  # against b2a4eda, the code issue 32 measured
    python bench/against.py e2a4a36 --rounds 3 --repeats 20

A shared VM's speed moves by 2x and more within hours (bench/README.md), so milliseconds measured on one day
cannot be held against milliseconds measured on another. This script measures both codes now: the past
revision's core/ (taken with `git archive` into a temporary folder) and this tree's, each in processes of its own,
alternating round by round, each program the best of `--repeats` runs (the garbage collector between runs, not
during one, as bench/interpreter.py times). The programs are this tree's bench/interpreter.py programs, the same
text for both.

The ratio of the two is what a change did, whatever the machine. With the default revision it also translates the
figures issue 32 measured on that code when it set its targets: ours on that machine on that day is about its
figure × (our time here / its time here).
"""

from __future__ import annotations

import argparse
import gc
import io
import json
import os
import subprocess
import sys
import tarfile
import tempfile
import time
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[1]

# The code issue 32 measured ("bench/interpreter.py, side by side in one run on this 2-core machine") and the
# figures it wrote down for it, in ms — the slow end of each range it gave: the translation errs on our side's
# cost. Its targets are bench/interpreter.py's.
ISSUE_32_REVISION = "b2a4eda"
ISSUE_32 = {"pal": 8.2, "traub": 11.8, "cycles": 23.0}
ISSUE_32_RUN_RATIO = 2.53  # run rate / pygcode Machine then (2.53–2.74x)
# the programs: name → (dialect, the bench/interpreter.py generator, its argument)
PROGRAMS = {
    "pal": ("pal-mill", "generate_realistic", None),
    "traub": ("traub-tx8d", "generate_turning", None),
    "cycles": ("traub-tx8d", "generate_turning_cycles", None),
    "iso1k": ("pal-mill", "generate_iso", 1000),
}
LABELS = {
    "pal": "300-block PAL program",
    "traub": "300-block TRAUB program",
    "cycles": "TRAUB program with cycles",
    "iso1k": "1k-block ISO program",
}


def child(code: str, programs_file: str, repeats: int) -> None:
    """In a process of its own: each program through `code`'s core.pipeline.run; prints {name: best ms}."""
    sys.path.insert(0, code)
    import core
    from core.pipeline import run

    assert Path(core.__file__).resolve().is_relative_to(Path(code).resolve()), core.__file__
    programs = json.loads(Path(programs_file).read_text("utf-8"))
    best: dict[str, float] = {}
    for name, (dialect, text) in programs.items():
        run(text, dialect)  # (imports and tables made before the clock runs)
        # (bench/interpreter.py's best_time, written out: importing that module would import this tree's core)
        times = []
        for _ in range(repeats):
            gc.collect()
            gc.disable()
            try:
                t0 = time.perf_counter()
                run(text, dialect)
                times.append(time.perf_counter() - t0)
            finally:
                gc.enable()
        best[name] = min(times) * 1000
    print(json.dumps(best))


def this_trees_bench() -> Any:
    """bench/interpreter.py of this tree: its programs and targets (imported in the parent only: it imports this
    tree's core)."""
    sys.path.insert(0, str(ROOT))
    import bench.interpreter

    return bench.interpreter


def programs_json(folder: Path) -> Path:
    """This tree's benchmark programs as a file both sides read."""
    programs = this_trees_bench()
    texts = {}
    for name, (dialect, generator, argument) in PROGRAMS.items():
        make = getattr(programs, generator)
        texts[name] = (dialect, make(argument) if argument is not None else make())
    path = folder / "programs.json"
    path.write_text(json.dumps(texts), "utf-8")
    return path


def past_core(revision: str, folder: Path) -> Path:
    """The revision's core/ unpacked into `folder`."""
    archive = subprocess.run(
        ["git", "-C", str(ROOT), "archive", "--format=tar", revision, "core"],
        check=True,
        capture_output=True,
    ).stdout
    target = folder / "past"
    target.mkdir()
    with tarfile.open(
        fileobj=io.BytesIO(archive)
    ) as tar:  # (our own repository's files; the filter where Python has it)
        if hasattr(tarfile, "data_filter"):
            tar.extractall(target, filter="data")
        else:  # Python before 3.11.4
            tar.extractall(target)
    return target


def timed(code: Path, programs: Path, repeats: int) -> dict[str, float]:
    out = subprocess.run(
        [sys.executable, __file__, "--child", str(code), str(programs), str(repeats)],
        check=True,
        capture_output=True,
        text=True,
        cwd=code,
        env={**os.environ, "PYTHONPATH": ""},
    ).stdout
    return {k: float(v) for k, v in json.loads(out.strip().splitlines()[-1]).items()}


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("revision", nargs="?", default=ISSUE_32_REVISION, help="the past code (a git revision)")
    ap.add_argument("--rounds", type=int, default=5, help="processes of each side, alternating")
    ap.add_argument("--repeats", type=int, default=40, help="runs of each program per process (best counts)")
    args = ap.parse_args(argv)

    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        programs = programs_json(folder)
        try:
            past = past_core(args.revision, folder)
        except subprocess.CalledProcessError as err:  # an unknown revision, or no git clone
            print(
                f"git archive {args.revision}: {err.stderr.decode(errors='replace').strip()}", file=sys.stderr
            )
            return 2
        theirs: dict[str, float] = {}
        ours: dict[str, float] = {}
        for k in range(args.rounds):
            for side, code in (("past", past), ("ours", ROOT)):
                figures = timed(code, programs, args.repeats)
                kept = theirs if side == "past" else ours
                for name, ms in figures.items():
                    kept[name] = min(kept.get(name, ms), ms)
            print(f"round {k + 1} of {args.rounds} done", file=sys.stderr, flush=True)
    sys.stderr.flush()

    print(
        f"{args.revision} against this tree, best of {args.rounds} x {args.repeats} runs each, alternating "
        f"processes on this machine ({os.cpu_count()} CPUs)"
    )
    print(f"  {'program':<27} {args.revision:>10} {'ours':>10} {'speed-up':>9}")
    for name in PROGRAMS:
        print(
            f"  {LABELS[name]:<27} {theirs[name]:>7.2f} ms {ours[name]:>7.2f} ms {theirs[name] / ours[name]:>8.2f}x"
        )
    if args.revision == ISSUE_32_REVISION:
        bench = this_trees_bench()
        targets = {
            "pal": bench.TARGET_REALISTIC_MS,
            "traub": bench.TARGET_TURNING_MS,
            "cycles": bench.TARGET_CYCLES_MS,
        }
        print(
            f"Issue 32's figures for {ISSUE_32_REVISION}, and ours on the machine and day it measured them:"
        )
        for name, then in ISSUE_32.items():
            now = then * ours[name] / theirs[name]
            print(
                f"  {LABELS[name]:<27} {then:5.1f} ms -> {now:5.2f} ms (target < {targets[name]:.0f} ms)  "
                f"{bench.verdict(now < targets[name])}"
            )
        ratio = ISSUE_32_RUN_RATIO * theirs["iso1k"] / ours["iso1k"]
        least = bench.TARGET_RUN_VS_PYGCODE
        print(
            f"  run rate / pygcode Machine    {ISSUE_32_RUN_RATIO:.2f}x -> {ratio:.2f}x (target >= {least:.1f}x)  "
            f"{bench.verdict(ratio >= least)}"
        )
    return 0


if __name__ == "__main__":
    if len(sys.argv) == 5 and sys.argv[1] == "--child":
        child(sys.argv[2], sys.argv[3], int(sys.argv[4]))
    else:
        sys.exit(main())
