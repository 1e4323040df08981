"""WebSocket /api/v1/live: live per-block diagnostics and toolpath while a program is typed.

Protocol (JSON text frames; `version` is the client's document version, strictly increasing):

client → server
  {"type": "open", "version": 0, "text": "...", "dialect": "pal-mill", "exercise": null,
   "tools": [{"number": 1, "diameter": 25}], "skip_blocks": false}
  {"type": "edit", "version": 5, "line": 3, "text": "N30 G1 X10"}            replace line 3
  {"type": "edit", "version": 6, "line": 4, "end_line": 3, "text": "N35 G0 Z2"}  insert before line 4
  {"type": "edit", "version": 7, "line": 4, "end_line": 5, "text": ""}       lines 4–5 become one empty line
  {"type": "sync", "version": 8, "text": "..."}                              the whole text again

  An edit replaces lines `line`…`end_line` (default: `line`) with the lines of `text`; `line` may be
  one past the last line (append).

server → client
  {"type": "update", "version": 7, "line_count": 40,
   "diagnostics": [{"line": 3, "items": [<diagnostic>, ...]}, {"line": 40, "items": []}],
   "toolpath": [{"line": 3, "moves": [...], "dwells": [...], "tool_changes": [...]}],
   "final": [x, y, z]}
     Only the lines whose diagnostics or toolpath differ from the previous update are listed; an empty
     list clears a line. The first update after open lists every line that has something.
  {"type": "error", "version": 7, "code": "STALE_VERSION", "message": "...", "message_en": "..."}

The document is re-run in a worker process after each change. Edits that arrive while a run is in
progress are applied to the document, and the next run takes them all at once: every run is of
the newest document the server has, and every run is answered, so under load an update may answer
several keystrokes and may be older than the client's newest version. Each update lists the changes
since the previous update and describes the document at its `version`: a client that has typed
since either maps the line numbers through its later edits or drops the update (the next follows).
Updates of one connection come in version order.
"""

from __future__ import annotations

import asyncio
import contextlib
import json
import logging
import uuid
from dataclasses import dataclass, field
from typing import Annotated, Any

from fastapi import APIRouter, WebSocket, WebSocketDisconnect
from pydantic import Field, TypeAdapter, ValidationError
from starlette.concurrency import run_in_threadpool

from server import repository as repo
from server.config import Settings
from server.db import Database
from server.deps import ANONYMOUS, SESSION_COOKIE, Principal, resolve
from server.errors import ApiError
from server.schemas import ToolSpec
from server.services import check_program, exercise_spec
from server.workers import Workers, job_live, job_live_close

router = APIRouter()
log = logging.getLogger("paltrainer.server")
TOOL_LIST = TypeAdapter(Annotated[list[ToolSpec], Field(max_length=99)])

LIVE_ERRORS: dict[str, tuple[str, str]] = {
    "BAD_MESSAGE": ("Ungültige Nachricht: {detail}", "Invalid message: {detail}"),
    "NOT_OPEN": ("Zuerst ein Dokument öffnen (open).", "Open a document first (open)."),
    "STALE_VERSION": ("Version {version} ist nicht neuer als {current}; die Änderung wird ignoriert.",
                      "Version {version} is not newer than {current}; the change is ignored."),
    "BAD_LINE": ("Zeile {line} gibt es nicht (das Dokument hat {count} Zeilen).",
                 "Line {line} does not exist (the document has {count} lines)."),
    "TOO_MANY_LINES": ("Das Dokument hat zu viele Zeilen (höchstens {limit}).",
                       "The document has too many lines (at most {limit})."),
}


class LiveError(Exception):
    def __init__(self, code: str, **params: Any) -> None:
        super().__init__(code)
        self.code, self.params = code, params


@dataclass
class Document:
    lines: list[str] = field(default_factory=list)
    version: int = -1
    dialect: str = ""
    spec: dict[str, Any] = field(default_factory=dict)

    @property
    def text(self) -> str:
        return "\n".join(self.lines) + "\n"

    def replace(self, first: int, last: int, text: str) -> None:
        count = len(self.lines)
        if not 1 <= first <= count + 1 or not first - 1 <= last <= count:
            raise LiveError("BAD_LINE", line=first if not 1 <= first <= count + 1 else last, count=count)
        self.lines[first - 1:last] = text.split("\n")


def split_lines(text: str) -> list[str]:
    lines = text.split("\n")
    if len(lines) > 1 and lines[-1] == "":
        lines.pop()
    return lines


class LiveSession:
    """One editor connection: the document, the last result sent, and the task that re-runs it."""

    def __init__(self, ws: WebSocket, settings: Settings, database: Database, workers: Workers) -> None:
        self.ws, self.settings, self.database, self.workers = ws, settings, database, workers
        self.doc: Document | None = None
        self.doc_id = ""
        self.slot = 0
        self.gen = 0  # generation of the last result applied below (0: none)
        # the newest result, per line, and what the client has been sent, per line
        self.current: dict[str, dict[int, Any]] = {"diagnostics": {}, "toolpath": {}}
        self.sent: dict[str, dict[int, Any]] = {"diagnostics": {}, "toolpath": {}}
        self.dirty: set[int] = set()
        self.changed = asyncio.Event()
        self._send_lock = asyncio.Lock()

    async def send(self, payload: dict[str, Any]) -> None:
        async with self._send_lock:
            await self.ws.send_text(json.dumps(payload, ensure_ascii=False))

    async def send_error(self, code: str, at_version: int | None, **params: Any) -> None:
        if code in LIVE_ERRORS:
            de, en = LIVE_ERRORS[code]
            message, message_en = de.format(**params), en.format(**params)
        else:
            err = ApiError(code, **params)
            message, message_en = err.message, err.message_en
        await self.send({"type": "error", "version": at_version, "code": code, "message": message,
                         "message_en": message_en})

    def _open_spec(self, msg: dict[str, Any]) -> tuple[str, dict[str, Any]]:
        with self.database.session() as db:
            slug = msg.get("exercise")
            if slug is not None:
                exercise = repo.exercise_by_slug(db, str(slug))
                if exercise is None:
                    raise ApiError("EXERCISE_NOT_FOUND", exercise=slug)
                spec, dialect = exercise_spec(exercise, bool(msg.get("skip_blocks"))), exercise.dialect
            else:
                spec, dialect = {"skip_blocks": bool(msg.get("skip_blocks"))}, str(msg.get("dialect", "pal-mill"))
        tools = msg.get("tools")
        if tools is not None:
            try:  # the same tool entries as the REST requests' "tools"
                checked = TOOL_LIST.validate_python(tools)
            except ValidationError:
                raise LiveError("BAD_MESSAGE", detail="tools") from None
            spec["tools"] = [*(spec.get("tools") or []), *(t.model_dump() for t in checked)]
        return dialect, spec

    async def handle(self, msg: dict[str, Any]) -> None:
        kind, version = msg.get("type"), msg.get("version")
        if not isinstance(version, int) or isinstance(version, bool):
            raise LiveError("BAD_MESSAGE", detail="version")
        text = msg.get("text", "")
        if not isinstance(text, str):
            raise LiveError("BAD_MESSAGE", detail="text")
        if kind == "open":
            dialect, spec = await run_in_threadpool(self._open_spec, msg)
            check_program(self.settings, text, dialect)
            lines = split_lines(text)
            self._check_lines(len(lines))
            self.doc = Document(lines, version, dialect, spec)
            if self.doc_id:
                await self.close()
            self.doc_id = uuid.uuid4().hex
            self.slot = self.workers.take_slot()
            self.gen = 0
            self.dirty |= self.sent["diagnostics"].keys() | self.sent["toolpath"].keys()
            self.current = {"diagnostics": {}, "toolpath": {}}
        else:
            doc = self.doc
            if doc is None:
                raise LiveError("NOT_OPEN")
            if version <= doc.version:
                raise LiveError("STALE_VERSION", version=version, current=doc.version)
            if kind == "sync":
                check_program(self.settings, text, doc.dialect)
                lines = split_lines(text)
                self._check_lines(len(lines))
                doc.lines = lines
            elif kind == "edit":
                first, last = msg.get("line"), msg.get("end_line", msg.get("line"))
                if not isinstance(first, int) or not isinstance(last, int):
                    raise LiveError("BAD_MESSAGE", detail="line")
                if len(text) > self.settings.max_program_chars:
                    raise ApiError("PROGRAM_TOO_LARGE", size=len(text), limit=self.settings.max_program_chars)
                self._check_lines(len(doc.lines) - max(0, last - first + 1) + text.count("\n") + 1)
                doc.replace(first, last, text)
            else:
                raise LiveError("BAD_MESSAGE", detail=f"type {kind!r}")
            doc.version = version
        self.changed.set()

    def _check_lines(self, count: int) -> None:
        if count > self.settings.max_live_lines:
            raise LiveError("TOO_MANY_LINES", limit=self.settings.max_live_lines)

    def apply(self, result: dict[str, Any]) -> None:
        """Fold a worker's answer (changed lines, or all lines when `full`) into the current result."""
        for part in ("diagnostics", "toolpath"):
            lines: dict[int, Any] = result[part]
            current = self.current[part]
            if result["full"]:
                self.dirty |= current.keys()
                current.clear()
            for n, value in lines.items():
                if part == "diagnostics" and not value or part == "toolpath" and not any(value.values()):
                    current.pop(n, None)
                else:
                    current[n] = value
            self.dirty |= lines.keys()
        self.gen = result["gen"]

    def changes(self) -> tuple[list[dict[str, Any]], list[dict[str, Any]]]:
        """The lines whose diagnostics, and those whose toolpath, differ from what the client has."""
        diags: list[dict[str, Any]] = []
        path: list[dict[str, Any]] = []
        empty: dict[str, list[Any]] = {"moves": [], "dwells": [], "tool_changes": []}
        for n in sorted(self.dirty):
            for part, out in (("diagnostics", diags), ("toolpath", path)):
                now, sent = self.current[part].get(n), self.sent[part].get(n)
                if now != sent:
                    if part == "diagnostics":
                        out.append({"line": n, "items": now or []})
                    else:
                        out.append({"line": n, **(now or empty)})
                    if now is None:
                        self.sent[part].pop(n, None)
                    else:
                        self.sent[part][n] = now
        self.dirty.clear()
        return diags, path

    async def compute(self) -> None:
        """Re-run the newest document whenever it changed; send only what changed since the last update."""
        while True:
            await self.changed.wait()
            self.changed.clear()
            doc = self.doc
            if doc is None:
                continue
            version, text = doc.version, doc.text
            if len(text) > self.settings.max_program_chars:
                await self.send_error("PROGRAM_TOO_LARGE", version, size=len(text),
                                      limit=self.settings.max_program_chars)
                continue
            try:
                result = await self.workers.call(job_live, self.doc_id, self.gen, self.gen + 1, text, doc.dialect,
                                                 doc.spec, affinity=self.slot)
            except ApiError as err:
                self.gen = -1  # the worker may have lost the document: the next answer is complete
                await self.send_error(err.code, version, **err.params)
                continue
            if self.doc is not doc:
                continue  # reopened meanwhile
            self.apply(result)
            diags, path = self.changes()
            await self.send({"type": "update", "version": version, "line_count": len(doc.lines),
                             "diagnostics": diags, "toolpath": path, "final": result["final"]})

    async def close(self) -> None:
        """Forget the open document, here and in its worker."""
        if self.doc_id:
            doc_id, self.doc_id = self.doc_id, ""
            self.workers.release_slot(self.slot)
            with contextlib.suppress(ApiError):
                await self.workers.call(job_live_close, doc_id, affinity=self.slot)


def ws_principal(database: Database, settings: Settings, ws: WebSocket) -> Principal:
    with database.session() as db:
        return resolve(db, settings, ws.query_params.get("token"), ws.headers.get("x-api-key"),
                       ws.cookies.get(SESSION_COOKIE))


@router.websocket("/live")
async def live(ws: WebSocket) -> None:
    app = ws.app
    settings: Settings = app.state.settings
    database: Database = app.state.db
    await ws.accept()  # accepted first, so that a refusal reaches the client as a close code
    try:
        principal = await run_in_threadpool(ws_principal, database, settings, ws)
    except ApiError as err:
        await ws.close(code=4401, reason=err.code)
        return
    if principal is ANONYMOUS and not settings.free_practice:
        await ws.close(code=4401, reason="FREE_PRACTICE_OFF")
        return
    if not principal.has_scope("practice"):
        await ws.close(code=4403, reason="MISSING_SCOPE")
        return
    session = LiveSession(ws, settings, database, app.state.workers)
    worker = asyncio.create_task(session.compute())
    try:
        while True:
            raw = await ws.receive_text()
            msg: Any = None
            try:
                msg = json.loads(raw)
                if not isinstance(msg, dict):
                    raise LiveError("BAD_MESSAGE", detail="not a JSON object")
                await session.handle(msg)
            except json.JSONDecodeError:
                await session.send_error("BAD_MESSAGE", None, detail="not JSON")
            except LiveError as err:
                await session.send_error(err.code, msg.get("version") if isinstance(msg, dict) else None,
                                         **err.params)
            except ApiError as err:
                await session.send_error(err.code, msg.get("version") if isinstance(msg, dict) else None,
                                         **err.params)
    except WebSocketDisconnect:
        pass
    finally:
        worker.cancel()
        with contextlib.suppress(asyncio.CancelledError):
            await worker
        await session.close()
