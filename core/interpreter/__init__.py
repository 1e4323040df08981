"""The interpreter: Program → Toolpath. Runs the blocks in order and keeps the state of every line.

The loop owns what concerns the program as a whole: skip blocks, the end at M30, the budgets of work
(executed blocks, evaluation steps, programmed moves: core/limits.py), the missing M30, the cap on
diagnostics. What a single block means is the dialect's block executor (core/interpreter/pal_mill.py).
"""

from __future__ import annotations

import dataclasses
from array import array
from typing import Any, Protocol

from core.diagnostics import Diagnostic, diag
from core.dialects.codes import CodeTable
from core.interpreter.checkpoints import (
    MAX_STEPS,
    STATS,
    Checkpoint,
    FramePoint,
    Keep,
    LineMap,
    Trace,
    UnitKey,
    Unmappable,
    changed_lines,
    structure_kept,
)
from core.interpreter.contour import Item, Planned, finish
from core.interpreter.followups import FollowUps
from core.interpreter.run import (
    Cursor,
    Frame,
    Unit,
    cap_diagnostics,
    dedupe,
    finish_toolpath,
    library_unit,
    split_units,
)
from core.interpreter.state import ModalState, RunSetup, switch_on_state
from core.limits import Budget
from core.syntax.blocks import Block, Program, Span
from core.toolpath import Move, Toolpath, Vec3


class BlockExecutor(Protocol):
    def __call__(
        self,
        setup: RunSetup,
        state: ModalState,
        position: Vec3,
        block: Block,
        params: dict[int, float],
        *,
        cache: dict[Any, Any] | None = None,
    ) -> BlockOutcome: ...


class BlockOutcome(Protocol):
    @property
    def state(self) -> ModalState: ...
    @property
    def position(self) -> Vec3: ...
    @property
    def commands(self) -> list[Item]: ...
    @property
    def diagnostics(self) -> list[Diagnostic]: ...
    @property
    def ended(self) -> bool: ...
    @property
    def sub_end(self) -> bool: ...
    @property
    def flow(self) -> tuple[str, int, int] | None: ...
    @property
    def repeat(self) -> tuple[int, int, int] | None: ...


def _frame_points(frames: list[Frame]) -> tuple[FramePoint, ...]:
    """The frames in lines (checkpoints): a call's callee runs from its start; a G23 section names its lines."""
    points: list[FramePoint] = []
    for f in frames:
        u = f.caller
        if f.repeat:
            assert f.end is not None
            points.append(
                (
                    u.key,
                    u.first + f.return_index,
                    u.key,
                    u.first + f.start,
                    u.first + f.end,
                    f.remaining,
                    f.line,
                    True,
                )
            )
        else:
            points.append(
                (u.key, u.first + f.return_index, f.callee.key, 0, None, f.remaining, f.line, False)
            )
    return tuple(points)


def _frames_at(points: tuple[FramePoint, ...], units: dict[UnitKey, Unit]) -> list[Frame]:
    frames = []
    for u, r, c, s, e, n, ln, repeat in points:
        caller = units[u]
        first = caller.first
        if repeat:
            assert e is not None
            frames.append(Frame(caller, r - first, caller, s - first, e - first, n, ln, True))
        else:
            frames.append(Frame(caller, r - first, units[c], 0, None, n, ln))
    return frames


def interpret(  # noqa: C901
    program: Program,
    table: CodeTable,
    execute: BlockExecutor,
    setup: RunSetup,
    diagnostics: list[Diagnostic] | None = None,
    library: dict[int, Program] | None = None,
    readings: dict[Any, Any] | None = None,
    keep: Keep | None = None,
) -> Toolpath:
    """Execute the program from its first block, following calls, repeats and jumps; never raises on user input.

    `readings` is the executor's reading of blocks kept from an earlier run of the same blocks (see
    core.pipeline.Memo; each entry holds its block); once it has grown it is pruned to this program's blocks.
    `keep` holds the checkpoints of the previous run of the same document (core/interpreter/checkpoints.py):
    this run executes only what the change can affect and takes the rest over; the result is the same as a
    full run's. It then holds this run's.
    """
    limits = setup.limits
    result = Toolpath(diagnostics=list(diagnostics or []), limits=limits)
    diags = result.diagnostics
    n_initial = len(diags)  # the parser's diagnostics come first
    state = result.initial = switch_on_state(table)
    position = setup.start
    params = result.params
    prefix = table.program_prefix
    flow = _FLOW_CODES[prefix]
    main, subs = split_units(program, prefix)
    for number, prog in (library or {}).items():
        subs.setdefault(number, library_unit(number, prog, prefix))
    units = {main.key: main, **{u.key: u for u in subs.values()}}
    n_lines = len(program.blocks)
    states: list[ModalState | None] = [None] * n_lines
    positions: list[Vec3 | None] = [None] * n_lines
    planned: list[Item] = []
    # the executor keeps its reading of blocks once the program first goes back (a call, a repeat, a
    # jump): until then every block runs once and keeping them would only cost
    cache: dict[Any, Any] | None = readings
    cur = Cursor(main)  # where the run is, and the calls and G23 sections in progress
    ended = False
    budget = Budget(limits)
    last_line = 0
    follow = FollowUps()  # what blocks dropped by an error leave unknown (follow-up errors)
    # -- checkpoints: this run's, and where the previous run's let it start and stop ---------------
    identity = (setup, table, execute)
    trace = Trace(program.blocks, identity, limits) if keep is not None else None
    set_at = [-1] * n_lines if trace is not None else []
    last_set = -1
    params_now: dict[int, float] = {}  # a copy of params as they are now (the checkpoints share it)
    step = 0
    old = keep.trace if keep is not None and isinstance(keep.trace, Trace) else None
    meet: Meeting | None = None  # the steps of the previous run this one may meet
    lines = LineMap(1, 1, 0)
    resume_at: Checkpoint | None = None
    kind = "full"
    shifted: dict[int, Move] = {}  # moves taken over with their lines shifted → the previous run's (Keep)
    if old is not None and trace is not None:
        resumed = _resume(old, trace, program.blocks, identity, units)
        if resumed is None:
            STATS["full"] += 1
        else:
            k, lines, meet, resume_at = resumed
            STATS["to_end"] += 1  # until it meets the previous run
            kind = "to_end"
        if resumed is not None and resume_at is not None:
            cp = resume_at
            cur.unit, cur.index = units[cp.unit], cp.line - units[cp.unit].first
            state, position = cp.state, cp.position
            params.update(cp.params)
            params_now = cp.params
            cur.frames = _frames_at(cp.frames, units)
            follow.unknown = cp.unknown
            for _, where, unknown in trace.at_log:
                follow.at.setdefault(where, unknown)
            budget.executed, budget.steps, budget.moves = old.executed[k], old.steps[k], old.moves[k]
            planned = old.items[: old.planned[k]]
            # (a subprogram without blocks names its header line, which may lie after the change)
            diags.extend(
                old.loop_diags[: old.diags[k]]
                if lines.delta == 0
                else [lines.diagnostic(d) for d in old.loop_diags[: old.diags[k]]]
            )
            last_line, last_set = _last_main(old, k)
            # the state after each line as of step k: lines are met once (the previous run's last setting of
            # a line is its only one before k, if it is before k) or else step by step
            if old.revisits:
                cps, sets = old.checkpoints, old.sets
                for i in range(k):
                    if sets[i]:
                        n = cps[i].line - 1
                        states[n], positions[n], set_at[n] = cps[i + 1].state, cps[i + 1].position, i
                trace.revisits = True
            else:
                for i, at in enumerate(old.set_at):
                    if 0 <= at < k:
                        n = lines.line(i + 1) - 1
                        states[n], positions[n], set_at[n] = old.states[i], old.positions[i], at
            step = k
    elif trace is not None:
        STATS["full"] += 1

    def report(d: Diagnostic) -> None:
        diags.append(d if cur.unit.source is None else dataclasses.replace(d, source=cur.unit.source))

    while True:
        unit = cur.unit
        if cur.index >= len(unit.blocks):
            if not cur.calling():
                break
            tail = unit.tail  # (empty: its header)
            report(diag(flow["PAL-E409"], Span(tail, 1, tail, 1), number=unit.number))
            cur.leave(again=False)
            continue
        block = unit.blocks[cur.index]
        if trace is not None:
            cp = Checkpoint(
                unit.key,
                block.line,
                state,
                position,
                params_now,
                _frame_points(cur.frames) if cur.frames else (),
                follow.unknown,
            )
            if meet:
                was = lines.back(block.line, unit.source)
                candidates = meet.get(unit.key, was) if was is not None else None
                if candidates and old is not None:
                    done = _take_over(
                        old,
                        trace,
                        candidates,
                        cp,
                        lines,
                        step,
                        budget,
                        planned,
                        diags,
                        n_initial,
                        follow,
                        states,
                        positions,
                        set_at,
                        last_line,
                        last_set,
                        shifted,
                    )
                    if done is not None:
                        STATS["to_end"] -= 1
                        STATS["incremental"] += 1
                        kind = "incremental"
                        state, position, ended, last_line, last_set = done
                        params.clear()
                        params.update(old.params)
                        break
            if step < MAX_STEPS:
                trace.checkpoints.append(cp)
                trace.executed.append(budget.executed)
                trace.steps.append(budget.steps)
                trace.moves.append(budget.moves)
                trace.planned.append(len(planned))
                trace.diags.append(len(diags) - n_initial)
                trace.sets.append(0)
                trace.where.append(block.line if unit.source is None else 0)
            else:
                trace = None  # too long to keep: the next run is a full one
        here = cur.index
        cur.index += 1
        step += 1
        if not block.ok or block.is_empty or block.header is not None:
            if not block.ok:
                follow.dropped(block)
            continue
        if unit is main:
            last_line, last_set = block.line, step - 1
        if block.skip is not None and setup.skip_blocks:
            continue
        spent = budget.block(block)
        if spent is not None:
            report(spent)
            ended = True  # stopped: a missing M30 is no news
            if trace is not None:
                trace.spent = True
            break
        out = execute(setup, state, position, block, params, cache=cache)
        if trace is not None:
            if follow.unknown:
                trace.at_log.append((step - 1, (unit.source, block.line), follow.unknown))
            if block.assignments:
                params_now = dict(params)
        if follow.unknown or out.diagnostics:  # (else nothing is unknown before or after it)
            follow.ran(
                block,
                unit.source,
                out.diagnostics,
                getattr(out, "executed", True),
                out.position != position,
                out.state.active("dimensions") != "G91",
            )
        budget.reported(len(out.diagnostics))
        spent = budget.made(sum(type(c) is Planned for c in out.commands), block)
        if spent is not None:
            report(spent)
            ended = True
            if trace is not None:
                trace.spent = True
            break
        if cur.frames and cur.calling():
            stack = cur.call_stack()
            for c in out.commands:
                if isinstance(c, Planned):
                    c.move = dataclasses.replace(c.move, source=unit.source, call_stack=stack)
        planned.extend(out.commands)
        for d in out.diagnostics:
            report(d)
        state, position = out.state, out.position
        if unit.source is None:
            states[block.line - 1] = state
            positions[block.line - 1] = position
            if trace is not None:
                if set_at[block.line - 1] >= 0:
                    trace.revisits = True
                set_at[block.line - 1] = step - 1
                trace.sets[-1] = 1
        # -- program flow -----------------------------------------------------------------------
        if cache is None and (out.flow is not None or out.repeat is not None or out.sub_end):
            cache = {}
        if out.flow is not None and out.flow[0] == "call":
            number, count = out.flow[1], out.flow[2]
            callee = subs.get(number)
            if callee is None:
                report(diag(flow["PAL-E401"], block.span, number=number))
            elif cur.active(callee):
                report(diag(flow["PAL-E404"], block.span, number=number))
            elif cur.depth() >= setup.max_call_depth:
                report(diag(flow["PAL-E405"], block.span, limit=setup.max_call_depth))
            elif count >= 1:
                cur.enter(Frame(unit, cur.index, callee, 0, None, count - 1, block.line))
                continue
        elif out.flow is not None:  # a G29 jump that is taken
            if trace is not None:
                trace.labels = True
            target = unit.numbers.get(out.flow[1])
            if target is None:
                report(diag("PAL-E406", block.span, number=out.flow[1]))
            else:
                cur.index = target
                continue
        if out.repeat is not None:
            if trace is not None:
                trace.labels = True
            first, last, count = out.repeat
            start, end = unit.numbers.get(first), unit.numbers.get(last)
            if start is None or end is None:
                report(diag("PAL-E406", block.span, number=first if start is None else last))
            elif end < start:
                report(diag("PAL-E407", block.span, start=first, end=last))
            elif count >= 1:
                cur.enter(Frame(unit, cur.index, unit, start, end, count - 1, block.line, repeat=True))
                continue
        cur.after(here)
        if out.sub_end:
            calling = cur.calling()
            if (
                not calling and prefix == "O"
            ):  # M99 in the main program: the control starts it again, without end
                report(diag("ISO-W306", block.span))
                ended = True
                break
            if not calling:
                report(diag("PAL-E402", block.span))
            else:
                cur.leave()
            continue
        if getattr(
            out, "stopped", False
        ):  # an error that stops decoding: nothing after it runs, no M30 needed
            ended = True
            break
        if out.ended:
            if cur.calling():
                report(diag(flow["PAL-E403"], block.span, number=unit.number))
            ended = True
            rest = next(
                (b for b in cur.unit.blocks[cur.index :] if b.ok and not b.is_empty and b.header is None),
                None,
            )
            if unit is main and rest is not None:
                diags.append(diag("PAL-W101", rest.span))
            break
    if trace is not None and keep is not None:
        trace.items = planned
        trace.loop_diags = diags[n_initial:]
        trace.states, trace.positions, trace.set_at = list(states), list(positions), set_at
        trace.state, trace.position, trace.params = state, position, dict(params)
        trace.unknown, trace.final_line, trace.final_set = follow.unknown, last_line, last_set
        trace.ended, trace.counters = ended, budget.counters
    if keep is not None:
        keep.trace, keep.kind, keep.shifted = trace, kind, shifted
    truncated = any(
        d.code == "PAL-E006" for d in diags
    )  # lines beyond the limit were not read: M30 may be there
    if not ended and not truncated and program.has_content:  # a rejected program needs no second word
        line = last_line or 1
        diags.append(diag("PAL-W102", Span(line, 1, line, 1)))
    result.commands = finish(planned, diags)
    result.work = budget.counters
    finish_toolpath(result, states, positions, setup.start)
    if readings is not None and len(readings) > 2 * n_lines + 256:  # keep what this program's blocks can use
        alive = {id(b) for b in program.blocks}
        for key in [k for k in readings if k[0] not in alive]:
            del readings[key]
    dedupe(diags)
    follow.finish(diags)
    cap_diagnostics(diags, limits.max_diagnostics)
    result.final_position = position
    return result


main_key: UnitKey = (None, None)
# the program flow's diagnostics in the words of each kind of program: PAL's L<n> … M17, ISO's O<n> … M99
_FLOW_CODES = {
    "L": {c: c for c in ("PAL-E401", "PAL-E403", "PAL-E404", "PAL-E405", "PAL-E409")},
    "O": {
        "PAL-E401": "ISO-E301",
        "PAL-E403": "ISO-E304",
        "PAL-E404": "ISO-E303",
        "PAL-E405": "ISO-E302",
        "PAL-E409": "ISO-E305",
    },
}


class Meeting:
    """The steps `start` ≤ j < `stop` of the previous run, found by unit and line: where this run may meet it."""

    def __init__(self, old: Trace, start: int, stop: int) -> None:
        self.old, self.start, self.stop = old, start, stop
        self.library: dict[tuple[UnitKey, int], list[int]] | None = None

    def __bool__(self) -> bool:
        return self.start < self.stop

    def get(self, key: UnitKey, line: int) -> list[int]:
        old = self.old
        found: list[int] = []
        if key[0] is None:  # a unit of the program file: its lines are in `where`
            where, i = old.where, self.start
            while True:
                try:
                    i = where.index(line, i, self.stop)
                except ValueError:
                    return found
                found.append(i)
                i += 1
        if self.library is None:
            self.library = {}
            for j in range(self.start, self.stop):
                cp = old.checkpoints[j]
                if cp.unit[0] is not None:
                    self.library.setdefault((cp.unit, cp.line), []).append(j)
        return self.library.get((key, line), found)


def _resume(
    old: Trace,
    trace: Trace,
    blocks: list[Block],
    identity: tuple[Any, ...],
    units: dict[UnitKey, Unit],
) -> tuple[int, LineMap, Meeting, Checkpoint | None] | None:
    """Where this run starts from the previous run's checkpoints: (step, line map, the previous run's steps
    it may meet again, the checkpoint or None for the program start); None: a full run. Fills `trace` with
    the steps before the start."""
    if (
        not old.checkpoints
        or old.setup[1] is not identity[1]
        or old.setup[2] is not identity[2]
        or old.setup[0] != identity[0]
    ):
        return None
    first, old_end, new_end = changed_lines(old.blocks, blocks)
    if not structure_kept(old.blocks, blocks, first, old_end, new_end, old.labels):
        return None
    lines = LineMap(first, old_end, new_end - old_end)
    # the changed lines and the one before them, from which the run goes on into them
    lo = max(1, first - 1)
    cps = old.checkpoints
    last = len(cps) - 1
    k, last_touch = last, -1
    where = old.where  # per step: its line in the program file, 0 in a library program
    if lines.delta == 0:  # few lines to look for, each found by the array's own search
        backwards = where[::-1]
        for line in range(lo, old_end):
            if line in where:
                k = min(k, where.index(line))
                last_touch = max(last_touch, last - backwards.index(line))
    else:  # lines after an insertion or deletion move too: the restart is before the first step at any
        for i, line in enumerate(where):
            if line >= lo:
                k = min(k, i)
                if line < old_end:
                    last_touch = i
    if old.ended and cps[last].unit == main_key and cps[last].line < old_end:
        last_touch = last  # its M30 looked at the blocks after it for PAL-W101, the changed ones among them
    # the previous run's last step is never taken over: M30 looks at the blocks after it (PAL-W101)
    meet = Meeting(old, max(k, last_touch + 1), last)
    # the step before the first changed one runs again, so that it goes on to what now follows it
    r = k - 1
    if r < 0:
        return 0, lines, meet, None
    try:
        start = lines.checkpoint(cps[r])
        kept = cps[:r] if lines.delta == 0 else [lines.checkpoint(cp) for cp in cps[:r]]
        if lines.delta != 0:
            for d in old.loop_diags[: old.diags[r]]:
                lines.diagnostic(d)  # the run maps them once it starts
    except Unmappable:
        return None
    if start.unit not in units or any(f[0] not in units or f[2] not in units for f in start.frames):
        return None
    trace.checkpoints = kept
    trace.executed, trace.steps, trace.moves = old.executed[:r], old.steps[:r], old.moves[:r]
    trace.planned, trace.diags, trace.sets = old.planned[:r], old.diags[:r], old.sets[:r]
    trace.where = old.where[:r]
    trace.at_log = [
        (st, (src, lines.line(ln, src)), lines.unknown(unk)) for st, (src, ln), unk in old.at_log if st < r
    ]
    trace.labels = old.labels
    return r, lines, meet, start


def _last_main(old: Trace, k: int) -> tuple[int, int]:
    """The last line of the main program the previous run met before step `k` (for PAL-W102), and its step."""
    main = (None, None)
    for i in range(k - 1, -1, -1):
        cp = old.checkpoints[i]
        if cp.unit == main:
            b = old.blocks[cp.line - 1]
            if b.ok and not b.is_empty and b.header is None:
                return cp.line, i
    return 0, -1


def _take_over(
    old: Trace,
    trace: Trace,
    candidates: list[int],
    now: Checkpoint,
    lines: LineMap,
    step: int,
    budget: Budget,
    planned: list[Item],
    diags: list[Diagnostic],
    n_initial: int,
    follow: FollowUps,
    states: list[ModalState | None],
    positions: list[Vec3 | None],
    set_at: list[int],
    last_line: int,
    last_set: int,
    shifted: dict[int, Move],
) -> tuple[ModalState, Vec3, bool, int, int] | None:
    """If the run, about to take step `step` in state `now`, is where the previous run was at one of its
    steps `candidates`, append the rest of the previous run (its lines mapped) to this one's lists and trace
    and answer (state, position, ended, last line, the step that set it) at the end; else None."""
    for j in candidates:
        if not old.fits(budget.executed, budget.steps, budget.moves, j):
            continue
        try:
            then = lines.checkpoint(old.checkpoints[j])
            if then != now:
                continue
            shift = lines.delta != 0
            items = old.items[old.planned[j] :]
            found = old.loop_diags[old.diags[j] :]
            cps = old.checkpoints[j:]
            was = items
            if shift:
                items = [lines.item(x) for x in items]
                found = [lines.diagnostic(x) for x in found]
                cps = [lines.checkpoint(x) for x in cps]
            at_log = [
                (st - j + step, (src, lines.line(ln, src)), lines.unknown(unk))
                for st, (src, ln), unk in old.at_log
                if st >= j
            ]
            unknown = lines.unknown(old.unknown)
            final_line = lines.line(old.final_line) if old.final_set >= j else last_line
        except Unmappable:
            continue
        d_e, d_s, d_m = (
            budget.executed - old.executed[j],
            budget.steps - old.steps[j],
            budget.moves - old.moves[j],
        )
        d_p, d_d = len(planned) - old.planned[j], len(diags) - n_initial - old.diags[j]
        if shift:  # (only now: an id kept from a candidate given up could name another object later)
            for a, b in zip(was, items, strict=True):
                if isinstance(a, Planned) and isinstance(b, Planned) and b.move is not a.move:
                    shifted[id(b.move)] = a.move
        planned.extend(items)
        diags.extend(found)
        for _, where, unk in at_log:
            follow.at.setdefault(where, unk)
        trace.at_log.extend(at_log)
        follow.unknown = unknown
        # the lines the rest of the previous run set last (none of them changed lines)
        first, delta, old_states, old_positions = lines.first, lines.delta, old.states, old.positions
        for i, at in enumerate(old.set_at):
            if at >= j:
                n = i if i + 1 < first else i + delta
                if set_at[n] >= 0:
                    trace.revisits = True
                states[n], positions[n], set_at[n] = old_states[i], old_positions[i], at - j + step
        e, s, m = old.counters
        budget.executed, budget.steps, budget.moves = e + d_e, s + d_s, m + d_m
        if len(trace.checkpoints) + len(cps) <= MAX_STEPS:
            trace.checkpoints.extend(cps)
            for mine, theirs, d in (
                (trace.executed, old.executed, d_e),
                (trace.steps, old.steps, d_s),
                (trace.moves, old.moves, d_m),
                (trace.planned, old.planned, d_p),
                (trace.diags, old.diags, d_d),
            ):
                mine.extend(theirs[j:] if d == 0 else array("q", [x + d for x in theirs[j:]]))
            trace.sets.extend(old.sets[j:])
            if delta == 0:
                trace.where.extend(old.where[j:])
            else:
                trace.where.extend(array("q", [x + delta if x >= first else x for x in old.where[j:]]))
        else:
            trace.checkpoints.clear()  # too long to keep: the next run is a full one
        trace.spent = old.spent
        trace.labels = trace.labels or old.labels  # the steps taken over may have resolved block numbers
        trace.revisits = trace.revisits or old.revisits
        final_set = old.final_set - j + step if old.final_set >= j else last_set
        assert old.state is not None
        return old.state, old.position, old.ended, final_line, final_set
    return None
