"""The milling interpreter reads a plain move (G0–G3 with end point, centre, R, F, S, RN) on a fast path: it must
read every block exactly as the general path does, or leave the block to it (core/interpreter/pal_mill.py)."""

from __future__ import annotations

from pathlib import Path

import pytest

from core.diagnostics import Diagnostic
from core.interpreter import pal_mill, traub_turn
from core.interpreter.state import RunSetup
from core.pipeline import DIALECTS

ROOT = Path(__file__).parents[1]
FOLDERS = {
    "pal-mill": (
        "tests/seeds",
        "exercises/pal-mill",
        "exercises/pal-mill-fehler",
        "exercises/pal-mill-ergaenzen",
    ),
    "sinumerik-iso": ("exercises/sinumerik-iso", "tests/programs/iso"),
    "beckhoff": ("tests/seeds/beckhoff", "exercises/beckhoff", "tests/programs/beckhoff"),
}
# plain moves and their near misses: a word twice, a centre word of another plane, a negative feed, a word the
# code does not take, an expression, a modal move, technology alone, two G codes, a code that is not a move
LINES = [
    "G0 X10 Y20 Z5",
    "G1 X10 Y-20 F150",
    "G1 X10 X20",
    "G1 F-5 X1",
    "G1 S-100 X1",
    "G0 X1 RN2",
    "G1 X10 RN-2 F100",
    "G2 X10 Y0 I5 J0",
    "G3 X10 Y0 R5 F80",
    "G2 X10 Y0 K5",
    "G2 Z10 X0 K5 I0",
    "G2 X10 Y0 I5 J0 R5",
    "G2 I5 J0",
    "G1 X=P1 Y2",
    "X10 Y10",
    "Z-3",
    "I5 J5",
    "F200",
    "S1200 F150",
    "G1 G1 X1",
    "G17 G2 X10 Y0 I5 J0",
    "G1 G9 X5",
    "G4 U2",
    "G1 XI5 Y5",
    "G01 X.5 Y-0.25",
]
SETUP = RunSetup()


def blocks_of(dialect: str) -> list[pal_mill.Block]:
    parser = DIALECTS[dialect].parser()
    texts = ["\n".join(LINES)]
    for folder in FOLDERS[dialect]:
        texts += [p.read_text(encoding="utf-8") for p in sorted((ROOT / folder).glob("*.nc"))]
    return [
        b
        for text in texts
        for b in parser.parse_program(text, SETUP.limits)[0].blocks
        if b.ok and b.words and b.header is None
    ]


@pytest.mark.parametrize("dialect", sorted(FOLDERS))
def test_the_fast_path_reads_blocks_as_the_general_path_does(dialect: str) -> None:
    table = DIALECTS[dialect].table
    motions = [m for m in ("G0", "G1", "G2", "G3", "G11") if m in table.codes]
    planes = [p for p in ("G17", "G18") if p in table.codes]
    cycles = [None, "G80", "G81"] if "G81" in table.codes else [None]
    fast = 0
    for block in blocks_of(dialect):
        for motion in motions:
            for plane in planes:
                for cycle in cycles:
                    params = {1: 2.5}
                    plain = pal_mill._plain_reading(block, table, SETUP, motion, plane, cycle)
                    if plain is None:
                        continue
                    fast += 1
                    words = pal_mill._sort_words(block, table, SETUP, params)
                    general = pal_mill._checked(block, table, SETUP, words, motion, plane, cycle)
                    assert plain == general, (block.text, motion, plane, cycle)
    assert fast > 100  # most moves take the fast path


def test_blocks_that_break_a_rule_take_the_general_path() -> None:
    table = DIALECTS["pal-mill"].table
    parser = DIALECTS["pal-mill"].parser()
    taken = {}
    for line in LINES:
        block = parser.parse_program(line, SETUP.limits)[0].blocks[0]
        taken[line] = pal_mill._plain_reading(block, table, SETUP, "G1", "G17", None) is not None
    assert [line for line, fast in taken.items() if fast] == [
        "G0 X10 Y20 Z5",
        "G1 X10 Y-20 F150",
        "G1 X10 RN-2 F100",
        "G2 X10 Y0 I5 J0",
        "G3 X10 Y0 R5 F80",
        "G2 X10 Y0 I5 J0 R5",
        "G2 I5 J0",
        "X10 Y10",
        "Z-3",
        "G01 X.5 Y-0.25",
    ]


TURNING_LINES = [
    "G0 X79 Z2",
    "G1 Z-20.5 F0.3",
    "G1 W-0,5 F0,3",
    "G0 U1",
    "G2 X40 Z-20 R5",
    "G1 X40 D-2 E0,1",
    "X40 Z-3",
    "F0,2",
    "G1 F-0,2 X4",
    "G1 X4 X5",
    "G1 X4 Q5",
    "G0 X4 T0303",
    "G0 X4 M8",
    "G96 V200 X40",
    "G1 G0 X4",
    "G71 P10 Q20 I0,5 K0,1 D2 F0,3",
    "G1 X L2",
    "G1 X4 H1,5",
    "G4 X0,5",
]


def test_the_turning_fast_path_reads_blocks_as_the_general_path_does() -> None:
    """TRAUB's plain moves (core/interpreter/traub_turn.py, _plain_read): the same reading as _read, or none."""
    parser = DIALECTS["traub-tx8d"].parser()
    texts = ["\n".join(TURNING_LINES)]
    for folder in ("exercises/traub-tx8d", "tests/seeds/traub"):
        texts += [p.read_text(encoding="utf-8") for p in sorted((ROOT / folder).glob("*.nc"))]
    blocks = [
        b
        for text in texts
        for b in parser.parse_program(text, SETUP.limits)[0].blocks
        if b.ok and b.words and b.header is None
    ]
    fast = 0
    for block in blocks:
        for motion in ("G0", "G1", "G2", "G9"):
            plain = traub_turn._plain_read(block, SETUP.limits.max_abs_value, motion)
            if plain is None:
                continue
            fast += 1
            found: list[Diagnostic] = []
            general = traub_turn._read(block, {}, found, None, SETUP.limits.max_abs_value, motion)
            assert plain == general and found == [], (block.text, motion)
    assert fast > 100  # most moves take the fast path
    # of the lines above, the first eight are plain moves; the others each break one of its rules
    lines = parser.parse_program("\n".join(TURNING_LINES), SETUP.limits)[0].blocks
    assert len(lines) == len(TURNING_LINES)
    taken = [
        line
        for line, b in zip(TURNING_LINES, lines, strict=True)
        if b.ok and b.words and traub_turn._plain_read(b, 1e5, "G1")
    ]
    assert taken == TURNING_LINES[:8]
