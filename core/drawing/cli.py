"""`paltrainer drawing`: the dimensioned drawing of an exercise's part as SVG.

Exit codes: 0 written, 2 usage or I/O error (unknown exercise, unwritable file).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Any

from core.cli import EXIT_OK, UsageError
from core.drawing import part_drawing
from core.grading.cli import exercise_named


def register(subparsers: Any, common: argparse.ArgumentParser) -> None:
    p = subparsers.add_parser(
        "drawing", help="Bemaßte Zeichnung einer Aufgabe als SVG / dimensioned drawing of an exercise as SVG"
    )
    p.add_argument("exercise", help="Aufgaben-ID oder Aufgabendatei (YAML) / exercise id or file")
    p.add_argument("--out", help="SVG-Datei (ohne: Standardausgabe) / SVG file (default: standard output)")
    p.add_argument("--lang", choices=("de", "en"), default="de", help="Sprache / language")
    p.set_defaults(handler=_drawing)


def _drawing(args: argparse.Namespace) -> int:
    svg = part_drawing(exercise_named(args.exercise), args.lang)
    if not args.out:
        sys.stdout.write(svg)
        return EXIT_OK
    try:
        Path(args.out).write_text(svg, encoding="utf-8")
    except OSError as err:
        raise UsageError(
            f"»{args.out}« kann nicht geschrieben werden: {err.strerror} / cannot write"
        ) from None
    return EXIT_OK
