"""`paltrainer simulate`: the command-line shell around the stock simulation (the only module of
core/sim that reads or writes files). Registered through the entry-point group "paltrainer.commands".
"""

from __future__ import annotations

import argparse
import json
import math
import sys
from pathlib import Path
from typing import Any

from core.cli import EXIT_ERRORS, EXIT_OK, UsageError, read_program, setup_from_args
from core.diagnostics import Diagnostic, Severity, has_errors
from core.pipeline import DIALECTS, run
from core.sim.engine import DEFAULT_RESOLUTION, Stock, simulate
from core.sim.export import depth_png, stl_bytes, surface_mesh
from core.sim.lathe_export import half_section_png, revolved_mesh
from core.sim.lathe_report import turning_json
from core.sim.report import simulation_json
from core.sim.tooltable import DEFAULT_SIM_TOOLS, ToolTableError, parse_tool_table
from core.sim.turning import DEFAULT_LATHE_TOOLS, DEFAULT_TURNING_RESOLUTION, Blank, simulate_turning
from core.tools import ToolTable

DEFAULT_BLANK = "bar:60,100"  # turning: a bar Ø60 × 100, the last 30 mm in the chuck
DEFAULT_STOCK = (
    "0,0,-30:80,70,0"  # the PAL examples' 80 × 70 × 30 block, origin at the top's lower left corner
)
_LABEL = {
    Severity.ERROR: ("Fehler", "error"),
    Severity.WARNING: ("Warnung", "warning"),
    Severity.INFO: ("Hinweis", "info"),
}


def _stock(text: str) -> Stock:
    try:
        a, b = text.split(":")
        p = [float(v) for v in a.split(",")]
        q = [float(v) for v in b.split(",")]
        if len(p) != 3 or len(q) != 3:
            raise ValueError
        return Stock(
            min(p[0], q[0]),
            min(p[1], q[1]),
            min(p[2], q[2]),
            max(p[0], q[0]),
            max(p[1], q[1]),
            max(p[2], q[2]),
        )
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"»{text}«: erwartet X0,Y0,Z0:X1,Y1,Z1 mit Länge, Breite und Höhe > 0, z. B. {DEFAULT_STOCK} "
            "/ expected two corners X0,Y0,Z0:X1,Y1,Z1"
        ) from None


def _blank(text: str) -> Blank:
    """`bar:D,L[,C[,J]]` or `tube:D,d,L[,C[,J]]`: diameter, bore, length, clamping length C and the jaws'
    outer diameter J in mm."""
    try:
        kind, rest = text.split(":", 1)
        values = [float(v) for v in rest.split(",")]
        if kind == "bar" and 2 <= len(values) <= 4:
            values.insert(1, 0.0)
        elif not (kind == "tube" and 3 <= len(values) <= 5):
            raise ValueError
        d, bore, length, *chuck = values
        return Blank(d, length, bore, chuck[0] if chuck else None, chuck[1] if len(chuck) == 2 else None)
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"»{text}«: erwartet bar:D,L[,C[,J]] oder tube:D,d,L[,C[,J]] (Durchmesser, Bohrung, Länge, Spannlänge, "
            f"Backendurchmesser in mm, Bohrung < Durchmesser < Backendurchmesser, Spannlänge < Länge), "
            f"z. B. {DEFAULT_BLANK} / expected bar:D,L[,C[,J]] or tube:D,d,L[,C[,J]]"
        ) from None


def _resolution(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not 0.005 <= value <= 10:
        raise argparse.ArgumentTypeError(f"»{text}«: Rasterweite 0.005 … 10 mm / cell size 0.005 … 10 mm")
    return value


def _expected(text: str) -> tuple[int, float]:
    try:
        number, diameter = text.split("=", 1)
        return int(number), float(diameter)
    except ValueError:
        raise argparse.ArgumentTypeError(f"»{text}«: erwartet N=D / expected N=D") from None


def register(subparsers: Any, common: argparse.ArgumentParser) -> None:
    """Add `simulate` to the `paltrainer` command line."""
    p = subparsers.add_parser(
        "simulate",
        parents=[common],
        help="Zerspanung simulieren: Rohteil, Kollisionen, Laufzeit / simulate the machining",
    )
    p.add_argument(
        "--stock",
        type=_stock,
        default=_stock(DEFAULT_STOCK),
        metavar="X0,Y0,Z0:X1,Y1,Z1",
        help=f"Rohteil als zwei Ecken in Werkstückkoordinaten (Standard {DEFAULT_STOCK})",
    )
    p.add_argument(
        "--blank",
        type=_blank,
        default=None,
        metavar="bar:D,L[,C[,J]]|tube:D,d,L[,C[,J]]",
        help=(
            f"Drehen: Rohteil Stange oder Rohr mit Spannlänge C im Futter und Backendurchmesser J "
            f"(Standard {DEFAULT_BLANK}) / turning: the bar or tube, its clamping length and the jaws' "
            "diameter"
        ),
    )
    p.add_argument("--tools", metavar="YAML", help="Werkzeugtabelle (YAML, docs/tools.md) / tool table")
    p.add_argument(
        "--resolution",
        type=_resolution,
        default=None,
        metavar="MM",
        help=(
            f"Rasterweite in mm (Standard {DEFAULT_RESOLUTION}; Drehen: Abstand in Z, Standard "
            f"{DEFAULT_TURNING_RESOLUTION}) / cell size"
        ),
    )
    p.add_argument(
        "--expect-tool",
        type=_expected,
        action="append",
        default=[],
        metavar="N=D",
        help="die Aufgabe sieht für TN den Durchmesser D vor / the exercise expects TN of diameter D",
    )
    p.add_argument(
        "--stl", metavar="FILE", help="Rohteil als binäre STL schreiben / write the stock as binary STL"
    )
    p.add_argument(
        "--png", metavar="FILE", help="Tiefenbild von oben schreiben / write a top-view depth image"
    )
    p.add_argument(
        "--max-triangles",
        type=int,
        default=500_000,
        metavar="N",
        help="höchstens N Dreiecke in der STL (Standard 500000)",
    )
    p.set_defaults(handler=handle)


def _write(path: str, data: bytes) -> None:
    try:
        Path(path).write_bytes(data)
    except OSError as err:
        raise UsageError(
            f"Datei »{path}« kann nicht geschrieben werden: {err.strerror} / cannot write file"
        ) from None


def _line(path: str, d: Diagnostic, lang: str, column: bool) -> str:
    label = _LABEL[d.severity][0 if lang == "de" else 1]
    where = f"{d.span.line}:{d.span.column}" if column else f"{d.span.line}"
    return f"{path}:{where}: {label} {d.code}: {d.message if lang == 'de' else d.message_en}"


def handle(args: argparse.Namespace) -> int:
    tools = DEFAULT_SIM_TOOLS
    if args.tools:
        try:
            tools = parse_tool_table(Path(args.tools).read_text(encoding="utf-8"))
        except OSError as err:
            raise UsageError(
                f"Datei »{args.tools}« kann nicht gelesen werden: {err.strerror} / cannot read file"
            ) from None
        except ToolTableError as err:
            raise UsageError(str(err)) from None
    if args.max_triangles < 12:
        raise UsageError("--max-triangles: mindestens 12 / at least 12")
    if DIALECTS[args.dialect].lathe:
        return _turn(args, tools if args.tools else DEFAULT_LATHE_TOOLS)
    setup = setup_from_args(args, tools)
    toolpath = run(read_program(args.file), args.dialect, setup)
    result = simulate(
        toolpath,
        args.stock,
        setup.tools,
        args.resolution or DEFAULT_RESOLUTION,
        expected_diameters=dict(args.expect_tool),
    )
    if args.stl:
        _write(args.stl, stl_bytes(*surface_mesh(result.heightmap, args.max_triangles)))
    if args.png:
        _write(args.png, depth_png(result.heightmap))
    if args.json:
        print(json.dumps(simulation_json(result), ensure_ascii=False))
    else:
        _summary(
            args,
            result.diagnostics,
            result.events,
            result.removed_volume,
            result.remaining_volume,
            result.cycle_time,
            result.resolution,
        )
    return EXIT_ERRORS if has_errors(result.diagnostics) or has_errors(result.events) else EXIT_OK


def _turn(args: argparse.Namespace, tools: ToolTable) -> int:
    """`simulate` for a lathe dialect: the blank as a revolved profile (core/sim/turning.py)."""
    setup = setup_from_args(args, tools)
    toolpath = run(read_program(args.file), args.dialect, setup)
    blank = args.blank or _blank(DEFAULT_BLANK)
    result = simulate_turning(toolpath, blank, setup.tools, args.resolution or DEFAULT_TURNING_RESOLUTION)
    if args.stl:
        _write(
            args.stl,
            stl_bytes(
                *revolved_mesh(result.profile, max_triangles=args.max_triangles),
                name="PAL Trainer turned part",
            ),
        )
    if args.png:
        _write(args.png, half_section_png(result.profile, blank))
    if args.json:
        print(json.dumps(turning_json(result), ensure_ascii=False))
    else:
        _summary(
            args,
            result.diagnostics,
            result.events,
            result.removed_volume,
            result.remaining_volume,
            result.cycle_time,
            result.resolution,
        )
    return EXIT_ERRORS if has_errors(result.diagnostics) or has_errors(result.events) else EXIT_OK


def _summary(
    args: argparse.Namespace,
    diagnostics: list[Diagnostic],
    events: list[Diagnostic],
    removed: float,
    remaining: float,
    total: float,
    resolution: float,
) -> None:
    de = args.lang == "de"
    for d in diagnostics:
        print(_line(args.file, d, args.lang, True), file=sys.stderr)
    for d in events:
        print(_line(args.file, d, args.lang, False))
    print(
        (
            "Abgetragen {:.1f} mm³, Rest {:.1f} mm³, Laufzeit {:d}:{:02d} min (Raster {:g} mm)"
            if de
            else "Removed {:.1f} mm³, remaining {:.1f} mm³, cycle time {:d}:{:02d} min (cells {:g} mm)"
        ).format(removed, remaining, int(total // 60), round(total % 60) % 60, resolution)
    )
