"""The 3D view of a turning program (TRAUB TX 8 D): the toolpath in the lathe's drawing view — Z (the spindle
axis) to the right, X (the radius) up, the chuck on the left — no milling block (the turned part:
test_server_viz_lathe_stock.py), the camera on the part from the front, the modal state's X a diameter on
the page."""

from __future__ import annotations

import numpy as np
from server_helpers import Api

from server import viz

TURNING = (
    "%\nO0001\nN10 G95 G97 S1200 M4\nN20 T0101\nN30 G0 X40 Z2\nN40 G1 Z0 F0.2\nN50 G1 Z-20\n"
    "N60 U5\nN70 G2 X60 Z-30 R10\nN80 G0 X100 Z100\nN90 M30\n"
)


def _scene(api: Api, program: str, dialect: str) -> tuple[dict, viz.Scene]:
    token = api.client.post("/api/v1/viz").json()["token"]
    r = api.client.post(f"/api/v1/viz/{token}/scene", json={"program": program, "dialect": dialect})
    assert r.status_code == 200, r.text
    ticket = api.app.state.scenes.ticket(token)
    assert ticket is not None
    return r.json(), api.app.state.scenes.scene(ticket)


def _segment_of(scene: viz.Scene, line: int) -> np.ndarray:
    assert scene.playback is not None
    p = scene.playback
    return np.asarray([s for s, n in zip(p.segments, p.lines, strict=True) if n == line])


def test_turning_toolpath_in_the_lathe_orientation(api: Api) -> None:
    body, scene = _scene(api, TURNING, "traub-tx8d")
    assert body["errors"] == 0 and body["lathe"] is True
    # N50 G1 Z-20 from X40 Z0: a horizontal segment at height 20 (the radius), from 0 to -20 to the left
    ((a, b),) = _segment_of(scene, 7)
    assert np.allclose(a, [0, 0, 20]) and np.allclose(b, [-20, 0, 20])
    # N60 U5: up by 5 (U is a radius value), at Z-20
    ((a, b),) = _segment_of(scene, 8)
    assert np.allclose(a, [-20, 0, 20]) and np.allclose(b, [-20, 0, 25])
    # N70 G2 X60 Z-30 R10: every chord point at 10 mm from the arc's centre, mapped the same way
    arc = _segment_of(scene, 9)
    points = arc.reshape(-1, 3)
    assert (
        np.allclose(points[:, 1], 0)
        and np.allclose(points[0], [-20, 0, 25])
        and np.allclose(points[-1], [-30, 0, 30])
    )
    moves = api.client.post("/api/v1/run", json={"program": TURNING, "dialect": "traub-tx8d"}).json()["moves"]
    cx, _, cz = next(m for m in moves if m["line"] == 9)["center"]
    assert np.allclose(np.linalg.norm(points - [cz, 0, cx], axis=1), 10, atol=0.06)
    # as seen from the front (the camera at -Y, right = +Z of the lathe, up = X): clockwise
    turn = np.cross(arc[0, 1] - arc[0, 0], arc[1, 1] - arc[1, 0])  # two chords one after the other
    assert turn[1] > 0  # the y of the cross product: negative turn in the picture's (right, up) plane = cw
    # no milling block but the turned part (a bar Ø60 × 55 around the program, test_server_viz_lathe_stock.py);
    # the camera looks from the front at the part, the cutting moves and the chuck's jaws
    assert scene.has_stock and scene.tiles and all(k.startswith("z") for k in scene.tiles)
    assert scene.view == "front" and scene.bounds is not None
    lo, hi = scene.bounds
    assert np.allclose(lo[1:], [-30, -30]) and np.allclose(hi, [2, 30, 30]) and lo[0] < -55
    camera = scene.server.initial_camera
    eye, target = np.asarray(camera.position), np.asarray(camera.look_at)
    assert eye[1] < target[1] and abs(eye[0] - target[0]) < 1e-6  # straight from the front
    # the modal state: the position is the radius (the page shows X = 2 × radius), the plane G18
    assert body["states"]["7"]["position"] == [20.0, 0.0, -20.0] and body["states"]["7"]["plane"] == "G18"


def test_milling_scene_is_unchanged(api: Api) -> None:
    program = "N10 T1 TC1 M6\nN20 S1200 F150 M3\nN30 G0 X0 Y0 Z2\nN40 G1 Z-2\nN50 G1 X20\nN60 G0 Z50 M30\n"
    body, scene = _scene(api, program, "pal-mill")
    assert body["lathe"] is False and scene.has_stock
    ((a, b),) = _segment_of(scene, 5)
    assert np.allclose(a, [0, 0, -2]) and np.allclose(b, [20, 0, -2])


def test_lathe_playhead_moves(api: Api) -> None:
    token = api.client.post("/api/v1/viz").json()["token"]
    body = api.client.post(
        f"/api/v1/viz/{token}/scene", json={"program": TURNING, "dialect": "traub-tx8d"}
    ).json()
    index = body["lines"].index(7)
    r = api.client.post(f"/api/v1/viz/{token}/playhead", json={"index": index})
    assert r.status_code == 200 and r.json()["line"] == 7
    r = api.client.post(f"/api/v1/viz/{token}/view", json={"view": "reset"})
    assert r.status_code == 200 and r.json()["view"] == "front"  # a lathe's own view is the drawing view


def _pixels(png: bytes) -> np.ndarray:
    """An RGB PNG as the server writes it (filter 0 on every row) as an array of rows."""
    import struct
    import zlib

    assert png[:8] == b"\x89PNG\r\n\x1a\n"
    width, height, depth, colour = struct.unpack(">IIBB", png[16:26])
    assert depth == 8 and colour == 2
    data, at = b"", 8
    while at < len(png):
        size = struct.unpack(">I", png[at : at + 4])[0]
        if png[at + 4 : at + 8] == b"IDAT":
            data += png[at + 8 : at + 8 + size]
        at += 12 + size
    rows = np.frombuffer(zlib.decompress(data), dtype=np.uint8).reshape(height, 1 + 3 * width)
    return rows[:, 1:].reshape(height, width, 3)


def test_picture_of_a_turning_program_is_its_turned_part_in_half_section(api: Api) -> None:
    """While the 3D view is off: not a milling block from above but the turned part, Z right, X up, the upper
    half cut open and hatched (core/drawing/turned_picture.py); test_drawing_lathe.py looks at it closer."""
    from core.drawing import turned_picture as tp

    r = api.client.post("/api/v1/viz/picture.png", json={"program": TURNING, "dialect": "traub-tx8d"})
    assert r.status_code == 200 and r.headers["x-picture-view"] == "lathe"
    image = _pixels(r.content)
    section = np.all(image == tp.SECTION, axis=2) | np.all(image == tp.HATCH, axis=2)
    rows, cols = np.nonzero(section)
    assert len(rows) > 1000 and np.all(image == tp.HATCH, axis=2).sum() > 100
    axis = int(np.argmax(np.all(image == tp.AXIS, axis=2).sum(axis=1)))
    assert rows.max() <= axis  # the section is the upper half, the view the lower
    # the part is Ø40 at the face and Ø60 behind Z-30: the section is higher at the left than at the right
    left = np.flatnonzero(section[:, cols.min() + 2]).min()
    right = np.flatnonzero(section[:, cols.max() - 2]).min()
    assert axis - left > 1.3 * (axis - right)
    milling = api.client.post(
        "/api/v1/viz/picture.png", json={"program": TURNING.replace("%\n", ""), "dialect": "pal-mill"}
    )
    assert "x-picture-view" not in milling.headers
