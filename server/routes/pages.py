"""The browser IDE's pages and its built assets (server/static, made by `npm run build` in web/)."""

from __future__ import annotations

from pathlib import Path

from fastapi import APIRouter
from fastapi.responses import FileResponse

router = APIRouter(include_in_schema=False)
PAGES = Path(__file__).resolve().parents[1] / "pages"


def _page(name: str) -> FileResponse:
    return FileResponse(PAGES / f"{name}.html", media_type="text/html")


@router.get("/")
def home() -> FileResponse:
    """The exercise list (after login)."""
    return _page("exercises")


@router.get("/practice")
def practice() -> FileResponse:
    """Free practice: the editor with live diagnostics, usable without an account."""
    return _page("practice")


@router.get("/exercises/{slug}")
def exercise(slug: str) -> FileResponse:
    """One exercise: task, stock, tools, the finished part, the editor and submitting."""
    return _page("exercise")


@router.get("/login")
def login() -> FileResponse:
    return _page("login")


@router.get("/instructor")
def instructor() -> FileResponse:
    """The submissions one may see (instructors: those to their exercises), with CSV export."""
    return _page("instructor")
