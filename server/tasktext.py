"""The words of an exercise as its page shows them: the task as safe HTML, the blank and the workpiece zero.

The same functions make the printed task sheet (core/sheet/tasktext.py), so that the page and the PDF say the
same. The task's Markdown comes from authors (and through the API from anyone allowed to write exercises): it is
rendered with raw HTML off and https links only, never inserted as it is.
"""

from __future__ import annotations

from typing import Any

from core.sheet.tasktext import blank_text, states_blank, task_html, zero_text
from server.models import Exercise


def task_view(exercise: Exercise) -> dict[str, Any]:
    """The fields of ExerciseOut made from the task text and the blank (German and English)."""
    document = exercise.document or {}
    blank = document.get("blank") if isinstance(document.get("blank"), dict) else None
    stock = document.get("stock") if isinstance(document.get("stock"), dict) else exercise.stock
    task = {"de": exercise.task_de or "", "en": exercise.task_en or exercise.task_de or ""}
    out: dict[str, Any] = {}
    for lang in ("de", "en"):
        out[f"task_html_{lang}"] = task_html(task[lang])
        out[f"blank_{lang}"] = blank_text(stock, blank, lang)
        out[f"zero_{lang}"] = zero_text(stock, blank, lang) if stock or blank else ""
        out[f"blank_in_task_{lang}"] = states_blank(task[lang], stock, blank)
    return out
