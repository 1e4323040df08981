"""The browser IDE's pages and its built assets (server/static, made by `npm run build` in web/).

Every page is the shared frame `pages/layout.html` (head, header, navigation, language switch) around
the page's own `pages/{name}.html`; the texts are German, and the bundle turns them to English when asked.
"""

from __future__ import annotations

import inspect
from functools import cache
from html import escape
from pathlib import Path
from string import Template
from typing import Annotated

from fastapi import APIRouter, Depends, FastAPI, Query, Request
from fastapi.responses import HTMLResponse, RedirectResponse, Response
from starlette.exceptions import HTTPException as StarletteHTTPException

from server.deps import SESSION_COOKIE, AppSettings, DbSession, token_user
from server.models import User
from server.security import safe_redirect

router = APIRouter(include_in_schema=False)
PAGES = Path(__file__).resolve().parents[1] / "pages"


@cache
def _html(name: str, title_key: str, title: str) -> str:
    layout = Template((PAGES / "layout.html").read_text(encoding="utf-8"))
    body = (PAGES / f"{name}.html").read_text(encoding="utf-8")
    return layout.substitute(title_key=title_key, title=title, body=body, page=name)


def viewer(request: Request, db: DbSession, settings: AppSettings) -> User | None:
    """The user of the session cookie, if it is valid: the header shows the name and "Abmelden"."""
    token = request.cookies.get(SESSION_COOKIE)
    return token_user(db, settings, token) if token else None


Viewer = Annotated[User | None, Depends(viewer)]


def _page(name: str, title: str, status_code: int = 200, who: User | None = None) -> HTMLResponse:
    if who is not None and who.must_change_password and name != "password":
        # a one-time password (server/accounts.py): the change form first, nothing else
        return HTMLResponse("", status_code=303, headers={"Location": "/password"})
    html = _html(name, f"title.{name}", title)
    if (
        who is not None
    ):  # for the header (web/src/header.js): who is logged in, and whether to show instructor links
        html = html.replace(
            "<body ", f'<body data-user="{escape(who.username)}" data-role="{escape(who.role)}" ', 1
        )
    return HTMLResponse(html, status_code=status_code)


def not_found() -> HTMLResponse:
    """The German 404 page for unknown pages (paths under /api/ answer JSON)."""
    return _page("not_found", "Seite nicht gefunden", status_code=404)


def install_not_found(app: FastAPI) -> None:
    """A 404 outside /api/ (a page that does not exist) is the 404 page; everything else keeps the JSON error
    of server/errors.py (install that first)."""
    json_handler = app.exception_handlers[StarletteHTTPException]

    async def handler(request: Request, exc: Exception) -> Response:
        if (
            isinstance(exc, StarletteHTTPException)
            and exc.status_code == 404
            and request.method in ("GET", "HEAD")
            and not request.url.path.startswith(("/api/", "/static/"))
        ):
            return not_found()
        result = json_handler(request, exc)
        return await result if inspect.isawaitable(result) else result

    app.add_exception_handler(StarletteHTTPException, handler)


@router.get("/", response_model=None)
def home(who: Viewer) -> HTMLResponse | RedirectResponse:
    """The exercise list (after login; without a session: the login page, before any script asks the API)."""
    if who is None:
        return RedirectResponse("/login", status_code=303)
    return _page("exercises", "Aufgaben", who=who)


@router.get("/practice")
def practice(who: Viewer) -> HTMLResponse:
    """Free practice: the editor with live diagnostics, usable without an account."""
    return _page("practice", "Freies Üben", who=who)


@router.get("/exercises/new", response_model=None)
def exercise_new(who: Viewer) -> HTMLResponse | RedirectResponse:
    """The exercise editor for a new exercise (instructors; the API decides what they may save)."""
    if who is None:
        return RedirectResponse("/login?next=/exercises/new", status_code=303)
    return _page("exercise-edit", "Neue Aufgabe", who=who)


@router.get("/exercises/{slug}/edit", response_model=None)
def exercise_edit(slug: str, who: Viewer) -> HTMLResponse | RedirectResponse:
    """The exercise editor for one of the instructor's exercises (the page asks the API for its document)."""
    if who is None:
        return RedirectResponse("/login?next=/instructor", status_code=303)
    return _page("exercise-edit", "Aufgabe bearbeiten", who=who)


@router.get("/exercises/{slug}")
def exercise(slug: str, who: Viewer) -> HTMLResponse:
    """One exercise: task, stock, tools, the finished part, the editor and submitting."""
    return _page("exercise", "Aufgabe", who=who)


@router.get("/exercises/{slug}/drawing")
def exercise_drawing(slug: str, who: Viewer) -> HTMLResponse:
    """The exercise's dimensioned drawing over the whole window: zoom, move and "Drucken" (A4 landscape); the
    page asks the API for the drawing (GET /api/v1/exercises/{slug}/drawing.svg), which decides who may see it."""
    return _page("drawing", "Zeichnung", who=who)


@router.get("/examples/{slug}/drawing")
def example_drawing(slug: str, who: Viewer) -> HTMLResponse:
    """The same for a built-in example of free practice (GET /api/v1/examples/{slug}/drawing.svg), without login."""
    return _page("drawing", "Zeichnung", who=who)


@router.get("/login")
def login(settings: AppSettings, next_: Annotated[str | None, Query(alias="next")] = None) -> Response:
    """The login form; `next` (where to go afterwards) must be a path on this site, else it is dropped
    (the page checks it again before it goes there)."""
    if next_ is not None and safe_redirect(next_) != next_:
        return RedirectResponse("/login", status_code=303)
    page = _page("login", "Anmelden")
    if settings.self_signup == "course-code":  # "Neu hier? Mit dem Beitrittscode registrieren"
        page = HTMLResponse(
            bytes(page.body).decode("utf-8").replace('<p id="signup-link" hidden>', '<p id="signup-link">', 1)
        )
    return page


@router.get("/password", response_model=None)
def password(who: Viewer) -> HTMLResponse | RedirectResponse:
    """Change one's password (reached from the user menu of the header; after a one-time password, every page
    leads here until it is changed)."""
    if who is None:
        return RedirectResponse("/login?next=/password", status_code=303)
    page = _page("password", "Passwort ändern", who=who)
    if who.must_change_password:  # why the page is shown: "Ihr Passwort wurde zurückgesetzt …"
        hidden = '<p id="password-required" class="notice" role="alert" hidden'
        page = HTMLResponse(
            bytes(page.body).decode("utf-8").replace(hidden, hidden.removesuffix(" hidden"), 1)
        )
    return page


@router.get("/signup")
def signup(settings: AppSettings) -> HTMLResponse:
    """Self-registration with a course's join code; only with PALTRAINER_SELF_SIGNUP=course-code."""
    if settings.self_signup != "course-code":
        return not_found()
    return _page("signup", "Registrieren")


@router.get("/docs")
def docs() -> HTMLResponse:
    """Swagger UI from our own copy (server/static/swagger, copied from swagger-ui-dist by the web build)."""
    return HTMLResponse((PAGES / "docs.html").read_text(encoding="utf-8"))


@router.get("/instructor")
def instructor(who: Viewer) -> HTMLResponse:
    """The submissions one may see (instructors: those to their exercises), with CSV export."""
    return _page("instructor", "Abgaben", who=who)


@router.get("/courses/{course_id}", response_model=None)
def course(course_id: str, who: Viewer) -> HTMLResponse | RedirectResponse:
    """An instructor's course: members, assignments, the results matrix and the class's insights (the page asks
    the API, which decides who may see what)."""
    if not (course_id.isascii() and course_id.isdigit()):
        return not_found()
    if who is None:
        return RedirectResponse(f"/login?next=/courses/{course_id}", status_code=303)
    return _page("course", "Klasse", who=who)


def course_frame() -> HTMLResponse:
    """The course page without a session cookie: inside a learning platform's frame (server/routes/lti.py)."""
    return _page("course", "Klasse")


@router.get("/admin", response_model=None)
def admin(who: Viewer) -> HTMLResponse | RedirectResponse:
    """The admin page: users, API keys, learning platforms (web/src/page-admin.js asks /api/v1/users,
    /api/v1/api-keys and /api/v1/admin/…). Anyone else logged in reads "Nur für Administratoren" (403)."""
    if who is None:
        return RedirectResponse("/login?next=/admin", status_code=303)
    return _page("admin", "Verwaltung", status_code=200 if who.role == "admin" else 403, who=who)


@router.get("/about")
def about(who: Viewer) -> HTMLResponse:
    """Über / Lizenzen: PAL Trainer's licence and those of the browser packages bundled with it."""
    return _page("about", "Über / Lizenzen", who=who)
