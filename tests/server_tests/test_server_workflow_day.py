"""A working day through the API: the instructor makes a student; the student types (draft), reloads, submits
twice and reopens the first submission; the instructor sees both in the results table, opens them, and
downloads the CSV, which parses with `;` and a BOM."""

from __future__ import annotations

import csv
import io

from server_helpers import GOOD, Api, auth, builtin_exercise, reference_of, unique


def test_a_day_with_pal_trainer(api: Api) -> None:
    teacher = api.user("instructor")
    slug = builtin_exercise(api, order=1, hints=[{"de": "Erst das Werkzeug.", "en": "The tool first."}])
    name, password = unique("azubi"), "ein langes Passwort"
    r = api.client.post("/api/v1/users", json={"username": name, "password": password}, headers=auth(teacher))
    assert r.status_code == 201 and r.json()["instructor"] == teacher["name"]

    # the student logs in in the browser (session cookie)
    assert (
        api.client.post("/api/v1/auth/login", json={"username": name, "password": password}).status_code
        == 200
    )
    try:
        listed = api.client.get("/api/v1/exercises").json()
        assert slug in {e["slug"] for e in listed}
        progress = {p["exercise"]: p for p in api.client.get("/api/v1/me/progress").json()}
        assert progress[slug]["status"] == "not_started"

        # types: the editor saves the draft while typing …
        typed = ""
        for line in GOOD.splitlines(keepends=True)[:3]:
            typed += line
            assert (
                api.client.put(f"/api/v1/exercises/{slug}/draft", json={"program": typed}).status_code == 200
            )
        # … reloads the page: the text is back
        assert api.client.get(f"/api/v1/exercises/{slug}/draft").json()["program"] == typed
        assert {p["exercise"]: p for p in api.client.get("/api/v1/me/progress").json()}[slug][
            "status"
        ] == "draft"
        assert api.client.get(f"/api/v1/exercises/{slug}/hints/1").json()["text"] == "Erst das Werkzeug."

        # submits twice
        first = api.client.post("/api/v1/submissions", json={"exercise": slug, "program": GOOD})
        second = api.client.post("/api/v1/submissions", json={"exercise": slug, "program": reference_of()})
        assert first.status_code == second.status_code == 201
        assert first.json()["score"] < 100 and second.json()["score"] == 100
        first_id, second_id = first.json()["id"], second.json()["id"]

        # "Meine Abgaben", and the first one opened again ("in den Editor laden")
        history = api.client.get(f"/api/v1/me/submissions?exercise={slug}").json()
        assert [h["id"] for h in history] == [second_id, first_id]
        reopened = api.client.get(f"/api/v1/submissions/{first_id}").json()
        assert reopened["program"] == GOOD and reopened["score"] == first.json()["score"]
        progress = {p["exercise"]: p for p in api.client.get("/api/v1/me/progress").json()}
        assert progress[slug]["status"] == "submitted" and progress[slug]["best_score"] == 100
        assert api.client.get(f"/api/v1/exercises/{slug}/solution").status_code == 200  # after a submission
    finally:
        api.client.post("/api/v1/auth/logout")
        api.client.cookies.clear()

    # the instructor: both submissions in the results table, each one opens with what the trainee saw
    table = api.client.get("/api/v1/results", headers=auth(teacher)).json()
    row = next(t for t in table["trainees"] if t["username"] == name)
    cell = row["results"][slug]
    assert cell["submissions"] == [second_id, first_id] and cell["best_submission"] == second_id
    assert cell["best_score"] == 100
    opened = api.client.get(f"/api/v1/submissions/{first_id}", headers=auth(teacher)).json()
    assert opened["program"] == GOOD and opened["diagnostics"] == reopened["diagnostics"]
    assert opened["grading"]["criteria"] and all("lines" in c for c in opened["grading"]["criteria"])

    r = api.client.get("/api/v1/results.csv", headers=auth(teacher))
    assert r.status_code == 200 and r.content[:3] == b"\xef\xbb\xbf"
    rows = list(csv.DictReader(io.StringIO(r.content.decode("utf-8-sig")), delimiter=";"))
    mine = [x for x in rows if x["Benutzer"] == name]
    assert len(mine) == 1 and mine[0]["Aufgabe"] == slug and mine[0]["Beste Punktzahl"] == "100"
    assert (
        mine[0]["Abgaben"] == "2"
        and mine[0]["Beste Abgabe"] == str(second_id)
        and mine[0]["Prozent"] == "100,0"
    )
