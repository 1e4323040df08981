"""Every built-in exercise's task sheet reads like a PAL exam paper: no raw Markdown, no "null", "undefined", "NaN",
"None" or template braces in what is printed, the blank named once (the HTML the PDF is made from, so that this runs
without Pango; tests/test_sheet.py reads real PDFs)."""

from __future__ import annotations

import html
import io
import re

import pytest

from core.exercises import Exercise, builtin_exercises
from core.sheet import SheetUnavailable, pdf_engine, task_sheet_html, task_sheet_pdf

EXERCISES = list(builtin_exercises().values())
PLACEHOLDER = re.compile(r"\b(null|undefined|NaN|None)\b|\{|\}")


def printed_text(page: str) -> str:
    """The words a reader sees: without style, the inlined drawing (a data: URI) and the tags."""
    page = re.sub(r"<style.*?</style>", " ", page, flags=re.DOTALL)
    page = re.sub(r'src="data:[^"]*"', " ", page)
    page = re.sub(r"<[^>]+>", " ", page)
    return html.unescape(page)


@pytest.mark.parametrize("exercise", EXERCISES, ids=[e.id for e in EXERCISES])
@pytest.mark.parametrize("lang", ["de", "en"])
def test_the_sheet_has_no_raw_markdown_and_no_placeholder(exercise: Exercise, lang: str) -> None:
    text = printed_text(task_sheet_html([exercise], lang))
    assert "**" not in text and "`" not in text, "raw Markdown on the sheet"
    assert not re.search(r"^\s*- \S", text, flags=re.MULTILINE), "a Markdown list printed as text"
    found = PLACEHOLDER.search(text)
    assert found is None, (
        f"»{found.group(0)}« printed: …{text[max(0, found.start() - 60) : found.end() + 60]}…"
    )


def test_there_are_turning_and_milling_exercises_among_them() -> None:
    assert {e.dialect for e in EXERCISES} >= {"pal-mill", "traub-tx8d"} and len(EXERCISES) >= 30


def test_the_printed_pdf_of_every_exercise_has_no_placeholder_and_no_markdown() -> None:
    # the PDF itself (WeasyPrint), all built-in exercises in one document as an instructor prints them
    try:
        pdf_engine()
    except SheetUnavailable:
        pytest.skip("WeasyPrint or Pango missing (bash .ci/run installs them)")
    from pypdf import PdfReader

    reader = PdfReader(io.BytesIO(task_sheet_pdf(EXERCISES, "de")))
    text = "\n".join(page.extract_text() for page in reader.pages)
    assert len(reader.pages) >= 2 * len(EXERCISES)  # a task page and a program form each
    assert "**" not in text
    found = PLACEHOLDER.search(text)
    assert found is None, (
        f"»{found.group(0)}« printed: …{text[max(0, found.start() - 60) : found.end() + 60]}…"
    )
    for e in EXERCISES:
        assert e.title.get("de").split(" – ")[0] in text
