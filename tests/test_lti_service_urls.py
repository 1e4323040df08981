"""The platform's service URLs (AGS line item and line items, NRPS roster) come from its id_token and its answers:
we request them only on the platform's registered origins, so they cannot turn PAL Trainer against its own
network (SSRF). A service on loopback next to the tool plays the target; it must never hear from us. What the
instructor reads about a failed passback or roster pull is our own fixed text, never the answer's body, and a
roster pull does not tell a closed port from an open one."""

from __future__ import annotations

import asyncio
from collections.abc import Iterator
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

import pytest
from fastapi import FastAPI, Request
from fastapi.responses import PlainTextResponse
from fastapi.testclient import TestClient
from lti_platform import Served, free_port
from lti_testplatform import INSTRUCTOR, LTI, Platform, launch, registered_platform, tool_client
from sqlalchemy import select
from test_lti_ags import World, build

from server.errors import ApiError
from server.lti import ags, nrps, registration
from server.models import Course, LtiContext, LtiPlatform, LtiResourceLink, LtiScore

SECRET = "internes Geheimnis: db-password=hunter2"
AGS = "https://purl.imsglobal.org/spec/lti-ags/claim/endpoint"
NRPS = "https://purl.imsglobal.org/spec/lti-nrps/claim/namesroleservice"


class Internal:
    """A service on loopback that only the tool's own machine reaches (an admin page, a metadata service …)."""

    def __init__(self) -> None:
        self.requests: list[tuple[str, str]] = []
        app = FastAPI()

        @app.api_route("/{path:path}", methods=["GET", "POST"])
        async def anything(path: str, request: Request) -> PlainTextResponse:
            self.requests.append((request.method, "/" + path))
            return PlainTextResponse(SECRET, status_code=200 if request.method == "GET" else 500)

        self.server = Served(app, free_port())
        self.url = self.server.url


@pytest.fixture
def internal() -> Iterator[Internal]:
    service = Internal()
    service.server.start()
    try:
        yield service
    finally:
        service.server.stop()


@pytest.fixture
def world(tmp_path: Path) -> Iterator[World]:
    w = build(tmp_path, "sqlite")
    try:
        yield w
    finally:
        w.platform.stop()
        w.database.engine.dispose()
        ags.forget_tokens()


def set_link(world: World, **values: Any) -> None:
    with world.database.session() as db:
        link = db.get(LtiResourceLink, world.link_id)
        assert link is not None
        for name, value in values.items():
            setattr(link, name, value)
        db.commit()


def passback(world: World) -> LtiScore:
    world.enqueue(world.submit(7))
    world.drain(datetime.now(UTC))
    (row,) = world.rows()
    return row


def test_a_score_is_not_posted_to_a_line_item_off_the_platform(world: World, internal: Internal) -> None:
    world.platform.start()
    set_link(world, lineitem_url=f"{internal.url}/admin/lineitem")  # as stored before this check
    row = passback(world)
    assert internal.requests == []
    assert world.state.scores == [] and world.state.token_requests == 0
    assert (row.state, row.attempts) == ("pending", 1)
    assert row.last_error == (
        "Die Adresse (Notenübertragung) gehört nicht zur registrierten Lernplattform; nichts "
        "gesendet. / The address (score service) is not on the registered platform; nothing "
        "sent."
    )


def test_no_line_item_is_looked_up_or_made_off_the_platform(world: World, internal: Internal) -> None:
    world.platform.start()
    set_link(
        world,
        lineitem_url=None,
        lineitems_url=f"{internal.url}/lineitems",
        ags_scopes=[ags.SCORE_SCOPE, ags.LINEITEM_SCOPE],
    )
    row = passback(world)
    assert internal.requests == []
    assert SECRET not in (row.last_error or "") and "registrierten Lernplattform" in (row.last_error or "")


def test_a_line_item_the_platform_names_off_its_origin_gets_no_score(
    world: World, internal: Internal
) -> None:
    world.platform.start()
    world.state.lineitems.append(
        {
            "id": f"{internal.url}/x/lineitem",
            "resourceLinkId": "link-1",
            "scoreMaximum": 100,
            "label": "Nuten",
        }
    )
    set_link(world, lineitem_url=None, ags_scopes=[ags.SCORE_SCOPE, ags.LINEITEM_SCOPE])
    row = passback(world)
    assert internal.requests == []
    assert "registrierten Lernplattform" in (row.last_error or "")
    with world.database.session() as db:
        link = db.get(LtiResourceLink, world.link_id)
        assert link is not None and link.lineitem_url is None  # not kept for the link's next scores either


def test_the_instructor_reads_our_message_not_the_platform_answer(world: World) -> None:
    """The platform refuses the score with a page of its own: the status is shown, its text is not."""
    world.platform.start()
    set_link(world, lineitem_url=f"{world.platform.url}/lineitems/li-1/lineitem-gone")
    row = passback(world)
    assert row.last_error == (
        "Die Lernplattform hat die Anfrage abgelehnt (Notenübertragung, HTTP 404). / "
        "The learning platform refused the request (score service, HTTP 404)."
    )


def roster_course(world: World, memberships_url: str) -> int:
    with world.database.session() as db:
        course = Course(name="FT-2A", join_code="LTISSRF1")
        db.add(course)
        db.flush()
        context = db.scalars(select(LtiContext)).one()
        context.course_id, context.memberships_url = course.id, memberships_url
        db.commit()
        return course.id


def pull(world: World, course_id: int) -> ApiError:
    async def go() -> None:
        with world.database.session() as db:
            await nrps.pull_roster(db, course_id)

    with pytest.raises(ApiError) as caught:
        asyncio.run(go())
    return caught.value


def test_the_roster_is_not_read_off_the_platform(world: World, internal: Internal) -> None:
    world.platform.start()
    err = pull(world, roster_course(world, f"{internal.url}/contexts/course-42/memberships"))
    assert internal.requests == []
    assert (err.status, err.code) == (502, "LTI_PLATFORM_ERROR")
    assert SECRET not in err.message + err.message_en


def test_a_roster_pull_does_not_tell_a_closed_port_from_an_open_one(world: World) -> None:
    course = roster_course(world, f"{world.platform.url}/contexts/course-42/memberships")
    closed = pull(world, course)  # the platform's port: nobody listens
    world.platform.start()
    with world.database.session() as db:  # listening, answering 404
        db.scalars(select(LtiContext)).one().memberships_url = f"{world.platform.url}/nothing-here"
        db.commit()
    opened = pull(world, course)
    assert (closed.status, closed.message, closed.message_en) == (
        opened.status,
        opened.message,
        opened.message_en,
    )
    assert "Teilnehmerliste ließ sich nicht abrufen" in opened.message


# --- what a launch keeps -------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def client(tmp_path_factory: pytest.TempPathFactory) -> Iterator[TestClient]:
    with tool_client(tmp_path_factory.mktemp("lti-service-urls")) as c:
        yield c


@pytest.fixture(scope="module")
def platform(client: TestClient) -> Platform:
    return registered_platform(client)


OFF = [
    "http://127.0.0.1:6379/ags",
    "https://lms.example.test@127.0.0.1/ags",
    "http://lms.example.test/ags",
    "https://lms.example.test:8443/ags",
    "https://metadata.internal/ags",
    "https://lms.example.test\\@10.0.0.1/ags",
]


@pytest.mark.parametrize("n", range(len(OFF)), ids=OFF)
def test_a_launch_keeps_no_service_url_off_the_platform(
    client: TestClient, platform: Platform, n: int
) -> None:
    url, ctx = OFF[n], f"course-off-{n}"
    claims = {
        LTI + "context": {"id": ctx, "title": "Fachklasse"},
        LTI + "resource_link": {"id": f"link-{ctx}"},
        AGS: {
            "scope": [ags.SCORE_SCOPE, ags.LINEITEM_SCOPE],
            "lineitem": f"{url}/1/lineitem",
            "lineitems": url,
        },
        NRPS: {"context_memberships_url": f"{url}/memberships", "service_versions": ["2.0"]},
    }
    assert launch(client, platform, sub="teacher-ssrf", roles=INSTRUCTOR, **claims).status_code == 303
    with client.app.state.db.session() as db:  # type: ignore[attr-defined]
        link = db.scalars(
            select(LtiResourceLink).where(LtiResourceLink.resource_link_id == f"link-{ctx}")
        ).one()
        context = db.scalars(select(LtiContext).where(LtiContext.context_id == ctx)).one()
        assert (link.lineitem_url, link.lineitems_url, context.memberships_url) == (None, None, None)


def test_service_urls_on_the_registered_origins() -> None:
    https = LtiPlatform(
        issuer="https://moodle.schule.de",
        auth_login_url="https://moodle.schule.de/mod/lti/auth.php",
        token_url="https://sso.schule.de/token",
        jwks_url="https://moodle.schule.de/mod/lti/certs.php",
    )
    ok = [
        "https://moodle.schule.de/mod/lti/services.php/2/lineitems",
        "https://MOODLE.schule.de:443/x",
        "https://sso.schule.de/lineitems",
    ]
    bad = [
        "http://moodle.schule.de/mod/lti/services.php",
        "https://moodle.schule.de:8443/x",
        "https://moodle.schule.de.evil.example/x",
        "https://user@moodle.schule.de/x",
        "ftp://moodle.schule.de/x",
        "https://moodle.schule.de\\@evil.example/x",
        "//moodle.schule.de/x",
        "/mod/lti/services.php",
        "",
        "http://127.0.0.1:8000/x",
    ]
    assert [u for u in ok if not registration.service_url_ok(https, u)] == []
    assert [u for u in bad if registration.service_url_ok(https, u)] == []
    # http only where the platform itself is registered on loopback http (local trials, these tests)
    local = LtiPlatform(
        issuer="http://127.0.0.1:8080",
        auth_login_url="http://127.0.0.1:8080/auth",
        token_url="http://127.0.0.1:8080/token",
        jwks_url="http://127.0.0.1:8080/jwks",
    )
    assert registration.service_url_ok(local, "http://127.0.0.1:8080/lineitems")
    assert not registration.service_url_ok(local, "http://127.0.0.1:8081/lineitems")
    assert not registration.service_url_ok(local, "http://localhost:8080/lineitems")
    lan = LtiPlatform(
        issuer="http://10.0.0.5",
        auth_login_url="http://10.0.0.5/auth",
        token_url="http://10.0.0.5/t",
        jwks_url="http://10.0.0.5/k",
    )
    assert not registration.service_url_ok(lan, "http://10.0.0.5/lineitems")
