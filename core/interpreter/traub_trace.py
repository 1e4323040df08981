"""Checkpoints of a TRAUB run (core/interpreter/traub_turn.py), so that the live editor's next run of the same
program changed in a few lines executes only from the first changed block until its state meets the previous
run's state again — the same scheme as the shared run loop's (core/interpreter/checkpoints.py, whose line map,
change finder, `Keep` and `STATS` this uses), with TRAUB's state: the modal state and technology, position,
L parameters, zero point and G59 shift, SRK, the cycles' state, the call stack, the budgets.

TRAUB programs skip blocks (not-ok lines are not part of a program), so a step also records which lines the
run passed over to reach its block, and a cycle which contour lines it read; a step "touches" the change
where one of these line ranges does. The run restarts before the first step that touches it and may meet
the previous run at a step after the last one that touches it.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field
from typing import Any, NamedTuple

from core.diagnostics import Diagnostic, diag
from core.interpreter import turn_contour
from core.interpreter.checkpoints import LineMap, Unmappable
from core.interpreter.state import ModalState, RunSetup
from core.limits import Limits
from core.syntax.blocks import Block
from core.toolpath import Dwell, Move, ToolChange, Vec3

INF = 1 << 40  # "to the end of the file" in a touched line range

Key = tuple[
    str | None, int | None
]  # a program of the run: (source, number); (None, None) is the main program
# a call in progress: caller, calling line, callee, first line, last line (None: up to M99), runs to come
FramePoint = tuple[Key, int, Key, int, int | None, int]


class TurnPoint(NamedTuple):
    """The run loop's state before it meets a block (lines in the program's numbering; -1: past the end)."""

    unit: Key
    line: int
    end: int | None
    calls: tuple[FramePoint, ...]
    run: tuple[Any, ...]  # TurnRun's state (traub_turn.snapshot), compared as a whole


@dataclass(slots=True)
class TurnTrace:
    """One TRAUB run's checkpoints, one per step, and what it made."""

    blocks: list[Block]
    setup: RunSetup
    units: tuple[tuple[int | None, int], ...] = ()  # the programs: number and the line of their O block
    points: list[TurnPoint] = field(default_factory=list)
    contours: list[dict[Any, Any]] = field(default_factory=list)  # per step: the cycles' contour cache
    counters: list[tuple[int, int, int]] = field(default_factory=list)  # per step: executed, steps, moves
    n_items: list[int] = field(default_factory=list)
    n_diags: list[int] = field(default_factory=list)
    lasts: list[tuple[int, int]] = field(
        default_factory=list
    )  # per step: last main line, the step that set it
    library: bytearray = field(default_factory=bytearray)  # per step: the block is a library program's
    sets: list[tuple[int, ModalState, Vec3] | None] = field(default_factory=list)  # per step: line state set
    # (step, lo, hi, arrival): the step met lines lo < line ≤ hi (arrival: on its way to its block)
    touches: list[tuple[int, int, int, bool]] = field(default_factory=list)
    items: list[turn_contour.Item] = field(default_factory=list)
    loop_diags: list[Diagnostic] = field(default_factory=list)
    early: set[int] = field(default_factory=set)
    final: TurnPoint | None = None
    final_contours: dict[Any, Any] = field(default_factory=dict)
    ended: bool = False
    end_counters: tuple[int, int, int] = (0, 0, 0)
    last: tuple[int, int] = (0, -1)
    spent: bool = False

    def fits(self, limits: Limits, now: tuple[int, int, int], j: int) -> bool:
        """Whether the rest of this run from step `j`, with the counters at `now`, spends its budgets as it did."""
        if self.spent:
            return now == self.counters[j]
        e, s, m = self.end_counters
        je, js, jm = self.counters[j]
        return (
            e + now[0] - je <= limits.max_executed_blocks
            and s + now[1] - js <= limits.max_evaluation_steps
            and m + now[2] - jm <= limits.max_moves
        )


def touches(lo: int, hi: int, first: int, end: int) -> bool:
    """Whether the lines lo < line ≤ hi meet the changed lines first ≤ line < end (an insertion when equal)."""
    if first == end:
        return lo < first <= hi
    return max(lo + 1, first) <= min(hi, end - 1)


def map_point(lm: LineMap, p: TurnPoint, shift_run: Any) -> TurnPoint:
    """`p` in the new numbering (Unmappable where it names a changed line)."""
    if lm.identity:
        return p
    if lm.delta == 0:  # the same lines; only whether it names a changed one
        first, end = lm.first, lm.end
        if (p.unit[0] is None and first <= p.line < end) or (
            p.end is not None and p.unit[0] is None and first <= p.end < end
        ):
            raise Unmappable
        for u, c, k, s, e, _ in p.calls:
            if (u[0] is None and first <= c < end) or (
                k[0] is None and (first <= s < end or (e is not None and first <= e < end))
            ):
                raise Unmappable
        shift_run(lm, p.run)
        return p

    def ln(line: int, source: str | None) -> int:
        return line if line < 0 else lm.line(line, source)

    calls = tuple(
        (u, ln(c, u[0]), k, ln(s, k[0]), None if e is None else ln(e, k[0]), n)
        for u, c, k, s, e, n in p.calls
    )
    return TurnPoint(
        p.unit,
        ln(p.line, p.unit[0]),
        None if p.end is None else ln(p.end, p.unit[0]),
        calls,
        shift_run(lm, p.run),
    )


def map_item(lm: LineMap, item: turn_contour.Item, library: bool) -> turn_contour.Item:
    """An item of a block in the new numbering (a library program's block keeps its lines, not its call stack)."""
    if lm.delta == 0:  # the same lines (an item of a step that meets the change is never mapped)
        return item
    if isinstance(item, turn_contour.TurnItem):
        t = _move(lm, item.template, library)
        return item if t is item.template else dataclasses.replace(item, template=t)
    if isinstance(item, Move):
        return _move(lm, item, library)
    if isinstance(item, (Dwell, ToolChange, turn_contour.SrkSwitch)) and not library:
        span = lm.span(item.span)
        return item if span == item.span else dataclasses.replace(item, span=span)
    return item


def _move(lm: LineMap, m: Move, library: bool) -> Move:
    if not library:
        return lm.move(m)
    stack = tuple((s, lm.line(ln, s)) for s, ln in m.call_stack) if m.call_stack else m.call_stack
    return m if stack == m.call_stack else dataclasses.replace(m, call_stack=stack)


_LINE_PARAM = ("TX-E404", "TX-W405", "TX-E410")  # their message names a line of the contour: `second`


def map_diagnostic(lm: LineMap, d: Diagnostic) -> Diagnostic:
    """`d` in the new numbering, the line its message names included."""
    new = lm.diagnostic(d)
    if d.code in _LINE_PARAM and "second" in d.params and not lm.identity:
        second = lm.line(int(d.params["second"]), d.source)
        if second != d.params["second"]:
            made = diag(d.code, new.span, **{**d.params, "second": second})
            new = dataclasses.replace(made, source=new.source, follows_from=new.follows_from)
    return new


def map_contours(lm: LineMap, contours: dict[Any, Any], done: dict[int, dict[Any, Any]]) -> dict[Any, Any]:
    """The cycles' contour cache in the new numbering (its keys and points name lines); `done` by id."""
    if lm.identity or not contours:
        return contours
    found = done.get(id(contours))
    if found is None:
        found = done[id(contours)] = {
            (k[0], lm.line(k[1], k[0]) if k[1] else 0, *k[2:]): [(p, lm.line(ln, k[0])) for p, ln in v]
            for k, v in contours.items()
        }
    return found


def carry_contours(
    lm: LineMap,
    base: dict[Any, Any],
    now: dict[Any, Any],
    later: dict[Any, Any],
    done: dict[int, dict[Any, Any]],
) -> dict[Any, Any]:
    """The cache of the previous run at a later step (`later`, which grew from `base` where this run met it
    with `now`) as this run has it there: `now` and what the previous run added, in the new numbering."""
    if later is base:
        return now
    found = done.get(id(later))
    if found is None:
        found = done[id(later)] = dict(now)
        for k, v in later.items():
            if k not in base:
                found[(k[0], lm.line(k[1], k[0]) if k[1] else 0, *k[2:])] = [
                    (p, lm.line(ln, k[0])) for p, ln in v
                ]
    return found
