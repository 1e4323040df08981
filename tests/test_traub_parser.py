"""TRAUB words as the manual writes them: blanks inside words, decimal comma, comments in parentheses,
`%` and `O` lines, L parameters with brackets — parsed to the same values as the plain spelling."""

from __future__ import annotations

import pytest

from core.pipeline import parse, run
from tests.conftest import codes


def words(line: str) -> list[tuple[str, float | None]]:
    program, diagnostics = parse(line, "traub-tx8d")
    assert diagnostics == []
    (block,) = program.blocks
    return [(w.address, w.value) for w in block.words]


@pytest.mark.parametrize(
    ("written", "plain"),
    [
        ("G 96 V 200 T 0303 M 04", "G96 V200 T303 M4"),
        ("G 1 Z - 30", "G1 Z-30"),  # TX-27, second copy
        ("G 0 X - 1,6 Z 1", "G0 X-1.6 Z1"),
        ("G 1 X 40 D 2 F 0,2 E 0,1", "G1 X40 D2 F0.2 E0.1"),
        ("N2 T02 02", "N2 T0202"),
        ("B 06 3500", "B063500"),
        ("G01 Z-106 F 0,2", "G1 Z-106 F.2"),
        ("G 4 X0.5 (0,5 sek. Verweilzeit)", "G4 X0.5"),
        ("G1 X5 (Mitte) Z3", "G1 X5 Z3"),
    ],
)
def test_written_like_the_manual_reads_like_the_plain_spelling(written: str, plain: str) -> None:
    assert words(written) == words(plain)


def test_program_lines_and_comments() -> None:
    program, diagnostics = parse("%\nO 4711\n(SCHRUPPEN)\n/G 01 Z-106 F 0,2\n%\n", "traub-tx8d")
    assert diagnostics == []
    header, number, comment, skip, footer = program.blocks
    assert header.header is not None and footer.header is not None
    assert [(w.address, w.value) for w in number.words] == [("O", 4711)]
    assert comment.comment == "SCHRUPPEN" and comment.is_empty
    assert skip.skip == 0


def test_parameters_in_brackets_and_as_bare_values() -> None:
    text = (
        "L 1 = 20\nL2 = [L 1 + 5]\nL3 = [[L1 - L2] * 2]\nG97 S500 T0101 M3\nG0 X L2 Z-[L2/2]\n"
        "G1 Z-L1 F[L3 * -0.01]\nM30"
    )
    tp = run(text, "traub-tx8d")
    assert codes(tp) == []
    assert tp.params == {1: 20, 2: 25, 3: -10}
    assert [(round(m.end[0] * 2, 3), round(m.end[2], 3)) for m in tp.moves] == [(25.0, -12.5), (25.0, -20.0)]
    assert tp.moves[1].feed == pytest.approx(0.1)


def test_pal_still_refuses_the_decimal_comma_and_l_assignments() -> None:
    assert ("PAL-E010", 1) in codes(run("G1 X1,5\nM30"))
    assert ("PAL-E009", 1) in codes(run("L1=5\nM30"))


def test_a_syntax_error_names_its_column() -> None:
    tp = run("G1 X1,2.3\nM30", "traub-tx8d")
    (d,) = tp.diagnostics
    assert (d.code, d.span.line, d.span.column) == ("TX-E1002", 1, 5)
