"""The teacher has the last word (grades issue, section 3): an instructor of the course — or the one who manages
the student — sets a score and a comment on a submission; the trainee reads both, the instructor still sees the
grader's score, who and when is kept, and the results matrix, its CSV and the platform's gradebook use it. The
matrix's sum counts every exercise of the assignment."""

from __future__ import annotations

import csv
import io

from exam_helpers import assign, course_with
from server_helpers import BAD, GOOD, Api, auth, builtin_exercise, error_code

from server import repository as repo
from server.lti import ags


def _submit(api: Api, who: dict[str, str], slug: str, program: str = GOOD) -> dict[str, object]:
    r = api.client.post("/api/v1/submissions", json={"exercise": slug, "program": program}, headers=auth(who))
    assert r.status_code == 201, r.text
    return dict(r.json())


def test_an_override_is_what_counts_and_what_the_trainee_reads(api: Api) -> None:
    teacher, student, stranger, admin = (
        api.user("instructor"),
        api.user(),
        api.user("instructor"),
        api.user("admin"),
    )
    course = course_with(api, teacher, student)
    slug, other, third = builtin_exercise(api), builtin_exercise(api), builtin_exercise(api)
    practice = assign(api, teacher, course, [slug, other, third], exam=False, start=-1, minutes=600)
    submitted = _submit(api, student, slug, BAD)  # an error: the grader gives less than full marks
    auto = int(submitted["score"])  # type: ignore[call-overload]
    assert auto < 100 and submitted["override"] is None
    url = f"/api/v1/submissions/{submitted['id']}/override"

    # who may: the course's instructor and admins; not the student, not another instructor
    r = api.client.put(
        url, json={"score": 80, "comment": "Nur ein Tippfehler im Vorschub."}, headers=auth(student)
    )
    assert r.status_code == 403
    r = api.client.put(url, json={"score": 80}, headers=auth(stranger))
    assert r.status_code == 404 and error_code(r) == "SUBMISSION_NOT_FOUND"
    r = api.client.put(url, json={"score": 101}, headers=auth(teacher))
    assert r.status_code == 422 and error_code(r) == "OVERRIDE_OUT_OF_RANGE"
    r = api.client.put(
        url, json={"score": 80, "comment": "Nur ein Tippfehler im Vorschub."}, headers=auth(teacher)
    )
    assert r.status_code == 200, r.text
    seen = r.json()
    assert seen["score"] == 80 and seen["grading"]["score"] == auto  # the grader's score stays visible
    assert seen["override"]["by"] == teacher["name"] and seen["override"]["automatic_score"] == auto

    # the trainee reads both
    mine = api.client.get(f"/api/v1/submissions/{submitted['id']}", headers=auth(student)).json()
    assert mine["score"] == 80 and mine["lms"]["score"] == 80
    assert mine["override"]["message"] == (
        f"Punktzahl von der Lehrkraft geändert: 80 statt {auto} – Nur ein Tippfehler im Vorschub."
    )
    assert "Nur ein Tippfehler" in mine["lms"]["comment"]
    history = api.client.get(f"/api/v1/me/submissions?exercise={slug}", headers=auth(student)).json()
    assert (
        history[0]["score"] == 80 and history[0]["override"]["comment"] == "Nur ein Tippfehler im Vorschub."
    )
    item = next(
        a
        for a in api.client.get("/api/v1/me/assignments", headers=auth(student)).json()
        if a["id"] == practice
    )["items"][0]
    assert item["score"] == 80 and item["override"]["score"] == 80
    progress = {p["exercise"]: p for p in api.client.get("/api/v1/me/progress", headers=auth(student)).json()}
    assert progress[slug]["best_score"] == 80

    # the matrix: the override counts, the sum over all three exercises (two not tried: 0 of 100 each)
    table = api.client.get(f"/api/v1/assignments/{practice}/results", headers=auth(teacher)).json()
    row = table["trainees"][0]
    assert row["results"][slug]["score"] == 80 and row["results"][slug]["overridden"] is True
    assert (row["total"], row["max_total"], row["percent"]) == (80, 300, 26.7)
    text = api.client.get(f"/api/v1/assignments/{practice}/results.csv", headers=auth(teacher)).text
    rows = list(csv.reader(io.StringIO(text.lstrip("\ufeff")), delimiter=";"))
    assert rows[0][-1] == "Von der Lehrkraft geändert"
    assert next(r for r in rows if r[1] == slug)[2:5] == ["80", "100", "80,0"]
    assert next(r for r in rows if r[1] == "Summe")[2:5] == ["80", "300", "26,7"]
    overall = api.client.get("/api/v1/results", headers=auth(teacher)).json()
    assert (
        next(t for t in overall["trainees"] if t["username"] == student["name"])["results"][slug][
            "best_score"
        ]
        == 80
    )

    # the learning platform's gradebook takes the score that counts
    with api.app.state.db.session() as db:
        stored = repo.submission_by_id(db, int(submitted["id"]))  # type: ignore[call-overload]
        assert stored is not None and ags._percent(stored) == 80.0
        assert [(o.score, o.by_user_id is not None) for o in repo.overrides_of(db, stored.id)] == [(80, True)]

    # an admin takes it back: the grader's score again, both changes kept
    r = api.client.delete(url, headers=auth(admin))
    assert r.status_code == 200 and r.json()["score"] == auto and r.json()["override"] is None
    with api.app.state.db.session() as db:
        assert [o.score for o in repo.overrides_of(db, int(submitted["id"]))] == [80, None]  # type: ignore[call-overload]


def test_the_managing_instructor_may_override_practice_and_ungraded_work_cannot_be(api: Api) -> None:
    teacher = api.user("instructor")
    name = "verwaltet-" + teacher["name"]
    r = api.client.post(
        "/api/v1/users",
        json={"username": name, "password": "geheim-genug", "role": "student"},
        headers=auth(teacher),
    )
    assert r.status_code == 201
    token = api.client.post("/api/v1/auth/token", data={"username": name, "password": "geheim-genug"}).json()
    student = {"name": name, "Authorization": f"Bearer {token['access_token']}"}
    submitted = _submit(api, student, builtin_exercise(api))
    r = api.client.put(
        f"/api/v1/submissions/{submitted['id']}/override",
        json={"score": 95, "comment": ""},
        headers=auth(teacher),
    )
    assert r.status_code == 200 and r.json()["override"]["message"].endswith(f"95 statt {submitted['score']}")
    ungraded = api.exercise(teacher)["slug"]  # an exercise without a grader's document
    submitted = _submit(api, student, ungraded)
    r = api.client.put(
        f"/api/v1/submissions/{submitted['id']}/override", json={"score": 5}, headers=auth(teacher)
    )
    assert r.status_code == 409 and error_code(r) == "NOT_GRADED"
