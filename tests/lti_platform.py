"""A learning platform for the LTI tests, "playing Moodle": the PyPI package lti1p3platform (an LTI 1.3
platform we did not write) behind a small FastAPI app on 127.0.0.1.

lti1p3platform is a library without an HTTP server: it makes the OIDC login initiation, signs the id_token of
LtiResourceLinkRequest and LtiDeepLinkingRequest (with the AGS, NRPS and deep-linking claims), checks the
tool's deep-linking response, issues client-credentials access tokens (checking the tool's JWT assertion
against the tool's published JWKS) and checks them on its AGS score and NRPS membership services. This module
only routes HTTP requests to it and keeps what the platform received (scores, deep-linked items) in memory
across restarts of the HTTP server, like a platform's database.
"""

from __future__ import annotations

import html
import json
import socket
import threading
import time
import typing as t
from dataclasses import dataclass, field
from typing import Any
from urllib.parse import parse_qs

import jwt
import uvicorn
from cryptography.hazmat.primitives import serialization
from cryptography.hazmat.primitives.asymmetric import rsa
from fastapi import FastAPI, Request
from fastapi.responses import HTMLResponse, JSONResponse, RedirectResponse, Response
from lti1p3platform import exceptions as lti_errors
from lti1p3platform.lineitem import TLineItem
from lti1p3platform.ltiplatform import LTI1P3PlatformConfAbstract
from lti1p3platform.membership import Context
from lti1p3platform.message_launch import LTIAdvantageMessageLaunchAbstract
from lti1p3platform.oidc_login import OIDCLoginAbstract
from lti1p3platform.registration import Registration
from lti1p3platform.request import Request as LtiRequest
from lti1p3platform.request import TRequest
from lti1p3platform.score import TScore, UpdateScoreStatus
from lti1p3platform.service_connector import AssignmentsGradesService, NamesRoleProvisioningService, TPage

ROLE = "http://purl.imsglobal.org/vocab/lis/v2/membership#"
LEARNER = ROLE + "Learner"
INSTRUCTOR = ROLE + "Instructor"
CLIENT_ID = "paltrainer-moodle"
DEPLOYMENT_ID = "1"
CONTEXT_ID = "course-42"


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def rsa_pem_pair() -> tuple[str, str]:
    key = rsa.generate_private_key(public_exponent=65537, key_size=2048)
    private = key.private_bytes(
        serialization.Encoding.PEM, serialization.PrivateFormat.PKCS8, serialization.NoEncryption()
    ).decode()
    public = (
        key.public_key()
        .public_bytes(serialization.Encoding.PEM, serialization.PublicFormat.SubjectPublicKeyInfo)
        .decode()
    )
    return private, public


@dataclass
class Member:
    sub: str
    name: str
    email: str
    roles: list[str]


@dataclass
class PlatformState:
    """What the platform keeps across restarts of its HTTP server: its key, the course, what it received."""

    private_pem: str
    public_pem: str
    members: list[Member] = field(default_factory=list)
    scores: list[tuple[str, dict[str, Any]]] = field(default_factory=list)  # (line item id, score JSON)
    deep_linked: list[dict[str, Any]] = field(default_factory=list)
    lineitems: list[dict[str, Any]] = field(default_factory=list)  # made by the tool (AGS line item service)
    token_requests: int = 0
    tool_jwks: dict[str, Any] | None = (
        None  # the tool's keys as entered by hand; None: fetched from its /lti/jwks
    )

    @classmethod
    def new(cls) -> PlatformState:
        return cls(*rsa_pem_pair())


class MoodleConf(LTI1P3PlatformConfAbstract):
    """The platform's registration of our tool (what a Moodle admin enters under "External tool")."""

    def init_platform_config(self, **kwargs: Any) -> None:
        self.base: str = kwargs["base"]
        self.tool: str = kwargs["tool"]
        self.state: PlatformState = kwargs["state"]

    def get_registration_by_params(self, **kwargs: Any) -> Registration:
        registration = (
            Registration()
            .set_iss(self.base)
            .set_client_id(CLIENT_ID)
            .set_deployment_id(DEPLOYMENT_ID)
            .set_oidc_login_url(f"{self.tool}/lti/login")
            .set_launch_url(f"{self.tool}/lti/launch")
            .set_deeplink_launch_url(f"{self.tool}/lti/launch")
            .set_tool_key_set_url(f"{self.tool}/lti/jwks")
            .set_platform_public_key(self.state.public_pem)
            .set_platform_private_key(self.state.private_pem)
        )
        if self.state.tool_jwks is not None:
            registration.set_tool_key_set(t.cast(Any, self.state.tool_jwks))
        return registration


class Login(OIDCLoginAbstract):
    def set_lti_message_hint(self, **kwargs: Any) -> None:
        self._lti_message_hint = json.dumps(kwargs)

    def get_redirect(self, url: str) -> RedirectResponse:
        return RedirectResponse(url, status_code=302)


class Launch(LTIAdvantageMessageLaunchAbstract):
    def __init__(self, query: dict[str, Any], conf: MoodleConf) -> None:
        super().__init__(t.cast(LtiRequest, None), conf)
        self._query = query

    def get_preflight_response(self) -> dict[str, Any]:
        return self._query

    def render_launch_form(self, launch_data: dict[str, Any], **kwargs: Any) -> HTMLResponse:
        # the auto-submitting form a browser posts to the tool (the test reads its fields)
        fields = "".join(
            f'<input type="hidden" name="{k}" value="{html.escape(str(launch_data[k]))}">'
            for k in ("id_token", "state")
        )
        return HTMLResponse(
            f'<form method="post" action="{html.escape(str(launch_data["launch_url"]))}">{fields}</form>'
        )


class PlainRequest(LtiRequest):
    def build_metadata(self, request: Any) -> TRequest:
        return t.cast(TRequest, request)


class Grades(AssignmentsGradesService):
    def __init__(self, request: LtiRequest, conf: MoodleConf, base: str, state: PlatformState) -> None:
        super().__init__(request, conf, f"{base}/lineitems", None)
        self.state = state

    def update_score(self, line_item_id: str, score: TScore) -> UpdateScoreStatus:
        self.state.scores.append((line_item_id, dict(score)))
        return UpdateScoreStatus.SUCCESS

    def find_lineitems(
        self,
        page: int = 1,
        limit: int | None = None,
        line_item_id: str | None = None,
        resource_link_id: str | None = None,
        resource_id: str | None = None,
        tag: str | None = None,
    ) -> TPage:
        items = [i for i in self.state.lineitems if resource_link_id in (None, i.get("resourceLinkId"))]
        return {"content": items, "has_next": False, "next": None}

    def find_lineitem(self, line_item_id: str) -> TLineItem:
        return {"id": line_item_id, "scoreMaximum": 100}

    def create_lineitem(self, creation_data: TLineItem) -> TLineItem:
        item = t.cast(
            TLineItem,
            {
                **creation_data,
                "id": f"{self.ags.lineitems_url}/made-{len(self.state.lineitems) + 1}/lineitem",
            },
        )
        self.state.lineitems.append(dict(item))
        return item

    def update_lineitem(self, update_data: TLineItem) -> TLineItem:
        return update_data

    def delete_lineitem(self, line_item_id: str) -> None:
        return None

    def get_results(
        self, line_item_id: str, page: int = 1, limit: int | None = None, user_id: str | None = None
    ) -> TPage:
        return {"content": [], "has_next": False, "next": None}


class Roster(NamesRoleProvisioningService):
    def __init__(self, request: LtiRequest, conf: MoodleConf, url: str, state: PlatformState) -> None:
        super().__init__(request, conf, url)
        self.state = state

    def get_member_data_page(
        self, page: int = 1, limit: int | None = None, role: str | None = None, since: str | None = None
    ) -> TPage:
        members = [
            {"user_id": m.sub, "name": m.name, "email": m.email, "roles": m.roles, "status": "Active"}
            for m in self.state.members
        ]
        return {"content": members, "has_next": False, "next": None}

    def get_context_by_id(self) -> Context:
        return Context(id=CONTEXT_ID, label="FT-2A", title="Fertigungstechnik 2A")


def _answer(resp: Any) -> Response:
    if resp.code >= 400:
        return JSONResponse({"error": resp.message}, status_code=resp.code)
    if resp.result is None:
        return Response(status_code=resp.code)
    return JSONResponse(resp.result, status_code=resp.code, media_type=resp.media_type)


def platform_app(base: str, tool: str, state: PlatformState) -> FastAPI:
    """The platform's HTTP side: start a launch, the OIDC authorization endpoint, JWKS, token, AGS, NRPS."""
    app = FastAPI()

    def conf() -> MoodleConf:
        return MoodleConf(base=base, tool=tool, state=state)

    def service_request(request: Request, body: Any) -> LtiRequest:
        return PlainRequest(
            {
                "method": request.method,
                "form_data": {},
                "get_data": dict(request.query_params),
                "headers": request.headers,
                "content_type": request.headers.get("content-type"),
                "path": request.url.path,
                "json": body,
            }
        )

    @app.get("/jwks")
    def jwks() -> dict[str, Any]:
        c = conf()
        c.get_registration()
        return dict(c.get_jwks())

    @app.get("/start")
    def start(
        user: str, kind: str = "resource", link: str = "link-1", exercise: str = "", lineitem: str = "li-1"
    ) -> Response:
        """A user clicks the tool's link in the course (kind "resource") or the teacher adds content ("deeplink")."""
        c = conf()
        login = Login(None, c)
        login.set_lti_message_hint(kind=kind, link=link, exercise=exercise, lineitem=lineitem)
        if kind == "deeplink":
            login.set_deeplinking_launch_url()
        return t.cast(Response, login.initiate_login(user))

    @app.get("/auth")
    def auth(request: Request) -> Response:
        """The OIDC authorization endpoint: the tool's authentication request, answered with the id_token."""
        query = dict(request.query_params)
        hint = json.loads(query.get("lti_message_hint", "{}"))
        member = next((m for m in state.members if m.sub == query.get("login_hint")), None)
        if member is None:
            return JSONResponse({"error": "unknown user"}, status_code=400)
        launch = Launch(query, conf())
        launch.set_user_data(member.sub, member.roles, full_name=member.name, email_address=member.email)
        launch.set_launch_context_claim(
            CONTEXT_ID, context_title="Fertigungstechnik 2A", context_label="FT-2A"
        )
        launch.set_nrps(f"{base}/contexts/{CONTEXT_ID}/memberships")
        if hint.get("kind") == "deeplink":
            launch.set_dl(f"{base}/deep_link_return", title="PAL Trainer", accept_types={"ltiResourceLink"})
        else:
            launch.set_resource_link_claim(hint["link"], title="PAL-Aufgabe")
            if hint.get("exercise"):
                launch.set_custom_parameters_claim({"exercise": hint["exercise"]})
            if hint.get("lineitem"):
                launch.set_ags(
                    f"{base}/lineitems",
                    f"{base}/lineitems/{hint['lineitem']}/lineitem",
                    allow_creating_lineitems=False,
                )
            else:  # a link without a grade item: the tool may make one (scope lineitem)
                launch.set_ags(f"{base}/lineitems", None, allow_creating_lineitems=True)
        try:
            return t.cast(Response, launch.lti_launch())
        except lti_errors.PreflightRequestValidationException as err:  # wrong client id, no nonce …
            return JSONResponse({"error": type(err).__name__}, status_code=400)

    @app.post("/token")
    async def token(request: Request) -> Response:
        form = {k: v[0] for k, v in parse_qs((await request.body()).decode()).items()}
        state.token_requests += 1
        c = conf()
        c.get_registration()
        try:
            return JSONResponse(dict(c.get_access_token(form)))
        except (lti_errors.MissingRequiredClaim, lti_errors.UnsupportedGrantType, KeyError) as err:
            return JSONResponse({"error": "invalid_request", "detail": type(err).__name__}, status_code=400)
        except (lti_errors.LtiException, jwt.PyJWTError) as err:  # unknown kid, bad signature, expired
            return JSONResponse({"error": "invalid_client", "detail": type(err).__name__}, status_code=401)

    @app.post("/lineitems/{item}/lineitem/scores")
    async def scores(item: str, request: Request) -> Response:
        if request.headers.get("content-type") != "application/vnd.ims.lis.v1.score+json":
            return JSONResponse({"error": "wrong media type"}, status_code=415)
        c = conf()
        c.get_registration()
        service = Grades(service_request(request, await request.json()), c, base, state)
        try:
            return _answer(service.handle_resp(service.handle_update_score, line_item_id=item))
        except jwt.PyJWTError as err:  # a token the platform did not sign, or expired
            return JSONResponse({"error": type(err).__name__}, status_code=401)

    @app.api_route("/lineitems", methods=["GET", "POST"])
    async def lineitems(request: Request) -> Response:
        c = conf()
        c.get_registration()
        body = await request.json() if request.method == "POST" else None
        service = Grades(service_request(request, body), c, base, state)
        handler = service.handle_create_lineitem if request.method == "POST" else service.handle_get_lineitems
        try:
            resp = service.handle_resp(handler)
        except jwt.PyJWTError as err:
            return JSONResponse({"error": type(err).__name__}, status_code=401)
        if request.method == "GET" and resp.code == 200:  # the spec's answer is the array of line items
            return JSONResponse(resp.result["content"], media_type=resp.media_type)
        return _answer(resp)

    @app.get("/contexts/{context}/memberships")
    def memberships(context: str, request: Request) -> Response:
        c = conf()
        c.get_registration()
        service = Roster(service_request(request, None), c, str(request.url).split("?")[0], state)
        try:
            return _answer(service.handle_resp(service.handle_get_members))
        except jwt.PyJWTError as err:
            return JSONResponse({"error": type(err).__name__}, status_code=401)

    @app.post("/deep_link_return")
    async def deep_link_return(request: Request) -> Response:
        form = {k: v[0] for k, v in parse_qs((await request.body()).decode()).items()}
        c = conf()
        c.get_registration()
        items = c.validate_deeplinking_resp({"JWT": form["JWT"]})
        state.deep_linked.extend(items)
        return JSONResponse({"items": len(items)})

    return app


class Served:
    """An ASGI app served by uvicorn in a thread on 127.0.0.1:`port`; stop() and start() again on the same port."""

    def __init__(self, app: Any, port: int) -> None:
        self.app = app
        self.port = port
        self.url = f"http://127.0.0.1:{port}"
        self._server: uvicorn.Server | None = None
        self._thread: threading.Thread | None = None

    def start(self) -> Served:
        config = uvicorn.Config(
            self.app, host="127.0.0.1", port=self.port, log_level="warning", lifespan="on"
        )
        self._server = uvicorn.Server(config)
        self._thread = threading.Thread(target=self._server.run, daemon=True)
        self._thread.start()
        deadline = time.monotonic() + 60
        while not self._server.started:
            if not self._thread.is_alive() or time.monotonic() > deadline:
                raise RuntimeError(f"the server on port {self.port} did not start")
            time.sleep(0.05)
        return self

    def stop(self) -> None:
        if self._server is not None and self._thread is not None:
            self._server.should_exit = True
            self._thread.join(timeout=30)
        self._server = None
        self._thread = None
