"""The turned part in the lathe's 3D view: the bar revolved from the turning simulation's profile in chunks along
Z (scene x = Z, the radius in the scene's y-z plane), the chuck, playback resending only the chunks that
changed, and the half section that cuts the part open."""

from __future__ import annotations

from typing import Any

import numpy as np
from server_helpers import Api, unique

from core.scene.meshes import InsertShape
from core.scene.turned import BAND_LIFT, CUT_OFFSET
from server import viz

# a bar Ø40 × 60 (20 mm in the chuck) turned to Ø30 over 20 mm, then a shoulder up to Ø42
PROGRAM = (
    "%\nO1\nN10 G95 G97 S1000 M4\nN20 T0101\nN30 G0 X30 Z2\nN40 G1 Z-20 F0.2\nN50 G1 X42\n"
    "N60 G0 X100 Z100\nN70 M30\n"
)
BAR = {"diameter": 40, "length": 60, "chuck_length": 20}
LINE = {"N30": 5, "N40": 6, "N50": 7, "N60": 8}


def _open(
    api: Api, blank: dict[str, Any] | None = BAR, program: str = PROGRAM
) -> tuple[str, dict, viz.Scene]:
    token = api.client.post("/api/v1/viz").json()["token"]
    body: dict[str, Any] = {"program": program, "dialect": "traub-tx8d"}
    if blank is not None:
        body["blank"] = blank
    r = api.client.post(f"/api/v1/viz/{token}/scene", json=body)
    assert r.status_code == 200, r.text
    ticket = api.app.state.scenes.ticket(token)
    assert ticket is not None
    return token, r.json(), api.app.state.scenes.scene(ticket)


def _chunk_vertices(scene: viz.Scene, cut: bool = False) -> np.ndarray:
    """All vertices (scene mm) of the part's surface chunks (or of its cut faces) as the scene holds them."""
    handles = scene.server.scene._handle_from_node_name
    names = [f"/stock/{k}" for k in scene.tiles if k.startswith("z") and k.endswith("_cut") == cut]
    assert names, scene.tiles
    return np.vstack([np.asarray(handles[n].vertices) for n in names]) / viz.M


def _radius_between(vertices: np.ndarray, z0: float, z1: float) -> np.ndarray:
    inside = (vertices[:, 0] > z0) & (vertices[:, 0] < z1)
    return np.hypot(vertices[inside, 1], vertices[inside, 2])


def _index(body: dict, line: int) -> int:
    """The last segment of a block's line (the stock after that block)."""
    return len(body["lines"]) - 1 - body["lines"][::-1].index(line)


def test_bar_turned_to_a_smaller_diameter_is_revolved_with_its_radii(api: Api) -> None:
    _, body, scene = _open(api)
    assert body["lathe"] is True and body["blank"]["diameter"] == 40 and body["blank"]["length"] == 60
    chunks = sorted(k for k in scene.tiles if k.startswith("z"))
    assert len(chunks) == 6 and not any(k.endswith("_cut") for k in chunks)  # 60 mm in chunks of 10 mm
    v = _chunk_vertices(scene)
    turned = _radius_between(v, -18.0, -1.0)
    assert len(turned) > 48 and np.allclose(turned.max(), 15.0, atol=0.01)  # Ø30 over the first 20 mm
    assert turned.min() > 14.99  # no faces across the bar inside the turned length (between chunks)
    untouched = _radius_between(v, -59.0, -21.5)
    assert np.allclose(untouched.max(), 20.0, atol=0.01) and untouched.min() > 19.99  # Ø40 elsewhere
    assert np.allclose(_radius_between(v, -60.01, -59.99).min(), 0.0)  # the bar's end in the chuck is closed
    front = _radius_between(v, -0.01, 0.01)  # the front face at Z0: from the axis out to R15
    assert np.isclose(front.min(), 0.0) and np.isclose(front.max(), 15.0, atol=0.01)
    # round: 48 sections around the axis
    ring = v[np.isclose(v[:, 0], -10.0, atol=1e-3) & np.isclose(np.hypot(v[:, 1], v[:, 2]), 15.0, atol=0.01)]
    assert len({round(float(np.degrees(np.arctan2(y, z))) % 360, 1) for _, y, z in ring}) == 48
    # the chuck: its jaws hold the last 20 mm from outside the bar
    handles = scene.server.scene._handle_from_node_name
    jaws = np.asarray(handles["/chuck/jaws"].vertices) / viz.M
    assert np.isclose(jaws[:, 0].min(), -60.0) and np.isclose(jaws[:, 0].max(), -40.0)
    assert np.isclose(jaws[jaws[:, 2] > 0, 2].min(), 20.0, atol=0.01)  # the top jaw's face on the bar
    # the tool: the generic outside insert (C 80°) with its theoretical tip at the end of the path
    cutter = np.asarray(handles["/tool/cutter"].vertices) / viz.M
    assert np.ptp(cutter[:, 0]) > 5 and np.ptp(cutter[:, 2]) > 5  # an insert, not a point
    tool = np.asarray(handles["/tool"].position) / viz.M
    assert np.allclose(tool, [100, 0, 50], atol=1e-3)  # N60 X100 Z100: Z100, radius 50


def test_blank_derived_from_the_program_without_one(api: Api) -> None:
    _, body, scene = _open(api, blank=None)
    # the largest diameter cut (N50 X42) and long enough that the chuck stays clear of Z-20
    assert body["blank"]["diameter"] == 42 and body["blank"]["length"] - body["blank"]["clamp"] > 20
    assert np.allclose(_radius_between(_chunk_vertices(scene), -18, -1).max(), 15.0, atol=0.01)


def test_bad_blank_is_refused(api: Api) -> None:
    token = api.client.post("/api/v1/viz").json()["token"]
    r = api.client.post(
        f"/api/v1/viz/{token}/scene",
        json={
            "program": PROGRAM,
            "dialect": "traub-tx8d",
            "blank": {"diameter": 40, "inner_diameter": 40, "length": 60},
        },
    )
    assert r.status_code == 422


def test_playback_resends_only_the_chunks_that_changed(api: Api) -> None:
    token, body, scene = _open(api)
    sent: list[str] = []
    original = scene.server.scene.add_mesh_simple

    def spy(name: str, *args: Any, **kwargs: Any) -> Any:
        sent.append(name)
        return original(name, *args, **kwargs)

    scene.server.scene.add_mesh_simple = spy  # type: ignore[method-assign]

    def step(line: int) -> list[str]:
        sent.clear()
        r = api.client.post(f"/api/v1/viz/{token}/playhead", json={"index": _index(body, line)})
        assert r.status_code == 200 and r.json()["line"] == line
        return sorted(n for n in sent if n.startswith("/stock/"))

    # after N30 (a rapid move, nothing cut yet): the two chunks of the turned length are whole again
    assert step(LINE["N30"]) == ["/stock/z4", "/stock/z5"]
    assert np.allclose(_radius_between(_chunk_vertices(scene), -18, -1).max(), 20.0, atol=0.01)
    # N40 turns them to Ø30; the chunks over the rest of the bar are not sent again
    assert step(LINE["N40"]) == ["/stock/z4", "/stock/z5"]
    assert np.allclose(_radius_between(_chunk_vertices(scene), -18, -1).max(), 15.0, atol=0.01)
    # N60 moves away in rapid: nothing changes, nothing is sent
    step(LINE["N50"])
    assert step(LINE["N60"]) == []


def test_half_section_cuts_the_part_open(api: Api) -> None:
    tube = {"diameter": 40, "inner_diameter": 20, "length": 60, "chuck_length": 20}
    token, _, scene = _open(api, blank=tube)
    whole = _chunk_vertices(scene)
    assert whole[:, 1].min() < -19  # round all the way
    r = api.client.post(f"/api/v1/viz/{token}/section", json={"half": True})
    assert r.status_code == 200 and r.json() == {"half": True}
    half = _chunk_vertices(scene)
    assert half[:, 1].min() > -1e-4  # only the back half is left (the camera looks from the front, −y)
    cut = _chunk_vertices(scene, cut=True)
    assert np.allclose(cut[:, 1], CUT_OFFSET)  # the cut face lies in the drawing plane
    # the section shows the bore: at Z-10 the wall reaches from R10 (the bore) to R15 above and below the axis
    wall = cut[np.isclose(cut[:, 0], cut[np.argmin(np.abs(cut[:, 0] + 10)), 0])]
    assert np.isclose(wall[:, 2].max(), 15, atol=0.01) and np.isclose(wall[:, 2].min(), -15, atol=0.01)
    assert np.isclose(np.abs(wall[:, 2]).min(), 10, atol=0.01)
    jaws = np.asarray(scene.server.scene._handle_from_node_name["/chuck/jaws"].vertices) / viz.M
    assert len(jaws) == 2 * 8 and jaws[:, 1].min() > -5.01  # the jaw in front of the cut is left out
    # the cut stays for the next program and playback; switched off, the part is whole again
    r = api.client.post(
        f"/api/v1/viz/{token}/scene", json={"program": PROGRAM, "dialect": "traub-tx8d", "blank": tube}
    )
    assert r.status_code == 200 and any(k.endswith("_cut") for k in scene.tiles)
    r = api.client.post(f"/api/v1/viz/{token}/section", json={"half": False})
    assert r.json() == {"half": False} and not any(k.endswith("_cut") for k in scene.tiles)
    assert _chunk_vertices(scene)[:, 1].min() < -19


def test_milling_scene_after_a_lathe_scene_has_no_chuck(api: Api) -> None:
    token, _, scene = _open(api)
    milling = "N10 T1 TC1 M6\nN20 S1200 F150 M3\nN30 G0 X0 Y0 Z2\nN40 G1 Z-2\nN50 G1 X20\nN60 G0 Z50 M30\n"
    r = api.client.post(f"/api/v1/viz/{token}/scene", json={"program": milling, "dialect": "pal-mill"})
    assert r.status_code == 200 and r.json()["lathe"] is False
    names = scene.server.scene._handle_from_node_name
    assert "/chuck" not in names and not any(k.startswith("z") for k in scene.tiles)


def test_exercise_blank_and_its_tools_insert(api: Api) -> None:
    """An exercise's blank (traub-01-srk-fase: Ø44 × 80, 30 mm in the chuck) and its tool T1 (C, R0.8)."""
    from core.exercises import EXERCISES_DIR, load_exercise
    from server import repository as repo
    from server.seed import exercise_fields

    doc = load_exercise(EXERCISES_DIR / "traub-tx8d" / "traub-01-srk-fase.yaml")
    doc = type(doc).model_validate({**doc.model_dump(), "id": unique("turning-"), "order": None})
    with api.app.state.db.session() as db:
        repo.create_exercise(db, exercise_fields(doc), owner_id=None, builtin=True)
    token = api.client.post("/api/v1/viz").json()["token"]
    r = api.client.post(
        f"/api/v1/viz/{token}/scene",
        json={"program": doc.reference, "dialect": "traub-tx8d", "exercise": doc.id},
    )
    assert r.status_code == 200, r.text
    blank = r.json()["blank"]
    assert (blank["diameter"], blank["length"], blank["clamp"]) == (44, 80, 30)
    ticket = api.app.state.scenes.ticket(token)
    assert ticket is not None
    scene = api.app.state.scenes.scene(ticket)
    v = _chunk_vertices(scene)
    assert np.isclose(v[:, 0].min(), -80) and np.hypot(v[:, 1], v[:, 2]).max() <= 22.0 + 1e-3
    assert scene.playback is not None
    shape = scene.playback.shapes[1]
    assert isinstance(shape, InsertShape) and shape.insert == "C"
    # the nose radius R0.8 rounds the insert's point: its outline stays 0.8 mm and more away from the sharp tip
    outline = np.asarray(shape.outline)
    assert np.hypot(outline[:, 0], outline[:, 1]).min() > 0.3


def test_deviation_after_grading_as_bands_on_the_turned_part(api: Api) -> None:
    """A shoulder turned to Ø38 instead of Ø40 over 30 mm: red bands (too much removed) around the part there,
    with the volume π·(20² − 19²)·30 mm³ less what the tolerance band keeps; the reference: no bands."""
    from core.exercises import EXERCISES_DIR, load_exercise
    from server import repository as repo
    from server.seed import exercise_fields

    doc = load_exercise(EXERCISES_DIR / "traub-tx8d" / "traub-01-srk-fase.yaml")
    doc = type(doc).model_validate({**doc.model_dump(), "id": unique("turning-"), "order": None})
    with api.app.state.db.session() as db:
        repo.create_exercise(db, exercise_fields(doc), owner_id=None, builtin=True)
    token = api.client.post("/api/v1/viz").json()["token"]
    wrong = doc.reference.replace("G1 X40 D2", "G1 X38 D2")
    assert wrong != doc.reference
    body = {"program": wrong, "dialect": "traub-tx8d", "exercise": doc.id}
    assert api.client.post(f"/api/v1/viz/{token}/scene", json=body).status_code == 200
    r = api.client.post(f"/api/v1/viz/{token}/deviation", json=body)
    assert r.status_code == 200, r.text
    d = r.json()
    assert d["too_much"] > 0 and d["too_little"] == 0 and np.isclose(d["largest_mm"], 1.0 - 0.05, atol=0.02)
    assert 0.8 * np.pi * (20**2 - 19**2) * 28 < d["too_much_mm3"] < np.pi * (20**2 - 19**2) * 31
    ticket = api.app.state.scenes.ticket(token)
    assert ticket is not None
    handles = api.app.state.scenes.scene(ticket).server.scene._handle_from_node_name
    band = np.asarray(handles["/deviation/too_much"].vertices) / viz.M
    radius = np.hypot(band[:, 1], band[:, 2])
    assert band[:, 0].min() > -31 and band[:, 0].max() < 0.5  # over the shoulder's 30 mm
    shoulder = radius[(band[:, 0] > -29) & (band[:, 0] < -3)]
    assert np.allclose(shoulder, 19 + BAND_LIFT, atol=0.01)  # on the Ø38 surface, just outside it
    assert radius.min() > 17  # down the chamfer D2 at the front
    assert "/deviation/too_little" not in handles
    body["program"] = doc.reference
    r = api.client.post(f"/api/v1/viz/{token}/deviation", json=body)
    assert r.json()["too_much"] == 0 and r.json()["too_little"] == 0
    assert "/deviation/too_much" not in api.app.state.scenes.scene(ticket).server.scene._handle_from_node_name
