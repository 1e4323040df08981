"""`paltrainer sheet`: exercises as a printed task sheet (PDF) with the empty programming form.

Exit codes: 0 written, 2 usage or I/O error (unknown exercise, unwritable file, no PDF engine here).
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from core.cli import EXIT_OK, UsageError
from core.grading.cli import exercise_named
from core.sheet import SheetUnavailable, task_sheet_pdf


def register(subparsers: Any, common: argparse.ArgumentParser) -> None:
    p = subparsers.add_parser(
        "sheet",
        help="Aufgabenblatt mit Zeichnung und Programmierblatt als PDF / "
        "task sheet with drawing and programming form as PDF",
    )
    p.add_argument(
        "exercise",
        nargs="+",
        help="Aufgaben-ID oder Aufgabendatei (YAML), auch mehrere / exercise ids or files",
    )
    p.add_argument("--out", required=True, help="PDF-Datei / PDF file")
    p.add_argument("--lang", choices=("de", "en"), default="de", help="Sprache / language")
    p.set_defaults(handler=_sheet)


def _sheet(args: argparse.Namespace) -> int:
    exercises = [exercise_named(name) for name in args.exercise]
    try:
        pdf = task_sheet_pdf(exercises, args.lang)
    except SheetUnavailable as err:
        raise UsageError(str(err)) from None
    try:
        Path(args.out).write_bytes(pdf)
    except OSError as err:
        message = f"»{args.out}« kann nicht geschrieben werden: {err.strerror} / cannot write"
        raise UsageError(message) from None
    return EXIT_OK
