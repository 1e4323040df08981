"""Exercises written in the browser (issue 31): who sees an exercise (draft, courses, public, set in an assignment),
versions, archive, duplicate, every validation error at once, own drawings (hostile uploads refused), the drawing
preview of the unsaved editor state and the task preview."""

from __future__ import annotations

import copy
import struct
import zlib
from typing import Any

import pytest
from exam_helpers import assign, course_with, shift
from server_helpers import BAD, GOOD, Api, auth, builtin_exercise, error_code, reference_of

from server import repository as repo

ANON: dict[str, str] = {"name": "anonymous"}


def _duplicate(api: Api, who: dict[str, str], slug: str) -> dict[str, Any]:
    r = api.client.post(f"/api/v1/exercises/{slug}/duplicate", headers=auth(who))
    assert r.status_code == 201, r.text
    return dict(r.json())


def _patch(api: Api, who: dict[str, str], slug: str, **body: Any) -> Any:
    return api.client.patch(f"/api/v1/exercises/{slug}", json=body, headers=auth(who))


def _sees(api: Api, who: dict[str, str], slug: str) -> dict[str, bool]:
    """What `who` sees of the exercise: its page, the list, the live check, the drawing, a draft, a submission."""
    h = auth(who)
    if who is ANON:  # without an account: only free practice's live check, which names the exercise
        check = api.client.post("/api/v1/check", json={"program": GOOD, "exercise": slug}).status_code
        assert check in (200, 404) and api.client.get(f"/api/v1/exercises/{slug}").status_code == 401
        return {"check": check == 200}
    listed = slug in [e["slug"] for e in api.client.get("/api/v1/exercises", headers=h).json()]
    page = api.client.get(f"/api/v1/exercises/{slug}", headers=h).status_code
    check = api.client.post("/api/v1/check", json={"program": GOOD, "exercise": slug}, headers=h).status_code
    drawing = api.client.get(f"/api/v1/exercises/{slug}/drawing.svg", headers=h).status_code
    seen = {"list": listed, "page": page == 200, "check": check == 200, "drawing": drawing == 200}
    for code in (page, check, drawing):
        assert code in (200, 404), code  # not seen: "not found", alike for names that do not exist
    draft = api.client.put(f"/api/v1/exercises/{slug}/draft", json={"program": GOOD}, headers=h).status_code
    assert draft in (200, 404), draft
    seen["draft"] = draft == 200
    return seen


def _all(value: bool, anonymous: bool = False) -> dict[str, bool]:
    keys = ["check"] if anonymous else ["list", "page", "check", "drawing", "draft"]
    return dict.fromkeys(keys, value)


def test_visibility_matrix_draft_courses_public(api: Api) -> None:
    author, other, admin = api.user("instructor"), api.user("instructor"), api.user("admin")
    mine, theirs = api.user(), api.user()
    course_with(api, author, mine)
    course_with(api, other, theirs)
    ex = _duplicate(api, author, builtin_exercise(api))
    slug = ex["slug"]
    assert ex["visibility"] == "draft" and ex["owner"] == author["name"]

    # draft: the author and admins only
    assert _sees(api, author, slug) == _all(True)
    assert _sees(api, admin, slug) == _all(True)
    for who in (mine, theirs, other):
        assert _sees(api, who, slug) == _all(False), who["name"]
    assert _sees(api, ANON, slug) == _all(False, anonymous=True)
    r = api.client.post("/api/v1/submissions", json={"exercise": slug, "program": GOOD}, headers=auth(mine))
    assert r.status_code == 404 and error_code(r) == "EXERCISE_NOT_FOUND"

    # courses: also the students of the author's course; not another course's, not anonymous
    r = _patch(api, author, slug, visibility="courses")
    assert r.status_code == 200 and r.json()["visibility"] == "courses", r.text
    assert _sees(api, mine, slug) == _all(True)
    assert _sees(api, theirs, slug) == _all(False)
    assert _sees(api, other, slug) == _all(False)
    assert _sees(api, ANON, slug) == _all(False, anonymous=True)

    # public: everyone
    assert _patch(api, author, slug, visibility="public").status_code == 200
    assert _sees(api, theirs, slug) == _all(True)
    assert _sees(api, ANON, slug) == _all(True, anonymous=True)

    # only the author (or an admin) changes it
    assert _patch(api, other, slug, visibility="draft").status_code == 403
    assert _patch(api, mine, slug, visibility="draft").status_code == 403


def test_a_draft_set_in_an_assignment_is_seen_from_its_opening(api: Api) -> None:
    author, student, stranger = api.user("instructor"), api.user(), api.user()
    course = course_with(api, author, student)
    slug = _duplicate(api, author, builtin_exercise(api))["slug"]
    assignment = assign(api, author, course, [slug], exam=False, start=60)
    assert _sees(api, student, slug) == _all(False)  # not before it opens
    shift(api, assignment, 61)
    assert _sees(api, student, slug) == _all(True)
    assert _sees(api, stranger, slug) == _all(False)
    r = api.client.post(
        "/api/v1/submissions", json={"exercise": slug, "program": reference_of()}, headers=auth(student)
    )
    assert r.status_code == 201, r.text


def test_edit_of_a_published_exercise_makes_a_version_and_submissions_keep_theirs(api: Api) -> None:
    author, student = api.user("instructor"), api.user()
    course = course_with(api, author, student)
    ex = _duplicate(api, author, builtin_exercise(api))
    slug, document = ex["slug"], ex["document"]
    practice = assign(api, author, course, [slug], exam=False)
    assert document["id"] == slug and ex["version"] == 1

    # a draft's edits make no versions
    document = {**document, "task": {"de": "Fräsen Sie die Kontur.", "en": ""}}
    r = _patch(api, author, slug, document=document)
    assert r.status_code == 200 and r.json()["version"] == 1, r.text
    assert _patch(api, author, slug, visibility="courses").json()["version"] == 1

    r = api.client.post(
        "/api/v1/submissions", json={"exercise": slug, "program": reference_of()}, headers=auth(student)
    )
    assert r.status_code == 201, r.text
    first = r.json()
    assert first["exercise_version"] == 1 and first["version_note"] == "" and first["score"] == 100

    # the content changes: version 2; the old document is kept
    changed = copy.deepcopy(document)
    changed["task"] = {"de": "Fräsen Sie die Kontur, neu.", "en": ""}
    r = _patch(api, author, slug, document=changed)
    assert r.status_code == 200 and r.json()["version"] == 2, r.text
    with api.app.state.db.session() as db:
        exercise = repo.exercise_by_slug(db, slug)
        assert exercise is not None
        versions = repo.exercise_versions(db, exercise.id)
        assert [(v.version, v.document["task"]["de"]) for v in versions] == [(1, "Fräsen Sie die Kontur.")]
    # the same content again, or only the visibility: no new version
    assert _patch(api, author, slug, document=changed).json()["version"] == 2
    assert _patch(api, author, slug, visibility="public").json()["version"] == 2

    old = api.client.get(f"/api/v1/submissions/{first['id']}", headers=auth(student)).json()
    assert old["exercise_version"] == 1 and old["version_note"] == "Version 1"
    r = api.client.post(
        "/api/v1/submissions", json={"exercise": slug, "program": GOOD}, headers=auth(student)
    )
    assert r.json()["exercise_version"] == 2 and r.json()["version_note"] == ""

    # the results matrix names the version of the best submission (the first one, full marks)
    results = api.client.get("/api/v1/results", headers=auth(author)).json()
    row = next(t for t in results["trainees"] if t["username"] == student["name"])
    assert row["results"][slug]["best_submission"] == first["id"]
    assert row["results"][slug]["version_note"] == "Version 1"
    # and so does the course's matrix of the assignment
    matrix = api.client.get(f"/api/v1/assignments/{practice}/results", headers=auth(author)).json()
    cell = next(t for t in matrix["trainees"] if t["username"] == student["name"])["results"][slug]
    assert (
        cell["submission"] == first["id"]
        and cell["version_note"] == "Version 1"
        and cell["exercise_version"] == 1
    )


def test_archive_hides_keeps_submissions_and_delete_without_submissions_deletes(api: Api) -> None:
    author, student = api.user("instructor"), api.user()
    slug = _duplicate(api, author, builtin_exercise(api))["slug"]
    assert _patch(api, author, slug, visibility="public").status_code == 200
    r = api.client.post(
        "/api/v1/submissions", json={"exercise": slug, "program": reference_of()}, headers=auth(student)
    )
    assert r.status_code == 201
    submission = r.json()["id"]
    assert api.client.delete(f"/api/v1/exercises/{slug}", headers=auth(author)).status_code == 204
    assert _sees(api, student, slug) == _all(False)
    mine = api.client.get(f"/api/v1/submissions/{submission}", headers=auth(student))
    assert mine.status_code == 200 and mine.json()["score"] == 100  # the submission and its grade stay
    own = api.client.get("/api/v1/exercises?mine=true", headers=auth(author)).json()
    assert slug not in [e["slug"] for e in own]
    own = api.client.get("/api/v1/exercises?mine=true&archived=true", headers=auth(author)).json()
    assert [e["archived"] for e in own if e["slug"] == slug] == [True]
    assert _patch(api, author, slug, archived=False).json()["archived"] is False
    assert _sees(api, student, slug) == _all(True)

    fresh = _duplicate(api, author, builtin_exercise(api))["slug"]
    assert api.client.delete(f"/api/v1/exercises/{fresh}", headers=auth(author)).status_code == 204
    assert api.client.get(f"/api/v1/exercises/{fresh}", headers=auth(author)).status_code == 404


def test_duplicate_built_in_or_own_as_a_new_draft(api: Api) -> None:
    author, other, student = api.user("instructor"), api.user("instructor"), api.user()
    builtin = builtin_exercise(api)
    first = _duplicate(api, author, builtin)
    second = _duplicate(api, author, builtin)
    assert first["slug"] == f"{builtin}-kopie" and second["slug"] == f"{builtin}-kopie-2"
    assert first["title_de"].endswith("(Kopie)") and first["visibility"] == "draft" and not first["builtin"]
    assert first["reference_program"] == reference_of()
    own = _duplicate(api, author, first["slug"])  # one's own
    assert own["owner"] == author["name"] and own["slug"] != first["slug"]
    assert _patch(api, author, first["slug"], visibility="public").status_code == 200
    r = api.client.post(f"/api/v1/exercises/{first['slug']}/duplicate", headers=auth(other))
    assert r.status_code == 403 and error_code(r) == "EXERCISE_NOT_COPYABLE"  # another author's
    assert api.client.post(f"/api/v1/exercises/{builtin}/duplicate", headers=auth(student)).status_code == 403
    assert api.client.post(f"/api/v1/exercises/{builtin}/duplicate").status_code == 401
    r = api.client.post(f"/api/v1/exercises/{own['slug']}/duplicate", headers=auth(other))
    assert r.status_code == 404  # a draft they do not see


def _broken_document(slug: str) -> dict[str, Any]:
    return {
        "id": slug,
        "title": {"de": ""},
        "task": {"de": "Aufgabe"},
        "dialect": "pal-mill",
        "kind": "complete",
        "stock": {"min": [0, 0, -10], "max": [80, -5, 0]},
        "tools": [{"number": 1, "diameter": -3}],
        "reference": "",
        "locked_lines": [4],
        "rubric": [{"id": "geometry", "points": 90}],
        "cutting_data": [{"tool": 1, "feed": 100}],
    }


def test_every_validation_error_at_once_per_field_german_first(api: Api) -> None:
    author = api.user("instructor")
    r = api.client.post(
        "/api/v1/exercises", json={"document": _broken_document("kaputt-1")}, headers=auth(author)
    )
    assert r.status_code == 422 and error_code(r) == "EXERCISE_INVALID", r.text
    errors = r.json()["error"]["details"]["errors"]
    fields = {e["field"] for e in errors}
    assert {
        "title.de",
        "reference",
        "stock",
        "tools",
        "start_program",
        "locked_lines",
        "rubric",
        "cutting_data",
    } <= fields, errors
    by_field = {e["field"]: e for e in errors}
    assert by_field["rubric"]["message"] == "die Punkte müssen 100 ergeben (sind 90)"
    assert by_field["title.de"]["message"].startswith("fehlt") and by_field["title.de"]["message_en"]
    assert api.client.get("/api/v1/exercises/kaputt-1", headers=auth(author)).status_code == 404

    # the YAML import reads the same model and says the same
    import yaml  # type: ignore[import-untyped, unused-ignore]

    text = yaml.safe_dump(_broken_document("kaputt-2"), allow_unicode=True)
    r = api.client.post(
        "/api/v1/exercises/import",
        content=text.encode(),
        headers={**auth(author), "Content-Type": "application/yaml"},
    )
    assert r.status_code == 422
    assert {e["field"] for e in r.json()["error"]["details"]["errors"]} == fields

    # a published exercise's reference must score full marks; a draft's need not
    doc = _duplicate(api, author, builtin_exercise(api))["document"]
    doc = {**doc, "id": "voll-1", "reference": BAD}  # a syntax error: the reference loses points
    r = api.client.post(
        "/api/v1/exercises", json={"document": doc, "visibility": "courses"}, headers=auth(author)
    )
    assert r.status_code == 422 and error_code(r) == "REFERENCE_NOT_CLEAN"
    assert r.json()["error"]["details"]["errors"][0]["field"] == "reference"
    r = api.client.post("/api/v1/exercises", json={"document": doc}, headers=auth(author))
    assert r.status_code == 201 and r.json()["visibility"] == "draft", r.text


def test_yaml_export_reads_back(api: Api) -> None:
    author, student = api.user("instructor"), api.user()
    ex = _duplicate(api, author, builtin_exercise(api))
    r = api.client.get(f"/api/v1/exercises/{ex['slug']}/export", headers=auth(author))
    assert r.status_code == 200 and r.headers["content-type"].startswith("application/yaml")
    assert api.client.get(f"/api/v1/exercises/{ex['slug']}/export", headers=auth(student)).status_code == 403
    text = r.text.replace(f"id: {ex['slug']}", f"id: {ex['slug']}-wieder")
    r = api.client.post(
        "/api/v1/exercises/import?visibility=draft",
        content=text.encode(),
        headers={**auth(author), "Content-Type": "application/yaml"},
    )
    assert r.status_code == 201, r.text
    assert r.json()["visibility"] == "draft" and r.json()["reference_program"] == ex["reference_program"]


def _png(width: int = 4, height: int = 3) -> bytes:
    def chunk(kind: bytes, data: bytes) -> bytes:
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))

    raw = b"".join(b"\x00" + b"\xff\xff\xff" * width for _ in range(height))
    return (
        b"\x89PNG\r\n\x1a\n"
        + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0))
        + chunk(b"IDAT", zlib.compress(raw))
        + chunk(b"IEND", b"")
    )


CLEAN_SVG = (
    b'<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 100 50"><rect x="1" y="1" width="98" '
    b'height="48" fill="none" stroke="black"/><text x="10" y="30">Eigene Zeichnung</text></svg>'
)
HOSTILE = {
    "script": b'<svg xmlns="http://www.w3.org/2000/svg"><script>alert(1)</script></svg>',
    "onload": b'<svg xmlns="http://www.w3.org/2000/svg" onload="alert(1)"><rect width="1" height="1"/></svg>',
    "external href": (
        b'<svg xmlns="http://www.w3.org/2000/svg" xmlns:xlink="http://www.w3.org/1999/xlink">'
        b'<image xlink:href="https://evil.example/x.png" width="10" height="10"/></svg>'
    ),
    "external url": (
        b'<svg xmlns="http://www.w3.org/2000/svg"><rect width="1" height="1" '
        b'style="fill: url(https://evil.example/a.svg#p)"/></svg>'
    ),
    "entity": (
        b'<?xml version="1.0"?><!DOCTYPE svg [<!ENTITY a "aaaa">]>'
        b'<svg xmlns="http://www.w3.org/2000/svg">&a;</svg>'
    ),
    "foreignObject": (
        b'<svg xmlns="http://www.w3.org/2000/svg"><foreignObject><div xmlns="http://www.w3.org/1999/'
        b'xhtml">x</div></foreignObject></svg>'
    ),
    "html named png": b"<html><body><script>alert(1)</script></body></html>",
}


def test_own_drawing_upload_refuses_hostile_files(api: Api) -> None:
    author, other, student = api.user("instructor"), api.user("instructor"), api.user()
    slug = _duplicate(api, author, builtin_exercise(api))["slug"]
    url = f"/api/v1/exercises/{slug}/own-drawing"
    for name, data in HOSTILE.items():
        r = api.client.put(
            f"{url}?filename=zeichnung.png",
            content=data,
            headers={**auth(author), "Content-Type": "image/png"},
        )
        assert r.status_code == 422 and error_code(r) == "DRAWING_INVALID", name
    r = api.client.put(url, content=b"%PDF-1.4\n" + b"0" * 2_000_001, headers=auth(author))
    assert r.status_code == 413  # refused by the size, whatever the content
    assert (
        api.client.put(url, content=CLEAN_SVG, headers=auth(other)).status_code == 404
    )  # a draft they do not see
    assert api.client.get(url, headers=auth(author)).status_code == 404  # none yet

    generated = api.client.get(f"/api/v1/exercises/{slug}/drawing.svg", headers=auth(author)).text
    r = api.client.put(f"{url}?filename=teil.svg", content=CLEAN_SVG, headers=auth(author))
    assert r.status_code == 200 and r.json()["own_drawing"] == "image/svg+xml", r.text
    shown = api.client.get(f"/api/v1/exercises/{slug}/drawing.svg", headers=auth(author))
    assert "Eigene Zeichnung" in shown.text and shown.text != generated
    assert "default-src 'none'" in shown.headers["content-security-policy"]
    assert api.client.get(f"/api/v1/exercises/{slug}/drawing.svg", headers=auth(student)).status_code == 404

    r = api.client.put(f"{url}?filename=teil.png", content=_png(), headers=auth(author))
    assert r.status_code == 200 and r.json()["own_drawing"] == "image/png"
    shown = api.client.get(f"/api/v1/exercises/{slug}/drawing.svg", headers=auth(author)).text
    assert "data:image/png;base64," in shown and 'viewBox="0 0 4 3"' in shown
    assert api.client.get(url, headers=auth(author)).content == _png()

    assert _patch(api, author, slug, visibility="public").status_code == 200
    assert (
        "data:image/png"
        in api.client.get(f"/api/v1/exercises/{slug}/drawing.svg", headers=auth(student)).text
    )
    assert api.client.put(url, content=_png(), headers=auth(other)).status_code == 403  # seen, not theirs
    assert api.client.delete(url, headers=auth(author)).status_code == 204
    assert api.client.get(f"/api/v1/exercises/{slug}/drawing.svg", headers=auth(author)).text == generated


def test_drawing_preview_follows_the_unsaved_editor_state(api: Api) -> None:
    author, student = api.user("instructor"), api.user()
    doc = _duplicate(api, author, builtin_exercise(api))["document"]
    part = {k: doc[k] for k in ("dialect", "stock", "tools", "reference")}
    r = api.client.post("/api/v1/exercises/drawing-preview", json={"document": part}, headers=auth(author))
    assert r.status_code == 200 and r.headers["content-type"].startswith("image/svg+xml") and "<svg" in r.text
    bigger = {
        **part,
        "stock": {**part["stock"], "max": [part["stock"]["max"][0] + 20, *part["stock"]["max"][1:]]},
    }
    r2 = api.client.post("/api/v1/exercises/drawing-preview", json={"document": bigger}, headers=auth(author))
    assert r2.status_code == 200 and r2.text != r.text
    broken = {**part, "stock": {"min": [0, 0, 0], "max": [0, 0, 0]}}
    r3 = api.client.post("/api/v1/exercises/drawing-preview", json={"document": broken}, headers=auth(author))
    assert r3.status_code == 422 and r3.json()["error"]["details"]["errors"][0]["field"] == "stock"
    assert (
        api.client.post(
            "/api/v1/exercises/drawing-preview", json={"document": part}, headers=auth(student)
        ).status_code
        == 403
    )


def test_task_preview_renders_as_the_pages_do(api: Api) -> None:
    author, student = api.user("instructor"), api.user()
    r = api.client.post(
        "/api/v1/exercises/task-preview",
        json={"markdown": "**Kontur** fräsen <script>x</script>"},
        headers=auth(author),
    )
    assert r.status_code == 200
    html = r.json()["html"]
    assert "<strong>Kontur</strong>" in html and "<script>" not in html
    assert (
        api.client.post(
            "/api/v1/exercises/task-preview", json={"markdown": "x"}, headers=auth(student)
        ).status_code
        == 403
    )


def _pdf_available() -> bool:
    from core.sheet import SheetUnavailable, pdf_engine

    try:
        pdf_engine()
    except SheetUnavailable:
        return False
    return True


@pytest.mark.skipif(not _pdf_available(), reason="WeasyPrint or Pango missing (bash .ci/run installs them)")
def test_the_sheet_prints_the_own_drawing(api: Api) -> None:
    import io

    from pypdf import PdfReader

    from core.sheet import pdf_engine

    author = api.user("instructor")
    slug = _duplicate(api, author, builtin_exercise(api))["slug"]
    sheet = f"/api/v1/exercises/{slug}/sheet.pdf"
    generated = api.client.get(sheet, headers=auth(author))
    assert generated.status_code == 200
    pages = len(PdfReader(io.BytesIO(generated.content)).pages)
    # a PNG: on the task page in place of the generated drawing (the same pages, other content)
    assert (
        api.client.put(
            f"/api/v1/exercises/{slug}/own-drawing", content=_png(40, 30), headers=auth(author)
        ).status_code
        == 200
    )
    with_png = api.client.get(sheet, headers=auth(author))
    assert (
        len(PdfReader(io.BytesIO(with_png.content)).pages) == pages and with_png.content != generated.content
    )
    # a PDF drawing: its page follows the sheet's pages
    drawing = pdf_engine().HTML(string="<p>Eigene Zeichnung</p>").write_pdf()
    assert (
        api.client.put(f"/api/v1/exercises/{slug}/own-drawing", content=drawing, headers=auth(author)).json()[
            "own_drawing"
        ]
        == "application/pdf"
    )
    with_pdf = PdfReader(io.BytesIO(api.client.get(sheet, headers=auth(author)).content))
    assert len(with_pdf.pages) == pages + 1 and "Eigene Zeichnung" in with_pdf.pages[-1].extract_text()


def test_an_exam_submitted_at_its_end_records_the_version(api: Api) -> None:
    from exam_helpers import finalize

    author, student = api.user("instructor"), api.user()
    course = course_with(api, author, student)
    ex = _duplicate(api, author, builtin_exercise(api))
    slug = ex["slug"]
    assert _patch(api, author, slug, visibility="courses").status_code == 200
    changed = {**ex["document"], "task": {"de": "Neu: Fräsen Sie die Kontur.", "en": ""}}
    assert _patch(api, author, slug, document=changed).json()["version"] == 2
    exam = assign(api, author, course, [slug], start=-1, minutes=30)
    assert (
        api.client.put(
            f"/api/v1/exercises/{slug}/draft", json={"program": GOOD}, headers=auth(student)
        ).status_code
        == 200
    )
    shift(api, exam, 31)
    assert finalize(api) >= 1
    with api.app.state.db.session() as db:
        assert [(s.auto, s.exercise_version) for s in repo.assignment_submissions(db, exam)] == [(True, 2)]


def test_drawing_preview_is_rate_limited_as_pictures(tmp_path_factory: pytest.TempPathFactory) -> None:
    from fastapi.testclient import TestClient
    from server_helpers import make_settings

    from server.app import create_app

    settings = make_settings(
        tmp_path_factory.mktemp("preview"), "sqlite", workers=1, rate_picture_per_minute=2
    )
    with TestClient(create_app(settings), base_url="http://127.0.0.1") as client:
        small = Api(client)
        author = small.user("instructor")
        doc = _duplicate(small, author, builtin_exercise(small))["document"]
        part = {"document": {k: doc[k] for k in ("dialect", "stock", "tools", "reference")}}
        codes = [
            small.client.post(
                "/api/v1/exercises/drawing-preview", json=part, headers=auth(author)
            ).status_code
            for _ in range(3)
        ]
        assert codes == [200, 200, 429]
