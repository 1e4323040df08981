"""The block parser: words with spans, numbers, comments, headers, skip blocks, assignments."""

from __future__ import annotations

from pathlib import Path

import pytest

from core.diagnostics import Diagnostic
from core.limits import Limits
from core.syntax.blocks import Block
from core.syntax.parser import LineMemo, parser_for

PARSER = parser_for("pal_mill")
LIMITS = Limits()


def parse(text: str) -> tuple[Block, list[Diagnostic]]:
    d: list[Diagnostic] = []
    return PARSER.parse_line(text, 1, LIMITS, d), d


def slow(text: str) -> Block:
    """The same line through lark only, bypassing the fast path."""
    d: list[Diagnostic] = []
    upper = text.upper()
    return PARSER._tree_block(text, 1, PARSER._lark.parse(upper), d)


def test_words_with_spans_and_block_number() -> None:
    block, diags = parse("N70 G2 X56.4 Y10 I-20 J6.4")
    assert diags == []
    assert block.number == 70
    assert [(w.address, w.value) for w in block.words] == [
        ("G", 2),
        ("X", 56.4),
        ("Y", 10),
        ("I", -20),
        ("J", 6.4),
    ]
    x = block.words[1]
    assert (x.span.line, x.span.column, x.span.end_column) == (1, 8, 13)


def test_two_letter_addresses_match_longest_first() -> None:
    block, _ = parse("G1 XI5 YA-3 RN-15 TC2 AS85 IA50")
    assert [w.address for w in block.words] == ["G", "XI", "YA", "RN", "TC", "AS", "IA"]


@pytest.mark.parametrize(
    "text,value", [("G01", 1), ("T01", 1), ("X+5", 5), ("X-.5", -0.5), ("X5.", 5), ("X007.50", 7.5)]
)
def test_numbers_with_leading_zeros_and_signs(text: str, value: float) -> None:
    block, diags = parse(text)
    assert diags == [] and block.words[0].value == value


def test_comment_header_and_skip() -> None:
    block, _ = parse("/ N10 G1 X5 ; Kontur fräsen")
    assert block.skip == 0 and block.number == 10 and block.comment == "Kontur fräsen"
    header, _ = parse("%100 ; Hauptprogramm")
    assert header.header == "100" and header.comment == "Hauptprogramm"


def test_lowercase_is_accepted() -> None:
    block, diags = parse("n10 g1 x5 rn-2")
    assert diags == [] and [w.address for w in block.words] == ["G", "X", "RN"]


def test_parameter_assignments_with_precedence() -> None:
    block, diags = parse("N40 P12=P12+1 P2=(P1+2)*3")
    assert diags == [] and [a.param for a in block.assignments] == [12, 2]
    from core.interpreter.params import evaluate

    assert evaluate(block.assignments[1].expr, {1: 4.0}, 1, []) == 18


def test_value_less_flags_for_mirroring() -> None:
    block, _ = parse("G66 X Y")
    assert [(w.address, w.value) for w in block.words[1:]] == [("X", None), ("Y", None)]


@pytest.mark.parametrize(
    "line",
    [
        "N10 G1 X-3.5 Y+.5 ; c",
        "G01X10Y20",
        "N120 G0 X250 Y150 Z250 M30",
        "/1 N5 M3",
        "T1 TC1 M6",
        "N70 G2 X56.4 Y10 I-20 J6.4 F150",
        "  G1   X1  ",
        "",
        "; only a comment",
        "X 10",
    ],
)
def test_fast_path_and_grammar_agree(line: str) -> None:
    fast, diags = parse(line)
    assert diags == []
    assert fast == slow(line)


@pytest.mark.parametrize(
    ("grammar", "line"),
    [
        ("pal_mill", "N10 P1=5 P2 = -2.5 X=P1 Y=-P2 ; c"),
        ("pal_mill", "/ p12=p3 g1 x=.5"),
        ("pal_mill", "X5=3 P1.5=2 P4=1"),  # PAL-E009 twice: not an address of parameters, not a whole number
        ("traub", "L1 = 11"),
        ("traub", "N3 G97 V30 X L2 T0505 M3"),
        ("traub", "G1 Z- L 4 F0,1 (Einstich)"),
        ("traub", "L 2 = L1 L3=-2,5 L1 2 = 5"),
        ("beckhoff", "G301=20 #CHR=2 X=P1 P7=-P1 (c)"),
    ],
)
def test_simple_parameter_lines_read_as_the_grammar_reads_them(grammar: str, line: str) -> None:
    """Assignments and parameter words whose value is one number or parameter take the second fast path;
    they read as lark reads them, diagnostics included."""
    parser = parser_for(grammar)
    assert parser._simple_line is not None and parser._simple_line.fullmatch(line.upper())
    fast: list[Diagnostic] = []
    block = parser.parse_line(line, 3, LIMITS, fast)
    slow: list[Diagnostic] = []
    assert block == parser._tree_block(line, 3, parser._lark.parse(line.upper()), slow) and fast == slow
    assert block.assignments or any(w.expr is not None for w in block.words)


@pytest.mark.parametrize(
    "lines",
    [
        ["N10 G1 X5 Y3 ; a", "N20 G1 X5 Y3 ; a", "N100G1 X5 Y3 ; a", "G1 X5 Y3 ; a", "n30 g1 x5 y3 ; a"],
        ["N5 N10 G1", " N10 G1", "N10 G1", "N7 N10 G1", "N10.5 G1", "N11.5 G1", "N1 G1\r", "N2 G1\r\r"],
        ["G1 X5", "N1 P1=2", "N2 P1=2", "N3 G1 X5", "N4 G1 X=P1", "N5 G1 X=P1", "/N6 G1 X5", "/N6 G1 X5"],
        ["N1 G1 X" + "1" * 20, "N12345 G1 X" + "1" * 20, "N1 %", "N2 %", "N1 O5", "N2 O5"],
    ],
)
def test_a_repeated_line_reads_as_its_own_parse(lines: list[str]) -> None:
    """A program's parse takes the words of a line read before with the same text after the block number, moved
    to its line and columns: the same blocks and diagnostics as every line parsed on its own (a line limit of 30
    characters: the longer number makes the last but three lines too long)."""
    for parser in (PARSER, parser_for("iso", program_numbers=True), parser_for("traub")):
        limits = Limits(max_line_length=30)
        alone: list[Diagnostic] = []
        blocks = [parser.parse_line(raw, n, limits, alone) for n, raw in enumerate(lines, 1)]
        program, found = parser.parse_program("\n".join(lines), limits)
        assert program.blocks == blocks and found == alone


def test_error_points_at_the_bad_word_and_other_blocks_still_parse() -> None:
    program, diags = PARSER.parse_program("N10 G1 X5\nN20 G1 Y1..5\nN30 G1 Z2\n", LIMITS)
    assert [(d.code, d.span.line, d.span.column) for d in diags] == [("PAL-E002", 2, 9)]
    assert [b.ok for b in program.blocks] == [True, False, True]


def test_a_memo_parses_only_the_changed_lines_and_moves_the_others() -> None:
    """The live editor's parse with a memo: a keystroke parses its line only (the others are the same
    blocks); a new line moves the blocks after it (a line with a diagnostic is parsed again, its span
    moves); every result equals a parse without the memo."""
    lines = [f"N{10 * i} G1 X{i} Y{i % 7}" for i in range(1, 200)] + ["N2000 G1 X1..5", "M30"]
    memo = LineMemo()
    first, _ = PARSER.parse_program("\n".join(lines) + "\n", LIMITS, memo)
    typed = [*lines[:50], "N505 G1 X5", *lines[51:]]
    program, diags = PARSER.parse_program("\n".join(typed) + "\n", LIMITS, memo)
    assert sum(a is not b for a, b in zip(first.blocks, program.blocks, strict=True)) == 1
    # the run need not compare the programs again: the parse says which lines changed (line 51)
    assert program.base is first.blocks and program.changed == (51, 52, 52)
    broken = [*typed[:10], "", *typed[10:]]  # Enter in line 11
    before = program.blocks
    program, diags = PARSER.parse_program("\n".join(broken) + "\n", LIMITS, memo)
    assert program.base is before and program.changed == (11, 11, 12)
    fresh, fresh_diags = PARSER.parse_program("\n".join(broken) + "\n", LIMITS)
    assert program.blocks == fresh.blocks and diags == fresh_diags
    assert [d.span.line for d in diags] == [201]  # N2000 G1 X1..5, one line further down


@pytest.mark.parametrize("grammar", ["pal_mill", "iso", "beckhoff", "traub"])
@pytest.mark.parametrize("raw", ["%", "  %\t", "%\r"])
def test_a_lone_percent_line_reads_as_the_grammar_reads_it(grammar: str, raw: str) -> None:
    """The start and end mark `%` of a program file (TRAUB, ISO) is read without the grammar's parser, as
    the grammar reads it: a header line with no words."""
    parser = parser_for(grammar)
    found: list[Diagnostic] = []
    block = parser.parse_line(raw, 3, LIMITS, found)
    text = raw.removesuffix("\r")
    expected = parser._tree_block(text, 3, parser._lark.parse(text.upper()), [])
    assert block == expected and found == []
    assert block.header == "" and block.words == () and block.ok


# lines at the edges of the word-by-word reading: blanks, comments, skip marks, numbers with blanks (TRAUB),
# a comment in the middle (ISO), words run together, a word that is not one, lower case and umlauts
EDGE_LINES = [
    "G1 X5 ",
    "G1 X5\t; Kontur fräsen",
    "G1 X5 ;",
    "G1X5;a;b",
    "N10G1X5",
    "X5.;c",
    "T02 02 M6",
    "X1 2",
    "G1 X5 (Fase)",
    "G1 (a) X5",
    "(a) G1",
    "G1 X5 (offen",
    "G1 X=5",
    "G1 X5 %",
    "g1 x5 ; Überlauf",
    "G1 XÄ5",
    "/G1 X5",
    "\tG1 X5",
    "G1\tX5",
    "/1 N5 M3",
    " / G1",
    "/",
    "   ",
    "; nur ein Kommentar",
    "G1 / X5",
]


# the grammar of the programs in each folder (a program's folder names its dialect)
GRAMMAR_OF_FOLDER = {
    "beckhoff": "beckhoff",
    "traub": "traub",
    "traub-tx8d": "traub",
    "iso": "iso",
    "sinumerik-iso": "iso",
}


def _program_lines() -> list[tuple[str, str]]:
    """(grammar, line) of every built-in exercise (and its start program), seed and test program, and the edge
    lines in every grammar."""
    root = Path(__file__).parents[1]
    found: set[tuple[str, str]] = set()
    for folder in ("exercises", "tests/seeds", "tests/programs"):
        for path in (*(root / folder).rglob("*.nc"), *(root / folder).rglob("*-start.txt")):
            grammar = GRAMMAR_OF_FOLDER.get(path.parent.name, "pal_mill")
            found.update(
                (grammar, line.removesuffix("\r")) for line in path.read_text(encoding="utf-8").split("\n")
            )
    for grammar in ("pal_mill", "iso", "beckhoff", "traub"):
        found.update((grammar, line) for line in EDGE_LINES)
    return sorted(found)


def test_the_word_by_word_reading_reads_every_line_as_the_grammar_reads_it() -> None:
    """A line of plain words (an optional skip mark, words, at most a comment at the end) is read word by word;
    every such line of every program we have reads as lark reads it, and the rest are left to the other paths."""
    taken, kinds = 0, set()
    for grammar, line in _program_lines():
        parser = parser_for(grammar)
        text = line.upper()
        found: list[Diagnostic] = []
        block = parser._plain_block(line, text, 4, found)
        if block is None:
            continue
        taken += 1
        kinds.add(grammar)
        slow: list[Diagnostic] = []
        assert block == parser._tree_block(line, 4, parser._lark.parse(text), slow), (grammar, line)
        assert found == slow, (grammar, line)
    assert taken > 1000 and kinds == {
        "pal_mill",
        "iso",
        "beckhoff",
        "traub",
    }  # most lines are read word by word
