"""The browser IDE's pages and its built assets (server/static, made by `npm run build` in web/)."""

from __future__ import annotations

from pathlib import Path

from fastapi import APIRouter
from fastapi.responses import FileResponse, RedirectResponse

router = APIRouter(include_in_schema=False)
PAGES = Path(__file__).resolve().parents[1] / "pages"


@router.get("/")
def home() -> RedirectResponse:
    return RedirectResponse("/practice")


@router.get("/practice")
def practice() -> FileResponse:
    """Free practice: the editor with live diagnostics, usable without an account."""
    return FileResponse(PAGES / "practice.html", media_type="text/html")
