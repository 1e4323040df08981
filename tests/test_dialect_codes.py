"""Every dialect reports its diagnostics with its own prefix: a TRAUB, ISO or Beckhoff program never shows a PAL-
code. The checks the dialects share are catalogued once under PAL- and shown as <prefix>-<letter><number + 1000>
(core.diagnostics.in_dialect), which never collides with a dialect's own code."""

from __future__ import annotations

import string

import pytest

from core.diagnostics import CATALOGUE, SHARED_OFFSET, catalogue_code, diag, in_dialect
from core.interpreter.state import RunSetup
from core.limits import Limits
from core.pipeline import DIALECTS, parse, run, summarised
from core.syntax.blocks import Span

# bad programs that trip the shared checks: syntax, block structure, technology, limits, end of program
BAD = {
    "traub-tx8d": [
        ("G1 X1,2.3\nM30", "TX-E1002", 1),  # malformed number
        ("G1 Y5\nM30", "TX-E1003", 1),  # unknown address
        ("G4 X1 Z3\nM30", "TX-E1101", 1),  # word not allowed with G4
        ("G22 H2\nM30", "TX-E1102", 1),  # mandatory word missing
        ("G5 X1\nM30", "TX-E1105", 1),  # unknown G code
        ("M47\nM30", "TX-W1103", 1),  # unknown M function
        ("G96 V200 T0101 M4\nG0 X40 Z2\nG1 Z-5\nM30", "TX-E1301", 3),  # feed move without feed
        ("T0101\nF0.1\nG0 X40 Z2\nG1 Z-5\nM30", "TX-E1302", 4),  # spindle at rest
        ("G0 X40 Z2", "TX-W1102", 1),  # no M30
    ],
    "sinumerik-iso": [
        ("G01 X1.2.3\nM30", "ISO-E1002", 1),
        ("G01 X10 Y10 F0\nM30", "ISO-E1301", 1),
        ("G00 X10\n", "ISO-W1102", 1),
        ("M47\nM30", "ISO-W1103", 1),
    ],
    "beckhoff": [
        ("G01 X1,5\nM30", "BK-E1010", 1),  # decimal comma
        ("G01 X10 Y10 F0\nM30", "BK-E1301", 1),
        ("G00 X10\n", "BK-W1102", 1),
        ("M47\nM30", "BK-W1103", 1),
    ],
}


@pytest.mark.parametrize(
    ("dialect", "text", "code", "line"), [(d, t, c, n) for d, cases in BAD.items() for t, c, n in cases]
)
def test_a_shared_check_carries_the_dialects_prefix(dialect: str, text: str, code: str, line: int) -> None:
    diagnostics = run(text, dialect).diagnostics
    assert (code, line) in [(d.code, d.span.line) for d in diagnostics]
    assert not [d.code for d in diagnostics if d.code.startswith("PAL-")]
    (shown,) = [d for d in diagnostics if d.code == code]
    assert shown.to_json()["same_as"] == catalogue_code(code)
    assert CATALOGUE[catalogue_code(code)].de.split("{")[0] in shown.message  # the shared check's own text


def test_pal_keeps_its_codes_and_no_same_as() -> None:
    (d,) = run("G1 X10 F0\nM30").diagnostics[:1]
    assert d.code.startswith("PAL-")
    assert "same_as" not in d.to_json()


@pytest.mark.parametrize("dialect", sorted(set(DIALECTS) - {"pal-mill"}))
def test_parse_errors_and_shortened_answers_are_in_the_dialect_too(dialect: str) -> None:
    prefix = DIALECTS[dialect].code_prefix
    _, diagnostics = parse("G01 X1 §\n", dialect)
    assert [d.code for d in diagnostics] == [f"{prefix}-E1001"]
    text = "".join(f"G0 X{i % 7}\n" for i in range(12)) + "M30\n"
    limits = Limits(max_answer_commands=5)
    shortened = summarised(run(text, dialect, RunSetup(limits=limits)))
    assert f"{prefix}-I1018" in [d.code for d in shortened.diagnostics]


def test_no_shown_code_collides_with_a_dialects_own_code() -> None:
    shared = [c for c in CATALOGUE if c.startswith("PAL-")]
    prefixes = {d.code_prefix for d in DIALECTS.values()} - {"PAL"}
    for prefix in prefixes:
        for code in shared:
            shown = in_dialect(diag(code, Span(1, 1, 1, 1), **_params(code)), prefix).code
            assert shown not in CATALOGUE, shown
            assert catalogue_code(shown) == code
            assert int(shown.split("-")[1][1:]) >= SHARED_OFFSET
    assert catalogue_code("TX-E301") == "TX-E301" and catalogue_code("PAL-E301") == "PAL-E301"
    assert catalogue_code("SIM-E001") == "SIM-E001" and catalogue_code("DIN-E203") == "DIN-E203"


def _params(code: str) -> dict[str, str]:
    """Any value for every {named} field of the code's texts."""

    entry = CATALOGUE[code]
    names = {n for text in (entry.de, entry.en) for _, n, _, _ in string.Formatter().parse(text) if n}
    return dict.fromkeys(names, "x")
