"""Courses (issue 19): create, join with a code, members, class lists; who sees which course, member list,
submission and results (student / instructor of A / instructor of B / admin); migration 0006 turns the students
an instructor manages into the course "Meine Klasse"."""

from __future__ import annotations

from pathlib import Path

from server_helpers import GOOD, Api, auth, builtin_exercise, error_code, unique
from sqlalchemy import create_engine, text

from server.db import alembic_config


def _course(api: Api, instructor: dict[str, str], name: str = "FA 23a") -> dict[str, object]:
    r = api.client.post("/api/v1/courses", json={"name": name}, headers=auth(instructor))
    assert r.status_code == 201, r.text
    return dict(r.json())


def _join(api: Api, student: dict[str, str], code: object) -> None:
    r = api.client.post("/api/v1/courses/join", json={"code": code}, headers=auth(student))
    assert r.status_code == 200, r.text


def test_course_join_members_and_role_matrix(api: Api) -> None:
    a, b, admin = api.user("instructor"), api.user("instructor"), api.user("admin")
    s1, s2 = api.user(), api.user()
    ca, cb = _course(api, a, "Klasse A"), _course(api, b, "Klasse B")
    assert ca["instructors"] == [a["name"]] and ca["students"] == 0 and len(str(ca["join_code"])) == 8
    _join(api, s1, str(ca["join_code"]).lower())  # case does not matter
    _join(api, s1, ca["join_code"])  # twice is fine
    _join(api, s2, cb["join_code"])
    r = api.client.post("/api/v1/courses/join", json={"code": "NOPE1234"}, headers=auth(s1))
    assert r.status_code == 404 and error_code(r) == "JOIN_CODE_INVALID"

    # a student sees their course (without the join code), not its member list, not the other course
    r = api.client.get(f"/api/v1/courses/{ca['id']}", headers=auth(s1))
    assert r.status_code == 200 and r.json()["join_code"] is None and r.json()["students"] == 1
    assert api.client.get(f"/api/v1/courses/{ca['id']}/members", headers=auth(s1)).status_code == 403
    r = api.client.get(f"/api/v1/courses/{cb['id']}", headers=auth(s1))
    assert r.status_code == 404 and error_code(r) == "COURSE_NOT_FOUND"
    assert [c["id"] for c in api.client.get("/api/v1/courses", headers=auth(s1)).json()] == [ca["id"]]

    # instructor A: their course and members; B's course, members and changes are 404
    r = api.client.get(f"/api/v1/courses/{ca['id']}/members", headers=auth(a))
    assert r.json() == [
        {"username": a["name"], "role": "instructor", "signed_up": False},
        {"username": s1["name"], "role": "student", "signed_up": False},
    ]
    for method, path in (
        ("GET", ""),
        ("GET", "/members"),
        ("PATCH", ""),
        ("DELETE", ""),
        ("GET", "/assignments"),
    ):
        r = api.client.request(
            method,
            f"/api/v1/courses/{cb['id']}{path}",
            headers=auth(a),
            json={"name": "x"} if method == "PATCH" else None,
        )
        assert r.status_code == 404, (method, path)
    listed = {c["id"] for c in api.client.get("/api/v1/courses", headers=auth(a)).json()}
    assert ca["id"] in listed and cb["id"] not in listed
    # the admin sees every course
    listed = {c["id"] for c in api.client.get("/api/v1/courses", headers=auth(admin)).json()}
    assert {ca["id"], cb["id"]} <= listed

    # submissions: A sees s1's work in course A's assignment, not s1's free practice, not s2's (course B)
    slug = builtin_exercise(api)
    r = api.client.post(
        f"/api/v1/courses/{ca['id']}/assignments",
        headers=auth(a),
        json={
            "title": "Übung",
            "exercises": [slug],
            "opens_at": "2026-01-01T00:00:00Z",
            "deadline": "2099-01-01T00:00:00Z",
        },
    )
    assert r.status_code == 201, r.text
    practice_only = builtin_exercise(api)
    ids = {}
    for who, exercise in ((s1, slug), (s2, slug), (s1, practice_only)):
        r = api.client.post(
            "/api/v1/submissions", json={"exercise": exercise, "program": GOOD}, headers=auth(who)
        )
        assert r.status_code == 201, r.text
        ids[who["name"], exercise] = r.json()["id"]
    in_course, elsewhere, free = ids[s1["name"], slug], ids[s2["name"], slug], ids[s1["name"], practice_only]
    assert api.client.get(f"/api/v1/submissions/{in_course}", headers=auth(a)).status_code == 200
    for other in (elsewhere, free):
        assert api.client.get(f"/api/v1/submissions/{other}", headers=auth(a)).status_code == 404
    listed = {s["id"] for s in api.client.get("/api/v1/submissions", headers=auth(a)).json()}
    assert in_course in listed and not {elsewhere, free} & listed
    rows = {t["username"] for t in api.client.get("/api/v1/results", headers=auth(a)).json()["trainees"]}
    assert s1["name"] in rows and s2["name"] not in rows

    # what s1 did in course A stays A's after s1 leaves
    assert (
        api.client.delete(f"/api/v1/courses/{ca['id']}/members/{s1['name']}", headers=auth(a)).status_code
        == 204
    )
    assert api.client.get(f"/api/v1/submissions/{in_course}", headers=auth(a)).status_code == 200
    # adding by name: only students A manages (s1 joins with the code again); a second instructor
    r = api.client.post(f"/api/v1/courses/{ca['id']}/members", json={"username": s1["name"]}, headers=auth(a))
    assert r.status_code == 404 and error_code(r) == "USER_NOT_FOUND"
    _join(api, s1, ca["join_code"])
    r = api.client.post(
        f"/api/v1/courses/{ca['id']}/members",
        json={"username": s2["name"], "role": "instructor"},
        headers=auth(a),
    )
    assert r.status_code == 422 and error_code(r) == "NOT_AN_INSTRUCTOR"
    r = api.client.post(
        f"/api/v1/courses/{ca['id']}/members",
        json={"username": b["name"], "role": "instructor"},
        headers=auth(a),
    )
    assert r.status_code == 201
    assert api.client.get(f"/api/v1/courses/{ca['id']}", headers=auth(b)).json()["instructors"] == sorted(
        [a["name"], b["name"]]
    )
    old = ca["join_code"]
    r = api.client.patch(
        f"/api/v1/courses/{ca['id']}", json={"name": "Klasse A2", "new_join_code": True}, headers=auth(a)
    )
    assert r.status_code == 200 and r.json()["name"] == "Klasse A2" and r.json()["join_code"] != old
    # students cannot make courses
    r = api.client.post("/api/v1/courses", json={"name": "x"}, headers=auth(s1))
    assert r.status_code == 403 and error_code(r) == "FORBIDDEN"
    assert api.client.delete(f"/api/v1/courses/{ca['id']}", headers=auth(s1)).status_code == 403
    assert api.client.delete(f"/api/v1/courses/{cb['id']}", headers=auth(admin)).status_code == 204
    assert api.client.get(f"/api/v1/courses/{cb['id']}", headers=auth(admin)).status_code == 404


def test_class_list_into_a_course(api: Api) -> None:
    a = api.user("instructor")
    course = _course(api, a)
    names = [unique("kl"), unique("kl")]
    r = api.client.post(
        f"/api/v1/courses/{course['id']}/members/import",
        content=f"name\n{names[0]}\n{names[1]}\n",
        headers={**auth(a), "Content-Type": "text/csv"},
    )
    assert r.status_code == 201, r.text
    assert all(u["password"] for u in r.json()["users"])
    members = api.client.get(f"/api/v1/courses/{course['id']}/members", headers=auth(a)).json()
    assert {m["username"] for m in members if m["role"] == "student"} == set(names)


def test_students_an_instructor_creates_are_in_meine_klasse(api: Api) -> None:
    a = api.user("instructor")
    name = unique("neu")
    r = api.client.post(
        "/api/v1/users",
        json={"username": name, "password": "geheim-genug", "role": "student"},
        headers=auth(a),
    )
    assert r.status_code == 201, r.text
    courses = api.client.get("/api/v1/courses", headers=auth(a)).json()
    assert [c["name"] for c in courses] == ["Meine Klasse"]
    members = api.client.get(f"/api/v1/courses/{courses[0]['id']}/members", headers=auth(a)).json()
    assert {"username": name, "role": "student", "signed_up": False} in members


def test_migration_0006_makes_meine_klasse_from_managed_students(tmp_path: Path) -> None:
    from alembic import command

    url = f"sqlite:///{tmp_path / 'm.db'}"
    cfg = alembic_config(url)
    command.upgrade(cfg, "0005")
    engine = create_engine(url)
    with engine.begin() as conn:
        for uid, name, role, boss in (
            (1, "lehrer", "instructor", None),
            (2, "anna", "student", 1),
            (3, "ben", "student", 1),
            (4, "cem", "student", None),
        ):
            conn.execute(
                text(
                    "INSERT INTO users (id, username, password_hash, role, created_at, token_version, "
                    "instructor_id) VALUES (:i, :n, 'x', :r, '2026-01-01', 0, :b)"
                ),
                {"i": uid, "n": name, "r": role, "b": boss},
            )
    command.upgrade(cfg, "head")
    with engine.begin() as conn:
        courses = conn.execute(text("SELECT id, name, join_code FROM courses")).all()
        assert [(c[1], len(c[2])) for c in courses] == [("Meine Klasse", 8)]
        members = conn.execute(text("SELECT user_id, role FROM course_members ORDER BY user_id")).all()
        assert [tuple(m) for m in members] == [(1, "instructor"), (2, "student"), (3, "student")]
    command.downgrade(cfg, "0005")
    command.upgrade(cfg, "head")
    engine.dispose()
