"""WebSocket /api/v1/live under bad frames, failing jobs and dead workers: every frame is answered (an error
message or a proper close code) and the session keeps answering valid edits; Origin and connection limits."""

from __future__ import annotations

import json
import os
import signal
from typing import Any

import anyio
import pytest
from server_helpers import GOOD, Api, auth
from starlette.testclient import WebSocketTestSession

from server import live

URL = "/api/v1/live"


def receive(ws: WebSocketTestSession, seconds: float = 30) -> dict[str, Any]:
    """The next message, or the close as {"type": "close", ...}; a session gone silent fails the test, not hangs it."""

    async def get() -> dict[str, Any]:
        with anyio.fail_after(seconds):
            message: dict[str, Any] = await ws._send_rx.receive()
            return message

    message = ws.portal.call(get)
    if message["type"] == "websocket.close":
        return {"type": "close", "code": message.get("code", 1000), "reason": message.get("reason", "")}
    assert message["type"] == "websocket.send", message
    answer: dict[str, Any] = json.loads(message["text"])
    return answer


def opened(ws: WebSocketTestSession) -> None:
    ws.send_text(json.dumps({"type": "open", "version": 0, "text": GOOD}))
    update = receive(ws)
    assert update["type"] == "update" and update["version"] == 0


def still_answers(ws: WebSocketTestSession, version: int, x: int = 33) -> None:
    ws.send_text(json.dumps({"type": "edit", "version": version, "line": 5, "text": f"N50 G1 X{x}"}))
    update = receive(ws)
    assert update["type"] == "update" and update["version"] == version
    assert update["final"] == [float(x), 0.0, 50.0]


@pytest.mark.parametrize(
    "frame",
    [
        {"type": "open", "version": 1, "text": "N10 G0 X\ud800\n"},
        {"type": "edit", "version": 1, "line": 2, "text": "N20 \ud800"},
        {"type": "sync", "version": 1, "text": "N10 \udfff M30\n"},
        {"type": "open", "version": 1, "text": GOOD, "exercise": "\ud800"},
        {"type": "open", "version": 1, "text": GOOD, "dialect": "pal-\ud800"},
        {"type": "edit", "version": 1, "line": 2, "text": "x", "\ud800": 1},
    ],
)
def test_a_lone_surrogate_is_an_error_and_the_session_goes_on(api: Api, frame: dict[str, Any]) -> None:
    with api.client.websocket_connect(URL) as ws:
        opened(ws)
        ws.send_text(
            json.dumps(frame)
        )  # ensure_ascii: the frame carries the escape \ud800, as a browser's would
        error = receive(ws)
        assert error["type"] == "error" and error["code"] == "BAD_MESSAGE" and error["version"] == 1
        assert error["message"] and error["message_en"]
        still_answers(ws, 2)


def test_a_binary_frame_is_an_error_and_the_session_goes_on(api: Api) -> None:
    with api.client.websocket_connect(URL) as ws:
        opened(ws)
        ws.send_bytes(json.dumps({"type": "edit", "version": 1, "line": 5, "text": "N50 G1 X40"}).encode())
        error = receive(ws)
        assert error["type"] == "error" and error["code"] == "BAD_MESSAGE"
        assert "Binärnachricht" in error["message"] and "binary" in error["message_en"]
        still_answers(ws, 2)


@pytest.mark.parametrize("depth", [100_000, 5_000])
def test_deeply_nested_json_is_an_error_and_the_session_goes_on(api: Api, depth: int) -> None:
    with api.client.websocket_connect(URL) as ws:
        opened(ws)
        ws.send_text("[" * depth + "]" * depth)
        assert receive(ws)["code"] == "BAD_MESSAGE"
        ws.send_text(
            '{"type": "edit", "version": 1, "line": 5, "text": "N50 G1 X1", "x": '
            + "[" * depth
            + "]" * depth
            + "}"
        )
        assert receive(ws)["code"] == "BAD_MESSAGE"
        still_answers(ws, 2)


def test_a_frame_over_the_size_limit_closes_with_1009(api: Api) -> None:
    with api.client.websocket_connect(URL) as ws:
        opened(ws)
        ws.send_text(json.dumps({"type": "sync", "version": 1, "text": "N10 G0 X0\n" * 200_000}))
        closed = receive(ws)
    assert closed["type"] == "close" and closed["code"] == 1009


def test_a_job_that_fails_is_answered_with_an_error_update(api: Api, monkeypatch: pytest.MonkeyPatch) -> None:
    with api.client.websocket_connect(URL) as ws:
        opened(ws)
        monkeypatch.setattr(live, "job_live", int)  # raises TypeError in the worker, like a defect in a job
        ws.send_text(json.dumps({"type": "edit", "version": 1, "line": 5, "text": "N50 G1 X40"}))
        error = receive(ws)
        assert error["type"] == "error" and error["code"] == "RUN_FAILED" and error["version"] == 1
        assert error["message"] and error["message_en"]
        monkeypatch.undo()
        still_answers(ws, 2)


def test_a_job_over_the_time_limit_is_answered_and_the_session_goes_on(api: Api) -> None:
    workers = api.app.state.workers
    with api.client.websocket_connect(URL) as ws:
        opened(ws)
        old = workers.seconds
        workers.seconds = 0.0001
        try:
            ws.send_text(json.dumps({"type": "sync", "version": 1, "text": GOOD * 300}))
            error = receive(ws)
        finally:
            workers.seconds = old
        assert error["type"] == "error" and error["code"] == "TIME_LIMIT" and error["version"] == 1
        ws.send_text(json.dumps({"type": "sync", "version": 2, "text": GOOD}))
        assert receive(ws)["type"] == "update"
        still_answers(ws, 3)


def test_a_killed_worker_does_not_silence_the_session(api: Api) -> None:
    workers = api.app.state.workers
    with api.client.websocket_connect(URL) as ws:
        opened(ws)
        for pid in workers.pids():
            os.kill(pid, signal.SIGKILL)
        ws.send_text(json.dumps({"type": "edit", "version": 1, "line": 5, "text": "N50 G1 X41"}))
        update = receive(ws, 90)
        assert update["type"] == "update" and update["version"] == 1 and update["final"] == [41.0, 0.0, 50.0]
        assert [x["line"] for x in update["toolpath"]] == [5, 6]  # still only what changed for the client
        still_answers(ws, 2)


# --- Origin and connection limits -------------------------------------------------------------


def refusal(api: Api, **headers: str) -> dict[str, Any]:
    with api.client.websocket_connect(URL, headers=headers) as ws:
        return receive(ws)


def test_a_foreign_origin_is_refused(api: Api) -> None:
    closed = refusal(api, origin="https://evil.example")
    assert closed["type"] == "close" and closed["code"] == 4403 and closed["reason"] == "ORIGIN_NOT_ALLOWED"
    for origin in ("http://testserver.evil.example", "null", "http://testserver:81"):
        assert refusal(api, origin=origin)["code"] == 4403


@pytest.mark.parametrize(
    "origin", [None, "http://testserver", "https://testserver", "https://moodle.example.org"]
)
def test_the_own_origin_configured_origins_and_non_browsers_are_accepted(
    api: Api, origin: str | None
) -> None:
    old = api.settings.cors_origins
    api.settings.cors_origins = ["https://moodle.example.org"]
    try:
        with api.client.websocket_connect(URL, headers={"origin": origin} if origin else {}) as ws:
            opened(ws)
    finally:
        api.settings.cors_origins = old


def test_connections_per_address_and_per_user_are_limited(api: Api) -> None:
    settings = api.settings
    old = settings.live_connections_per_address, settings.live_connections_per_user
    settings.live_connections_per_address, settings.live_connections_per_user = 2, 1
    try:
        with api.client.websocket_connect(URL) as one, api.client.websocket_connect(URL) as two:
            opened(one)
            opened(two)
            closed = refusal(api)
            assert closed["type"] == "close" and closed["code"] == 4429
            assert "höchstens 2" in closed["reason"] and "at most 2" in closed["reason"]
            assert len(closed["reason"].encode()) <= 123
            token = auth(api.user())["Authorization"].split()[1]
            with api.client.websocket_connect(f"{URL}?token={token}") as mine:
                opened(mine)  # a logged-in user is counted as the user, not as the address
                with api.client.websocket_connect(f"{URL}?token={token}") as ws:
                    assert receive(ws)["code"] == 4429
        with api.client.websocket_connect(URL) as again:  # closed connections no longer count
            opened(again)
    finally:
        settings.live_connections_per_address, settings.live_connections_per_user = old
