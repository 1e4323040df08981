"""The drawing's own page (issue 28: "Zeichnung groß öffnen" opens a page of ours, not the raw SVG): served for an
exercise and for a free practice example as every page is (the shared frame, the page named in data-page, the
Content-Security-Policy, no inline script); the SVG it shows says where its views are (data-views), which the
viewer fits to the Zeichnung tab."""

from __future__ import annotations

import re
import xml.etree.ElementTree as ET

import pytest
from server_helpers import Api, builtin_exercise


def _directives(csp: str) -> dict[str, list[str]]:
    return {part.split()[0]: part.split()[1:] for part in (p.strip() for p in csp.split(";")) if part}


@pytest.mark.parametrize(
    "path", ["/exercises/pal-05-g2-kreisbogen/drawing", "/examples/traub-10-schruppen-g71-g88/drawing"]
)
def test_the_drawing_page_is_ours(api: Api, path: str) -> None:
    r = api.client.get(path)
    assert r.status_code == 200 and r.headers["content-type"].startswith("text/html")
    html = r.text
    assert 'data-page="drawing"' in html and 'id="drawing-page"' in html and 'id="drawing-viewer"' in html
    assert '<script type="module" src="/static/app.js"></script>' in html
    for attrs, body in re.findall(r"<script\b([^>]*)>(.*?)</script>", html, flags=re.DOTALL | re.IGNORECASE):
        assert "src=" in attrs and not body.strip()
    csp = _directives(r.headers["content-security-policy"])
    assert csp["script-src"] == ["'self'"] and "blob:" in csp["img-src"]  # the viewer shows the SVG as a blob


def test_the_svg_says_where_its_views_are(api: Api) -> None:
    slug = builtin_exercise(api)  # PAL-01 (80 × 70 × 30) as a built-in example
    r = api.client.get(f"/api/v1/examples/{slug}/drawing.svg")
    assert r.status_code == 200
    views = [float(v) for v in (ET.fromstring(r.content).get("data-views") or "").split()]
    assert len(views) == 4 and 0 <= views[0] < views[2] <= 297 and 0 <= views[1] < views[3] <= 210
    assert views[2] < 297 - 100  # the views of the 80 × 70 part, not the whole sheet with its title block
