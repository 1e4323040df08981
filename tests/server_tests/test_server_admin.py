"""The admin page and its API (issue 31): /admin and /api/v1/admin/… answer admins only (401 without login, 403 for
students, instructors and API keys); a role change by PATCH /api/v1/users/{name}; a learning platform registered
through the API is the one `paltrainer admin lti-platforms` lists, and bad input is a 422 naming every wrong field in
German; admins see and revoke every API key."""

from __future__ import annotations

from typing import Any

import pytest
from server_helpers import PASSWORD, Api, auth, error_code, unique

from core.cli import main
from server.models import SCOPES


def platform(**changes: Any) -> dict[str, Any]:
    host = f"https://{unique('moodle')}.schule.example"
    return {
        "issuer": host,
        "client_id": unique("client-"),
        "auth_login_url": f"{host}/mod/lti/auth.php",
        "token_url": f"{host}/mod/lti/token.php",
        "jwks_url": f"{host}/mod/lti/certs.php",
        "deployment_ids": ["1"],
        "name": "Moodle Berufsschule",
        **changes,
    }


def admin_routes(api: Api, admin: dict[str, str]) -> list[tuple[str, str, Any, int]]:
    """Every admin-only route: method, path, JSON body, the status an admin gets."""
    kid = api.client.post("/api/v1/admin/lti/keys/rotate", headers=auth(admin)).json()["kid"]
    api.client.post("/api/v1/admin/lti/keys/rotate", headers=auth(admin))  # the older one may be retired now
    student = api.user()["name"]
    return [
        ("GET", "/api/v1/admin/lti/platforms", None, 200),
        ("POST", "/api/v1/admin/lti/platforms", platform(), 201),
        ("POST", "/api/v1/admin/lti/registration-url", None, 200),
        ("GET", "/api/v1/admin/lti/keys", None, 200),
        ("POST", "/api/v1/admin/lti/keys/rotate", None, 201),
        ("POST", f"/api/v1/admin/lti/keys/{kid}/retire", None, 200),
        ("PATCH", f"/api/v1/users/{student}", {"role": "instructor"}, 200),
    ]


def test_role_matrix_of_the_admin_routes(api: Api) -> None:
    admin, student, instructor = api.user("admin"), api.user("student"), api.user("instructor")
    key = api.api_key(list(SCOPES), owner=admin)  # an admin's key acts for the admin, but is no admin
    for method, path, body, status in admin_routes(api, admin):
        anonymous = api.client.request(method, path, json=body)
        assert anonymous.status_code == 401 and error_code(anonymous) == "NOT_AUTHENTICATED", (method, path)
        for who in (student, instructor, key):
            r = api.client.request(method, path, json=body, headers=auth(who))
            assert r.status_code == 403 and error_code(r) == "FORBIDDEN", (method, path, who.get("name"))
        r = api.client.request(method, path, json=body, headers=auth(admin))
        assert r.status_code == status, (method, path, r.text)


def page_as(api: Api, who: dict[str, str] | None) -> Any:
    """GET /admin in a browser session of `who` (None: without one)."""
    api.client.cookies.clear()
    if who is not None:
        login = api.client.post("/api/v1/auth/login", json={"username": who["name"], "password": PASSWORD})
        assert login.status_code == 200, login.text
    try:
        return api.client.get("/admin", follow_redirects=False)
    finally:
        api.client.cookies.clear()


def test_admin_page_is_the_admin_page_only_for_admins(api: Api) -> None:
    """Without a session the page sends a visitor to the login (and back afterwards); anyone but an admin gets 403
    (the page says "Nur für Administratoren"); the header's link to it is shown by the script for admins only."""
    r = page_as(api, None)
    assert r.status_code == 303 and r.headers["location"] == "/login?next=/admin"
    for role, status in (("admin", 200), ("instructor", 403), ("student", 403)):
        r = page_as(api, api.user(role))
        assert r.status_code == status
        assert 'data-page="admin"' in r.text and f'data-role="{role}"' in r.text
        assert (
            '<span data-role="admin" hidden> · <a href="/admin" data-i18n="nav.admin">Verwaltung</a></span>'
            in r.text
        )


def test_admin_changes_a_role(api: Api) -> None:
    admin, trainee, teacher = api.user("admin"), api.user("student"), api.user("instructor")
    name = trainee["name"]
    # as a trainee: no instructor's routes
    assert api.client.get("/api/v1/api-keys", headers=auth(trainee)).status_code == 403
    r = api.client.patch(f"/api/v1/users/{name}", json={"role": "instructor"}, headers=auth(admin))
    assert r.status_code == 200 and r.json()["role"] == "instructor" and r.json()["username"] == name
    # the same token now acts as an instructor (the role is read from the account on every request)
    assert api.client.get("/api/v1/api-keys", headers=auth(trainee)).status_code == 200
    listed = {u["username"]: u for u in api.client.get("/api/v1/users", headers=auth(admin)).json()}
    assert listed[name]["role"] == "instructor"
    # back to a trainee, managed by an instructor, in one request
    r = api.client.patch(
        f"/api/v1/users/{name}", json={"role": "student", "instructor": teacher["name"]}, headers=auth(admin)
    )
    assert r.status_code == 200 and (r.json()["role"], r.json()["instructor"]) == ("student", teacher["name"])
    assert api.client.get("/api/v1/api-keys", headers=auth(trainee)).status_code == 403
    # a role change alone keeps the instructor
    r = api.client.patch(f"/api/v1/users/{name}", json={"role": "student"}, headers=auth(admin))
    assert r.json()["instructor"] == teacher["name"]
    # the instructor alone keeps the role
    r = api.client.patch(f"/api/v1/users/{name}", json={"instructor": None}, headers=auth(admin))
    assert (r.json()["role"], r.json()["instructor"]) == ("student", None)


def test_bad_role_changes(api: Api) -> None:
    admin, trainee = api.user("admin"), api.user("student")
    r = api.client.patch(f"/api/v1/users/{admin['name']}", json={"role": "student"}, headers=auth(admin))
    assert r.status_code == 409 and error_code(r) == "OWN_ACCOUNT"
    assert (
        "eigene" in r.json()["error"]["message"]
    )  # German: one cannot demote oneself (and lock everyone out)
    r = api.client.patch(f"/api/v1/users/{trainee['name']}", json={"role": "king"}, headers=auth(admin))
    assert r.status_code == 422 and error_code(r) == "VALIDATION"
    assert r.json()["error"]["message"] == (
        "Die Anfrage ist ungültig: Rolle »king« gibt es nicht (student, "
        "instructor oder admin) / no such role (student, instructor or admin)"
    )
    r = api.client.patch("/api/v1/users/niemand-hier", json={"role": "admin"}, headers=auth(admin))
    assert r.status_code == 404 and r.json()["error"]["message"] == "Benutzer »niemand-hier« nicht gefunden."
    # an unknown instructor changes nothing, the role neither
    r = api.client.patch(
        f"/api/v1/users/{trainee['name']}",
        json={"role": "instructor", "instructor": "niemand"},
        headers=auth(admin),
    )
    assert r.status_code == 404
    listed = {u["username"]: u for u in api.client.get("/api/v1/users", headers=auth(admin)).json()}
    assert listed[trainee["name"]]["role"] == "student"


def test_platform_registered_by_rest_is_listed_by_the_cli(
    api: Api, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    admin = api.user("admin")
    body = platform(deployment_ids=["7", "8"])
    r = api.client.post("/api/v1/admin/lti/platforms", json=body, headers=auth(admin))
    assert r.status_code == 201, r.text
    out = r.json()
    assert (out["issuer"], out["client_id"], out["deployment_ids"], out["name"]) == (
        body["issuer"],
        body["client_id"],
        ["7", "8"],
        "Moodle Berufsschule",
    )
    # again with another deployment: still one platform, the deployment added
    again = api.client.post(
        "/api/v1/admin/lti/platforms", json={**body, "deployment_ids": ["9"]}, headers=auth(admin)
    )
    assert again.json()["id"] == out["id"] and again.json()["deployment_ids"] == ["7", "8", "9"]
    listed = api.client.get("/api/v1/admin/lti/platforms", headers=auth(admin)).json()
    assert [p["deployment_ids"] for p in listed if p["id"] == out["id"]] == [["7", "8", "9"]]
    # the command line reads the same database
    settings = api.settings
    monkeypatch.setenv("PALTRAINER_DATA_DIR", str(settings.data_dir))
    monkeypatch.setenv("PALTRAINER_SECRET_KEY", settings.jwt_secret())
    if settings.database_url:
        monkeypatch.setenv("DATABASE_URL", settings.database_url)
    else:
        monkeypatch.delenv("DATABASE_URL", raising=False)
    capsys.readouterr()
    assert main(["admin", "lti-platforms"]) == 0
    assert (
        f"{out['id']}\t{body['issuer']}\t{body['client_id']}\t7,8,9\tMoodle Berufsschule"
        in capsys.readouterr().out
    )
    # and the keys: the state the page shows is the one the command line prints
    keys = api.client.get("/api/v1/admin/lti/keys", headers=auth(admin)).json()
    assert sum(k["state"] == "current" for k in keys) == 1
    assert main(["admin", "lti-keys"]) == 0
    printed = capsys.readouterr().out
    for k in keys:
        assert f"{k['kid']}\t" in printed and printed.split(f"{k['kid']}\t")[1].split("\n")[0].endswith(
            k["state"]
        )


def test_bad_platforms_are_422_in_german_naming_every_field(api: Api) -> None:
    admin = api.user("admin")
    before = len(api.client.get("/api/v1/admin/lti/platforms", headers=auth(admin)).json())
    body = platform(
        issuer="moodle.schule.example",
        auth_login_url="http://moodle.schule.example/auth.php",
        token_url="javascript:alert(1)",
        client_id="  ",
        deployment_ids=["", "x" * 300],
    )
    r = api.client.post("/api/v1/admin/lti/platforms", json=body, headers=auth(admin))
    assert r.status_code == 422 and error_code(r) == "VALIDATION"
    errors = {e["field"]: e["message"] for e in r.json()["error"]["details"]["errors"]}
    assert errors == {
        "issuer": "keine gültige https-Adresse (z. B. https://moodle.schule.de/…)",
        "auth_login_url": "keine gültige https-Adresse (z. B. https://moodle.schule.de/…)",
        "token_url": "keine gültige https-Adresse (z. B. https://moodle.schule.de/…)",
        "client_id": "darf nicht leer sein",
        "deployment_ids": "jede Deployment-ID 1 bis 255 Zeichen",
    }
    message = r.json()["error"]["message"]
    assert (
        message.startswith("Die Anfrage ist ungültig: issuer: keine gültige https-Adresse")
        and "token_url" in message
    )
    too_long = platform(name="N" * 201, deployment_ids=[str(i) for i in range(51)])
    r = api.client.post("/api/v1/admin/lti/platforms", json=too_long, headers=auth(admin))
    errors = {e["field"]: e["message"] for e in r.json()["error"]["details"]["errors"]}
    assert r.status_code == 422 and errors == {
        "name": "höchstens 200 Zeichen",
        "deployment_ids": "höchstens 50 Deployment-IDs",
    }
    for bad in (
        {**platform(), "issuer": "https://a.example/\u0000"},
        {**platform(), "extra": 1},
        [1, 2],
        "text",
    ):
        r = api.client.post("/api/v1/admin/lti/platforms", json=bad, headers=auth(admin))
        assert r.status_code == 422 and error_code(r) == "VALIDATION", r.text
    r = api.client.post(
        "/api/v1/admin/lti/platforms",
        content=b"{kaputt",
        headers={**auth(admin), "Content-Type": "application/json"},
    )
    assert r.status_code == 422
    assert len(api.client.get("/api/v1/admin/lti/platforms", headers=auth(admin)).json()) == before
    r = api.client.post("/api/v1/admin/lti/keys/no-such-kid/retire", headers=auth(admin))
    assert r.status_code == 404 and r.json()["error"]["message"] == "Nicht gefunden."


def test_registration_url_is_one_use_code_on_this_server(api: Api) -> None:
    admin = api.user("admin")
    r = api.client.post("/api/v1/admin/lti/registration-url", headers=auth(admin))
    assert r.status_code == 200 and r.json()["valid_days"] == 7
    assert r.json()["url"].startswith("http://127.0.0.1/lti/register?code=")
    other = api.client.post("/api/v1/admin/lti/registration-url", headers=auth(admin)).json()["url"]
    assert other != r.json()["url"]


def test_admin_sees_and_revokes_every_api_key(api: Api) -> None:
    admin, teacher = api.user("admin"), api.user("instructor")
    r = api.client.post(
        "/api/v1/api-keys", json={"name": "Schulsystem", "scopes": ["exercises:read"]}, headers=auth(teacher)
    )
    assert r.status_code == 201
    created = r.json()
    key = {"X-API-Key": created["key"]}
    assert api.client.get("/api/v1/exercises", headers=key).status_code == 200
    listed = {k["id"]: k for k in api.client.get("/api/v1/api-keys", headers=auth(admin)).json()}
    assert listed[created["id"]]["owner"] == teacher["name"] and "key" not in listed[created["id"]]
    r = api.client.delete(f"/api/v1/api-keys/{created['id']}", headers=auth(admin))
    assert r.status_code == 200 and r.json()["revoked_at"]
    assert api.client.get("/api/v1/exercises", headers=key).status_code == 401
    r = api.client.post("/api/v1/api-keys", json={"name": "x", "scopes": ["alles"]}, headers=auth(admin))
    assert r.status_code == 422 and r.json()["error"]["message"].startswith("Die Anfrage ist ungültig")
