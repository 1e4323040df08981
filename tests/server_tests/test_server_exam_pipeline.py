"""During an exam the REST pipeline follows the exam's settings like the live socket and the 3D view do: a trainee
whose running exam switches live diagnostics off gets no /check or /run, one whose exam switches 3D off no
/simulate; everybody else, and the same trainee after the exam, works as before (issue 19)."""

from __future__ import annotations

from datetime import UTC, datetime, timedelta
from typing import Any

from server_helpers import GOOD, Api, auth, builtin_exercise, error_code

from server import repository as repo
from server.jobs import HAS_SIM


def _exam(api: Api, student: dict[str, str], **settings: Any) -> tuple[int, str]:
    teacher = api.user("instructor")
    course = api.client.post("/api/v1/courses", json={"name": "Prüfung"}, headers=auth(teacher)).json()
    assert (
        api.client.post(
            "/api/v1/courses/join", json={"code": course["join_code"]}, headers=auth(student)
        ).status_code
        == 200
    )
    slug = builtin_exercise(api)
    r = api.client.post(
        f"/api/v1/courses/{course['id']}/assignments",
        headers=auth(teacher),
        json={
            "title": "Prüfung G1",
            "exercises": [slug],
            "mode": "exam",
            "duration_minutes": 90,
            "opens_at": (datetime.now(UTC) - timedelta(minutes=1)).isoformat(),
            "settings": settings,
        },
    )
    assert r.status_code == 201, r.text
    return int(r.json()["id"]), slug


def _post(api: Api, who: dict[str, str], path: str, exercise: str | None = None) -> Any:
    return api.client.post(f"/api/v1/{path}", json={"program": GOOD, "exercise": exercise}, headers=auth(who))


def test_running_exam_refuses_check_run_and_simulate(api: Api) -> None:
    student, free = api.user(), api.user()
    exam, _ = _exam(api, student)
    paths = ["check", "run", *(["simulate"] if HAS_SIM else [])]
    for path in paths:
        r = _post(api, student, path)
        assert r.status_code == 403 and error_code(r) == "EXAM_RUNNING", (path, r.text)
        assert "Prüfung" in r.json()["error"]["message"]
        assert _post(api, free, path).status_code == 200, path  # not in the exam: as before
    with api.app.state.db.session() as db:  # the exam is over: free practice again
        a = repo.assignment_by_id(db, exam)
        assert a is not None
        a.opens_at -= timedelta(minutes=91)
        a.deadline -= timedelta(minutes=91)
        db.commit()
    for path in paths:
        assert _post(api, student, path).status_code == 200, path


def test_exam_settings_decide_which_pipeline_requests_are_allowed(api: Api) -> None:
    student = api.user()
    _, slug = _exam(api, student, live_diagnostics=True, viz=False)
    assert _post(api, student, "check", slug).status_code == 200
    assert _post(api, student, "run", slug).status_code == 200
    if HAS_SIM:
        r = _post(api, student, "simulate", slug)
        assert r.status_code == 403 and error_code(r) == "EXAM_RUNNING"
    # without the exam's exercise it is free practice, which the exam does not allow
    r = _post(api, student, "check")
    assert r.status_code == 403 and error_code(r) == "EXAM_RUNNING"
