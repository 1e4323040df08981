"""Instructors and their students: who manages whom (users.instructor_id: POST /users, class lists), and the
role matrix of who sees which submission (student / instructor A / instructor B / admin / API keys)."""

from __future__ import annotations

import pytest
from server_helpers import GOOD, PASSWORD, Api, auth, builtin_exercise, error_code, unique

from server import repository as repo


def _set_instructor(api: Api, student: dict[str, str], instructor: dict[str, str]) -> None:
    with api.app.state.db.session() as db:
        user = repo.user_by_name(db, student["name"])
        boss = repo.user_by_name(db, instructor["name"])
        assert user is not None and boss is not None
        repo.set_instructor(db, user, boss.id)  # also enrols the student in the instructor's course


def _submit(api: Api, who: dict[str, str], slug: str) -> int:
    r = api.client.post("/api/v1/submissions", json={"exercise": slug, "program": GOOD}, headers=auth(who))
    assert r.status_code == 201, r.text
    return int(r.json()["id"])


def test_role_matrix(api: Api) -> None:
    a, b, admin = api.user("instructor"), api.user("instructor"), api.user("admin")
    s1, s2 = api.user(), api.user()
    _set_instructor(api, s1, a)
    _set_instructor(api, s2, b)
    builtin = builtin_exercise(api)
    b_own = api.exercise(b)["slug"]
    sub = {
        "s1_builtin": _submit(api, s1, builtin),
        "s2_builtin": _submit(api, s2, builtin),
        "s1_b_own": _submit(api, s1, b_own),
    }
    key_a = api.api_key(["submissions:read"], owner=a)
    platform = api.api_key(["submissions:read", "submissions:write"])
    sub["platform"] = _submit(api, platform, builtin)
    sees = {
        "student 1": (s1, {"s1_builtin", "s1_b_own"}),
        "student 2": (s2, {"s2_builtin"}),
        "instructor A": (a, {"s1_builtin", "s1_b_own"}),  # A's student, also on B's exercise
        "instructor B": (b, {"s2_builtin", "s1_b_own"}),  # B's student, and everything on B's exercise
        "admin": (admin, set(sub)),
        "key of A": (key_a, {"s1_builtin", "s1_b_own"}),
        "platform key": (platform, {"platform"}),
    }
    for who, (headers, visible) in sees.items():
        for name, sid in sub.items():
            r = api.client.get(f"/api/v1/submissions/{sid}", headers=auth(headers))
            if name in visible:
                assert r.status_code == 200, (who, name)
                assert r.json()["program"] == GOOD and r.json()["diagnostics"] is not None
                assert r.json()["grading"] is None or r.json()["grading"]["criteria"]
            else:
                assert r.status_code == 404 and error_code(r) == "SUBMISSION_NOT_FOUND", (who, name)
        listed = {s["id"] for s in api.client.get("/api/v1/submissions", headers=auth(headers)).json()}
        assert listed & set(sub.values()) == {sub[n] for n in visible}, who

    # results: instructors and admins; rows are their students
    for who, headers in (("student", s1), ("platform key", platform)):
        r = api.client.get("/api/v1/results", headers=auth(headers))
        assert r.status_code == 403 and error_code(r) == "FORBIDDEN", who
        assert api.client.get("/api/v1/results.csv", headers=auth(headers)).status_code == 403
    rows_a = {t["username"] for t in api.client.get("/api/v1/results", headers=auth(a)).json()["trainees"]}
    assert rows_a == {s1["name"]}
    rows_b = {t["username"] for t in api.client.get("/api/v1/results", headers=auth(b)).json()["trainees"]}
    assert rows_b == {s1["name"], s2["name"]}  # s1 through B's own exercise
    rows_admin = {
        t["username"] for t in api.client.get("/api/v1/results", headers=auth(admin)).json()["trainees"]
    }
    assert {s1["name"], s2["name"]} <= rows_admin and a["name"] not in rows_admin
    assert api.client.get("/api/v1/results").status_code == 401

    # users: admins all, instructors their students, students nothing
    assert {u["username"] for u in api.client.get("/api/v1/users", headers=auth(a)).json()} == {s1["name"]}
    by_name = {u["username"]: u for u in api.client.get("/api/v1/users", headers=auth(admin)).json()}
    assert by_name[s1["name"]]["instructor"] == a["name"] and by_name[a["name"]]["instructor"] is None
    assert api.client.get("/api/v1/users", headers=auth(s1)).status_code == 403
    assert api.client.get("/api/v1/users", headers=key_a).status_code == 403


def test_an_instructor_sees_the_hidden_criteria_of_their_students_work(api: Api) -> None:
    a, s1 = api.user("instructor"), api.user()
    _set_instructor(api, s1, a)
    slug = builtin_exercise(
        api,
        rubric=[
            {"id": "geometry", "points": 50},
            {"id": "safety", "points": 40},
            {"id": "syntax", "points": 10, "hidden": True},
        ],
    )
    sid = _submit(api, s1, slug)
    student_view = api.client.get(f"/api/v1/submissions/{sid}", headers=auth(s1)).json()
    assert "syntax" not in {c["id"] for c in student_view["grading"]["criteria"]}
    instructor_view = api.client.get(f"/api/v1/submissions/{sid}", headers=auth(a)).json()
    assert "syntax" in {c["id"] for c in instructor_view["grading"]["criteria"]}
    assert all("lines" in c for c in instructor_view["grading"]["criteria"])


def test_create_users_with_an_instructor(api: Api) -> None:
    admin, a, b, s = api.user("admin"), api.user("instructor"), api.user("instructor"), api.user()
    # admin: any role, managed by a named instructor
    name = unique("pupil")
    r = api.client.post(
        "/api/v1/users",
        json={"username": name, "password": PASSWORD, "instructor": a["name"]},
        headers=auth(admin),
    )
    assert r.status_code == 201 and r.json()["instructor"] == a["name"] and r.json()["role"] == "student"
    r = api.client.post(
        "/api/v1/users",
        json={"username": unique("x"), "password": PASSWORD, "instructor": s["name"]},
        headers=auth(admin),
    )
    assert r.status_code == 422 and error_code(r) == "NOT_AN_INSTRUCTOR"
    r = api.client.post(
        "/api/v1/users",
        json={"username": unique("x"), "password": PASSWORD, "instructor": "nobody-x"},
        headers=auth(admin),
    )
    assert r.status_code == 404 and error_code(r) == "USER_NOT_FOUND"
    r = api.client.post(
        "/api/v1/users",
        json={"username": unique("t"), "password": PASSWORD, "role": "instructor"},
        headers=auth(admin),
    )
    assert r.status_code == 201 and r.json()["instructor"] is None
    # an instructor: students managed by themselves, nothing else
    name = unique("pupil")
    r = api.client.post("/api/v1/users", json={"username": name, "password": PASSWORD}, headers=auth(a))
    assert r.status_code == 201 and r.json()["instructor"] == a["name"]
    assert name in {u["username"] for u in api.client.get("/api/v1/users", headers=auth(a)).json()}
    for body in ({"role": "instructor"}, {"role": "admin"}, {"instructor": b["name"]}):
        r = api.client.post(
            "/api/v1/users", json={"username": unique("x"), "password": PASSWORD, **body}, headers=auth(a)
        )
        assert r.status_code == 403 and error_code(r) == "FORBIDDEN", body
    r = api.client.post(
        "/api/v1/users", json={"username": unique("x"), "password": PASSWORD}, headers=auth(s)
    )
    assert r.status_code == 403
    r = api.client.post("/api/v1/users", json={"username": name, "password": PASSWORD}, headers=auth(a))
    assert r.status_code == 409 and error_code(r) == "USER_EXISTS"
    # the new student logs in
    r = api.client.post("/api/v1/auth/token", data={"username": name, "password": PASSWORD})
    assert r.status_code == 200


@pytest.mark.parametrize(
    "encoding,delimiter,header", [("utf-8-sig", ";", True), ("utf-8", ",", False), ("utf-8", ";", False)]
)
def test_class_list_import(api: Api, encoding: str, delimiter: str, header: bool) -> None:
    a = api.user("instructor")
    one, two = unique("klasse"), unique("klasse")
    lines = ([f"Name{delimiter}Passwort"] if header else []) + [
        f"{one}{delimiter}geheim-genug-1",
        f"{two}",
        "",
    ]
    data = "\r\n".join(lines).encode(encoding)
    r = api.client.post("/api/v1/users/import", content=data, headers={**auth(a), "Content-Type": "text/csv"})
    assert r.status_code == 201, r.text
    users = {u["username"]: u for u in r.json()["users"]}
    assert set(users) == {one, two} and all(u["instructor"] == a["name"] for u in users.values())
    assert users[one]["password"] is None  # given in the list: not repeated
    generated = users[two]["password"]
    assert isinstance(generated, str) and len(generated) >= 10
    assert (
        api.client.post("/api/v1/auth/token", data={"username": two, "password": generated}).status_code
        == 200
    )
    assert (
        api.client.post(
            "/api/v1/auth/token", data={"username": one, "password": "geheim-genug-1"}
        ).status_code
        == 200
    )
    assert {one, two} <= {u["username"] for u in api.client.get("/api/v1/users", headers=auth(a)).json()}


def test_class_list_errors_name_the_rows_and_import_nothing(api: Api) -> None:
    a, admin, s = api.user("instructor"), api.user("admin"), api.user()
    ok, taken = unique("klasse"), api.user()["name"]
    data = f"{ok};lang-genug-1\nMüller\n{ok}\nkurz;abc\n".encode()
    r = api.client.post("/api/v1/users/import", content=data, headers=auth(a))
    assert r.status_code == 422 and error_code(r) == "CLASS_LIST_INVALID"
    rows = {e["row"]: e for e in r.json()["error"]["details"]["errors"]}
    assert set(rows) == {2, 3, 4}
    assert (
        "Umlaute" in rows[2]["message"]
        and "doppelt" in rows[3]["message"]
        and "8 Zeichen" in rows[4]["message"]
    )
    assert "Zeile 2" in r.json()["error"]["message"] and "row 2" in r.json()["error"]["message_en"]
    r = api.client.post("/api/v1/users/import", content=f"{ok}\n{taken}\n".encode(), headers=auth(a))
    assert r.status_code == 409 and error_code(r) == "USER_EXISTS" and taken in r.json()["error"]["message"]
    assert ok not in {u["username"] for u in api.client.get("/api/v1/users", headers=auth(admin)).json()}
    r = api.client.post("/api/v1/users/import", content=b"\xff\xfe n\x00a\x00", headers=auth(a))
    assert r.status_code == 422 and error_code(r) == "CLASS_LIST_INVALID"
    r = api.client.post("/api/v1/users/import", content=b"", headers=auth(a))
    assert r.status_code == 422 and error_code(r) == "CLASS_LIST_INVALID"
    many = "".join(f"{unique('viele')}\n" for _ in range(101)).encode()
    r = api.client.post("/api/v1/users/import", content=many, headers=auth(a))
    assert r.status_code == 422 and "mehr als 100 Zeilen" in r.json()["error"]["message"]
    # students may not; instructors only for themselves; admins for a named instructor
    assert api.client.post("/api/v1/users/import", content=b"someone\n", headers=auth(s)).status_code == 403
    other = api.user("instructor")
    r = api.client.post(
        f"/api/v1/users/import?instructor={other['name']}", content=b"someone\n", headers=auth(a)
    )
    assert r.status_code == 403
    name = unique("klasse")
    r = api.client.post(
        f"/api/v1/users/import?instructor={other['name']}", content=f"{name}\n".encode(), headers=auth(admin)
    )
    assert r.status_code == 201 and r.json()["users"][0]["instructor"] == other["name"]


def test_admin_puts_an_existing_user_under_an_instructor(api: Api) -> None:
    admin, a, s = api.user("admin"), api.user("instructor"), api.user()
    slug = builtin_exercise(api)
    sid = _submit(api, s, slug)
    assert api.client.get(f"/api/v1/submissions/{sid}", headers=auth(a)).status_code == 404
    r = api.client.patch(f"/api/v1/users/{s['name']}", json={"instructor": a["name"]}, headers=auth(admin))
    assert r.status_code == 200 and r.json()["instructor"] == a["name"]
    assert api.client.get(f"/api/v1/submissions/{sid}", headers=auth(a)).status_code == 200
    r = api.client.patch(f"/api/v1/users/{s['name']}", json={"instructor": None}, headers=auth(admin))
    assert r.status_code == 200 and r.json()["instructor"] is None
    assert api.client.get(f"/api/v1/submissions/{sid}", headers=auth(a)).status_code == 404
    r = api.client.patch(f"/api/v1/users/{s['name']}", json={"instructor": a["name"]}, headers=auth(a))
    assert r.status_code == 403 and error_code(r) == "FORBIDDEN"
    r = api.client.patch("/api/v1/users/nobody-here", json={"instructor": a["name"]}, headers=auth(admin))
    assert r.status_code == 404 and error_code(r) == "USER_NOT_FOUND"
    r = api.client.patch(f"/api/v1/users/{s['name']}", json={"instructor": s["name"]}, headers=auth(admin))
    assert r.status_code == 422 and error_code(r) == "NOT_AN_INSTRUCTOR"
