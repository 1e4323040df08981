"""GET /api/v1/exercises/{slug}/sheet.pdf: the printed task sheet over HTTP; 503 where no PDF can be made."""

from __future__ import annotations

import io

import pytest
from server_helpers import Api, auth, error_code, unique

import core.sheet
from core.exercises import EXERCISES_DIR, load_exercise
from core.sheet import SheetUnavailable, pdf_engine
from server import repository as repo
from server.seed import exercise_fields


def _pdf_available() -> bool:
    try:
        pdf_engine()
    except SheetUnavailable:
        return False
    return True


def arch_exercise(api: Api) -> str:
    """PAL G41 outer contour (an arch R20 about X35 Y75) as a built-in exercise under a new slug."""
    doc = load_exercise(EXERCISES_DIR / "pal-mill" / "pal-13-g41-aussenkontur.yaml")
    doc = type(doc).model_validate({**doc.model_dump(), "id": unique("blatt-")})
    with api.app.state.db.session() as db:
        repo.create_exercise(db, exercise_fields(doc), owner_id=None, builtin=True)
    return doc.id


@pytest.mark.skipif(not _pdf_available(), reason="WeasyPrint or Pango missing (bash .ci/run installs them)")
def test_sheet_of_an_exercise(api: Api) -> None:
    from pypdf import PdfReader

    slug, student = arch_exercise(api), api.user()
    r = api.client.get(f"/api/v1/exercises/{slug}/sheet.pdf", headers=auth(student))
    assert r.status_code == 200, r.text
    assert r.headers["content-type"] == "application/pdf" and r.content.startswith(b"%PDF-")
    assert r.headers["content-disposition"] == f'inline; filename="{slug}-aufgabenblatt.pdf"'
    task, form = (page.extract_text() for page in PdfReader(io.BytesIO(r.content)).pages)
    assert "G41 – Außenkontur (Bogenform)" in task and "Draufsicht" in task
    assert {"R20", "35", "75"} <= set(task.split())
    assert "Programmierblatt" in form and "Bemerkung" in form
    en = api.client.get(f"/api/v1/exercises/{slug}/sheet.pdf?lang=en", headers=auth(student))
    assert en.status_code == 200 and "task-sheet.pdf" in en.headers["content-disposition"]
    assert "Remark" in PdfReader(io.BytesIO(en.content)).pages[1].extract_text()


def test_sheet_needs_an_account_and_an_exercise(api: Api) -> None:
    slug, student = arch_exercise(api), api.user()
    r = api.client.get(f"/api/v1/exercises/{slug}/sheet.pdf")
    assert r.status_code == 401 and error_code(r) == "NOT_AUTHENTICATED"
    missing = api.client.get("/api/v1/exercises/no-such-exercise/sheet.pdf", headers=auth(student))
    assert missing.status_code == 404 and error_code(missing) == "EXERCISE_NOT_FOUND"
    bad_lang = api.client.get(f"/api/v1/exercises/{slug}/sheet.pdf?lang=xx", headers=auth(student))
    assert bad_lang.status_code == 422


def test_without_weasyprint_the_sheet_is_503_and_the_rest_works(
    api: Api, monkeypatch: pytest.MonkeyPatch
) -> None:
    def no_pango() -> None:
        raise OSError("cannot load library 'libpango-1.0-0': libpango-1.0-0: cannot open shared object file")

    monkeypatch.setattr(core.sheet, "_import_weasyprint", no_pango)
    slug, student = arch_exercise(api), api.user()
    r = api.client.get(f"/api/v1/exercises/{slug}/sheet.pdf", headers=auth(student))
    assert r.status_code == 503 and error_code(r) == "PDF_UNAVAILABLE"
    error = r.json()["error"]
    assert "nicht verfügbar" in error["message"] and "libpango-1.0-0" in error["message"]
    assert "not available" in error["message_en"] and "libpango-1.0-0" in error["message_en"]
    # the drawing and the exercise itself do not need it
    assert api.client.get(f"/api/v1/exercises/{slug}/drawing.svg", headers=auth(student)).status_code == 200
    assert api.client.get(f"/api/v1/exercises/{slug}", headers=auth(student)).status_code == 200
