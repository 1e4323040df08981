"""Fuzzing the pipeline with mutated example programs: no exception, every program fast, bounded answers.

The programs of exercises/ and tests/seeds/ are mutated (lines deleted, doubled, swapped or taken from
another program; numbers replaced by extreme values; words, loops, subprogram calls and characters
inserted; characters deleted) and each goes through what a request does: parse and interpret with the
default limits (the server's), the JSON answer, the 3D view's drawing. Prints the crashes (exception and
program), the slowest input, the answers over 5 MB and the peak memory of the processes.

    python bench/fuzz.py                      # 10^6 cases
    python bench/fuzz.py --count 2000 --seed 7 --processes 2

Case k of seed s is always the same program (`case(s, k)`), so a finding can be run again alone:
python bench/fuzz.py --show 7:1234. tests/test_fuzz.py drives the same `mutate` with hypothesis.
"""

from __future__ import annotations

import argparse
import json
import multiprocessing
import random
import re
import resource
import sys
import time
import traceback
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from functools import cache
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from core.pipeline import DIALECTS, drawing, run, toolpath_json

Pick = Callable[[int], int]  # pick(n): a number in 0 … n-1

SEED_DIRS = (ROOT / "exercises", ROOT / "tests" / "seeds")
# the dialect of the programs in a directory of that name; other directories: pal-mill
DIALECT_DIRS = {"beckhoff": "beckhoff", "sinumerik-iso": "sinumerik-iso", "traub": "traub-tx8d"}
MAX_SECONDS = 1.0
MAX_ANSWER_BYTES = 5_000_000

NUMBERS = (
    "0",
    "-0",
    "1",
    "-1",
    "2",
    "0.001",
    "-0.001",
    "0.5",
    "45",
    "-90",
    "360",
    "720",
    "9999",
    "50000",
    "-50000",
    "99999",
    "100000",
    "1e5",
    "1.5.5",
    "99999999999",
    "00",
    "3,5",
)
WORDS = (
    "G0",
    "G1",
    "G2",
    "G3",
    "G4",
    "G17",
    "G18",
    "G19",
    "G40",
    "G41",
    "G42",
    "G45",
    "G46",
    "G47",
    "G48",
    "G53",
    "G54",
    "G59",
    "G66",
    "G90",
    "G91",
    "G94",
    "G95",
    "M3",
    "M4",
    "M5",
    "M6",
    "M8",
    "M17",
    "M30",
    "T1",
    "T2",
    "T99",
    "TC1",
    "TR0.5",
    "F0",
    "F100",
    "S0",
    "S2000",
    "RN5",
    "RN-2",
    "AS45",
    "RP10",
    "I50000",
    "J50000",
    "I0",
    "J0",
    "R5",
    "R-5",
    "R0.01",
    "D5",
    "E0",
    "XI5",
    "YI-5",
    "XA5",
    "X=P1",
    "Z=-P2*2",
    "P1=P1+1",
    "P2=P1*2",
    "P3=1/0",
    "P1000=1",
    "U2",
    "O2",
    "H9999",
    "H0",
    "/",
    "; Kommentar",
    "%L1",
    "L1",
    "#CHF=2",
    "#RND=3",
    "G301=2",
    "G302=3",
)
CHARS = "XYZIJKRNPGFSMTLHO=+-*/().,;%# \t0123456789äÜ\u00a0\x00\x7f"


def seeds() -> list[tuple[str, str, str]]:
    """(name, dialect, text) of every example program."""
    out = []
    for base in SEED_DIRS:
        for path in sorted(base.rglob("*.nc")):
            parts = set(path.relative_to(base).parts[:-1])
            dialect = next((d for name, d in DIALECT_DIRS.items() if name in parts), "pal-mill")
            if dialect not in DIALECTS:
                continue
            out.append((str(path.relative_to(ROOT)), dialect, path.read_text(encoding="utf-8")))
    return out


_NUMBER = re.compile(r"-?\d+(?:\.\d*)?")
_BLOCK_NUMBER = re.compile(r"^\s*N(\d+)", re.MULTILINE)


def mutate(text: str, pick: Pick, others: tuple[str, ...] = (), loops: bool = True) -> str:
    """`text` changed by one to six random edits; `pick` makes every choice (random or hypothesis).
    `loops=False`: no loops or subprogram calls added (most of those run into a budget of core/limits.py)."""
    lines = text.splitlines()
    for _ in range(1 + pick(6)):
        lines = _edit(lines, pick, others, loops)
    return "\n".join(lines) + "\n"


def _edit(lines: list[str], pick: Pick, others: tuple[str, ...], loops: bool) -> list[str]:
    if not lines:
        lines = [""]
    k = pick(len(lines))
    line = lines[k]
    numbers = [int(n) for n in _BLOCK_NUMBER.findall("\n".join(lines))] or [10]
    target = numbers[pick(len(numbers))]
    op = pick(11)
    if op in (8, 9) and not loops:
        op = 3
    if op == 0:  # delete a line
        return lines[:k] + lines[k + 1 :]
    if op == 1:  # double a line
        return lines[: k + 1] + lines[k:]
    if op == 2:  # swap two lines
        j = pick(len(lines))
        lines = list(lines)
        lines[k], lines[j] = lines[j], lines[k]
        return lines
    if op == 3:  # a number becomes an extreme one
        found = list(_NUMBER.finditer(line))
        if found:
            m = found[pick(len(found))]
            line = line[: m.start()] + NUMBERS[pick(len(NUMBERS))] + line[m.end() :]
        return lines[:k] + [line] + lines[k + 1 :]
    if op == 4:  # a word inserted between words
        cuts = [0, *(m.start() for m in re.finditer(" ", line)), len(line)]
        at = cuts[pick(len(cuts))]
        return lines[:k] + [f"{line[:at]} {WORDS[pick(len(WORDS))]} {line[at:]}".strip()] + lines[k + 1 :]
    if op == 5:  # a character inserted
        at = pick(len(line) + 1)
        return lines[:k] + [line[:at] + CHARS[pick(len(CHARS))] + line[at:]] + lines[k + 1 :]
    if op == 6:  # a character deleted
        if line:
            at = pick(len(line))
            line = line[:at] + line[at + 1 :]
        return lines[:k] + [line] + lines[k + 1 :]
    if op == 7 and others:  # a line of another program
        other = others[pick(len(others))].splitlines() or [""]
        return lines[:k] + [other[pick(len(other))]] + lines[k:]
    if op == 8:  # a jump back or a repeat: loops, endless ones too
        n = max(numbers) + 1 + pick(9)
        loop = (
            f"N{n} G29 N{target}",
            f"N{n} G23 N{target} N{numbers[pick(len(numbers))]} H{1 + pick(9999)}",
            f"N{n} P1=P1+1 G29 P1 O4 P2 N{target}",
        )[pick(3)]
        return lines[:k] + [loop] + lines[k:]
    if op == 9:  # a call of a subprogram at the end of the file
        n = 1 + pick(3)
        body = lines[pick(len(lines))]
        return (
            lines[:k]
            + [f"G22 L{n} H{1 + pick(9999)}"]
            + lines[k:]
            + [f"%L{n}", body, "G22 L1" if pick(4) == 0 else "G1 XI1", "M17"]
        )
    return lines[:k] + [line * (2 + pick(3))] + lines[k + 1 :]  # a line written several times over


@dataclass(frozen=True, slots=True)
class Outcome:
    seconds: float  # CPU time of this thread: parse, interpret, answer and drawing
    answer_bytes: int
    codes: frozenset[str]
    work: tuple[int, int, int]  # blocks executed, evaluation steps, programmed moves (core/limits.py Budget)
    moves: int  # moves in the toolpath (every generated one: cycles, compensation, contour trains)
    segments: int  # line segments of the 3D view's drawing


def check(text: str, dialect: str) -> Outcome:
    """What a request does with `text`; raises what the pipeline raises."""
    t = time.thread_time()
    toolpath = run(text, dialect)
    answer = json.dumps(toolpath_json(toolpath), ensure_ascii=False).encode()
    lines, _ = drawing(toolpath, 0.05)
    seconds = time.thread_time() - t
    return Outcome(
        seconds,
        len(answer),
        frozenset(d.code for d in toolpath.diagnostics),
        toolpath.work,
        len(toolpath.moves),
        sum(max(0, len(points) - 1) for points in lines),
    )


@cache
def _seeds() -> list[tuple[str, str, str]]:
    return seeds()


def case(seed: int, k: int) -> tuple[str, str, str]:
    """(seed name, dialect, program) of case `k` of run `seed`: the same every time."""
    rng = random.Random(f"{seed}:{k}")
    all_seeds = _seeds()
    name, dialect, text = all_seeds[rng.randrange(len(all_seeds))]
    others = tuple(t for _, d, t in all_seeds if d == dialect)
    return name, dialect, mutate(text, rng.randrange, others)


def _one(args: tuple[int, int]) -> tuple[int, float, int, str | None, int]:
    seed, k = args
    _, dialect, text = case(seed, k)
    try:
        out = check(text, dialect)
        return k, out.seconds, out.answer_bytes, None, _peak_kb()
    except Exception:  # noqa: BLE001 - a crash is the finding
        return k, 0.0, 0, traceback.format_exc(limit=-3), _peak_kb()


def _peak_kb() -> int:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss


def _cases(seed: int, count: int) -> Iterator[tuple[int, int]]:
    return ((seed, k) for k in range(count))


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--count", type=int, default=1_000_000, help="cases to run (default 10^6)")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--processes", type=int, default=1)
    ap.add_argument("--show", metavar="SEED:K", help="print the program of one case and run it")
    args = ap.parse_args(argv)
    if args.show:
        seed, k = (int(x) for x in args.show.split(":"))
        name, dialect, text = case(seed, k)
        print(f"# {name} ({dialect}), mutated\n{text}")
        out = check(text, dialect)
        print(f"# {out.seconds * 1000:.1f} ms, answer {out.answer_bytes} bytes, {sorted(out.codes)}")
        return 0
    crashes: dict[str, tuple[int, str]] = {}  # last lines of the traceback → first case
    slowest = (0.0, -1)
    over_time = over_size = 0
    largest = 0
    peak = 0
    started = time.perf_counter()
    with multiprocessing.get_context("spawn").Pool(args.processes) as pool:
        for done, (k, seconds, size, error, peak_kb) in enumerate(
            pool.imap_unordered(_one, _cases(args.seed, args.count), chunksize=16), 1
        ):
            peak = max(peak, peak_kb)
            largest = max(largest, size)
            if error is not None:
                key = "\n".join(error.strip().splitlines()[-3:])
                crashes.setdefault(key, (k, error))
            slowest = max(slowest, (seconds, k))
            over_time += seconds >= MAX_SECONDS
            over_size += size >= MAX_ANSWER_BYTES
            if done % max(1_000, min(10_000, args.count // 10)) == 0:
                rate = done / (time.perf_counter() - started)
                print(
                    f"{done} cases, {rate:.0f}/s, {len(crashes)} crashes, slowest {slowest[0] * 1000:.0f} ms",
                    flush=True,
                )
    print(f"\n{args.count} cases in {time.perf_counter() - started:.0f} s (seed {args.seed})")
    print(f"crashes: {len(crashes)}")
    for k, error in crashes.values():
        name, dialect, text = case(args.seed, k)
        print(f"--- case {args.seed}:{k} ({name}, {dialect})\n{text}{error}")
    seconds, k = slowest
    if k >= 0:
        name, dialect, text = case(args.seed, k)
        print(f"slowest: {seconds * 1000:.1f} ms, case {args.seed}:{k} ({name}, {dialect}):\n{text}")
    print(
        f"over {MAX_SECONDS:g} s: {over_time}; answers over {MAX_ANSWER_BYTES // 1_000_000} MB: {over_size} "
        f"(largest {largest / 1e6:.2f} MB)"
    )
    print(f"peak memory of a process: {peak / 1024:.0f} MB")
    return 1 if crashes or over_time or over_size else 0


if __name__ == "__main__":
    sys.exit(main())
