"""Class insights of an assignment (issue 19): per exercise the most frequent diagnostics and lost criteria of the
class, from each student's best submission; who may read them (student 403, another course's instructor 404,
admin 200)."""

from __future__ import annotations

from datetime import UTC, datetime, timedelta

import pytest
from server_helpers import BAD, GOOD, Api, auth, builtin_exercise, error_code

from server import insights


def _iso(delta_minutes: float) -> str:
    return (datetime.now(UTC) + timedelta(minutes=delta_minutes)).isoformat()


def _class(api: Api, n: int) -> tuple[dict[str, str], list[dict[str, str]], int, int, str]:
    """A course of `n` students with a practice assignment of one built-in exercise."""
    teacher = api.user("instructor")
    students = [api.user() for _ in range(n)]
    course = api.client.post("/api/v1/courses", json={"name": "Einsichten"}, headers=auth(teacher)).json()
    for s in students:
        assert (
            api.client.post(
                "/api/v1/courses/join", json={"code": course["join_code"]}, headers=auth(s)
            ).status_code
            == 200
        )
    slug = builtin_exercise(api)
    r = api.client.post(
        f"/api/v1/courses/{course['id']}/assignments",
        headers=auth(teacher),
        json={"title": "Gerade", "exercises": [slug], "opens_at": _iso(-1), "deadline": _iso(60)},
    )
    assert r.status_code == 201, r.text
    return teacher, students, int(course["id"]), int(r.json()["id"]), slug


def _submit(api: Api, who: dict[str, str], slug: str, program: str, assignment: int) -> None:
    r = api.client.post(
        "/api/v1/submissions",
        json={"exercise": slug, "program": program, "assignment": assignment},
        headers=auth(who),
    )
    assert r.status_code == 201, r.text


def test_insights_name_the_most_frequent_diagnostic_and_lost_criterion(api: Api) -> None:
    teacher, (s1, s2, s3, _s4), _, assignment, slug = _class(api, 4)
    _submit(api, s1, slug, BAD, assignment)
    _submit(api, s2, slug, BAD, assignment)
    _submit(api, s2, slug, BAD + "\n", assignment)  # a second try: still one student
    _submit(api, s3, slug, GOOD, assignment)
    # s4 submits nothing
    r = api.client.get(f"/api/v1/assignments/{assignment}/insights", headers=auth(teacher))
    assert r.status_code == 200, r.text
    body = r.json()
    assert (
        body["basis"] == "best" and body["students"] == 4 and body["scanned"] == 4 and body["capped"] is False
    )
    (ex,) = body["exercises"]
    assert ex["exercise"] == slug and ex["students"] == 3 and ex["graded"] == 3
    top = ex["diagnostics"][0]
    # "N20 G1 X1,5": the decimal comma is PAL-E010 in line 2, a G1 block, for s1 and s2
    assert top["code"] == "PAL-E010" and top["students"] == 2 and top["severity"] == "error"
    assert "1,5" in top["message"] and "1,5" in top["message_en"]
    assert top["where"] == {"block": "G1", "students": 2}
    lost = {c["id"]: c for c in ex["criteria"]}
    # nobody's program makes the exercise's part: all three lost the geometry criterion
    assert (
        lost["geometry"]["lost"] == 3
        and lost["geometry"]["of"] == 3
        and lost["geometry"]["name"] == "Geometrie"
    )
    assert lost["geometry"]["name_en"] == "geometry" and lost["geometry"]["points"] > 0
    # the syntax criterion: only the two with the error
    assert lost["syntax"]["lost"] == 2
    assert ex["criteria"][0]["id"] == "geometry"  # the most lost first


def test_insights_role_matrix(api: Api) -> None:
    teacher, (s1,), _, assignment, slug = _class(api, 1)
    _submit(api, s1, slug, BAD, assignment)
    path = f"/api/v1/assignments/{assignment}/insights"
    r = api.client.get(path, headers=auth(s1))
    assert r.status_code == 403 and error_code(r) == "FORBIDDEN"
    r = api.client.get(path, headers=auth(api.user("instructor")))  # another course's instructor
    assert r.status_code == 404 and error_code(r) == "ASSIGNMENT_NOT_FOUND"
    assert api.client.get(path, headers=auth(api.user("student"))).status_code == 404
    assert api.client.get(path, headers=auth(api.user("admin"))).status_code == 200
    assert api.client.get(path).status_code == 401
    r = api.client.get("/api/v1/assignments/999999/insights", headers=auth(teacher))
    assert r.status_code == 404 and error_code(r) == "ASSIGNMENT_NOT_FOUND"


def test_insights_read_a_bounded_number_of_submissions(api: Api, monkeypatch: pytest.MonkeyPatch) -> None:
    teacher, (s1, s2), _, assignment, slug = _class(api, 2)
    _submit(api, s1, slug, BAD, assignment)
    _submit(api, s2, slug, GOOD, assignment)
    _submit(api, s2, slug, GOOD + "\n", assignment)
    monkeypatch.setattr(insights, "MAX_SUBMISSIONS", 2)
    body = api.client.get(f"/api/v1/assignments/{assignment}/insights", headers=auth(teacher)).json()
    # the newest two (both s2's): s1's older submission is left out, and the answer says so
    assert body["capped"] is True and body["scanned"] == 2
    assert body["exercises"][0]["students"] == 1 and body["exercises"][0]["diagnostics"] == []


def test_feature_of_a_block() -> None:
    program = "N10 T1 TC1 M6\nN20 G47 R5 X10 (Anfahren G40)\nN30 M30 ; G1\n"
    assert insights.feature(program, 1) == "T1"
    assert insights.feature(program, 2) == "G47"
    assert insights.feature(program, 3) == "M30"
    assert insights.feature(program, 9) is None and insights.feature(program, 0) is None
    assert insights.feature("N10 G01 X1", 1) == "G1"


def test_course_page_route(api: Api) -> None:
    """/courses/{id}: the page for a logged-in user (the API decides what it shows), the login first without a
    session (and back here afterwards), the 404 page for a path that names no course."""
    from server.deps import SESSION_COOKIE

    r = api.client.get("/courses/7", follow_redirects=False)
    assert r.status_code == 303 and r.headers["location"] == "/login?next=/courses/7"
    teacher = api.user("instructor")
    cookie = {"Cookie": f"{SESSION_COOKIE}={teacher['Authorization'].removeprefix('Bearer ')}"}
    r = api.client.get("/courses/7", headers=cookie)
    assert r.status_code == 200 and 'data-page="course"' in r.text and 'id="course"' in r.text
    assert f'data-user="{teacher["name"]}"' in r.text
    for path in ("/courses/abc", "/courses/%C2%B2"):
        r = api.client.get(path, headers=cookie)
        assert r.status_code == 404 and "Seite nicht gefunden" in r.text
