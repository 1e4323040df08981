"""The 3D view cannot exhaust the server (issue 13, point 4): new sessions, scene, playhead, deviation and the
pictures are rate-limited; live 3D sessions are capped per user, per address and in total (the one idle the
longest is stopped first); a 3D token drives only its creator's scene; one log line per session, not viser's
banner on standard output."""

from __future__ import annotations

import json
import logging
import os
from collections.abc import Iterator
from pathlib import Path

import pytest
from fastapi.testclient import TestClient
from server_helpers import GOOD, Api, auth, error_code, make_settings
from starlette.websockets import WebSocketDisconnect

from server import viz
from server.app import create_app

VISER_PROTOCOL = "viser-v" + __import__("viser").__version__


@pytest.fixture(scope="module")
def small(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Api]:
    """An app with small limits: 4 new 3D sessions a minute, 3 scene runs, 5 playhead steps, 2 pictures;
    at most 2 live sessions per user, 3 per address, 4 in all."""
    settings = make_settings(
        tmp_path_factory.mktemp("vizlimits"),
        "sqlite",
        workers=1,
        rate_viz_per_minute=4,
        rate_viz_scene_per_minute=3,
        rate_viz_playhead_per_minute=5,
        rate_picture_per_minute=2,
        viz_sessions_per_user=2,
        viz_sessions_per_address=3,
        viz_sessions_max=4,
    )
    with TestClient(create_app(settings), base_url="http://127.0.0.1") as client:
        yield Api(client)


@pytest.fixture(autouse=True)
def _fresh(small: Api) -> Iterator[None]:
    small.app.state.limiter.reset()
    small.app.state.scenes.stop_all()
    small.client.cookies.clear()
    yield


def scenes_of(api: Api) -> viz.Scenes:
    scenes: viz.Scenes = api.app.state.scenes
    return scenes


def new_token(api: Api, headers: dict[str, str] | None = None) -> str:
    r = api.client.post("/api/v1/viz", headers=headers or {})
    assert r.status_code == 201, r.text
    return str(r.json()["token"])


def open_fds() -> int:
    return len(os.listdir("/proc/self/fd"))


def test_new_3d_sessions_are_rate_limited(small: Api) -> None:
    for _ in range(4):
        new_token(small)
    r = small.client.post("/api/v1/viz")
    assert r.status_code == 429 and error_code(r) == "RATE_LIMITED"
    assert int(r.headers["Retry-After"]) > 0
    # another user has a budget of their own
    assert small.client.post("/api/v1/viz", headers=auth(small.user())).status_code == 201


def test_scene_deviation_and_playhead_are_rate_limited(small: Api) -> None:
    student = small.user()
    token = new_token(small, auth(student))
    codes = [
        small.client.post(
            f"/api/v1/viz/{token}/scene", json={"program": GOOD}, headers=auth(student)
        ).status_code
        for _ in range(4)
    ]
    assert codes == [200, 200, 200, 429]
    # the deviation runs the program too: the same budget
    r = small.client.post(
        f"/api/v1/viz/{token}/deviation", json={"program": GOOD, "exercise": "x"}, headers=auth(student)
    )
    assert r.status_code == 429
    steps = [
        small.client.post(
            f"/api/v1/viz/{token}/playhead", json={"index": 0}, headers=auth(student)
        ).status_code
        for _ in range(6)
    ]
    assert steps == [200] * 5 + [429]


def test_pictures_are_rate_limited(small: Api) -> None:
    student = small.user()
    codes = [
        small.client.post(
            "/api/v1/viz/picture.png", json={"program": GOOD}, headers=auth(student)
        ).status_code
        for _ in range(3)
    ]
    assert codes == [200, 200, 429]
    # the exercise's picture counts in the same budget
    r = small.client.get("/api/v1/exercises/no-such-exercise/picture.png", headers=auth(student))
    assert r.status_code == 429


def test_picture_of_the_current_state(small: Api) -> None:
    r = small.client.post("/api/v1/viz/picture.png", json={"program": GOOD})
    assert r.status_code == 200 and r.headers["content-type"] == "image/png"
    assert r.content.startswith(b"\x89PNG")
    width, height = int.from_bytes(r.content[16:20], "big"), int.from_bytes(r.content[20:24], "big")
    assert width > height > 100  # the 80 × 70 mm block seen from above
    bad = small.client.post(
        "/api/v1/viz/picture.png", json={"program": GOOD, "stock": {"min": [0, 0, 0], "max": [0, 0, 0]}}
    )
    assert bad.status_code == 422


def test_live_sessions_are_capped_per_address_and_the_oldest_idle_goes_first(small: Api) -> None:
    tokens = [new_token(small) for _ in range(4)]  # anonymous, all from 127.0.0.1 (testclient)
    for token in tokens:
        assert small.client.get(f"/viz/{token}/").status_code == 200
    scenes = scenes_of(small)
    assert len(scenes) == 3  # per address
    live = scenes.sids()
    assert scenes.ticket(tokens[0]).sid not in live  # the one idle the longest was stopped
    assert all(scenes.ticket(t).sid in live for t in tokens[1:])


def test_live_sessions_are_capped_per_user_and_in_total(small: Api) -> None:
    a, b = small.user(), small.user()
    mine = [new_token(small, auth(a)) for _ in range(3)]
    for token in mine:
        assert (
            small.client.post(f"/api/v1/viz/{token}/playhead", json={"index": 0}, headers=auth(a)).status_code
            == 200
        )
    scenes = scenes_of(small)
    assert len(scenes) == 2
    assert scenes.ticket(mine[0]).sid not in scenes.sids()
    theirs = [new_token(small, auth(b)) for _ in range(2)]
    anonymous = new_token(small)
    for token in theirs:
        small.client.post(f"/api/v1/viz/{token}/playhead", json={"index": 0}, headers=auth(b))
    small.client.get(f"/viz/{anonymous}/")
    assert len(scenes) == 4  # in total
    assert scenes.ticket(mine[1]).sid not in scenes.sids()  # a's oldest went first


def test_thousands_of_sessions_do_not_use_up_descriptors(small: Api) -> None:
    before = open_fds()
    settings = small.settings
    for i in range(40):
        small.app.state.limiter.reset()
        small.client.cookies.clear()
        who = auth(small.user()) if i % 2 else {}
        assert small.client.get(f"/viz/{new_token(small, who)}/", headers=who).status_code == 200
    assert len(scenes_of(small)) <= settings.viz_sessions_max
    assert open_fds() - before <= 8 * settings.viz_sessions_max


def test_a_token_drives_only_its_creators_scene(small: Api) -> None:
    owner, other = small.user(), small.user()
    token = new_token(small, auth(owner))
    ok = small.client.post(f"/api/v1/viz/{token}/scene", json={"program": GOOD}, headers=auth(owner))
    assert ok.status_code == 200
    for who in (auth(other), {}):
        for path, body in (
            ("scene", {"program": GOOD}),
            ("playhead", {"index": 0}),
            ("view", {"view": "top"}),
            ("layers", {"rapid": False}),
            ("deviation", {"program": GOOD, "exercise": "x"}),
        ):
            r = small.client.post(f"/api/v1/viz/{token}/{path}", json=body, headers=who)
            assert r.status_code == 403 and error_code(r) == "VIZ_FOREIGN", (path, who, r.text)
    assert small.client.get(f"/viz/{token}/").status_code == 403  # the browser without the owner's cookie
    with (
        pytest.raises(WebSocketDisconnect) as closed,
        small.client.websocket_connect(f"/viz/{token}", subprotocols=[VISER_PROTOCOL]) as ws,
    ):
        ws.receive_bytes()
    assert closed.value.code == 4403


def test_an_anonymous_token_belongs_to_its_browser(small: Api, tmp_path: Path) -> None:
    token = new_token(small)
    assert small.client.cookies.get(viz.VIZ_COOKIE)  # the browser's anonymous 3D cookie
    assert small.client.post(f"/api/v1/viz/{token}/playhead", json={"index": 0}).status_code == 200
    assert small.client.get(f"/viz/{token}/").status_code == 200
    cookie = small.client.cookies.get(viz.VIZ_COOKIE)
    small.client.cookies.clear()  # another browser
    r = small.client.post(f"/api/v1/viz/{token}/playhead", json={"index": 0})
    assert r.status_code == 403 and error_code(r) == "VIZ_FOREIGN"
    small.client.cookies.set(viz.VIZ_COOKIE, "forged-" + (cookie or ""), domain="127.0.0.1")
    assert small.client.get(f"/viz/{token}/").status_code == 403
    # a second session of the same browser keeps its cookie
    small.client.cookies.clear()
    small.client.cookies.set(viz.VIZ_COOKIE, cookie or "", domain="127.0.0.1")
    again = new_token(small)
    assert small.client.cookies.get(viz.VIZ_COOKIE) == cookie
    assert small.client.post(f"/api/v1/viz/{again}/playhead", json={"index": 0}).status_code == 200


def test_one_log_line_per_session_and_no_banner(small: Api, capfd: pytest.CaptureFixture[str]) -> None:
    records: list[logging.LogRecord] = []
    handler = logging.Handler()
    handler.emit = records.append  # type: ignore[method-assign]
    logger = logging.getLogger("paltrainer.server")
    level = logger.level
    logger.addHandler(handler)
    logger.setLevel(logging.INFO)
    try:
        token = new_token(small)
        small.client.get(f"/viz/{token}/")
        small.app.state.scenes.stop_all()
    finally:
        logger.removeHandler(handler)
        logger.setLevel(level)
    out = capfd.readouterr()
    assert "Websocket" not in out.out + out.err and "╭" not in out.out + out.err  # viser's banner
    assert "Server stopped" not in out.out + out.err
    mine = [r for r in records if r.getMessage().startswith("3D view")]
    assert [r.getMessage() for r in mine] == ["3D view started", "3D view stopped"]
    started = mine[0].viz  # type: ignore[attr-defined]
    assert started["owner"] == "anonymous" and started["port"] > 0 and started["live"] == 1
    assert mine[1].viz["reason"] == "shutdown"  # type: ignore[attr-defined]
    json.dumps(started)  # plain data: the JSON log formatter writes it as it is
