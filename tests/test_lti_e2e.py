"""LTI 1.3 end to end on loopback: PAL Trainer (uvicorn, 127.0.0.1) as a tool of a platform we did not write —
the PyPI package lti1p3platform behind a small app (lti_platform.py), playing Moodle. Registration, launches as
instructor and learner, deep linking, a graded submission whose score arrives at the platform's AGS score
service (also when the platform was down meanwhile: once), and the roster pulled with NRPS."""

from __future__ import annotations

import re
import time
from collections.abc import Iterator
from dataclasses import dataclass
from datetime import timedelta
from html import unescape
from pathlib import Path
from types import SimpleNamespace
from typing import Any

import httpx
import pytest
from lti_platform import (
    CLIENT_ID,
    DEPLOYMENT_ID,
    INSTRUCTOR,
    LEARNER,
    Member,
    PlatformState,
    Served,
    free_port,
    platform_app,
)
from server_tests.server_helpers import builtin_exercise, make_settings, reference_of
from sqlalchemy import select

from server import repository as repo
from server.app import create_app
from server.lti import ags
from server.models import LtiContext, LtiScore
from server.security import hash_password, make_token


@dataclass
class Setup:
    tool: Served
    platform: Served
    state: PlatformState
    app: Any
    slug: str
    admin: dict[str, str]

    def user(self, role: str, name: str) -> dict[str, str]:
        with self.app.state.db.session() as db:
            user = repo.create_user(db, name, hash_password("ein langes Passwort"), role)
        token = make_token(self.app.state.settings.jwt_secret(), user.id, user.role, 60)
        return {"Authorization": f"Bearer {token}"}

    def api(self) -> httpx.Client:
        return httpx.Client(base_url=self.tool.url, timeout=30)

    def launch(self, user: str, **params: str) -> httpx.Response:
        """A user clicks the link in the platform's course: the browser's way through the OIDC login to the
        tool's launch (the answer of the tool's /lti/launch)."""
        with httpx.Client(timeout=30) as browser:
            r = browser.get(f"{self.platform.url}/start", params={"user": user, **params})
            assert r.status_code == 302 and r.headers["location"].startswith(f"{self.tool.url}/lti/login?")
            r = browser.get(r.headers["location"])  # the tool: state and nonce, on to the platform
            assert r.status_code == 302 and r.headers["location"].startswith(f"{self.platform.url}/auth?"), (
                r.text
            )
            r = browser.get(r.headers["location"])  # the platform signs the id_token
            assert r.status_code == 200, r.text
            return browser.post(form_action(r.text), data=form_fields(r.text))

    def session(self, user: str, **params: str) -> dict[str, Any]:
        """Launch and exchange the one-time ticket as the tool's page does; its API token, role, next page."""
        r = self.launch(user, **params)
        assert r.status_code == 303, r.text
        ticket = r.headers["location"].split("#ticket=", 1)[1]
        with self.api() as api:
            s = api.post("/lti/session", json={"ticket": ticket})
        assert s.status_code == 200, s.text
        return dict(s.json())

    def course_id(self) -> int:
        with self.app.state.db.session() as db:
            ctx = db.scalars(select(LtiContext)).first()
            assert ctx is not None and ctx.course_id is not None
            return ctx.course_id


def form_action(page: str) -> str:
    m = re.search(r'<form[^>]*action="([^"]+)"', page)
    assert m, page
    return unescape(m.group(1))


def form_fields(page: str) -> dict[str, str]:
    return {
        unescape(n): unescape(v)
        for n, v in re.findall(r'<input type="hidden" name="([^"]+)" value="([^"]*)"', page)
    }


def bearer(token: str) -> dict[str, str]:
    return {"Authorization": f"Bearer {token}"}


def wait_for(check: Any, seconds: float = 30.0) -> None:
    deadline = time.monotonic() + seconds
    while not check():
        if time.monotonic() > deadline:
            pytest.fail("waited in vain")
        time.sleep(0.1)


@pytest.fixture(scope="module")
def setup(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Setup]:
    mp = pytest.MonkeyPatch()
    mp.setattr(ags, "DRAIN_EVERY_SECONDS", 0.2)  # the drainer looks every 0.2 s instead of every 5 s
    mp.setattr(ags, "BACKOFF_BASE", timedelta(seconds=1))  # and retries after 1 s, 2 s … instead of 30 s …
    tmp: Path = tmp_path_factory.mktemp("lti")
    tool_port, platform_port = free_port(), free_port()
    tool_url, platform_url = f"http://127.0.0.1:{tool_port}", f"http://127.0.0.1:{platform_port}"
    app = create_app(make_settings(tmp, "sqlite", workers=1))
    tool = Served(app, tool_port).start()
    state = PlatformState.new()
    state.members = [
        Member("moodle-teacher-1", "Frau Lehmann", "lehmann@schule.example", [INSTRUCTOR]),
        Member("moodle-student-2", "Anna Azubi", "anna@schule.example", [LEARNER]),
        Member("moodle-student-3", "Carla Ceran", "carla@schule.example", [LEARNER]),
    ]
    platform = Served(platform_app(platform_url, tool_url, state), platform_port).start()
    slug = builtin_exercise(SimpleNamespace(app=app))
    s = Setup(tool, platform, state, app, slug, {})
    s.admin = s.user("admin", "lti-admin")
    try:
        yield s
    finally:
        platform.stop()
        tool.stop()
        ags.forget_tokens()
        mp.undo()


def test_1_registration_of_the_platform(setup: Setup) -> None:
    body = {
        "issuer": setup.platform.url,
        "client_id": CLIENT_ID,
        "auth_login_url": f"{setup.platform.url}/auth",
        "token_url": f"{setup.platform.url}/token",
        "jwks_url": f"{setup.platform.url}/jwks",
        "deployment_ids": [DEPLOYMENT_ID],
        "name": "Moodle der Berufsschule",
    }
    with setup.api() as api:
        r = api.post("/api/v1/admin/lti/platforms", json=body, headers=setup.admin)
        assert r.status_code == 201, r.text
        keys = api.get("/lti/jwks").json()["keys"]
    assert keys and all(k["kty"] == "RSA" and k["alg"] == "RS256" and "d" not in k for k in keys)


def test_2_launch_as_instructor_makes_the_course(setup: Setup) -> None:
    s = setup.session("moodle-teacher-1", exercise=setup.slug, link="link-1", lineitem="li-1")
    assert s["role"] == "instructor"
    assert s["next"].startswith(f"/lti/exercise/{setup.slug}")
    with setup.api() as api:
        members = api.get(f"/api/v1/courses/{setup.course_id()}/members", headers=bearer(s["token"]))
    assert members.status_code == 200
    assert [m["role"] for m in members.json()] == ["instructor"]


def test_3_learner_submits_and_the_score_arrives_at_the_platform(setup: Setup) -> None:
    s = setup.session("moodle-student-2", exercise=setup.slug, link="link-1", lineitem="li-1")
    assert s["role"] == "learner"
    with setup.api() as api:
        # a learner's launch grants no instructor rights
        assert (
            api.get(
                "/api/v1/lti/scores", params={"course": setup.course_id()}, headers=bearer(s["token"])
            ).status_code
            == 403
        )
        r = api.post(
            "/api/v1/submissions",
            json={"exercise": setup.slug, "program": reference_of()},
            headers=bearer(s["token"]),
        )
        assert r.status_code == 201, r.text
        assert r.json()["grading"]["score"] == r.json()["grading"]["max_score"]
    wait_for(lambda: len(setup.state.scores) == 1)
    line_item, score = setup.state.scores[0]
    assert line_item == "li-1"
    assert (score["userId"], score["scoreGiven"], score["scoreMaximum"]) == ("moodle-student-2", 100.0, 100)
    assert (score["activityProgress"], score["gradingProgress"]) == ("Completed", "FullyGraded")
    teacher = setup.session("moodle-teacher-1", exercise=setup.slug, link="link-1", lineitem="li-1")
    with setup.api() as api:
        status = api.get(
            "/api/v1/lti/scores", params={"course": setup.course_id()}, headers=bearer(teacher["token"])
        )
    assert status.status_code == 200
    rows = status.json()["scores"]
    assert [(x["submission"], x["state"], x["score"], x["exercise"], x["name"]) for x in rows] == [
        (r.json()["id"], "sent", 100.0, setup.slug, "Anna Azubi")
    ]
    assert status.json()["counts"]["sent"] == 1


def test_4_platform_down_during_passback_then_up_the_score_arrives_once(setup: Setup) -> None:
    s = setup.session("moodle-student-2", exercise=setup.slug, link="link-1", lineitem="li-1")
    setup.platform.stop()  # Moodle is down
    with setup.api() as api:
        r = api.post(
            "/api/v1/submissions",
            json={"exercise": setup.slug, "program": reference_of()},
            headers=bearer(s["token"]),
        )
        assert r.status_code == 201, r.text

        def failed_once() -> bool:
            rows = api.get("/api/v1/lti/scores", headers=setup.admin).json()["scores"]
            mine = [x for x in rows if x["submission"] == r.json()["id"]]
            return bool(mine) and mine[0]["state"] == "pending" and mine[0]["attempts"] >= 1

        wait_for(failed_once)
        row = next(
            x
            for x in api.get("/api/v1/lti/scores", headers=setup.admin).json()["scores"]
            if x["submission"] == r.json()["id"]
        )
        assert "unreachable" in row["last_error"]
    assert len(setup.state.scores) == 1
    setup.platform.start()  # Moodle is back, with what it had
    wait_for(lambda: len(setup.state.scores) == 2)
    time.sleep(2.5)  # further drains (every 0.2 s) send nothing more
    assert len(setup.state.scores) == 2
    with setup.api() as api:
        rows = api.get("/api/v1/lti/scores", headers=setup.admin).json()["scores"]
    assert [x["state"] for x in rows if x["submission"] == r.json()["id"]] == ["sent"]


def test_5_deep_linking_returns_a_resource_link_with_a_line_item(setup: Setup) -> None:
    r = setup.launch("moodle-teacher-1", kind="deeplink")
    assert r.status_code == 200, r.text
    assert f'value="{setup.slug}"' in r.text  # the exercise picker
    with setup.api() as api:
        picked = api.post("/lti/deep-link", data={**form_fields(r.text), "exercise": setup.slug})
    assert picked.status_code == 200, picked.text
    assert form_action(picked.text) == f"{setup.platform.url}/deep_link_return"
    with httpx.Client(timeout=30) as browser:
        back = browser.post(form_action(picked.text), data=form_fields(picked.text))
    assert back.json() == {"items": 1}
    item = setup.state.deep_linked[0]
    assert item["type"] == "ltiResourceLink"
    assert item["lineItem"]["scoreMaximum"] == 100
    assert item["custom"]["exercise"] == setup.slug


def test_6_a_learner_cannot_pick_content(setup: Setup) -> None:
    r = setup.launch("moodle-student-2", kind="deeplink")
    assert r.status_code == 403
    assert "LTI_NOT_INSTRUCTOR" in r.text


def test_7_roster_pulled_with_nrps(setup: Setup) -> None:
    course = setup.course_id()
    teacher = bearer(setup.session("moodle-teacher-1", exercise=setup.slug, link="link-1")["token"])
    learner = bearer(setup.session("moodle-student-2", exercise=setup.slug, link="link-1")["token"])
    other = setup.user("instructor", "andere-lehrkraft")
    url = f"/api/v1/courses/{course}/lti/roster"
    with setup.api() as api:
        linked = api.get(f"/api/v1/courses/{course}/lti", headers=teacher)
        assert linked.status_code == 200
        assert linked.json() == [
            {"platform": "Moodle der Berufsschule", "context": "Fertigungstechnik 2A", "roster": True}
        ]
        assert api.get(f"/api/v1/courses/{course}/lti", headers=learner).status_code == 403
        assert api.post(url).status_code == 401
        assert api.post(url, headers=learner).status_code == 403
        assert api.post(url, headers=other).status_code == 404  # not their course
        r = api.post(url, headers=teacher)
        assert r.status_code == 200, r.text
        out = r.json()
        assert (out["members"], out["created"], out["students"], out["instructors"]) == (3, 1, 2, 1)
        assert {u["name"]: (u["role"], u["created"]) for u in out["users"]} == {
            "Frau Lehmann": ("instructor", False),
            "Anna Azubi": ("student", False),
            "Carla Ceran": ("student", True),
        }
        members = api.get(f"/api/v1/courses/{course}/members", headers=teacher).json()
        assert sorted(m["role"] for m in members) == ["instructor", "student", "student"]
        again = api.post(url, headers=setup.admin)  # admins too; a second pull makes nobody twice
        assert again.status_code == 200 and again.json()["created"] == 0
        assert len(api.get(f"/api/v1/courses/{course}/members", headers=teacher).json()) == 3
        # a course no platform course is linked to has no roster to pull
        mine = api.post("/api/v1/courses", json={"name": "Ohne Lernplattform"}, headers=other).json()
        assert api.get(f"/api/v1/courses/{mine['id']}/lti", headers=other).json() == []
        r = api.post(f"/api/v1/courses/{mine['id']}/lti/roster", headers=other)
        assert r.status_code == 409 and r.json()["error"]["code"] == "LTI_NO_ROSTER"


def test_8_a_given_up_passback_is_sent_again_by_the_instructor(setup: Setup) -> None:
    teacher = bearer(setup.session("moodle-teacher-1", exercise=setup.slug, link="link-1")["token"])
    learner = bearer(setup.session("moodle-student-2", exercise=setup.slug, link="link-1")["token"])
    with setup.api() as api:
        sent = api.get("/api/v1/lti/scores", params={"state": "sent"}, headers=teacher).json()["scores"][0]
        r = api.post(f"/api/v1/lti/scores/{sent['id']}/retry", headers=teacher)
        assert r.status_code == 409 and r.json()["error"]["code"] == "LTI_SCORE_NOT_FAILED"
        with setup.app.state.db.session() as db:  # as after ags.MAX_ATTEMPTS failed attempts
            row = db.get(LtiScore, sent["id"])
            assert row is not None
            row.state, row.attempts = "failed", ags.MAX_ATTEMPTS
            db.commit()
        before = len(setup.state.scores)
        assert api.post(f"/api/v1/lti/scores/{sent['id']}/retry", headers=learner).status_code == 404
        r = api.post(f"/api/v1/lti/scores/{sent['id']}/retry", headers=teacher)
        assert r.status_code == 200, r.text
        assert (r.json()["state"], r.json()["attempts"]) == ("pending", 0)
    wait_for(lambda: len(setup.state.scores) == before + 1)
    assert setup.state.scores[-1][1]["userId"] == "moodle-student-2"


def test_9_a_link_without_a_grade_item_gets_one_made_once(setup: Setup) -> None:
    s = setup.session("moodle-student-2", exercise=setup.slug, link="link-3", lineitem="")
    before = len(setup.state.scores)
    with setup.api() as api:
        for _ in range(2):
            r = api.post(
                "/api/v1/submissions",
                json={"exercise": setup.slug, "program": reference_of()},
                headers=bearer(s["token"]),
            )
            assert r.status_code == 201, r.text
            count = len(setup.state.scores)
            wait_for(lambda count=count: len(setup.state.scores) == count + 1)
    assert [(i["resourceLinkId"], i["scoreMaximum"], i["resourceId"]) for i in setup.state.lineitems] == [
        ("link-3", 100, setup.slug)
    ]
    assert [item for item, _ in setup.state.scores[before:]] == ["made-1", "made-1"]
