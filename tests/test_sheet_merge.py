"""Task sheets made one exercise at a time and put together (core.sheet.merge_pdfs): the server renders and caches
each exercise's pages on their own and hands out an assignment's sheets as one file."""

from __future__ import annotations

import io

import pytest
from test_sheet import exercise, needs_pdf, pages_text

import core.sheet
from core.sheet import SheetUnavailable, merge_pdfs, task_sheet_pdf


@needs_pdf
def test_merged_sheets_keep_each_exercise_with_its_own_pages() -> None:
    from pypdf import PdfReader

    fix, slots = exercise("fehler-02-spindel"), exercise("pal-09-g23-l-nuten")
    parts = [task_sheet_pdf([fix], "de"), task_sheet_pdf([slots], "de")]
    merged = merge_pdfs(parts)
    assert merged.startswith(b"%PDF-")
    pages = pages_text(merged)
    assert len(pages) == sum(len(PdfReader(io.BytesIO(p)).pages) for p in parts) == 4
    assert "Fehlersuche – Technologie" in pages[0] and "Ausgangsprogramm" in pages[0]
    assert slots.title.de in pages[2] and "Programmierblatt 1 von 1" in pages[3]
    # each exercise's pages are counted and named on their own: a sheet handed out alone reads right
    assert "Seite 2 von 2" in pages[1] and f"Aufgabe {fix.id}" in pages[1]
    assert "Seite 2 von 2" in pages[3] and f"Aufgabe {slots.id}" in pages[3]


def test_one_part_is_returned_as_it_is_and_none_is_an_error() -> None:
    assert merge_pdfs([b"%PDF-1.7 one"]) == b"%PDF-1.7 one"
    with pytest.raises(ValueError):
        merge_pdfs([])


def test_without_pypdf_it_says_what_is_missing(monkeypatch: pytest.MonkeyPatch) -> None:
    import builtins

    real_import = builtins.__import__

    def no_pypdf(name: str, *args: object, **kwargs: object) -> object:
        if name == "pypdf":
            raise ImportError("No module named 'pypdf'")
        return real_import(name, *args, **kwargs)  # type: ignore[arg-type]

    monkeypatch.setattr(builtins, "__import__", no_pypdf)
    with pytest.raises(SheetUnavailable) as err:
        core.sheet.merge_pdfs([b"%PDF-a", b"%PDF-b"])
    assert "pypdf" in err.value.message and "pypdf" in err.value.message_en
