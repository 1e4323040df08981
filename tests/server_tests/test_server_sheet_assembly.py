"""Task sheets over HTTP are rendered one exercise per worker job and cached by content (the exercise's document and
the language), then put together: an assignment of 32 exercises gets its sheets, however long all of them together
would take, and a sheet asked for again costs no rendering. The jobs are counted, not timed."""

from __future__ import annotations

import io
from collections.abc import Iterator
from typing import Any

import pytest
from exam_helpers import assign, course_with
from fastapi.testclient import TestClient
from server_helpers import Api, auth, builtin_exercise, make_settings

from core.sheet import SheetUnavailable, pdf_engine
from server.app import create_app


def _pdf_available() -> bool:
    try:
        pdf_engine()
    except SheetUnavailable:
        return False
    return True


pytestmark = pytest.mark.skipif(
    not _pdf_available(), reason="WeasyPrint or Pango missing (bash .ci/run installs them)"
)


class Jobs:
    """The worker jobs an app is given, by name with their arguments."""

    def __init__(self, app: Any) -> None:
        self.calls: list[tuple[str, tuple[Any, ...]]] = []
        workers = app.state.workers
        real = workers.call

        async def call(fn: Any, *args: Any, **kwargs: Any) -> Any:
            self.calls.append((getattr(fn, "__name__", "job"), args))
            return await real(fn, *args, **kwargs)

        workers.call = call

    def named(self, name: str) -> list[tuple[Any, ...]]:
        return [args for n, args in self.calls if n == name]


@pytest.fixture(scope="module")
def own(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Api]:
    settings = make_settings(
        tmp_path_factory.mktemp("sheets"), "sqlite", workers=2, rate_picture_per_minute=1000
    )
    with TestClient(create_app(settings), base_url="http://127.0.0.1") as client:
        yield Api(client)


def pages(pdf: bytes) -> list[str]:
    from pypdf import PdfReader

    return [page.extract_text() for page in PdfReader(io.BytesIO(pdf)).pages]


def test_an_assignment_of_32_exercises_gets_its_sheets_one_job_per_exercise(own: Api) -> None:
    teacher, student, admin = own.user("instructor"), own.user(), own.user("admin")
    course = course_with(own, teacher, student)
    slugs = [builtin_exercise(own) for _ in range(32)]
    assignment = assign(own, teacher, course, slugs, exam=False)
    jobs = Jobs(own.app)

    r = own.client.get(f"/api/v1/assignments/{assignment}/sheets.pdf", headers=auth(student))
    assert r.status_code == 200, r.text
    assert r.headers["content-type"] == "application/pdf"
    sheets = pages(r.content)
    assert len(sheets) == 2 * 32  # per exercise its task page and one programming-form page, in order
    for k in (0, 17, 31):
        assert f"Aufgabe {slugs[k]}" in sheets[2 * k] and "Programmierblatt" in sheets[2 * k + 1]
    rendered = jobs.named("job_sheet")
    assert len(rendered) == 32
    assert all(
        isinstance(args[0], dict) for args in rendered
    )  # one exercise's document per job, no list of them
    assert len(jobs.named("job_merge_pdfs")) == 1

    # asked for again (another trainee of the class): nothing is rendered or put together again
    jobs.calls.clear()
    again = own.client.get(f"/api/v1/assignments/{assignment}/sheets.pdf", headers=auth(teacher))
    assert again.status_code == 200 and again.content == r.content
    assert jobs.calls == []

    # one exercise changes: only its sheet is rendered again
    changed = own.client.patch(
        f"/api/v1/exercises/{slugs[5]}", json={"title_de": "Neue Überschrift"}, headers=auth(admin)
    )
    assert changed.status_code == 200, changed.text
    third = own.client.get(f"/api/v1/assignments/{assignment}/sheets.pdf", headers=auth(student))
    assert third.status_code == 200
    assert len(jobs.named("job_sheet")) == 1 and jobs.named("job_sheet")[0][0]["id"] == slugs[5]
    assert "Neue Überschrift" in pages(third.content)[10]


def test_an_exercise_sheet_is_rendered_once_per_language(own: Api) -> None:
    student, slug = own.user(), builtin_exercise(own)
    jobs = Jobs(own.app)
    first = own.client.get(f"/api/v1/exercises/{slug}/sheet.pdf", headers=auth(student))
    second = own.client.get(f"/api/v1/exercises/{slug}/sheet.pdf", headers=auth(own.user()))
    english = own.client.get(f"/api/v1/exercises/{slug}/sheet.pdf?lang=en", headers=auth(student))
    assert [x.status_code for x in (first, second, english)] == [200, 200, 200]
    assert first.content == second.content and "Programming form" in pages(english.content)[1]
    assert [args[1] for args in jobs.named("job_sheet")] == ["de", "en"]


def test_the_picture_and_the_drawing_are_made_once_per_exercise(own: Api) -> None:
    slug = builtin_exercise(own)
    jobs = Jobs(own.app)
    for _ in range(3):
        who = auth(own.user())
        assert own.client.get(f"/api/v1/exercises/{slug}/picture.png", headers=who).status_code == 200
        assert own.client.get(f"/api/v1/exercises/{slug}/drawing.svg", headers=who).status_code == 200
    assert own.client.get(f"/api/v1/examples/{slug}/drawing.svg").status_code == 200
    assert len(jobs.named("job_picture")) == 1 and len(jobs.named("job_drawing")) == 1
