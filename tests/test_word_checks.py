"""The word checks every dialect makes from its code table (core/interpreter/words.py): a negative value where
the address's `non_negative` column says none, a missing required address, two members of one modal group."""

from __future__ import annotations

import pytest

from core.pipeline import DIALECTS, run

# dialect, the addresses its table marks (the manuals' rules), a block with a negative value of one of them
NEGATIVE = [
    ("pal-mill", ("F", "S", "H", "E", "U", "RP"), "N10 G1 X10 F-100\n", "PAL-E109", 12),
    ("traub-tx8d", ("H", "F", "E", "S", "V"), "N10 G1 X10 F-0.2\n", "TX-E1109", 12),
    ("sinumerik-iso", ("F", "S", "D", "K", "H", "P", "L"), "N10 G1 X10 D-1\n", "ISO-E1109", 12),
    ("beckhoff", ("F", "S", "D", "K"), "N10 G01 X10 S-100\n", "BK-E1109", 13),
]


@pytest.mark.parametrize(("dialect", "marked", "text", "code", "column"), NEGATIVE)
def test_a_negative_value_of_a_marked_address_is_reported_at_its_word(
    dialect: str, marked: tuple[str, ...], text: str, code: str, column: int
) -> None:

    assert set(DIALECTS[dialect].table.non_negative) == set(marked)
    tp = run(text, dialect)
    found = [(d.code, d.span.line, d.span.column) for d in tp.diagnostics if d.code == code]
    assert found == [(code, 1, column)]


def test_traub_program_end_codes_in_one_block_are_two_members_of_one_group() -> None:
    tp = run("N10 M30 M99\n", "traub-tx8d")
    codes = {d.code for d in tp.diagnostics}
    assert "TX-E105" in codes  # they must stand alone
    assert "TX-E1103" in codes  # and M30 and M99 are both program ends (PAL-E103)


def test_a_required_address_missing_is_named_with_its_code() -> None:
    tp = run("N10 G4\n", "traub-tx8d")
    missing = [d for d in tp.diagnostics if d.code == "TX-E1102"]
    assert [d.span.column for d in missing] == [5]
    assert "X/U" in missing[0].message
