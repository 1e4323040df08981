"""The built-in exercises: every exercises/**/*.yaml file (the format of core.exercises, docs/exercises.md)
is loaded on start and kept in the database. A file that does not validate is skipped with a log line.
Also: the exercise document the grader needs, built from the fields of an exercise made through the API.
"""

from __future__ import annotations

import logging
from pathlib import Path
from typing import Any

from pydantic import ValidationError
from sqlalchemy.orm import Session

from core.exercises import Exercise as ExerciseDocument
from core.exercises import ExerciseError, load_exercise
from server import repository as repo

log = logging.getLogger("paltrainer.server")


def exercise_fields(doc: ExerciseDocument) -> dict[str, Any]:
    """The database fields of one exercise document; hidden criteria are kept apart from the rubric."""
    data = doc.model_dump(mode="json")
    return {
        "slug": doc.id,
        "title_de": doc.title.de[:200],
        "title_en": doc.title.en[:200],
        "task_de": doc.task.de,
        "task_en": doc.task.en,
        "dialect": doc.dialect,
        "stock": {"min": data["stock"]["min"], "max": data["stock"]["max"]},
        "tools": data["tools"],
        "reference_program": doc.reference,
        "rubric": {"criteria": [c for c in data["rubric"] if not c["hidden"]]},
        "hidden_criteria": {"criteria": [c for c in data["rubric"] if c["hidden"]]},
        "document": data,
    }


def document_from_fields(fields: dict[str, Any], base: dict[str, Any] | None = None) -> dict[str, Any] | None:
    """The grader's exercise document for an exercise made or changed through the API (on top of its
    previous document `base`, whose other parts stay), or None if it is incomplete (no stock, no
    reference program, a rubric that does not add up to 100 …)."""
    data: dict[str, Any] = {
        **(base or {}),
        "id": fields["slug"],
        "title": {"de": fields["title_de"], "en": fields.get("title_en") or ""},
        "task": {"de": fields.get("task_de") or "", "en": fields.get("task_en") or ""},
        "dialect": fields.get("dialect"),
        "stock": fields.get("stock"),
        "tools": fields.get("tools") or [],
        "reference": fields.get("reference_program") or "",
        "source": (base or {}).get("source") or "api",
    }
    rubric = fields.get("rubric") or {}
    hidden = fields.get("hidden_criteria") or {}
    criteria = [
        *(rubric.get("criteria") or []),
        *({**c, "hidden": True} for c in hidden.get("criteria") or []),
    ]
    if criteria:
        data["rubric"] = criteria
    else:
        data.pop("rubric", None)
    if not data["reference"].strip() or data["stock"] is None:
        return None
    try:
        return ExerciseDocument.model_validate(data).model_dump(mode="json")
    except (ValidationError, ValueError, TypeError):
        return None


def load_exercises(db: Session, folder: Path) -> int:
    """Insert or update the built-in exercises found under `folder`; exercises made by users stay as they are."""
    count = 0
    if not folder.is_dir():
        return 0
    for path in sorted(folder.rglob("*.yaml")):
        try:
            fields = exercise_fields(load_exercise(path))
        except (OSError, ExerciseError, ValueError) as err:
            log.warning("exercise file skipped", extra={"job": f"{path.name}: {type(err).__name__}"})
            continue
        existing = repo.exercise_by_slug(db, fields["slug"])
        if existing is None:
            repo.create_exercise(db, fields, owner_id=None, builtin=True)
        elif existing.builtin:
            repo.update_exercise(db, existing, fields)
        else:
            continue
        count += 1
    return count
