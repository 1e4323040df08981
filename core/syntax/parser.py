"""Text → Program: splits a program into lines and parses each line as one block.

The grammar of a dialect lives in a `.lark` file beside this module (LALR, contextual lexer).
Each line is parsed on its own, so a bad block yields its diagnostic and the others still
parse. Lines made only of plain words (`N10 G1 X5 Y-3 F150 ; comment`), by far the most common
kind, take a fast path: one regular expression assembled from the grammar's own terminals.
Lines whose assignments and parameter words have one number or parameter as their value
(`L1 = 11`, `X L2`, `Z-L4`, `P3=-P1`) take a second one, assembled the same way. Every other line
(expressions, flags, errors) goes through lark, whose parser costs ten times as much. All paths
build the same blocks; tests/test_parser.py checks that they agree.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from functools import cache
from itertools import chain
from pathlib import Path

from lark import Lark, Token, Tree
from lark.exceptions import UnexpectedCharacters, UnexpectedEOF, UnexpectedInput, UnexpectedToken

from core.diagnostics import Diagnostic, diag
from core.limits import Limits
from core.sequences import common_ends
from core.syntax.blocks import Assignment, BinOp, Block, Expr, Neg, Num, ParamRef, Program, Span, Word

_CONTROL = re.compile(r"[\x00-\x08\x0b-\x1f\x7f\ufffd]")
_LOOSE_WORD = re.compile(r"([A-Z]+)[ \t]*([-+0-9.,]+)")

# How the parser names a terminal in "expected ..." messages: (German, English).
_TERMINAL_NAMES: dict[str, tuple[str, str]] = {
    "ADDRESS": ("eine Adresse", "an address"),
    "NUMBER": ("eine Zahl", "a number"),
    "UNUM": ("eine Zahl", "a number"),
    "PREF": ("ein Parameter", "a parameter"),
    "LPAR": ("»(«", "'('"),
    "RPAR": ("»)«", "')'"),
    "NEG": ("»-«", "'-'"),
    "ADDOP": ("»+« oder »-«", "'+' or '-'"),
    "MULOP": ("»*« oder »/«", "'*' or '/'"),
    "EQUAL": ("»=«", "'='"),
    "COMMENT": ("ein Kommentar", "a comment"),
    "$END": ("das Satzende", "the end of the block"),
}


@dataclass(slots=True)
class LineMemo:
    """A document's lines as its last parse read them, with each line's block and diagnostics (the live
    editor's next parse of the same document reuses the lines that did not change)."""

    lines: list[str] = field(default_factory=list)
    blocks: list[Block] = field(default_factory=list)
    found: list[list[Diagnostic]] = field(default_factory=list)  # per line its diagnostics


class BlockParser:
    """Parses the lines of one dialect's grammar into blocks."""

    def __init__(
        self, grammar_file: Path, valued_codes: frozenset[str] = frozenset(), program_numbers: bool = False
    ) -> None:
        self._valued = valued_codes  # codes written with a value, as Beckhoff's G301=20
        self._programs = program_numbers  # a leading O word is a program number (ISO: `O1000`)
        self._lark = Lark(
            grammar_file.read_text(encoding="utf-8"),
            start="line",
            parser="lalr",
            lexer="contextual",
            maybe_placeholders=False,
        )
        term = {t.name: t.pattern.to_regexp() for t in self._lark.terminals}
        ws = "[ \t]*"
        address, number = _without_groups(term["ADDRESS"]), _without_groups(term["NUMBER"])
        self._fast_word = re.compile(f"({address}){ws}({number})")
        # the commonest lines are read word by word (`_plain_block`): an optional skip mark, words with blanks
        # between them and at most a comment at the end
        self._plain_head = re.compile(f"{ws}(?P<skip>{term['SKIP']})?{ws}")
        self._plain_word = re.compile(f"({address}){ws}({number}){ws}")
        self._plain_tail = re.compile(f"(?:{term['COMMENT']})?")
        # a dialect whose numbers take a decimal comma or blanks (TRAUB: `F0,2`, `T02 02`) reads them loosely
        self._loose = "," in term["NUMBER"]
        self._param = term["PREF"][0] if "PREF" in term else "P"  # the letter of parameters: P1 or L1
        self._simple_line, self._simple_item = _simple_patterns(self._lark, term, address, number)

    # -- whole programs --------------------------------------------------------------------

    def parse_program(
        self,
        text: str,
        limits: Limits,
        memo: LineMemo | None = None,
    ) -> tuple[Program, list[Diagnostic]]:
        """Parse every line of `text`; never raises on user input.

        `memo` (the lines of the last parse of the same document and their blocks) lets a program that changed
        in a few lines reuse the others (the live editor); it is updated to hold this program's lines.
        """
        diagnostics: list[Diagnostic] = []
        if len(text) > limits.max_program_chars:
            diagnostics.append(
                diag("PAL-E005", Span(1, 1, 1, 1), size=len(text), limit=limits.max_program_chars)
            )
            return Program([], 0), diagnostics
        lines = text.split("\n")
        if lines and lines[-1] == "":
            lines.pop()  # a final newline ends the last line, it does not start a new one
        line_count = len(lines)
        if line_count > limits.max_blocks:
            diagnostics.append(
                diag(
                    "PAL-E006",
                    Span(limits.max_blocks + 1, 1, limits.max_blocks + 1, 1),
                    count=line_count,
                    limit=limits.max_blocks,
                    line=limits.max_blocks + 1,
                )
            )
            lines = lines[: limits.max_blocks]
        if memo is None:
            return Program(self._parse_lines(lines, limits, diagnostics), line_count), diagnostics
        old_blocks = memo.blocks
        blocks, found, changed = self._reparse(memo, lines, limits)
        diagnostics.extend(chain.from_iterable(filter(None, found)))
        memo.lines, memo.blocks, memo.found = lines, blocks, found
        return Program(blocks, line_count, old_blocks, changed), diagnostics

    def _parse_lines(self, lines: list[str], limits: Limits, diagnostics: list[Diagnostic]) -> list[Block]:
        """Each line's block. A program repeats its lines, most often under another block number (a contour's
        passes at the next depth, the holes of a pattern): a line of plain words whose text after the number
        was read before takes that block's words, moved to its line and columns, as its parse would make them.
        """
        blocks: list[Block] = []
        # the text after a line's block number → the first block of that text, and where the text begins
        seen: dict[str, tuple[Block, int]] = {}
        number_word = self._fast_word
        read = self._read_line
        new = tuple.__new__  # the hot path: skips NamedTuple's argument handling
        for n, raw in enumerate(lines, 1):
            cut, digits = 0, ""
            if raw[:1] == "N":
                lead = number_word.match(raw)
                if lead is not None and lead[1] == "N" and lead[2].isdigit():
                    cut, digits = lead.end(), lead[2]
            rest = raw[cut:] if cut else raw
            hit = seen.get(rest)
            # (both numbered, or the same text: a number read as part of the other's text is not its number)
            if hit is not None and (hit[1] > 0) == (cut > 0) and len(raw) <= limits.max_line_length:
                first, at = hit
                shift = cut - at
                words = tuple(
                    [new(Word, (w[0], w[1], w[2], n, w[4] + shift, w[5] + shift, None)) for w in first.words]
                )
                number = int(digits) if cut else first.number
                blocks.append(Block(n, raw.removesuffix("\r"), number, words, (), None, first.comment))
                continue
            count = len(diagnostics)
            block, plain = read(raw, n, limits, diagnostics)
            blocks.append(block)
            # (diagnostics name their line: such a line is read again)
            if plain and len(diagnostics) == count:
                seen[rest] = (block, cut)
        return blocks

    def _reparse(
        self, memo: LineMemo, lines: list[str], limits: Limits
    ) -> tuple[list[Block], list[list[Diagnostic]], tuple[int, int, int]]:
        """Each line's block and diagnostics, and the changed lines (first, old end, new end): those before and
        after the changed lines (the longest common prefix and suffix with the memo's lines) as they were,
        moved to their new line where lines were inserted or deleted; the changed ones parsed, or found among
        the memo's changed lines by text."""
        old, old_blocks, old_found = memo.lines, memo.blocks, memo.found
        n_old, n_new = len(old), len(lines)
        a, b = common_ends(old, lines)
        blocks, found = old_blocks[:a], old_found[:a]
        # the memo's changed lines without diagnostics, by text: a line moved within the change
        moved = {old[i]: old_blocks[i] for i in range(a, n_old - b) if not old_found[i]}
        for i in range(a, n_new - b):
            raw, n = lines[i], i + 1
            other = moved.get(raw)
            if other is not None:
                blocks.append(other if other.line == n else _relined(other, n))
                found.append([])
            else:
                now: list[Diagnostic] = []
                blocks.append(self.parse_line(raw, n, limits, now))
                found.append(now)
        changed = (a + 1, n_old - b + 1, n_new - b + 1)
        delta = n_new - n_old
        if delta == 0:
            blocks += old_blocks[n_old - b :]
            found += old_found[n_old - b :]
            return blocks, found, changed
        for i in range(n_old - b, n_old):  # after the change, `delta` lines further
            n = i + 1 + delta
            if old_found[i]:  # its diagnostics name its line: parsed again
                again: list[Diagnostic] = []
                blocks.append(self.parse_line(old[i], n, limits, again))
                found.append(again)
            else:
                blocks.append(_relined(old_blocks[i], n))
                found.append([])
        return blocks, found, changed

    # -- one line --------------------------------------------------------------------------

    def parse_line(self, raw: str, line: int, limits: Limits, diagnostics: list[Diagnostic]) -> Block:
        """Parse one line into a block, appending any diagnostics."""
        return self._read_line(raw, line, limits, diagnostics)[0]

    def _read_line(
        self, raw: str, line: int, limits: Limits, diagnostics: list[Diagnostic]
    ) -> tuple[Block, bool]:
        """`parse_line`, and whether the line is plain words without a skip mark (read by the first fast path:
        no expression, assignment or header), which `_parse_lines` may move to another line."""
        raw = raw.removesuffix("\r")
        if len(raw) > limits.max_line_length:
            diagnostics.append(
                diag(
                    "PAL-E004",
                    Span(line, 1, line, limits.max_line_length + 1),
                    length=len(raw),
                    limit=limits.max_line_length,
                )
            )
            return Block(line, raw[: limits.max_line_length], None, (), ok=False), False
        text = raw.upper() if raw.isascii() else "".join(c.upper() if c.isascii() else c for c in raw)
        plain = self._plain_block(raw, text, line, diagnostics)
        if plain is not None:
            return plain, plain.skip is None and plain.header is None  # (ISO: O<n> is a header)
        if (
            text.strip(" \t") == "%"
        ):  # a program's start or end mark alone, as the grammar reads it (TRAUB, ISO)
            return _finish_block(raw, line, [], (), None, None, "", diagnostics, self._programs), False
        simple = self._simple_line.fullmatch(text) if self._simple_line is not None else None
        if simple is not None:
            return self._simple_block(raw, text, line, simple, diagnostics), False
        bad = _CONTROL.search(text)
        if bad is not None:
            col = bad.start() + 1
            diagnostics.append(diag("PAL-E008", Span(line, col, line, col + 1), char_code=ord(bad.group())))
            return Block(line, raw, None, (), ok=False), False
        try:
            tree = self._lark.parse(text)
        except UnexpectedInput as err:
            diagnostics.append(self._syntax_diagnostic(err, text, line))
            return Block(line, raw, None, (), ok=False), False
        try:
            return self._tree_block(raw, line, tree, diagnostics), False
        except _TooDeep as err:
            diagnostics.append(
                diag("PAL-E014", Span(line, err.column, line, len(raw) + 1), limit=MAX_EXPR_DEPTH)
            )
            return Block(line, raw, None, (), ok=False), False

    def _plain_block(self, raw: str, text: str, line: int, diagnostics: list[Diagnostic]) -> Block | None:
        """The block of a line of plain words (an optional skip mark, words with blanks between them and at most
        a comment at the end), as the grammar reads it; None for any other line. The words are matched one
        after the other, each where the last one ended: the line is read in one pass."""
        pos, size, skip = 0, len(text), None
        if text[:1] in " \t/":  # (and an empty line)
            head = self._plain_head.match(text)
            assert head is not None  # (all of it is optional)
            pos, mark = head.end(), head["skip"]
            skip = None if mark is None else _skip_level(mark)
        match = self._plain_word.match
        number = _loose_number if self._loose else float
        new = tuple.__new__  # the hot path: skips NamedTuple's argument handling
        words: list[Word] = []
        append = words.append
        while pos < size:
            w = match(text, pos)
            if w is None:
                break
            address, digits = w.groups()
            end = w.end(2)
            append(new(Word, (address, number(digits), digits, line, pos + 1, end + 1, None)))
            pos = w.end()
        comment = None
        if pos < size:
            if self._plain_tail.fullmatch(text, pos) is None:
                return None
            comment = _comment_text(raw[pos:])
        return _finish_block(raw, line, words, (), skip, comment, None, diagnostics, self._programs)

    def _simple_block(
        self, raw: str, text: str, line: int, m: re.Match[str], diagnostics: list[Diagnostic]
    ) -> Block:
        """A line of words, assignments and parameter words whose value is one number or parameter with an
        optional sign (`_simple_patterns`), as `_tree_block` reads it from lark's tree."""
        words: list[Word] = []
        assignments: list[Assignment] = []
        item = self._simple_item
        assert item is not None
        for w in item.finditer(text, m.start("body"), m.end("body")):
            addr, num, start = w["address"], w["number"], w.start() + 1
            if num is not None and w["value"] is None:  # a word
                value = _loose_number(num) if self._loose else float(num)
                words.append(Word(addr, value, num, line, start, w.end("number") + 1))
                continue
            group, sign = ("value", "sign") if num is not None else ("param", "param_sign")
            at, end = w.start(group) + 1, w.end(group) + 1
            operand: Expr = (
                ParamRef(int(w[group][1:]), at, end)
                if w[group].startswith(self._param)
                else Num(_loose_number(w[group]), at, end)
            )
            expr = operand if w[sign] is None else Neg(operand, w.start(sign) + 1, end)
            if num is None:  # a parameter word: X=P1, X L2
                words.append(Word(addr, None, "=" + raw[expr[-2] - 1 : expr[-1] - 1], line, start, end, expr))
            else:
                self._assignment(raw, line, addr, num, start, expr, words, assignments, diagnostics)
        skip, comment_start = m.group("skip"), m.start("comment")
        return _finish_block(
            raw,
            line,
            words,
            tuple(assignments),
            None if skip is None else _skip_level(skip),
            None if comment_start < 0 else _comment_text(raw[comment_start:]),
            None,
            diagnostics,
            self._programs,
        )

    def _assignment(
        self,
        raw: str,
        line: int,
        addr: str,
        num: str,
        start: int,
        expr: Expr,
        words: list[Word],
        assignments: list[Assignment],
        diagnostics: list[Diagnostic],
    ) -> None:
        """`addr num = expr`: a valued code (Beckhoff's G301=20) is a word, P<n> (TRAUB: L<n>) an assignment,
        anything else PAL-E009."""
        if num.isdigit() and f"{addr}{int(num)}" in self._valued:
            text = "=" + raw[expr[-2] - 1 : expr[-1] - 1]
            words.append(Word(f"{addr}{int(num)}", None, text, line, start, expr[-1], expr))
        elif str(addr) != self._param or not num.isdigit():
            diagnostics.append(diag("PAL-E009", Span(line, start, line, expr[-1]), address=f"{addr}{num}"))
        else:
            assignments.append(Assignment(int(num), expr, line, start, expr[-1]))

    def _tree_block(self, raw: str, line: int, tree: Tree[Token], diagnostics: list[Diagnostic]) -> Block:
        words: list[Word] = []
        assignments: list[Assignment] = []
        skip: int | None = None
        comment: str | None = None
        header: str | None = None
        for child in tree.children:
            if isinstance(child, Token):
                if child.type == "SKIP":
                    skip = _skip_level(str(child))
                elif child.type == "COMMENT":
                    comment = _comment_text(raw[child.column - 1 : child.end_column - 1])  # type: ignore[operator]
                elif child.type == "HEADER":
                    header = raw[child.column : child.end_column - 1].strip()  # type: ignore[operator]
                continue
            if child.data == "unsupported":  # #HSC ON [...], $IF …, V.P.X = 5, V.L.TIME: one word, no value
                tok: Token = child.children[0]  # type: ignore[assignment]
                text = raw[tok.column - 1 : tok.end_column - 1].rstrip()  # type: ignore[operator]
                name = re.split(r"[\s=\[]", str(tok), maxsplit=1)[0]
                column: int = tok.column  # type: ignore[assignment]
                words.append(Word(name, None, text, line, column, column + len(text)))
                continue
            addr: Token = child.children[0]  # type: ignore[assignment]
            start: int = addr.column  # type: ignore[assignment]
            if (
                child.data == "bare"
            ):  # a value without an address (Beckhoff's G04 3.0): the interpreter decides
                words.append(Word("", float(addr), str(addr), line, start, addr.end_column))  # type: ignore[arg-type]
            elif child.data == "unsupported_value":  # X=V.P.X: the variable is what is not supported
                ref: Token = child.children[1]  # type: ignore[assignment]
                text = raw[start - 1 : ref.end_column - 1]  # type: ignore[operator]
                words.append(Word(str(ref), None, text, line, start, ref.end_column))  # type: ignore[arg-type]
            elif child.data == "word":
                num: Token = child.children[1]  # type: ignore[assignment]
                value = _loose_number(num) if self._loose else float(num)
                words.append(Word(str(addr), value, str(num), line, start, num.end_column))  # type: ignore[arg-type]
            elif child.data == "flag":
                words.append(Word(str(addr), None, "", line, start, addr.end_column))  # type: ignore[arg-type]
            elif child.data == "exprword":
                expr = _expr(child.children[1])
                words.append(
                    Word(str(addr), None, "=" + raw[expr[-2] - 1 : expr[-1] - 1], line, start, expr[-1], expr)
                )
            else:  # assign
                num = child.children[1]  # type: ignore[assignment]
                expr = _expr(child.children[2])
                self._assignment(raw, line, addr, num, start, expr, words, assignments, diagnostics)
        return _finish_block(
            raw, line, words, tuple(assignments), skip, comment, header, diagnostics, self._programs
        )

    def _syntax_diagnostic(self, err: UnexpectedInput, text: str, line: int) -> Diagnostic:
        """Turn lark's exception into the most helpful diagnostic for the trainee."""
        for m in _LOOSE_WORD.finditer(text):
            value = m.group(2)
            if self._fast_word.fullmatch(m.group(0).replace(" ", "").replace("\t", "")):
                continue
            span = Span(line, m.start(2) + 1, line, m.end(2) + 1)
            fixed = value.replace(",", ".")
            if "," in value and self._fast_word.fullmatch(m.group(1) + fixed):
                return diag("PAL-E010", span, text=f"{m.group(1)}{value}", fixed=f"{m.group(1)}{fixed}")
            return diag("PAL-E002", span, text=value, address=m.group(1))
        col = getattr(err, "column", None)
        if isinstance(err, UnexpectedCharacters) or col is None or col < 1:
            col = col if isinstance(col, int) and col >= 1 else len(text) + 1
            char = text[col - 1] if col <= len(text) else " "
            return diag("PAL-E001", Span(line, col, line, col + 1), char=char)
        if isinstance(err, (UnexpectedToken, UnexpectedEOF)):
            token = getattr(err, "token", None)
            expected = sorted(getattr(err, "expected", ()) or ())
            de = " oder ".join(sorted({_TERMINAL_NAMES.get(t, (t, t))[0] for t in expected})) or "nichts"
            en = " or ".join(sorted({_TERMINAL_NAMES.get(t, (t, t))[1] for t in expected})) or "nothing"
            shown = "Satzende" if token is None or token.type == "$END" else str(token)
            end = col + max(1, len(shown) if token is not None and token.type != "$END" else 1)
            d = diag("PAL-E007", Span(line, col, line, end), token=shown, expected=de)
            en_msg = diag(
                "PAL-E007", d.span, token=shown if shown != "Satzende" else "end of block", expected=en
            ).message_en
            return Diagnostic(d.code, d.severity, d.span, d.message, en_msg, d.params)
        return diag("PAL-E001", Span(line, col, line, col + 1), char=text[col - 1 : col] or " ")


def _finish_block(
    raw: str,
    line: int,
    words: list[Word],
    assignments: tuple[Assignment, ...],
    skip: int | None,
    comment: str | None,
    header: str | None,
    diagnostics: list[Diagnostic],
    programs: bool = False,
) -> Block:
    """Take a leading N word as the block number; with `programs`, a leading O word is a program number (the block
    becomes a header `O<n>` that starts a program, as the `%L<n>` lines of PAL do)."""
    number: int | None = None
    if words and words[0].address == "N" and words[0].value is not None:
        first = words[0]
        if first.raw.isdigit():
            number = int(first.raw)
        else:
            diagnostics.append(diag("PAL-E011", first.span, raw=first.raw))
        words = words[1:]
    if programs and words and words[0].address == "O" and words[0].value is not None and not assignments:
        first = words[0]
        if not first.raw.isdigit():
            diagnostics.append(diag("PAL-E108", first.span, address="O", raw=first.raw))
            return Block(line, raw, number, (), assignments, skip, comment, None, ok=False)
        if len(words) > 1:
            rest = words[1]
            diagnostics.append(
                diag(
                    "ISO-E307",
                    Span(line, rest.column, line, words[-1].end_column),
                    number=int(first.raw),
                    words=" ".join(str(w) for w in words[1:]),
                )
            )
        return Block(line, raw, number, (), assignments, skip, comment, f"O{int(first.raw)}")
    return Block(line, raw, number, tuple(words), assignments, skip, comment, header)


def _simple_patterns(
    lark: Lark, term: dict[str, str], address: str, number: str
) -> tuple[re.Pattern[str] | None, re.Pattern[str] | None]:
    """The line and the item of the second fast path, assembled from the grammar's terminals: words,
    assignments `ADDRESS NUMBER = value` and parameter words `ADDRESS = value` (TRAUB: `ADDRESS value`, whose
    value is a parameter: `X 5` is a word), the value one number or parameter with an optional sign (NEG).
    (None, None) for a grammar without parameters."""
    if "PREF" not in term or "UNUM" not in term:
        return None, None
    ws = "[ \t]*"
    exprword = next(r.expansion for r in lark.rules if r.origin.name == "exprword")
    equal = any(t.name == "EQUAL" for t in exprword)  # PAL: X=P1; TRAUB: X L2
    pref = _without_groups(term["PREF"])
    value = f"{_without_groups(term['UNUM'])}|{pref}"
    param = value if equal else pref
    lead = f"={ws}" if equal else ""
    item = f"(?:{address}){ws}(?:(?:{number})(?:{ws}={ws}(?:-{ws})?(?:{value}))?|{lead}(?:-{ws})?(?:{param}))"
    line = re.compile(
        f"{ws}(?P<skip>{term['SKIP']})?(?P<body>(?:{ws}{item})*){ws}(?P<comment>{term['COMMENT']})?"
    )
    read = re.compile(
        f"(?P<address>{address}){ws}(?:(?P<number>{number})(?:{ws}={ws}(?P<sign>-{ws})?(?P<value>{value}))?"
        f"|{lead}(?P<param_sign>-{ws})?(?P<param>{param}))"
    )
    return line, read


def _without_groups(pattern: str) -> str:
    """A terminal's pattern with its groups made non-capturing: the same matches, found faster (every group
    a repeated pattern captures costs time). The terminals have no parenthesis inside a character class."""
    found = re.sub(r"(?<!\\)\((?!\?)", "(?:", pattern)
    assert re.compile(found).groups == 0, pattern
    return found


def _loose_number(text: str) -> float:
    """A number as the TRAUB manual writes it: decimal comma or point, blanks inside (`- 1,6`, `02 02`)."""
    if "," not in text and " " not in text and "\t" not in text:
        return float(text)  # the common case
    return float(text.replace(",", ".").replace(" ", "").replace("\t", ""))


def _comment_text(text: str) -> str:
    """The text of a comment without its marks: `; text` or `(text)`."""
    if text.startswith("("):
        return text[1:].removesuffix(")").strip()
    return text[1:].strip()


def _skip_level(token: str) -> int:
    return int(token[1:]) if len(token) > 1 else 0


MAX_EXPR_DEPTH = 200  # depth of one expression's tree (operators and signs)


class _TooDeep(Exception):
    def __init__(self, column: int) -> None:
        self.column = column


def _expr(node: Tree[Token] | Token, depth: int = 0) -> Expr:
    """Convert an expression subtree; every node carries its column range."""
    if isinstance(node, Token):  # a parenthesised single token is inlined by `?factor`
        raise TypeError(node)
    if depth > MAX_EXPR_DEPTH:
        raise _TooDeep(1)
    kind = node.data
    if kind == "num":
        tok: Token = node.children[0]  # type: ignore[assignment]
        return Num(_loose_number(tok), tok.column, tok.end_column)  # type: ignore[arg-type]
    if kind == "pref":
        tok = node.children[0]  # type: ignore[assignment]
        return ParamRef(int(tok[1:]), tok.column, tok.end_column)  # type: ignore[arg-type]
    if kind == "neg":
        sign: Token = node.children[0]  # type: ignore[assignment]
        operand = _expr(node.children[1], depth + 1)
        return Neg(operand, sign.column, operand[-1])  # type: ignore[arg-type]
    left = _expr(node.children[0], depth + 1)
    op: Token = node.children[1]  # type: ignore[assignment]
    right = _expr(node.children[2], depth + 1)
    return BinOp(str(op), left, right, left[-2], right[-1])


@cache
def parser_for(
    grammar: str, valued_codes: frozenset[str] = frozenset(), program_numbers: bool = False
) -> BlockParser:
    """The (cached) parser of grammar file `<grammar>.lark` in this package."""
    return BlockParser(Path(__file__).with_name(f"{grammar}.lark"), valued_codes, program_numbers)


def _relined(block: Block, line: int) -> Block:
    """`block` as the parse of its text in line `line` (a block is its text and its line)."""
    return Block(
        line,
        block.text,
        block.number,
        tuple(w._replace(line=line) for w in block.words),
        tuple(a._replace(line=line) for a in block.assignments),
        block.skip,
        block.comment,
        block.header,
        block.ok,
    )
