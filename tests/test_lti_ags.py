"""LTI grade passback (server/lti/ags.py): the score queue against the lti1p3platform platform on loopback —
the score JSON, the token, backoff while the platform is down, one delivery per submission, rows that outlive a
restart of the server."""

from __future__ import annotations

import asyncio
import threading
from collections.abc import Iterator
from dataclasses import dataclass
from datetime import UTC, datetime, timedelta
from pathlib import Path
from typing import Any

import pytest
from lti_platform import CLIENT_ID, PlatformState, Served, free_port, platform_app
from server_tests.server_helpers import BACKENDS, POSTGRES_URL, make_settings
from sqlalchemy import create_engine, event, select, text

from server.config import Settings
from server.db import Database, migrate
from server.lti import ags, keys
from server.models import (
    ApiKey,
    Assignment,
    Course,
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


@dataclass
class World:
    settings: Settings
    database: Database
    state: PlatformState
    platform: Served
    link_id: int
    user_id: int
    exercise_id: int

    def submit(
        self,
        score: int | None,
        max_score: int = 10,
        exercise_id: int | None = None,
        assignment_id: int | None = None,
        held: bool = False,
    ) -> Submission:
        grading = None if score is None else {"score": score, "max_score": max_score, "criteria": []}
        with self.database.session() as db:
            sub = Submission(
                exercise_id=exercise_id or self.exercise_id,
                user_id=self.user_id,
                program="N10 M30\n",
                dialect="pal-mill",
                result={},
                grading=grading,
                assignment_id=assignment_id,
                held=held,
            )
            db.add(sub)
            db.commit()
            return sub

    def enqueue(self, submission: Submission) -> LtiScore | None:
        with self.database.session() as db:
            link = db.get(LtiResourceLink, self.link_id)
            assert link is not None
            sub = db.get(Submission, submission.id)
            assert sub is not None
            return ags.enqueue(db, sub, link)

    def rows(self) -> list[LtiScore]:
        with self.database.session() as db:
            return list(db.scalars(select(LtiScore).order_by(LtiScore.id)))

    def drain(self, at: datetime) -> int:
        return asyncio.run(ags.drain(self.database, at=at))


def own_postgres_schema(name: str) -> str:
    """A fresh schema of its own in the test database (other server tests use the public one meanwhile)."""
    assert POSTGRES_URL
    engine = create_engine(POSTGRES_URL.replace("postgresql://", "postgresql+psycopg://", 1))
    with engine.begin() as conn:
        conn.execute(text(f"DROP SCHEMA IF EXISTS {name} CASCADE"))
        conn.execute(text(f"CREATE SCHEMA {name}"))
    engine.dispose()
    return f"{POSTGRES_URL}{'&' if '?' in POSTGRES_URL else '?'}options=-csearch_path%3D{name}"


def build(tmp: Path, backend: str) -> World:
    settings = (
        make_settings(tmp, "sqlite", database_url=own_postgres_schema("lti_ags"))
        if backend == "postgresql"
        else make_settings(tmp, backend)
    )
    keys.configure(settings)
    database = Database(settings)
    migrate(database.engine)
    state = PlatformState.new()
    port = free_port()
    base = f"http://127.0.0.1:{port}"
    with database.session() as db:
        state.tool_jwks = keys.jwks(db)  # entered by hand in the platform: these tests run no tool server
        platform = LtiPlatform(
            issuer=base,
            client_id=CLIENT_ID,
            auth_login_url=f"{base}/auth",
            token_url=f"{base}/token",
            jwks_url=f"{base}/jwks",
            name="Moodle",
        )
        user = User(username="anna", password_hash="-", role="student")
        exercise = Exercise(slug="pal-nuten", title_de="Nuten", dialect="pal-mill")
        db.add_all([platform, user, exercise])
        db.flush()
        context = LtiContext(platform_id=platform.id, context_id="course-42", title="FT-2A")
        db.add_all([context, LtiUser(platform_id=platform.id, sub="moodle-user-7", user_id=user.id)])
        db.flush()
        link = LtiResourceLink(
            platform_id=platform.id,
            context_pk=context.id,
            resource_link_id="link-1",
            exercise_slug="pal-nuten",
            lineitem_url=f"{base}/lineitems/li-1/lineitem",
            lineitems_url=f"{base}/lineitems",
            ags_scopes=[ags.SCORE_SCOPE],
        )
        db.add(link)
        db.commit()
        ids = (link.id, user.id, exercise.id)
    return World(
        settings, database, state, Served(platform_app(base, "http://127.0.0.1:9", state), port), *ids
    )


@pytest.fixture(params=BACKENDS)
def world(request: pytest.FixtureRequest, tmp_path: Path) -> Iterator[World]:
    w = build(tmp_path, request.param)
    try:
        yield w
    finally:
        w.platform.stop()
        w.database.engine.dispose()
        ags.forget_tokens()


def utc(value: datetime) -> datetime:
    return value.replace(tzinfo=UTC) if value.tzinfo is None else value


def test_score_json_and_url() -> None:
    row = LtiScore(lti_sub="u-7", score_given=85.0, timestamp=datetime(2026, 11, 22, 9, 30, tzinfo=UTC))
    assert ags.score_json(row) == {
        "userId": "u-7",
        "scoreGiven": 85.0,
        "scoreMaximum": 100.0,
        "activityProgress": "Completed",
        "gradingProgress": "FullyGraded",
        "timestamp": "2026-11-22T09:30:00.000+00:00",
    }
    row.score_given = None  # handed in, not gradable here: the platform's teacher grades it
    body = ags.score_json(row)
    assert (body["activityProgress"], body["gradingProgress"]) == ("Submitted", "Pending")
    assert "scoreGiven" not in body
    # Moodle's line items carry their type in the query: /scores goes on the path
    assert (
        ags.scores_url("https://moodle.example/mod/lti/services.php/2/lineitems/5/lineitem?type_id=3")
        == "https://moodle.example/mod/lti/services.php/2/lineitems/5/lineitem/scores?type_id=3"
    )


def test_backoff_schedule() -> None:
    assert [ags.backoff(n).total_seconds() for n in range(1, 6)] == [30, 60, 120, 240, 480]
    assert ags.backoff(30) == timedelta(hours=6)
    total = sum((ags.backoff(n) for n in range(1, ags.MAX_ATTEMPTS)), timedelta())
    assert timedelta(days=2) < total < timedelta(days=4)  # a platform down over a weekend loses nothing


def test_score_arrives_at_the_platform_with_a_client_credentials_token(world: World) -> None:
    world.platform.start()
    sub = world.submit(7)
    assert world.enqueue(sub) is not None
    assert world.drain(datetime.now(UTC)) == 1
    assert [(item, s["userId"], s["scoreGiven"], s["scoreMaximum"]) for item, s in world.state.scores] == [
        ("li-1", "moodle-user-7", 70.0, 100)
    ]
    row = world.rows()[0]
    assert (row.state, row.attempts, row.last_error) == ("sent", 1, None)
    # the token is kept until it expires: a second score asks the platform for none
    world.enqueue(world.submit(9))
    assert world.drain(datetime.now(UTC)) == 1
    assert world.state.token_requests == 1
    assert [s["scoreGiven"] for _, s in world.state.scores] == [70.0, 90.0]


def test_the_sender_leaves_the_database_to_threads_and_the_event_loop_free(world: World) -> None:
    """Sending scores runs in the server's event loop: every database call of it (claiming, the key, the line
    item, the outcome) runs in a thread, so that a database waiting for a lock stops no other request."""
    loop_thread = threading.get_ident()  # (asyncio.run runs the loop in this thread)
    on_the_loop: list[str] = []

    def seen(_conn: Any, _cursor: Any, statement: str, *_: Any) -> None:
        if threading.get_ident() == loop_thread:
            on_the_loop.append(statement)

    with world.database.session() as db:  # no line item yet: the sender finds the platform's
        link = db.get(LtiResourceLink, world.link_id)
        assert link is not None
        link.lineitem_url, link.ags_scopes = None, [ags.SCORE_SCOPE, ags.LINEITEM_SCOPE]
        db.commit()
    world.enqueue(world.submit(6))
    event.listen(world.database.engine, "before_cursor_execute", seen)
    try:
        t0 = datetime.now(UTC)
        assert world.drain(t0) == 0  # the platform is down: a failed attempt recorded
        world.platform.start()
        sent = world.drain(t0 + timedelta(minutes=1))
        assert sent == 1, world.rows()[0].last_error  # a token, the line item, the score, the outcome
    finally:
        event.remove(world.database.engine, "before_cursor_execute", seen)
    assert [s["scoreGiven"] for _, s in world.state.scores] == [60.0]
    assert world.rows()[0].attempts == 2
    assert on_the_loop == []


def test_backoff_while_the_platform_is_down_then_delivered_once(world: World) -> None:
    world.enqueue(world.submit(8))
    t0 = datetime.now(UTC)
    assert world.drain(t0) == 0  # nobody listens on the platform's port
    row = world.rows()[0]
    assert (row.state, row.attempts) == ("pending", 1)
    assert "unreachable" in (row.last_error or "")
    assert utc(row.next_attempt_at) == t0 + timedelta(seconds=30)
    assert world.drain(t0 + timedelta(seconds=20)) == 0  # not due yet: not even tried
    assert world.rows()[0].attempts == 1
    world.drain(t0 + timedelta(seconds=31))
    row = world.rows()[0]
    assert (row.attempts, utc(row.next_attempt_at)) == (2, t0 + timedelta(seconds=31 + 60))
    world.platform.start()
    assert world.drain(t0 + timedelta(minutes=5)) == 1
    assert world.drain(t0 + timedelta(hours=7)) == 0
    assert [s["scoreGiven"] for _, s in world.state.scores] == [80.0]
    assert (world.rows()[0].state, world.rows()[0].attempts) == ("sent", 3)


def test_given_up_after_the_last_attempt_and_retried_by_hand(world: World) -> None:
    world.enqueue(world.submit(5))
    at = datetime.now(UTC)
    for _ in range(ags.MAX_ATTEMPTS):
        world.drain(at)
        at += ags.BACKOFF_CAP
    row = world.rows()[0]
    assert (row.state, row.attempts) == ("failed", ags.MAX_ATTEMPTS)
    world.platform.start()
    assert world.drain(at) == 0  # failed rows stay put
    with world.database.session() as db:
        failed = db.get(LtiScore, row.id)
        assert failed is not None
        ags.retry(db, failed)
    assert world.drain(datetime.now(UTC) + timedelta(seconds=1)) == 1
    assert len(world.state.scores) == 1


def test_one_row_and_one_delivery_per_submission(world: World) -> None:
    world.platform.start()
    sub = world.submit(6)
    first = world.enqueue(sub)
    again = world.enqueue(sub)
    assert first is not None and again is not None and first.id == again.id
    assert len(world.rows()) == 1

    async def two_senders() -> list[int]:  # two replicas drain at the same moment
        at = datetime.now(UTC)
        return list(await asyncio.gather(ags.drain(world.database, at=at), ags.drain(world.database, at=at)))

    assert sorted(asyncio.run(two_senders())) == [0, 1]
    assert world.drain(datetime.now(UTC) + timedelta(days=1)) == 0
    assert len(world.state.scores) == 1


def test_a_newer_score_carries_the_best_and_supersedes_the_waiting_one(world: World) -> None:
    world.enqueue(world.submit(9))
    world.enqueue(world.submit(4))  # worse, later: the gradebook keeps 90
    assert [r.state for r in world.rows()] == ["superseded", "pending"]
    world.platform.start()
    world.drain(datetime.now(UTC))
    assert [
        (s["scoreGiven"], s["activityProgress"], s["gradingProgress"]) for _, s in world.state.scores
    ] == [(90.0, "Completed", "FullyGraded")]


def test_no_score_lost_across_a_server_restart(tmp_path: Path) -> None:
    w = build(tmp_path, "sqlite")
    try:
        w.enqueue(w.submit(10))
        t0 = datetime.now(UTC)
        w.drain(t0)  # the platform is down
        w.database.engine.dispose()  # the server stops …
        w.database = Database(w.settings)  # … and starts again on the same database
        migrate(w.database.engine)
        ags.forget_tokens()
        assert [(r.state, r.attempts) for r in w.rows()] == [("pending", 1)]
        w.platform.start()
        assert w.drain(t0 + timedelta(minutes=1)) == 1
        assert [(s["userId"], s["scoreGiven"]) for _, s in w.state.scores] == [("moodle-user-7", 100.0)]
    finally:
        w.platform.stop()
        w.database.engine.dispose()
        ags.forget_tokens()


def test_an_assignment_link_gets_the_mean_of_its_exercises(world: World) -> None:
    """A link placed for a whole assignment (custom assignment=…): one grade, the mean of the best score per
    exercise; InProgress until every exercise was handed in."""
    now = datetime.now(UTC)
    with world.database.session() as db:
        first = db.get(LtiResourceLink, world.link_id)
        assert first is not None
        course = Course(name="FT-2A", join_code="LTIAGS01")
        second = Exercise(slug="pal-taschen", title_de="Taschen", dialect="pal-mill")
        db.add_all([course, second])
        db.flush()
        a = Assignment(
            course_id=course.id,
            title="Woche 3",
            exercises=["pal-nuten", "pal-taschen"],
            mode="practice",
            late="accept",
            opens_at=now - timedelta(hours=1),
            deadline=now + timedelta(days=1),
            settings={},
        )
        db.add(a)
        db.flush()
        link = LtiResourceLink(
            platform_id=first.platform_id,
            context_pk=first.context_pk,
            resource_link_id="link-2",
            assignment_id=a.id,
            lineitem_url=first.lineitem_url.replace("li-1", "li-2"),
            ags_scopes=[ags.SCORE_SCOPE],
        )
        db.add(link)
        db.flush()
        lti_user = db.scalars(select(LtiUser)).one()
        db.add(
            LtiLaunch(
                platform_id=first.platform_id,
                deployment_id="1",
                message_type="LtiResourceLinkRequest",
                user_id=world.user_id,
                lti_user_pk=lti_user.id,
                resource_link_pk=link.id,
                exercise_slug="pal-nuten",
                role="learner",
                ticket_hash="x" * 64,
                ticket_expires_at=now,
            )
        )
        db.commit()
        ids = (a.id, second.id)
    world.platform.start()
    for score, exercise in ((8, None), (10, ids[1])):
        sub = world.submit(score, exercise_id=exercise, assignment_id=ids[0])
        with world.database.session() as db:
            stored = db.get(Submission, sub.id)
            assert stored is not None
            ags.after_graded(db, stored)
        world.drain(datetime.now(UTC))
    assert [(item, s["scoreGiven"], s["activityProgress"]) for item, s in world.state.scores] == [
        ("li-2", 40.0, "InProgress"),
        ("li-2", 90.0, "Completed"),
    ]


def test_a_platform_that_does_not_answer_costs_one_attempt_per_round(world: World) -> None:
    world.enqueue(world.submit(7))
    with world.database.session() as db:  # a second trainee of the same course
        ben = User(username="ben", password_hash="-", role="student")
        db.add(ben)
        db.flush()
        link = db.get(LtiResourceLink, world.link_id)
        assert link is not None
        db.add(LtiUser(platform_id=link.platform_id, sub="moodle-user-8", user_id=ben.id))
        db.commit()
        world.user_id, anna = ben.id, world.user_id
    world.enqueue(world.submit(9))
    world.user_id = anna
    t0 = datetime.now(UTC)
    assert world.drain(t0) == 0
    assert sorted(r.attempts for r in world.rows()) == [0, 1]  # the second waits for the next round
    world.platform.start()
    assert world.drain(t0 + timedelta(minutes=1)) == 2
    assert sorted((s["userId"], s["scoreGiven"]) for _, s in world.state.scores) == [
        ("moodle-user-7", 70.0),
        ("moodle-user-8", 90.0),
    ]


def test_an_exam_score_waits_for_the_release_and_shows_in_no_other_score(world: World) -> None:
    world.platform.start()
    exam = world.submit(10, held=True)  # an exam's, results not released yet
    world.enqueue(exam)
    assert world.drain(datetime.now(UTC)) == 0
    world.enqueue(world.submit(5))  # practice afterwards: its best so far is 50, not the exam's 100
    assert world.drain(datetime.now(UTC)) == 1
    assert [s["scoreGiven"] for _, s in world.state.scores] == [50.0]
    assert [r.state for r in world.rows()] == ["pending", "sent"]
    with world.database.session() as db:  # the instructor releases the results
        stored = db.get(Submission, exam.id)
        assert stored is not None
        stored.held = False
        db.commit()
    assert world.drain(datetime.now(UTC)) == 1
    assert [s["scoreGiven"] for _, s in world.state.scores] == [50.0, 100.0]


def test_a_submission_through_an_api_key_is_not_passed_back_for_the_key_owner(world: World) -> None:
    with world.database.session() as db:
        link = db.get(LtiResourceLink, world.link_id)
        user = db.get(User, world.user_id)
        assert link is not None and user is not None
        key = ApiKey(
            name="lms", prefix="pt_test1", key_hash="-", scopes=["submissions:write"], owner_id=user.id
        )
        db.add(key)
        db.add(
            LtiLaunch(
                platform_id=link.platform_id,
                deployment_id="1",
                message_type="LtiResourceLinkRequest",
                user_id=user.id,
                lti_user_pk=db.scalars(select(LtiUser)).one().id,
                resource_link_pk=link.id,
                exercise_slug="pal-nuten",
                role="learner",
                ticket_hash="y" * 64,
                ticket_expires_at=datetime.now(UTC),
            )
        )
        db.commit()
        for api_key_id in (key.id, None):
            sub = Submission(
                exercise_id=world.exercise_id,
                user_id=user.id,
                api_key_id=api_key_id,
                external_user="azubi-17" if api_key_id else None,
                program="N10 M30\n",
                dialect="pal-mill",
                result={},
                grading={"score": 3, "max_score": 10, "criteria": []},
            )
            db.add(sub)
            db.commit()
            ags.after_graded(db, sub)
    assert [(r.lti_sub, r.score_given) for r in world.rows()] == [
        ("moodle-user-7", 30.0)
    ]  # the user's own only
