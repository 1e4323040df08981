"""WebSocket /api/v1/live: open, per-line edits, only changed lines answered, versions, errors."""

from __future__ import annotations

import json
from typing import Any

import pytest
from server_helpers import GOOD, Api, auth
from starlette.testclient import WebSocketTestSession
from starlette.websockets import WebSocketDisconnect

from core.pipeline import run

URL = "/api/v1/live"


def receive(ws: WebSocketTestSession) -> dict[str, Any]:
    message: dict[str, Any] = json.loads(ws.receive_text())
    return message


def lines_of(items: list[dict[str, Any]]) -> dict[int, list[dict[str, Any]]]:
    return {x["line"]: x["items"] for x in items}


def test_open_answers_every_line_with_something(api: Api) -> None:
    with api.client.websocket_connect(URL) as ws:
        ws.send_text(json.dumps({"type": "open", "version": 0, "text": GOOD, "dialect": "pal-mill"}))
        update = receive(ws)
    assert update["type"] == "update" and update["version"] == 0 and update["line_count"] == 6
    assert update["diagnostics"] == []
    expected_lines = sorted({c.span.line for c in run(GOOD).commands})
    assert [x["line"] for x in update["toolpath"]] == expected_lines
    assert update["final"] == [20.0, 0.0, 50.0]


def test_edit_answers_only_changed_lines_including_later_ones(api: Api) -> None:
    with api.client.websocket_connect(URL) as ws:
        ws.send_text(json.dumps({"type": "open", "version": 0, "text": GOOD}))
        receive(ws)
        ws.send_text(json.dumps({"type": "edit", "version": 1, "line": 2, "text": "N20 S1200 F150 M3 X1,5"}))
        update = receive(ws)
        assert update["version"] == 1
        diags = lines_of(update["diagnostics"])
        assert [d["code"] for d in diags[2]] == ["PAL-E010"]
        assert diags.keys() > {2}  # later lines now lack feed and spindle: they get diagnostics too
        # a block with an error changes nothing: the spindle no longer turns in any later move
        assert [x["line"] for x in update["toolpath"]] == [3, 4, 5, 6]
        assert all(m["spindle"] == 0 for x in update["toolpath"] for m in x["moves"])
        ws.send_text(json.dumps({"type": "edit", "version": 2, "line": 2, "text": "N20 S1200 F150 M3"}))
        update = receive(ws)
        assert lines_of(update["diagnostics"]) == {n: [] for n in diags}
        assert [x["line"] for x in update["toolpath"]] == [3, 4, 5, 6]
        ws.send_text(json.dumps({"type": "edit", "version": 3, "line": 5, "text": "N50 G1 X30"}))
        update = receive(ws)
        assert update["diagnostics"] == []
        # the end of line 5 moves, so does the start of line 6; lines 1-4 are not sent again
        assert [x["line"] for x in update["toolpath"]] == [5, 6]
        assert update["toolpath"][1]["moves"][0]["start"][0] == 30


def test_insert_and_delete_lines(api: Api) -> None:
    with api.client.websocket_connect(URL) as ws:
        ws.send_text(json.dumps({"type": "open", "version": 0, "text": GOOD}))
        receive(ws)
        ws.send_text(
            json.dumps({"type": "edit", "version": 1, "line": 4, "end_line": 3, "text": "N35 G0 X5"})
        )
        update = receive(ws)
        assert update["line_count"] == 7
        assert 4 in [x["line"] for x in update["toolpath"]]
        ws.send_text(json.dumps({"type": "edit", "version": 2, "line": 6, "end_line": 7, "text": ""}))
        update = receive(ws)
        assert update["line_count"] == 6
        assert [d["code"] for d in lines_of(update["diagnostics"])[5]] == ["PAL-W102"]
        ws.send_text(json.dumps({"type": "sync", "version": 3, "text": GOOD}))
        update = receive(ws)
        assert update["line_count"] == 6 and all(not x["items"] for x in update["diagnostics"])


def test_stale_version_is_ignored(api: Api) -> None:
    with api.client.websocket_connect(URL) as ws:
        ws.send_text(json.dumps({"type": "open", "version": 0, "text": GOOD}))
        receive(ws)
        ws.send_text(json.dumps({"type": "edit", "version": 5, "line": 2, "text": "N20 S1200 F150 M3 X1,5"}))
        assert receive(ws)["version"] == 5
        ws.send_text(json.dumps({"type": "edit", "version": 4, "line": 2, "text": "N20 S1200 F150 M3"}))
        error = receive(ws)
        assert error["type"] == "error" and error["code"] == "STALE_VERSION" and error["version"] == 4
        ws.send_text(json.dumps({"type": "edit", "version": 6, "line": 6, "text": "N60 G0 Z50 M30"}))
        update = receive(ws)
        assert update["version"] == 6 and update["diagnostics"] == []  # line 2 still has its error, unchanged


def test_fast_edits_are_answered_in_order_and_end_at_the_newest_version(api: Api) -> None:
    with api.client.websocket_connect(URL) as ws:
        ws.send_text(json.dumps({"type": "open", "version": 0, "text": GOOD}))
        receive(ws)
        for v, x in enumerate((21, 22, 23, 24, 25, 26, 27, 28), start=1):
            ws.send_text(json.dumps({"type": "edit", "version": v, "line": 5, "text": f"N50 G1 X{x}"}))
        updates = []
        while not updates or updates[-1]["version"] != 8:
            updates.append(receive(ws))
        versions = [u["version"] for u in updates]
        assert versions == sorted(set(versions)) and len(versions) <= 8
        # folding every update's changes in order gives the newest document's result
        ends: dict[int, float] = {}
        for u in updates:
            for entry in u["toolpath"]:
                if entry["moves"]:
                    ends[entry["line"]] = entry["moves"][-1]["end"][0]
        assert ends[5] == 28
        ws.send_text(json.dumps({"type": "edit", "version": 9, "line": 1, "text": "N10 T1 TC1 M6"}))
        update = receive(ws)
        assert update.pop("run") in ("incremental", "to_end")  # not a full run: the worker has the last one
        assert update == {
            "type": "update",
            "version": 9,
            "line_count": 6,
            "diagnostics": [],
            "toolpath": [],
            "final": [28.0, 0.0, 50.0],
        }


def test_protocol_errors(api: Api) -> None:
    with api.client.websocket_connect(URL) as ws:
        ws.send_text("not json")
        assert receive(ws)["code"] == "BAD_MESSAGE"
        ws.send_text(json.dumps({"type": "edit", "version": 1, "line": 1, "text": "x"}))
        assert receive(ws)["code"] == "NOT_OPEN"
        ws.send_text(json.dumps({"type": "open", "version": 0, "text": GOOD, "dialect": "iso"}))
        assert receive(ws)["code"] == "UNKNOWN_DIALECT"
        ws.send_text(json.dumps({"type": "open", "version": 0, "text": GOOD, "exercise": "nope"}))
        assert receive(ws)["code"] == "EXERCISE_NOT_FOUND"
        ws.send_text(json.dumps({"type": "open", "version": 0, "text": GOOD}))
        receive(ws)
        ws.send_text(json.dumps({"type": "edit", "version": 1, "line": 99, "text": "x"}))
        error = receive(ws)
        assert error["code"] == "BAD_LINE" and error["message"] and error["message_en"]
        ws.send_text(json.dumps({"type": "frobnicate", "version": 2}))
        assert receive(ws)["code"] == "BAD_MESSAGE"
        ws.send_text(json.dumps({"type": "edit", "version": "x", "line": 1, "text": ""}))
        assert receive(ws)["code"] == "BAD_MESSAGE"
        big = "N10 G0 X0\n" * (api.settings.max_program_chars // 10 + 1)
        ws.send_text(json.dumps({"type": "sync", "version": 3, "text": big}))
        assert receive(ws)["code"] == "PROGRAM_TOO_LARGE"
        old = api.settings.max_live_lines
        api.settings.max_live_lines = 7
        try:
            ws.send_text(json.dumps({"type": "edit", "version": 4, "line": 1, "end_line": 0, "text": "\n\n"}))
            assert receive(ws)["code"] == "TOO_MANY_LINES"
        finally:
            api.settings.max_live_lines = old
        ws.send_text(json.dumps({"type": "edit", "version": 5, "line": 1, "text": "N10 T1 TC1 M6"}))
        update = receive(ws)
        assert update["type"] == "update" and update["version"] == 5 and update["line_count"] == 6


def test_free_practice_off_closes_anonymous_sockets(api: Api) -> None:
    api.settings.free_practice = False
    try:
        with pytest.raises(WebSocketDisconnect) as err, api.client.websocket_connect(URL) as ws:
            ws.receive_text()
        assert err.value.code == 4401
        student = api.user()
        token = auth(student)["Authorization"].split()[1]
        with api.client.websocket_connect(f"{URL}?token={token}") as ws:
            ws.send_text(json.dumps({"type": "open", "version": 0, "text": GOOD}))
            assert receive(ws)["type"] == "update"
    finally:
        api.settings.free_practice = True


def test_key_without_practice_scope_is_refused(api: Api) -> None:
    key = api.api_key(["exercises:read"])
    with pytest.raises(WebSocketDisconnect) as err, api.client.websocket_connect(URL, headers=key) as ws:
        ws.receive_text()
    assert err.value.code == 4403


def test_exercise_document_uses_its_tools(api: Api) -> None:
    owner = api.user("instructor")
    ex = api.exercise(owner, tools=[{"number": 3, "diameter": 10}])
    with api.client.websocket_connect(URL) as ws:
        ws.send_text(
            json.dumps(
                {"type": "open", "version": 0, "text": "N10 T1 TC1 M6\nN20 M30\n", "exercise": ex["slug"]}
            )
        )
        update = receive(ws)
    assert any(d["severity"] == "error" for d in lines_of(update["diagnostics"]).get(1, []))
