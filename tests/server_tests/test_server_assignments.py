"""Assignments and exam mode (issue 19): deadlines with late submissions accepted or refused, the trainee's
list, results as JSON and CSV; an exam refuses work after its end, submits the last draft itself and hides the
results until the instructor releases them."""

from __future__ import annotations

import csv
import io
from typing import Any

from exam_helpers import iso, shift
from server_helpers import GOOD, Api, auth, builtin_exercise, error_code

from server import repository as repo


def _course_with(api: Api, *students: dict[str, str]) -> tuple[dict[str, str], int]:
    teacher = api.user("instructor")
    r = api.client.post("/api/v1/courses", json={"name": "Prüfungsklasse"}, headers=auth(teacher))
    assert r.status_code == 201, r.text
    for s in students:
        assert (
            api.client.post(
                "/api/v1/courses/join", json={"code": r.json()["join_code"]}, headers=auth(s)
            ).status_code
            == 200
        )
    return teacher, int(r.json()["id"])


def _assign(api: Api, teacher: dict[str, str], course: int, **body: Any) -> dict[str, Any]:
    r = api.client.post(f"/api/v1/courses/{course}/assignments", json=body, headers=auth(teacher))
    assert r.status_code == 201, r.text
    return dict(r.json())


def _submit(api: Api, who: dict[str, str], slug: str, **extra: Any) -> Any:
    return api.client.post(
        "/api/v1/submissions", json={"exercise": slug, "program": GOOD, **extra}, headers=auth(who)
    )


def test_practice_deadline_late_accept_and_refuse(api: Api) -> None:
    student = api.user()
    teacher, course = _course_with(api, student)
    slug = builtin_exercise(api)
    accept = _assign(
        api,
        teacher,
        course,
        title="Übung G1",
        exercises=[slug],
        opens_at=iso(-1),
        deadline=iso(60),
        late="accept",
    )
    refuse = _assign(
        api,
        teacher,
        course,
        title="Übung G1 streng",
        exercises=[slug],
        opens_at=iso(-1),
        deadline=iso(60),
        late="refuse",
    )
    assert accept["mode"] == "practice" and accept["settings"]["hints"] is True
    mine = {a["id"]: a for a in api.client.get("/api/v1/me/assignments", headers=auth(student)).json()}
    assert mine[accept["id"]]["status"] == "open" and 3500 < mine[accept["id"]]["seconds_left"] <= 3600
    shift(api, accept["id"], 120)
    shift(api, refuse["id"], 120)
    r = _submit(api, student, slug, assignment=refuse["id"])
    assert r.status_code == 409 and error_code(r) == "ASSIGNMENT_CLOSED"
    assert "Abgabefrist ist abgelaufen" in r.json()["error"]["message"]
    r = _submit(api, student, slug, assignment=accept["id"])
    assert r.status_code == 201, r.text
    mine = {a["id"]: a for a in api.client.get("/api/v1/me/assignments", headers=auth(student)).json()}
    item = mine[accept["id"]]["items"][0]
    assert mine[accept["id"]]["status"] == "late" and item["late"] is True and item["score"] is not None
    assert mine[refuse["id"]]["status"] == "closed" and mine[refuse["id"]]["items"][0]["submitted"] is False
    # without naming an assignment the work after the deadline is plain practice (nothing is refused)
    assert _submit(api, student, slug).status_code == 201

    table = api.client.get(f"/api/v1/assignments/{accept['id']}/results", headers=auth(teacher)).json()
    cell = table["trainees"][0]["results"][slug]
    assert table["trainees"][0]["username"] == student["name"] and cell["late"] is True
    r = api.client.get(f"/api/v1/assignments/{accept['id']}/results?format=csv", headers=auth(teacher))
    assert (
        r.status_code == 200
        and r.headers["content-type"].startswith("text/csv")
        and r.text.startswith("\ufeff")
    )
    rows = list(csv.reader(io.StringIO(r.text.lstrip("\ufeff")), delimiter=";"))
    assert rows[0][:3] == ["Benutzer", "Aufgabe", "Punktzahl"] and rows[1][0] == student["name"]
    assert rows[1][5] == "ja"
    assert (
        api.client.get(f"/api/v1/assignments/{accept['id']}/results.csv", headers=auth(teacher)).text
        == r.text
    )
    # the student and another instructor do not see the results
    assert (
        api.client.get(f"/api/v1/assignments/{accept['id']}/results", headers=auth(student)).status_code
        == 403
    )
    other = api.user("instructor")
    r = api.client.get(f"/api/v1/assignments/{accept['id']}/results", headers=auth(other))
    assert r.status_code == 404 and error_code(r) == "ASSIGNMENT_NOT_FOUND"


def test_assignment_validation(api: Api) -> None:
    teacher, course = _course_with(api)
    slug = builtin_exercise(api)
    base = {"title": "X", "exercises": [slug], "opens_at": iso(0)}
    r = api.client.post(
        f"/api/v1/courses/{course}/assignments", json={**base, "mode": "exam"}, headers=auth(teacher)
    )
    assert r.status_code == 422 and error_code(r) == "ASSIGNMENT_TIMES"
    r = api.client.post(
        f"/api/v1/courses/{course}/assignments", json={**base, "deadline": iso(-5)}, headers=auth(teacher)
    )
    assert r.status_code == 422 and error_code(r) == "ASSIGNMENT_TIMES"
    r = api.client.post(
        f"/api/v1/courses/{course}/assignments",
        json={**base, "exercises": ["gibt-es-nicht"], "deadline": iso(5)},
        headers=auth(teacher),
    )
    assert r.status_code == 404 and error_code(r) == "EXERCISE_NOT_FOUND"
    foreign = api.exercise(api.user("instructor"))["slug"]  # another instructor's own exercise
    r = api.client.post(
        f"/api/v1/courses/{course}/assignments",
        json={**base, "exercises": [foreign], "deadline": iso(5)},
        headers=auth(teacher),
    )
    assert r.status_code == 403
    own = api.exercise(teacher)["slug"]
    a = _assign(api, teacher, course, **{**base, "exercises": [slug, own], "deadline": iso(5)})
    r = api.client.patch(
        f"/api/v1/assignments/{a['id']}", json={"title": "Neu", "deadline": iso(10)}, headers=auth(teacher)
    )
    assert r.status_code == 200 and r.json()["title"] == "Neu" and r.json()["exercises"] == [slug, own]
    assert api.client.delete(f"/api/v1/assignments/{a['id']}", headers=auth(teacher)).status_code == 204
    assert api.client.get(f"/api/v1/assignments/{a['id']}", headers=auth(teacher)).status_code == 404


def test_exam_time_limit_auto_submission_and_release(api: Api) -> None:
    s1, s2, s3 = api.user(), api.user(), api.user()
    teacher, course = _course_with(api, s1, s2, s3)
    slug, other = (
        builtin_exercise(api, hints=[{"de": "Erst Z, dann X.", "en": "Z first, then X."}]),
        builtin_exercise(api),
    )
    exam = _assign(
        api,
        teacher,
        course,
        title="Prüfung G1",
        exercises=[slug],
        mode="exam",
        opens_at=iso(-1),
        duration_minutes=90,
    )
    assert exam["settings"] == {
        "live_diagnostics": False,
        "viz": False,
        "hints": False,
        "solution": False,
        "free_practice": False,
        "max_submissions": 1,
    }
    assert exam["late"] == "refuse"
    # while it runs: the exam's exercise only, no hints, no solution, one submission, no score shown
    mine = api.client.get("/api/v1/me/assignments", headers=auth(s1)).json()
    assert mine[0]["status"] == "running" and 5300 < mine[0]["seconds_left"] <= 5340
    r = api.client.put(f"/api/v1/exercises/{other}/draft", json={"program": GOOD}, headers=auth(s1))
    assert r.status_code == 403 and error_code(r) == "EXAM_RUNNING"
    r = _submit(api, s1, other)
    assert r.status_code == 403 and error_code(r) == "EXAM_RUNNING"
    r = api.client.get(f"/api/v1/exercises/{slug}/hints/1", headers=auth(s1))
    assert r.status_code == 403 and error_code(r) == "EXAM_RUNNING"
    r = api.client.get(f"/api/v1/exercises/{slug}/solution", headers=auth(s1))
    assert r.status_code == 403 and error_code(r) == "EXAM_RUNNING"
    r = _submit(api, s1, slug)
    assert r.status_code == 201 and r.json()["grading"] is None and r.json()["score"] is None
    first = r.json()["id"]
    r = _submit(api, s1, slug)
    assert r.status_code == 409 and error_code(r) == "ASSIGNMENT_SUBMITTED"
    assert (
        api.client.put(
            f"/api/v1/exercises/{slug}/draft", json={"program": GOOD}, headers=auth(s2)
        ).status_code
        == 200
    )
    r = api.client.post(f"/api/v1/assignments/{exam['id']}/release", headers=auth(teacher))
    assert r.status_code == 409 and error_code(r) == "EXAM_NOT_OVER"

    shift(api, exam["id"], 91)  # the exam is over; s2 closed the browser with a saved draft
    r = _submit(api, s3, slug, assignment=exam["id"])
    assert r.status_code == 403 and error_code(r) == "EXAM_OVER"
    assert "Prüfungszeit ist abgelaufen" in r.json()["error"]["message"]
    r = api.client.put(
        f"/api/v1/exercises/{slug}/draft?assignment={exam['id']}",
        json={"program": "N10 M30\n"},
        headers=auth(s2),
    )
    assert r.status_code == 403 and error_code(r) == "EXAM_OVER"
    # practice on the exercise goes on, into the practice draft, without a grade until the release
    r = api.client.put(f"/api/v1/exercises/{slug}/draft", json={"program": "N10 M30\n"}, headers=auth(s2))
    assert r.status_code == 200 and r.json()["assignment"] is None
    r = _submit(api, s1, slug)
    assert r.status_code == 201 and r.json()["grading"] is None and r.json()["score"] is None
    assert _submit(api, s1, other).status_code == 201  # practice is free again

    mine = api.client.get("/api/v1/me/assignments", headers=auth(s2)).json()[0]
    assert mine["status"] == "submitting" and mine["items"][0]["submitted"] is False  # pages only read
    portal = api.client.portal  # the background task's round, now (the app's event loop owns the workers)
    assert portal is not None
    from server.courses import finalize_ended_exams

    assert portal.call(finalize_ended_exams, api.app.state.db, api.app.state.workers) == 1
    mine = api.client.get("/api/v1/me/assignments", headers=auth(s2)).json()[0]
    item = mine["items"][0]
    assert mine["status"] == "submitted" and item["submitted"] and item["auto"] is True
    assert item["score"] is None and item["criteria"] is None and item["program"] is None
    assert mine["results_visible"] is False
    progress = {p["exercise"]: p for p in api.client.get("/api/v1/me/progress", headers=auth(s2)).json()}
    assert progress[slug]["best_score"] is None
    table = api.client.get(f"/api/v1/assignments/{exam['id']}/results", headers=auth(teacher)).json()
    rows = {t["username"]: t for t in table["trainees"]}
    assert rows[s1["name"]]["results"][slug]["submission"] == first
    score = rows[s1["name"]]["results"][slug]["score"]
    assert rows[s1["name"]]["results"][slug]["auto"] is False and isinstance(score, int)
    assert (
        rows[s2["name"]]["results"][slug]["auto"] is True
        and rows[s2["name"]]["results"][slug]["score"] == score
    )
    assert rows[s3["name"]]["results"] == {}  # no draft, nothing submitted
    # finalising again changes nothing
    assert portal.call(finalize_ended_exams, api.app.state.db, api.app.state.workers) == 0
    again = api.client.get(f"/api/v1/assignments/{exam['id']}/results", headers=auth(teacher)).json()
    assert again == table
    auto_id = rows[s2["name"]]["results"][slug]["submission"]
    assert api.client.get(f"/api/v1/submissions/{auto_id}", headers=auth(s2)).json()["grading"] is None

    r = api.client.post(f"/api/v1/assignments/{exam['id']}/release", headers=auth(s1))
    assert r.status_code == 403
    r = api.client.post(f"/api/v1/assignments/{exam['id']}/release", headers=auth(teacher))
    assert r.status_code == 200 and r.json()["released"] is True
    item = api.client.get("/api/v1/me/assignments", headers=auth(s2)).json()[0]["items"][0]
    assert (
        item["score"] == score and item["criteria"] and item["program"] == GOOD
    )  # the exam's draft, not practice's
    assert (
        api.client.get(f"/api/v1/submissions/{auto_id}", headers=auth(s2)).json()["grading"]["score"] == score
    )
    assert (
        api.client.put(
            f"/api/v1/exercises/{slug}/draft", json={"program": GOOD}, headers=auth(s2)
        ).status_code
        == 200
    )  # released: practising it is free again


def test_ended_exam_is_finalised_by_the_background_task(api: Api) -> None:
    from server.courses import finalize_ended_exams

    student = api.user()
    teacher, course = _course_with(api, student)
    slug = builtin_exercise(api)
    exam = _assign(
        api,
        teacher,
        course,
        title="Prüfung",
        exercises=[slug],
        mode="exam",
        opens_at=iso(-1),
        duration_minutes=30,
    )
    assert (
        api.client.put(
            f"/api/v1/exercises/{slug}/draft", json={"program": GOOD}, headers=auth(student)
        ).status_code
        == 200
    )
    shift(api, exam["id"], 31)
    portal = api.client.portal  # the app's event loop: the worker pool belongs to it
    assert portal is not None
    made = portal.call(finalize_ended_exams, api.app.state.db, api.app.state.workers)
    assert made >= 1
    assert portal.call(finalize_ended_exams, api.app.state.db, api.app.state.workers) == 0
    with api.app.state.db.session() as db:
        subs = repo.assignment_submissions(db, exam["id"])
        assert [(s.auto, s.held, s.program) for s in subs] == [(True, True, GOOD)]


def test_running_exam_refuses_live_diagnostics_and_3d(api: Api) -> None:
    import pytest
    from starlette.websockets import WebSocketDisconnect

    student, free = api.user(), api.user()
    teacher, course = _course_with(api, student)
    slug = builtin_exercise(api)
    before = api.client.post("/api/v1/viz", headers=auth(student)).json()["token"]  # a 3D view opened before
    _assign(
        api,
        teacher,
        course,
        title="Prüfung",
        exercises=[slug],
        mode="exam",
        opens_at=iso(-1),
        duration_minutes=90,
    )
    token = student["Authorization"].removeprefix("Bearer ")
    with (
        pytest.raises(WebSocketDisconnect) as err,
        api.client.websocket_connect(f"/api/v1/live?token={token}") as ws,
    ):
        ws.receive_text()
    assert err.value.code == 4403 and err.value.reason == "EXAM_RUNNING"
    r = api.client.post("/api/v1/viz", headers=auth(student))
    assert r.status_code == 403 and error_code(r) == "EXAM_RUNNING"
    for path, body in (("scene", {"program": GOOD}), ("playhead", {"index": 0}), ("view", {"view": "top"})):
        r = api.client.post(f"/api/v1/viz/{before}/{path}", json=body, headers=auth(student))
        assert r.status_code == 403 and error_code(r) == "EXAM_RUNNING", path
    # someone outside the course works as before
    with api.client.websocket_connect(
        f"/api/v1/live?token={free['Authorization'].removeprefix('Bearer ')}"
    ) as ws:
        ws.send_text('{"type": "open", "version": 0, "text": "N10 M30\\n"}')
        assert '"update"' in ws.receive_text()


def test_sheets_of_an_assignment(api: Api) -> None:
    from core.sheet import SheetUnavailable, pdf_engine

    student = api.user()
    teacher, course = _course_with(api, student)
    slugs = [builtin_exercise(api), builtin_exercise(api)]
    later = _assign(
        api, teacher, course, title="Später", exercises=slugs, opens_at=iso(60), deadline=iso(120)
    )
    r = api.client.get(f"/api/v1/assignments/{later['id']}/sheets.pdf", headers=auth(student))
    assert r.status_code == 409 and error_code(r) == "ASSIGNMENT_NOT_OPEN"
    r = api.client.get(f"/api/v1/assignments/{later['id']}/sheets.pdf", headers=auth(teacher))
    try:
        pdf_engine()
    except SheetUnavailable:
        assert r.status_code == 503 and error_code(r) == "PDF_UNAVAILABLE"
        return
    from pypdf import PdfReader

    assert r.status_code == 200 and r.headers["content-type"] == "application/pdf"
    single = api.client.get(f"/api/v1/exercises/{slugs[0]}/sheet.pdf", headers=auth(teacher))
    pages = len(PdfReader(io.BytesIO(r.content)).pages)
    assert pages == 2 * len(PdfReader(io.BytesIO(single.content)).pages)  # both exercises' sheets
