"""Exercises: who sees what (students never the reference or hidden criteria), who may change what,
and the built-in exercises loaded from exercises/*.yaml."""

from __future__ import annotations

from pathlib import Path

from server_helpers import GOOD, Api, auth, error_code

from server import repository as repo
from server.seed import load_exercises


def test_student_sees_exercise_without_reference_or_hidden_criteria(api: Api) -> None:
    instructor, student = api.user("instructor"), api.user()
    ex = api.exercise(instructor)
    assert ex["reference_program"] == GOOD and ex["hidden_criteria"] == {"max_depth": 2}
    r = api.client.get(f"/api/v1/exercises/{ex['slug']}", headers=auth(student))
    assert r.status_code == 200
    body = r.json()
    assert (
        body["title_de"] == "Nuten"
        and body["rubric"] == {"points": 10}
        and body["owner"] == instructor["name"]
    )
    assert body["reference_program"] is None and body["hidden_criteria"] is None
    listed = {e["slug"]: e for e in api.client.get("/api/v1/exercises", headers=auth(student)).json()}
    assert listed[ex["slug"]]["reference_program"] is None
    other = api.user("instructor")
    assert (
        api.client.get(f"/api/v1/exercises/{ex['slug']}", headers=auth(other)).json()["reference_program"]
        is None
    )
    admin = api.user("admin")
    assert (
        api.client.get(f"/api/v1/exercises/{ex['slug']}", headers=auth(admin)).json()["reference_program"]
        == GOOD
    )


def test_exercises_need_a_login_or_a_key(api: Api) -> None:
    r = api.client.get("/api/v1/exercises")
    assert r.status_code == 401 and error_code(r) == "NOT_AUTHENTICATED"
    assert api.client.get("/api/v1/exercises", headers=api.api_key(["exercises:read"])).status_code == 200


def test_student_cannot_create_exercise(api: Api) -> None:
    student = api.user()
    r = api.client.post("/api/v1/exercises", json={"slug": "mine", "title_de": "x"}, headers=auth(student))
    assert r.status_code == 403 and error_code(r) == "FORBIDDEN"


def test_api_key_needs_exercises_write(api: Api) -> None:
    instructor = api.user("instructor")
    key = api.api_key(["exercises:read"], owner=instructor)
    r = api.client.post("/api/v1/exercises", json={"slug": "by-key", "title_de": "x"}, headers=key)
    assert r.status_code == 403 and error_code(r) == "MISSING_SCOPE"
    key = api.api_key(["exercises:read", "exercises:write"], owner=instructor)
    r = api.client.post("/api/v1/exercises", json={"slug": "by-key", "title_de": "x"}, headers=key)
    assert r.status_code == 201 and r.json()["owner"] == instructor["name"]


def test_create_validation_and_conflict(api: Api) -> None:
    instructor = api.user("instructor")
    ex = api.exercise(instructor)
    r = api.client.post(
        "/api/v1/exercises", json={"slug": ex["slug"], "title_de": "x"}, headers=auth(instructor)
    )
    assert r.status_code == 409 and error_code(r) == "EXERCISE_EXISTS"
    r = api.client.post(
        "/api/v1/exercises", json={"slug": "Bad Slug!", "title_de": "x"}, headers=auth(instructor)
    )
    assert r.status_code == 422 and error_code(r) == "VALIDATION"
    r = api.client.post(
        "/api/v1/exercises", json={"slug": "d1", "title_de": "x", "dialect": "iso"}, headers=auth(instructor)
    )
    assert r.status_code == 422 and error_code(r) == "UNKNOWN_DIALECT"


def test_only_owner_or_admin_updates_and_deletes(api: Api) -> None:
    owner, other, admin, student = (
        api.user("instructor"),
        api.user("instructor"),
        api.user("admin"),
        api.user(),
    )
    ex = api.exercise(owner)
    url = f"/api/v1/exercises/{ex['slug']}"
    for who in (other, student):
        r = api.client.patch(url, json={"title_de": "Neu"}, headers=auth(who))
        assert r.status_code == 403 and error_code(r) == "FORBIDDEN"
        assert api.client.delete(url, headers=auth(who)).status_code == 403
    r = api.client.patch(url, json={"title_de": "Neu"}, headers=auth(owner))
    assert (
        r.status_code == 200 and r.json()["title_de"] == "Neu" and r.json()["task_de"] == "Fräse die Nuten."
    )
    r = api.client.patch(url, json={"title_de": "Admin"}, headers=auth(admin))
    assert r.status_code == 200 and r.json()["title_de"] == "Admin"
    r = api.client.patch(url, json={"nonsense": 1}, headers=auth(owner))
    assert r.status_code == 422
    r = api.client.patch(url, json={"title_en": None, "rubric": None}, headers=auth(owner))
    assert r.status_code == 200 and r.json()["title_en"] == "Slots" and r.json()["rubric"] is None
    assert api.client.delete(url, headers=auth(owner)).status_code == 204
    r = api.client.get(url, headers=auth(owner))
    assert r.status_code == 404 and error_code(r) == "EXERCISE_NOT_FOUND"
    assert api.client.patch(url, json={"title_de": "x"}, headers=auth(owner)).status_code == 404
    assert api.client.delete(url, headers=auth(owner)).status_code == 404


def test_exercise_with_submissions_is_archived_not_deleted(api: Api) -> None:
    owner, student = api.user("instructor"), api.user()
    ex = api.exercise(owner)
    r = api.client.post(
        "/api/v1/submissions", json={"exercise": ex["slug"], "program": GOOD}, headers=auth(student)
    )
    assert r.status_code == 201
    r = api.client.delete(f"/api/v1/exercises/{ex['slug']}", headers=auth(owner))
    assert r.status_code == 204
    # hidden from the trainee, the submission kept; the owner still has it, marked archived
    assert api.client.get(f"/api/v1/exercises/{ex['slug']}", headers=auth(student)).status_code == 404
    assert [s["exercise"] for s in api.client.get("/api/v1/submissions", headers=auth(student)).json()] == [
        ex["slug"]
    ]
    assert api.client.get(f"/api/v1/exercises/{ex['slug']}", headers=auth(owner)).json()["archived"] is True


def test_exercise_tool_table_is_used_by_check(api: Api) -> None:
    owner = api.user("instructor")
    ex = api.exercise(owner, tools=[{"number": 3, "diameter": 10}])
    program = "N10 T1 TC1 M6\nN20 M30\n"
    free = api.client.post("/api/v1/check", json={"program": program}).json()["diagnostics"]
    bound = api.client.post("/api/v1/check", json={"program": program, "exercise": ex["slug"]}).json()[
        "diagnostics"
    ]
    assert not [d for d in free if d["severity"] == "error"]
    assert [d for d in bound if d["severity"] == "error"]


SHIPPED = Path(__file__).parents[2] / "exercises"
RUBRIC = """rubric:
  - {id: geometry, points: 50, tolerance: 0.05}
  - {id: safety, points: 20}
  - {id: technology, points: 10, tolerance: 0.1}
  - {id: syntax, points: 10}
  - {id: program_end, points: 10, hidden: true}
"""


def write_exercise(folder: Path, slug: str) -> None:
    folder.mkdir(parents=True, exist_ok=True)
    (folder / f"{slug}.nc").write_text(
        (SHIPPED / "pal-mill" / "pal-01-g1-gerade.nc").read_text(encoding="utf-8"), encoding="utf-8"
    )
    (folder / f"{slug}.yaml").write_text(
        f"format: 1\nid: {slug}\ntitle: {{de: Absätze, en: Steps}}\ntask: {{de: Fräsen, en: Mill}}\n"
        "stock: {min: [0, 0, -30], max: [80, 70, 0]}\n"
        "tools:\n  - {number: 1, kind: end_mill, diameter: 25, cutting_length: 40, overall_length: 100}\n"
        f"cutting_data:\n  - {{tool: 1, speed: 1200, feed: 150}}\nreference_file: {slug}.nc\n{RUBRIC}",
        encoding="utf-8",
    )


def test_builtin_exercises_are_loaded_from_yaml(api: Api, tmp_path: Path) -> None:
    folder = tmp_path / "exercises" / "pal-mill"
    write_exercise(folder, "builtin-steps")
    (folder / "broken.yaml").write_text("- just\n- a list\n", encoding="utf-8")
    (folder / "bad-syntax.yaml").write_text("title: [unclosed\n", encoding="utf-8")
    (folder / "incomplete.yaml").write_text("format: 1\nid: incomplete\ntitle: {de: x}\n", encoding="utf-8")
    with api.app.state.db.session() as db:
        assert load_exercises(db, tmp_path / "exercises") == 1
        assert load_exercises(db, tmp_path / "exercises") == 1  # again: updated, not duplicated
        assert load_exercises(db, tmp_path / "missing") == 0
        ex = repo.exercise_by_slug(db, "builtin-steps")
        assert ex is not None and ex.builtin and ex.title_en == "Steps" and ex.document is not None
    student, admin = api.user(), api.user("admin")
    body = api.client.get("/api/v1/exercises/builtin-steps", headers=auth(student)).json()
    assert body["builtin"] and body["gradable"] and body["reference_program"] is None
    assert body["hidden_criteria"] is None and "program_end" not in str(body["rubric"])
    assert body["tools"][0]["diameter"] == 25 and body["stock"] == {"min": [0, 0, -30], "max": [80, 70, 0]}
    full = api.client.get("/api/v1/exercises/builtin-steps", headers=auth(admin)).json()
    assert full["hidden_criteria"]["criteria"][0]["id"] == "program_end" and full["reference_program"]


def test_the_shipped_exercises_all_load(api: Api) -> None:
    with api.app.state.db.session() as db:
        assert load_exercises(db, SHIPPED) == len(list(SHIPPED.rglob("*.yaml")))
    student = api.user()
    slugs = {e["slug"]: e for e in api.client.get("/api/v1/exercises", headers=auth(student)).json()}
    assert slugs["pal-01-g1-gerade"]["gradable"] and slugs["pal-01-g1-gerade"]["title_en"]
