"""The browser IDE's pages and its built assets (server/static, made by `npm run build` in web/).

Every page is the shared frame `pages/layout.html` (head, header, navigation, language switch) around
the page's own `pages/{name}.html`; the texts are German, and the bundle turns them to English when asked.
"""

from __future__ import annotations

from functools import cache
from pathlib import Path
from string import Template

from fastapi import APIRouter
from fastapi.responses import HTMLResponse

router = APIRouter(include_in_schema=False)
PAGES = Path(__file__).resolve().parents[1] / "pages"


@cache
def _html(name: str, title_key: str, title: str) -> str:
    layout = Template((PAGES / "layout.html").read_text(encoding="utf-8"))
    body = (PAGES / f"{name}.html").read_text(encoding="utf-8")
    return layout.substitute(title_key=title_key, title=title, body=body)


def _page(name: str, title: str) -> HTMLResponse:
    return HTMLResponse(_html(name, f"title.{name}", title))


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
def login() -> HTMLResponse:
    return _page("login", "Anmelden")


@router.get("/instructor")
def instructor() -> HTMLResponse:
    """The submissions one may see (instructors: those to their exercises), with CSV export."""
    return _page("instructor", "Abgaben")
