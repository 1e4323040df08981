"""GET /api/v1/exercises/{slug}/drawing.svg: the dimensioned drawing over HTTP."""

from __future__ import annotations

import xml.etree.ElementTree as ET

from server_helpers import Api, auth, error_code, unique
from test_server_lms import exercise_file


def test_drawing_of_an_uploaded_exercise(api: Api) -> None:
    owner, student = api.user("instructor"), api.user()
    slug = unique("zeichnung-")
    assert (
        api.client.post(
            "/api/v1/exercises/import", content=exercise_file(slug).encode(), headers=auth(owner)
        ).status_code
        == 201
    )
    r = api.client.get(f"/api/v1/exercises/{slug}/drawing.svg", headers=auth(student))
    assert r.status_code == 200 and r.headers["content-type"].startswith("image/svg+xml")
    root = ET.fromstring(r.content)
    texts = {t.text for t in root.iter("{http://www.w3.org/2000/svg}text")}
    assert {"23,6", "56,4", "70"} <= texts and "Draufsicht" in texts
    en = api.client.get(f"/api/v1/exercises/{slug}/drawing.svg?lang=en&download=true", headers=auth(student))
    assert "Top view" in en.text and "23.6" in en.text
    assert en.headers["content-disposition"] == f'attachment; filename="{slug}.svg"'
    assert api.client.get(f"/api/v1/exercises/{slug}/drawing.svg").status_code == 401
    missing = api.client.get("/api/v1/exercises/no-such-exercise/drawing.svg", headers=auth(student))
    assert missing.status_code == 404 and error_code(missing) == "EXERCISE_NOT_FOUND"
    assert (
        api.client.get(f"/api/v1/exercises/{slug}/drawing.svg?lang=xx", headers=auth(student)).status_code
        == 422
    )
