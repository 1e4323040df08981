"""LTI 1.3 launches as a platform sends them: learner and instructor land on the exercise inside the iframe
(ticket → bearer token, frame-ancestors of the platform only), users/course/membership are made, the AGS and
NRPS claims are kept; deep linking answers a response signed with our key that names the chosen exercises."""

from __future__ import annotations

import re
from collections.abc import Iterator
from html import unescape

import jwt
import pytest
from fastapi.testclient import TestClient
from lti_testplatform import (
    INSTRUCTOR,
    LEARNER,
    LTI,
    Platform,
    admin_headers,
    launch,
    login,
    registered_platform,
    tool_client,
)
from sqlalchemy import select

from server.lti.launch import resource_link_for
from server.models import CourseMember, LtiContext, LtiResourceLink, LtiUser, User

SLUG = "pal-01-g1-gerade"


@pytest.fixture(scope="module")
def client(tmp_path_factory: pytest.TempPathFactory) -> Iterator[TestClient]:
    with tool_client(tmp_path_factory.mktemp("lti")) as c:
        yield c


@pytest.fixture(scope="module")
def platform(client: TestClient) -> Platform:
    return registered_platform(client)


def _open(client: TestClient, response) -> dict:  # type: ignore[no-untyped-def]
    """Follow the launch's redirect like the framed page does: /lti/open, then the ticket exchange."""
    assert response.status_code == 303, response.text
    location = response.headers["location"]
    m = re.fullmatch(r"/lti/open\?p=(\d+)#ticket=([\w-]+)", location)
    assert m, location
    page = client.get(location.split("#")[0])
    assert page.status_code == 200 and "/lti/static/open.js" in page.text
    r = client.post("/lti/session", json={"ticket": m.group(2)})
    assert r.status_code == 200, r.text
    return dict(r.json())


def _user(client: TestClient, sub: str, iss: str = "https://lms.example.test") -> tuple[User, LtiUser]:
    with client.app.state.db.session() as db:  # type: ignore[attr-defined]
        row = db.execute(
            select(User, LtiUser).join(LtiUser, LtiUser.user_id == User.id).where(LtiUser.sub == sub)
        ).one()
        return row[0], row[1]


def test_instructor_launch_makes_user_course_and_lands_on_the_exercise(
    client: TestClient, platform: Platform
) -> None:
    session = _open(client, launch(client, platform, sub="teacher-1", roles=INSTRUCTOR, name="Frau Lehrer"))
    assert session["next"] == f"/lti/exercise/{SLUG}?p=1"
    assert session["role"] == "instructor"
    user, lti_user = _user(client, "teacher-1")
    assert user.role == "instructor" and lti_user.name == "Frau Lehrer"
    with client.app.state.db.session() as db:  # type: ignore[attr-defined]
        ctx = db.scalars(select(LtiContext).where(LtiContext.context_id == "course-7")).one()
        assert (
            ctx.course_id is not None and ctx.memberships_url == "https://lms.example.test/nrps/7/memberships"
        )
        member = db.scalars(select(CourseMember).where(CourseMember.user_id == user.id)).one()
        assert (member.course_id, member.role) == (ctx.course_id, "instructor")
        link = db.scalars(select(LtiResourceLink).where(LtiResourceLink.resource_link_id == "link-1")).one()
        assert link.exercise_slug == SLUG
        assert link.lineitem_url == "https://lms.example.test/ags/7/lineitems/1/lineitem"
        assert link.ags_scopes == ["https://purl.imsglobal.org/spec/lti-ags/scope/score"]
    # the framed exercise page: the platform (and we) may frame it, nobody else
    page = client.get(session["next"])
    assert page.status_code == 200 and 'data-page="exercise"' in page.text
    csp = page.headers["content-security-policy"]
    assert "frame-ancestors 'self' https://lms.example.test;" in csp + ";"
    # the token works as a bearer token for the page's API calls (no cookie)
    me = client.get("/api/v1/me", headers={"Authorization": f"Bearer {session['token']}"})
    assert me.status_code == 200 and me.json()["role"] == "instructor"


def test_learner_launch_joins_the_course_as_student_and_keeps_the_link(
    client: TestClient, platform: Platform
) -> None:
    launch(client, platform, sub="teacher-2", roles=INSTRUCTOR)  # the course exists
    session = _open(client, launch(client, platform, sub="pupil-1", roles=LEARNER))
    assert session["role"] == "learner" and session["next"].startswith(f"/lti/exercise/{SLUG}")
    user, lti_user = _user(client, "pupil-1")
    assert user.role == "student" and lti_user.email == "erika@example.test"
    with client.app.state.db.session() as db:  # type: ignore[attr-defined]
        ctx = db.scalars(select(LtiContext).where(LtiContext.context_id == "course-7")).one()
        member = db.scalars(select(CourseMember).where(CourseMember.user_id == user.id)).one()
        assert (member.course_id, member.role) == (ctx.course_id, "student")
        link = resource_link_for(db, user.id, SLUG)
        assert link is not None and link.resource_link_id == "link-1"
        assert resource_link_for(db, user.id, "another-exercise") is None
    # a second launch of the same person is the same user
    _open(client, launch(client, platform, sub="pupil-1", roles=LEARNER))
    assert _user(client, "pupil-1")[0].id == user.id


def test_ticket_is_good_once(client: TestClient, platform: Platform) -> None:
    r = launch(client, platform, sub="pupil-2")
    ticket = r.headers["location"].split("#ticket=")[1]
    assert client.post("/lti/session", json={"ticket": ticket}).status_code == 200
    again = client.post("/lti/session", json={"ticket": ticket})
    assert again.status_code == 401 and again.json()["error"]["code"] == "BAD_TOKEN"


def test_launch_without_exercise_explains_itself(client: TestClient, platform: Platform) -> None:
    r = launch(client, platform, sub="pupil-3", **{LTI + "custom": {}})
    assert r.status_code == 200 and "keiner Aufgabe zugeordnet" in r.text


def test_login_redirects_to_the_registered_auth_url_only(client: TestClient, platform: Platform) -> None:
    r = client.post(
        "/lti/login",
        data={
            "iss": platform.issuer,
            "login_hint": "1",
            "client_id": platform.client_id,
            "target_link_uri": "http://127.0.0.1/lti/launch",
            "redirect_uri": "https://evil.example/steal",
        },
        follow_redirects=False,
    )
    assert r.status_code == 302 and r.headers["location"].startswith(platform.auth_url + "?")
    assert "evil.example" not in r.headers["location"]
    state, nonce = login(client, platform)
    assert state != nonce and len(state) > 30


def test_deep_linking_returns_signed_response_with_the_chosen_exercises(
    client: TestClient, platform: Platform
) -> None:
    dl = {
        LTI + "message_type": "LtiDeepLinkingRequest",
        "https://purl.imsglobal.org/spec/lti-dl/claim/deep_linking_settings": {
            "deep_link_return_url": "https://lms.example.test/mod/lti/contentitem_return.php",
            "accept_types": ["ltiResourceLink"],
            "accept_presentation_document_targets": ["iframe"],
            "accept_multiple": True,
            "data": "opaque-42",
        },
    }
    r = launch(client, platform, sub="teacher-3", roles=INSTRUCTOR, **dl)
    assert r.status_code == 200 and "Aufgaben für den Kurs auswählen" in r.text
    assert "frame-ancestors 'self' https://lms.example.test" in r.headers["content-security-policy"]
    ticket = re.search(r'name="ticket" value="([^"]+)"', r.text).group(1)  # type: ignore[union-attr]
    assert f'value="{SLUG}"' in r.text
    chosen = [SLUG, "pal-02-g1-rn-radius"]
    assert all(f'value="{s}"' in r.text for s in chosen)
    answer = client.post("/lti/deep-link", data={"ticket": ticket, "exercise": chosen})
    assert answer.status_code == 200, answer.text
    assert 'action="https://lms.example.test/mod/lti/contentitem_return.php"' in answer.text
    assert '<script src="/lti/static/autosubmit.js"' in answer.text and "<script>" not in answer.text
    assert "form-action 'self' https://lms.example.test" in answer.headers["content-security-policy"]
    token = unescape(re.search(r'name="JWT" value="([^"]+)"', answer.text).group(1))  # type: ignore[union-attr]
    # verify with our published JWKS, as the platform does
    jwks = client.get("/lti/jwks").json()
    kid = jwt.get_unverified_header(token)["kid"]
    key = jwt.PyJWK({k: v for k, v in next(k for k in jwks["keys"] if k["kid"] == kid).items()})
    claims = jwt.decode(token, key, algorithms=["RS256"], audience=platform.issuer)
    assert claims["iss"] == platform.client_id
    assert claims[LTI + "message_type"] == "LtiDeepLinkingResponse"
    assert claims[LTI + "deployment_id"] == platform.deployment
    assert claims["https://purl.imsglobal.org/spec/lti-dl/claim/data"] == "opaque-42"
    items = claims["https://purl.imsglobal.org/spec/lti-dl/claim/content_items"]
    assert [i["custom"]["exercise"] for i in items] == chosen
    assert all(i["type"] == "ltiResourceLink" and i["lineItem"]["scoreMaximum"] == 100 for i in items)
    assert items[0]["lineItem"]["label"] == items[0]["title"]
    # the selection is sent once
    assert client.post("/lti/deep-link", data={"ticket": ticket, "exercise": chosen}).status_code == 403


def test_config_page_lists_the_urls(client: TestClient) -> None:
    page = client.get("/lti/config")
    assert page.status_code == 200
    for path in ("/lti/login", "/lti/launch", "/lti/jwks", "/lti/register"):
        assert f"http://127.0.0.1{path}" in page.text
    assert "Login-URL" in page.text


def test_admin_lists_platforms_and_rotates_keys(client: TestClient, platform: Platform) -> None:
    headers = admin_headers(client)
    listed = client.get("/api/v1/admin/lti/platforms", headers=headers).json()
    assert any(p["issuer"] == platform.issuer and p["deployment_ids"] == ["dep-1"] for p in listed)
    before = {k["kid"] for k in client.get("/lti/jwks").json()["keys"]}
    new = client.post("/api/v1/admin/lti/keys/rotate", headers=headers).json()["kid"]
    after = {k["kid"] for k in client.get("/lti/jwks").json()["keys"]}
    assert after == before | {new}  # the old key stays published
    old = min(before)
    assert client.post(f"/api/v1/admin/lti/keys/{old}/retire", headers=headers).status_code == 200
    assert old not in {k["kid"] for k in client.get("/lti/jwks").json()["keys"]}
    # students may not register platforms
    assert client.get("/api/v1/admin/lti/platforms").status_code == 401


def test_assignment_link_opens_its_first_exercise_only_in_its_own_course(
    client: TestClient, platform: Platform
) -> None:
    ctx = {LTI + "context": {"id": "course-asg", "title": "Klasse mit Aufgabenstellung"}}
    teacher = _open(client, launch(client, platform, sub="teacher-asg", roles=INSTRUCTOR, **ctx))
    headers = {"Authorization": f"Bearer {teacher['token']}"}
    with client.app.state.db.session() as db:  # type: ignore[attr-defined]
        course_id = db.scalars(
            select(LtiContext.course_id).where(LtiContext.context_id == "course-asg")
        ).one()
    body = {
        "title": "Übung Konturen",
        "exercises": ["pal-02-g1-rn-radius", SLUG],
        "mode": "practice",
        "opens_at": "2026-01-01T08:00:00Z",
        "deadline": "2099-01-01T08:00:00Z",
    }
    r = client.post(f"/api/v1/courses/{course_id}/assignments", json=body, headers=headers)
    assert r.status_code == 201, r.text
    assignment = r.json()["id"]
    custom = {
        LTI + "custom": {"assignment": str(assignment)},
        LTI + "resource_link": {"id": "link-asg", "title": "Übung"},
    }
    pupil = _open(client, launch(client, platform, sub="pupil-asg", roles=LEARNER, **ctx, **custom))
    assert pupil["next"].startswith("/lti/exercise/pal-02-g1-rn-radius?")
    # the same assignment id from another platform course opens nothing
    other = {LTI + "context": {"id": "course-other", "title": "Andere Klasse"}}
    launch(client, platform, sub="teacher-other", roles=INSTRUCTOR, **other)
    r = launch(
        client,
        platform,
        sub="pupil-other",
        roles=LEARNER,
        **other,
        **{**custom, LTI + "resource_link": {"id": "link-asg-2"}},
    )
    assert r.status_code == 200 and "keiner Aufgabe zugeordnet" in r.text
