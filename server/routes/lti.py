"""LTI 1.3 endpoints: /lti/login, /lti/launch, /lti/jwks, /lti/config, /lti/register, /lti/open, /lti/session,
/lti/exercise/{slug}, /lti/deep-link (docs/lti.md); the admin's /api/v1/admin/lti/… are in admin.py.

The pages a platform frames get a Content-Security-Policy whose frame-ancestors name that platform only
(request.state.csp_extra, read by server/middleware.py); refused launches answer a German page and are logged.
"""

from __future__ import annotations

import logging
from datetime import UTC, datetime, timedelta
from html import escape
from pathlib import Path
from typing import Annotated, Any

from fastapi import APIRouter, FastAPI, Form, Request
from fastapi.responses import FileResponse, HTMLResponse, JSONResponse, RedirectResponse, Response
from pydantic import BaseModel, ConfigDict, Field
from starlette.concurrency import run_in_threadpool

from server import repository as repo
from server.deps import AppSettings, DbSession, client_address
from server.errors import ApiError
from server.lti import deep_linking, keys, launch, registration
from server.models import LtiPlatform
from server.ratelimit import RateLimiter
from server.routes import pages
from server.security import make_token

log = logging.getLogger("paltrainer.lti")
router = APIRouter(include_in_schema=False)
STATIC = Path(__file__).resolve().parents[1] / "lti" / "static"
DEEP_LINK_TICKET_MINUTES = 30  # the teacher picks exercises meanwhile


def install(app: FastAPI) -> None:
    """The LTI routes, the platform-JWKS cache and the HTTP transport (tests put a loopback one there)."""
    keys.configure(app.state.settings)
    app.state.lti_jwks = launch.JwksCache()
    app.state.lti_transport = None
    app.include_router(router)


def _base(request: Request) -> str:
    return str(request.base_url).rstrip("/")


def _frame(request: Request, platform: LtiPlatform | None, form_action: list[str] | None = None) -> None:
    """Let `platform` (its issuer's and login page's origins) frame this response, and post forms to
    `form_action`; without a platform: anyone may frame it (used for pages with nothing to click)."""
    origins = (
        sorted({registration.origin(platform.issuer), registration.origin(platform.auth_login_url)})
        if platform is not None
        else ["*"]
    )
    extra: dict[str, list[str]] = {"frame-ancestors": origins}
    if form_action:
        extra["form-action"] = form_action
    request.state.csp_extra = extra


def _html(title: str, body: str, status: int = 200, script: str | None = None) -> HTMLResponse:
    tag = f'\n  <script src="/lti/static/{script}" defer></script>' if script else ""
    return HTMLResponse(
        f'<!doctype html>\n<html lang="de">\n<head>\n  <meta charset="utf-8">\n'
        f'  <meta name="viewport" content="width=device-width, initial-scale=1">\n'
        f'  <title>PAL Trainer – {escape(title)}</title>\n  <link rel="icon" href="data:,">\n'
        f'  <link rel="stylesheet" href="/static/app.css">{tag}\n</head>\n<body class="lti">\n'
        f"<header><h1>PAL Trainer</h1></header>\n<main>\n{body}\n</main>\n</body>\n</html>\n",
        status_code=status,
    )


def refused(request: Request, err: launch.LtiRefusal, logged: bool = True) -> HTMLResponse:
    """The page of a refused launch (German first); logged with its code unless `logged` is off."""
    if logged:
        log.warning(
            "lti launch refused",
            extra={"job": f"{err.code}: {err.message_en}", "client": client_address(request)},
        )
    _frame(request, None)
    body = (
        f'<h2>Start aus der Lernplattform abgelehnt</h2>\n<p class="error" data-code="{escape(err.code)}">'
        f'{escape(err.message)}</p>\n<p lang="en"><small>Launch refused: {escape(err.message_en)}</small></p>\n'
        f"<p><small>Code: {escape(err.code)}</small></p>"
    )
    return _html("Start abgelehnt", body, status=err.status)


# --- keys and configuration --------------------------------------------------------------------------


@router.get("/lti/jwks")
def jwks(db: DbSession) -> JSONResponse:
    data = keys.jwks(db)
    db.commit()  # a first key made now is kept
    return JSONResponse(data, headers={"Cache-Control": "public, max-age=300"})


@router.get("/lti/static/{name}")
def static(name: str) -> Response:
    if name not in ("open.js", "autosubmit.js", "close.js"):
        return pages.not_found()
    return FileResponse(STATIC / name, media_type="text/javascript")


@router.get("/lti/config")
def config(request: Request) -> HTMLResponse:
    """The URLs a platform's admin enters (German, English below each)."""
    urls = registration.tool_urls(_base(request))
    rows = [
        ("Tool-URL / Start-URL", "Tool URL", urls["tool_url"]),
        ("Login-URL (OpenID Connect Login initiieren)", "Initiate login URL", urls["login_url"]),
        ("Weiterleitungs-URL(s)", "Redirection URI(s)", urls["redirect_url"]),
        ("Öffentlicher Schlüsselsatz (JWKS-URL)", "Public keyset URL", urls["jwks_url"]),
        ("Deep-Linking-URL (Inhaltsauswahl)", "Content selection URL", urls["deep_linking_url"]),
    ]
    table = "\n".join(
        f'<tr><th>{escape(de)}<br><small lang="en">{escape(en)}</small></th>'
        f"<td><code>{escape(url)}</code></td></tr>"
        for de, en, url in rows
    )
    body = (
        "<h2>LTI 1.3: PAL Trainer in Moodle, ILIAS und anderen Lernplattformen</h2>\n"
        "<p>Diese Adressen trägt die Administration der Lernplattform beim Anlegen des externen Tools ein "
        "(LTI-Version 1.3, Schlüsseltyp: Schlüsselsatz-URL). Anleitung: docs/lti.md.</p>\n"
        f'<table class="lti-config">\n{table}\n</table>\n'
        "<h3>Dynamische Registrierung (Moodle 4.x)</h3>\n"
        "<p>Die Registrierungs-URL mit Code erzeugt die Administration von PAL Trainer: "
        "<code>paltrainer admin lti-registration-url</code> oder "
        "<code>POST /api/v1/admin/lti/registration-url</code>. Ohne gültigen Code wird keine Plattform "
        "registriert; jede URL gilt 7 Tage für eine Registrierung. "
        f"Adresse: <code>{escape(urls['registration_url'])}?code=…</code></p>\n"
        "<h3>Benutzerdefinierte Parameter</h3>\n<p><code>exercise=&lt;Kennung der Aufgabe&gt;</code> oder "
        "<code>assignment=&lt;Nummer der Aufgabenstellung&gt;</code>; mit Deep Linking setzt PAL Trainer sie "
        "selbst.</p>\n"
        '<p lang="en"><small>English: the URLs above go into the platform\'s external tool form (LTI 1.3, '
        "public keyset URL). Dynamic registration needs a registration URL with a code from "
        "<code>paltrainer admin lti-registration-url</code>; each URL is good for one registration.</small></p>"
    )
    _frame(request, None)
    return _html("LTI-Konfiguration", body)


# --- dynamic registration ----------------------------------------------------------------------------


_CODE_REFUSED = launch.LtiRefusal(
    "LTI_REGISTRATION_CODE",
    "Die Registrierungs-URL ist ungültig, abgelaufen oder schon verwendet (jede gilt für "
    "eine Registrierung); bitte bei der Administration von PAL Trainer eine neue erzeugen lassen.",
    "The registration URL is invalid, expired or used already (each is good for one registration); ask PAL "
    "Trainer's admin for a new one.",
    403,
)


@router.get("/lti/register")
async def register(request: Request, db: DbSession, settings: AppSettings) -> HTMLResponse:
    params = request.query_params
    _frame(request, None)
    code = registration.read_code(db, settings, params.get("code"))
    if code is None:
        return refused(request, _CODE_REFUSED)
    openid = params.get("openid_configuration")
    if not openid:  # e.g. the URL opened in a browser to try it: that does not use the code up
        return refused(
            request,
            launch.LtiRefusal(
                "LTI_REGISTRATION_INCOMPLETE",
                "Der Aufruf enthält keine openid_configuration der Plattform.",
                "The request carries no openid_configuration.",
                400,
            ),
        )
    if not registration.use_code(db, code):  # one platform per code; used before the platform is contacted
        return refused(request, _CODE_REFUSED)
    try:
        platform = await registration.dynamic_register(
            db, openid, params.get("registration_token"), _base(request), request.app.state.lti_transport
        )
    except registration.RegistrationError as err:
        return refused(
            request, launch.LtiRefusal("LTI_REGISTRATION_FAILED", err.message, err.message_en, 502)
        )
    body = (
        f"<h2>PAL Trainer ist registriert</h2>\n<p>Plattform: {escape(platform.name)} "
        f"({escape(platform.issuer)}), Client-ID <code>{escape(platform.client_id)}</code>.</p>\n"
        '<p>Dieses Fenster kann geschlossen werden.</p>\n<p lang="en"><small>PAL Trainer is registered; '
        "this window may be closed.</small></p>"
    )
    return _html("Registriert", body, script="close.js")


# --- launch ------------------------------------------------------------------------------------------


@router.api_route("/lti/login", methods=["GET", "POST"])
async def login(request: Request, db: DbSession, settings: AppSettings) -> Response:
    """OIDC third-party login initiation: on to the platform's registered authorization endpoint."""
    # anyone may start a login, and each stores a state: counted per address (not per user: a browser's stale
    # session cookie must not stand in the way of a launch), within the per-address login budget
    limiter: RateLimiter = request.app.state.limiter
    wait = limiter.hit("lti-login", f"ip:{client_address(request)}", settings.rate_lti_login_per_minute)
    if wait:
        page = refused(
            request,
            launch.LtiRefusal(
                "RATE_LIMITED",
                f"Zu viele Starts von dieser Adresse; bitte in {wait} s erneut aus der Lernplattform öffnen.",
                f"Too many launches from this address; open it again from the platform in {wait} s.",
                429,
            ),
            logged=False,
        )  # a flood is not written to the log line by line
        page.headers["Retry-After"] = str(wait)
        return page
    params: dict[str, str] = {k: v for k, v in request.query_params.items()}
    if request.method == "POST":
        form = await request.form()
        params.update({k: v for k, v in form.items() if isinstance(v, str)})
    try:
        target = await run_in_threadpool(launch.begin_login, db, params, _base(request))
    except launch.LtiRefusal as err:
        return refused(request, err)
    return RedirectResponse(target, status_code=302)


@router.post("/lti/launch")
def launch_(
    request: Request,
    db: DbSession,
    id_token: Annotated[str | None, Form()] = None,
    state: Annotated[str | None, Form()] = None,
) -> Response:
    try:
        verified = launch.verify(db, request.app.state.lti_jwks, id_token, state)
        row, ticket = launch.accept(db, verified)
    except launch.LtiRefusal as err:
        db.rollback()
        return refused(request, err)
    platform = verified.platform
    if row.message_type == launch.DEEP_LINKING_REQUEST:
        row.ticket_expires_at = datetime.now(UTC) + timedelta(minutes=DEEP_LINK_TICKET_MINUTES)
        db.commit()
        _frame(request, platform)
        return picker(db, ticket)
    if row.exercise_slug is None:
        _frame(request, platform)
        what = (
            "Lehrkräfte wählen die Aufgabe über »Inhalt auswählen« (Deep Linking) oder den Parameter "
            "<code>exercise=…</code>."
            if row.role != "learner"
            else "Bitte die Lehrkraft fragen."
        )
        return _html(
            "Keine Aufgabe",
            "<h2>Dieser Link ist keiner Aufgabe zugeordnet</h2>\n"
            f'<p>{what}</p>\n<p lang="en"><small>This link names no exercise.</small></p>',
        )
    return RedirectResponse(f"/lti/open?p={platform.id}#ticket={ticket}", status_code=303)


@router.get("/lti/open")
def open_page(request: Request, db: DbSession, p: int | None = None) -> HTMLResponse:
    """Exchanges the ticket (script open.js) and goes on to the exercise."""
    _frame(request, db.get(LtiPlatform, p) if p is not None and 0 < p < 2**31 else None)
    body = (
        '<p id="status" data-missing="Der Start enthält kein Ticket; bitte erneut aus der Lernplattform öffnen." '
        'data-failed="Das Ticket ist abgelaufen oder schon verwendet; bitte erneut aus der Lernplattform '
        'öffnen.">PAL Trainer wird geöffnet …</p>'
    )
    return _html("Wird geöffnet", body, script="open.js")


class TicketIn(BaseModel):
    model_config = ConfigDict(extra="forbid")

    ticket: str = Field(min_length=10, max_length=200)


@router.post("/lti/session")
def session(body: TicketIn, request: Request, db: DbSession, settings: AppSettings) -> JSONResponse:
    """The one-time ticket of a launch → the page's API token (bearer) and where to go."""
    row = launch.redeem(db, body.ticket)
    user = repo.user_by_id(db, row.user_id) if row is not None else None
    if row is None or user is None or row.exercise_slug is None:
        log.warning("lti ticket refused", extra={"client": request.client.host if request.client else "-"})
        raise ApiError("BAD_TOKEN")
    token = make_token(settings.jwt_secret(), user.id, user.role, settings.token_minutes, user.token_version)
    return JSONResponse(
        {"token": token, "next": f"/lti/exercise/{row.exercise_slug}?p={row.platform_id}", "role": row.role}
    )


@router.get("/lti/exercise/{slug}")
def exercise_page(slug: str, request: Request, db: DbSession, p: int | None = None) -> HTMLResponse:
    """The exercise page, framable by the platform `p` (the page's script sends the token from open.js)."""
    _frame(request, db.get(LtiPlatform, p) if p is not None and 0 < p < 2**31 else None)
    if p is None:
        request.state.csp_extra = {}
    return pages.exercise(slug, None)


@router.get("/courses/{course_id}/lti")
def course_page(course_id: int, request: Request, db: DbSession, p: int | None = None) -> HTMLResponse:
    """The instructor's course page inside the platform `p`'s frame (reached from the framed exercise page; the
    page's script sends the token of the URL fragment, the API decides what it shows). Without `p`: not framable."""
    platform = db.get(LtiPlatform, p) if p is not None and 0 < p < 2**31 else None
    if platform is not None:
        _frame(request, platform)
    return pages.course_frame()


# --- deep linking ------------------------------------------------------------------------------------


def _exercises(db: DbSession) -> list[Any]:
    return [e for e in repo.list_exercises(db) if e.document is not None]


def picker(db: DbSession, ticket: str) -> HTMLResponse:
    items = "\n".join(
        f'<li><label><input type="checkbox" name="exercise" value="{escape(e.slug)}"> {escape(e.title_de)} '
        f"<small>({escape(e.slug)}, {escape(e.dialect)})</small></label></li>"
        for e in _exercises(db)
    )
    body = (
        "<h2>Aufgaben für den Kurs auswählen</h2>\n<p>Jede gewählte Aufgabe wird ein eigener Link im Kurs, "
        "mit einer Bewertung von 0 bis 100 Punkten.</p>\n"
        f'<form method="post" action="/lti/deep-link">\n<input type="hidden" name="ticket" '
        f'value="{escape(ticket)}">\n<ul class="lti-picker">\n{items}\n</ul>\n'
        '<button type="submit">Einfügen</button>\n</form>\n'
        '<p lang="en"><small>Pick the exercises to place in the course; each becomes a link with a grade '
        "item of 100 points.</small></p>"
    )
    return _html("Aufgaben auswählen", body)


@router.post("/lti/deep-link")
def deep_link(
    request: Request,
    db: DbSession,
    ticket: Annotated[str, Form(max_length=200)],
    exercise: Annotated[list[str] | None, Form(max_length=500)] = None,
) -> HTMLResponse:
    """The signed LtiDeepLinkingResponse, posted back to the platform by the page (autosubmit.js / button)."""
    row = launch.redeem(db, ticket)
    if (
        row is None
        or row.message_type != launch.DEEP_LINKING_REQUEST
        or row.deep_link_return_url is None
        or row.role == "learner"
    ):
        return refused(
            request,
            launch.LtiRefusal(
                "LTI_BAD_TICKET",
                "Die Auswahl ist abgelaufen oder wurde schon gesendet; bitte erneut aus der "
                "Lernplattform öffnen.",
                "The selection has expired or was sent already.",
                403,
            ),
        )
    platform = db.get(LtiPlatform, row.platform_id)
    assert platform is not None
    wanted = list(dict.fromkeys(exercise or []))
    chosen = [e for e in _exercises(db) if e.slug in wanted]
    chosen.sort(key=lambda e: wanted.index(e.slug))
    token = deep_linking.response_jwt(db, row, platform, chosen, f"{_base(request)}/lti/launch")
    db.commit()
    if not registration.url_ok(row.deep_link_return_url):
        return refused(
            request,
            launch.LtiRefusal(
                "LTI_BAD_DEEP_LINKING",
                "Die Rücksprungadresse der Plattform ist ungültig.",
                "The platform's return URL is invalid.",
            ),
        )
    _frame(request, platform, form_action=[registration.origin(row.deep_link_return_url)])
    body = (
        f'<form id="deep-link-return" method="post" action="{escape(row.deep_link_return_url)}">\n'
        f'<input type="hidden" name="JWT" value="{escape(token)}">\n'
        f"<p>{len(chosen)} Aufgabe(n) ausgewählt.</p>\n"
        '<button type="submit">Zurück zur Lernplattform</button>\n</form>'
    )
    return _html("Auswahl senden", body, script="autosubmit.js")
