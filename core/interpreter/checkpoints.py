"""Checkpoints of a run, so that the next run of the same program changed in a few lines (the live editor)
executes only from the first changed block until its state meets the previous run's state again — one
scheme for every dialect (the run loop: core/interpreter/loop.py; the machine's state: its `snap`).

A `Trace` keeps, for every block the run loop met (a step), a `Point`: where the loop is (unit, line, the
calls and repeated sections in progress, in lines) and the machine's state before the block, as a value
that is never mutated; beside it the budgets' counters, how many items and diagnostics the run had made,
the line state the step set and the last line of the main program. A step also records which lines of the
program file it *touched*: on its way to its block (the lines it passed over, its own included: an
arrival) and while it ran (a TRAUB cycle reads its contour's lines, M30 looks at every line after it).

The next run:
- finds the changed lines: the longest common prefix and suffix of the two programs' lines;
- falls back to a full run when the change adds or removes a unit header (`%L`, `O` blocks), changes the
  programs of the file, or changes block numbers that the previous run resolved (G29, G23, TRAUB's P/Q);
- restarts from the checkpoint of the step before the first one that touched the change;
- after each block, compares its point with the previous run's points at the same unit and line (mapped
  by the line delta) after the last step that touched the change (arrivals: from that step on); where
  they are equal and the budgets cannot run out differently, the rest of the previous run is taken over,
  its lines shifted.

Backward jumps and loops into or across the changed lines are covered by that last condition: the previous
run's steps after such a jump touch the changed lines again, so the new run only meets it after the last
pass (or runs to the end). `STATS` counts how each run went.
"""

from __future__ import annotations

import dataclasses
from array import array
from collections import Counter
from dataclasses import dataclass, field
from typing import Any, NamedTuple

from core.diagnostics import Diagnostic, diag
from core.interpreter.contour import Blend, Planned
from core.interpreter.state import ModalState
from core.interpreter.turn_contour import SrkSwitch, TurnItem
from core.limits import Limits
from core.sequences import common_ends
from core.syntax.blocks import Block, Span
from core.toolpath import Dwell, Move, ToolChange, Vec3

UnitKey = tuple[str | None, int | None]  # (source, number): (None, None) is the main program
# a frame in progress: caller, the calling line, callee, the first and last line of its section (first -1:
# past its end; last None: to its end or M17/M99), runs still to come, whether a G23 section repeat
FramePoint = tuple[UnitKey, int, UnitKey, int, int | None, int, bool]
INF = 1 << 40  # "to the end of the file" in a touched line range

STATS: Counter[str] = Counter()  # "full", "incremental" (met the previous run), "to_end" (restarted, ran on)
MAX_STEPS = 10_000  # a run that meets more blocks keeps no trace (memory); the next one runs in full


class Point(NamedTuple):
    """The run loop's state before it meets a block (lines in their unit's source's numbering; -1: past
    the end). Two runs are in the same state where these are equal."""

    unit: UnitKey
    line: int
    frames: tuple[FramePoint, ...]
    machine: Any  # the machine's state (Machine.snap), never mutated


@dataclass(slots=True)
class Trace:
    """One run's checkpoints (one per step) and what it made, for the next run of the same document."""

    blocks: list[Block]  # the program's blocks, one per line
    identity: Any  # the machine's set-up (Machine.identity): another one runs in full
    limits: Limits
    units: tuple[tuple[int | None, int], ...] = ()  # the file's programs: number and header line
    points: list[Point] = field(default_factory=list)
    # per step: the budgets' counters, the numbers of items and of the loop's diagnostics before it, the
    # last line of the main program and the step that set it, whether its block is a library program's
    executed: array[int] = field(default_factory=lambda: array("q"))
    steps: array[int] = field(default_factory=lambda: array("q"))
    moves: array[int] = field(default_factory=lambda: array("q"))
    n_items: array[int] = field(default_factory=lambda: array("q"))
    n_diags: array[int] = field(default_factory=lambda: array("q"))
    last_lines: array[int] = field(default_factory=lambda: array("q"))
    last_steps: array[int] = field(default_factory=lambda: array("q"))
    library: bytearray = field(default_factory=bytearray)
    lines: array[int] = field(default_factory=lambda: array("q"))  # its block's line in the file (0: library)
    sets: list[tuple[int, ModalState, Vec3] | None] = field(
        default_factory=list
    )  # line index, state, position
    # (step, lo, hi, arrival), in step order: the step touched the lines lo < line ≤ hi (arrival: on its way
    # to its block)
    touches: list[tuple[int, int, int, bool]] = field(default_factory=list)
    notes: list[tuple[int, Any]] = field(default_factory=list)  # (step, what the machine noted: Machine.note)
    labels: bool = False  # block numbers were resolved (G29, G23, P/Q): changing them runs in full
    # what the run made (before the machine's last stage)
    items: list[Any] = field(default_factory=list)
    loop_diags: list[Diagnostic] = field(default_factory=list)
    marks: set[int] = field(default_factory=set)  # ids of items the machine marked (Machine.marks)
    # the end of the run
    final: Any = None  # the machine's state
    ended: bool = False
    counters: tuple[int, int, int] = (0, 0, 0)  # executed, steps, moves
    last: tuple[int, int] = (0, -1)  # the last main line and its step
    spent: bool = False  # a budget ran out (PAL-E013/E016/E017)

    def record(
        self, point: Point, counters: tuple[int, int, int], n_items: int, n_diags: int, last: tuple[int, int]
    ) -> None:
        self.points.append(point)
        self.executed.append(counters[0])
        self.steps.append(counters[1])
        self.moves.append(counters[2])
        self.n_items.append(n_items)
        self.n_diags.append(n_diags)
        self.last_lines.append(last[0])
        self.last_steps.append(last[1])
        library = point.unit[0] is not None
        self.library.append(library)
        self.lines.append(0 if library else point.line)
        self.sets.append(None)

    def fits(self, now: tuple[int, int, int], j: int) -> bool:
        """Whether the rest of this run from step `j`, with the counters at `now` instead of the ones at `j`,
        spends its budgets exactly as it did."""
        at = (self.executed[j], self.steps[j], self.moves[j])
        if self.spent:
            return now == at
        lim = self.limits
        e, s, m = self.counters
        return (
            e + now[0] - at[0] <= lim.max_executed_blocks
            and s + now[1] - at[1] <= lim.max_evaluation_steps
            and m + now[2] - at[2] <= lim.max_moves
        )

    def counters_at(self, j: int) -> tuple[int, int, int]:
        return self.executed[j], self.steps[j], self.moves[j]

    def take_start(self, old: Trace, until: int) -> None:
        """The steps of `old` before `until` as this trace's first ones (lines as they were: the caller maps
        what names one)."""
        self.points = old.points[:until]
        for name in (
            "executed",
            "steps",
            "moves",
            "n_items",
            "n_diags",
            "last_lines",
            "last_steps",
            "library",
            "lines",
        ):
            setattr(self, name, getattr(old, name)[:until])
        self.sets = old.sets[:until]
        self.labels = self.labels or old.labels


class Unmappable(Exception):
    """A line of the previous run that lies in the changed lines: nothing of it carries over."""


@dataclass(frozen=True, slots=True)
class LineMap:
    """Old lines → new lines of the program file: before the change the same, after it shifted by `delta`;
    the changed lines themselves (`first` ≤ line < `end`, old numbering) have no counterpart."""

    first: int
    end: int
    delta: int

    @property
    def identity(self) -> bool:
        return self.delta == 0 and self.first == self.end

    def line(self, line: int, source: str | None = None) -> int:
        if source is not None or line < self.first:
            return line
        if line >= self.end:
            return line + self.delta
        raise Unmappable

    def after(self, line: int, source: str | None = None) -> int:
        """A line where the run goes on after the block before it (a return from a call or a G23 section).
        Where lines were inserted or deleted right after that block, the new run goes on into them but the
        previous run went on after them: Unmappable."""
        after = self.line(line - 1, source) + 1
        if after != self.line(line, source):
            raise Unmappable
        return after

    def back(self, line: int, source: str | None = None) -> int | None:
        """New line → old line; None in the changed lines."""
        if source is not None or line < self.first:
            return line
        if line >= self.end + self.delta:
            return line - self.delta
        return None

    def span(self, span: Span, source: str | None = None) -> Span:
        if source is not None or (span.line < self.first and span.end_line < self.first):
            return span
        return Span(self.line(span.line), span.column, self.line(span.end_line), span.end_column)

    def unknown(self, unknown: dict[str, int]) -> dict[str, int]:
        if self.delta == 0 and all(not self.first <= v < self.end for v in unknown.values()):
            return unknown
        return {k: self.line(v) for k, v in unknown.items()}

    def move(self, m: Move) -> Move:
        span = self.span(m.span) if m.source is None and m.span.line >= self.first else m.span
        stack = tuple((s, self.line(ln, s)) for s, ln in m.call_stack) if m.call_stack else m.call_stack
        if span is m.span and stack == m.call_stack:
            return m
        return dataclasses.replace(m, span=span, call_stack=stack)

    def item(self, item: Any, library: bool) -> Any:
        """An item of a block in the new numbering (a library program's block keeps its lines, not its call
        stack; a move knows its source)."""
        if isinstance(item, Planned):
            move = self.move(item.move)
            blend = item.blend_span
            if blend is not None:
                blend = self.span(blend, move.source)
            if move is item.move and blend == item.blend_span:
                return item
            return dataclasses.replace(item, move=move, blend_span=blend)
        if isinstance(item, TurnItem):
            t = self.move(item.template)
            return item if t is item.template else dataclasses.replace(item, template=t)
        if isinstance(item, Move):
            return self.move(item)
        if isinstance(item, (Dwell, ToolChange, Blend, SrkSwitch)) and not library:
            span = self.span(item.span)
            return item if span == item.span else dataclasses.replace(item, span=span)
        return item

    def diagnostic(self, d: Diagnostic) -> Diagnostic:
        """`d` in the new numbering, the line its message names included."""
        span = self.span(d.span, d.source)
        new = d if span == d.span else dataclasses.replace(d, span=span)
        if d.code in _LINE_PARAM and "second" in d.params and not self.identity:
            second = self.line(int(d.params["second"]), d.source)
            if second != d.params["second"]:
                made = diag(d.code, new.span, **{**d.params, "second": second})
                new = dataclasses.replace(made, source=new.source, follows_from=new.follows_from)
        return new


_LINE_PARAM = ("TX-E404", "TX-W405", "TX-E410")  # their message names a line of the contour: `second`


def changed_lines(old: list[Block], new: list[Block]) -> tuple[int, int, int]:
    """(first, old end, new end): the 1-based line range [first, end) that differs between the programs
    (their longest common prefix and suffix of line texts apart)."""
    a, b = common_ends(old, new, _same_line)
    return a + 1, len(old) - b + 1, len(new) - b + 1


def _same_line(old: Block, new: Block) -> bool:
    return old is new or old.text == new.text


def touches(lo: int, hi: int, first: int, end: int) -> bool:
    """Whether the lines lo < line ≤ hi meet the changed lines first ≤ line < end (an insertion when equal)."""
    if first == end:
        return lo < first <= hi
    return max(lo + 1, first) <= min(hi, end - 1)


def structure_kept(old: Trace, new: list[Block], first: int, old_end: int, new_end: int) -> bool:
    """Whether the changed lines and the line before them (a unit starting after it starts with the change)
    hold no unit header or O block and, where the run resolved block numbers, the same numbers: then every
    call, jump, section and contour outside them goes where it went."""
    lo = max(1, first - 1)
    was, now = old.blocks[lo - 1 : old_end - 1], new[lo - 1 : new_end - 1]
    for b in (*was, *now):
        if b.header is not None or (b.ok and b.words and b.words[0].address == "O"):
            return False
    if not old.labels:
        return True
    return [b.number for b in was if b.number is not None] == [b.number for b in now if b.number is not None]


def restart(old: Trace, first: int, end: int) -> tuple[int, int]:
    """(k, start): the first step of the previous run that touched the changed lines first ≤ line < end
    (its last step when none did), and the first step where this run may meet it again: after the last
    step that touched them while it ran, from the last one that touched them on its way."""
    k, last_exec, last_arrival = len(old.points) - 1, -1, -1
    insertion, last = first == end, end - 1
    for s, lo, hi, arrival in old.touches:  # (touches() inline: this loop meets every step; in step order)
        if (lo < first <= hi) if insertion else (lo < last and hi >= first):
            k = min(k, s)
            if arrival:
                last_arrival = s
            else:
                last_exec = s
    return k, max(k, last_exec + 1, last_arrival)


def map_touch(lm: LineMap, lo: int, hi: int) -> tuple[int, int]:
    return (lo if lo <= 0 else lm.line(lo + 1) - 1), (hi if hi >= INF else lm.line(hi))


@dataclass(slots=True)
class Keep:
    """Where a document's runs keep their trace for the next run (core.pipeline.Memo holds one)."""

    trace: Trace | None = None
    kind: str = "full"  # how the last run went: "full", "incremental" or "to_end" (as STATS counts)
    # the moves the last run took over with their lines shifted: id(new move) → the previous run's move
    shifted: dict[int, Move] = field(default_factory=dict)
