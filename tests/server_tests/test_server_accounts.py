"""Accounts: token and session login, who am I, users (admins), API keys (shown once, hashed, scoped, revocable)."""

from __future__ import annotations

from typing import Any

from fastapi.testclient import TestClient
from server_helpers import GOOD, PASSWORD, Api, auth, error_code, unique

from server import repository as repo
from server.security import password_problem


def test_token_flow(api: Api) -> None:
    student = api.user()
    r = api.client.post("/api/v1/auth/token", data={"username": student["name"], "password": PASSWORD})
    assert r.status_code == 200 and r.json()["token_type"] == "bearer"
    me = api.client.get("/api/v1/me", headers={"Authorization": f"Bearer {r.json()['access_token']}"})
    assert me.json() == {"kind": "user", "username": student["name"], "role": "student", "scopes": None}


def test_wrong_password_and_unknown_user_are_401(api: Api) -> None:
    student = api.user()
    for name, pw in ((student["name"], "wrong password"), ("nobody-here", PASSWORD)):
        r = api.client.post("/api/v1/auth/token", data={"username": name, "password": pw})
        assert r.status_code == 401 and error_code(r) == "BAD_CREDENTIALS"
    r = api.client.post("/api/v1/auth/token", data={"username": student["name"]})
    assert r.status_code == 422 and error_code(r) == "VALIDATION"


def test_browser_session_cookie(api: Api) -> None:
    student = api.user()
    r = api.client.post("/api/v1/auth/login", json={"username": student["name"], "password": PASSWORD})
    assert r.status_code == 200 and r.json()["role"] == "student"
    cookie = r.headers["set-cookie"]
    assert "HttpOnly" in cookie and "SameSite=lax" in cookie and "paltrainer_session=" in cookie
    assert api.client.get("/api/v1/me").json()["username"] == student["name"]
    assert api.client.post("/api/v1/auth/logout").status_code == 204
    r = api.client.get("/api/v1/me")
    assert r.status_code == 401 and error_code(r) == "NOT_AUTHENTICATED"


def test_bad_token_is_401(api: Api) -> None:
    r = api.client.get("/api/v1/me", headers={"Authorization": "Bearer not.a.token"})
    assert r.status_code == 401 and error_code(r) == "BAD_TOKEN"
    r = api.client.get("/api/v1/me")
    assert r.status_code == 401 and error_code(r) == "NOT_AUTHENTICATED"


def test_login_rate_limit_is_429(api: Api) -> None:
    old = api.settings.rate_login_per_minute
    api.settings.rate_login_per_minute = 2
    try:
        codes = [
            api.client.post("/api/v1/auth/token", data={"username": "x", "password": "y"}).status_code
            for _ in range(3)
        ]
        assert codes == [401, 401, 429]
    finally:
        api.settings.rate_login_per_minute = old


def test_only_admins_manage_users(api: Api) -> None:
    """Admins make users of any role; instructors only students of their own (test_server_instructors.py)."""
    admin, instructor = api.user("admin"), api.user("instructor")
    body = {"username": "new-student-1", "password": "long enough pw", "role": "student"}
    r = api.client.post("/api/v1/users", json={**body, "role": "instructor"}, headers=auth(instructor))
    assert r.status_code == 403 and error_code(r) == "FORBIDDEN"
    r = api.client.post("/api/v1/users", json=body, headers=auth(admin))
    assert r.status_code == 201 and r.json()["username"] == "new-student-1"
    r = api.client.post("/api/v1/users", json=body, headers=auth(admin))
    assert r.status_code == 409 and error_code(r) == "USER_EXISTS"
    r = api.client.post("/api/v1/users", json={**body, "username": "x2", "role": "king"}, headers=auth(admin))
    assert r.status_code == 422
    names = [u["username"] for u in api.client.get("/api/v1/users", headers=auth(admin)).json()]
    assert "new-student-1" in names and "password_hash" not in str(names)
    assert api.client.get("/api/v1/users", headers=auth(instructor)).json() == []  # nobody they manage
    assert api.client.get("/api/v1/users", headers=auth(api.user())).status_code == 403


def test_api_key_lifecycle(api: Api) -> None:
    instructor, student = api.user("instructor"), api.user()
    r = api.client.post(
        "/api/v1/api-keys", json={"name": "moodle", "scopes": ["practice"]}, headers=auth(student)
    )
    assert r.status_code == 403
    r = api.client.post(
        "/api/v1/api-keys",
        json={"name": "moodle", "scopes": ["practice", "exercises:read"]},
        headers=auth(instructor),
    )
    assert r.status_code == 201
    created = r.json()
    key = created["key"]
    assert key.startswith("pal_") and created["last_used_at"] is None
    with api.app.state.db.session() as db:
        stored = repo.api_key_by_prefix(db, created["prefix"])
        assert stored is not None and key not in stored.key_hash
    me = api.client.get("/api/v1/me", headers={"X-API-Key": key}).json()
    assert me["kind"] == "api_key" and me["scopes"] == ["exercises:read", "practice"]
    assert (
        api.client.post(
            "/api/v1/check", json={"program": GOOD}, headers={"Authorization": f"Bearer {key}"}
        ).status_code
        == 200
    )
    listed = api.client.get("/api/v1/api-keys", headers=auth(instructor)).json()
    assert [k["prefix"] for k in listed] == [created["prefix"]]
    assert "key" not in listed[0] and listed[0]["last_used_at"] is not None
    other = api.user("instructor")
    assert api.client.delete(f"/api/v1/api-keys/{created['id']}", headers=auth(other)).status_code == 404
    r = api.client.delete(f"/api/v1/api-keys/{created['id']}", headers=auth(instructor))
    assert r.status_code == 200 and r.json()["revoked_at"] is not None
    r = api.client.get("/api/v1/me", headers={"X-API-Key": key})
    assert r.status_code == 401 and error_code(r) == "BAD_API_KEY"


def test_wrong_api_key_is_401_and_scopes_are_checked(api: Api) -> None:
    r = api.client.get("/api/v1/me", headers={"X-API-Key": "pal_deadbeef_nothing"})
    assert r.status_code == 401 and error_code(r) == "BAD_API_KEY"
    key = api.api_key(["practice"])
    r = api.client.get("/api/v1/exercises", headers=key)
    assert r.status_code == 403 and error_code(r) == "MISSING_SCOPE"
    r = api.client.post("/api/v1/api-keys", json={"name": "x", "scopes": ["practice"]}, headers=key)
    assert r.status_code == 403


# --- accounts without the command line (issue 31): passwords, one-time passwords, deactivation, self-signup ----


def _token(api: Api, name: str, password: str = PASSWORD) -> Any:
    return api.client.post("/api/v1/auth/token", data={"username": name, "password": password})


def _bearer(api: Api, name: str, password: str = PASSWORD) -> dict[str, str]:
    r = _token(api, name, password)
    assert r.status_code == 200, r.text
    return {"Authorization": f"Bearer {r.json()['access_token']}"}


def _browser(api: Api) -> TestClient:
    """A browser of its own (its own cookies), on the same server."""
    return TestClient(api.app, base_url="http://127.0.0.1")


def test_one_password_rule_for_imports_new_users_and_changes() -> None:
    assert password_problem("kurz") == (
        "das Passwort braucht mindestens 8 Zeichen",
        "the password needs at least 8 characters",
    )
    assert password_problem("x" * 1001) is not None and password_problem("a\x00bcdefghi") is not None
    assert password_problem("acht8888") is None and password_problem("x" * 1000) is None


def test_the_rule_is_named_in_german_wherever_a_password_is_chosen(api: Api) -> None:
    instructor = api.user("instructor")
    r = api.client.post(
        "/api/v1/users", json={"username": unique("s"), "password": "kurz"}, headers=auth(instructor)
    )
    assert r.status_code == 422 and "mindestens 8 Zeichen" in r.json()["error"]["message"]
    r = api.client.post(
        "/api/v1/users/import", content=f"{unique('s')};kurz\n".encode(), headers=auth(instructor)
    )
    assert r.status_code == 422 and "mindestens 8 Zeichen" in r.json()["error"]["message"]
    r = api.client.post(
        "/api/v1/me/password",
        json={"current_password": PASSWORD, "new_password": "kurz"},
        headers=auth(instructor),
    )
    assert r.status_code == 422 and error_code(r) == "PASSWORD_RULE"
    assert "mindestens 8 Zeichen" in r.json()["error"]["message"]
    assert "at least 8 characters" in r.json()["error"]["message_en"]


def test_change_password_needs_the_right_current_one(api: Api) -> None:
    student = api.user()
    old_token = _bearer(api, student["name"])
    r = api.client.post(
        "/api/v1/me/password",
        json={"current_password": "not my password", "new_password": "ein neues Passwort"},
        headers=old_token,
    )
    assert r.status_code == 403 and error_code(r) == "WRONG_PASSWORD"
    assert r.json()["error"]["message"] == "Das bisherige Passwort ist falsch."
    r = api.client.post(
        "/api/v1/me/password",
        json={"current_password": PASSWORD, "new_password": PASSWORD},
        headers=old_token,
    )
    assert r.status_code == 422 and "unterscheiden" in r.json()["error"]["message"]
    browser = _browser(api)
    assert (
        browser.post(
            "/api/v1/auth/login", json={"username": student["name"], "password": PASSWORD}
        ).status_code
        == 200
    )
    r = browser.post(
        "/api/v1/me/password", json={"current_password": PASSWORD, "new_password": "ein neues Passwort"}
    )
    assert r.status_code == 204
    assert browser.get("/api/v1/me").json()["username"] == student["name"]  # this browser stays logged in
    assert api.client.get("/api/v1/me", headers=old_token).status_code == 401  # every other session ends
    assert _token(api, student["name"]).status_code == 401
    assert _token(api, student["name"], "ein neues Passwort").status_code == 200


def test_wrong_current_passwords_use_up_the_login_budget(api: Api) -> None:
    student = api.user()
    token = _bearer(api, student["name"])
    old = api.settings.rate_login_per_minute
    api.settings.rate_login_per_minute = 2
    try:
        codes = [
            api.client.post(
                "/api/v1/me/password",
                json={"current_password": f"guess {i}", "new_password": "ein neues Passwort"},
                headers=token,
            ).status_code
            for i in range(3)
        ]
    finally:
        api.settings.rate_login_per_minute = old
    assert codes == [403, 403, 429]


def _course(api: Api, instructor: dict[str, str]) -> dict[str, Any]:
    r = api.client.post("/api/v1/courses", json={"name": unique("FA ")}, headers=auth(instructor))
    assert r.status_code == 201, r.text
    return dict(r.json())


def test_instructor_resets_own_student_who_must_change_it_first(api: Api) -> None:
    instructor, name = api.user("instructor"), unique("azubi")
    r = api.client.post(
        "/api/v1/users", json={"username": name, "password": PASSWORD}, headers=auth(instructor)
    )
    assert r.status_code == 201 and r.json()["must_change_password"] is False
    before = _bearer(api, name)
    r = api.client.post(f"/api/v1/users/{name}/password-reset", headers=auth(instructor))
    assert r.status_code == 200 and r.json()["username"] == name
    once = r.json()["password"]
    assert len(once) >= 8 and once != PASSWORD
    assert api.client.get("/api/v1/me", headers=before).status_code == 401  # the old session ended
    assert _token(api, name).status_code == 401
    browser = _browser(api)
    r = browser.post("/api/v1/auth/login", json={"username": name, "password": once})
    assert r.status_code == 200 and r.json()["must_change_password"] is True
    for path in ("/api/v1/exercises", "/api/v1/me/progress", "/api/v1/courses"):
        r = browser.get(path)
        assert r.status_code == 403 and error_code(r) == "PASSWORD_CHANGE_REQUIRED", path
    assert browser.get("/api/v1/me").status_code == 200
    # the pages send the user to the change form
    r = browser.get("/", follow_redirects=False)
    assert r.status_code == 303 and r.headers["location"] == "/password"
    assert browser.get("/password").status_code == 200
    r = browser.post(
        "/api/v1/me/password", json={"current_password": once, "new_password": "mein eigenes Passwort"}
    )
    assert r.status_code == 204
    assert browser.get("/api/v1/exercises").status_code == 200
    assert browser.get("/", follow_redirects=False).status_code == 200
    listed = {u["username"]: u for u in api.client.get("/api/v1/users", headers=auth(instructor)).json()}
    assert listed[name]["must_change_password"] is False


def test_instructor_resets_a_student_of_a_course_they_teach(api: Api) -> None:
    instructor, student = api.user("instructor"), api.user()
    course = _course(api, instructor)
    r = api.client.post(f"/api/v1/users/{student['name']}/password-reset", headers=auth(instructor))
    assert r.status_code == 404  # not theirs yet
    assert (
        api.client.post(
            "/api/v1/courses/join", json={"code": course["join_code"]}, headers=auth(student)
        ).status_code
        == 200
    )
    r = api.client.post(f"/api/v1/users/{student['name']}/password-reset", headers=auth(instructor))
    assert r.status_code == 200
    assert _token(api, student["name"], r.json()["password"]).status_code == 200


def test_reset_of_anyone_else_is_404_alike_and_admins_reset_anyone(api: Api) -> None:
    instructor, other_instructor, admin = api.user("instructor"), api.user("instructor"), api.user("admin")
    foreign = api.user()
    course = _course(api, other_instructor)
    api.client.post("/api/v1/courses/join", json={"code": course["join_code"]}, headers=auth(foreign))
    bodies = []
    for name in (foreign["name"], other_instructor["name"], admin["name"], "gibt-es-nicht"):
        r = api.client.post(f"/api/v1/users/{name}/password-reset", headers=auth(instructor))
        assert r.status_code == 404 and error_code(r) == "USER_NOT_FOUND"
        bodies.append(r.json()["error"]["message"].replace(name, "…"))
    assert len(set(bodies)) == 1
    assert _token(api, foreign["name"]).status_code == 200  # nothing changed
    r = api.client.post(f"/api/v1/users/{foreign['name']}/password-reset", headers=auth(api.user()))
    assert r.status_code == 403
    for name in (foreign["name"], other_instructor["name"]):
        r = api.client.post(f"/api/v1/users/{name}/password-reset", headers=auth(admin))
        assert r.status_code == 200
        assert _token(api, name, r.json()["password"]).status_code == 200


def test_deactivated_user_cannot_log_in_and_their_tokens_and_keys_stop(api: Api) -> None:
    admin, instructor = api.user("admin"), api.user("instructor")
    token = _bearer(api, instructor["name"])
    key = api.api_key(["exercises:read"], owner=instructor)
    assert api.client.get("/api/v1/exercises", headers=key).status_code == 200
    browser = _browser(api)
    assert (
        browser.post(
            "/api/v1/auth/login", json={"username": instructor["name"], "password": PASSWORD}
        ).status_code
        == 200
    )
    r = api.client.post(f"/api/v1/users/{instructor['name']}/deactivate", headers=auth(instructor))
    assert r.status_code == 403
    r = api.client.post(f"/api/v1/users/{instructor['name']}/deactivate", headers=auth(admin))
    assert r.status_code == 200 and r.json()["active"] is False
    r = _token(api, instructor["name"])
    assert r.status_code == 403 and error_code(r) == "ACCOUNT_DEACTIVATED"
    assert "deaktiviert" in r.json()["error"]["message"]
    assert _token(api, instructor["name"], "wrong password").status_code == 401  # told only with the password
    assert api.client.get("/api/v1/me", headers=token).status_code == 401
    assert api.client.get("/api/v1/me", headers=auth(instructor)).status_code == 401
    assert browser.get("/api/v1/me").status_code == 401
    r = api.client.get("/api/v1/exercises", headers=key)
    assert r.status_code == 401 and error_code(r) == "BAD_API_KEY"
    r = api.client.post(f"/api/v1/users/{admin['name']}/deactivate", headers=auth(admin))
    assert r.status_code == 409 and error_code(r) == "OWN_ACCOUNT"
    assert api.client.post("/api/v1/users/gibt-es-nicht/deactivate", headers=auth(admin)).status_code == 404
    r = api.client.post(f"/api/v1/users/{instructor['name']}/activate", headers=auth(admin))
    assert r.status_code == 200 and r.json()["active"] is True
    assert _token(api, instructor["name"]).status_code == 200
    assert api.client.get("/api/v1/exercises", headers=key).status_code == 200


def _signup(client: TestClient, code: str, name: str, password: str = PASSWORD) -> Any:
    return client.post(
        "/api/v1/auth/signup", json={"join_code": code, "username": name, "password": password}
    )


def test_signup_is_off_by_default(api: Api) -> None:
    instructor = api.user("instructor")
    course = _course(api, instructor)
    r = _signup(api.client, course["join_code"], unique("neu"))
    assert r.status_code == 404 and error_code(r) == "NOT_FOUND"
    assert api.client.get("/signup").status_code == 404
    assert '<p id="signup-link" hidden>' in api.client.get("/login").text  # the login page does not offer it


def test_signup_with_a_course_code(api: Api) -> None:
    instructor = api.user("instructor")
    course = _course(api, instructor)
    api.settings.self_signup = "course-code"
    try:
        browser = _browser(api)
        taken = api.user()["name"]
        for code in ("FALSCH12", "", "x" * 40):
            r = _signup(browser, code, taken)
            assert r.status_code in (404, 422), r.text
        r = _signup(browser, "FALSCH12", taken)
        assert r.status_code == 404 and error_code(r) == "JOIN_CODE_INVALID"  # not 409: no name oracle
        r = _signup(browser, course["join_code"], taken)
        assert r.status_code == 409 and error_code(r) == "USER_EXISTS"
        name = unique("neu")
        r = _signup(browser, course["join_code"], name, "kurz")
        assert r.status_code == 422 and error_code(r) == "PASSWORD_RULE"
        r = _signup(browser, f" {course['join_code'].lower()} ", name)
        assert r.status_code == 201, r.text
        assert r.json()["role"] == "student" and r.json()["signed_up_to"] == course["id"]
        assert "paltrainer_session=" in r.headers["set-cookie"]
        assert browser.get("/api/v1/me").json()["username"] == name
        assert [c["id"] for c in browser.get("/api/v1/courses").json()] == [course["id"]]
        members = {
            m["username"]: m
            for m in api.client.get(
                f"/api/v1/courses/{course['id']}/members", headers=auth(instructor)
            ).json()
        }
        assert members[name]["signed_up"] is True and members[instructor["name"]]["signed_up"] is False
        assert api.client.get("/signup").status_code == 200
        assert '<p id="signup-link">' in api.client.get("/login").text
        r = api.client.delete(f"/api/v1/courses/{course['id']}/members/{name}", headers=auth(instructor))
        assert r.status_code == 204
        assert browser.get("/api/v1/courses").json() == []
    finally:
        api.settings.self_signup = "off"


def test_signup_is_rate_limited(api: Api) -> None:
    old = api.settings.rate_signup_per_minute
    api.settings.self_signup, api.settings.rate_signup_per_minute = "course-code", 2
    try:
        codes = [_signup(api.client, "FALSCH12", unique("neu")).status_code for _ in range(3)]
    finally:
        api.settings.self_signup, api.settings.rate_signup_per_minute = "off", old
    assert codes == [404, 404, 429]
