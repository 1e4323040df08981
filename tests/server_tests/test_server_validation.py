"""Bad input at the edge is a 4xx with our error shape, never a 500: text that cannot be stored (a lone
surrogate, NUL), ids beyond the database's integer range, malformed rubrics, YAML nested without end."""

from __future__ import annotations

import json
from typing import Any

import pytest
from server_helpers import GOOD, Api, auth, error_code, unique

SURROGATE = "\ud800"
NUL = "\x00"


def send(api: Api, method: str, path: str, body: Any, headers: dict[str, str] | None = None) -> Any:
    """A JSON request with the body encoded as Python's json module does: a lone surrogate becomes "\\ud800"."""
    return api.client.request(
        method,
        path,
        content=json.dumps(body),
        headers={"Content-Type": "application/json", **(headers or {})},
    )


def requests_with(api: Api, bad: str) -> list[tuple[str, str, dict[str, Any], dict[str, str]]]:
    """One request per string field of every endpoint, with `bad` in that field."""
    admin, owner = api.user("admin"), api.user("instructor")
    ex = api.exercise(owner)
    key = api.api_key(["submissions:write", "submissions:read"])
    program = {"program": GOOD}
    exercise = {"slug": unique("val-"), "title_de": "Nuten", "reference_program": GOOD}
    found: list[tuple[str, str, dict[str, Any], dict[str, str]]] = []
    for path in ("/api/v1/check", "/api/v1/run", "/api/v1/simulate"):
        found += [
            ("POST", path, {"program": f"N10 G0 X0{bad}\n"}, {}),
            ("POST", path, {**program, "dialect": f"pal-mill{bad}"}, {}),
            ("POST", path, {**program, "exercise": f"{ex['slug']}{bad}"}, {}),
            ("POST", path, {**program, "tools": [{"number": 3, "diameter": 8, "name": bad}]}, {}),
            ("POST", path, {**program, bad: 1}, {}),
        ]
    found += [
        ("POST", "/api/v1/auth/login", {"username": f"a{bad}", "password": "xxxxxxxxxx"}, {}),
        ("POST", "/api/v1/auth/login", {"username": "someone", "password": f"pass{bad}word"}, {}),
        ("POST", "/api/v1/users", {"username": f"u{bad}", "password": "long enough password"}, auth(admin)),
        ("POST", "/api/v1/users", {"username": unique("u"), "password": f"long enough{bad}"}, auth(admin)),
        ("POST", "/api/v1/api-keys", {"name": f"key{bad}", "scopes": ["practice"]}, auth(owner)),
    ]
    for field in ("title_de", "title_en", "task_de", "task_en", "dialect", "reference_program"):
        found.append(("POST", "/api/v1/exercises", {**exercise, field: f"text{bad}"}, auth(owner)))
        found.append(("PATCH", f"/api/v1/exercises/{ex['slug']}", {field: f"text{bad}"}, auth(owner)))
    found += [
        ("POST", "/api/v1/exercises", {**exercise, "slug": f"ex{bad}"}, auth(owner)),
        ("POST", "/api/v1/exercises", {**exercise, "rubric": {"note": bad}}, auth(owner)),
        ("POST", "/api/v1/exercises", {**exercise, "rubric": {bad: 1}}, auth(owner)),
        ("POST", "/api/v1/exercises", {**exercise, "hidden_criteria": {"x": [bad]}}, auth(owner)),
        (
            "POST",
            "/api/v1/exercises",
            {**exercise, "stock": {"min": [0, 0, -30], "max": [80, 70, 0], bad: 1}},
            auth(owner),
        ),
        ("PATCH", f"/api/v1/exercises/{ex['slug']}", {"rubric": {"note": bad}}, auth(owner)),
        (
            "POST",
            "/api/v1/submissions",
            {"exercise": ex["slug"], "program": f"N10 G0 X0{bad}\n"},
            auth(owner),
        ),
        ("POST", "/api/v1/submissions", {"exercise": f"{ex['slug']}{bad}", "program": GOOD}, auth(owner)),
        (
            "POST",
            "/api/v1/submissions",
            {"exercise": ex["slug"], "program": GOOD, "external_user": f"learner{bad}"},
            key,
        ),
    ]
    return found


@pytest.mark.parametrize("bad", [SURROGATE, NUL], ids=["lone-surrogate", "nul"])
def test_text_that_cannot_be_stored_is_a_422_on_every_endpoint(api: Api, bad: str) -> None:
    for method, path, body, headers in requests_with(api, bad):
        r = send(api, method, path, body, headers)
        assert r.status_code == 422, (method, path, body, r.status_code, r.text[:300])
        assert error_code(r) == "VALIDATION"


def test_nothing_was_stored_from_the_rejected_requests(api: Api) -> None:
    admin = api.user("admin")
    names = [u["username"] for u in api.client.get("/api/v1/users", headers=auth(admin)).json()]
    assert not any(SURROGATE in n or NUL in n for n in names)


@pytest.mark.parametrize("bad", [SURROGATE, NUL], ids=["lone-surrogate", "nul"])
def test_looked_up_text_that_cannot_be_stored_is_a_4xx(api: Api, bad: str) -> None:
    owner = api.user("instructor")
    quoted = "%ED%A0%80" if bad == SURROGATE else "%00"
    assert api.client.get(f"/api/v1/exercises/x{quoted}", headers=auth(owner)).status_code in (404, 422)
    assert api.client.get(f"/api/v1/exercises/x{quoted}/picture.png", headers=auth(owner)).status_code in (
        404,
        422,
    )
    assert api.client.delete(f"/api/v1/exercises/x{quoted}", headers=auth(owner)).status_code in (404, 422)
    # quoted by hand: the client itself refuses to encode a lone surrogate
    r = api.client.get(f"/api/v1/submissions?exercise=x{quoted}", headers=auth(owner))
    assert r.status_code in (404, 422) and error_code(r)
    r = api.client.get(f"/api/v1/submissions/export.csv?exercise=x{quoted}", headers=auth(owner))
    assert r.status_code in (404, 422) and error_code(r)
    r = api.client.post(
        "/api/v1/auth/token",
        content=f"username=x{quoted}&password=whatever1".encode(),
        headers={"Content-Type": "application/x-www-form-urlencoded"},
    )
    assert r.status_code in (401, 422) and error_code(r)


@pytest.mark.parametrize("number", ["99999999999999999999", "2147483648", "9223372036854775808", "-1", "0"])
def test_ids_beyond_the_integer_range_are_404_or_422(api: Api, number: str) -> None:
    admin = api.user("admin")
    r = api.client.get(f"/api/v1/submissions/{number}", headers=auth(admin))
    assert r.status_code in (404, 422) and error_code(r) in ("SUBMISSION_NOT_FOUND", "VALIDATION")
    r = api.client.delete(f"/api/v1/api-keys/{number}", headers=auth(admin))
    assert r.status_code in (404, 422) and error_code(r) in (
        "API_KEY_NOT_FOUND",
        "VALIDATION",
        "OUT_OF_RANGE",
    )


@pytest.mark.parametrize(
    "field, value",
    [
        ("rubric", {"criteria": 5}),
        ("rubric", {"criteria": [1]}),
        ("rubric", {"criteria": [{"id": "geometry"}]}),
        ("rubric", {"criteria": "geometry"}),
        ("hidden_criteria", {"criteria": [1]}),
        ("hidden_criteria", {"criteria": {"id": "program_end", "points": 10}}),
        ("hidden_criteria", {"criteria": [{"id": "warp-drive", "points": 10}]}),
    ],
)
def test_malformed_criteria_are_a_422_on_create_and_patch(api: Api, field: str, value: Any) -> None:
    owner = api.user("instructor")
    ex = api.exercise(owner)
    body = {"slug": unique("crit-"), "title_de": "Nuten", "reference_program": GOOD, field: value}
    r = api.client.post("/api/v1/exercises", json=body, headers=auth(owner))
    assert r.status_code == 422 and error_code(r) == "VALIDATION", r.text
    assert "criteria" in r.json()["error"]["message"]
    r = api.client.patch(f"/api/v1/exercises/{ex['slug']}", json={field: value}, headers=auth(owner))
    assert r.status_code == 422 and error_code(r) == "VALIDATION", r.text
    assert api.client.get(f"/api/v1/exercises/{ex['slug']}", headers=auth(owner)).json()[field] == ex[field]


def test_free_form_rubric_notes_nested_without_end_are_a_422(api: Api) -> None:
    owner = api.user("instructor")
    nested: Any = "deep"
    for _ in range(200):
        nested = {"a": nested}
    body = {"slug": unique("deep-"), "title_de": "Nuten", "rubric": nested}
    r = api.client.post("/api/v1/exercises", json=body, headers=auth(owner))
    assert r.status_code == 422 and error_code(r) == "VALIDATION"


@pytest.mark.parametrize(
    "document",
    [
        "a: " + "[" * 10_000 + "]" * 10_000 + "\n",
        "a: " + "{b: " * 10_000 + "1" + "}" * 10_000 + "\n",
        "".join(f"{'  ' * i}a{i}:\n" for i in range(500)) + "  " * 500 + "x\n",
    ],
    ids=["flow-sequences", "flow-mappings", "block-mappings"],
)
def test_yaml_nested_ten_thousand_deep_is_a_422(api: Api, document: str) -> None:
    owner = api.user("instructor")
    r = api.client.post(
        "/api/v1/exercises/import",
        content=document.encode(),
        headers={**auth(owner), "Content-Type": "application/yaml"},
    )
    assert r.status_code == 422 and error_code(r) == "EXERCISE_INVALID", r.text[:300]
    assert "verschachtelt" in r.json()["error"]["message"] and "nested" in r.json()["error"]["message_en"]


def test_yaml_with_a_lone_surrogate_or_nul_escape_is_a_422(api: Api) -> None:
    owner = api.user("instructor")
    for escape in ("\\ud800", "\\0"):
        document = f'id: {unique("esc-")}\ntitle: {{de: "Nuten{escape}"}}\n'
        r = api.client.post(
            "/api/v1/exercises/import",
            content=document.encode(),
            headers={**auth(owner), "Content-Type": "application/yaml"},
        )
        assert r.status_code == 422 and error_code(r) == "EXERCISE_INVALID", r.text[:300]
