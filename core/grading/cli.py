"""`paltrainer exercises` and `paltrainer grade`: the exercise list and the grader on the command line.

Exit codes of `grade`: 0 full marks, 1 points lost, 2 usage or I/O error (unknown exercise, unreadable
or invalid file).
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path
from typing import Any

from core.cli import EXIT_ERRORS, EXIT_OK, UsageError, read_program
from core.exercises import Exercise, ExerciseError, builtin_exercises, load_exercise
from core.grading import grade


def register_exercises(subparsers: Any, common: argparse.ArgumentParser) -> None:
    p = subparsers.add_parser("exercises", help="Die eingebauten Aufgaben / the built-in exercises")
    p.add_argument("--json", action="store_true", help="Ausgabe als JSON / output as JSON")
    p.set_defaults(handler=_list)


def register_grade(subparsers: Any, common: argparse.ArgumentParser) -> None:
    p = subparsers.add_parser("grade", help="Ein Programm gegen eine Aufgabe bewerten / grade a program")
    p.add_argument("exercise", help="Aufgaben-ID oder Aufgabendatei (YAML) / exercise id or file")
    p.add_argument("program", nargs="?", help="NC-Programm / NC program")
    p.add_argument(
        "--reference",
        action="store_true",
        help="die Musterlösung der Aufgabe bewerten / grade the exercise's own reference",
    )
    p.add_argument(
        "--view",
        choices=("instructor", "student"),
        default="instructor",
        help="student: verdeckte Kriterien weglassen / leave out hidden criteria",
    )
    p.add_argument("--json", action="store_true", help="Ausgabe als JSON / output as JSON")
    p.add_argument("--lang", choices=("de", "en"), default="de", help="Sprache / language")
    p.set_defaults(handler=_grade)


def _list(args: argparse.Namespace) -> int:
    exercises = _builtin()
    if args.json:
        print(
            json.dumps(
                {
                    "exercises": [
                        {
                            "id": e.id,
                            "title": e.title.de,
                            "title_en": e.title.en,
                            "dialect": e.dialect,
                            "kind": e.kind,
                        }
                        for e in exercises.values()
                    ]
                },
                ensure_ascii=False,
                indent=1,
            )
        )
    else:
        for e in exercises.values():
            print(f"{e.id:32s} {e.dialect:14s} {e.title.de}")
    return EXIT_OK


def _builtin() -> dict[str, Exercise]:
    try:
        return builtin_exercises()
    except ExerciseError as err:
        raise UsageError(str(err)) from None


def exercise_named(name: str) -> Exercise:
    """A built-in exercise by id, or an exercise file by path; UsageError otherwise."""
    path = Path(name)
    if path.suffix in (".yaml", ".yml") or path.is_file():
        try:
            return load_exercise(path)
        except OSError as err:
            raise UsageError(
                f"Aufgabe »{name}« kann nicht gelesen werden: {err.strerror} / cannot read"
            ) from None
        except ExerciseError as err:
            raise UsageError(str(err)) from None
    found = _builtin().get(name)
    if found is None:
        raise UsageError(f"Unbekannte Aufgabe »{name}« (paltrainer exercises listet sie) / unknown exercise")
    return found


def _grade(args: argparse.Namespace) -> int:
    exercise = exercise_named(args.exercise)
    if args.reference == (args.program is not None):
        raise UsageError("Entweder ein Programm oder --reference angeben / give a program or --reference")
    program = exercise.reference if args.reference else read_program(args.program)
    result = grade(exercise, program)
    if args.json:
        print(json.dumps(result.to_json(args.view), ensure_ascii=False, indent=1))
    else:
        print(f"{exercise.id}: {result.score} / {result.max_score}")
        for c in result.criteria:
            if args.view == "student" and c.hidden:
                continue
            mark = {"passed": "✓", "partial": "◐", "failed": "✗"}[c.status]
            text = c.message if args.lang == "de" else c.message_en
            print(f"  {mark} {c.id:17s} {c.points:3d}/{c.max_points:<3d} {text}")
    return EXIT_OK if result.score == result.max_score else EXIT_ERRORS
