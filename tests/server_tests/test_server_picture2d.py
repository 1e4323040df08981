"""POST /api/v1/viz/picture.svg: the 2D view the page shows while the 3D view is off (core/picture2d.py) — the
plan view of a milling program, the drawing view of a turning program; its cost bounded (the height map's cells,
the path's points) and said in headers; the same rate limit and exam rules as the picture it replaces. And
viser's client page: unpacked, patched (no string evaluation) and packed again losslessly."""

from __future__ import annotations

import re
from xml.etree import ElementTree as ET

import pytest
from exam_helpers import assign, course_with
from server_helpers import GOOD, Api, auth, builtin_exercise, error_code

from server import viz
from server.jobs import HAS_SIM, picture_resolution

pytestmark = pytest.mark.skipif(not HAS_SIM, reason="the simulation (numpy) is not installed")
SVG = "{http://www.w3.org/2000/svg}"
TURNING = (
    "%\nO0001\nN10 G95 G97 S1200 M4\nN20 T0101\nN30 G0 X40 Z2\nN40 G1 Z0 F0.2\nN50 G1 Z-20\n"
    "N60 U5\nN70 G2 X60 Z-30 R10\nN80 G0 X100 Z100\nN90 M30\n"
)


def _texts(svg: bytes) -> list[str]:
    root = ET.fromstring(svg)
    return ["".join(t.itertext()) for t in root.iter(f"{SVG}text")]


def test_the_plan_view_of_a_milling_program(api: Api) -> None:
    r = api.client.post("/api/v1/viz/picture.svg", json={"program": GOOD})
    assert r.status_code == 200, r.text
    assert r.headers["content-type"].startswith("image/svg+xml") and r.headers["cache-control"] == "no-store"
    assert r.headers["x-picture-view"] == "mill" and r.headers["x-picture-path-cut"] == "false"
    assert r.headers["x-picture-raster"] == "320x280" and r.headers["x-picture-cell"] == "0.25"
    texts = _texts(r.content)
    assert "Tiefe Z in mm" in texts and "Eilgang" in texts and "Werkstücknullpunkt" in texts
    assert b"<script" not in r.content and b"<style" not in r.content
    english = api.client.post("/api/v1/viz/picture.svg?lang=en", json={"program": GOOD})
    assert "Depth Z in mm" in _texts(english.content)
    # a program with an error: its block is marked with its line
    bad = api.client.post("/api/v1/viz/picture.svg", json={"program": GOOD.replace("M3", "M3 Q7", 1)})
    assert bad.status_code == 200 and any(t.startswith("Satz mit Fehler") for t in _texts(bad.content))


def test_a_big_stock_gets_coarser_cells(api: Api) -> None:
    """At most 400 cells along the stock's longer side: a 1000 mm block is simulated at 2.5 mm."""
    r = api.client.post(
        "/api/v1/viz/picture.svg",
        json={"program": GOOD, "stock": {"min": [0, 0, -30], "max": [1000, 200, 0]}},
    )
    assert r.status_code == 200
    assert r.headers["x-picture-raster"] == "400x80" and r.headers["x-picture-cell"] == "2.5"
    assert picture_resolution({"stock": {"min": [0, 0, 0], "max": [80, 70, 1]}, "resolution": 0.1}) == 0.25


def test_the_drawing_view_of_a_turning_program(api: Api) -> None:
    r = api.client.post("/api/v1/viz/picture.svg", json={"program": TURNING, "dialect": "traub-tx8d"})
    assert r.status_code == 200 and r.headers["x-picture-view"] == "lathe"
    texts = _texts(r.content)
    assert "X (Ø)" in texts and "Schnitt" in texts and "60" in texts  # Ø60 behind Z-30
    # the request's blank is the one drawn (the 3D view turns the same)
    r = api.client.post(
        "/api/v1/viz/picture.svg",
        json={"program": TURNING, "dialect": "traub-tx8d", "blank": {"diameter": 80, "length": 100}},
    )
    assert r.status_code == 200 and "-100" in _texts(r.content)


def test_rate_limit_and_exam_rules_as_the_picture(api: Api) -> None:
    """The same bucket as picture.png; refused while an exam without 3D runs for the trainee."""
    teacher, student = api.user("instructor"), api.user()
    course = course_with(api, teacher, student)
    slug = builtin_exercise(api)
    assign(api, teacher, course, [slug])
    body = {"program": GOOD, "exercise": slug}
    r = api.client.post("/api/v1/viz/picture.svg", json=body, headers=auth(student))
    assert r.status_code == 403 and error_code(r) == "EXAM_RUNNING", r.text
    r = api.client.post("/api/v1/viz/picture.svg", json=body)  # nobody logged in: the exercise is locked
    assert r.status_code == 403 and error_code(r) == "EXAM_EXERCISE_LOCKED"


def test_viser_client_round_trip() -> None:
    """viser's page packs its application (zstd, base 88): unpacked, changed (CLIENT_PATCHES) and packed again
    the way viser's loader reads it; base 88 encodes every length and byte losslessly."""
    import random

    import zstandard

    rng = random.Random(7)
    for n in (0, 1, 2, 3, 4, 5, 7, 8, 9, 1000, 1001, 1002, 1003):
        data = bytes(rng.randrange(256) for _ in range(n))
        encoded = viz.base88_encode(data)
        assert len(encoded) == n // 4 * 5 + (n % 4 + 1 if n % 4 else 0)
        assert set(encoded) <= set(viz.BASE88) and b'"' not in encoded and b"&" not in encoded
        assert viz.base88_decode(encoded) == data
    assert viz.base88_decode(viz.base88_encode(b"\xff" * 12)) == b"\xff" * 12
    from importlib import resources

    original = (resources.files("viser") / "client" / "build" / "index.html").read_bytes()
    style, code = viz.viser_client(original)  # type: ignore[misc]
    assert b"RunJavascriptMessage" in code and len(style) > 1000
    patched = viz.viser_page()
    new_style, new_code = viz.viser_client(patched)  # type: ignore[misc]
    assert new_style == style
    assert b"Function(" not in new_code.split(b"RunJavascriptMessage", 1)[1][:80]  # runs no script it is sent
    # an idle view redraws every 10 s, not every second
    assert re.search(
        rb"requestRender\(\);let [\w$]+=setInterval\(\(\)=>[\w$]+\(\),%d\)" % viz.VIEW_REDRAW_MS, new_code
    )
    for pattern, _ in viz.CLIENT_PATCHES:
        assert pattern.search(code) and not pattern.search(new_code)
    # the same page around it: only the packed attributes differ
    assert (
        patched.replace(b'<link rel="stylesheet" href="/static/viz-frame.css">', b"").split(b"data-p=")[0]
        == original.split(b"data-p=")[0]
    )
    assert (
        zstandard.ZstdDecompressor().decompress(
            viz.base88_decode(viz._PACKED.search(patched).group(1)),
            max_output_size=len(new_style) + len(new_code),
        )
        == new_style + new_code
    )
