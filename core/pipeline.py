"""The pipeline's front door: the dialects, and text → diagnostics / toolpath in one call.

The CLI and the server call these functions; they hold no logic of their own.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from dataclasses import dataclass, field
from functools import partial
from typing import Any

from core.diagnostics import Diagnostic, diag, in_dialect
from core.dialects.beckhoff import TABLE as BECKHOFF_TABLE
from core.dialects.beckhoff import VALUED_CODES as BECKHOFF_VALUED
from core.dialects.codes import CodeTable
from core.dialects.pal_mill import TABLE as PAL_MILL_TABLE
from core.dialects.sinumerik_iso import TABLE as ISO_TABLE
from core.dialects.traub_tx8d import TABLE as TRAUB_TABLE
from core.interpreter.checkpoints import Keep
from core.interpreter.loop import Machine, run_loop
from core.interpreter.mill_machine import MillMachine
from core.interpreter.pal_mill import execute_block as pal_mill_block
from core.interpreter.state import RunSetup
from core.interpreter.traub_turn import TurnMachine
from core.syntax.blocks import Program
from core.syntax.parser import BlockParser, LineMemo, parser_for
from core.toolpath import Dwell, Move, ToolChange, Toolpath, Vec3


@dataclass(frozen=True)
class Dialect:
    name: str
    title_de: str
    title_en: str
    grammar: str  # core/syntax/<grammar>.lark
    table: CodeTable
    # the machine of a run (core/interpreter/loop.py), made for its set-up and the memo's readings of blocks
    machine: Callable[[RunSetup, dict[Any, Any] | None], Machine]
    valued_codes: frozenset[str] = frozenset()  # codes the grammar takes with a value (G301=20)
    skip_blocks: bool = False  # the default of the skip switch: True = "/" blocks are not executed
    library_prefix: str = "L"  # --lib DIR: the files <prefix><n>.nc are the programs of the library
    lathe: bool = False  # turning: X is shown as a diameter (the moves' x is the radius, DECISIONS §15)
    program_numbers: bool = False  # a leading O word starts a program (ISO: `O1000` … `M99`)
    code_prefix: str = "PAL"  # the prefix of its diagnostics; shared checks become e.g. TX-E1301 (in_dialect)

    def parser(self) -> BlockParser:
        return parser_for(self.grammar, self.valued_codes, self.program_numbers)


DIALECTS: dict[str, Dialect] = {
    "pal-mill": Dialect(
        "pal-mill",
        "PAL Fräsen",
        "PAL milling",
        "pal_mill",
        PAL_MILL_TABLE,
        partial(MillMachine, PAL_MILL_TABLE, pal_mill_block),
    ),
    "sinumerik-iso": Dialect(
        "sinumerik-iso",
        "SINUMERIK 808D ISO Fräsen",
        "SINUMERIK 808D ISO milling",
        "iso",
        ISO_TABLE,
        partial(MillMachine, ISO_TABLE, partial(pal_mill_block, table=ISO_TABLE)),
        library_prefix="O",
        program_numbers=True,
        code_prefix="ISO",
    ),
    "beckhoff": Dialect(
        "beckhoff",
        "Beckhoff TwinCAT CNC",
        "Beckhoff TwinCAT CNC",
        "beckhoff",
        BECKHOFF_TABLE,
        partial(MillMachine, BECKHOFF_TABLE, partial(pal_mill_block, table=BECKHOFF_TABLE)),
        BECKHOFF_VALUED,
        code_prefix="BK",
    ),
    "traub-tx8d": Dialect(
        "traub-tx8d",
        "TRAUB TX 8 D Drehen",
        "TRAUB TX 8 D turning",
        "traub",
        TRAUB_TABLE,
        TurnMachine,
        skip_blocks=True,
        library_prefix="O",
        lathe=True,
        code_prefix="TX",
    ),
}
DEFAULT_DIALECT = "pal-mill"


def parse(
    text: str, dialect: str = DEFAULT_DIALECT, setup: RunSetup | None = None
) -> tuple[Program, list[Diagnostic]]:
    setup = setup or RunSetup()
    d = DIALECTS[dialect]
    program, diagnostics = d.parser().parse_program(text, setup.limits)
    return program, [in_dialect(x, d.code_prefix) for x in diagnostics]


@dataclass
class Memo:
    """What one run keeps for the next run of the same document, changed in a few lines (the live editor):
    the parsed lines, the executor's reading of each block and the run's checkpoints, from which the next
    run restarts (core/interpreter/checkpoints.py). Use one memo per document, dialect and set-up.
    """

    lines: LineMemo = field(default_factory=LineMemo)
    readings: dict[Any, Any] = field(default_factory=dict)
    runs: Keep = field(default_factory=Keep)  # the last run's checkpoints (core/interpreter/checkpoints.py)


def run(
    text: str, dialect: str = DEFAULT_DIALECT, setup: RunSetup | None = None, memo: Memo | None = None
) -> Toolpath:
    """Parse and interpret `text`; the diagnostics of both stages are in the result, sorted by position."""
    setup = setup or RunSetup()
    d = DIALECTS[dialect]
    parser = d.parser()
    program, diagnostics = parser.parse_program(text, setup.limits, memo.lines if memo is not None else None)
    library = {}
    for number, sub_text in setup.subprograms:
        sub, sub_diagnostics = parser.parse_program(sub_text, setup.limits)
        library[number] = sub
        diagnostics += [dataclasses.replace(x, source=f"{d.library_prefix}{number}") for x in sub_diagnostics]
    if setup.skip_blocks is None and d.skip_blocks:
        setup = dataclasses.replace(setup, skip_blocks=True)
    machine = d.machine(setup, memo.readings if memo is not None else None)
    toolpath = run_loop(
        program, machine, setup, diagnostics, library, memo.runs if memo is not None else None
    )
    toolpath.diagnostics = sorted(
        (in_dialect(x, d.code_prefix) for x in toolpath.diagnostics),
        key=lambda x: (x.span.line, x.span.column),
    )
    toolpath.limits = setup.limits
    toolpath.code_prefix = d.code_prefix
    return toolpath


def check(text: str, dialect: str = DEFAULT_DIALECT, setup: RunSetup | None = None) -> list[Diagnostic]:
    return run(text, dialect, setup).diagnostics


def diagnostics_json(diagnostics: list[Diagnostic]) -> dict[str, Any]:
    return {"diagnostics": [x.to_json() for x in diagnostics]}


def summarised(toolpath: Toolpath) -> Toolpath:
    """The toolpath as an answer shows it (run, live update): its first `max_answer_commands` commands and,
    where more follow, a PAL-I018 at the first one left out. Simulation and grading take the whole toolpath."""
    limit = toolpath.limits.max_answer_commands
    commands = toolpath.commands
    if len(commands) <= limit:
        return toolpath
    kept = commands[:limit]
    notice = in_dialect(
        diag("PAL-I018", commands[limit].span, shown=limit, total=len(commands)), toolpath.code_prefix
    )
    return dataclasses.replace(
        toolpath,
        commands=kept,
        moves=[c for c in kept if type(c) is Move],
        dwells=[c for c in kept if type(c) is Dwell],
        tool_changes=[c for c in kept if type(c) is ToolChange],
        diagnostics=sorted([*toolpath.diagnostics, notice], key=lambda x: (x.span.line, x.span.column)),
    )


def drawing(toolpath: Toolpath, tolerance: float) -> tuple[list[list[Vec3]], Diagnostic | None]:
    """The moves as polylines for a picture (the 3D view), arcs as chords within `tolerance` mm: those of the
    first moves whose segments stay within `max_drawn_segments`, and a PAL-I019 at the first move left out.
    Each move's count is computed before its points are made, so a huge arc costs only what is drawn."""
    budget = toolpath.limits.max_drawn_segments
    lines: list[list[Vec3]] = []
    for m in toolpath.moves:
        n = m.chords(tolerance)
        if n > budget:
            return lines, in_dialect(
                diag("PAL-I019", m.span, limit=toolpath.limits.max_drawn_segments), toolpath.code_prefix
            )
        budget -= n
        lines.append(m.points(tolerance))
    return lines, None


def toolpath_json(toolpath: Toolpath) -> dict[str, Any]:
    """The shape of `paltrainer run --json` and of POST /api/v1/run: at most `max_answer_commands` commands
    (see `summarised`)."""
    toolpath = summarised(toolpath)
    p = toolpath.final_position
    return {
        "moves": [m.to_json() for m in toolpath.moves],
        "dwells": [x.to_json() for x in toolpath.dwells],
        "tool_changes": [x.to_json() for x in toolpath.tool_changes],
        "diagnostics": [x.to_json() for x in toolpath.diagnostics],
        "final": {"position": [round(p[0], 6), round(p[1], 6), round(p[2], 6)]},
    }
