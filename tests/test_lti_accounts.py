"""Accounts of platform users: a launch reaches only the account it made for that platform user (the link
platform + sub), never one that merely carries the name it would give — the name lti<platform>-<sha256(sub)> is
predictable (Moodle's sub is the numeric user id). Local accounts cannot take such names."""

from __future__ import annotations

import hashlib
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
from fastapi.testclient import TestClient
from lti_testplatform import (
    INSTRUCTOR,
    LEARNER,
    LTI,
    Platform,
    admin_headers,
    launch,
    registered_platform,
    tool_client,
)
from sqlalchemy import select

from core.cli import main
from server import repository as repo
from server.models import CourseMember, LtiContext, LtiPlatform, LtiUser, User
from server.security import hash_password, make_token

PASSWORD = "ein geheimes Passwort"


@pytest.fixture(scope="module")
def client(tmp_path_factory: pytest.TempPathFactory) -> Iterator[TestClient]:
    with tool_client(tmp_path_factory.mktemp("lti-accounts")) as c:
        yield c


@pytest.fixture(scope="module")
def platform(client: TestClient) -> Platform:
    return registered_platform(client)


def db(client: TestClient) -> Any:
    return client.app.state.db.session()  # type: ignore[attr-defined]


def generated_name(client: TestClient, platform: Platform, sub: str) -> str:
    """The name a first launch of `sub` gives its account: anyone can work it out."""
    with db(client) as s:
        pid = s.scalars(select(LtiPlatform.id).where(LtiPlatform.issuer == platform.issuer)).one()
    return f"lti{pid}-{hashlib.sha256(sub.encode()).hexdigest()[:16]}"


def instructor(client: TestClient, name: str) -> dict[str, str]:
    with db(client) as s:
        user = repo.user_by_name(s, name) or repo.create_user(s, name, hash_password(PASSWORD), "instructor")
    token = make_token(client.app.state.settings.jwt_secret(), user.id, "instructor", 60)  # type: ignore[attr-defined]
    return {"Authorization": f"Bearer {token}"}


def session(client: TestClient, response: Any) -> dict[str, Any]:
    assert response.status_code == 303, response.text
    ticket = response.headers["location"].split("#ticket=")[1]
    r = client.post("/lti/session", json={"ticket": ticket})
    assert r.status_code == 200, r.text
    return dict(r.json())


def me(client: TestClient, token: str) -> dict[str, Any]:
    return dict(client.get("/api/v1/me", headers={"Authorization": f"Bearer {token}"}).json())


def test_an_account_made_before_the_first_launch_is_not_taken_over(
    client: TestClient, platform: Platform
) -> None:
    # an instructor of this PAL Trainer made an account with the name the platform's teacher would get
    # (before this release the API allowed it; the name is refused now, see below)
    victim = "moodle-user-4711"
    squatted = generated_name(client, platform, victim)
    with db(client) as s:
        repo.create_user(s, squatted, hash_password(PASSWORD), "student")
    ctx = {LTI + "context": {"id": "course-hijack", "title": "Fachklasse"}}
    teacher = session(client, launch(client, platform, sub=victim, roles=INSTRUCTOR, **ctx))
    launched = me(client, teacher["token"])
    assert launched["username"] != squatted and launched["username"].startswith(squatted + "-")
    assert launched["role"] == "instructor"
    # the squatter's password opens their own account only: not the teacher's, nor the teacher's class
    r = client.post("/api/v1/auth/token", data={"username": squatted, "password": PASSWORD})
    assert r.status_code == 200, r.text
    assert me(client, r.json()["access_token"])["username"] == squatted
    with db(client) as s:
        planted = repo.user_by_name(s, squatted)
        assert planted is not None and planted.role == "student"
        link = s.scalars(select(LtiUser).where(LtiUser.sub == victim)).one()
        assert link.user_id != planted.id
        course = s.scalars(select(LtiContext.course_id).where(LtiContext.context_id == "course-hijack")).one()
        assert (
            s.scalars(
                select(CourseMember).where(
                    CourseMember.course_id == course, CourseMember.user_id == planted.id
                )
            ).first()
            is None
        )
    # the next launch of the same person finds the account made for them
    again = me(
        client, session(client, launch(client, platform, sub=victim, roles=INSTRUCTOR, **ctx))["token"]
    )
    assert again["username"] == launched["username"]


def test_a_launch_keeps_the_generated_name_when_it_is_free(client: TestClient, platform: Platform) -> None:
    s = session(client, launch(client, platform, sub="moodle-user-12", roles=LEARNER))
    assert me(client, s["token"])["username"] == generated_name(client, platform, "moodle-user-12")


def test_local_accounts_cannot_take_a_platform_name(client: TestClient, platform: Platform) -> None:
    name = generated_name(client, platform, "moodle-user-4712")
    for who in (admin_headers(client), instructor(client, "frau-kurz")):
        for username in (name, "LTI7-abc", "lti0"):
            r = client.post("/api/v1/users", json={"username": username, "password": PASSWORD}, headers=who)
            assert r.status_code == 422, r.text
            assert "Konten aus Lernplattformen vorbehalten" in r.json()["error"]["message"]
    # "lti" without a digit after it is an ordinary name
    r = client.post(
        "/api/v1/users", json={"username": "lti-fan", "password": PASSWORD}, headers=admin_headers(client)
    )
    assert r.status_code == 201, r.text
    with db(client) as s:
        assert repo.user_by_name(s, name) is None


def test_class_lists_cannot_take_a_platform_name(client: TestClient, platform: Platform) -> None:
    name = generated_name(client, platform, "moodle-user-4713")
    headers = instructor(client, "herr-lang")
    csv = f"name;password\nanna-k;{PASSWORD}\n{name};{PASSWORD}\n".encode()
    r = client.post("/api/v1/users/import", content=csv, headers={**headers, "Content-Type": "text/csv"})
    assert r.status_code == 422 and r.json()["error"]["code"] == "CLASS_LIST_INVALID", r.text
    course = client.post("/api/v1/courses", json={"name": "Klasse ohne Plattform"}, headers=headers).json()[
        "id"
    ]
    r = client.post(
        f"/api/v1/courses/{course}/members/import",
        content=csv,
        headers={**headers, "Content-Type": "text/csv"},
    )
    assert r.status_code == 422 and r.json()["error"]["code"] == "CLASS_LIST_INVALID", r.text
    with db(client) as s:
        assert repo.user_by_name(s, name) is None and repo.user_by_name(s, "anna-k") is None


def test_the_admin_commands_refuse_a_platform_name(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    monkeypatch.setenv("PALTRAINER_DATA_DIR", str(tmp_path / "data"))
    monkeypatch.delenv("DATABASE_URL", raising=False)
    assert main(["admin", "create-user", "lti1-0123456789abcdef", "--password", PASSWORD]) == 2
    assert "Konten aus Lernplattformen vorbehalten" in capsys.readouterr().err
    names = tmp_path / "klasse.csv"
    names.write_text(f"name;password\nberta-k;{PASSWORD}\nLti3-x;{PASSWORD}\n", encoding="utf-8")
    assert main(["admin", "import-users", str(names)]) == 1
    err = capsys.readouterr().err
    assert "»Lti3-x«" in err and "Konten aus Lernplattformen vorbehalten" in err
    assert main(["admin", "create-user", "lti-fan", "--password", PASSWORD]) == 0
    from server.cli import _database

    with _database().session() as s:
        assert [u.username for u in s.scalars(select(User).order_by(User.username))] == ["lti-fan"]
