"""The run loop of every dialect: Program → Toolpath, following calls, repeated sections, jumps and the end.

The loop owns what concerns the program as a whole — the units and the frames in progress (run.py), the
budgets of work (core/limits.py), the end at M30 and the missing M30, the line states, the checkpoints for
the next run (checkpoints.py) and the cap on diagnostics. What a block means is the dialect's *machine*:
PAL, ISO and Beckhoff milling (mill_machine.py) and TRAUB turning (traub_turn.py). A machine executes a
block and says where the program goes on (`Step`); its state is a value (`Machine.snap`) that a checkpoint
keeps and the loop restores.

PAL's G23 section repeat, its L call, ISO's M98 and TRAUB's G22 with or without P/Q are one `Step.call`.
"""

from __future__ import annotations

import dataclasses
from array import array
from bisect import bisect_left
from dataclasses import dataclass
from typing import Any

from core.diagnostics import Diagnostic, diag
from core.interpreter.checkpoints import (
    INF,
    MAX_STEPS,
    STATS,
    FramePoint,
    Keep,
    LineMap,
    Point,
    Trace,
    Unmappable,
    changed_lines,
    map_touch,
    restart,
    structure_kept,
)
from core.interpreter.contour import Planned
from core.interpreter.run import Cursor, Frame, Unit, UnitKey, cap_diagnostics, dedupe
from core.interpreter.state import ModalState, RunSetup
from core.limits import Budget
from core.syntax.blocks import Block, Program, Span
from core.toolpath import Move, Toolpath, Vec3


@dataclass(frozen=True)
class FlowCodes:
    """The program flow's diagnostics in a dialect's words (PAL's L<n> … M17, ISO's and TRAUB's O<n> … M99)."""

    missing: str  # a called program that is not there (number)
    recursion: str  # a program that calls itself (number)
    depth: str  # calls nested too deep (limit)
    no_number: str  # a block number that a section or jump names is not there (number[, program])
    order: str  # a section that ends before it starts (start, end)
    fell_off: str  # a called program ends without its return (number)
    end_in_call: str  # M30 in a called program (number)
    return_in_main: str  # M17/M99 with no call in progress
    return_ends: bool = False  # whether that ends the run (ISO, TRAUB: the control would start again)
    fell_off_again: bool = False  # a called program that ends without its return runs its next runs (TRAUB)
    names_program: bool = False  # `no_number` also names the program
    repeat_in_itself: str = "PAL-E411"  # a section repeat inside its own section (start, end)


@dataclass(slots=True)
class Step:
    """What one block did, as the loop needs it."""

    items: list[Any]
    diagnostics: list[Diagnostic]
    moves: int = 0  # programmed moves among the items (the budget)
    call: tuple[int | None, int | None, int | None, int, bool] | None = None  # program, first N, last N,
    # count, a G23 repeat; program None: a section of the running program
    jump: int | None = None  # G29: the block number to go on at
    ret: bool = False  # M17 / M99
    end: bool = False  # M30
    stop: bool = False  # an error that stops decoding: nothing after it runs
    reads: list[tuple[int, int]] | None = None  # program-file lines lo < line ≤ hi it read besides its own
    note: Any = None  # something the machine keeps per step for the next run (Machine.replay)


@dataclass(slots=True)
class Rest:
    """The rest of the previous run from the step where this run met it, in the new numbering."""

    final: Any  # the machine's state at its end
    items: list[Any]
    marks: list[int]
    found: list[Diagnostic]
    points: list[Point]
    sets: list[tuple[int, ModalState, Vec3] | None]
    touched: list[tuple[int, int, int, bool]]
    notes: list[tuple[int, Any]]
    lasts: tuple[array[int], array[int]]  # per step: the last main line and its step
    last: tuple[int, int]


class Machine:
    """A dialect's execution of blocks, with its state. The defaults suit a state that names no lines."""

    codes: FlowCodes
    identity: Any  # the set-up: a trace of another one is not used
    initial: ModalState
    marks: set[int]  # ids of items the machine marked (kept with the trace)
    resolves_numbers = False  # blocks resolve block numbers besides the loop's flow (TRAUB's contours)
    carries_as_is = (
        True  # `carry` is `shift`: with the same lines, a later state of the previous run is this one's
    )

    def units(
        self, program: Program, library: dict[int, Program], diags: list[Diagnostic]
    ) -> tuple[Unit, dict[int, Unit], list[Unit]]:
        """The main program, the programs a call can name, and the program file's programs in their order."""
        raise NotImplementedError

    def step(self, block: Block, unit: Unit, program: str | None) -> Step:
        raise NotImplementedError

    def commit(self) -> tuple[ModalState, Vec3]:
        """The block ran within the budgets: take its state; answer the line's state and position."""
        raise NotImplementedError

    def dropped(self, block: Block) -> None:
        """A block the parser rejected was met."""

    def skipped(self, block: Block) -> bool:
        return False

    def stamp(self, items: list[Any], source: str | None, stack: tuple[tuple[str | None, int], ...]) -> None:
        """Give the moves among `items` (in place) the program they run in and the calling blocks."""

    def snap(self) -> Any:
        raise NotImplementedError

    def restore(self, snap: Any) -> None:
        raise NotImplementedError

    def shift(self, lm: LineMap, snap: Any, done: dict[int, Any]) -> Any:
        """A state of the previous run in the new numbering (Unmappable where it names a changed line)."""
        return snap

    def same(self, lm: LineMap, old: Any, now: Any) -> bool:
        """Whether the previous run's state `old` is this run's `now`."""
        return bool(self.shift(lm, old, {}) == now)

    def carry(self, lm: LineMap, base: Any, now: Any, later: Any, done: dict[int, Any]) -> Any:
        """A later state of the previous run, which met this one at `base` = `now`, as this run has it."""
        return self.shift(lm, later, done)

    def shift_note(self, lm: LineMap, note: Any) -> Any:
        return note

    def replay(self, note: Any) -> None:
        """A note of a step taken over from the previous run."""

    def commands(self, items: list[Any], diags: list[Diagnostic]) -> list[Any]:
        """The items as the toolpath's commands (the contour stage)."""
        raise NotImplementedError

    def finish(self, result: Toolpath, states: list[ModalState | None], positions: list[Vec3 | None]) -> None:
        """The rest of the toolpath: line states, parameters, the final position."""
        raise NotImplementedError

    def judge(self, diags: list[Diagnostic]) -> None:
        """A last look at the findings (deduplicated, not yet capped)."""


def run_loop(
    program: Program,
    machine: Machine,
    setup: RunSetup,
    diagnostics: list[Diagnostic] | None = None,
    library: dict[int, Program] | None = None,
    keep: Keep | None = None,
) -> Toolpath:
    """Execute the program from its first block; never raises on user input.

    `keep` holds the checkpoints of the previous run of the same document (checkpoints.py): this run
    executes only what the change can affect and takes the rest over; the result is the same as a full
    run's. It then holds this run's."""
    return Loop(program, machine, setup, diagnostics, library, keep).run()


class Loop:
    """One run: where it is, what it made, and its checkpoints."""

    def __init__(
        self,
        program: Program,
        machine: Machine,
        setup: RunSetup,
        diagnostics: list[Diagnostic] | None,
        library: dict[int, Program] | None,
        keep: Keep | None,
    ) -> None:
        self.program, self.machine, self.setup, self.keep = program, machine, setup, keep
        self.result = Toolpath(diagnostics=list(diagnostics or []), limits=setup.limits)
        self.diags = self.result.diagnostics
        self.main, self.subs, file_units = machine.units(program, library or {}, self.diags)
        self.result.initial = machine.initial
        self.n_initial = len(self.diags)  # the parser's diagnostics (and the programs') come first
        self.keys: dict[UnitKey, Unit] = {self.main.key: self.main, **{u.key: u for u in self.subs.values()}}
        n = len(program.blocks)
        self.states: list[ModalState | None] = [None] * n
        self.positions: list[Vec3 | None] = [None] * n
        self.items: list[Any] = []
        self.cur = Cursor(self.main)
        self.budget = Budget(setup.limits)
        self.ended = False
        self.last = (0, -1)  # the last line of the main program that ran (PAL-W102) and its step
        self.step = 0
        self.came_from: int | None = 0  # the program-file line the run passed last on its way (None: a jump)
        # -- checkpoints: this run's, and the previous run's steps it may meet --------------------------
        self.trace: Trace | None = None
        if keep is not None:
            signature = tuple((u.number, u.line) for u in file_units)
            self.trace = Trace(program.blocks, machine.identity, setup.limits, signature)
            self.trace.labels = machine.resolves_numbers
        self.old = keep.trace if keep is not None else None
        self.lm = LineMap(1, 1, 0)
        self.meet = -1  # the previous run's steps from this one on may be met (-1: none)
        self._library_steps: dict[tuple[UnitKey, int], list[int]] | None = None
        self.kind = "full"
        self.shifted: dict[int, Move] = {}  # moves taken over with their lines shifted → the previous run's

    def run(self) -> Toolpath:
        if self.trace is not None:
            if self.old is not None and self._resume():
                self.kind = "to_end"  # until it meets the previous run
            STATS[self.kind] += 1
        self._loop()
        if self.kind == "incremental":
            STATS["to_end"] -= 1
            STATS["incremental"] += 1
        return self._finish()

    def report(self, d: Diagnostic) -> None:
        source = self.cur.unit.source
        self.diags.append(d if source is None else dataclasses.replace(d, source=source))

    # -- the loop ----------------------------------------------------------------------------------

    def _loop(self) -> None:
        cur, machine = self.cur, self.machine
        main = self.main
        while True:
            unit, index = cur.unit, cur.index
            if index >= len(unit.blocks):
                if not self._fell_off(unit):
                    return
                continue
            block = unit.blocks[index]
            if self.trace is not None and self._checkpoint(unit, index, block):
                return  # the rest is the previous run's
            self.came_from = block.line if unit.source is None else None
            cur.index += 1
            self.step += 1
            if not block.ok or block.is_empty or block.header is not None:
                if not block.ok:
                    machine.dropped(block)
                continue
            if unit is main:
                self.last = (block.line, self.step - 1)
            if machine.skipped(block):
                continue
            if not self._execute(unit, index, block):
                return

    def _execute(self, unit: Unit, index: int, block: Block) -> bool:
        """Run the block and go on where it says; False: the run ends."""
        cur, budget, trace = self.cur, self.budget, self.trace
        spent = budget.block(block)
        if spent is None:
            out = self.machine.step(block, unit, cur.frames[-1].callee.name if cur.frames else None)
            if trace is not None:
                if out.reads:
                    trace.touches.extend((self.step - 1, lo, hi, False) for lo, hi in out.reads)
                if out.note is not None:
                    trace.notes.append((self.step - 1, out.note))
            budget.reported(len(out.diagnostics))
            spent = budget.made(out.moves, block)
        if spent is not None:
            self.report(spent)
            self.ended = True  # stopped: a missing M30 is no news
            if trace is not None:
                trace.spent = True
            return False
        line_state = self.machine.commit()
        if cur.frames and cur.calling():
            self.machine.stamp(out.items, unit.source, cur.call_stack())
        self.items.extend(out.items)
        for d in out.diagnostics:
            self.report(d)
        if unit.source is None:
            at = block.line - 1
            self.states[at], self.positions[at] = line_state
            if trace is not None:
                trace.sets[-1] = (at, *line_state)
        if out.call is not None:
            if self._call(out.call, block):
                self.came_from = None
                return True
        elif out.jump is not None:
            if trace is not None:
                trace.labels = True
            target = unit.numbers.get(out.jump)
            if target is None:
                self.report(self._no_number(block.span, out.jump, unit))
            else:
                cur.index, self.came_from = target, None
                return True
        if out.ret:
            return self._return(index, block)
        if out.stop:
            self.ended = True
            return False
        if out.end:
            self._end(unit, block)
            return False
        self._after(index)
        return True

    def _arrived(self, how: str | None) -> int | None:
        """The program-file line the run passed last after a move of the cursor (None: a jump)."""
        if how == "returned" and self.cur.unit.source is None:
            return self.cur.returned_from  # on after the calling block
        return None

    def _after(self, index: int) -> None:
        how = self.cur.after(index)
        if how is not None:
            self.came_from = self._arrived(how)

    def _no_number(self, span: Span, number: int, unit: Unit) -> Diagnostic:
        codes = self.machine.codes
        if codes.names_program:
            return diag(codes.no_number, span, number=number, program=unit.name)
        return diag(codes.no_number, span, number=number)

    def _call(self, call: tuple[int | None, int | None, int | None, int, bool], block: Block) -> bool:
        """Enter a program or a section; False after an error or with no run to make."""
        target, first_n, last_n, count, repeat = call
        cur, codes = self.cur, self.machine.codes
        unit = cur.unit
        callee = unit
        if target is not None:
            found = self.subs.get(target)
            if found is None:
                self.report(diag(codes.missing, block.span, number=target))
                return False
            if cur.active(found):
                self.report(diag(codes.recursion, block.span, number=target))
                return False
            callee = found
        if repeat and cur.repeating(unit, block.line):
            # the section holds its own G23: each pass would open another repeat, never ending (and never nested
            # too deep, a repeat being no call) — skipped, so that the section runs its passes once each
            self.report(diag(codes.repeat_in_itself, block.span, start=first_n, end=last_n))
            return False
        if not repeat and cur.depth() >= self.setup.max_call_depth:
            self.report(diag(codes.depth, block.span, limit=self.setup.max_call_depth))
            return False
        if first_n is not None or last_n is not None:
            if self.trace is not None:
                self.trace.labels = True
            missing = [n for n in (first_n, last_n) if n is not None and n not in callee.numbers]
            for n in missing:
                self.report(self._no_number(block.span, n, callee))
            if missing:
                return False
        start = 0 if first_n is None else callee.numbers[first_n]
        stop = None if last_n is None else callee.numbers[last_n]
        if stop is not None and stop < start:
            self.report(diag(codes.order, block.span, start=first_n, end=last_n))
            return False
        if count < 1:
            return False
        cur.enter(Frame(unit, cur.index, callee, start, stop, count - 1, block.line, repeat))
        return True

    def _return(self, index: int, block: Block) -> bool:
        """M17 / M99: back to the caller; in the main program a finding (and the end, where it says so)."""
        cur, codes = self.cur, self.machine.codes
        if cur.calling():
            self.came_from = self._arrived(cur.leave())
            return True
        self.report(diag(codes.return_in_main, block.span))
        if codes.return_ends:
            self.ended = True
            return False
        self._after(index)  # (it may end a repeated section)
        return True

    def _end(self, unit: Unit, block: Block) -> None:
        """M30: the end; in a called program a finding, in the main program blocks after it are one."""
        self.ended = True
        if self.cur.calling() and unit is not self.main:
            self.report(diag(self.machine.codes.end_in_call, block.span, number=unit.number))
            return
        if self.trace is not None and unit.source is None:
            self.trace.touches.append((self.step - 1, block.line, INF, False))  # PAL-W101 looks at the rest
        rest = next(
            (b for b in unit.blocks[self.cur.index :] if b.ok and not b.is_empty and b.header is None), None
        )
        if unit is self.main and rest is not None:
            self.diags.append(diag("PAL-W101", rest.span))

    def _fell_off(self, unit: Unit) -> bool:
        """Past a unit's last block: back to the caller (True) or the end of the run."""
        cur = self.cur
        if self.trace is not None and unit.source is None:
            self.trace.touches.append((self.step, unit.tail, INF, True))  # the lines after its last block
        if not cur.calling():
            return False
        codes = self.machine.codes
        if unit is not self.main:
            tail = unit.tail
            self.report(diag(codes.fell_off, Span(tail, 1, tail, 1), number=unit.number))
        self.came_from = self._arrived(cur.leave(again=codes.fell_off_again))
        return True

    # -- the end of the run ------------------------------------------------------------------------

    def _finish(self) -> Toolpath:
        trace, keep, machine, diags = self.trace, self.keep, self.machine, self.diags
        if trace is not None:
            trace.items, trace.loop_diags, trace.marks = (
                self.items,
                diags[self.n_initial :],
                set(machine.marks),
            )
            trace.final, trace.ended = machine.snap(), self.ended
            trace.counters, trace.last = self.budget.counters, self.last
        if keep is not None:
            keep.trace, keep.kind, keep.shifted = trace, self.kind, self.shifted
        truncated = any(d.code == "PAL-E006" for d in diags)  # lines beyond the limit were not read
        if not self.ended and not truncated and self.program.has_content:
            line = self.last[0] or 1
            diags.append(diag("PAL-W102", Span(line, 1, line, 1)))
        result = self.result
        result.commands = machine.commands(self.items, diags)
        result.work = self.budget.counters
        machine.finish(result, self.states, self.positions)
        dedupe(diags)
        machine.judge(diags)
        cap_diagnostics(diags, self.setup.limits.max_diagnostics)
        return result

    # -- checkpoints (checkpoints.py) ------------------------------------------------------------

    def _frame_points(self) -> tuple[FramePoint, ...]:
        points = []
        for f in self.cur.frames:
            callee = f.callee.blocks
            points.append(
                (
                    f.caller.key,
                    f.line,
                    f.callee.key,
                    callee[f.start].line if f.start < len(callee) else -1,
                    None if f.end is None else callee[f.end].line,
                    f.remaining,
                    f.repeat,
                )
            )
        return tuple(points)

    def _checkpoint(self, unit: Unit, index: int, block: Block) -> bool:
        """Record the point before `block`; True where the run met the previous one and took the rest over."""
        trace = self.trace
        assert trace is not None
        if unit.source is None:
            came = self.came_from
            if came is None and index == 0:
                came = unit.line if unit is not self.main else 0
            # (after a jump: the block itself, which may have changed but kept its number)
            scan = block.line - 1 if came is None else came
            if scan < block.line:
                trace.touches.append((self.step, scan, block.line, True))
        point = Point(
            unit.key, block.line, self._frame_points() if self.cur.frames else (), self.machine.snap()
        )
        if self.meet >= 0:
            candidates = self._candidates(point.unit, point.line)
            if candidates and self._take_over(candidates, point):
                return True
        if self.step < MAX_STEPS:
            trace.record(
                point, self.budget.counters, len(self.items), len(self.diags) - self.n_initial, self.last
            )
        else:
            self.trace = None  # too long to keep: the next run is a full one
        return False

    def _candidates(self, key: UnitKey, line: int) -> list[int]:
        """The previous run's steps this run may meet at `line` of unit `key` (new numbering)."""
        old = self.old
        assert old is not None
        was = self.lm.back(line, key[0])
        if was is None:
            return []
        if key[0] is None:  # a unit of the program file: its lines are in `lines`, found by the array
            where, points, i = old.lines, old.points, self.meet
            found: list[int] = []
            while True:
                try:
                    i = where.index(was, i)
                except ValueError:
                    return found
                if points[i].unit == key:
                    found.append(i)
                i += 1
        if self._library_steps is None:
            self._library_steps = {}
            for j in range(self.meet, len(old.points)):
                p = old.points[j]
                if p.unit[0] is not None:
                    self._library_steps.setdefault((p.unit, p.line), []).append(j)
        return self._library_steps.get((key, was), [])

    def _map_where(self, p: Point) -> Point:
        """`p` of the previous run with its lines in the new numbering, the machine's state as it was
        (Unmappable where it names a changed line)."""
        lm = self.lm
        if lm.identity:
            return p
        frames = tuple(
            (
                u,
                lm.line(c, u[0]),
                k,
                s if s < 0 else lm.line(s, k[0]),
                None if e is None else lm.line(e, k[0]),
                n,
                r,
            )
            for u, c, k, s, e, n, r in p.frames
        )
        line = lm.line(p.line, p.unit[0])
        if line == p.line and frames == p.frames:
            return p
        return Point(p.unit, line, frames, p.machine)

    def _map_point(self, p: Point, done: dict[int, Any]) -> Point:
        """`p` of the previous run in the new numbering, the machine's state included."""
        q = self._map_where(p)
        snap = self.machine.shift(self.lm, p.machine, done)
        return q if snap is q.machine else q._replace(machine=snap)

    def _place(self, p: Point) -> tuple[Unit, int, list[Frame]]:
        """The loop's position and frames at `p` (Unmappable where a line is no block of its program)."""
        keys = self.keys
        frames = []
        for u, c, k, s, e, n, repeat in p.frames:
            caller, callee = keys[u], keys[k]
            frames.append(
                Frame(
                    caller,
                    caller.index_of(c) + 1,
                    callee,
                    callee.index_of(s),
                    None if e is None else callee.index_of(e),
                    n,
                    c,
                    repeat,
                )
            )
        unit = keys[p.unit]
        return unit, unit.index_of(p.line), frames

    def _resume(self) -> bool:
        """Start where the previous run's checkpoints let this one start; False: a full run."""
        old, trace, machine = self.old, self.trace, self.machine
        assert old is not None and trace is not None
        if not old.points or old.identity != trace.identity:
            return False
        blocks = self.program.blocks
        if self.program.base is old.blocks and self.program.changed is not None:
            first, old_end, new_end = self.program.changed  # (the parse compared the lines already)
        else:
            first, old_end, new_end = changed_lines(old.blocks, blocks)
        if not structure_kept(old, blocks, first, old_end, new_end):
            return False
        lm = LineMap(first, old_end, new_end - old_end)
        try:  # the file's programs: an O block may head the main program or start a program of its own
            if tuple((u, lm.line(ln) if ln else 0) for u, ln in old.units) != trace.units:
                return False
        except Unmappable:
            return False
        k, self.meet = restart(old, first, old_end)
        self.lm = lm
        r = k - 1  # the step before the first changed one runs again: it goes on to what now follows it
        if r < 0:
            return True
        done: dict[int, Any] = {}
        try:
            cp = self._map_point(old.points[r], done)
            place = self._place(cp)
            same = lm.delta == 0  # the same lines before and after the change: nothing to map
            kept = old.points[:r] if same else [self._map_point(p, done) for p in old.points[:r]]
            touched = old.touches[: bisect_left(old.touches, (r + 1,))]  # (those of step r: conservative)
            notes = old.notes[: bisect_left(old.notes, (r,), key=lambda x: (x[0],))]
            found = old.loop_diags[: old.n_diags[r]]
            if not same:
                touched = [(s, *map_touch(lm, a, b), arr) for s, a, b, arr in touched]
                notes = [(s, machine.shift_note(lm, x)) for s, x in notes]
                found = [lm.diagnostic(d) for d in found]
                last_lines = array("q", [lm.line(a) if a else 0 for a in old.last_lines[:r]])
                lines = array("q", [lm.line(a) if a else 0 for a in old.lines[:r]])
            items, marks = self._carried_items(0, old.n_items[r])
            sets = old.sets[:r] if lm.delta == 0 else [self._map_set(x) for x in old.sets[:r]]
            last = (lm.line(old.last_lines[r]) if old.last_lines[r] else 0, old.last_steps[r])
        except (Unmappable, KeyError):
            self.meet = -1
            return False
        trace.take_start(old, r)
        trace.points, trace.touches, trace.notes, trace.sets = kept, touched, notes, sets
        if not same:
            trace.last_lines, trace.lines = last_lines, lines
        self.cur.unit, self.cur.index, self.cur.frames = place
        machine.restore(cp.machine)
        for _, note in notes:
            machine.replay(note)
        self.budget.executed, self.budget.steps, self.budget.moves = old.counters_at(r)
        self.items = items
        machine.marks.update(marks)
        self._set_lines(sets)
        self.diags.extend(found)
        self.last, self.came_from, self.step = last, None, r
        return True

    def _map_set(self, x: tuple[int, ModalState, Vec3] | None) -> tuple[int, ModalState, Vec3] | None:
        return None if x is None else (self.lm.line(x[0] + 1) - 1, x[1], x[2])

    def _set_lines(self, sets: list[tuple[int, ModalState, Vec3] | None]) -> None:
        if self.setup.answer_only:
            return  # (no state per line)
        states, positions = self.states, self.positions
        for x in sets:
            if x is not None:
                states[x[0]], positions[x[0]] = x[1], x[2]

    def _carried_items(self, j: int, stop: int | None = None) -> tuple[list[Any], list[int]]:
        """The previous run's items of steps `j`… (up to item `stop`) in the new numbering, and the ids of the
        marked ones."""
        old, lm = self.old, self.lm
        assert old is not None
        begin = old.n_items[j] if j < len(old.n_items) else len(old.items)
        end = len(old.items) if stop is None else stop
        marked = old.marks
        if lm.delta == 0:  # the same lines: the same items
            items = old.items[begin:end]
            return items, [id(x) for x in items if id(x) in marked] if marked else []
        items, marks = [], []
        n = len(old.points)
        for s in range(j, n):
            lo = old.n_items[s]
            if lo >= end:
                break
            hi = min(old.n_items[s + 1] if s + 1 < n else len(old.items), end)
            library = bool(old.library[s])
            for it in old.items[lo:hi]:
                new = lm.item(it, library)
                items.append(new)
                if id(it) in marked:
                    marks.append(id(new))
        return items, marks

    def _same(self, then: Point, now: Point) -> bool:
        lm = self.lm
        if then.unit != now.unit or len(then.frames) != len(now.frames):
            return False
        p = self._map_where(then)
        return (
            p.line == now.line and p.frames == now.frames and self.machine.same(lm, then.machine, now.machine)
        )

    def _take_over(self, candidates: list[int], now: Point) -> bool:
        """If the run, about to take its next step at `now`, is where the previous run was at one of its steps
        `candidates`, append the rest of the previous run (its lines mapped) and end; else False."""
        old = self.old
        assert old is not None
        counters = self.budget.counters
        for j in candidates:
            if not old.fits(counters, j):
                continue
            try:
                if not self._same(old.points[j], now):
                    continue
                rest = self._rest(j, now)
            except Unmappable:
                continue
            self._take(j, rest)
            self.last, self.ended, self.kind = rest.last, old.ended, "incremental"
            return True
        return False

    def _rest(self, j: int, now: Point) -> Rest:
        """The rest of the previous run from its step `j`, where this run meets it at `now`, in the new
        numbering (Unmappable where some of it names a changed line)."""
        old, lm, machine, step = self.old, self.lm, self.machine, self.step
        assert old is not None
        same = lm.delta == 0  # the same lines: nothing after the meeting names a changed one
        done: dict[int, Any] = {}
        base = old.points[j].machine
        final = machine.carry(lm, base, now.machine, old.final, done)
        items, marks = self._carried_items(j)
        found = old.loop_diags[old.n_diags[j] :]
        touched = old.touches[bisect_left(old.touches, (j,)) :]
        notes = old.notes[bisect_left(old.notes, (j,), key=lambda x: (x[0],)) :]
        if same and machine.carries_as_is:
            points, sets = old.points[j:], old.sets[j:]
        else:
            points = []
            for p in map(self._map_where, old.points[j:]):
                snap = machine.carry(lm, base, now.machine, p.machine, done)
                points.append(p if snap is p.machine else p._replace(machine=snap))
            sets = old.sets[j:] if same else [self._map_set(x) for x in old.sets[j:]]
        if not same:
            found = [lm.diagnostic(d) for d in found]
            touched = [(s - j + step, *map_touch(lm, a, b), arr) for s, a, b, arr in touched]
            notes = [(s - j + step, machine.shift_note(lm, x)) for s, x in notes]
        elif step != j:
            touched = [(s - j + step, a, b, arr) for s, a, b, arr in touched]
            notes = [(s - j + step, x) for s, x in notes]
        then = (old.last_lines[j], old.last_steps[j])
        if same and step == j and self.last == then:  # the same last line before the meeting
            lasts = (old.last_lines[j:], old.last_steps[j:])
        else:
            lines, steps = array("q"), array("q")
            for a, b in zip(old.last_lines[j:], old.last_steps[j:], strict=True):
                line, at = (lm.line(a) if a else 0, b - j + step) if b >= j else self.last
                lines.append(line)
                steps.append(at)
            lasts = (lines, steps)
        last = (lm.line(old.last[0]), old.last[1] - j + step) if old.last[1] >= j else self.last
        return Rest(final, items, marks, found, points, sets, touched, notes, lasts, last)

    def _take(self, j: int, rest: Rest) -> None:
        """Append the rest of the previous run from its step `j` (mapped by `_take_over`) to this run."""
        old, trace, machine, budget = self.old, self.trace, self.machine, self.budget
        assert old is not None and trace is not None
        items, points = rest.items, rest.points
        lm = self.lm
        d = tuple(x - y for x, y in zip(budget.counters, old.counters_at(j), strict=True))
        d_items, d_diags = len(self.items) - old.n_items[j], len(self.diags) - self.n_initial - old.n_diags[j]
        if lm.delta:  # the moves that only moved lines (Keep.shifted)
            for a, b in zip(old.items[old.n_items[j] :], items, strict=True):
                if isinstance(a, Planned) and isinstance(b, Planned) and b.move is not a.move:
                    self.shifted[id(b.move)] = a.move
        self.items.extend(items)
        machine.marks.update(rest.marks)
        self._set_lines(rest.sets)
        machine.restore(rest.final)
        for _, note in rest.notes:
            machine.replay(note)
        e, s, m = old.counters
        budget.executed, budget.steps, budget.moves = e + d[0], s + d[1], m + d[2]
        if len(trace.points) + len(points) <= MAX_STEPS:
            trace.points.extend(points)
            for mine, theirs, delta in (
                (trace.executed, old.executed, d[0]),
                (trace.steps, old.steps, d[1]),
                (trace.moves, old.moves, d[2]),
                (trace.n_items, old.n_items, d_items),
                (trace.n_diags, old.n_diags, d_diags),
            ):
                mine.extend(theirs[j:] if delta == 0 else array("q", [x + delta for x in theirs[j:]]))
            trace.last_lines.extend(rest.lasts[0])
            trace.last_steps.extend(rest.lasts[1])
            trace.library.extend(old.library[j:])
            trace.lines.extend(
                old.lines[j:]
                if lm.delta == 0
                else array("q", [lm.line(x) if x else 0 for x in old.lines[j:]])
            )
            trace.sets.extend(rest.sets)
            trace.touches.extend(rest.touched)
            trace.notes.extend(rest.notes)
            trace.spent = old.spent
            trace.labels = trace.labels or old.labels
        else:
            self.trace = None  # too long to keep: the next run is a full one
        self.diags.extend(rest.found)
