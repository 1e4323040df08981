"""LTI 1.3 launches that must be refused, each with a German page, its code and a log line: a replayed nonce,
an expired token, a key the platform does not publish, a wrong audience, an unknown deployment, an unregistered
issuer, a bad or missing state; and a learner's launch never gives instructor rights."""

from __future__ import annotations

import logging
import time
from collections.abc import Iterator
from datetime import UTC, datetime, timedelta
from typing import Any

import httpx
import pytest
from fastapi.testclient import TestClient
from lti_testplatform import (
    INSTRUCTOR,
    LEARNER,
    LTI,
    Platform,
    launch,
    login,
    registered_platform,
    rsa_key,
    tool_client,
)
from sqlalchemy import select

from server.lti import launch as lti_launch
from server.lti.launch import JwksCache, role_of
from server.models import CourseMember, LtiLoginState, LtiPlatform, LtiUser, User


@pytest.fixture(scope="module")
def client(tmp_path_factory: pytest.TempPathFactory) -> Iterator[TestClient]:
    with tool_client(tmp_path_factory.mktemp("lti-security")) as c:
        yield c


@pytest.fixture(scope="module")
def platform(client: TestClient) -> Platform:
    return registered_platform(client)


def refused(response: httpx.Response, code: str, caplog: pytest.LogCaptureFixture, status: int = 403) -> None:
    assert response.status_code == status, response.text
    assert "text/html" in response.headers["content-type"]
    assert "Start aus der Lernplattform abgelehnt" in response.text
    assert f'data-code="{code}"' in response.text
    assert any(
        r.name == "paltrainer.lti" and code in r.getMessage() + str(getattr(r, "job", ""))
        for r in caplog.records
    ), [r.__dict__ for r in caplog.records]


@pytest.fixture(autouse=True)
def _log(caplog: pytest.LogCaptureFixture) -> None:
    caplog.set_level(logging.INFO, logger="paltrainer.lti")


def test_replayed_nonce_is_refused(
    client: TestClient, platform: Platform, caplog: pytest.LogCaptureFixture
) -> None:
    state, nonce = login(client, platform)
    token = platform.sign(platform.claims(nonce, sub="replay-1"))
    assert (
        client.post(
            "/lti/launch", data={"id_token": token, "state": state}, follow_redirects=False
        ).status_code
        == 303
    )
    # the same post again: its state is used up
    refused(
        client.post("/lti/launch", data={"id_token": token, "state": state}), "LTI_BAD_STATE", caplog, 400
    )
    # the same token with a fresh state: the nonce was used
    fresh, _ = login(client, platform)
    refused(client.post("/lti/launch", data={"id_token": token, "state": fresh}), "LTI_REPLAY", caplog)


def test_expired_token_is_refused(
    client: TestClient, platform: Platform, caplog: pytest.LogCaptureFixture
) -> None:
    now = int(time.time())
    refused(launch(client, platform, iat=now - 900, exp=now - 600), "LTI_EXPIRED", caplog)


def test_token_from_the_future_is_refused(
    client: TestClient, platform: Platform, caplog: pytest.LogCaptureFixture
) -> None:
    now = int(time.time())
    refused(launch(client, platform, iat=now + 3600, exp=now + 4000), "LTI_BAD_TOKEN", caplog)


def test_token_signed_by_an_unknown_key_is_refused(
    client: TestClient, platform: Platform, caplog: pytest.LogCaptureFixture
) -> None:
    other, other_jwk = rsa_key()
    r = launch(
        client,
        platform,
        token_for=lambda n: platform.sign(platform.claims(n), key=other, kid=other_jwk["kid"]),
    )
    refused(r, "LTI_UNKNOWN_KEY", caplog)
    # another key under the platform's kid: the signature does not verify
    r = launch(client, platform, token_for=lambda n: platform.sign(platform.claims(n), key=other))
    refused(r, "LTI_BAD_SIGNATURE", caplog)


def test_wrong_audience_is_refused(
    client: TestClient, platform: Platform, caplog: pytest.LogCaptureFixture
) -> None:
    refused(launch(client, platform, aud="another-tool"), "LTI_WRONG_AUDIENCE", caplog)
    # several audiences: azp must name us
    refused(launch(client, platform, aud=["another-tool", platform.client_id]), "LTI_WRONG_AUDIENCE", caplog)
    ok = launch(
        client, platform, sub="azp-1", aud=["another-tool", platform.client_id], azp=platform.client_id
    )
    assert ok.status_code == 303


def test_unknown_deployment_is_refused(
    client: TestClient, platform: Platform, caplog: pytest.LogCaptureFixture
) -> None:
    refused(
        launch(client, platform, **{LTI + "deployment_id": "dep-unknown"}), "LTI_UNKNOWN_DEPLOYMENT", caplog
    )


def test_unregistered_issuer_is_refused(
    client: TestClient, platform: Platform, caplog: pytest.LogCaptureFixture
) -> None:
    stranger = Platform(issuer="https://stranger.example.test")
    r = client.get(
        "/lti/login",
        params={
            "iss": stranger.issuer,
            "login_hint": "1",
            "client_id": "x",
            "target_link_uri": "http://127.0.0.1/lti/launch",
        },
        follow_redirects=False,
    )
    refused(r, "LTI_UNKNOWN_ISSUER", caplog)
    # a token of an unregistered issuer posted with a registered platform's state
    state, nonce = login(client, platform)
    token = stranger.sign({**stranger.claims(nonce), "aud": platform.client_id})
    refused(
        client.post("/lti/launch", data={"id_token": token, "state": state}), "LTI_UNKNOWN_ISSUER", caplog
    )


def test_bad_or_missing_state_is_refused(
    client: TestClient, platform: Platform, caplog: pytest.LogCaptureFixture
) -> None:
    refused(launch(client, platform, state="made-up-state"), "LTI_BAD_STATE", caplog, 400)
    _, nonce = login(client, platform)
    token = platform.sign(platform.claims(nonce))
    refused(client.post("/lti/launch", data={"id_token": token}), "LTI_BAD_STATE", caplog, 400)
    # the nonce must be the one of this state
    state, _ = login(client, platform)
    refused(client.post("/lti/launch", data={"id_token": token, "state": state}), "LTI_BAD_NONCE", caplog)


def test_unsupported_message_and_garbage_are_refused(
    client: TestClient, platform: Platform, caplog: pytest.LogCaptureFixture
) -> None:
    refused(
        launch(client, platform, **{LTI + "message_type": "LtiSubmissionReviewRequest"}),
        "LTI_UNSUPPORTED_MESSAGE",
        caplog,
        400,
    )
    refused(launch(client, platform, token_for=lambda n: "not.a.jwt"), "LTI_BAD_TOKEN", caplog, 400)


def _member(client: TestClient, sub: str) -> tuple[User, CourseMember | None]:
    with client.app.state.db.session() as db:  # type: ignore[attr-defined]
        user = db.scalars(
            select(User).join(LtiUser, LtiUser.user_id == User.id).where(LtiUser.sub == sub)
        ).one()
        return user, db.scalars(select(CourseMember).where(CourseMember.user_id == user.id)).first()


def test_learner_never_gets_instructor_rights(
    client: TestClient, platform: Platform, caplog: pytest.LogCaptureFixture
) -> None:
    ctx = {LTI + "context": {"id": "course-sec", "title": "Sicherheit"}}
    # a learner first: no course is made for them, and they are no instructor
    first = launch(client, platform, sub="learner-a", roles=LEARNER, **ctx)
    assert first.status_code == 303
    user, member = _member(client, "learner-a")
    assert user.role == "student" and member is None
    # the instructor makes the course; the learner then joins it as a student
    launch(client, platform, sub="teacher-a", roles=INSTRUCTOR, **ctx)
    r = launch(client, platform, sub="learner-a", roles=LEARNER, **ctx)
    ticket = r.headers["location"].split("#ticket=")[1]
    session: dict[str, Any] = client.post("/lti/session", json={"ticket": ticket}).json()
    user, member = _member(client, "learner-a")
    assert user.role == "student" and member is not None and member.role == "student"
    headers = {"Authorization": f"Bearer {session['token']}"}
    assert client.get(f"/api/v1/courses/{member.course_id}/members", headers=headers).status_code == 403
    assert client.get("/api/v1/admin/lti/platforms", headers=headers).status_code == 403
    # an account made by a launch has no password: nothing logs in as it
    for password in ("!lti", "", "x" * 12):
        r = client.post("/api/v1/auth/token", data={"username": user.username, "password": password})
        assert r.status_code in (401, 422), r.text
    # unknown roles, look-alikes and mentors are learners
    assert (
        role_of(
            {
                LTI + "roles": [
                    "urn:lti:role:ims/lis/Instructor",
                    "Instructor#Learner",
                    "http://purl.imsglobal.org/vocab/lis/v2/membership#Mentor",
                ]
            }
        )
        == "learner"
    )
    assert (
        role_of({LTI + "roles": "http://purl.imsglobal.org/vocab/lis/v2/membership#Instructor"}) == "learner"
    )
    # a learner cannot pick content (deep linking)
    dl = {
        LTI + "message_type": "LtiDeepLinkingRequest",
        "https://purl.imsglobal.org/spec/lti-dl/claim/deep_linking_settings": {
            "deep_link_return_url": "https://lms.example.test/return"
        },
    }
    refused(launch(client, platform, sub="learner-a", roles=LEARNER, **dl), "LTI_NOT_INSTRUCTOR", caplog)


def test_platform_jwks_is_cached_and_fetched_again_for_a_new_kid() -> None:
    p = Platform()
    cache = JwksCache(transport=httpx.MockTransport(p.handler), min_refetch=0.0)
    first_kid = p.jwk["kid"]
    assert cache.key(p.jwks_url, first_kid) is not None
    assert cache.key(p.jwks_url, first_kid) is not None
    assert p.jwks_fetches == 1  # within the TTL: from the cache
    p.key, p.jwk = rsa_key()  # the platform rotates its key
    assert cache.key(p.jwks_url, p.jwk["kid"]) is not None
    assert p.jwks_fetches == 2
    # unknown kids do not make a fetch each while the last one is recent
    slow = JwksCache(transport=httpx.MockTransport(p.handler))
    slow.key(p.jwks_url, p.jwk["kid"])
    for kid in ("a", "b", "c"):
        assert slow.key(p.jwks_url, kid) is None
    assert p.jwks_fetches == 3


def test_login_needs_its_parameters(client: TestClient, caplog: pytest.LogCaptureFixture) -> None:
    refused(
        client.get("/lti/login", params={"iss": "https://lms.example.test"}),
        "LTI_LOGIN_INCOMPLETE",
        caplog,
        400,
    )


def test_login_sends_the_id_token_only_to_our_launch(
    client: TestClient, platform: Platform, caplog: pytest.LogCaptureFixture
) -> None:
    for target in (
        "https://evil.example/steal",
        "javascript:alert(1)",
        "http://127.0.0.1/lti/jwks",
        "https://evil.example/lti/launch",
        "http://127.0.0.1:8001/lti/launch",
        "https://127.0.0.1/lti/launch",
        "http://evil.example@127.0.0.1/lti/launch",
    ):
        r = client.get(
            "/lti/login",
            params={
                "iss": platform.issuer,
                "login_hint": "1",
                "client_id": platform.client_id,
                "target_link_uri": target,
            },
            follow_redirects=False,
        )
        refused(r, "LTI_BAD_TARGET", caplog, 400)
    # our own launch endpoint, as the platform has it registered, is fine
    state, _ = login(client, platform)
    assert state


def test_logins_from_one_address_are_limited(tmp_path_factory: pytest.TempPathFactory) -> None:
    with tool_client(tmp_path_factory.mktemp("lti-login-limit"), rate_lti_login_per_minute=5) as limited:
        p = registered_platform(limited)
        for _ in range(5):
            assert login(limited, p)
        r = limited.get(
            "/lti/login",
            params={
                "iss": p.issuer,
                "login_hint": "1",
                "client_id": p.client_id,
                "target_link_uri": "http://127.0.0.1/lti/launch",
            },
            follow_redirects=False,
        )
        assert r.status_code == 429 and 'data-code="RATE_LIMITED"' in r.text
        assert "Zu viele Starts von dieser Adresse" in r.text and int(r.headers["retry-after"]) > 0
        with limited.app.state.db.session() as db:  # type: ignore[attr-defined]
            assert len(db.scalars(select(LtiLoginState)).all()) == 5  # nothing stored for the refused one


def test_stored_login_states_are_bounded(
    client: TestClient, platform: Platform, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(lti_launch, "MAX_LOGIN_STATES", 4, raising=False)
    with client.app.state.db.session() as db:  # type: ignore[attr-defined]
        platform_id = db.scalars(select(LtiPlatform.id).where(LtiPlatform.issuer == platform.issuer)).one()
        db.add(
            LtiLoginState(
                state="expired-one",
                nonce="n",
                platform_id=platform_id,
                expires_at=datetime.now(UTC) - timedelta(seconds=1),
            )
        )
        db.commit()
    states = [login(client, platform) for _ in range(7)]
    with client.app.state.db.session() as db:  # type: ignore[attr-defined]
        kept = {row.state for row in db.scalars(select(LtiLoginState))}
    assert kept == {state for state, _ in states[-4:]}  # the newest; the oldest and the expired one are gone
    # a login that comes back finds its state; one pushed out starts again from the platform
    newest, nonce = states[-1]
    token = platform.sign(platform.claims(nonce, sub="bounded-1"))
    assert (
        client.post(
            "/lti/launch", data={"id_token": token, "state": newest}, follow_redirects=False
        ).status_code
        == 303
    )
    oldest, nonce = states[0]
    token = platform.sign(platform.claims(nonce, sub="bounded-2"))
    r = client.post("/lti/launch", data={"id_token": token, "state": oldest})
    assert r.status_code == 400 and 'data-code="LTI_BAD_STATE"' in r.text
