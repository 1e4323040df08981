"""An LTI 1.3 launch in a real browser: a stand-in platform on another site (http://localhost:<port>) frames
PAL Trainer (http://127.0.0.1:<port>); the OIDC login, the platform's form post of the id_token, the ticket
exchange and the exercise page all run inside the iframe, under our Content-Security-Policy, with no cookie and
no storage: the page's API calls carry the bearer token handed over in the URL fragment."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import threading
import time
from collections.abc import Iterator
from html import escape
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from pathlib import Path
from typing import Any, ClassVar
from urllib.parse import parse_qs, urlencode, urlsplit

import jwt
import pytest
from browser_helpers import NEEDS_CHROMIUM, ROOT, running_server
from cryptography.hazmat.primitives.asymmetric import rsa
from jwt.algorithms import RSAAlgorithm

pytestmark = [NEEDS_CHROMIUM]
LTI = "https://purl.imsglobal.org/spec/lti/claim/"
KEY = rsa.generate_private_key(public_exponent=65537, key_size=2048)
JWK = {**json.loads(RSAAlgorithm.to_jwk(KEY.public_key())), "kid": "platform-1", "alg": "RS256", "use": "sig"}


class Platform(BaseHTTPRequestHandler):
    """The platform: a course page framing the tool, its OIDC authorization endpoint, its JWKS."""

    issuer = ""
    tool = ""
    returned: ClassVar[list[str]] = []  # the deep-linking answers (JWT) posted back to the platform

    def log_message(self, *args: Any) -> None:
        pass

    def _send(self, body: str, kind: str = "text/html; charset=utf-8") -> None:
        data = body.encode("utf-8")
        self.send_response(200)
        self.send_header("Content-Type", kind)
        self.send_header("Content-Length", str(len(data)))
        self.end_headers()
        self.wfile.write(data)

    def do_GET(self) -> None:
        url = urlsplit(self.path)
        query = {k: v[0] for k, v in parse_qs(url.query).items()}
        if url.path == "/jwks":
            self._send(json.dumps({"keys": [JWK]}), "application/json")
        elif url.path == "/course":
            login = (
                self.tool
                + "/lti/login?"
                + urlencode(
                    {
                        "iss": self.issuer,
                        "login_hint": query.get("who", "u-7"),
                        "target_link_uri": self.tool + "/lti/launch",
                        "client_id": "browser-client",
                        "lti_deployment_id": "d-1",
                    }
                )
            )
            self._send(
                f'<!doctype html><title>Kurs</title><iframe id="tool" src="{escape(login)}" '
                'width="1200" height="900"></iframe>'
            )
        elif url.path == "/auth":
            now = int(time.time())
            claims = {
                "iss": self.issuer,
                "aud": query["client_id"],
                "sub": query["login_hint"],
                "iat": now,
                "exp": now + 300,
                "nonce": query["nonce"],
                "name": "Lena Lernend",
                LTI + "message_type": "LtiResourceLinkRequest",
                LTI + "version": "1.3.0",
                LTI + "deployment_id": "d-1",
                LTI + "target_link_uri": query["redirect_uri"],
                LTI + "roles": ["http://purl.imsglobal.org/vocab/lis/v2/membership#Learner"],
                LTI + "context": {"id": "c-1", "title": "Fachklasse"},
                LTI + "resource_link": {"id": "rl-1"},
                LTI + "custom": {"exercise": "pal-01-g1-gerade"},
            }
            if query["login_hint"] == "teacher":  # content selection (deep linking) by an instructor
                claims.update(
                    {
                        LTI + "message_type": "LtiDeepLinkingRequest",
                        LTI + "roles": ["http://purl.imsglobal.org/vocab/lis/v2/membership#Instructor"],
                        "https://purl.imsglobal.org/spec/lti-dl/claim/deep_linking_settings": {
                            "deep_link_return_url": f"{self.issuer}/return",
                            "accept_types": ["ltiResourceLink"],
                            "accept_multiple": True,
                            "data": "d-42",
                        },
                    }
                )
            token = jwt.encode(claims, KEY, algorithm="RS256", headers={"kid": "platform-1"})
            self._send(
                f'<!doctype html><form method="post" action="{escape(query["redirect_uri"])}">'
                f'<input type="hidden" name="id_token" value="{escape(token)}">'
                f'<input type="hidden" name="state" value="{escape(query["state"])}"></form>'
                "<script>document.forms[0].submit()</script>"
            )
        else:
            self.send_error(404)

    def do_POST(self) -> None:
        body = self.rfile.read(int(self.headers.get("Content-Length", "0"))).decode("utf-8")
        if urlsplit(self.path).path == "/return":
            Platform.returned.append(parse_qs(body)["JWT"][0])
            self._send("<!doctype html><p id='done'>Inhalt übernommen</p>")
        else:
            self.send_error(404)


@pytest.fixture(scope="module")
def platform_and_tool(tmp_path_factory: pytest.TempPathFactory) -> Iterator[tuple[str, str]]:
    httpd = ThreadingHTTPServer(("127.0.0.1", 0), Platform)
    issuer = f"http://localhost:{httpd.server_address[1]}"
    Platform.issuer = issuer
    threading.Thread(target=httpd.serve_forever, daemon=True).start()
    data: Path = tmp_path_factory.mktemp("lti-browser")
    env = {
        **os.environ,
        "PALTRAINER_DATA_DIR": str(data),
        "PALTRAINER_EXERCISES_DIR": str(ROOT / "exercises"),
    }
    subprocess.run(
        [
            sys.executable,
            "-m",
            "core.cli",
            "admin",
            "lti-register",
            "--issuer",
            issuer,
            "--client-id",
            "browser-client",
            "--deployment",
            "d-1",
            "--auth-url",
            f"{issuer}/auth",
            "--token-url",
            f"{issuer}/token",
            "--jwks-url",
            f"{issuer}/jwks",
        ],
        cwd=ROOT,
        env=env,
        check=True,
        capture_output=True,
    )
    try:
        with running_server(data) as tool:
            Platform.tool = tool
            yield issuer, tool
    finally:
        httpd.shutdown()


def test_learner_launch_opens_the_exercise_inside_the_platform_frame(
    browser: Any, platform_and_tool: tuple[str, str]
) -> None:
    issuer, tool = platform_and_tool
    context = browser.new_context()
    page = context.new_page()
    csp: list[str] = []
    page.on("console", lambda m: csp.append(m.text) if "Content Security Policy" in m.text else None)
    refused: list[str] = []
    page.on("pageerror", lambda e: refused.append(f"page error: {e}"))
    page.on(
        "response",
        lambda r: (
            refused.append(f"{r.status} {r.url}") if r.status >= 400 and r.url.startswith(tool) else None
        ),
    )
    page.goto(f"{issuer}/course")
    page.frame_locator("#tool").locator("#title").wait_for(timeout=30000)
    tool_frame = next(f for f in page.frames if f.url.startswith(f"{tool}/lti/exercise/pal-01-g1-gerade"))
    # the page's script has run (the title is the exercise's, no longer the page's placeholder "Aufgabe"): its
    # requests carry the token from here on
    tool_frame.wait_for_function(
        "() => { const t = document.getElementById('title').textContent.trim(); return t && t !== 'Aufgabe'; }",
        timeout=30000,
    )
    answer = tool_frame.evaluate(
        "fetch('/api/v1/me').then(async r => ({status: r.status, body: await r.text()}))"
    )
    assert answer["status"] == 200, answer  # (the error's code and message, if not)
    me = json.loads(answer["body"])
    assert me["role"] == "student" and me["username"].startswith("lti")
    # no cookie was needed (the tool set none): the token came in the URL fragment, which no server sees
    assert not [c for c in context.cookies() if c["domain"] in ("127.0.0.1", "localhost")]
    assert "#token=" in tool_frame.url
    # the frame shows the exercise alone: no links to pages that would need a login of their own
    assert tool_frame.locator("header nav a").count() == 0
    assert tool_frame.locator("#lang").is_visible()
    # the drawing (an <img> of the API) came with the token too
    tool_frame.wait_for_function(
        "() => [...document.images].some(i => i.src.startsWith('blob:') && i.complete && i.naturalWidth > 0)",
        timeout=30000,
    )
    assert csp == [], csp
    assert refused == [], refused  # nothing was refused for want of a cookie, no script failed
    context.close()


def test_deep_linking_answer_goes_back_to_the_platform_without_inline_script(
    browser: Any, platform_and_tool: tuple[str, str]
) -> None:
    issuer, _ = platform_and_tool
    context = browser.new_context()
    page = context.new_page()
    csp: list[str] = []
    page.on("console", lambda m: csp.append(m.text) if "Content Security Policy" in m.text else None)
    page.goto(f"{issuer}/course?who=teacher")
    picker = page.frame_locator("#tool")
    picker.locator("input[value='pal-01-g1-gerade']").check(timeout=30000)
    picker.locator("input[value='pal-02-g1-rn-radius']").check()
    picker.locator("button[type=submit]").click()
    # autosubmit.js (a file of ours, no inline script) posts the signed answer to the platform
    picker.locator("#done").wait_for(timeout=30000)
    assert len(Platform.returned) == 1
    claims = jwt.decode(Platform.returned[0], options={"verify_signature": False})
    items = claims["https://purl.imsglobal.org/spec/lti-dl/claim/content_items"]
    assert [i["custom"]["exercise"] for i in items] == ["pal-01-g1-gerade", "pal-02-g1-rn-radius"]
    assert claims["https://purl.imsglobal.org/spec/lti-dl/claim/data"] == "d-42"
    assert csp == [], csp
    context.close()
