"""Helpers of the exam tests: a course with students, an exam or practice assignment on it, moving an assignment's
times as if time had passed, and one round of the background task that submits ended exams' drafts."""

from __future__ import annotations

from datetime import UTC, datetime, timedelta
from typing import Any

from server_helpers import Api, auth

from server import repository as repo
from server.courses import finalize_ended_exams


def iso(delta_minutes: float) -> str:
    return (datetime.now(UTC) + timedelta(minutes=delta_minutes)).isoformat()


def course_with(api: Api, teacher: dict[str, str], *students: dict[str, str]) -> int:
    r = api.client.post("/api/v1/courses", json={"name": "Klasse"}, headers=auth(teacher))
    assert r.status_code == 201, r.text
    for s in students:
        assert (
            api.client.post(
                "/api/v1/courses/join", json={"code": r.json()["join_code"]}, headers=auth(s)
            ).status_code
            == 200
        )
    return int(r.json()["id"])


def assign(
    api: Api,
    teacher: dict[str, str],
    course: int,
    exercises: list[str],
    *,
    exam: bool = True,
    start: float = -1,
    minutes: int = 90,
    **settings: Any,
) -> int:
    """An exam (starting `start` minutes from now, `minutes` long) or a practice assignment (until start +
    minutes) of `exercises`; returns its id."""
    body: dict[str, Any] = {
        "title": "Prüfung" if exam else "Übung",
        "exercises": exercises,
        "mode": "exam" if exam else "practice",
        "opens_at": iso(start),
        "settings": settings,
    }
    body.update({"duration_minutes": minutes} if exam else {"deadline": iso(start + minutes)})
    r = api.client.post(f"/api/v1/courses/{course}/assignments", json=body, headers=auth(teacher))
    assert r.status_code == 201, r.text
    return int(r.json()["id"])


def shift(api: Api, assignment: int, minutes: float) -> None:
    """Move an assignment's times `minutes` into the past, as if that much time had gone by."""
    with api.app.state.db.session() as db:
        a = repo.assignment_by_id(db, assignment)
        assert a is not None
        a.opens_at -= timedelta(minutes=minutes)
        a.deadline -= timedelta(minutes=minutes)
        db.commit()


def finalize(api: Api) -> int:
    """One round of the background task (on the app's event loop, which owns the worker pool)."""
    portal = api.client.portal
    assert portal is not None
    made: int = portal.call(finalize_ended_exams, api.app.state.db, api.app.state.workers)
    return made


def release(api: Api, teacher: dict[str, str], assignment: int) -> None:
    r = api.client.post(f"/api/v1/assignments/{assignment}/release", headers=auth(teacher))
    assert r.status_code == 200, r.text
