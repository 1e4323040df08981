"""The interpreter: Program → Toolpath. Runs the blocks in order and keeps the state of every line.

The loop owns what concerns the program as a whole: skip blocks, the end at M30, the limit of
executed blocks, the missing M30, the cap on diagnostics. What a single block means is the
dialect's block executor (core/interpreter/pal_mill.py).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Protocol

from core.diagnostics import Diagnostic, diag
from core.dialects.codes import CodeTable
from core.interpreter.contour import Planned, finish
from core.interpreter.state import ModalState, RunSetup, switch_on_state
from core.syntax.blocks import Block, Program, Span
from core.toolpath import Dwell, Move, ToolChange, Vec3


class BlockExecutor(Protocol):
    def __call__(self, setup: RunSetup, state: ModalState, position: Vec3, block: Block,
                 params: dict[int, float]) -> BlockOutcome: ...


class BlockOutcome(Protocol):
    @property
    def state(self) -> ModalState: ...
    @property
    def position(self) -> Vec3: ...
    @property
    def commands(self) -> list[Planned | Dwell | ToolChange]: ...
    @property
    def diagnostics(self) -> list[Diagnostic]: ...
    @property
    def ended(self) -> bool: ...


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

    def state_at(self, line: int) -> tuple[ModalState, Vec3]:
        """What is active, and where the tool is, after line `line` (1-based) has run."""
        if line < 1 or not self.line_states:
            assert self.initial is not None
            return self.initial, self.line_positions[0] if self.line_positions else (0.0, 0.0, 0.0)
        i = min(line, len(self.line_states)) - 1
        return self.line_states[i], self.line_positions[i]


def interpret(program: Program, table: CodeTable, execute: BlockExecutor, setup: RunSetup,
              diagnostics: list[Diagnostic] | None = None) -> Toolpath:
    """Execute every block of `program`; never raises on user input."""
    limits = setup.limits
    result = Toolpath(diagnostics=list(diagnostics or []))
    diags = result.diagnostics
    state = result.initial = switch_on_state(table)
    position = setup.start
    params = result.params
    ended_at: int | None = None
    warned_after_end = False
    executed = 0
    last_line = 0
    states, positions = result.line_states, result.line_positions
    planned: list[Planned | Dwell | ToolChange] = []
    for block in program.blocks:
        if block.ok and not block.is_empty and block.header is None:
            last_line = block.line
            if ended_at is not None:
                if not warned_after_end:
                    diags.append(diag("PAL-W101", block.span))
                    warned_after_end = True
            elif block.skip is None or not setup.skip_blocks:
                executed += 1
                if executed > limits.max_executed_blocks:
                    diags.append(diag("PAL-E013", block.span, limit=limits.max_executed_blocks))
                    ended_at = block.line  # stopped: a missing M30 is no news
                    break
                out = execute(setup, state, position, block, params)
                planned.extend(out.commands)
                if out.diagnostics:
                    diags.extend(out.diagnostics)
                state, position = out.state, out.position
                if out.ended:
                    ended_at = block.line
        states.append(state)
        positions.append(position)
    if ended_at is None and (program.blocks or not diags):  # a rejected program needs no second word
        line = last_line or 1
        diags.append(diag("PAL-W102", Span(line, 1, line, 1)))
    result.commands = finish(planned, diags)
    for c in result.commands:
        if type(c) is Move:
            result.moves.append(c)
        elif type(c) is Dwell:
            result.dwells.append(c)
        else:
            result.tool_changes.append(c)  # type: ignore[arg-type]
    if len(diags) > limits.max_diagnostics:
        cut = diags[limits.max_diagnostics - 1]
        del diags[limits.max_diagnostics - 1:]
        diags.append(diag("PAL-E012", cut.span, limit=limits.max_diagnostics))
    result.final_position = position
    return result
