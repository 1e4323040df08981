"""POST /check and /run, health, the error shape, limits (413, 429), free practice, OpenAPI."""

from __future__ import annotations

from typing import Any

import pytest
from fastapi.testclient import TestClient
from server_helpers import BAD, GOOD, Api, auth, error_code

from core.pipeline import diagnostics_json, run, toolpath_json
from server import services


def test_health_and_ready(api: Api) -> None:
    assert api.client.get("/healthz").json() == {"status": "ok"}
    r = api.client.get("/readyz")
    assert r.status_code == 200 and r.json()["status"] == "ready"


def test_check_answers_in_the_cli_shape(api: Api) -> None:
    r = api.client.post("/api/v1/check", json={"program": BAD, "dialect": "pal-mill"})
    assert r.status_code == 200
    assert r.json() == diagnostics_json(run(BAD).diagnostics)
    assert ("PAL-E010", 2) in [(d["code"], d["line"]) for d in r.json()["diagnostics"]]


def test_run_answers_in_the_cli_shape(api: Api) -> None:
    r = api.client.post("/api/v1/run", json={"program": GOOD})
    assert r.status_code == 200
    assert r.json() == toolpath_json(run(GOOD))


def test_run_with_tools_and_skip_blocks(api: Api) -> None:
    program = "N10 T7 TC1 M6\n/N20 G0 X10 Y10 Z2\nN30 M30\n"
    r = api.client.post(
        "/api/v1/run", json={"program": program, "tools": [{"number": 7, "diameter": 8}], "skip_blocks": True}
    )
    body = r.json()
    assert r.status_code == 200
    assert [d["code"] for d in body["diagnostics"] if d["severity"] == "error"] == []
    assert body["moves"] == []


def test_unknown_dialect_is_422(api: Api) -> None:
    r = api.client.post("/api/v1/check", json={"program": GOOD, "dialect": "heidenhain"})
    assert r.status_code == 422 and error_code(r) == "UNKNOWN_DIALECT"


def test_validation_errors_have_the_error_shape(api: Api) -> None:
    for body in ({"program": 5}, {}, {"program": "x", "unknown": 1}):
        r = api.client.post("/api/v1/check", json=body)
        assert r.status_code == 422 and error_code(r) == "VALIDATION"
        assert r.json()["error"]["details"]["errors"]
    r = api.client.post("/api/v1/check", content=b"{not json", headers={"content-type": "application/json"})
    assert r.status_code == 422 and error_code(r) == "VALIDATION"


def test_unknown_path_and_method(api: Api) -> None:
    r = api.client.get("/api/v1/nothing")
    assert r.status_code == 404 and error_code(r) == "NOT_FOUND"
    r = api.client.get("/api/v1/check")
    assert r.status_code == 405 and error_code(r) == "METHOD_NOT_ALLOWED"


def test_unknown_exercise_is_404(api: Api) -> None:
    r = api.client.post("/api/v1/check", json={"program": GOOD, "exercise": "no-such"})
    assert r.status_code == 404 and error_code(r) == "EXERCISE_NOT_FOUND"


def test_program_too_long_is_413(api: Api) -> None:
    limit = api.settings.max_program_chars
    r = api.client.post("/api/v1/check", json={"program": "N10 G0 X0\n" * (limit // 10 + 1)})
    assert r.status_code == 413 and error_code(r) == "PROGRAM_TOO_LARGE"
    assert r.json()["error"]["details"]["limit"] == limit


def test_body_too_large_is_413(api: Api) -> None:
    big = b'{"program": "' + b"N" * (api.settings.max_body_bytes + 10) + b'"}'
    r = api.client.post("/api/v1/check", content=big, headers={"content-type": "application/json"})
    assert r.status_code == 413 and error_code(r) == "BODY_TOO_LARGE"

    def chunks() -> Any:
        for _ in range(api.settings.max_body_bytes // 10_000 + 2):
            yield b"x" * 10_000

    r = api.client.post("/api/v1/check", content=chunks(), headers={"content-type": "application/json"})
    assert r.status_code == 413 and error_code(r) == "BODY_TOO_LARGE"


def test_check_rate_limit_is_429_per_caller(api: Api) -> None:
    student = api.user()
    old = api.settings.rate_check_per_minute
    api.settings.rate_check_per_minute = 3
    try:
        codes = [
            api.client.post("/api/v1/check", json={"program": GOOD}, headers=auth(student)).status_code
            for _ in range(4)
        ]
        assert codes == [200, 200, 200, 429]
        r = api.client.post("/api/v1/run", json={"program": GOOD}, headers=auth(student))
        assert r.status_code == 429 and error_code(r) == "RATE_LIMITED"
        assert int(r.headers["retry-after"]) > 0
        other = api.user()
        assert (
            api.client.post("/api/v1/check", json={"program": GOOD}, headers=auth(other)).status_code == 200
        )
    finally:
        api.settings.rate_check_per_minute = old


def test_free_practice_off_needs_an_account(api: Api) -> None:
    api.settings.free_practice = False
    try:
        r = api.client.post("/api/v1/check", json={"program": GOOD})
        assert r.status_code == 401 and error_code(r) == "FREE_PRACTICE_OFF"
        student = api.user()
        assert (
            api.client.post("/api/v1/check", json={"program": GOOD}, headers=auth(student)).status_code == 200
        )
    finally:
        api.settings.free_practice = True


def test_api_key_without_practice_scope_is_403(api: Api) -> None:
    key = api.api_key(["exercises:read"])
    r = api.client.post("/api/v1/check", json={"program": GOOD}, headers=key)
    assert r.status_code == 403 and error_code(r) == "MISSING_SCOPE"
    key = api.api_key(["practice"])
    assert api.client.post("/api/v1/check", json={"program": GOOD}, headers=key).status_code == 200


def test_request_id_is_echoed(api: Api) -> None:
    r = api.client.get("/healthz", headers={"X-Request-ID": "abc123"})
    assert r.headers["x-request-id"] == "abc123"
    assert len(api.client.get("/healthz").headers["x-request-id"]) == 32


def test_openapi_describes_bodies_and_errors(api: Api) -> None:
    doc = api.client.get("/openapi.json").json()
    assert "ErrorBody" in doc["components"]["schemas"]
    check = doc["paths"]["/api/v1/check"]["post"]
    assert check["requestBody"]["content"]["application/json"]["schema"]["$ref"].endswith("/ProgramRequest")
    assert check["responses"]["200"]["content"]["application/json"]["schema"]["$ref"].endswith(
        "/CheckResponse"
    )
    for status in ("413", "422", "429"):
        assert check["responses"][status]["content"]["application/json"]["schema"]["$ref"].endswith(
            "/ErrorBody"
        )
    for path, methods in doc["paths"].items():
        for method, op in methods.items():
            for status, resp in op["responses"].items():
                if status.startswith(("4", "5")):
                    ref = resp["content"]["application/json"]["schema"]["$ref"]
                    assert ref.endswith("/ErrorBody"), (path, method, status)
    assert "HTTPValidationError" not in doc["components"]["schemas"]


def test_time_limit_is_503_and_the_worker_is_replaced(api: Api) -> None:
    workers = api.app.state.workers
    old = workers.seconds
    workers.seconds = 0.0001
    try:
        r = api.client.post("/api/v1/check", json={"program": GOOD * 200})
        assert r.status_code == 503 and error_code(r) == "TIME_LIMIT"
    finally:
        workers.seconds = old
    for _ in range(workers.processes):
        assert api.client.post("/api/v1/check", json={"program": GOOD}).status_code == 200
    assert api.client.get("/readyz").status_code == 200


def test_internal_error_is_json_without_a_stack_trace(api: Api, monkeypatch: pytest.MonkeyPatch) -> None:
    def broken(*args: Any) -> None:
        raise RuntimeError("secret internals")

    monkeypatch.setattr(services, "run_spec", broken)
    client = TestClient(api.app, raise_server_exceptions=False, base_url="http://127.0.0.1")
    r = client.post("/api/v1/check", json={"program": GOOD}, headers={"X-Request-ID": "req-77"})
    assert r.status_code == 500 and error_code(r) == "INTERNAL"
    assert "req-77" in r.json()["error"]["message"]
    assert "secret internals" not in r.text and "Traceback" not in r.text
