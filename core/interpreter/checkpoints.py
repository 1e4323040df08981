"""Checkpoints of a run, so that the next run of the same program changed in a few lines (the live editor)
executes only from the first changed block until its state meets the previous run's state again.

A `Trace` keeps, for every block the run loop met (a step), the loop's complete state before it: where it
is, the modal state, position, parameters, the call and repeat stacks, what dropped blocks left unknown
(core/interpreter/followups.py), the work budgets' counters and how many moves and diagnostics the run had
made. The next run (core/interpreter/__init__.py):

- finds the changed lines: the longest common prefix and suffix of the two programs' lines;
- falls back to a full run when the change adds or removes a `%L` header, or changes the block numbers that
  G29/G23 resolve and the previous run jumped or repeated;
- restarts from the checkpoint of the step before the first one that met a changed line or the line
  before them (which goes on into the change), or any line after that when lines were inserted or deleted,
  since the lines after the change move;
- after each block, compares its state with the previous run's checkpoints at the same block (mapped by the
  line delta) from which no later step of the previous run met a changed line or the line before them (from
  which the run goes on into the change); where they are equal and
  the budgets cannot run out differently, the rest of the previous run is taken over, its lines shifted.

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

from core.diagnostics import Diagnostic
from core.interpreter.contour import Blend, Item, Planned
from core.interpreter.state import ModalState
from core.limits import Limits
from core.syntax.blocks import Block, Span
from core.toolpath import Dwell, Move, ToolChange, Vec3

UnitKey = tuple[str | None, int | None]  # (source, subprogram number): None, None is the main program
# a frame in progress (core/interpreter/run.py: Frame): caller, the line it returns to, callee, the first and
# last line of a G23 section (a call: 0, None), runs still to come, the calling line, whether a G23 section
FramePoint = tuple[UnitKey, int, UnitKey, int, int | None, int, int, bool]

STATS: Counter[str] = Counter()  # "full", "incremental" (met the previous run), "to_end" (restarted, ran on)
MAX_STEPS = (
    10_000  # a run that meets more blocks keeps no trace (memory: ~150 bytes a step); the next runs in full
)


class Checkpoint(NamedTuple):
    """The run loop's state before it meets one block, with lines (the unit's source's numbering) instead of
    indices; the counters are in the trace's arrays. Two runs are in the same state where these are equal."""

    unit: UnitKey
    line: int
    state: ModalState
    position: Vec3
    params: dict[int, float]  # never mutated: a new copy after each block that assigns
    frames: tuple[FramePoint, ...]
    unknown: dict[str, int]  # FollowUps.unknown, never mutated (a change makes a new dict)


@dataclass(slots=True)
class Trace:
    """One run's checkpoints (one per step) and what it made, for the next run of the same document."""

    blocks: list[Block]  # the program's blocks, one per line
    setup: Any  # the RunSetup, code table and block executor of the run: another one runs in full
    limits: Limits  # the limits of the run
    checkpoints: list[Checkpoint] = field(default_factory=list)
    # per step: the budgets' counters, the lengths of the planned items and of the loop's diagnostics
    executed: array[int] = field(default_factory=lambda: array("q"))
    steps: array[int] = field(default_factory=lambda: array("q"))
    moves: array[int] = field(default_factory=lambda: array("q"))
    planned: array[int] = field(default_factory=lambda: array("q"))
    diags: array[int] = field(default_factory=lambda: array("q"))
    sets: bytearray = field(default_factory=bytearray)  # 1: the step set its line's state (line_states)
    where: array[int] = field(default_factory=lambda: array("q"))  # the step's line in the file (0: library)
    revisits: bool = False  # a line's state was set more than once (loops, calls)
    # every FollowUps.ran with something unknown: (step, (source, line), unknown) — `at` is first-wins
    at_log: list[tuple[int, tuple[str | None, int], dict[str, int]]] = field(default_factory=list)
    labels: bool = False  # a G29 jump or G23 repeat was resolved by block number
    # what the run made (before the contour stage and the follow-up pass)
    items: list[Item] = field(default_factory=list)
    loop_diags: list[Diagnostic] = field(default_factory=list)
    states: list[ModalState | None] = field(default_factory=list)  # per line, as the loop set them
    positions: list[Vec3 | None] = field(default_factory=list)
    set_at: list[int] = field(default_factory=list)  # per line: the last step that set its state (-1: none)
    # the end of the run
    state: ModalState | None = None
    position: Vec3 = (0.0, 0.0, 0.0)
    params: dict[int, float] = field(default_factory=dict)
    unknown: dict[str, int] = field(default_factory=dict)
    final_line: int = 0  # last_line at the end
    final_set: int = -1
    ended: bool = False
    counters: tuple[int, int, int] = (0, 0, 0)  # executed, steps, moves
    spent: bool = False  # a budget ran out (PAL-E013/E016/E017)

    def fits(self, executed: int, steps: int, moves: int, j: int) -> bool:
        """Whether the rest of this run from step `j`, with the counters now at these values instead of
        the ones at `j`, spends its budgets exactly as it did."""
        if self.spent:
            return (executed, steps, moves) == (self.executed[j], self.steps[j], self.moves[j])
        lim = self.limits
        e, s, m = self.counters
        return (
            e + executed - self.executed[j] <= lim.max_executed_blocks
            and s + steps - self.steps[j] <= lim.max_evaluation_steps
            and m + moves - self.moves[j] <= lim.max_moves
        )


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

    def checkpoint(self, cp: Checkpoint) -> Checkpoint:
        """`cp` in the new numbering (Unmappable where it names a changed line)."""
        frames = tuple(
            (
                u,
                self.after(r, u[0]),
                c,
                self.line(s, u[0]) if repeat else s,
                self.line(e, u[0]) if repeat and e is not None else e,
                n,
                self.line(ln, u[0]),
                repeat,
            )
            for u, r, c, s, e, n, ln, repeat in cp.frames
        )
        unknown = self.unknown(cp.unknown)
        line = self.line(cp.line, cp.unit[0])
        if line == cp.line and frames == cp.frames and unknown is cp.unknown:
            return cp
        return cp._replace(line=line, frames=frames, unknown=unknown)

    def move(self, m: Move) -> Move:
        span = self.span(m.span) if m.source is None and m.span.line >= self.first else m.span
        stack = tuple((s, self.line(ln, s)) for s, ln in m.call_stack) if m.call_stack else m.call_stack
        if span is m.span and stack == m.call_stack:
            return m
        return dataclasses.replace(m, span=span, call_stack=stack)

    def item(self, item: Item) -> Item:
        if isinstance(item, Planned):
            move = self.move(item.move)
            blend = item.blend_span
            if blend is not None:
                blend = self.span(blend, move.source)
            if move is item.move and blend == item.blend_span:
                return item
            return dataclasses.replace(item, move=move, blend_span=blend)
        if isinstance(item, (Dwell, ToolChange, Blend)):
            span = self.span(item.span)
            return item if span == item.span else dataclasses.replace(item, span=span)
        return item

    def diagnostic(self, d: Diagnostic) -> Diagnostic:
        span = self.span(d.span, d.source)
        return d if span == d.span else dataclasses.replace(d, span=span)


def changed_lines(old: list[Block], new: list[Block]) -> tuple[int, int, int]:
    """(first, old end, new end): the 1-based line range [first, end) that differs between the programs
    (their longest common prefix and suffix of line texts apart)."""
    n_old, n_new = len(old), len(new)
    a = 0
    limit = min(n_old, n_new)
    while a < limit and (old[a] is new[a] or old[a].text == new[a].text):
        a += 1
    b = 0
    while b < limit - a and (
        old[n_old - 1 - b] is new[n_new - 1 - b] or old[n_old - 1 - b].text == new[n_new - 1 - b].text
    ):
        b += 1
    return a + 1, n_old - b + 1, n_new - b + 1


def structure_kept(
    old: list[Block], new: list[Block], first: int, old_end: int, new_end: int, labels: bool
) -> bool:
    """Whether the units (`%L` headers) and, when the run resolved block numbers, the numbers in the
    changed lines are the same: then every call, jump and repeat outside them goes where it went. The line
    before the change counts as changed: a unit starting after it starts with the change."""
    lo = max(1, first - 1)
    was, now = old[lo - 1 : old_end - 1], new[lo - 1 : new_end - 1]
    if any(b.header is not None for b in was) or any(b.header is not None for b in now):
        return False
    return not labels or [b.number for b in was] == [b.number for b in now]


@dataclass(slots=True)
class Keep:
    """Where a document's runs keep their trace for the next run (core.pipeline.Memo holds one)."""

    trace: Any = None  # a Trace, or TRAUB's run loop's TurnTrace (core/interpreter/traub_trace.py)
    kind: str = "full"  # how the last run went: "full", "incremental" or "to_end" (as STATS counts)
    # the moves the last run took over with their lines shifted: id(new move) → the previous run's move
    shifted: dict[int, Move] = field(default_factory=dict)
