"""Accounts: token and session login, who am I, users (admins), API keys (shown once, hashed, scoped, revocable)."""

from __future__ import annotations

from server_helpers import GOOD, PASSWORD, Api, auth, error_code

from server import repository as repo


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
        codes = [api.client.post("/api/v1/auth/token", data={"username": "x", "password": "y"}).status_code
                 for _ in range(3)]
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
    r = api.client.post("/api/v1/api-keys", json={"name": "moodle", "scopes": ["practice"]}, headers=auth(student))
    assert r.status_code == 403
    r = api.client.post("/api/v1/api-keys", json={"name": "moodle", "scopes": ["practice", "exercises:read"]},
                        headers=auth(instructor))
    assert r.status_code == 201
    created = r.json()
    key = created["key"]
    assert key.startswith("pal_") and created["last_used_at"] is None
    with api.app.state.db.session() as db:
        stored = repo.api_key_by_prefix(db, created["prefix"])
        assert stored is not None and key not in stored.key_hash
    me = api.client.get("/api/v1/me", headers={"X-API-Key": key}).json()
    assert me["kind"] == "api_key" and me["scopes"] == ["exercises:read", "practice"]
    assert api.client.post("/api/v1/check", json={"program": GOOD},
                           headers={"Authorization": f"Bearer {key}"}).status_code == 200
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
