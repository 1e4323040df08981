"""The pipeline's front door: the dialects, and text → diagnostics / toolpath in one call.

The CLI and the server call these functions; they hold no logic of their own.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field
from functools import partial
from typing import Any

from core.diagnostics import Diagnostic
from core.dialects.beckhoff import TABLE as BECKHOFF_TABLE
from core.dialects.beckhoff import VALUED_CODES as BECKHOFF_VALUED
from core.dialects.codes import CodeTable
from core.dialects.pal_mill import TABLE as PAL_MILL_TABLE
from core.dialects.sinumerik_iso import TABLE as ISO_TABLE
from core.interpreter import BlockExecutor, Toolpath, interpret
from core.interpreter.pal_mill import execute_block as pal_mill_block
from core.interpreter.state import RunSetup
from core.syntax.blocks import Block, Program
from core.syntax.parser import parser_for


@dataclass(frozen=True)
class Dialect:
    name: str
    title_de: str
    title_en: str
    grammar: str  # core/syntax/<grammar>.lark
    table: CodeTable
    execute: BlockExecutor
    valued_codes: frozenset[str] = frozenset()  # codes the grammar takes with a value (G301=20)


DIALECTS: dict[str, Dialect] = {
    "pal-mill": Dialect("pal-mill", "PAL Fräsen", "PAL milling", "pal_mill", PAL_MILL_TABLE, pal_mill_block),
    # ISO words are PAL's words without the PAL-only addresses: the same grammar, another table
    "sinumerik-iso": Dialect("sinumerik-iso", "SINUMERIK 808D ISO Fräsen", "SINUMERIK 808D ISO milling",
                             "pal_mill", ISO_TABLE, partial(pal_mill_block, table=ISO_TABLE)),
    "beckhoff": Dialect("beckhoff", "Beckhoff TwinCAT CNC", "Beckhoff TwinCAT CNC", "beckhoff", BECKHOFF_TABLE,
                        partial(pal_mill_block, table=BECKHOFF_TABLE), BECKHOFF_VALUED),
}
DEFAULT_DIALECT = "pal-mill"


def parse(text: str, dialect: str = DEFAULT_DIALECT, setup: RunSetup | None = None) -> tuple[Program, list[Diagnostic]]:
    setup = setup or RunSetup()
    d = DIALECTS[dialect]
    return parser_for(d.grammar, d.valued_codes).parse_program(text, setup.limits)


@dataclass
class Memo:
    """What one run keeps for the next run of the same document, changed in a few lines (the live editor):
    the parsed lines and the executor's reading of each block. Use one memo per document, dialect and set-up.
    """

    lines: dict[tuple[int, str], tuple[Block, list[Diagnostic]]] = field(default_factory=dict)
    readings: dict[Any, Any] = field(default_factory=dict)


def run(text: str, dialect: str = DEFAULT_DIALECT, setup: RunSetup | None = None, memo: Memo | None = None) -> Toolpath:
    """Parse and interpret `text`; the diagnostics of both stages are in the result, sorted by position."""
    setup = setup or RunSetup()
    d = DIALECTS[dialect]
    parser = parser_for(d.grammar, d.valued_codes)
    program, diagnostics = parser.parse_program(text, setup.limits, memo.lines if memo is not None else None)
    library = {}
    for number, sub_text in setup.subprograms:
        sub, sub_diagnostics = parser.parse_program(sub_text, setup.limits)
        library[number] = sub
        diagnostics += [dataclasses.replace(x, source=f"L{number}") for x in sub_diagnostics]
    toolpath = interpret(program, d.table, d.execute, setup, diagnostics, library,
                         memo.readings if memo is not None else None)
    toolpath.diagnostics.sort(key=lambda x: (x.span.line, x.span.column))
    return toolpath


def check(text: str, dialect: str = DEFAULT_DIALECT, setup: RunSetup | None = None) -> list[Diagnostic]:
    return run(text, dialect, setup).diagnostics


def diagnostics_json(diagnostics: list[Diagnostic]) -> dict[str, Any]:
    return {"diagnostics": [x.to_json() for x in diagnostics]}


def toolpath_json(toolpath: Toolpath) -> dict[str, Any]:
    """The shape of `paltrainer run --json` and of POST /api/v1/run."""
    p = toolpath.final_position
    return {
        "moves": [m.to_json() for m in toolpath.moves],
        "dwells": [x.to_json() for x in toolpath.dwells],
        "tool_changes": [x.to_json() for x in toolpath.tool_changes],
        "diagnostics": [x.to_json() for x in toolpath.diagnostics],
        "final": {"position": [round(p[0], 6), round(p[1], 6), round(p[2], 6)]},
    }
