"""Security headers on every response, pages without inline script, /docs from our own files, a German 404
page (JSON under /api/), and the SQLite file readable by its owner only."""

from __future__ import annotations

import re
import stat
from pathlib import Path

import pytest
from server_helpers import Api

from server.config import Settings
from server.db import Database
from server.routes.pages import PAGES

PAGE_PATHS = ["/", "/practice", "/login", "/instructor", "/exercises/nuten", "/docs", "/no/such/page"]


def _directives(csp: str) -> dict[str, list[str]]:
    return {part.split()[0]: part.split()[1:] for part in (p.strip() for p in csp.split(";")) if part}


@pytest.mark.parametrize(
    "path",
    [*PAGE_PATHS, "/api/v1/dialects", "/api/v1/nothing", "/healthz", "/static/app.css", "/openapi.json"],
)
def test_every_response_has_the_security_headers(api: Api, path: str) -> None:
    r = api.client.get(path)
    assert r.headers["x-content-type-options"] == "nosniff"
    assert r.headers["referrer-policy"] == "same-origin"
    csp = _directives(r.headers["content-security-policy"])
    assert csp["script-src"] == ["'self'"]
    assert csp["frame-ancestors"] == ["'self'"]
    assert csp["object-src"] == ["'none'"] and csp["base-uri"] == ["'none'"]
    assert csp["default-src"] == ["'self'"] and csp["form-action"] == ["'self'"]


def test_a_refused_large_body_has_the_security_headers_too(api: Api) -> None:
    r = api.client.post(
        "/api/v1/check",
        content=b"x" * (api.settings.max_body_bytes + 1),
        headers={"Content-Type": "application/json"},
    )
    assert r.status_code == 413
    assert r.headers["x-content-type-options"] == "nosniff" and "content-security-policy" in r.headers


def test_frame_ancestors_takes_the_configured_origins(api: Api) -> None:
    old = api.settings.frame_ancestors
    api.settings.frame_ancestors = ["https://lms.example.org", "https://x.example; script-src *"]
    try:
        csp = _directives(api.client.get("/").headers["content-security-policy"])
        assert csp["frame-ancestors"] == ["'self'", "https://lms.example.org"]
        assert csp["script-src"] == ["'self'"]
    finally:
        api.settings.frame_ancestors = old


@pytest.mark.parametrize("name", sorted(p.name for p in PAGES.glob("*.html")))
def test_pages_have_no_inline_script(name: str) -> None:
    html = (PAGES / name).read_text(encoding="utf-8")
    for attrs, body in re.findall(r"<script\b([^>]*)>(.*?)</script>", html, flags=re.DOTALL | re.IGNORECASE):
        assert "src=" in attrs and not body.strip(), f"inline script in {name}"
    assert not re.search(r"\son[a-z]+\s*=", html, flags=re.IGNORECASE), f"inline event handler in {name}"
    assert "javascript:" not in html.lower()


@pytest.mark.parametrize("path", ["/", "/practice", "/login", "/instructor", "/exercises/nuten"])
def test_served_pages_have_no_inline_script(api: Api, path: str) -> None:
    html = api.client.get(path).text
    for attrs, body in re.findall(r"<script\b([^>]*)>(.*?)</script>", html, flags=re.DOTALL | re.IGNORECASE):
        assert "src=" in attrs and not body.strip()


def test_docs_use_our_own_swagger_files(api: Api) -> None:
    r = api.client.get("/docs")
    assert r.status_code == 200
    urls = [u for u in re.findall(r"(?:src|href)=\"([^\"]+)\"", r.text) if u != "data:,"]  # no favicon
    assert urls and all(u.startswith("/") and not u.startswith("//") for u in urls), urls
    for attrs, body in re.findall(
        r"<script\b([^>]*)>(.*?)</script>", r.text, flags=re.DOTALL | re.IGNORECASE
    ):
        assert "src=" in attrs and not body.strip()
    assert "/static/swagger/swagger-ui-bundle.js" in urls
    assert api.client.get("/redoc").status_code == 404


def test_unknown_page_is_a_german_404_page(api: Api) -> None:
    r = api.client.get("/no/such/page", headers={"Accept": "text/html"})
    assert r.status_code == 404 and r.headers["content-type"].startswith("text/html")
    assert "Seite nicht gefunden" in r.text and 'href="/"' in r.text


def test_unknown_api_path_is_json_404(api: Api) -> None:
    r = api.client.get("/api/v1/no-such-thing", headers={"Accept": "text/html"})
    assert r.status_code == 404 and r.json()["error"]["code"] == "NOT_FOUND"


def test_sqlite_file_is_private(tmp_path: Path) -> None:
    database = Database(Settings(data_dir=tmp_path / "data", secret_key="x" * 40))
    try:
        database.engine.connect().close()
        path = tmp_path / "data" / "paltrainer.sqlite3"
        assert path.exists() and stat.S_IMODE(path.stat().st_mode) == 0o600
    finally:
        database.engine.dispose()


def test_viser_page_allows_exactly_its_own_two_scripts(api: Api) -> None:
    r = api.client.post("/api/v1/viz")
    assert r.status_code == 201, r.text
    page = api.client.get(r.json()["url"])
    csp = _directives(page.headers["content-security-policy"])
    hashes = [s for s in csp["script-src"] if s.startswith("'sha256-")]
    assert len(hashes) == 2 and "'unsafe-inline'" not in csp["script-src"]
    assert csp["script-src"][0] == "'self'" and "'wasm-unsafe-eval'" in csp["script-src"]
    assert csp["frame-ancestors"] == ["'self'"]
