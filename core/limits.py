"""The explicit limits of one run; hitting one is a diagnostic, never a hang or a crash.

The work of a run is bounded three ways, so that any program, however small, finishes in well under a
second (bench/limits.py, bench/fuzz.py): executed blocks (PAL-E013), evaluation steps (PAL-E016) and
programmed moves (PAL-E017). What leaves the run is bounded as well: an answer shows the first
`max_answer_commands` commands (PAL-I018) and a drawing of the toolpath at most `max_drawn_segments`
segments (PAL-I019), counted before a point is made.
"""

from __future__ import annotations

import operator
from dataclasses import dataclass, field

from core.diagnostics import Diagnostic, diag
from core.syntax.blocks import BinOp, Block, Expr, Neg


@dataclass(frozen=True, slots=True)
class Limits:
    max_program_chars: int = 5_000_000  # whole program text
    max_line_length: int = 1_000  # characters in one block
    max_blocks: int = 20_000  # lines in one program (as many as the live editor takes); then PAL-E006
    # blocks executed in one run (loops count every pass): as many as a program may have lines, so that any program
    # the editor takes runs straight through; an endless loop stops here (50,000 before: up to 1.6 s of a loop
    # of cheap blocks, bench/fuzz.py)
    max_executed_blocks: int = 20_000
    # evaluation steps of one run: each word of an executed block, each number, parameter and operator of
    # its expressions, and DIAGNOSTIC_STEPS for each diagnostic it reports (loops count every pass)
    max_evaluation_steps: int = 300_000
    max_moves: int = 5_000  # programmed moves in one run (each motion block once per pass)
    max_cycle_passes: int = 500  # passes (levels, pecks, thread passes) of one cycle block or call (TRAUB: TX-E406, ISO: ISO-E404, PAL: PAL-E610)
    max_abs_value: float = 100_000.0  # any address value or parameter, in its unit
    max_diagnostics: int = 1_000  # further diagnostics are dropped with one PAL-E012
    max_answer_commands: int = 5_000  # moves, dwells and tool changes in one answer (JSON); then PAL-I018
    max_drawn_segments: int = 20_000  # line segments of one toolpath drawing (arcs as chords); then PAL-I019


DIAGNOSTIC_STEPS = 20  # making a diagnostic costs about as much as evaluating twenty terms

DEFAULT_LIMITS = Limits()

_expression = operator.attrgetter("expr")  # a word's expression (None: a number or a flag)


def work_ceiling(limits: Limits) -> tuple[int, int, int]:
    """The most work (blocks executed, evaluation steps, moves; Budget.counters) a run does under `limits`: the
    block that trips a budget is counted, with its words and its diagnostics, before it stops the run. Tests bound
    a program's cost by this, never by seconds (bench/ measures those)."""
    return (
        limits.max_executed_blocks + 1,
        limits.max_evaluation_steps + limits.max_line_length + DIAGNOSTIC_STEPS * limits.max_diagnostics,
        limits.max_moves,
    )


@dataclass(slots=True)
class Budget:
    """The work one run has done so far against its limits; the run loop (core/interpreter/loop.py) counts
    through it, in this order per block: `block` before the block runs, `reported` for its diagnostics,
    `made` for its moves. A returned diagnostic stops the run."""

    limits: Limits
    executed: int = 0  # blocks executed (loops count every pass)
    steps: int = 0  # evaluation steps
    moves: int = 0  # programmed moves
    costs: dict[int, int] = field(default_factory=dict)  # id(block) → the steps of a block with expressions

    def block(self, block: Block) -> Diagnostic | None:
        """Count one execution of `block`: PAL-E013 or PAL-E016 when that spends a budget."""
        self.executed += 1
        if self.executed > self.limits.max_executed_blocks:
            return diag("PAL-E013", block.span, limit=self.limits.max_executed_blocks)
        if block.assignments or any(map(_expression, block.words)):
            cost = self.costs.get(id(block))
            if cost is None:
                cost = self.costs[id(block)] = block_steps(block)
        else:  # one step per word (most blocks: counted without a loop)
            cost = len(block.words)
        self.steps += cost
        if self.steps > self.limits.max_evaluation_steps:
            return diag("PAL-E016", block.span, limit=self.limits.max_evaluation_steps)
        return None

    def reported(self, count: int) -> None:
        """A block reported `count` diagnostics."""
        self.steps += DIAGNOSTIC_STEPS * count

    def made(self, moves: int, block: Block) -> Diagnostic | None:
        """`block` programmed `moves` moves: PAL-E017 (and none counted) when they do not fit."""
        if moves and self.moves + moves > self.limits.max_moves:
            return diag("PAL-E017", block.span, limit=self.limits.max_moves)
        self.moves += moves
        return None

    @property
    def counters(self) -> tuple[int, int, int]:
        return self.executed, self.steps, self.moves


def block_steps(block: Block) -> int:
    """The evaluation steps of one execution of `block`: one per word, one per term of each expression."""
    steps = len(block.words)
    for w in block.words:  # (a loop, not sum() over a generator: this runs for every block)
        if w.expr is not None:
            steps += _terms(w.expr)
    for a in block.assignments:
        steps += 1 + _terms(a.expr)
    return steps


def _terms(expr: Expr) -> int:
    """Numbers, parameters and operators in `expr` (depth-limited by the parser, PAL-E014)."""
    if isinstance(expr, BinOp):
        return 1 + _terms(expr.left) + _terms(expr.right)
    if isinstance(expr, Neg):
        return 1 + _terms(expr.operand)
    return 1
