"""The built-in turning exercises through the API: seeded, listed with their dialect, a reference submission scores
100, and their drawing is the turned part's, dimensioned (Ø, lengths from the face)."""

from __future__ import annotations

from server_helpers import Api, auth

from core.exercises import EXERCISES_DIR, load_exercise
from server.seed import load_exercises


def test_builtin_turning_exercises_are_listed_and_graded(api: Api) -> None:
    with api.app.state.db.session() as db:
        assert load_exercises(db, EXERCISES_DIR / "traub-tx8d") >= 8
    student = api.user()
    listed = api.client.get("/api/v1/exercises", headers=auth(student))
    assert listed.status_code == 200
    body = listed.json()
    items = body["items"] if isinstance(body, dict) else body
    turning = {e["slug"]: e for e in items if e["dialect"] == "traub-tx8d"}
    assert "traub-01-srk-fase" in turning and len(turning) >= 8
    one = api.client.get("/api/v1/exercises/traub-01-srk-fase", headers=auth(student)).json()
    assert one["gradable"] and one["stock"]["max"][2] == 0
    assert {"tool": 1, "speed": 1000.0, "cutting_speed": None, "feed": 0.2, "spindle": "M4"} in one[
        "cutting_data"
    ]
    reference = load_exercise(EXERCISES_DIR / "traub-tx8d" / "traub-01-srk-fase.yaml").reference
    r = api.client.post(
        "/api/v1/submissions",
        json={"exercise": "traub-01-srk-fase", "program": reference},
        headers=auth(student),
    )
    assert r.status_code == 201, r.text
    assert r.json()["score"] == 100
    wrong = reference.replace("G1 X40 D2", "G1 X39 D2")
    r = api.client.post(
        "/api/v1/submissions", json={"exercise": "traub-01-srk-fase", "program": wrong}, headers=auth(student)
    )
    assert r.status_code == 201 and r.json()["score"] == 67  # geometry: 1 of its 3 features kept, 17 of 50
    geometry = next(c for c in r.json()["grading"]["criteria"] if c["id"] == "geometry")
    assert geometry["status"] == "partial" and "Ø39" in geometry["message"]
    drawing = api.client.get("/api/v1/exercises/traub-01-srk-fase/drawing.svg", headers=auth(student))
    assert drawing.status_code == 200 and drawing.headers["content-type"].startswith("image/svg+xml")
    assert (
        ">Ø40</text>" in drawing.text
        and ">2×45°</text>" in drawing.text
        and "Zeichnung für Drehteile" not in drawing.text
    )
