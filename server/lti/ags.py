"""LTI Assignment and Grade Services: a graded submission's score goes to the platform's line item.

after_graded() puts a row into the score queue (lti_scores, one per submission) when the trainee came from a
platform's link with a line item; the app's background task drain() sends due rows with an OAuth 2
client-credentials token (our JWT assertion, signed with server.lti.keys.signing_key) and retries failures
with exponential backoff, so that no score is lost while the platform is down or the server restarts.
A row is claimed before it is sent (a compare-and-set on next_attempt_at), so two replicas never send it twice.

The score sent is the trainee's best so far for that exercise (of 100): the gradebook never goes down because a
later try was worse. An exam's score waits until the instructor releases the results.
"""

from __future__ import annotations

import asyncio
import logging
import threading
import time
import uuid
from dataclasses import dataclass
from datetime import UTC, datetime, timedelta
from typing import Any
from urllib.parse import urlsplit, urlunsplit

import httpx
import jwt
from sqlalchemy import or_, select, update
from sqlalchemy.orm import Session

from server import access
from server.db import Database
from server.lti.keys import signing_key
from server.lti.launch import resource_link_for
from server.lti.registration import service_url_ok
from server.models import (
    Assignment,
    Exercise,
    LtiContext,
    LtiLaunch,
    LtiPlatform,
    LtiResourceLink,
    LtiScore,
    LtiUser,
    Submission,
    User,
)

log = logging.getLogger("paltrainer.lti")

SCORE_SCOPE = "https://purl.imsglobal.org/spec/lti-ags/scope/score"
SCORE_MEDIA_TYPE = "application/vnd.ims.lis.v1.score+json"
LINEITEM_SCOPE = "https://purl.imsglobal.org/spec/lti-ags/scope/lineitem"
LINEITEM_MEDIA_TYPE = "application/vnd.ims.lis.v2.lineitem+json"
LINEITEMS_MEDIA_TYPE = "application/vnd.ims.lis.v2.lineitemcontainer+json"
ASSERTION_TYPE = "urn:ietf:params:oauth:client-assertion-type:jwt-bearer"
SCORE_MAXIMUM = 100.0

BACKOFF_BASE = timedelta(seconds=30)
BACKOFF_CAP = timedelta(hours=6)
MAX_ATTEMPTS = 20  # 30 s doubling to 6 h: about three days of retries (a platform down over a weekend)
LEASE = timedelta(
    minutes=2
)  # a claimed row is not picked again for this long (its sender may still be at it)
DRAIN_EVERY_SECONDS = 5.0
BATCH = 50
HTTP_TIMEOUT = 10.0


def _utc(value: datetime) -> datetime:
    """SQLite gives naive datetimes back (stored as UTC)."""
    return value.replace(tzinfo=UTC) if value.tzinfo is None else value


def backoff(attempts: int) -> timedelta:
    """How long to wait after the `attempts`-th failed attempt: 30 s, 1 min, 2 min … at most 6 h."""
    wait: timedelta = BACKOFF_BASE * (2 ** max(attempts - 1, 0))
    return min(wait, BACKOFF_CAP)


# --- the queue ------------------------------------------------------------------------------------------------


def _percent(submission: Submission) -> float | None:
    """The score that counts (the teacher's override, else the grader's) of 100."""
    grading = submission.grading
    if not grading or not grading.get("max_score"):
        return None
    score = grading["score"] if submission.override_score is None else submission.override_score
    return round(100.0 * float(score) / float(grading["max_score"]), 2)


def _best_percent(db: Session, submission: Submission) -> float | None:
    """The best score (of 100) of the author's submissions of this exercise up to this one; an exam's that is
    not released yet counts only for its own row (which waits for the release)."""
    q = select(Submission).where(
        Submission.exercise_id == submission.exercise_id,
        Submission.user_id == submission.user_id,
        Submission.id <= submission.id,
        Submission.grading.is_not(None),
        or_(Submission.held.is_(False), Submission.id == submission.id),
    )
    scores = [p for p in (_percent(s) for s in db.scalars(q)) if p is not None]
    return max(scores) if scores else None


def _assignment_score(db: Session, submission: Submission, assignment: Assignment) -> tuple[float, bool]:
    """An assignment link's score: the mean of the author's best score (of 100) per exercise of the assignment
    (an exercise not handed in counts 0), and whether every exercise was handed in."""
    slugs = list(assignment.exercises)
    ids = {
        slug: pk
        for slug, pk in db.execute(select(Exercise.slug, Exercise.id).where(Exercise.slug.in_(slugs)))
    }
    best: dict[int, float] = {}
    q = select(Submission).where(
        Submission.assignment_id == assignment.id,
        Submission.user_id == submission.user_id,
        Submission.id <= submission.id,
    )
    for s in db.scalars(q):
        best[s.exercise_id] = max(best.get(s.exercise_id, 0.0), _percent(s) or 0.0)
    scores = [best.get(ids.get(slug, -1), 0.0) for slug in slugs]
    done = all(ids.get(slug, -1) in best for slug in slugs)
    return (round(sum(scores) / len(scores), 2) if scores else 0.0), done


def _lti_user(db: Session, platform_id: int, user_id: int) -> LtiUser | None:
    return db.scalars(
        select(LtiUser)
        .where(LtiUser.platform_id == platform_id, LtiUser.user_id == user_id)
        .order_by(LtiUser.id.desc())
    ).first()


def enqueue(db: Session, submission: Submission, link: LtiResourceLink) -> LtiScore | None:
    """The submission's row in the score queue (the existing one if there is one: once per submission); None if
    the link has no line item to post to or the user has no identity on the link's platform."""
    existing = db.scalars(select(LtiScore).where(LtiScore.submission_id == submission.id)).first()
    if existing is not None:
        return existing
    # a link without a line item of its own gets one made by the drainer, if the platform lets us ("" till then)
    may_make = bool(link.lineitems_url) and LINEITEM_SCOPE in (link.ags_scopes or [])
    target = link.lineitem_url or ("" if may_make else None)
    if target is None or submission.user_id is None:
        return None
    if link.ags_scopes and SCORE_SCOPE not in link.ags_scopes:
        return None  # the platform did not grant the score scope for this link
    lti_user = _lti_user(db, link.platform_id, submission.user_id)
    exercise = db.get(Exercise, submission.exercise_id)
    if lti_user is None or exercise is None:
        return None
    context = db.get(LtiContext, link.context_pk) if link.context_pk is not None else None
    # an older score still waiting for the same grade book cell is carried by this one (the best so far);
    # not an exam's waiting for its release: this one does not carry it
    released = select(Submission.id).where(Submission.held.is_(False))
    cell = or_(LtiScore.resource_link_pk == link.id, LtiScore.lineitem_url == link.lineitem_url)
    db.execute(
        update(LtiScore)
        .where(
            LtiScore.platform_id == link.platform_id,
            cell,
            LtiScore.lti_sub == lti_user.sub,
            LtiScore.state == "pending",
            LtiScore.submission_id.in_(released),
        )
        .values(state="superseded")
    )
    assignment = db.get(Assignment, link.assignment_id) if link.assignment_id is not None else None
    score: float | None
    if assignment is not None and submission.assignment_id == assignment.id:
        score, done = _assignment_score(db, submission, assignment)
        progress = "Completed" if done else "InProgress"
    else:
        score, progress = _best_percent(db, submission), "Completed"
    row = LtiScore(
        submission_id=submission.id,
        platform_id=link.platform_id,
        resource_link_pk=link.id,
        course_id=context.course_id if context else None,
        user_id=submission.user_id,
        exercise_slug=exercise.slug,
        lineitem_url=target,
        lti_sub=lti_user.sub,
        score_given=score,
        activity_progress=progress,
        timestamp=_utc(submission.created_at),
        state="pending",
        attempts=0,
        next_attempt_at=datetime.now(UTC),
    )
    db.add(row)
    db.commit()
    return row


def _assignment_link(db: Session, submission: Submission) -> LtiResourceLink | None:
    """The link of the author's latest launch into the submission's assignment (its line item is the whole
    assignment's), or None."""
    if submission.assignment_id is None:
        return None
    q = (
        select(LtiResourceLink)
        .join(LtiLaunch, LtiLaunch.resource_link_pk == LtiResourceLink.id)
        .where(
            LtiLaunch.user_id == submission.user_id, LtiResourceLink.assignment_id == submission.assignment_id
        )
        .order_by(LtiLaunch.created_at.desc(), LtiLaunch.id.desc())
        .limit(1)
    )
    return db.scalars(q).first()


def after_graded(db: Session, submission: Submission) -> None:
    """Hook: called wherever a submission got its grade. Queues its score if the author came from a platform's
    link with a line item for this exercise. Never fails the submission: a problem here is logged."""
    if submission.user_id is None or submission.api_key_id is not None:
        return  # made through an API key: for the key's learner (external_user), not its owner's gradebook cell
    try:
        exercise = db.get(Exercise, submission.exercise_id)
        author = db.get(User, submission.user_id)
        if (
            exercise is None
            or author is None
            or not (
                submission.held
                or access.grade_visible(
                    access.situation(db, author, exercise.slug), submission, exercise.slug
                )
            )
        ):
            return  # a practice grade an exam of the author's course withholds (server/access.py): not passed on
        link = _assignment_link(db, submission) or (
            resource_link_for(db, submission.user_id, exercise.slug) if exercise is not None else None
        )
        if link is not None:
            enqueue(db, submission, link)
    except Exception:  # the grade is stored either way; the instructor sees a missing passback in the status
        db.rollback()
        log.exception("queueing the LTI score failed", extra={"job": f"submission {submission.id}"})


def regraded(db: Session, submission: Submission) -> None:
    """Hook: a submission's score changed (the teacher's override): its row is made anew with the score that
    counts now, and sent again."""
    existing = db.scalars(select(LtiScore).where(LtiScore.submission_id == submission.id)).first()
    if existing is not None:
        db.delete(existing)
        db.commit()
    after_graded(db, submission)


def retry(db: Session, row: LtiScore) -> LtiScore:
    """A failed row back into the queue, due now, with a fresh count."""
    row.state = "pending"
    row.attempts = 0
    row.next_attempt_at = datetime.now(UTC)
    db.commit()
    return row


# --- sending --------------------------------------------------------------------------------------------------


def score_json(row: LtiScore) -> dict[str, Any]:
    """The AGS score (application/vnd.ims.lis.v1.score+json) of a queued row."""
    body: dict[str, Any] = {
        "userId": row.lti_sub,
        "scoreMaximum": SCORE_MAXIMUM,
        "timestamp": _utc(row.timestamp).isoformat(timespec="milliseconds"),
    }
    if row.score_given is None:  # handed in, not graded by us (an exercise without grading)
        body.update(activityProgress="Submitted", gradingProgress="Pending")
    else:  # an assignment link with exercises still open: InProgress, its score so far is the grade for now
        body.update(
            scoreGiven=row.score_given,
            activityProgress=row.activity_progress or "Completed",
            gradingProgress="FullyGraded",
        )
    return body


def scores_url(lineitem_url: str) -> str:
    """The line item's score service: its path + "/scores", its query kept (Moodle's carry ?type_id=…)."""
    parts = urlsplit(lineitem_url)
    return urlunsplit(parts._replace(path=parts.path.rstrip("/") + "/scores"))


class PassbackError(Exception):
    """The platform did not take the score (yet). The message goes into the row's last_error, which instructors
    read: always one of ours (German / English, at most with the HTTP status), never text from the platform's
    answer."""


def unreachable(service: tuple[str, str]) -> PassbackError:
    return PassbackError(
        f"Die Lernplattform war nicht erreichbar ({service[0]}). / "
        f"The learning platform was unreachable ({service[1]})."
    )


def refused(service: tuple[str, str], status: int) -> PassbackError:
    return PassbackError(
        f"Die Lernplattform hat die Anfrage abgelehnt ({service[0]}, HTTP {status}). / "
        f"The learning platform refused the request ({service[1]}, HTTP {status})."
    )


def not_understood(service: tuple[str, str]) -> PassbackError:
    return PassbackError(
        f"Die Antwort der Lernplattform war unverständlich ({service[0]}). / "
        f"The learning platform's answer was not understood ({service[1]})."
    )


def foreign_url(service: tuple[str, str]) -> PassbackError:
    return PassbackError(
        f"Die Adresse ({service[0]}) gehört nicht zur registrierten Lernplattform; nichts "
        f"gesendet. / The address ({service[1]}) is not on the registered platform; nothing sent."
    )


TOKEN = ("Zugriffstoken", "access token")
LINEITEMS = ("Bewertungsspalte", "line items")
SCORE = ("Notenübertragung", "score service")


@dataclass
class _Token:
    value: str
    expires: float  # time.monotonic()


_tokens: dict[tuple[int, str, str, str], _Token] = {}
_tokens_lock = threading.Lock()


def forget_tokens() -> None:
    with _tokens_lock:
        _tokens.clear()


def client_assertion(db: Session, platform: LtiPlatform) -> str:
    """Our signed JWT that authenticates us at the platform's token endpoint (IMS Security Framework 4.1)."""
    kid, key = signing_key(db)
    db.commit()  # the first call makes and stores our key
    issued = int(time.time())
    claims = {
        "iss": platform.client_id,
        "sub": platform.client_id,
        "aud": platform.token_url,
        "iat": issued,
        "exp": issued + 300,
        "jti": uuid.uuid4().hex,
    }
    return jwt.encode(claims, key, algorithm="RS256", headers={"kid": kid})


async def access_token(
    client: httpx.AsyncClient, db: Session, platform: LtiPlatform, scopes: list[str]
) -> str:
    """A bearer token for `scopes`, from the cache until a minute before it expires."""
    scope = " ".join(sorted(scopes))
    cache_key = (platform.id, platform.token_url, platform.client_id, scope)
    with _tokens_lock:
        cached = _tokens.get(cache_key)
    if cached is not None and cached.expires > time.monotonic():
        return cached.value
    form = {
        "grant_type": "client_credentials",
        "client_assertion_type": ASSERTION_TYPE,
        "client_assertion": await asyncio.to_thread(client_assertion, db, platform),
        "scope": scope,
    }
    await asyncio.to_thread(db.commit)  # no pooled connection is held while the platform answers
    try:
        resp = await client.post(platform.token_url, data=form, headers={"Accept": "application/json"})
    except httpx.HTTPError as err:
        raise unreachable(TOKEN) from err
    if resp.status_code != 200:
        raise refused(TOKEN, resp.status_code)
    try:
        body = resp.json()
        value = str(body["access_token"])
        lifetime = float(body.get("expires_in", 3600))
    except (ValueError, KeyError, TypeError, AttributeError) as err:
        raise not_understood(TOKEN) from err
    with _tokens_lock:
        _tokens[cache_key] = _Token(value, time.monotonic() + max(lifetime - 60, 0))
    return value


async def ensure_lineitem(
    client: httpx.AsyncClient, db: Session, platform: LtiPlatform, row: LtiScore
) -> str:
    """The line item of the row's link: the one the link has, else the platform's line item for this resource
    link (found by resource_link_id, or made with a maximum of 100) — kept on the link for all its rows."""
    link = (
        await asyncio.to_thread(db.get, LtiResourceLink, row.resource_link_pk)
        if row.resource_link_pk is not None
        else None
    )
    if link is None or not link.lineitems_url:
        raise PassbackError(
            "Der Link hat keine Bewertungsspalte, und keine lässt sich anlegen. / "
            "The link has no line item and none can be made."
        )
    if not link.lineitem_url:
        if not service_url_ok(platform, link.lineitems_url):
            raise foreign_url(LINEITEMS)
        token = await access_token(client, db, platform, [LINEITEM_SCOPE])
        auth = {"Authorization": f"Bearer {token}"}
        await asyncio.to_thread(db.commit)
        try:
            found = await client.get(
                link.lineitems_url,
                params={"resource_link_id": link.resource_link_id},
                headers={**auth, "Accept": LINEITEMS_MEDIA_TYPE},
            )
            items = found.json() if found.status_code == 200 else []
            mine = (
                [
                    i
                    for i in items
                    if isinstance(i, dict)
                    and i.get("resourceLinkId") == link.resource_link_id
                    and isinstance(i.get("id"), str)
                ]
                if isinstance(items, list)
                else []
            )
            if mine:
                made_id = mine[0]["id"]
            else:
                made = await client.post(
                    link.lineitems_url,
                    json={
                        "scoreMaximum": SCORE_MAXIMUM,
                        "label": (link.title or row.exercise_slug)[:200],
                        "resourceLinkId": link.resource_link_id,
                        "resourceId": row.exercise_slug,
                    },
                    headers={**auth, "Content-Type": LINEITEM_MEDIA_TYPE, "Accept": LINEITEM_MEDIA_TYPE},
                )
                if made.status_code not in (200, 201):
                    raise refused(LINEITEMS, made.status_code)
                body = made.json()
                made_id = body.get("id") if isinstance(body, dict) else None
                if not isinstance(made_id, str):
                    raise not_understood(LINEITEMS)
        except httpx.HTTPError as err:
            raise unreachable(LINEITEMS) from err
        except ValueError as err:
            raise not_understood(LINEITEMS) from err
        # the line item's id is where its scores go: the platform's answer names it, so it is checked as well
        if len(made_id) > 1000 or not service_url_ok(platform, made_id):
            raise foreign_url(LINEITEMS)
        link.lineitem_url = made_id
    row.lineitem_url = link.lineitem_url
    await asyncio.to_thread(db.commit)
    return row.lineitem_url


async def post_score(client: httpx.AsyncClient, db: Session, platform: LtiPlatform, row: LtiScore) -> None:
    if not row.lineitem_url:
        await ensure_lineitem(client, db, platform, row)
    url = scores_url(row.lineitem_url)
    if not service_url_ok(
        platform, url
    ):  # checked again before each request: stored rows may predate a change
        raise foreign_url(SCORE)
    token = await access_token(client, db, platform, [SCORE_SCOPE])
    await asyncio.to_thread(db.commit)
    try:
        resp = await client.post(
            url,
            json=score_json(row),
            headers={"Authorization": f"Bearer {token}", "Content-Type": SCORE_MEDIA_TYPE},
        )
    except httpx.HTTPError as err:
        raise unreachable(SCORE) from err
    if resp.status_code == 401:
        forget_tokens()  # revoked or expired early: the next attempt asks for a new one
    if not 200 <= resp.status_code < 300:
        raise refused(SCORE, resp.status_code)


def _claim(db: Session, row_id: int, at: datetime) -> bool:
    """Take a due row for this sender (pushing its next attempt past the lease); False if another took it."""
    result = db.execute(
        update(LtiScore)
        .where(LtiScore.id == row_id, LtiScore.state == "pending", LtiScore.next_attempt_at <= at)
        .values(next_attempt_at=at + LEASE)
    )
    db.commit()
    return bool(getattr(result, "rowcount", 0) == 1)


def _claimed(db: Session, row_id: int, at: datetime) -> LtiScore | None:
    """The row, fresh from the database, if this sender could claim it (`_claim`)."""
    if not _claim(db, row_id, at):
        return None
    row = db.get(LtiScore, row_id)
    if row is not None:
        db.refresh(row)
        db.commit()
    return row


def _due(db: Session, at: datetime) -> list[tuple[int, int]]:
    """(id, platform id) of the pending rows due at `at`, oldest first; an exam's scores only once its results
    are released."""
    q = (
        select(LtiScore.id, LtiScore.platform_id)
        .join(Submission, Submission.id == LtiScore.submission_id)
        .where(LtiScore.state == "pending", LtiScore.next_attempt_at <= at, Submission.held.is_(False))
        .order_by(LtiScore.next_attempt_at, LtiScore.id)
        .limit(BATCH)
    )
    return [(r[0], r[1]) for r in db.execute(q)]


def _failed(db: Session, row: LtiScore, at: datetime, error: str) -> None:
    """Record a failed attempt: the next one after the backoff, or given up after MAX_ATTEMPTS."""
    db.rollback()
    row = db.get(LtiScore, row.id) or row
    row.attempts += 1
    row.last_error = error[:500]
    if row.attempts >= MAX_ATTEMPTS:
        row.state = "failed"
        log.warning("LTI score given up", extra={"job": f"score {row.id}: {row.last_error}"})
    else:
        row.next_attempt_at = at + backoff(row.attempts)
    db.commit()


async def send(client: httpx.AsyncClient, db: Session, row: LtiScore, at: datetime) -> bool:
    """One attempt at a claimed row; the row records the outcome. True if the platform took the score."""
    platform = await asyncio.to_thread(db.get, LtiPlatform, row.platform_id)
    try:
        if platform is None:
            raise PassbackError(
                "Die Lernplattform ist in PAL Trainer nicht mehr registriert. / "
                "The platform is no longer registered."
            )
        await post_score(client, db, platform, row)
    except PassbackError as err:
        log.info("LTI score not taken", extra={"job": f"score {row.id}: {err} {err.__cause__!r}"[:500]})
        await asyncio.to_thread(_failed, db, row, at, str(err))
        return False
    except Exception as err:  # our key unreadable, a database hiccup …: retried the same way
        log.exception("sending an LTI score failed", extra={"job": f"score {row.id}"})
        await asyncio.to_thread(
            _failed,
            db,
            row,
            at,
            f"Interner Fehler beim Senden ({type(err).__name__}); Näheres im Server-Protokoll. / "
            f"Internal error while sending ({type(err).__name__}); see the server log.",
        )
        return False
    row.attempts += 1
    row.state = "sent"
    row.sent_at = datetime.now(UTC)
    row.last_error = None
    await asyncio.to_thread(db.commit)
    return True


async def drain(
    database: Database, at: datetime | None = None, client: httpx.AsyncClient | None = None
) -> int:
    """Send every due row once (rows another sender claimed are skipped); returns how many the platforms took."""
    at = at or datetime.now(UTC)
    own = client is None
    http = client or httpx.AsyncClient(timeout=HTTP_TIMEOUT)
    sent = 0
    failing: set[int] = set()  # platforms that refused or did not answer in this round: their rows wait
    try:
        with database.session() as db:
            for row_id, platform_id in await asyncio.to_thread(_due, db, at):
                if platform_id in failing:
                    continue
                row = await asyncio.to_thread(_claimed, db, row_id, at)
                if row is None:
                    continue
                if await send(http, db, row, at):
                    sent += 1
                else:
                    failing.add(platform_id)
    finally:
        if own:
            await http.aclose()
    return sent


async def drainer(database: Database) -> None:
    """The app's background task: drains the score queue every few seconds."""
    async with httpx.AsyncClient(timeout=HTTP_TIMEOUT) as client:
        while True:
            try:
                await drain(database, client=client)
            except asyncio.CancelledError:
                raise
            except Exception:  # a failed round is retried on the next one
                log.exception("sending LTI scores failed")
            await asyncio.sleep(DRAIN_EVERY_SECONDS)
