"""`paltrainer check|run|…`: the command-line shell around the pipeline.

Exit codes (a contract other tools rely on): 0 no errors, 1 the program has errors,
2 usage or I/O error.
"""

from __future__ import annotations

import argparse
import json
import re
import sys
from collections.abc import Sequence
from importlib.metadata import entry_points
from pathlib import Path

from core.diagnostics import Diagnostic, Severity, has_errors
from core.interpreter.state import RunSetup
from core.pipeline import DEFAULT_DIALECT, DIALECTS, diagnostics_json, run, toolpath_json
from core.tools import DEFAULT_TOOLS, Tool, ToolTable, turning_tool
from core.trace import trace_lines

EXIT_OK, EXIT_ERRORS, EXIT_USAGE = 0, 1, 2

_SEVERITY_DE = {Severity.ERROR: "Fehler", Severity.WARNING: "Warnung", Severity.INFO: "Hinweis"}


class UsageError(Exception):
    pass


def _tool_arg(text: str) -> Tool:
    """`N=D`: tool N is an end mill of diameter D mm."""
    try:
        number, diameter = text.split("=", 1)
        tool = Tool(int(number), "end_mill", float(diameter), f"Schaftfräser Ø{float(diameter):g}")
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"»{text}«: erwartet N=D, z. B. 1=25 (Werkzeug T1, Durchmesser 25 mm) / expected N=D"
        ) from None
    if tool.number < 1 or not 0 < tool.diameter <= 1000:
        raise argparse.ArgumentTypeError(
            f"»{text}«: Werkzeugnummer ≥ 1 und Durchmesser > 0 / tool ≥ 1, diameter > 0"
        )
    return tool


def _nose_arg(text: str) -> Tool:
    """`T=R:P`: turret station T has a cutting edge of nose radius R mm in quadrant P (DECISIONS §16)."""
    try:
        number, rest = text.split("=", 1)
        radius, quadrant = rest.split(":", 1)
        tool = turning_tool(int(number), float(radius), int(quadrant))
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"»{text}«: erwartet T=R:P, z. B. 3=0.4:3 (Werkzeug T3, Schneidenradius 0,4 mm, Quadrant 3) "
            "/ expected T=R:P"
        ) from None
    if not 1 <= tool.number <= 99 or not 0 <= tool.nose_radius <= 50 or not 1 <= tool.quadrant <= 4:
        raise argparse.ArgumentTypeError(f"»{text}«: T 1…99, R 0…50 mm, P 1…4 / T 1…99, R 0…50 mm, P 1…4")
    return tool


def _parser() -> argparse.ArgumentParser:
    common = argparse.ArgumentParser(add_help=False)
    common.add_argument("file", help="NC-Programm / NC program")
    common.add_argument(
        "--dialect",
        default=DEFAULT_DIALECT,
        choices=sorted(DIALECTS),
        help=f"Dialekt / dialect (Standard: {DEFAULT_DIALECT})",
    )
    common.add_argument(
        "--tool",
        action="append",
        type=_tool_arg,
        default=[],
        metavar="N=D",
        help="Werkzeug N ist ein Schaftfräser mit Durchmesser D mm (mehrfach möglich)",
    )
    defaults = ", ".join(
        f"{d.name}: {'überspringen' if d.skip_blocks else 'ausführen'}" for d in DIALECTS.values()
    )
    common.add_argument(
        "--skip-blocks",
        action=argparse.BooleanOptionalAction,
        default=None,
        help=(
            "Ausblendsätze (/) überspringen bzw. mit --no-skip-blocks ausführen; ohne Angabe "
            f"gilt der Standard des Dialekts ({defaults}) / skip or run blocks marked with /; "
            "default per dialect: PAL runs them, TRAUB skips them"
        ),
    )
    common.add_argument(
        "--nose",
        action="append",
        type=_nose_arg,
        default=[],
        metavar="T=R:P",
        help=(
            "Drehen (TRAUB): Werkzeug T hat den Schneidenradius R mm und die Schneidenlage "
            "(Quadrant) P 1…4, z. B. 3=0.4:3 (mehrfach möglich) / turning: nose radius and "
            "quadrant of tool T"
        ),
    )
    common.add_argument(
        "--lib",
        metavar="DIR",
        help=(
            "Unterprogramm-Bibliothek: L<n>.nc (PAL) bzw. O<n>.nc (TRAUB) in DIR ist "
            "Unterprogramm L<n> bzw. O<n> / subprogram library"
        ),
    )
    common.add_argument("--json", action="store_true", help="Ausgabe als JSON / output as JSON")
    common.add_argument("--lang", choices=("de", "en"), default="de", help="Sprache der Meldungen / language")

    parser = argparse.ArgumentParser(
        prog="paltrainer", description="PAL Trainer – PAL-Programme prüfen und ausführen"
    )
    sub = parser.add_subparsers(dest="command", required=True)
    sub.add_parser("check", parents=[common], help="Programm prüfen: alle Fehler mit Zeile und Spalte")
    sub.add_parser("run", parents=[common], help="Programm ausführen: die Werkzeugbahn")
    # Further commands (simulate, serve, admin …) come from the entry-point group "paltrainer.commands":
    # each entry is a function register(subparsers, common) that adds its parser and sets `handler`,
    # a function (args) -> exit code. So the shells around core plug in without core importing them.
    for entry in sorted(entry_points(group="paltrainer.commands"), key=lambda e: e.name):
        try:
            register = entry.load()
        except ImportError as err:  # a shell whose dependencies are missing must not take the others down
            print(f"paltrainer {entry.name}: nicht verfügbar / not available ({err})", file=sys.stderr)
            continue
        register(sub, common)
    return parser


def read_program(path: str) -> str:
    """The program text: UTF-8, else Windows-1252 (what German school PCs write)."""
    try:
        data = Path(path).read_bytes()
    except OSError as err:
        raise UsageError(
            f"Datei »{path}« kann nicht gelesen werden: {err.strerror} / cannot read file"
        ) from None
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError:
        return data.decode("cp1252", errors="replace")


def _format(path: str, d: Diagnostic, lang: str) -> str:
    s = d.span
    label = _SEVERITY_DE[d.severity] if lang == "de" else d.severity.value
    text = d.message if lang == "de" else d.message_en
    return f"{path}:{s.line}:{s.column}: {label} {d.code}: {text}"


def setup_from_args(args: argparse.Namespace, tools: ToolTable = DEFAULT_TOOLS) -> RunSetup:
    """The run set-up the common options describe (--tool, --skip-blocks, --lib)."""
    for tool in [*args.tool, *getattr(args, "nose", [])]:
        tools = tools.with_tool(tool)
    dialect = DIALECTS.get(getattr(args, "dialect", DEFAULT_DIALECT)) or DIALECTS[DEFAULT_DIALECT]
    return RunSetup(
        tools=tools, skip_blocks=args.skip_blocks, subprograms=read_library(args.lib, dialect.library_prefix)
    )


def read_library(folder: str | None, prefix: str = "L") -> tuple[tuple[int, str], ...]:
    """The subprograms of a library folder: file L<n>.nc (any case) is subprogram L<n> (TRAUB: O<n>.nc)."""
    if folder is None:
        return ()
    path = Path(folder)
    if not path.is_dir():
        raise UsageError(f"Bibliothek »{folder}« ist kein Ordner / library is not a folder")
    found = []
    for f in sorted(path.iterdir()):
        m = re.fullmatch(re.escape(prefix) + r"(\d+)\.nc", f.name, flags=re.IGNORECASE)
        if m is not None and f.is_file():
            found.append((int(m.group(1)), read_program(str(f))))
    return tuple(found)


def main(argv: Sequence[str] | None = None) -> int:
    try:
        args = _parser().parse_args(argv)
    except SystemExit as exc:  # argparse: --help exits 0, usage errors exit 2
        return int(exc.code) if isinstance(exc.code, int) else EXIT_USAGE
    handler = getattr(args, "handler", None)
    if handler is not None:
        try:
            return int(handler(args))
        except UsageError as err:
            print(err, file=sys.stderr)
            return EXIT_USAGE
    try:
        text = read_program(args.file)
        setup = setup_from_args(args)
    except UsageError as err:
        print(err, file=sys.stderr)
        return EXIT_USAGE
    toolpath = run(text, args.dialect, setup)
    diagnostics = toolpath.diagnostics
    if args.command == "check":
        if args.json:
            print(json.dumps(diagnostics_json(diagnostics), ensure_ascii=False, indent=1))
        else:
            for d in diagnostics:
                print(_format(args.file, d, args.lang))
            errors = sum(d.severity is Severity.ERROR for d in diagnostics)
            print(
                f"{errors} Fehler, {len(diagnostics) - errors} weitere Meldungen"
                if args.lang == "de"
                else f"{errors} errors, {len(diagnostics) - errors} other diagnostics",
                file=sys.stderr,
            )
    else:
        if args.json:
            print(json.dumps(toolpath_json(toolpath), ensure_ascii=False))
        else:
            for line in trace_lines(toolpath, DIALECTS[args.dialect].lathe):
                print(line)
            for d in diagnostics:
                print(_format(args.file, d, args.lang), file=sys.stderr)
    return EXIT_ERRORS if has_errors(diagnostics) else EXIT_OK


if __name__ == "__main__":
    sys.exit(main())
