"""The browser IDE's pages and its built assets (server/static, made by `npm run build` in web/).

Every page is the shared frame `pages/layout.html` (head, header, navigation, language switch) around
the page's own `pages/{name}.html`; the texts are German, and the bundle turns them to English when asked.
"""

from __future__ import annotations

import inspect
from functools import cache
from pathlib import Path
from string import Template
from typing import Annotated

from fastapi import APIRouter, FastAPI, Query, Request
from fastapi.responses import HTMLResponse, RedirectResponse, Response
from starlette.exceptions import HTTPException as StarletteHTTPException

from server.security import safe_redirect

router = APIRouter(include_in_schema=False)
PAGES = Path(__file__).resolve().parents[1] / "pages"


@cache
def _html(name: str, title_key: str, title: str) -> str:
    layout = Template((PAGES / "layout.html").read_text(encoding="utf-8"))
    body = (PAGES / f"{name}.html").read_text(encoding="utf-8")
    return layout.substitute(title_key=title_key, title=title, body=body, page=name)


def _page(name: str, title: str, status_code: int = 200) -> HTMLResponse:
    return HTMLResponse(_html(name, f"title.{name}", title), status_code=status_code)


def not_found() -> HTMLResponse:
    """The German 404 page for unknown pages (paths under /api/ answer JSON)."""
    return _page("not_found", "Seite nicht gefunden", status_code=404)


def install_not_found(app: FastAPI) -> None:
    """A 404 outside /api/ (a page that does not exist) is the 404 page; everything else keeps the JSON error
    of server/errors.py (install that first)."""
    json_handler = app.exception_handlers[StarletteHTTPException]

    async def handler(request: Request, exc: Exception) -> Response:
        if isinstance(exc, StarletteHTTPException) and exc.status_code == 404 and request.method in ("GET", "HEAD") \
                and not request.url.path.startswith(("/api/", "/static/")):
            return not_found()
        result = json_handler(request, exc)
        return await result if inspect.isawaitable(result) else result

    app.add_exception_handler(StarletteHTTPException, handler)


@router.get("/")
def home() -> HTMLResponse:
    """The exercise list (after login)."""
    return _page("exercises", "Aufgaben")


@router.get("/practice")
def practice() -> HTMLResponse:
    """Free practice: the editor with live diagnostics, usable without an account."""
    return _page("practice", "Freies Üben")


@router.get("/exercises/{slug}")
def exercise(slug: str) -> HTMLResponse:
    """One exercise: task, stock, tools, the finished part, the editor and submitting."""
    return _page("exercise", "Aufgabe")


@router.get("/login")
def login(next_: Annotated[str | None, Query(alias="next")] = None) -> Response:
    """The login form; `next` (where to go afterwards) must be a path on this site, else it is dropped
    (the page checks it again before it goes there)."""
    if next_ is not None and safe_redirect(next_) != next_:
        return RedirectResponse("/login", status_code=303)
    return _page("login", "Anmelden")


@router.get("/docs")
def docs() -> HTMLResponse:
    """Swagger UI from our own copy (server/static/swagger, copied from swagger-ui-dist by the web build)."""
    return HTMLResponse((PAGES / "docs.html").read_text(encoding="utf-8"))


@router.get("/instructor")
def instructor() -> HTMLResponse:
    """The submissions one may see (instructors: those to their exercises), with CSV export."""
    return _page("instructor", "Abgaben")
