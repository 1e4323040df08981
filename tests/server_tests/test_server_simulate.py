"""POST /simulate: the shape of `paltrainer simulate --json`, the stock, limits."""

from __future__ import annotations

import pytest
from server_helpers import GOOD, Api, auth, error_code

sim = pytest.importorskip("core.sim")

from core.pipeline import run


def test_simulate_answers_in_the_cli_shape(api: Api) -> None:
    r = api.client.post(
        "/api/v1/simulate",
        json={"program": GOOD, "resolution": 0.5, "stock": {"min": [0, 0, -30], "max": [80, 70, 0]}},
    )
    assert r.status_code == 200, r.text
    expected = sim.simulation_json(
        sim.simulate(run(GOOD), sim.Stock(0, 0, -30, 80, 70, 0), sim.DEFAULT_SIM_TOOLS, 0.5)
    )
    assert r.json() == expected
    assert r.json()["removed_volume_mm3"] > 0


def test_simulate_uses_the_exercise_stock_or_the_default(api: Api) -> None:
    owner = api.user("instructor")
    ex = api.exercise(owner, stock={"min": [0, 0, -10], "max": [40, 40, 0]})
    body = api.client.post(
        "/api/v1/simulate", json={"program": GOOD, "exercise": ex["slug"], "resolution": 0.5}
    ).json()
    assert body["stock"] == {"min": [0, 0, -10], "max": [40, 40, 0]}
    body = api.client.post("/api/v1/simulate", json={"program": GOOD, "resolution": 0.5}).json()
    assert body["stock"] == {"min": [0, 0, -30], "max": [80, 70, 0]}


def test_simulate_errors(api: Api) -> None:
    r = api.client.post(
        "/api/v1/simulate", json={"program": GOOD, "stock": {"min": [0, 0, 0], "max": [0, 70, 10]}}
    )
    assert r.status_code == 422 and error_code(r) == "BAD_STOCK"
    r = api.client.post("/api/v1/simulate", json={"program": GOOD, "resolution": 0})
    assert r.status_code == 422 and error_code(r) == "VALIDATION"
    r = api.client.post("/api/v1/simulate", json={"program": GOOD, "dialect": "iso"})
    assert r.status_code == 422 and error_code(r) == "UNKNOWN_DIALECT"
    student = api.user()
    old = api.settings.rate_simulate_per_minute
    api.settings.rate_simulate_per_minute = 1
    try:
        body = {"program": GOOD, "resolution": 1}
        assert api.client.post("/api/v1/simulate", json=body, headers=auth(student)).status_code == 200
        r = api.client.post("/api/v1/simulate", json=body, headers=auth(student))
        assert r.status_code == 429 and error_code(r) == "RATE_LIMITED"
    finally:
        api.settings.rate_simulate_per_minute = old
    api.settings.free_practice = False
    try:
        r = api.client.post("/api/v1/simulate", json={"program": GOOD})
        assert r.status_code == 401 and error_code(r) == "FREE_PRACTICE_OFF"
    finally:
        api.settings.free_practice = True
