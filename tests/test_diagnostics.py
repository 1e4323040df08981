"""Each diagnostic the interpreter promises, triggered by a minimal program: right code, right line."""

from __future__ import annotations

import pytest

from core.diagnostics import CATALOGUE, Severity
from core.pipeline import run
from tests.conftest import codes

READY = "N1 T1 M6\nN2 S1000 F100 M3\n"  # tool in, spindle on, feed set

CASES = [
    # (what, program, expected (code, line))
    ("unknown address", "N10 B5\nM30", ("PAL-E003", 1)),
    ("word not allowed with the command", "G0 X1 R5\nM30", ("PAL-E101", 1)),
    ("word not allowed with the modal command", "G0 X1\nX2 I4\nM30", ("PAL-E101", 2)),
    ("mandatory address missing", "N10 G4\nM30", ("PAL-E102", 1)),
    ("two G words of one modal group", "G90 G91\nM30", ("PAL-E103", 1)),
    ("two M words of one modal group", "T1 M3 M5\nM30", ("PAL-E103", 1)),
    ("M13 conflicts with M5", "S100 M13 M5\nM30", ("PAL-E103", 1)),
    ("more than two G words", "G1 G90 G17 X1\nM30", ("PAL-E104", 1)),
    ("unknown G code", "G5 X1\nM30", ("PAL-E105", 1)),
    ("address twice", "G1 X1 X2\nM30", ("PAL-E106", 1)),
    ("axis in two spellings", "G1 X1 XI2\nM30", ("PAL-E107", 1)),
    ("G code with decimals", "G1.5 X1\nM30", ("PAL-E108", 1)),
    ("negative feed", "F-100\nM30", ("PAL-E109", 1)),
    ("plane G18 is not PAL milling", "G18\nM30", ("PAL-E110", 1)),
    ("offset memory out of range", "T1 TC10 M6\nM30", ("PAL-E112", 1)),
    ("malformed number", "G1 X1.2.3\nM30", ("PAL-E002", 1)),
    ("decimal comma", "G1 X1,5\nM30", ("PAL-E010", 1)),
    ("unexpected character", "G1 X1 #\nM30", ("PAL-E001", 1)),
    ("arc without a solution", READY + "G0 X0 Y0 Z0\nG2 X10 Y0 R2\nM30", ("PAL-E201", 4)),
    (
        "arc end point inconsistent with the centre",
        READY + "G0 X0 Y0 Z0\nG2 X10 Y0 I3 J0\nM30",
        ("PAL-E202", 4),
    ),
    ("arc underdetermined", READY + "G0 X0 Y0\nG2 X10 Y0\nM30", ("PAL-E203", 4)),
    ("K in plane G17", READY + "G0 X0 Y0\nG2 X10 Y0 K5 R5\nM30", ("PAL-E204", 4)),
    ("full circle with R", READY + "G0 X0 Y0\nG2 X0 Y0 R5\nM30", ("PAL-E205", 4)),
    ("feed move with feed 0", "T1 M6\nS1000 M3\nG1 X5\nM30", ("PAL-E301", 3)),
    ("cutting move with spindle off", "T1 M6\nF100\nG1 X5\nM30", ("PAL-E302", 3)),
    ("cutting move with no tool", "F100 S100 M3\nG1 X5\nM30", ("PAL-E303", 2)),
    ("tool change switches the spindle off", READY + "T4 M6\nG1 X5\nM30", ("PAL-E302", 4)),
    ("unknown tool", "T9 M6\nM30", ("PAL-E304", 1)),
    ("dwell in revolutions with S0", "G4 U2 O2\nM30", ("PAL-E305", 1)),
    ("spindle on with S0", "T1 M6\nM3\nM30", ("PAL-E306", 2)),
    ("inches", "G70\nM30", ("PAL-E309", 1)),
    ("words after M30", "M30\nG1 X5", ("PAL-W101", 2)),
    ("missing M30", "G0 X5\nG0 Y5", ("PAL-W102", 2)),
    ("unknown M function", "M99\nM30", ("PAL-W103", 1)),
    ("scaling not supported yet", "G67\nM30", ("PAL-E901", 1)),
    ("cycles not supported yet", "G88\nM30", ("PAL-E901", 1)),
    ("missing subprogram", "G22 L5\nM30", ("PAL-E401", 1)),
    ("M17 outside a subprogram", "M17\nM30", ("PAL-E402", 1)),
    ("M30 inside a subprogram", "G22 L1\nM30\n%L1\nM30", ("PAL-E403", 4)),
    ("recursion", "G22 L1\nM30\n%L1\nG22 L1\nM17", ("PAL-E404", 4)),
    ("block number not found", "G23 N10 N20\nM30", ("PAL-E406", 1)),
    ("G23 end before start", "N10 G0 X1\nN20 G0 X2\nN30 G23 N20 N10\nM30", ("PAL-E407", 3)),
    ("jump target not found", "G29 N99\nM30", ("PAL-E406", 1)),
    ("shift while mirroring", "G66 X\nG59 XA5\nM30", ("PAL-E408", 2)),
    ("subprogram without M17", "G22 L1\nM30\n%L1\nG0 X1", ("PAL-E409", 4)),
    ("bad comparison", "P1=1\nG29 P1 O7 P2 N1\nM30", ("PAL-E410", 2)),
    ("division by zero", "P1=5/0\nM30", ("PAL-E114", 1)),
    ("parameter out of range", "P1000=1\nM30", ("PAL-E113", 1)),
    ("assignment to an address", "X1=5\nM30", ("PAL-E009", 1)),
    ("value out of range", "G0 X999999\nM30", ("PAL-E015", 1)),
]


@pytest.mark.parametrize("what,program,expected", CASES, ids=[c[0] for c in CASES])
def test_diagnostic(what: str, program: str, expected: tuple[str, int]) -> None:
    assert expected in codes(run(program))


def test_every_code_used_in_the_cases_is_in_the_catalogue() -> None:
    for _, _, (code, _) in CASES:
        assert code in CATALOGUE


def test_catalogue_codes_match_their_severity_letter() -> None:
    letters = {Severity.ERROR: "E", Severity.WARNING: "W", Severity.INFO: "I"}
    for code, entry in CATALOGUE.items():
        assert code.split("-")[1][0] == letters[entry.severity], code
        assert entry.de and entry.en and entry.de != entry.en


def test_diagnostic_carries_span_and_both_languages() -> None:
    (d,) = [d for d in run("N10 G1 X1,5\nM30").diagnostics]
    assert (d.code, d.span.line, d.span.column, d.span.end_column) == ("PAL-E010", 1, 9, 12)
    assert "Punkt" in d.message and "point" in d.message_en


def test_a_block_with_an_error_changes_nothing() -> None:
    tp = run(READY + "G91\nG0 X5 B1\nG0 X1\nM30")
    # line 4 is rejected (unknown B): no move, G91 still active, next move incremental from the old point
    assert ("PAL-E003", 4) in codes(tp)
    assert [m.line for m in tp.moves] == [5]
    assert tp.moves[0].end[0] == pytest.approx(251)


def test_one_bad_block_does_not_hide_the_others() -> None:
    tp = run("G1 X1.2.3\nG5\nN30 B1\nM30")
    assert [c for c in codes(tp)] == [("PAL-E002", 1), ("PAL-E105", 2), ("PAL-E003", 3)]


def test_clean_program_has_no_diagnostics() -> None:
    assert run(READY + "G0 X0 Y0 Z2\nG1 Z-1\nG1 X10\nG0 Z50 M30").diagnostics == []


def test_docs_list_every_diagnostic() -> None:
    from pathlib import Path

    from core.diagnostics import catalogue_markdown

    doc = Path(__file__).parents[1] / "docs" / "diagnostics.md"
    assert doc.read_text(encoding="utf-8") == catalogue_markdown(), (
        "run: python -m core.diagnostics > docs/diagnostics.md"
    )


@pytest.mark.parametrize("dialect", ["pal-mill", "sinumerik-iso", "beckhoff", "traub-tx8d"])
def test_an_empty_program_has_no_missing_end_warning(dialect: str) -> None:
    # an empty editor has nothing to report; one written block without M30 still gets the end-of-program warning
    assert [d.code for d in run("", dialect).diagnostics] == []
    assert [d.code for d in run("\n\n  \n", dialect).diagnostics] == []
    prefix = {
        "pal-mill": "PAL-W102",
        "sinumerik-iso": "ISO-W1102",
        "beckhoff": "BK-W1102",
        "traub-tx8d": "TX-W1102",
    }
    assert prefix[dialect] in [d.code for d in run("G0 X10\n", dialect).diagnostics]
