"""Issue 12, part 3: a PAL cycle not supported yet gets one clear "not supported yet" under its name, no follow-ups
on its words. (The cycles G72–G87 and their calls run since issue 30: tests/test_pal_cycles*.py.)"""

from __future__ import annotations

import pytest

from core.dialects.pal_mill import CYCLES
from core.pipeline import run
from tests.conftest import codes

READY = "N10 T1 TC1 M6\nN20 S1000 F100 M3\nN30 G0 X0 Y0 Z10\n"

# typical parameter words of each cycle (PAL addresses the table does not know among them)
WORDS = {
    "G34": "",
    "G35": "ZA-5 D2 V2 W5 AK0.5 AL0.2",
    "G36": "ZA-5 D2 V2 W5 RN3",
    "G37": "ZA-5 D2 V2 W5 AK0.5 AL0.2",
    "G38": "",
    "G39": "ZA-5 V2 W5",
    "G72": "ZA-5 LP40 BP30 D2 V2 W5 AK0.5 AL0.2 EP1 DB80 RN5 H4 F120",
    "G73": "ZA-5 R15 D2 V2 W5 AK0.5 AL0.2 EP1 H4",
    "G74": "ZA-5 LP40 BP10 D2 V2 W5 AK0.5 AL0.2 EP1 H4",
    "G75": "ZA-5 BP10 RP30 AN0 AO90 D2 V2 W5 H4",
    "G76": "X10 Y10 AS0 D20 O4",
    "G77": "IA50 JA50 R20 AN0 AI45 O4",
    "G78": "IA50 JA50 RP20 AP30 Z0",
    "G79": "X10 Y10 Z0 AR0 W5",
    "G80": "",
    "G81": "ZA-10 V2 W5",
    "G82": "ZA-30 D5 V2 W5 DR1 DM2",
    "G83": "ZA-30 D5 V2 W5 DA3 U1 O2",
    "G84": "ZA-20 F1.5 M3 V2 W5",
    "G85": "ZA-20 V2 W5 E50",
    "G86": "ZA-20 V2 W5 DR0.2",
    "G87": "ZA-10 R12 D2 V2 W5",
    "G88": "ZA-10 DN10 D1.5 Q1 V2 W5",
    "G89": "ZA-10 DN10 D1.5 Q1 V2 W5",
}


NOT_YET = [
    code for code in sorted(WORDS) if code in ("G34", "G35", "G36", "G37", "G38", "G39", "G80", "G88", "G89")
]


def test_examiner_g88_with_its_words_gives_one_clear_message() -> None:
    tp = run(READY + "N40 G88 ZA-10 DN10 D1.5 Q1 V2 W5\nN50 M30\n")
    assert codes(tp) == [("PAL-E901", 4)]
    d = tp.diagnostics[0]
    assert d.message.startswith("Innengewindefräszyklus G88 wird noch nicht unterstützt")
    assert d.message_en.startswith("Internal thread milling cycle G88 is not supported yet")


def test_every_cycle_code_is_named() -> None:
    assert sorted(CYCLES) == sorted([f"G{n}" for n in range(34, 40)] + [f"G{n}" for n in range(72, 90)])


@pytest.mark.parametrize("code", NOT_YET)
def test_each_cycle_with_its_words_gives_exactly_one_diagnostic(code: str) -> None:
    tp = run(READY + f"N40 {code} {WORDS[code]}\nN50 M30\n")
    assert codes(tp) == [("PAL-E901", 4)]
    name = CYCLES[code][0]
    assert (
        tp.diagnostics[0].message
        == f"{name} {code} wird noch nicht unterstützt; der Satz wird nicht ausgeführt."
    )
    # the block is not executed: nothing moves after N30
    assert [m.line for m in tp.moves] == [3]


@pytest.mark.parametrize(
    "block", ["N40 G90 G88 ZA-10 V2 W5", "N40 G88 ZA-10 V2 W5 M8", "N40 G88 ZA=P7 V2 W5 XX3"]
)
def test_cycle_beside_other_words_still_one_diagnostic(block: str) -> None:
    assert codes(run(READY + block + "\nN50 M30\n")) == [("PAL-E901", 4)]


def test_cycle_under_compensation_and_in_a_loop_reports_once() -> None:
    text = READY + "N40 G88 ZA-10 V2 W5\nN50 G23 N40 N40 H3\nN60 M30\n"
    assert codes(run(text)) == [("PAL-E901", 4)]


def test_scaling_g67_with_a_word_gives_one_diagnostic() -> None:
    tp = run(READY + "N40 G67 SK2\nN50 M30\n")
    assert codes(tp) == [("PAL-E901", 4)]
    assert tp.diagnostics[0].message.startswith("Skalieren G67")


def test_unknown_g_code_gives_no_follow_ups_on_its_words() -> None:
    assert codes(run(READY + "N40 G99 X10 ZA-3 V2\nN50 M30\n")) == [("PAL-E105", 4)]


@pytest.mark.parametrize(
    "dialect,expected",
    [
        ("sinumerik-iso", []),  # the ISO drilling cycle runs (tests/test_iso_beckhoff_programs.py)
        (
            "beckhoff",
            [("BK-W1901", 4), ("BK-W1901", 5)],
        ),  # Beckhoff's G80–G89: implicit subprogram calls, not yet
    ],
)
def test_iso_dialects_drilling_cycle_one_diagnostic_per_block(
    dialect: str, expected: list[tuple[str, int]]
) -> None:
    # the shared executor: a code not modelled gives one diagnostic, and its R is not blamed on the modal G0
    tp = run("T1 M6\nS1000 F100 M3\nG0 X0 Y0 Z10\nG81 X10 Y10 Z-5 R2 F100\nG80\nM30\n", dialect)
    assert codes(tp) == expected
