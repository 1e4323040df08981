"""The 3D view's preset views (issue 28, point 12): from above the tool does not cover the part — only the
circle it cuts is drawn there, the tool whole again in the other views. Each view fits the stock with a margin
and the stock's box is outlined: tests/test_scene_meshes.py."""

from __future__ import annotations

import numpy as np
from server_helpers import GOOD, Api, auth

from server import viz


def test_the_top_view_shows_the_tool_as_the_circle_it_cuts(api: Api) -> None:
    student = api.user()
    token = api.client.post("/api/v1/viz", headers=auth(student)).json()["token"]
    r = api.client.post(
        f"/api/v1/viz/{token}/scene",
        json={"program": GOOD, "stock": {"min": [0, 0, -30], "max": [80, 70, 0]}},
        headers=auth(student),
    )
    assert r.status_code == 200
    scenes: viz.Scenes = api.app.state.scenes
    ticket = scenes.ticket(token)
    assert ticket is not None
    scene = scenes.scene(ticket)
    body, ring = scene.nodes["tool_body"], scene.nodes["tool_footprint"]
    assert all(h.visible for h in body) and not ring.visible  # iso: the tool as it is
    for view, whole in (("top", False), ("front", True), ("top", False), ("reset", True)):
        r = api.client.post(
            f"/api/v1/viz/{token}/view", json={"view": view, "aspect": 1.2}, headers=auth(student)
        )
        assert r.status_code == 200
        assert all(h.visible == whole for h in scene.nodes["tool_body"]), view
        assert scene.nodes["tool_footprint"].visible == (not whole), view
    # the circle: the tool's radius (GOOD's T1 is the default table's), at its tip
    api.client.post(f"/api/v1/viz/{token}/view", json={"view": "top"}, headers=auth(student))
    points = np.asarray(scene.nodes["tool_footprint"].points) / viz.M
    radii = np.linalg.norm(points[..., :2], axis=-1)
    assert (
        np.allclose(radii, radii.flat[0], atol=1e-3)
        and radii.flat[0] > 1
        and np.all(np.abs(points[..., 2]) < 0.1)
    )
    # a new program while looking from above: the tool (rebuilt) stays a circle
    r = api.client.post(
        f"/api/v1/viz/{token}/scene", json={"program": GOOD.replace("X20", "X30")}, headers=auth(student)
    )
    assert r.status_code == 200 and scene.view == "top"
    assert not any(h.visible for h in scene.nodes["tool_body"]) and scene.nodes["tool_footprint"].visible
