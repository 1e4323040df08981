"""Submissions: the result (diagnostics and run summary, `grading` null until the grader exists), who sees
which submission, CSV export, API keys submitting for learners, the submit rate limit."""

from __future__ import annotations

import csv
import io

from server_helpers import BAD, GOOD, Api, auth, error_code


def test_submission_result_and_visibility(api: Api) -> None:
    owner, alice, bob = api.user("instructor"), api.user(), api.user()
    ex = api.exercise(owner)
    r = api.client.post(
        "/api/v1/submissions", json={"exercise": ex["slug"], "program": BAD}, headers=auth(alice)
    )
    assert r.status_code == 201
    sub = r.json()
    assert sub["grading"] is None and sub["score"] is None  # this exercise has no stock: not gradable
    assert sub["error_count"] >= 1 and sub["user"] == alice["name"]
    assert "PAL-E010" in [d["code"] for d in sub["diagnostics"]] and sub["program"] == BAD
    r = api.client.post(
        "/api/v1/submissions", json={"exercise": ex["slug"], "program": GOOD}, headers=auth(bob)
    )
    bob_sub = r.json()
    assert bob_sub["error_count"] == 0 and bob_sub["summary"]["feed"] == 2

    mine = api.client.get("/api/v1/submissions", headers=auth(alice)).json()
    assert [s["id"] for s in mine] == [sub["id"]] and mine[0]["program"] is None
    r = api.client.get(f"/api/v1/submissions/{bob_sub['id']}", headers=auth(alice))
    assert r.status_code == 404 and error_code(r) == "SUBMISSION_NOT_FOUND"
    assert api.client.get(f"/api/v1/submissions/{sub['id']}", headers=auth(alice)).json()["program"] == BAD

    listed = api.client.get(
        "/api/v1/submissions", params={"exercise": ex["slug"]}, headers=auth(owner)
    ).json()
    assert {s["id"] for s in listed} == {sub["id"], bob_sub["id"]}
    assert api.client.get(f"/api/v1/submissions/{bob_sub['id']}", headers=auth(owner)).status_code == 200
    stranger = api.user("instructor")
    assert api.client.get("/api/v1/submissions", headers=auth(stranger)).json() == []
    assert api.client.get(f"/api/v1/submissions/{sub['id']}", headers=auth(stranger)).status_code == 404
    admin = api.user("admin")
    assert api.client.get(f"/api/v1/submissions/{sub['id']}", headers=auth(admin)).status_code == 200


def test_submission_errors(api: Api) -> None:
    student = api.user()
    r = api.client.post(
        "/api/v1/submissions", json={"exercise": "nope", "program": GOOD}, headers=auth(student)
    )
    assert r.status_code == 404 and error_code(r) == "EXERCISE_NOT_FOUND"
    r = api.client.post("/api/v1/submissions", json={"exercise": "nope", "program": GOOD})
    assert r.status_code == 401
    r = api.client.post("/api/v1/submissions", json={"program": GOOD}, headers=auth(student))
    assert r.status_code == 422 and error_code(r) == "VALIDATION"
    assert api.client.get("/api/v1/submissions/999999", headers=auth(student)).status_code == 404
    r = api.client.get("/api/v1/submissions", params={"exercise": "nope"}, headers=auth(student))
    assert r.status_code == 404
    owner = api.user("instructor")
    ex = api.exercise(owner)
    big = "N10 G0 X0\n" * (api.settings.max_program_chars // 10 + 1)
    r = api.client.post(
        "/api/v1/submissions", json={"exercise": ex["slug"], "program": big}, headers=auth(student)
    )
    assert r.status_code == 413 and error_code(r) == "PROGRAM_TOO_LARGE"


def test_csv_export(api: Api) -> None:
    owner, student = api.user("instructor"), api.user()
    ex = api.exercise(owner)
    api.client.post(
        "/api/v1/submissions", json={"exercise": ex["slug"], "program": BAD}, headers=auth(student)
    )
    r = api.client.get("/api/v1/submissions/export.csv", params={"exercise": ex["slug"]}, headers=auth(owner))
    assert r.status_code == 200 and r.headers["content-type"].startswith("text/csv")
    assert r.content.startswith("\ufeff".encode())  # UTF-8 with BOM, `;`: German Excel
    rows = list(csv.DictReader(io.StringIO(r.content.decode("utf-8-sig")), delimiter=";"))
    assert len(rows) == 1 and rows[0]["Benutzer"] == student["name"] and rows[0]["Punktzahl"] == ""
    assert int(rows[0]["Fehler"]) >= 1
    r = api.client.get("/api/v1/submissions/export.csv", headers=auth(student))
    assert r.status_code == 403 and error_code(r) == "FORBIDDEN"


def test_api_key_submits_for_a_learner(api: Api) -> None:
    owner = api.user("instructor")
    ex = api.exercise(owner)
    key = api.api_key(["submissions:read", "submissions:write"])
    r = api.client.post(
        "/api/v1/submissions",
        json={"exercise": ex["slug"], "program": GOOD, "external_user": "moodle-42"},
        headers=key,
    )
    assert r.status_code == 201 and r.json()["external_user"] == "moodle-42" and r.json()["user"] is None
    assert [s["id"] for s in api.client.get("/api/v1/submissions", headers=key).json()] == [r.json()["id"]]
    assert api.client.get(f"/api/v1/submissions/{r.json()['id']}", headers=key).status_code == 200
    other_key = api.api_key(["submissions:read"])
    assert api.client.get(f"/api/v1/submissions/{r.json()['id']}", headers=other_key).status_code == 404
    assert api.client.get("/api/v1/submissions", headers=other_key).json() == []
    r = api.client.post(
        "/api/v1/submissions", json={"exercise": ex["slug"], "program": GOOD}, headers=other_key
    )
    assert r.status_code == 403 and error_code(r) == "MISSING_SCOPE"
    read_only = api.api_key(["practice"])
    r = api.client.get("/api/v1/submissions", headers=read_only)
    assert r.status_code == 403 and error_code(r) == "MISSING_SCOPE"


def test_submit_rate_limit_is_429(api: Api) -> None:
    owner, student = api.user("instructor"), api.user()
    ex = api.exercise(owner)
    old = api.settings.rate_submit_per_minute
    api.settings.rate_submit_per_minute = 2
    try:
        codes = [
            api.client.post(
                "/api/v1/submissions", json={"exercise": ex["slug"], "program": GOOD}, headers=auth(student)
            ).status_code
            for _ in range(3)
        ]
        assert codes == [201, 201, 429]
    finally:
        api.settings.rate_submit_per_minute = old


RUBRIC = {
    "criteria": [
        {"id": "geometry", "points": 50, "tolerance": 0.05},
        {"id": "safety", "points": 20},
        {"id": "technology", "points": 10, "tolerance": 0.1},
        {"id": "syntax", "points": 10},
    ]
}
HIDDEN = {"criteria": [{"id": "program_end", "points": 10}]}


def test_gradable_exercise_is_graded_and_hidden_criteria_stay_hidden(api: Api) -> None:
    owner, student = api.user("instructor"), api.user()
    ex = api.exercise(
        owner, stock={"min": [0, 0, -30], "max": [80, 70, 0]}, rubric=RUBRIC, hidden_criteria=HIDDEN
    )
    assert ex["gradable"]
    good = api.client.post(
        "/api/v1/submissions", json={"exercise": ex["slug"], "program": GOOD}, headers=auth(student)
    ).json()
    assert good["score"] == 100 and good["grading"]["max_score"] == 100
    assert [c["id"] for c in good["grading"]["criteria"]] == ["geometry", "safety", "technology", "syntax"]
    bad = api.client.post(
        "/api/v1/submissions", json={"exercise": ex["slug"], "program": BAD}, headers=auth(student)
    ).json()
    assert bad["score"] < 100
    seen_by_owner = api.client.get(f"/api/v1/submissions/{good['id']}", headers=auth(owner)).json()
    assert "program_end" in [c["id"] for c in seen_by_owner["grading"]["criteria"]]
    r = api.client.get("/api/v1/submissions/export.csv", params={"exercise": ex["slug"]}, headers=auth(owner))
    rows = csv.DictReader(io.StringIO(r.content.decode("utf-8-sig")), delimiter=";")
    scores = sorted(int(row["Punktzahl"]) for row in rows)
    assert scores == sorted([bad["score"], 100])
    r = api.client.patch(f"/api/v1/exercises/{ex['slug']}", json={"stock": None}, headers=auth(owner))
    assert r.status_code == 200 and not r.json()["gradable"]
