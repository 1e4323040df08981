"""Parameters P1…P999: evaluating expressions such as `P12+1` or `(P1+2)*-3/P4`.

Real arithmetic with + − * / and parentheses; an unassigned parameter reads as 0 with a
warning; division by zero is an error (DECISIONS.md §6).
"""

from __future__ import annotations

from collections.abc import Callable

from core.diagnostics import Diagnostic, diag
from core.syntax.blocks import Expr, Neg, Num, ParamRef, Span

Resolve = Callable[[ParamRef, Span], "float | None"]  # a dialect's own reading of a parameter reference


def evaluate(
    expr: Expr, params: dict[int, float], line: int, d: list[Diagnostic], resolve: Resolve | None = None
) -> float | None:
    """The value of `expr`, or None after an error diagnostic. Parameter references are PAL's P1…P999 unless
    `resolve` reads them (the TRAUB dialect's L parameters)."""
    if isinstance(expr, Num):
        return expr.value
    if isinstance(expr, ParamRef):
        if resolve is not None:
            return resolve(expr, Span(line, expr.column, line, expr.end_column))
        if not 1 <= expr.number <= 999:
            d.append(diag("PAL-E113", Span(line, expr.column, line, expr.end_column), number=expr.number))
            return None
        if expr.number not in params:
            d.append(diag("PAL-W106", Span(line, expr.column, line, expr.end_column), number=expr.number))
            return 0.0
        return params[expr.number]
    if isinstance(expr, Neg):
        v = evaluate(expr.operand, params, line, d, resolve)
        return None if v is None else -v
    left = evaluate(expr.left, params, line, d, resolve)
    right = evaluate(expr.right, params, line, d, resolve)
    if left is None or right is None:
        return None
    if expr.op == "+":
        return left + right
    if expr.op == "-":
        return left - right
    if expr.op == "*":
        return left * right
    if right == 0:
        d.append(diag("PAL-E114", Span(line, expr.column, line, expr.end_column)))
        return None
    return left / right
