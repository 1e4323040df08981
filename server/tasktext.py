"""The words of an exercise as its page shows them: the task as safe HTML, the blank and the workpiece zero.

The same functions make the printed task sheet (core/sheet/tasktext.py), so that the page and the PDF say the
same. The task's Markdown comes from authors (and through the API from anyone allowed to write exercises): it is
rendered with raw HTML off and https links only, never inserted as it is. For a turning exercise also which of a
tool's feeds are the reduced feed E (what the reference writes as E), as the sheet prints them (core.sheet.tool_feeds):
worked out once per document, the reference run with the interpreter's work budget.
"""

from __future__ import annotations

import logging
from collections import OrderedDict
from typing import Any

from core.exercises import LATHE_DIALECTS
from core.exercises import Exercise as ExerciseDocument
from core.sheet import tool_feeds
from core.sheet.tasktext import blank_text, states_blank, task_html, zero_text
from server.models import Exercise
from server.workers import content_key

log = logging.getLogger("paltrainer.server")
_FEEDS: OrderedDict[str, dict[str, dict[str, Any]]] = OrderedDict()


def feeds_view(document: dict[str, Any] | None) -> dict[str, dict[str, Any]]:
    """A turning exercise's feeds per tool ("4": {"feed": [0.35], "reduced": [0.12], "spindle": "M4"}); {} for
    milling, without a document or when its reference does not run."""
    if not document or document.get("dialect") not in LATHE_DIALECTS or not document.get("cutting_data"):
        return {}
    key = content_key("feeds", document)
    feeds = _FEEDS.get(key)  # (requests in several threads: read once, never after another one's eviction)
    if feeds is None:
        try:
            feeds = {
                str(tool): entry
                for tool, entry in tool_feeds(ExerciseDocument.model_validate(document)).items()
            }
        except Exception:  # a defect in one document's run: its page shows the feeds without E
            log.warning("feeds of a turning exercise not worked out", exc_info=True)
            feeds = {}
        _FEEDS[key] = feeds
        while len(_FEEDS) > 256:
            try:
                _FEEDS.popitem(last=False)
            except KeyError:  # emptied by another thread meanwhile
                break
    return feeds


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
    out["tool_feeds"] = feeds_view(exercise.document)
    return out
