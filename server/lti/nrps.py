"""LTI Names and Role Provisioning Services: an instructor pulls the platform course's roster into our course.

The course's LTI contexts (made by launches, server/lti/launch.py) carry the platform's context_memberships_url;
we read it with a client-credentials token (scope contextmembership.readonly, from server/lti/ags.py) and page
through it (Link: rel="next"). Each active member becomes a user the way a launch makes one (by platform + sub)
and a member of the course: Learner → student, Instructor or Administrator → instructor. Nobody is removed:
an inactive or deleted member on the platform keeps what they did here.
"""

from __future__ import annotations

import logging
from typing import Any

import httpx
from pydantic import BaseModel
from sqlalchemy import select
from sqlalchemy.orm import Session

from server import repository as repo
from server.errors import ApiError
from server.lti import ags, launch, registration
from server.models import LtiContext, LtiPlatform, LtiUser

log = logging.getLogger("paltrainer.lti")

NRPS_SCOPE = "https://purl.imsglobal.org/spec/lti-nrps/scope/contextmembership.readonly"
NRPS_MEDIA_TYPE = "application/vnd.ims.lti-nrps.v2.membershipcontainer+json"
MAX_PAGES = 100  # 100 pages of a platform's page size: far beyond a school class
ROSTER = ("Teilnehmerliste", "roster")
# what the instructor reads when a pull fails, whatever went wrong: an unreachable platform and one that answered
# look the same (the server log tells them apart), so the roster pull is no probe of our network
FAILED_DE = "Die Teilnehmerliste ließ sich nicht abrufen (Näheres im Server-Protokoll)."
FAILED_EN = "The roster could not be fetched (see the server log)."


class RosterUser(BaseModel):
    username: str
    name: str
    role: str  # "student" or "instructor" in the course
    created: bool  # new here (never launched the tool before)


class RosterOut(BaseModel):
    """What a roster pull did: members read, users made, course members by role; inactive ones skipped."""

    course: int
    members: int
    created: int
    students: int
    instructors: int
    skipped: int
    users: list[RosterUser]


async def _members(
    client: httpx.AsyncClient, db: Session, platform: LtiPlatform, url: str
) -> list[dict[str, Any]]:
    out: list[dict[str, Any]] = []
    next_url: str | None = url
    token: str | None = None
    for _ in range(MAX_PAGES):
        if next_url is None:
            break
        if not registration.service_url_ok(platform, next_url):  # the first page's URL and each "next" one
            raise ags.foreign_url(ROSTER)
        token = token or await ags.access_token(client, db, platform, [NRPS_SCOPE])
        try:
            resp = await client.get(
                next_url, headers={"Authorization": f"Bearer {token}", "Accept": NRPS_MEDIA_TYPE}
            )
        except httpx.HTTPError as err:
            raise ags.unreachable(ROSTER) from err
        if resp.status_code != 200:
            if resp.status_code == 401:
                ags.forget_tokens()
            raise ags.refused(ROSTER, resp.status_code)
        try:
            members = resp.json().get("members", [])
        except (ValueError, AttributeError) as err:
            raise ags.not_understood(ROSTER) from err
        out.extend(m for m in members if isinstance(m, dict))
        next_url = resp.links.get("next", {}).get("url")
    return out


def _add(db: Session, platform: LtiPlatform, course_id: int, member: dict[str, Any]) -> RosterUser | None:
    sub = member.get("user_id")
    if not isinstance(sub, str | int) or str(sub) == "":
        return None
    known = (
        db.scalars(
            select(LtiUser).where(LtiUser.platform_id == platform.id, LtiUser.sub == str(sub)[:255])
        ).first()
        is not None
    )
    role = launch.role_of({launch.CLAIM_ROLES: member.get("roles")})
    teaches = role in ("instructor", "administrator")
    claims = {
        "sub": str(sub),
        "name": member.get("name") or "",
        "given_name": member.get("given_name") or "",
        "family_name": member.get("family_name") or "",
        "email": member.get("email") or "",
    }
    user, lti_user = launch.platform_user(db, platform, claims, teaches)  # one rule for platform users
    course_role = "instructor" if teaches else "student"
    repo.add_member(db, course_id, user.id, course_role)
    return RosterUser(username=user.username, name=lti_user.name, role=course_role, created=not known)


async def pull_roster(db: Session, course_id: int, client: httpx.AsyncClient | None = None) -> RosterOut:
    """Read the rosters of the platform courses linked to our course `course_id` and enrol their members."""
    contexts = list(
        db.scalars(
            select(LtiContext).where(
                LtiContext.course_id == course_id, LtiContext.memberships_url.is_not(None)
            )
        )
    )
    if not contexts:
        raise ApiError("LTI_NO_ROSTER")
    own = client is None
    http = client or httpx.AsyncClient(timeout=ags.HTTP_TIMEOUT)
    users: list[RosterUser] = []
    seen = skipped = 0
    try:
        for context in contexts:
            platform = db.get(LtiPlatform, context.platform_id)
            if platform is None or context.memberships_url is None:
                continue
            db.commit()  # no pooled connection is held while the platform answers
            try:
                members = await _members(http, db, platform, context.memberships_url)
            except ags.PassbackError as err:
                log.warning(
                    "LTI roster failed", extra={"job": f"context {context.id}: {err} {err.__cause__!r}"}
                )
                raise ApiError("LTI_PLATFORM_ERROR", detail=FAILED_DE, detail_en=FAILED_EN) from None
            for member in members:
                seen += 1
                if str(member.get("status", "Active")) != "Active":
                    skipped += 1
                    continue
                added = _add(db, platform, course_id, member)
                if added is None:
                    skipped += 1
                else:
                    users.append(added)
    finally:
        if own:
            await http.aclose()
    log.info("LTI roster pulled", extra={"job": f"course {course_id}: {len(users)} members"})
    return RosterOut(
        course=course_id,
        members=seen,
        created=sum(u.created for u in users),
        students=sum(u.role == "student" for u in users),
        instructors=sum(u.role == "instructor" for u in users),
        skipped=skipped,
        users=users,
    )
