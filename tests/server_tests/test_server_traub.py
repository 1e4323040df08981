"""TRAUB turning over the API: the dialect is listed with its help, runs with nose data in `tools`, and the
skip switch defaults per dialect."""

from __future__ import annotations

from server_helpers import Api

PROGRAM = "G59 Z200\nG96 V200 T0303 M4\nG92 S3000\nG0 X40 Z2\n/G1 Z-50 F0.2\nG1 Z-20 F0.2\nM30\n"


def test_dialect_list_and_help_include_traub(api: Api) -> None:
    names = [d["name"] for d in api.client.get("/api/v1/dialects").json()]
    assert "traub-tx8d" in names
    body = api.client.get("/api/v1/dialects/traub-tx8d").json()
    u = next(a for a in body["addresses"] if a["name"] == "U")
    assert "RADIUSWERT" in u["help_de"] and "RADIUS" in u["help_en"]
    assert {"G96", "G92", "G22", "G201", "M99"} <= {c["name"] for c in body["codes"]}


def test_run_traub_with_nose_data_and_the_dialect_skip_default(api: Api) -> None:
    tools = [{"number": 3, "diameter": 0.8, "kind": "turning", "nose_radius": 0.4, "quadrant": 3}]
    r = api.client.post("/api/v1/run", json={"program": PROGRAM, "dialect": "traub-tx8d", "tools": tools})
    assert r.status_code == 200
    body = r.json()
    assert [d["code"] for d in body["diagnostics"] if d["severity"] == "error"] == []
    assert [m["end"] for m in body["moves"]] == [[20.0, 0.0, 2.0], [20.0, 0.0, -20.0]]  # x = radius
    assert body["moves"][0]["plane"] == "G18"
    r = api.client.post(
        "/api/v1/run", json={"program": PROGRAM, "dialect": "traub-tx8d", "skip_blocks": False}
    )
    assert [m["end"][2] for m in r.json()["moves"]] == [2.0, -50.0, -20.0]


def test_quadrant_out_of_range_is_422(api: Api) -> None:
    tools = [{"number": 3, "diameter": 0.8, "kind": "turning", "nose_radius": 0.4, "quadrant": 5}]
    r = api.client.post("/api/v1/run", json={"program": PROGRAM, "dialect": "traub-tx8d", "tools": tools})
    assert r.status_code == 422
