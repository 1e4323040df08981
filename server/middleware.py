"""ASGI middleware: request id and request log, the body-size limit (413 before the body is read whole), and
the security headers of every response (Content-Security-Policy, nosniff, Referrer-Policy)."""

from __future__ import annotations

import base64
import contextlib
import functools
import hashlib
import json
import logging
import re
import time
import uuid
from typing import Any

import numpy as np
import zstandard
from starlette.requests import ClientDisconnect
from starlette.types import ASGIApp, Message, Receive, Scope, Send

from server import viz
from server.config import Settings
from server.errors import ApiError

log = logging.getLogger("paltrainer.server")


class RequestMiddleware:
    """Gives every HTTP request an id (X-Request-ID), logs it, and answers 413 for bodies over the limit."""

    def __init__(self, app: ASGIApp, max_body_bytes: int) -> None:
        self.app, self.max_body = app, max_body_bytes

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] != "http":
            await self.app(scope, receive, send)
            return
        headers = dict(scope.get("headers") or [])
        given = headers.get(b"x-request-id", b"").decode("latin-1")
        request_id = given if 0 < len(given) <= 64 and given.isprintable() else uuid.uuid4().hex
        scope.setdefault("state", {})["request_id"] = request_id
        started, status = time.perf_counter(), 500
        response_started = False

        async def send_with_id(message: Message) -> None:
            nonlocal status, response_started
            if message["type"] == "http.response.start":
                response_started = True
                status = message["status"]
                message["headers"] = [*message.get("headers", []), (b"x-request-id", request_id.encode())]
            await send(message)

        length = headers.get(b"content-length")
        rejected = False

        async def guarded_send(message: Message) -> None:
            if not rejected:
                await send_with_id(message)

        try:
            if length is not None and length.isascii() and length.isdigit() and int(length) > self.max_body:
                await self._reject(int(length), send_with_id)
                return
            seen = 0

            async def limited_receive() -> Message:
                nonlocal seen, rejected
                if rejected:
                    return {"type": "http.disconnect"}
                message = await receive()
                if message["type"] == "http.request":
                    seen += len(message.get("body", b""))
                    if seen > self.max_body:
                        rejected = True
                        if not response_started:
                            await self._reject(seen, send_with_id)
                        return {"type": "http.disconnect"}
                return message

            with contextlib.suppress(ClientDisconnect):
                await self.app(scope, limited_receive, guarded_send)
        finally:
            state: dict[str, Any] = scope.get("state", {})
            log.info(
                "request",
                extra={
                    "request_id": request_id,
                    "method": scope["method"],
                    "path": scope["path"],
                    "status": status,
                    "duration_ms": round((time.perf_counter() - started) * 1000, 2),
                    "principal": state.get("principal", "-"),
                    "client": scope["client"][0] if scope.get("client") else "-",
                },
            )

    async def _reject(self, size: int, send: Send) -> None:
        err = ApiError("BODY_TOO_LARGE", size=size, limit=self.max_body)
        body = json.dumps(err.body(), ensure_ascii=False).encode("utf-8")
        await send(
            {
                "type": "http.response.start",
                "status": 413,
                "headers": [
                    (b"content-type", b"application/json"),
                    (b"content-length", str(len(body)).encode()),
                ],
            }
        )
        await send({"type": "http.response.body", "body": body})


# The Content-Security-Policy: scripts only from files of this site (no inline script, no eval), nothing
# plugged in, forms and the page's base URL kept here, and framing only by this site and the learning
# platforms in the setting `frame_ancestors`. Styles may be inline: CodeMirror and the 3D view set them.
_BASE_POLICY = {
    "default-src": ["'self'"],
    "script-src": ["'self'"],
    "style-src": ["'self'", "'unsafe-inline'"],
    "img-src": ["'self'", "data:", "blob:"],
    "font-src": ["'self'", "data:"],
    "connect-src": ["'self'"],
    "frame-src": ["'self'"],
    "worker-src": ["'self'"],
    "object-src": ["'none'"],
    "base-uri": ["'none'"],
    "form-action": ["'self'"],
}


def _script_hash(text: str) -> str:
    return "'sha256-" + base64.b64encode(hashlib.sha256(text.encode("utf-8")).digest()).decode("ascii") + "'"


_VISER_DIGITS = "!#$%()*+,-./0123456789:;=?@ABCDEFGHIJKLMNOPQRSTUVWXYZ[\\]^_abcdefghijklmnopqrstuvwxyz{|}~"


def _viser_payload(text: str) -> bytes:
    """Decode the page's `data-p` (base 88: five characters for four bytes, as the page's own loader does)."""
    digits = np.zeros(128, dtype=np.uint64)
    digits[[ord(c) for c in _VISER_DIGITS]] = np.arange(len(_VISER_DIGITS), dtype=np.uint64)
    whole = len(text) - len(text) % 5
    groups = digits[np.frombuffer(text[:whole].encode("ascii"), dtype=np.uint8)].reshape(-1, 5)
    values = np.zeros(len(groups), dtype=np.uint64)
    for column in range(5):
        values = values * 88 + groups[:, column]
    out = values.astype(">u4").tobytes()
    if len(text) > whole:
        rest = 0
        for c in text[whole:]:
            rest = rest * 88 + _VISER_DIGITS.index(c)
        out += rest.to_bytes(len(text) - whole - 1, "big")
    return out


@functools.cache
def viser_script_hashes() -> tuple[str, ...]:
    """The hashes of the two scripts viser's client page runs: its inline loader, and the application the
    loader unpacks (zstd in a base-88 attribute) and inserts as an inline module script. Allowing exactly
    these two keeps `script-src` free of 'unsafe-inline' on /viz/; they are computed from the installed
    viser, so an upgrade keeps working (tests/browser/test_login_redirect.py runs the page under the policy)."""
    hashes = []
    try:
        html = viz.viser_page().decode("utf-8")
        for attrs, body in re.findall(
            r"<script\b([^>]*)>(.*?)</script>", html, flags=re.DOTALL | re.IGNORECASE
        ):
            if body.strip():
                hashes.append(_script_hash(body))
            packed = dict(re.findall(r'data-(p|ss|cs)="([^"]*)"', attrs))
            if {"p", "ss", "cs"} <= packed.keys():
                style, code = int(packed["ss"]), int(packed["cs"])
                raw = zstandard.ZstdDecompressor().decompress(
                    _viser_payload(packed["p"]), max_output_size=style + code
                )
                # the loader decodes with TextDecoder, which drops a byte-order mark and replaces bad bytes
                hashes.append(_script_hash(raw[style : style + code].decode("utf-8-sig", errors="replace")))
    except (OSError, ValueError, KeyError, zstandard.ZstdError):
        # a viser whose page is packed differently: its scripts stay blocked (the 3D view stays empty)
        # rather than the policy allowing inline script
        log.exception("3D view: the scripts of viser's page could not be read; they stay blocked")
    return tuple(hashes)


def content_security_policy(
    path: str, frame_ancestors: list[str], extra: dict[str, list[str]] | None = None
) -> str:
    """`extra` (a route's request.state.csp_extra): "frame-ancestors" replaces the setting's origins for this
    response (an LTI page: its platform only), other directives are added to (a form posted to a platform)."""
    policy = {k: list(v) for k, v in _BASE_POLICY.items()}
    extra = extra or {}
    if "frame-ancestors" in extra:
        frame_ancestors = extra["frame-ancestors"]
    if path.startswith("/viz/") and path.endswith("/"):
        # viser's client page (see viser_script_hashes): its two scripts by hash, its decoders are
        # WebAssembly (one fetched from a data: URL), its mesh decoders run in workers made from blob: URLs
        policy["script-src"] += [*viser_script_hashes(), "'wasm-unsafe-eval'"]
        policy["connect-src"] += ["data:"]
        policy["worker-src"] += ["blob:"]
    # an origin is one token: a value with a space, ";" or "," could add directives of its own
    policy["frame-ancestors"] = ["'self'", *(o for o in frame_ancestors if re.fullmatch(r"[^\s;,']+", o))]
    for name, values in extra.items():
        if name != "frame-ancestors" and name in policy:
            policy[name] += [v for v in values if re.fullmatch(r"[^\s;,']+", v)]
    return "; ".join(f"{name} {' '.join(values)}" for name, values in policy.items())


class SecurityHeadersMiddleware:
    """Adds the Content-Security-Policy, X-Content-Type-Options and Referrer-Policy to every HTTP response."""

    def __init__(self, app: ASGIApp, settings: Settings) -> None:
        self.app, self.settings = app, settings

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] != "http":
            await self.app(scope, receive, send)
            return
        csp = content_security_policy(scope["path"], self.settings.frame_ancestors).encode("latin-1")

        async def send_with_headers(message: Message) -> None:
            if message["type"] == "http.response.start":
                extra = scope.get("state", {}).get("csp_extra")  # set by the route (server/routes/lti.py)
                policy = (
                    csp
                    if extra is None
                    else content_security_policy(scope["path"], self.settings.frame_ancestors, extra).encode(
                        "latin-1"
                    )
                )
                message["headers"] = [
                    *message.get("headers", []),
                    (b"content-security-policy", policy),
                    (b"x-content-type-options", b"nosniff"),
                    (b"referrer-policy", b"same-origin"),
                ]
            await send(message)

        await self.app(scope, receive, send_with_headers)
