"""ASGI middleware: request id and request log, and the body-size limit (413 before the body is read whole)."""

from __future__ import annotations

import contextlib
import json
import logging
import time
import uuid
from typing import Any

from starlette.requests import ClientDisconnect
from starlette.types import ASGIApp, Message, Receive, Scope, Send

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
            if length is not None and length.isdigit() and int(length) > self.max_body:
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
            log.info("request", extra={
                "request_id": request_id, "method": scope["method"], "path": scope["path"], "status": status,
                "duration_ms": round((time.perf_counter() - started) * 1000, 2),
                "principal": state.get("principal", "-"),
                "client": scope["client"][0] if scope.get("client") else "-"})

    async def _reject(self, size: int, send: Send) -> None:
        err = ApiError("BODY_TOO_LARGE", size=size, limit=self.max_body)
        body = json.dumps(err.body(), ensure_ascii=False).encode("utf-8")
        await send({"type": "http.response.start", "status": 413,
                    "headers": [(b"content-type", b"application/json"), (b"content-length", str(len(body)).encode())]})
        await send({"type": "http.response.body", "body": body})
