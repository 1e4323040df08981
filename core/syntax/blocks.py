"""The syntax tree of a CNC program: spans, words, parameter expressions, blocks.

These types are what the parser produces and the interpreter consumes. They carry no meaning
(no modal logic); a dialect's tables give the words their meaning. Lines and columns are
1-based; an end column points just past the last character (end exclusive).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import NamedTuple


class Span(NamedTuple):
    """A source range: 1-based line and column; the end column is exclusive."""

    line: int
    column: int
    end_line: int
    end_column: int


class Num(NamedTuple):
    """A number literal inside a parameter expression."""

    value: float
    column: int
    end_column: int


class ParamRef(NamedTuple):
    """A reference to parameter P<number> inside an expression."""

    number: int
    column: int
    end_column: int


class Neg(NamedTuple):
    """Unary minus."""

    operand: Expr
    column: int
    end_column: int


class BinOp(NamedTuple):
    """A binary operation + - * / of two expressions."""

    op: str
    left: Expr
    right: Expr
    column: int
    end_column: int


Expr = Num | ParamRef | Neg | BinOp


class Word(NamedTuple):
    """One address word such as `X56.4`, `G01`, `RN-15`, a value-less flag (`G66 X`) or `X=P1`.

    `value` is the number, `None` for a value-less flag; `expr` holds the expression when the
    word was written `ADDRESS=expression`. `raw` is the value as written (keeps leading zeros).
    """

    address: str
    value: float | None
    raw: str
    line: int
    column: int
    end_column: int
    expr: Expr | None = None

    @property
    def span(self) -> Span:
        return Span(self.line, self.column, self.line, self.end_column)

    @property
    def address_span(self) -> Span:
        return Span(self.line, self.column, self.line, self.column + len(self.address))

    def __str__(self) -> str:
        return f"{self.address}{self.raw}"


class Assignment(NamedTuple):
    """A parameter assignment such as `P12=P12+1`."""

    param: int
    expr: Expr
    line: int
    column: int
    end_column: int

    @property
    def span(self) -> Span:
        return Span(self.line, self.column, self.line, self.end_column)


@dataclass(slots=True)
class Block:
    """One line of the program, parsed. Not mutated after parsing.

    `number` is the leading N word's value (the block number), if any; `words` are the other
    words in written order; `skip` is the skip level of a leading `/` (0 for a plain `/`).
    `header` holds the text of a `%` program header line. `ok` is False when the line had a
    syntax error: such a block carries no words and is not executed.
    """

    line: int
    text: str
    number: int | None
    words: tuple[Word, ...]
    assignments: tuple[Assignment, ...] = ()
    skip: int | None = None
    comment: str | None = None
    header: str | None = None
    ok: bool = True

    @property
    def span(self) -> Span:
        # (tuple.__new__ skips NamedTuple's argument handling: the interpreter asks for this once per block)
        return tuple.__new__(Span, (self.line, 1, self.line, len(self.text) + 1))

    @property
    def is_empty(self) -> bool:
        """True for blank and comment-only lines, which the interpreter skips."""
        return not self.words and not self.assignments and self.header is None


@dataclass(slots=True)
class Program:
    """A parsed program: every line of the source as a block, in order."""

    blocks: list[Block]
    line_count: int
    # a parse with a memo (the live editor): the blocks of the last parse and the lines that differ from them,
    # (first, old end, new end) as checkpoints.changed_lines finds them, so that the run need not compare
    base: list[Block] | None = field(default=None, compare=False, repr=False)
    changed: tuple[int, int, int] | None = field(default=None, compare=False, repr=False)

    @property
    def has_content(self) -> bool:
        """Whether any line is more than blank or a comment (a bad line counts): an empty program is not missing
        its end (PAL-W102), it has not been written yet."""
        return any(not (b.ok and b.is_empty) for b in self.blocks)
