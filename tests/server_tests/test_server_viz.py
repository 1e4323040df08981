"""The 3D view's server side: session tokens, the viser client page, a scene from a program, the playhead,
and the bridge's filter that keeps the share-tunnel request (and anything else not needed) away from viser."""

from __future__ import annotations

import msgspec
import numpy as np
import pytest
from server_helpers import GOOD, Api, auth, unique
from test_server_lms import ROOT, exercise_file

from server import viz


def test_viz_session_page_scene_and_playhead(api: Api) -> None:
    r = api.client.post("/api/v1/viz")
    assert r.status_code == 201
    token, url = r.json()["token"], r.json()["url"]
    assert url == f"/viz/{token}/"
    page = api.client.get(url)
    assert page.status_code == 200 and page.headers["content-type"].startswith("text/html")
    assert b"<html" in page.content[:2000].lower()
    assert api.client.get("/viz/not-a-token/").status_code == 401

    r = api.client.post(f"/api/v1/viz/{token}/scene", json={"program": GOOD, "dialect": "pal-mill"})
    assert r.status_code == 200, r.text
    scene = r.json()
    assert scene["segments"] == len(scene["lines"]) >= 4 and scene["errors"] == 0 and not scene["cut"]
    assert set(scene["lines"]) <= {3, 4, 5, 6}
    r = api.client.post(f"/api/v1/viz/{token}/playhead", json={"index": 1})
    assert r.status_code == 200 and r.json()["line"] == scene["lines"][1]
    r = api.client.post("/api/v1/viz/bad/scene", json={"program": GOOD})
    assert r.status_code == 401


def test_exercise_scene_shows_the_stock(api: Api) -> None:
    owner, student = api.user("instructor"), api.user()
    slug = unique("viz-")
    assert api.client.post("/api/v1/exercises/import", content=exercise_file(slug).encode(),
                           headers=auth(owner)).status_code == 201
    token = api.client.post("/api/v1/viz", headers=auth(student)).json()["token"]
    program = (ROOT / "exercises" / "pal-mill" / "pal-05-g2-kreisbogen.nc").read_text(encoding="utf-8")
    r = api.client.post(f"/api/v1/viz/{token}/scene", json={"program": program, "exercise": slug},
                        headers=auth(student))
    assert r.status_code == 200 and r.json()["errors"] == 0
    states = r.json()["states"]
    assert states["8"]["compensation"] == "G41" and states["8"]["tool"] == 1 and states["8"]["feed"] == 150
    scenes: viz.Scenes = api.app.state.scenes
    ticket = scenes.ticket(token)
    assert ticket is not None
    scene = scenes.scene(ticket)
    assert scene.segments is not None and len(scene.segments) == r.json()["segments"]
    assert scene.has_stock  # the stock as cut by the program is in the scene
    # playing: the stock after the current block (the first moves are rapids above the part: uncut)
    from server.workers import job_stock_after

    assert scene.program is not None
    text, dialect, spec = scene.program
    uncut = job_stock_after(text, dialect, spec, 1)
    cut = job_stock_after(text, dialect, spec, len(scene.moves) and scene.moves[-1] + 1)

    def top(tiles: dict[str, tuple[str, np.ndarray, np.ndarray]]) -> float:  # lowest point of the upper surface
        z = np.concatenate([vertices[:, 2] for _, vertices, _ in tiles.values()])
        return float(z[z > -29].min())  # (the base is at Z-30)

    assert top(uncut) == 0 and top(cut) == -2  # at first the stock's top at Z0; at the end the steps 2 mm deep
    # the stock is 80 × 70 mm in tiles of 20 mm: the contour cuts along the right and the front edge only,
    # so the untouched tiles keep their digest and are not sent again
    changed = {key for key in uncut if uncut[key][0] != cut[key][0]}
    assert len(uncut) == 16 and 0 < len(changed) < len(uncut)
    assert "3_1" not in changed  # the back left corner (Y 60–70, X 20–40) is never cut
    r = api.client.post(f"/api/v1/viz/{token}/playhead", json={"index": 0}, headers=auth(student))
    assert r.status_code == 200
    assert scene.tiles == {key: digest for key, (digest, _, _) in uncut.items()}  # the stock after the first move


def test_deviation_colours_where_the_part_leaves_the_band(api: Api) -> None:
    owner, student = api.user("instructor"), api.user()
    slug = unique("dev-")
    assert api.client.post("/api/v1/exercises/import", content=exercise_file(slug).encode(),
                           headers=auth(owner)).status_code == 201
    token = api.client.post("/api/v1/viz", headers=auth(student)).json()["token"]
    program = (ROOT / "exercises" / "pal-mill" / "pal-05-g2-kreisbogen.nc").read_text(encoding="utf-8")
    r = api.client.post(f"/api/v1/viz/{token}/deviation", json={"program": program, "exercise": slug},
                        headers=auth(student))
    assert r.status_code == 200 and r.json() == {"too_much": 0, "too_little": 0, "too_much_mm3": 0,
                                                 "too_little_mm3": 0, "largest_mm": 0}
    too_deep = program.replace("N50 G0 Z-2", "N50 G0 Z-3")
    r = api.client.post(f"/api/v1/viz/{token}/deviation", json={"program": too_deep, "exercise": slug},
                        headers=auth(student))
    assert r.status_code == 200 and r.json()["too_much"] > 100 and r.json()["too_little"] == 0
    # in mm³ and mm, not in grid cells: the step is 1 mm too deep (0.95 beyond the 0.05 mm band) over its area
    gouge = r.json()
    assert gouge["largest_mm"] == pytest.approx(0.95, abs=0.01)
    from core.exercises import parse_exercise
    from core.grading import grade

    graded = grade(parse_exercise(exercise_file(slug)), too_deep).to_json("instructor")
    geometry = next(c for c in graded["criteria"] if c["id"] == "geometry")
    assert f"{gouge['too_much_mm3']:.1f} mm³" in geometry["message"]  # the volume the score names
    scenes: viz.Scenes = api.app.state.scenes
    ticket = scenes.ticket(token)
    assert ticket is not None
    scene = scenes.scene(ticket)
    assert scene.server.scene._handle_from_node_name.get("/deviation/too_much") is not None
    not_deep_enough = program.replace("N50 G0 Z-2", "N50 G0 Z-1")
    r = api.client.post(f"/api/v1/viz/{token}/deviation", json={"program": not_deep_enough, "exercise": slug},
                        headers=auth(student))
    assert r.json()["too_much"] == 0 and r.json()["too_little"] > 100
    r = api.client.post(f"/api/v1/viz/{token}/deviation", json={"program": program}, headers=auth(student))
    assert r.status_code == 422 and r.json()["error"]["code"] == "EXERCISE_REQUIRED"


@pytest.mark.parametrize("message,passes", [
    ({"type": "ViewerCameraMessage", "wxyz": [1, 0, 0, 0]}, True),
    ({"type": "GuiUpdateMessage", "uuid": "x", "updates": {}}, True),
    ({"type": "ShareUrlRequest"}, False),
    ({"type": "ShareUrlDisconnect"}, False),
    ({"type": "FileTransferStartUpload"}, False),
    ({"no": "type"}, False),
])
def test_bridge_lets_only_the_view_messages_through(message: dict[str, object], passes: bool) -> None:
    assert viz.passes(msgspec.msgpack.encode(message)) is passes


def test_bridge_drops_garbage() -> None:
    assert viz.passes(b"\xc1\xc1 not msgpack") is False
