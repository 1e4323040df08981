"""Security of logging in and out: the redirect after login stays on the site, failed logins are limited per
user name and per address (one budget for /auth/token and /auth/login), logout revokes the token, a token
whose subject is not a user id is 401."""

from __future__ import annotations

import jwt
import pytest
from fastapi.testclient import TestClient
from server_helpers import PASSWORD, Api, auth, error_code

from server import repository as repo
from server.security import make_token, safe_redirect

# (what `next` says, where the browser may go): the same table is checked against the page's JS
REDIRECTS = [
    ("/", "/"),
    ("/exercises/nuten", "/exercises/nuten"),
    ("/practice?dialect=beckhoff#x", "/practice?dialect=beckhoff#x"),
    (None, "/"),
    ("", "/"),
    ("javascript:fetch('/api/v1/api-keys')", "/"),
    ("JavaScript:alert(1)", "/"),
    ("https://evil.example", "/"),
    ("http://127.0.0.1/", "/"),
    ("//evil.example", "/"),
    ("/\\evil.example", "/"),
    ("\\\\evil.example", "/"),
    ("/\t/evil.example", "/"),
    ("/\n/evil.example", "/"),
    (" /x", "/"),
    ("data:text/html,<script>alert(1)</script>", "/"),
    ("exercises", "/"),
    ("/x\x00", "/"),
    ("/x\x7f", "/"),
    ("/" + "a" * 3000, "/"),
]


@pytest.mark.parametrize(("target", "expected"), REDIRECTS)
def test_safe_redirect_allows_only_site_paths(target: str | None, expected: str) -> None:
    assert safe_redirect(target) == expected


@pytest.mark.parametrize(
    "target", ["javascript:alert(1)", "https://evil.example", "//evil.example", "/\\evil"]
)
def test_login_page_drops_a_foreign_next(api: Api, target: str) -> None:
    r = api.client.get("/login", params={"next": target}, follow_redirects=False)
    assert r.status_code == 303 and r.headers["location"] == "/login"


def test_login_page_keeps_a_site_next(api: Api) -> None:
    r = api.client.get("/login", params={"next": "/exercises/nuten"}, follow_redirects=False)
    assert r.status_code == 200 and "Anmelden" in r.text


def _token_login(api: Api, name: str, password: str) -> int:
    return api.client.post("/api/v1/auth/token", data={"username": name, "password": password}).status_code


def _session_login(api: Api, name: str, password: str) -> int:
    return api.client.post("/api/v1/auth/login", json={"username": name, "password": password}).status_code


def test_ten_wrong_passwords_for_one_user_are_refused(api: Api) -> None:
    api.settings.rate_login_per_minute = 5  # the default: failed logins per user name and minute
    try:
        victim, other = api.user(), api.user()
        # one budget for both ways of logging in
        codes = [
            (_token_login if i % 2 else _session_login)(api, victim["name"], f"guess {i}") for i in range(10)
        ]
        assert codes[:5] == [401] * 5 and codes[5:] == [429] * 5
        r = api.client.post("/api/v1/auth/token", data={"username": victim["name"], "password": PASSWORD})
        assert r.status_code == 429 and error_code(r) == "RATE_LIMITED" and int(r.headers["retry-after"]) >= 1
        # the user name is counted, not the address: others from the same address still log in
        assert _session_login(api, other["name"], PASSWORD) == 200
        # and the name's budget does not depend on how it is spelt
        assert _token_login(api, victim["name"].upper(), "guess") == 429
    finally:
        api.settings.rate_login_per_minute = 1000


def test_a_class_behind_one_address_logs_in_within_a_minute(api: Api) -> None:
    api.settings.rate_login_per_minute = 5
    try:
        students = [api.user() for _ in range(30)]
        # each mistypes once, then logs in: 30 failures and 30 logins from one address within a minute
        for s in students:
            assert _session_login(api, s["name"], "tippfehler") == 401
            assert _session_login(api, s["name"], PASSWORD) == 200
    finally:
        api.settings.rate_login_per_minute = 1000


def test_guessing_many_names_from_one_address_is_refused(api: Api) -> None:
    api.settings.rate_login_per_minute = 5
    limit = api.settings.rate_login_address_per_minute = 12  # within a minute here, however slow argon2 runs
    try:
        codes = [_token_login(api, f"nobody{i}", "guess") for i in range(limit + 3)]
        assert codes[:limit] == [401] * limit and codes[limit:] == [429] * 3
        # another address is not affected
        elsewhere = TestClient(api.app, base_url="http://127.0.0.1", client=("10.0.0.2", 50000))
        assert (
            elsewhere.post("/api/v1/auth/token", data={"username": "nobody", "password": "x"}).status_code
            == 401
        )
    finally:
        api.settings.rate_login_per_minute = 1000
        api.settings.rate_login_address_per_minute = 100


def test_logout_revokes_the_token(api: Api) -> None:
    student = api.user()
    r = api.client.post("/api/v1/auth/login", json={"username": student["name"], "password": PASSWORD})
    assert r.status_code == 200
    cookie = api.client.cookies.get("paltrainer_session")
    assert cookie
    bearer = api.client.post("/api/v1/auth/token", data={"username": student["name"], "password": PASSWORD})
    token = bearer.json()["access_token"]
    assert api.client.post("/api/v1/auth/logout").status_code == 204
    # the cookie's value, replayed after logout, is refused; so is every earlier token of the user
    api.client.cookies.clear()
    r = api.client.get("/api/v1/me", headers={"Cookie": f"paltrainer_session={cookie}"})
    assert r.status_code == 401 and error_code(r) == "BAD_TOKEN"
    r = api.client.get("/api/v1/me", headers={"Authorization": f"Bearer {token}"})
    assert r.status_code == 401 and error_code(r) == "BAD_TOKEN"
    # logging in again works
    r = api.client.post("/api/v1/auth/token", data={"username": student["name"], "password": PASSWORD})
    me = api.client.get("/api/v1/me", headers={"Authorization": f"Bearer {r.json()['access_token']}"})
    assert me.status_code == 200 and me.json()["username"] == student["name"]


def test_logout_with_a_bearer_token_revokes_it(api: Api) -> None:
    student = api.user()
    assert api.client.post("/api/v1/auth/logout", headers=auth(student)).status_code == 204
    r = api.client.get("/api/v1/me", headers=auth(student))
    assert r.status_code == 401 and error_code(r) == "BAD_TOKEN"


def test_logout_without_or_with_a_stale_token_is_204(api: Api) -> None:
    api.client.cookies.clear()
    assert api.client.post("/api/v1/auth/logout").status_code == 204
    r = api.client.post("/api/v1/auth/logout", headers={"Cookie": "paltrainer_session=not.a.token"})
    assert r.status_code == 204


@pytest.mark.parametrize(
    "sub", ["abc", "²", "٣", "-1", "0", "99999999999999999999", "2147483648", "1e3", " 1", ""]
)
def test_token_whose_subject_is_not_a_user_id_is_401(api: Api, sub: str) -> None:
    token = jwt.encode(
        {"sub": sub, "role": "admin", "exp": 4102444800}, api.settings.jwt_secret(), algorithm="HS256"
    )
    r = api.client.get("/api/v1/me", headers={"Authorization": f"Bearer {token}"})
    assert r.status_code == 401 and error_code(r) == "BAD_TOKEN"


def test_token_of_a_deleted_or_unknown_user_is_401(api: Api) -> None:
    token = make_token(api.settings.jwt_secret(), 10**9, "admin", 5)
    r = api.client.get("/api/v1/me", headers={"Authorization": f"Bearer {token}"})
    assert r.status_code == 401 and error_code(r) == "BAD_TOKEN"


def test_tokens_carry_the_users_token_version(api: Api) -> None:
    student = api.user()
    with api.app.state.db.session() as db:
        user = repo.user_by_name(db, student["name"])
        assert user is not None and user.token_version == 0


def test_the_pages_navigate_only_through_the_one_rule() -> None:
    """Every place the page script sends the browser somewhere goes through safeNext or loginUrl."""
    import re
    from pathlib import Path

    web = Path(__file__).parents[2] / "web" / "src"
    for path in web.glob("*.js"):
        for line in path.read_text(encoding="utf-8").splitlines():
            if re.search(r"location\.(href\s*=(?!=)|assign\(|replace\()|window\.open\(", line):
                assert "safeNext(" in line or "loginUrl()" in line, f"{path.name}: {line.strip()}"
