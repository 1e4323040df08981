"""The interpreter: Program → Toolpath. Runs the blocks in order and keeps the state of every line.

The loop owns what concerns the program as a whole: skip blocks, the end at M30, the budgets of work
(executed blocks, evaluation steps, programmed moves: core/limits.py), the missing M30, the cap on
diagnostics. What a single block means is the dialect's block executor (core/interpreter/pal_mill.py).
"""

from __future__ import annotations

import copy
import dataclasses
import re
from dataclasses import dataclass, field
from typing import Any, Protocol

from core.diagnostics import Diagnostic, diag
from core.dialects.codes import CodeTable
from core.interpreter.contour import Item, Planned, finish
from core.interpreter.followups import FollowUps
from core.interpreter.state import ModalState, RunSetup, switch_on_state
from core.limits import DEFAULT_LIMITS, DIAGNOSTIC_STEPS, Limits
from core.syntax.blocks import BinOp, Block, Expr, Neg, Program, Span
from core.toolpath import Dwell, Move, ToolChange, Vec3


class BlockExecutor(Protocol):
    def __call__(self, setup: RunSetup, state: ModalState, position: Vec3, block: Block,
                 params: dict[int, float], *, cache: dict[Any, Any] | None = None) -> BlockOutcome: ...


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


@dataclass(slots=True)
class Toolpath:
    """The interpreter's result: canonical commands, diagnostics and the state after every line."""

    commands: list[Move | Dwell | ToolChange] = field(default_factory=list)  # in execution order
    moves: list[Move] = field(default_factory=list)
    dwells: list[Dwell] = field(default_factory=list)
    tool_changes: list[ToolChange] = field(default_factory=list)
    diagnostics: list[Diagnostic] = field(default_factory=list)
    final_position: Vec3 = (0.0, 0.0, 0.0)
    initial: ModalState | None = None
    # index = line - 1: the state and position after that line (lines not executed repeat the previous)
    line_states: list[ModalState] = field(default_factory=list)
    line_positions: list[Vec3] = field(default_factory=list)
    params: dict[int, float] = field(default_factory=dict)
    limits: Limits = DEFAULT_LIMITS  # the limits of the run (an answer shows at most max_answer_commands)

    def state_at(self, line: int) -> tuple[ModalState, Vec3]:
        """What is active, and where the tool is, after line `line` (1-based) has run."""
        if line < 1 or not self.line_states:
            assert self.initial is not None
            return self.initial, self.line_positions[0] if self.line_positions else (0.0, 0.0, 0.0)
        i = min(line, len(self.line_states)) - 1
        return self.line_states[i], self.line_positions[i]

    def until_move(self, moves: int) -> Toolpath:
        """The run as far as its first `moves` moves (for the stock after a block during playback)."""
        commands: list[Move | Dwell | ToolChange] = []
        count = 0
        for c in self.commands:
            if isinstance(c, Move):
                if count >= moves:
                    break
                count += 1
            commands.append(c)
        partial = copy.copy(self)
        partial.commands = commands
        return partial


@dataclass(slots=True)
class Unit:
    """One program of a run: the main program or a subprogram L<number>."""

    number: int | None  # None: the main program
    source: str | None  # None: the program file; "L200": a file of the program library
    blocks: list[Block]
    numbers: dict[int, int] = field(default_factory=dict)  # block number N → index of its first block

    def __post_init__(self) -> None:
        for i, b in enumerate(self.blocks):
            if b.number is not None:
                self.numbers.setdefault(b.number, i)

    @property
    def name(self) -> str:
        return "Hauptprogramm" if self.number is None else f"L{self.number}"


_SUB_HEADER = re.compile(r"L\s*(\d+)")


def split_units(program: Program) -> tuple[Unit, dict[int, Unit]]:
    """The main program and the subprograms that follow it in the same file, each after a `%L<n>` header."""
    main: list[Block] = []
    subs: dict[int, Unit] = {}
    current = main
    for b in program.blocks:
        m = _SUB_HEADER.fullmatch(b.header or "")
        if m is not None:
            current = []
            subs.setdefault(int(m.group(1)), Unit(int(m.group(1)), None, current))
            continue
        current.append(b)
    for u in subs.values():
        u.__post_init__()
    return Unit(None, None, main), subs


@dataclass(slots=True)
class _Call:
    unit: Unit  # the caller
    return_index: int
    callee: Unit
    remaining: int  # runs of the callee still to come after this one
    line: int  # the calling block
    source: str | None


@dataclass(slots=True)
class _Repeat:
    unit: Unit
    start: int
    end: int
    remaining: int
    return_index: int


def interpret(program: Program, table: CodeTable, execute: BlockExecutor, setup: RunSetup,
              diagnostics: list[Diagnostic] | None = None, library: dict[int, Program] | None = None,
              readings: dict[Any, Any] | None = None) -> Toolpath:
    """Execute the program from its first block, following calls, repeats and jumps; never raises on user input.

    `readings` is the executor's reading of blocks kept from an earlier run of the same blocks (see
    core.pipeline.Memo); it is pruned to this program's blocks.
    """
    limits = setup.limits
    result = Toolpath(diagnostics=list(diagnostics or []), limits=limits)
    diags = result.diagnostics
    state = result.initial = switch_on_state(table)
    position = setup.start
    params = result.params
    main, subs = split_units(program)
    for number, prog in (library or {}).items():
        subs.setdefault(number, Unit(number, f"L{number}", prog.blocks))
    n_lines = len(program.blocks)
    states: list[ModalState | None] = [None] * n_lines
    positions: list[Vec3 | None] = [None] * n_lines
    planned: list[Item] = []
    calls: list[_Call] = []
    # the executor keeps its reading of blocks once the program first goes back (a call, a repeat, a
    # jump): until then every block runs once and keeping them would only cost
    cache: dict[Any, Any] | None = readings
    repeats: list[_Repeat] = []
    unit, index = main, 0
    ended = False
    executed = 0
    steps = 0  # evaluation steps (see core.limits.Limits.max_evaluation_steps)
    costs: dict[int, int] = {}  # id(block) → the evaluation steps of its words
    moves = 0  # programmed moves
    last_line = 0
    follow = FollowUps()  # what blocks dropped by an error leave unknown (follow-up errors)

    def report(d: Diagnostic) -> None:
        diags.append(d if unit.source is None else dataclasses.replace(d, source=unit.source))

    def section_end(u: Unit, done: int, following: int) -> int:
        """Where to go on once block `done` of `u` has run (a call or a repeat it made included): back to the
        start of the G23 section it ends while that repeats, else `following`."""
        while repeats and repeats[-1].unit is u and repeats[-1].end == done:
            top = repeats[-1]
            top.remaining -= 1
            if top.remaining > 0:
                return top.start
            repeats.pop()  # the G23 block itself may end an outer section
            done, following = top.return_index - 1, top.return_index
        return following

    while True:
        if index >= len(unit.blocks):
            if not calls:
                break
            report(diag("PAL-E409", Span(unit.blocks[-1].line if unit.blocks else 1, 1, 1, 1),
                        number=unit.number))
            frame = calls.pop()
            unit, index = frame.unit, section_end(frame.unit, frame.return_index - 1, frame.return_index)
            continue
        block = unit.blocks[index]
        here = index
        index += 1
        if not block.ok or block.is_empty or block.header is not None:
            if not block.ok:
                follow.dropped(block)
            continue
        if unit is main:
            last_line = block.line
        if block.skip is not None and setup.skip_blocks:
            continue
        executed += 1
        if executed > limits.max_executed_blocks:
            report(diag("PAL-E013", block.span, limit=limits.max_executed_blocks))
            ended = True  # stopped: a missing M30 is no news
            break
        cost = costs.get(id(block))
        if cost is None:
            cost = costs[id(block)] = _steps(block)
        steps += cost
        if steps > limits.max_evaluation_steps:
            report(diag("PAL-E016", block.span, limit=limits.max_evaluation_steps))
            ended = True
            break
        out = execute(setup, state, position, block, params, cache=cache)
        follow.ran(block, unit.source, out.diagnostics, getattr(out, "executed", True), out.position != position,
                   out.state.active("dimensions") != "G91")
        steps += DIAGNOSTIC_STEPS * len(out.diagnostics)
        made = sum(type(c) is Planned for c in out.commands)
        if made and moves + made > limits.max_moves:
            report(diag("PAL-E017", block.span, limit=limits.max_moves))
            ended = True
            break
        moves += made
        if calls:
            stack = tuple((c.source, c.line) for c in calls)
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
        # -- program flow -----------------------------------------------------------------------
        if cache is None and (out.flow is not None or out.repeat is not None or out.sub_end):
            cache = {}
        if out.flow is not None and out.flow[0] == "call":
            number, count = out.flow[1], out.flow[2]
            callee = subs.get(number)
            if callee is None:
                report(diag("PAL-E401", block.span, number=number))
            elif callee is unit or any(c.callee is callee for c in calls):
                report(diag("PAL-E404", block.span, number=number))
            elif len(calls) >= setup.max_call_depth:
                report(diag("PAL-E405", block.span, limit=setup.max_call_depth))
            elif count >= 1:
                calls.append(_Call(unit, index, callee, count - 1, block.line, unit.source))
                unit, index = callee, 0
                continue
        elif out.flow is not None:  # a G29 jump that is taken
            target = unit.numbers.get(out.flow[1])
            if target is None:
                report(diag("PAL-E406", block.span, number=out.flow[1]))
            else:
                index = target
                continue
        if out.repeat is not None:
            first, last, count = out.repeat
            start, end = unit.numbers.get(first), unit.numbers.get(last)
            if start is None or end is None:
                report(diag("PAL-E406", block.span, number=first if start is None else last))
            elif end < start:
                report(diag("PAL-E407", block.span, start=first, end=last))
            elif count >= 1:
                repeats.append(_Repeat(unit, start, end, count, index))
                index = start
                continue
        index = section_end(unit, here, index)
        if out.sub_end:
            if not calls:
                report(diag("PAL-E402", block.span))
            else:
                frame = calls[-1]
                if frame.remaining > 0:
                    frame.remaining -= 1
                    index = 0
                else:
                    calls.pop()
                    unit, index = frame.unit, section_end(frame.unit, frame.return_index - 1, frame.return_index)
            continue
        if out.ended:
            if calls:
                report(diag("PAL-E403", block.span, number=unit.number))
            ended = True
            rest = next((b for b in unit.blocks[index:] if b.ok and not b.is_empty and b.header is None), None)
            if unit is main and rest is not None:
                diags.append(diag("PAL-W101", rest.span))
            break
    truncated = any(d.code == "PAL-E006" for d in diags)  # lines beyond the limit were not read: M30 may be there
    if not ended and not truncated and (program.blocks or not diags):  # a rejected program needs no second word
        line = last_line or 1
        diags.append(diag("PAL-W102", Span(line, 1, line, 1)))
    result.commands = finish(planned, diags)
    for command in result.commands:
        if type(command) is Move:
            result.moves.append(command)
        elif type(command) is Dwell:
            result.dwells.append(command)
        elif type(command) is ToolChange:
            result.tool_changes.append(command)
    # lines not executed hold the state of the line before them
    current_state, current_position = result.initial, setup.start
    for i in range(n_lines):
        if states[i] is None:
            states[i], positions[i] = current_state, current_position
        else:
            current_state, current_position = states[i], positions[i]  # type: ignore[assignment]
    result.line_states = states  # type: ignore[assignment]
    result.line_positions = positions  # type: ignore[assignment]
    if readings is not None:  # keep only what this program's blocks can use again
        alive = {id(b) for b in program.blocks}
        for key in [k for k in readings if k[0] not in alive]:
            del readings[key]
    _dedupe(diags)
    follow.finish(diags)
    if len(diags) > limits.max_diagnostics:
        cut = diags[limits.max_diagnostics - 1]
        del diags[limits.max_diagnostics - 1:]
        diags.append(diag("PAL-E012", cut.span, limit=limits.max_diagnostics))
    result.final_position = position
    return result


def _steps(block: Block) -> int:
    """The evaluation steps of one execution of `block`: one per word, one per term of each expression."""
    return len(block.words) + sum(_terms(w.expr) for w in block.words if w.expr is not None) + sum(
        1 + _terms(a.expr) for a in block.assignments)


def _terms(expr: Expr) -> int:
    """Numbers, parameters and operators in `expr` (depth-limited by the parser, PAL-E014)."""
    if isinstance(expr, BinOp):
        return 1 + _terms(expr.left) + _terms(expr.right)
    if isinstance(expr, Neg):
        return 1 + _terms(expr.operand)
    return 1


def _dedupe(diags: list[Diagnostic]) -> None:
    """A block run many times (loops, subprograms) reports each finding once."""
    seen: set[tuple[str, Span, str | None]] = set()
    keep = []
    for d in diags:
        key = (d.code, d.span, d.source)
        if key not in seen:
            seen.add(key)
            keep.append(d)
    diags[:] = keep
