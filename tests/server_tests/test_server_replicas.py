"""Replicas behind a load balancer (issue 21): a 3D token names the replica that holds its scene (REPLICA_ID),
another replica answers it 410 VIZ_ELSEWHERE (the page then opens a new scene there), the page's watch socket
stays open while the scene's replica lives; the rate limits count through `limits` (moving window), in the
process without REDIS_URL and still in the process while Redis does not answer."""

from __future__ import annotations

import logging
import socket
from collections.abc import Iterator
from pathlib import Path

import pytest
from fastapi.testclient import TestClient
from server_helpers import GOOD, Api, error_code, make_settings
from starlette.websockets import WebSocketDisconnect

from server import viz
from server.app import create_app
from server.config import Settings
from server.ratelimit import RateLimiter

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def replica(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Api]:
    settings = make_settings(tmp_path_factory.mktemp("replica"), "sqlite", workers=1, replica_id="r1")
    with TestClient(create_app(settings), base_url="http://127.0.0.1") as client:
        yield Api(client)


def other_replica_token(api: Api, name: str) -> str:
    """A token made by replica `name` with the same secret (as every replica of one installation has)."""
    return viz.Scenes(
        api.settings.jwt_secret(), api.settings.model_copy(update={"replica_id": name})
    ).new_token("anon:" + "x" * 20, "ip:127.0.0.1")


def test_a_3d_token_names_its_replica(replica: Api) -> None:
    r = replica.client.post("/api/v1/viz")
    assert r.status_code == 201, r.text
    token = r.json()["token"]
    assert token.startswith("r1.") and viz.replica_of(token) == "r1"
    assert r.json()["url"] == f"/viz/{token}/"
    r = replica.client.post(f"/api/v1/viz/{token}/scene", json={"program": GOOD})
    assert r.status_code == 200, r.text
    assert r.json()["segments"] > 0


def test_another_replicas_token_is_gone_here(replica: Api) -> None:
    token = other_replica_token(replica, "r2")
    r = replica.client.post(f"/api/v1/viz/{token}/scene", json={"program": GOOD})
    assert r.status_code == 410 and error_code(r) == "VIZ_ELSEWHERE"
    assert replica.client.post(f"/api/v1/viz/{token}/playhead", json={"index": 0}).status_code == 410
    assert replica.client.get(f"/viz/{token}/").status_code == 410
    with (
        pytest.raises(WebSocketDisconnect) as closed,
        replica.client.websocket_connect(f"/viz/{token}/alive") as ws,
    ):
        ws.receive_text()
    assert closed.value.code == 4410


def test_a_forged_token_is_still_401(replica: Api) -> None:
    r = replica.client.post("/api/v1/viz/r1.a.b.c/scene", json={"program": GOOD})
    assert r.status_code == 401 and error_code(r) == "BAD_TOKEN"


def test_the_watch_socket_stays_open_for_this_replicas_scene(replica: Api) -> None:
    token = replica.client.post("/api/v1/viz").json()["token"]
    with replica.client.websocket_connect(f"/viz/{token}/alive") as ws:
        ws.send_text("ping")  # still open: a closed socket would raise here or on close
    with (
        pytest.raises(WebSocketDisconnect) as closed,
        replica.client.websocket_connect("/viz/r1.x.y.z/alive") as ws,
    ):
        ws.receive_text()
    assert closed.value.code == 4401


def test_a_single_server_needs_no_replica_id() -> None:
    assert Settings(_env_file=None).replica_id == ""
    scenes = viz.Scenes("s" * 40)
    token = scenes.new_token("user:1", "user:1")
    assert token.count(".") == 2 and scenes.ticket(token) is not None and not scenes.elsewhere(token)


def test_moving_window_in_the_process() -> None:
    limiter = RateLimiter()
    assert [limiter.hit("check", "user:1", 3) for _ in range(3)] == [0, 0, 0]
    wait = limiter.hit("check", "user:1", 3)
    assert 55 <= wait <= 60
    assert limiter.hit("check", "user:2", 3) == 0  # another caller has their own budget
    assert limiter.wait("login", "name:a", 2) == 0
    limiter.record("login", "name:a", 2)
    limiter.record("login", "name:a", 2)
    assert limiter.wait("login", "name:a", 2) > 0
    limiter.reset()
    assert limiter.hit("check", "user:1", 3) == 0


def test_without_redis_the_limits_hold_in_the_process(caplog: pytest.LogCaptureFixture) -> None:
    with socket.socket() as s:  # a port nobody listens on
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    limiter = RateLimiter(f"redis://127.0.0.1:{port}/0")
    server_log = logging.getLogger(
        "paltrainer.server"
    )  # (the app's log set-up stops it propagating to caplog's)
    server_log.addHandler(caplog.handler)
    try:
        with caplog.at_level("WARNING", logger="paltrainer.server"):
            assert [limiter.hit("submit", "user:1", 2) for _ in range(2)] == [0, 0]
            assert limiter.hit("submit", "user:1", 2) > 0
    finally:
        server_log.removeHandler(caplog.handler)
    # one refused connection, then the process's counts for a while (not a connection attempt per request)
    refused = {id(r) for r in caplog.records if "Redis does not answer" in r.getMessage()}
    assert len(refused) == 1  # (a record seen through both handlers is one)


def connections_held_at_worker_calls(replica: Api, monkeypatch: pytest.MonkeyPatch) -> list[int]:
    """The pool's checked-out connections at each worker call, as the calls happen."""
    workers = replica.app.state.workers
    pool = replica.app.state.db.engine.pool
    held: list[int] = []
    original = workers.call

    async def call(*args: object, **kwargs: object) -> object:
        held.append(pool.checkedout())
        return await original(*args, **kwargs)

    monkeypatch.setattr(workers, "call", call)
    return held


def test_a_submission_being_graded_holds_no_database_connection(
    replica: Api, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Many submissions waiting for a worker at once must not take every pooled connection: a request that then
    needs one would wait for the pool inside the event loop, and the replica would stall (bench/scale.py with
    16 clients on one replica did)."""
    held = connections_held_at_worker_calls(replica, monkeypatch)
    with_exercises(replica)
    user = replica.user()
    program = (ROOT / "exercises" / "pal-mill" / "pal-01-g1-gerade.nc").read_text(encoding="utf-8")
    r = replica.client.post(
        "/api/v1/submissions",
        json={"exercise": "pal-01-g1-gerade", "program": program},
        headers={"Authorization": user["Authorization"]},
    )
    assert r.status_code == 201, r.text
    assert held == [0]


def test_a_3d_scene_being_computed_holds_no_database_connection(
    replica: Api, monkeypatch: pytest.MonkeyPatch
) -> None:
    held = connections_held_at_worker_calls(replica, monkeypatch)
    with_exercises(replica)
    auth = {"Authorization": replica.user()["Authorization"]}
    token = replica.client.post("/api/v1/viz", headers=auth).json()["token"]
    r = replica.client.post(
        f"/api/v1/viz/{token}/scene", json={"program": GOOD, "exercise": "pal-01-g1-gerade"}, headers=auth
    )
    assert r.status_code == 200, r.text
    assert held == [0]


def with_exercises(api: Api) -> None:
    from server import repository as repo
    from server.seed import load_exercises

    with api.app.state.db.session() as db:
        if repo.exercise_by_slug(db, "pal-01-g1-gerade") is None:
            load_exercises(db, ROOT / "exercises")


@pytest.mark.parametrize("path", ["/api/v1/check", "/api/v1/run", "/api/v1/simulate"])
def test_a_program_being_checked_holds_no_database_connection(
    replica: Api, monkeypatch: pytest.MonkeyPatch, path: str
) -> None:
    """/check, /run and /simulate wait for a worker like a submission: without their connection."""
    held = connections_held_at_worker_calls(replica, monkeypatch)
    auth = {"Authorization": replica.user()["Authorization"]}
    r = replica.client.post(path, json={"program": GOOD, "dialect": "pal-mill"}, headers=auth)
    assert r.status_code == 200, r.text
    assert held == [0]
