"""The checks of a block's words that every dialect makes the same way, from its code table: the members of
one modal group (PAL-E103), the addresses a code requires (PAL-E102), values that must not be negative
(PAL-E109, the addresses' `non_negative` column)."""

from __future__ import annotations

from collections.abc import Callable, Container

from core.diagnostics import Diagnostic, diag
from core.dialects.codes import Code, CodeTable
from core.syntax.blocks import Word


def group_conflicts(table: CodeTable, codes: list[tuple[Word, Code]], d: list[Diagnostic]) -> None:
    """Two codes of the block that switch on members of one modal group (M13 is M3 and M8)."""
    if len(codes) < 2:  # one code cannot conflict with itself
        return
    seen: dict[str, Word] = {}
    for w, code in codes:
        for member in table.activates(code):
            g = table.group_of[member]
            if g in seen:
                label = table.group(g)
                d.append(
                    diag(
                        "PAL-E103",
                        w.span,
                        first=str(seen[g]),
                        second=str(w),
                        group=label.label_de,
                        group_en=label.label_en,
                    )
                )
            seen[g] = w


def missing_words(codes: list[tuple[Word, Code]], words: Container[str], d: list[Diagnostic]) -> None:
    """A code without one of the addresses it requires (each group of `Code.required` needs one)."""
    for w, code in codes:
        for one_of in code.required:
            if not any(a in words for a in one_of):
                d.append(diag("PAL-E102", w.span, address="/".join(one_of), command=str(w)))


def negative_values(
    table: CodeTable, values: dict[str, float], word: Callable[[str], Word], d: list[Diagnostic]
) -> None:
    """A value below zero where the address does not take one; `word(a)` is the block's word of address a."""
    for a in table.non_negative:
        if a in values and values[a] < 0:
            w = word(a)
            d.append(diag("PAL-E109", w.span, address=a, raw=w.raw))
