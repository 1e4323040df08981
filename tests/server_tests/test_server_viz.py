"""The 3D view's server side: session tokens, the viser client page, a scene from a program, the playhead,
and the bridge's filter that keeps the share-tunnel request (and anything else not needed) away from viser."""

from __future__ import annotations

import msgspec
import numpy as np
import pytest
from server_helpers import GOOD, Api, auth, unique
from test_server_lms import ROOT, exercise_file

from server import viz
from server.jobs import job_scene


def test_viz_session_page_scene_and_playhead(api: Api) -> None:
    r = api.client.post("/api/v1/viz")
    assert r.status_code == 201
    token, url = r.json()["token"], r.json()["url"]
    assert url == f"/viz/{token}/"
    page = api.client.get(url)
    assert page.status_code == 200 and page.headers["content-type"].startswith("text/html")
    assert b"<html" in page.content[:2000].lower()
    assert b'href="/static/viz-frame.css"' in page.content  # hides viser's panel, status, address and notices
    assert api.client.get("/static/viz-frame.css").status_code == 200
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


POCKET = (
    "T2 M6\nS2000 F300 M3\nG0 X0 Y0 Z10\nN40 G72 ZI-5 LP40 BP30 D2 V2 RN8\nN50 G79 X50 Y40 Z0\nG0 Z50\nM30\n"
)


def test_playback_names_the_cycle_step_of_a_move() -> None:
    # the scene job (as the route's worker runs it) keeps the cycle of each move a PAL cycle made
    cycles = job_scene(POCKET, "pal-mill", {}).playback.cycles
    assert cycles and {c["code"] for c in cycles.values()} == {"G72"}
    assert {c["defined_in_line"] for c in cycles.values() if "defined_in_line" in c} == {4}
    assert {c["of"] for c in cycles.values()} == {3}  # ZI-5 in levels of at most 2 mm: 3 levels
    assert 0 not in cycles  # the rapid before the cycle belongs to none


def test_playhead_answers_the_cycle(api: Api) -> None:
    token = api.client.post("/api/v1/viz").json()["token"]
    scene = api.client.post(
        f"/api/v1/viz/{token}/scene", json={"program": POCKET, "dialect": "pal-mill"}
    ).json()
    at = [i for i, line in enumerate(scene["lines"]) if line == 5]
    first = api.client.post(f"/api/v1/viz/{token}/playhead", json={"index": at[0]}).json()
    last = api.client.post(f"/api/v1/viz/{token}/playhead", json={"index": at[-1]}).json()
    assert first["line"] == 5 and first["cycle"] == {
        "code": "G72",
        "pass": 1,
        "of": 3,
        "defined_in_line": 4,
        "point": 1,
        "points": 1,
    }
    assert last["cycle"]["pass"] == 3
    assert api.client.post(f"/api/v1/viz/{token}/playhead", json={"index": 0}).json()["cycle"] is None


def test_exercise_scene_shows_the_stock(api: Api) -> None:
    owner, student = api.user("instructor"), api.user()
    slug = unique("viz-")
    assert (
        api.client.post(
            "/api/v1/exercises/import", content=exercise_file(slug).encode(), headers=auth(owner)
        ).status_code
        == 201
    )
    token = api.client.post("/api/v1/viz", headers=auth(student)).json()["token"]
    program = (ROOT / "exercises" / "pal-mill" / "pal-05-g2-kreisbogen.nc").read_text(encoding="utf-8")
    r = api.client.post(
        f"/api/v1/viz/{token}/scene", json={"program": program, "exercise": slug}, headers=auth(student)
    )
    assert r.status_code == 200 and r.json()["errors"] == 0
    states = r.json()["states"]
    assert states["8"]["compensation"] == "G41" and states["8"]["tool"] == 1 and states["8"]["feed"] == 150
    scenes: viz.Scenes = api.app.state.scenes
    ticket = scenes.ticket(token)
    assert ticket is not None
    scene = scenes.scene(ticket)
    assert scene.playback is not None and len(scene.playback.segments) == r.json()["segments"]
    assert scene.has_stock  # the stock as cut by the program is in the scene
    # playing: the stock after the current block (the first moves are rapids above the part: uncut)
    from server.jobs import job_stock_after

    assert scene.program is not None
    text, dialect, spec = scene.program
    uncut = job_stock_after(text, dialect, spec, 1)
    cut = job_stock_after(text, dialect, spec, scene.playback.moves[-1] + 1)

    def top(
        tiles: dict[str, tuple[str, np.ndarray, np.ndarray]],
    ) -> float:  # lowest point of the upper surface
        z = np.concatenate([vertices[:, 2] for _, vertices, _ in tiles.values()])
        return float(z[z > -29].min())  # (the base is at Z-30)

    assert (
        top(uncut) == 0 and top(cut) == -2
    )  # at first the stock's top at Z0; at the end the steps 2 mm deep
    # the stock is 80 × 70 mm in tiles of 20 mm: the contour cuts along the right and the front edge only,
    # so the untouched tiles keep their digest and are not sent again
    changed = {key for key in uncut if uncut[key][0] != cut[key][0]}
    assert len(uncut) == 16 and 0 < len(changed) < len(uncut)
    assert "3_1" not in changed  # the back left corner (Y 60–70, X 20–40) is never cut
    r = api.client.post(f"/api/v1/viz/{token}/playhead", json={"index": 0}, headers=auth(student))
    assert r.status_code == 200
    assert scene.tiles == {
        key: digest for key, (digest, _, _) in uncut.items()
    }  # the stock after the first move


def test_deviation_colours_where_the_part_leaves_the_band(api: Api) -> None:
    owner, student = api.user("instructor"), api.user()
    slug = unique("dev-")
    assert (
        api.client.post(
            "/api/v1/exercises/import", content=exercise_file(slug).encode(), headers=auth(owner)
        ).status_code
        == 201
    )
    token = api.client.post("/api/v1/viz", headers=auth(student)).json()["token"]
    program = (ROOT / "exercises" / "pal-mill" / "pal-05-g2-kreisbogen.nc").read_text(encoding="utf-8")
    r = api.client.post(
        f"/api/v1/viz/{token}/deviation", json={"program": program, "exercise": slug}, headers=auth(student)
    )
    assert r.status_code == 200 and r.json() == {
        "too_much": 0,
        "too_little": 0,
        "too_much_mm3": 0,
        "too_little_mm3": 0,
        "largest_mm": 0,
    }
    too_deep = program.replace("N50 G0 Z-2", "N50 G0 Z-3")
    r = api.client.post(
        f"/api/v1/viz/{token}/deviation", json={"program": too_deep, "exercise": slug}, headers=auth(student)
    )
    assert r.status_code == 200 and r.json()["too_much"] > 100 and r.json()["too_little"] == 0
    # in mm³ and mm, not in grid cells: the step is 1 mm too deep (0.95 beyond the 0.05 mm band) over its area
    gouge = r.json()
    assert gouge["largest_mm"] == pytest.approx(0.95, abs=0.01)
    from core.exercises import parse_exercise
    from core.grading import grade

    graded = grade(parse_exercise(exercise_file(slug)), too_deep).to_json("instructor")
    geometry = next(c for c in graded["criteria"] if c["id"] == "geometry")
    from core.grading.numbers import volume

    assert geometry["status"] in ("partial", "failed")
    assert volume(gouge["too_much_mm3"]) in geometry["message"]  # the volume the score names, German form
    scenes: viz.Scenes = api.app.state.scenes
    ticket = scenes.ticket(token)
    assert ticket is not None
    scene = scenes.scene(ticket)
    assert scene.server.scene._handle_from_node_name.get("/deviation/too_much") is not None
    not_deep_enough = program.replace("N50 G0 Z-2", "N50 G0 Z-1")
    r = api.client.post(
        f"/api/v1/viz/{token}/deviation",
        json={"program": not_deep_enough, "exercise": slug},
        headers=auth(student),
    )
    assert r.json()["too_much"] == 0 and r.json()["too_little"] > 100
    r = api.client.post(f"/api/v1/viz/{token}/deviation", json={"program": program}, headers=auth(student))
    assert r.status_code == 422 and r.json()["error"]["code"] == "EXERCISE_REQUIRED"


@pytest.mark.parametrize(
    "message,passes",
    [
        ({"type": "ViewerCameraMessage", "wxyz": [1, 0, 0, 0]}, True),
        ({"type": "GuiUpdateMessage", "uuid": "x", "updates": {}}, True),
        ({"type": "ShareUrlRequest"}, False),
        ({"type": "ShareUrlDisconnect"}, False),
        ({"type": "FileTransferStartUpload"}, False),
        ({"no": "type"}, False),
    ],
)
def test_bridge_lets_only_the_view_messages_through(message: dict[str, object], passes: bool) -> None:
    assert viz.passes(msgspec.msgpack.encode(message)) is passes


def test_bridge_drops_garbage() -> None:
    assert viz.passes(b"\xc1\xc1 not msgpack") is False


def test_tool_node_is_not_turned_and_sits_on_the_tip(api: Api) -> None:
    student = api.user()
    token = api.client.post("/api/v1/viz", headers=auth(student)).json()["token"]
    r = api.client.post(f"/api/v1/viz/{token}/scene", json={"program": GOOD}, headers=auth(student))
    assert r.status_code == 200
    scenes: viz.Scenes = api.app.state.scenes
    ticket = scenes.ticket(token)
    assert ticket is not None
    scene = scenes.scene(ticket)
    tool = scene.nodes["tool"]
    assert np.allclose(tool.wxyz, (1, 0, 0, 0))  # viser's meshes are in scene coordinates: Z is up already
    assert np.allclose(np.asarray(tool.position) / viz.M, (20, 0, 50), atol=1e-3)  # GOOD ends at X20 Z50
    r = api.client.post(f"/api/v1/viz/{token}/playhead", json={"index": 1}, headers=auth(student))
    assert r.status_code == 200
    end = scene.playback.segments[1][1] if scene.playback is not None else None
    assert np.allclose(np.asarray(tool.position) / viz.M, end, atol=1e-3)


def test_views_and_layers(api: Api) -> None:
    student = api.user()
    token = api.client.post("/api/v1/viz", headers=auth(student)).json()["token"]
    assert (
        api.client.post(
            f"/api/v1/viz/{token}/scene",
            json={"program": GOOD, "stock": {"min": [0, 0, -30], "max": [80, 70, 0]}},
            headers=auth(student),
        ).status_code
        == 200
    )
    scenes: viz.Scenes = api.app.state.scenes
    ticket = scenes.ticket(token)
    assert ticket is not None
    scene = scenes.scene(ticket)
    r = api.client.post(
        f"/api/v1/viz/{token}/view", json={"view": "top", "aspect": 1.5}, headers=auth(student)
    )
    assert r.status_code == 200 and r.json() == {"view": "top"}
    eye = np.asarray(scene.server.initial_camera.position) / viz.M
    assert np.allclose(eye[:2], (40, 35), atol=0.5) and eye[2] > 30  # straight above the stock's centre
    r = api.client.post(
        f"/api/v1/viz/{token}/layers", json={"rapid": False, "stock": False}, headers=auth(student)
    )
    assert r.json() == {"rapid": False, "feed": True, "contour": True, "stock": False}
    assert scene.nodes["rapid"].visible is False and scene.nodes["stock"].visible is False
    assert scene.nodes["feed"].visible is True
    # a new program keeps the trainee's choice
    api.client.post(f"/api/v1/viz/{token}/scene", json={"program": GOOD}, headers=auth(student))
    assert scene.nodes["rapid"].visible is False
    assert (
        api.client.post(f"/api/v1/viz/{token}/view", json={"view": "side"}, headers=auth(student)).status_code
        == 422
    )
