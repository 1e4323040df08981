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
     "run" says how the worker checked the document (for monitoring and bench/live_latency.py; the result
     is the same): "incremental" (from the block before the first changed line until it met the previous
     run again, core/interpreter/checkpoints.py), "to_end" (from there to the end) or "full".
  {"type": "error", "version": 7, "code": "STALE_VERSION", "message": "...", "message_en": "..."}

The document is re-run in a worker process after each change. Edits that arrive while a run is in
progress are applied to the document, and the next run takes them all at once: every run is of
the newest document the server has, and every run is answered, so under load an update may answer
several keystrokes and may be older than the client's newest version. Each update lists the changes
since the previous update and describes the document at its `version`: a client that has typed
since either maps the line numbers through its later edits or drops the update (the next follows).
Updates of one connection come in version order.

Every frame is answered: a frame that is not a JSON object of the protocol (binary, not JSON, nested too
deeply, a lone surrogate such as "\ud800" in any string) gets an error BAD_MESSAGE and changes nothing; a
run that fails gets an error (TIME_LIMIT, WORKER_FAILED, BUSY, RUN_FAILED) at its version; a frame over
PALTRAINER_MAX_BODY_BYTES closes the socket with 1009. Refusals close the socket: 4401 (not logged in),
4403 (key without `practice`, or a browser page of another site: `Origin` is neither this site nor one of
PALTRAINER_CORS_ORIGINS; and at any message, after an error frame with the code, when server/access.py refuses
live diagnostics now: EXAM_RUNNING, EXAM_EXERCISE_LOCKED), 4429 (too many open connections of this user or
address).
"""

from __future__ import annotations

import asyncio
import contextlib
import json
import logging
import math
import time
import uuid
import weakref
from collections import Counter
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Annotated, Any
from urllib.parse import urlsplit

from fastapi import APIRouter, WebSocket, WebSocketDisconnect
from pydantic import Field, TypeAdapter, ValidationError
from starlette.concurrency import run_in_threadpool

from server import access
from server import repository as repo
from server.config import Settings
from server.db import Database
from server.deps import ANONYMOUS, SESSION_COOKIE, Principal, resolve
from server.errors import ApiError
from server.jobs import job_live, job_live_batch, job_live_close
from server.models import now
from server.schemas import ToolSpec
from server.services import check_program, exercise_spec
from server.workers import Workers

router = APIRouter()
_NO_PATH = '"moves":[],"dwells":[],"tool_changes":[]'  # a line's toolpath that is gone
log = logging.getLogger("paltrainer.server")
TOOL_LIST = TypeAdapter(Annotated[list[ToolSpec], Field(max_length=99)])

LIVE_ERRORS: dict[str, tuple[str, str]] = {
    "BAD_MESSAGE": ("Ungültige Nachricht: {detail}", "Invalid message: {detail_en}"),  # detail_en: detail
    "NOT_OPEN": ("Zuerst ein Dokument öffnen (open).", "Open a document first (open)."),
    "STALE_VERSION": (
        "Version {version} ist nicht neuer als {current}; die Änderung wird ignoriert.",
        "Version {version} is not newer than {current}; the change is ignored.",
    ),
    "BAD_LINE": (
        "Zeile {line} gibt es nicht (das Dokument hat {count} Zeilen).",
        "Line {line} does not exist (the document has {count} lines).",
    ),
    "TOO_MANY_LINES": (
        "Das Dokument hat zu viele Zeilen (höchstens {limit}).",
        "The document has too many lines (at most {limit}).",
    ),
    "RUN_FAILED": (
        "Das Programm konnte wegen eines internen Fehlers nicht ausgewertet werden; bitte weiter tippen.",
        "The program could not be evaluated because of an internal error; please keep typing.",
    ),
    "INTERNAL": (
        "Interner Fehler: die Nachricht wurde nicht verarbeitet.",
        "Internal error: the message was not processed.",
    ),
}
# close reasons (at most 123 bytes), German / English
TOO_MANY_CONNECTIONS = (
    "Zu viele Live-Verbindungen (höchstens {limit}) / Too many live connections (at most {limit})"
)
FRAME_TOO_LARGE = "Nachricht zu groß (höchstens {limit} Bytes) / Message too big (at most {limit} bytes)"


class LiveError(Exception):
    def __init__(self, code: str, **params: Any) -> None:
        super().__init__(code)
        self.code, self.params = code, params


class Refused(Exception):
    """server/access.py refuses live diagnostics now (an exam started): the socket closes with 4403 and the code."""

    def __init__(self, err: ApiError) -> None:
        super().__init__(err.code)
        self.error = err


class Gate:
    """server/access.py for one live connection, asked at every message: the trainee's situation is read on
    connect and again every `refresh` seconds (an exam created meanwhile counts from then on), and the rules are
    applied to it at each message's moment (an exam that starts while the socket is open stops it at its start).

    The reads are shared by the connections of one user (or of every anonymous trainee) and exercise in this
    process (`_Reads`), so that 500 editors typing at once make one read every `refresh` seconds, not 500 that
    their keystrokes wait for. A connection takes only reads made since it connected (a new connection, an
    exercise opened: a read of its own). A read older than `refresh` still serves for `stale` seconds more
    while the next one is made in the background; after that a message waits for it."""

    refresh = 10.0
    stale = 5.0

    def __init__(self, database: Database, principal: Principal) -> None:
        self.database, self.user = database, access.acting_user(principal)
        self.reads = _READS.setdefault(database, _Reads())
        self.since = time.monotonic()

    def _situation(self, slug: str | None) -> access.Situation:
        with self.database.session() as db:
            return access.situation(db, self.user, slug)

    async def situation(self, slug: str | None) -> access.Situation:
        key = (self.user.id if self.user is not None else None, slug)
        read = self.reads.done.get(key)
        if read is not None and read[0] < self.since:
            read = None  # read before this connection: not its own
        age = time.monotonic() - read[0] if read is not None else math.inf
        if read is not None and age <= self.refresh:
            return read[1]
        task = self.reads.start(key, lambda: self._situation(slug), self.since)
        if read is not None and age <= self.refresh + self.stale:
            return read[1]  # (the next read is under way)
        return await asyncio.shield(task)

    async def on_connect(self) -> ApiError | None:
        """Refused at once only where a running exam switches live diagnostics off (the exercise comes later)."""
        exam = access.switched_off(await self.situation(None), "live", now())
        return (
            None
            if exam is None
            else ApiError("EXAM_RUNNING", end=exam.end.isoformat(), until=access.german_time(exam.end))
        )

    async def check(self, slug: str | None) -> None:
        try:
            access.decide(await self.situation(slug), "live", slug)
        except ApiError as err:
            raise Refused(err) from None


class _Reads:
    """The situations read for the live connections of one database: by (user id, exercise) the last read
    (its start time, the situation) and the read under way."""

    def __init__(self) -> None:
        self.done: dict[tuple[int | None, str | None], tuple[float, access.Situation]] = {}
        self.running: dict[tuple[int | None, str | None], tuple[float, asyncio.Task[access.Situation]]] = {}

    def start(
        self, key: tuple[int | None, str | None], read: Callable[[], access.Situation], since: float
    ) -> asyncio.Task[access.Situation]:
        """The read of `key` under way in this event loop that started at `since` or later; started now where
        none is."""
        loop = asyncio.get_running_loop()
        running = self.running.get(key)
        if (
            running is not None
            and running[0] >= since
            and not running[1].done()
            and running[1].get_loop() is loop
        ):
            return running[1]
        at = time.monotonic()
        task = loop.create_task(self._read(key, read, at))
        # a failed background read is not news; a message that waits for it gets the error
        task.add_done_callback(_retrieved)
        self.running[key] = (at, task)
        return task

    async def _read(
        self, key: tuple[int | None, str | None], read: Callable[[], access.Situation], at: float
    ) -> access.Situation:
        try:
            value = await run_in_threadpool(read)
        finally:
            if self.running.get(key, (0.0,))[0] == at:
                del self.running[key]
        if key not in self.done or self.done[key][0] < at:
            self.done[key] = (at, value)
        if len(self.done) > _READS_KEPT:  # the oldest reads go first
            for old in sorted(self.done, key=lambda k: self.done[k][0])[: len(self.done) - _READS_KEPT]:
                del self.done[old]
        return value


def _retrieved(task: asyncio.Task[Any]) -> None:
    if not task.cancelled():
        task.exception()


_READS: weakref.WeakKeyDictionary[Database, _Reads] = weakref.WeakKeyDictionary()
_READS_KEPT = 10_000  # (user, exercise) situations kept per database


@dataclass
class Document:
    lines: list[str] = field(default_factory=list)
    version: int = -1
    dialect: str = ""
    spec: dict[str, Any] = field(default_factory=dict)
    exercise: str | None = None

    @property
    def text(self) -> str:
        return "\n".join(self.lines) + "\n"

    def replace(self, first: int, last: int, text: str) -> None:
        count = len(self.lines)
        if not 1 <= first <= count + 1 or not first - 1 <= last <= count:
            raise LiveError("BAD_LINE", line=first if not 1 <= first <= count + 1 else last, count=count)
        self.lines[first - 1 : last] = text.split("\n")


def _skip(msg: dict[str, Any]) -> bool | None:
    """The message's skip switch; not given: the dialect's default (PAL runs "/" blocks, TRAUB skips them)."""
    value = msg.get("skip_blocks")
    return None if value is None else bool(value)


def split_lines(text: str) -> list[str]:
    lines = text.split("\n")
    if len(lines) > 1 and lines[-1] == "":
        lines.pop()
    return lines


class LiveBatch:
    """The live runs waiting for one worker process, handed to it together (`job_live_batch`): under load a
    process answers every document that waited with one round trip instead of one each."""

    most = 64  # documents in one job

    def __init__(self, workers: Workers, slot: int) -> None:
        self.workers, self.slot = workers, slot
        self.waiting: list[tuple[tuple[Any, ...], asyncio.Future[dict[str, Any]]]] = []
        self.task: asyncio.Task[None] | None = None

    async def run(self, *request: Any) -> dict[str, Any]:
        """job_live(*request)'s answer; ApiError as `Workers.call` raises it."""
        loop = asyncio.get_running_loop()
        if self.task is not None and (self.task.done() or self.task.get_loop() is not loop):
            self.task = None  # an event loop that ended (tests start one per client)
            self.waiting = [(r, f) for r, f in self.waiting if f.get_loop() is loop and not f.done()]
        future: asyncio.Future[dict[str, Any]] = loop.create_future()
        self.waiting.append((request, future))
        if self.task is None:
            self.task = asyncio.create_task(self._drain())
        return await future

    async def _drain(self) -> None:
        batch: list[tuple[tuple[Any, ...], asyncio.Future[dict[str, Any]]]] = []
        try:
            while self.waiting:
                batch, self.waiting = self.waiting[: self.most], self.waiting[self.most :]
                try:  # job_live is looked up here, at each call (tests replace it)
                    answers = await self.workers.call(
                        job_live_batch,
                        job_live,
                        [r for r, _ in batch],
                        self.workers.seconds / 4,
                        affinity=self.slot,
                    )
                except ApiError as err:
                    for _, f in batch:
                        if not f.done():
                            f.set_exception(ApiError(err.code, **err.params))
                    continue
                except Exception:  # a defect here or in the job's hand-over: each session says so
                    log.exception("live batch failed")
                    for _, f in batch:
                        if not f.done():
                            f.set_exception(RuntimeError("live batch failed"))
                    continue
                later = []
                for (request, f), answer in zip(batch, answers, strict=True):
                    if f.done():
                        continue  # the session went away
                    if answer is None:
                        later.append((request, f))  # the job's time was up: first in the next one
                    elif answer.get("failed"):
                        f.set_exception(RuntimeError("live run failed"))
                    else:
                        f.set_result(answer)
                self.waiting[:0] = later
        except asyncio.CancelledError:  # the server stops: nobody waits in vain
            for _, f in [*batch, *self.waiting]:
                f.cancel()
            self.waiting = []
            raise
        finally:
            self.task = None


_BATCHES: weakref.WeakKeyDictionary[Workers, dict[int, LiveBatch]] = weakref.WeakKeyDictionary()


def live_batch(workers: Workers, slot: int) -> LiveBatch:
    batches = _BATCHES.setdefault(workers, {})
    if slot not in batches:
        batches[slot] = LiveBatch(workers, slot)
    return batches[slot]


def fold(current: dict[str, dict[int, str]], result: dict[str, Any]) -> set[int]:
    """Fold a worker's answer (changed lines, or all lines when `full`) into `current`: per part ("diagnostics",
    "toolpath") and line its JSON text, "" where the line has nothing (jobs.job_live). The lines it touched."""
    touched: set[int] = set()
    for part in ("diagnostics", "toolpath"):
        lines: dict[int, str] = result[part]
        now = current[part]
        if result["full"]:
            touched |= now.keys()
            now.clear()
        for n, value in lines.items():
            if value:
                now[n] = value
            else:
                now.pop(n, None)
        touched |= lines.keys()
    return touched


class LiveSession:
    """One editor connection: the document, the last result sent, and the task that re-runs it."""

    def __init__(
        self,
        ws: WebSocket,
        settings: Settings,
        database: Database,
        workers: Workers,
        gate: Gate | None = None,
    ) -> None:
        self.ws, self.settings, self.database, self.workers = ws, settings, database, workers
        self.gate = gate
        self.doc: Document | None = None
        self.doc_id = ""
        self.slot = 0
        self.gen = 0  # generation of the last result applied below (0: none)
        # the newest result, per line, and what the client has been sent, per line (JSON text)
        self.current: dict[str, dict[int, str]] = {"diagnostics": {}, "toolpath": {}}
        self.sent: dict[str, dict[int, str]] = {"diagnostics": {}, "toolpath": {}}
        self.dirty: set[int] = set()
        self.changed = asyncio.Event()
        self._send_lock = asyncio.Lock()

    async def send(self, payload: dict[str, Any]) -> None:
        # ASCII: whatever a string holds, the frame is valid UTF-8
        await self.send_text(json.dumps(payload))

    async def send_text(self, frame: str) -> None:
        async with self._send_lock:
            await self.ws.send_text(frame)

    async def send_error(self, code: str, at_version: int | None, **params: Any) -> None:
        if code in LIVE_ERRORS:
            de, en = LIVE_ERRORS[code]
            params.setdefault("detail_en", params.get("detail"))  # a field name reads the same in both
            message, message_en = de.format(**params), en.format(**params)
        else:
            err = ApiError(code, **params)
            message, message_en = err.message, err.message_en
        await self.send(
            {
                "type": "error",
                "version": at_version,
                "code": code,
                "message": message,
                "message_en": message_en,
            }
        )

    def _open_spec(self, msg: dict[str, Any]) -> tuple[str, dict[str, Any]]:
        with self.database.session() as db:
            slug = msg.get("exercise")
            if slug is not None:
                exercise = repo.exercise_by_slug(db, str(slug))
                if exercise is None:
                    raise ApiError("EXERCISE_NOT_FOUND", exercise=slug)
                spec, dialect = exercise_spec(exercise, _skip(msg)), exercise.dialect
            else:
                spec, dialect = {"skip_blocks": _skip(msg)}, str(msg.get("dialect", "pal-mill"))
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
        slug = msg.get("exercise") if kind == "open" else self.doc.exercise if self.doc else None
        if self.gate is not None:
            await self.gate.check(str(slug) if slug is not None else None)
        if kind == "open":
            dialect, spec = await run_in_threadpool(self._open_spec, msg)
            check_program(self.settings, text, dialect)
            lines = split_lines(text)
            self._check_lines(len(lines))
            self.doc = Document(lines, version, dialect, spec, str(slug) if slug is not None else None)
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
        """Fold a worker's answer into the current result."""
        self.dirty |= fold(self.current, result)
        self.gen = result["gen"]

    def changes(self) -> tuple[list[str], list[str]]:
        """The lines whose diagnostics, and those whose toolpath, differ from what the client has: the JSON
        text of each line's object in the update."""
        diags: list[str] = []
        path: list[str] = []
        for n in sorted(self.dirty):
            for part, out in (("diagnostics", diags), ("toolpath", path)):
                now, sent = self.current[part].get(n), self.sent[part].get(n)
                if now != sent:
                    if part == "diagnostics":
                        out.append(f'{{"line":{n},"items":{now or "[]"}}}')
                    else:
                        out.append(f'{{"line":{n},{now or _NO_PATH}}}')
                    if now is None:
                        self.sent[part].pop(n, None)
                    else:
                        self.sent[part][n] = now
        self.dirty.clear()
        return diags, path

    async def compute(self) -> None:
        """Re-run the newest document whenever it changed; send only what changed since the last update.
        Whatever goes wrong in one run is said to the client (never silence), and the next change runs again."""
        while True:
            await self.changed.wait()
            self.changed.clear()
            doc = self.doc
            if doc is None:
                continue
            version = doc.version
            try:
                await self._run(doc, version)
            except ApiError as err:
                self.gen = -1  # the worker may have lost the document: the next answer is complete
                await self.send_error(err.code, version, **err.params)
            except (WebSocketDisconnect, asyncio.CancelledError):
                raise
            except Exception:  # a defect in a job or here
                log.exception("live run failed")
                self.gen = -1
                await self.send_error("RUN_FAILED", version)

    async def _run(self, doc: Document, version: int) -> None:
        text = doc.text
        if len(text) > self.settings.max_program_chars:
            raise ApiError("PROGRAM_TOO_LARGE", size=len(text), limit=self.settings.max_program_chars)
        result = await live_batch(self.workers, self.slot).run(
            self.doc_id, self.gen, self.gen + 1, text, doc.dialect, doc.spec
        )
        if self.doc is not doc:
            return  # reopened meanwhile
        self.apply(result)
        diags, path = self.changes()
        head = json.dumps({"type": "update", "version": version, "line_count": len(doc.lines)})
        tail = json.dumps({"final": result["final"], "run": result["run"]})
        # the lines' parts are JSON text already (jobs.job_live): set into the frame, not encoded again
        await self.send_text(
            f'{head[:-1]}, "diagnostics": [{",".join(diags)}], "toolpath": [{",".join(path)}], {tail[1:]}'
        )

    async def close(self) -> None:
        """Forget the open document, here and in its worker."""
        if self.doc_id:
            doc_id, self.doc_id = self.doc_id, ""
            self.workers.release_slot(self.slot)
            with contextlib.suppress(ApiError):
                await self.workers.call(job_live_close, doc_id, affinity=self.slot)


def ws_principal(database: Database, settings: Settings, ws: WebSocket) -> Principal:
    with database.session() as db:
        return resolve(
            db,
            settings,
            ws.query_params.get("token"),
            ws.headers.get("x-api-key"),
            ws.cookies.get(SESSION_COOKIE),
        )


def origin_allowed(ws: WebSocket, settings: Settings) -> bool:
    """A browser says which site's page opened the socket: only this site (any scheme, since TLS may end at
    a proxy) and the configured CORS origins may. No Origin: not a browser (a script, the LMS), allowed."""
    origin = ws.headers.get("origin")
    if origin is None or origin in settings.cors_origins:
        return True
    host = ws.headers.get("host", "").lower()
    parts = urlsplit(origin.lower())
    return bool(host) and parts.scheme in ("http", "https") and parts.netloc == host


class Connections:
    """Open live connections per user, API key or (anonymous) address."""

    def __init__(self) -> None:
        self.open: Counter[str] = Counter()

    def enter(self, who: str, limit: int) -> bool:
        if self.open[who] >= limit:
            return False
        self.open[who] += 1
        return True

    def leave(self, who: str) -> None:
        self.open[who] -= 1
        if self.open[who] <= 0:
            del self.open[who]


def connections(app: Any) -> Connections:
    registry: Connections | None = getattr(app.state, "live_connections", None)
    if registry is None:
        registry = app.state.live_connections = Connections()
    return registry


async def refuse(ws: WebSocket, code: int, reason: str) -> None:
    await ws.close(code=code, reason=reason.encode()[:123].decode(errors="ignore"))


@router.websocket("/live")
async def live(ws: WebSocket) -> None:
    app = ws.app
    settings: Settings = app.state.settings
    database: Database = app.state.db
    await ws.accept()  # accepted first, so that a refusal reaches the client as a close code
    if not origin_allowed(ws, settings):
        log.info("live socket from another site refused: %s", ws.headers.get("origin", "")[:200])
        await refuse(ws, 4403, "ORIGIN_NOT_ALLOWED")
        return
    try:
        principal = await run_in_threadpool(ws_principal, database, settings, ws)
    except ApiError as err:
        await refuse(ws, 4401, err.code)
        return
    if principal is ANONYMOUS and not settings.free_practice:
        await refuse(ws, 4401, "FREE_PRACTICE_OFF")
        return
    if not principal.has_scope("practice"):
        await refuse(ws, 4403, "MISSING_SCOPE")
        return
    gate = Gate(database, principal)
    if await gate.on_connect() is not None:
        await refuse(ws, 4403, "EXAM_RUNNING")  # an exam without live diagnostics runs for this trainee
        return
    if principal is ANONYMOUS:
        who, limit = f"address:{ws.client.host if ws.client else '-'}", settings.live_connections_per_address
    else:
        who, limit = principal.identity, settings.live_connections_per_user
    registry = connections(app)
    if not registry.enter(who, limit):
        await refuse(ws, 4429, TOO_MANY_CONNECTIONS.format(limit=limit))
        return
    try:
        await serve(ws, settings, LiveSession(ws, settings, database, app.state.workers, gate))
    finally:
        registry.leave(who)


def parse(raw: str) -> dict[str, Any]:
    """A frame's JSON object; LiveError BAD_MESSAGE for anything else (the message then has no version)."""
    try:
        msg = json.loads(raw)
    except RecursionError:
        raise LiveError(
            "BAD_MESSAGE", detail="zu tief verschachtelt", detail_en="nested too deeply"
        ) from None
    except ValueError:
        raise LiveError("BAD_MESSAGE", detail="kein JSON", detail_en="not JSON") from None
    if not isinstance(msg, dict):
        raise LiveError("BAD_MESSAGE", detail="kein JSON-Objekt", detail_en="not a JSON object")
    return msg


def check_text(msg: dict[str, Any]) -> None:
    """Every string of a message (keys too) must be valid Unicode: "\\ud800" decodes to a lone surrogate,
    which no database, worker answer or frame can carry."""
    try:
        json.dumps(msg, ensure_ascii=False).encode("utf-8")
    except UnicodeEncodeError:
        raise LiveError(
            "BAD_MESSAGE",
            detail="einzelnes Surrogat, kein gültiges Unicode",
            detail_en="lone surrogate, not valid Unicode",
        ) from None
    except (RecursionError, ValueError):
        raise LiveError(
            "BAD_MESSAGE", detail="zu tief verschachtelt", detail_en="nested too deeply"
        ) from None


async def serve(ws: WebSocket, settings: Settings, session: LiveSession) -> None:
    """Read frames until the client leaves: each is handled or answered with an error; none ends the session."""
    worker = asyncio.create_task(session.compute())
    try:
        while True:
            frame = await ws.receive()
            if frame["type"] == "websocket.disconnect":
                break
            raw = frame.get("text")
            size = len(raw) if raw is not None else len(frame.get("bytes") or b"")
            if size > settings.max_body_bytes:
                await refuse(ws, 1009, FRAME_TOO_LARGE.format(limit=settings.max_body_bytes))
                break
            version: int | None = None
            try:
                if raw is None:
                    raise LiveError(
                        "BAD_MESSAGE",
                        detail="Binärnachricht; bitte JSON als Text senden",
                        detail_en="binary frame; send JSON as text",
                    )
                msg = parse(raw)
                if isinstance(msg.get("version"), int) and not isinstance(msg.get("version"), bool):
                    version = msg["version"]
                check_text(msg)
                await session.handle(msg)
            except Refused as refused:  # an exam began (or locks the exercise): the connection ends, said why
                await session.send_error(refused.error.code, version, **refused.error.params)
                await refuse(ws, 4403, refused.error.code)
                break
            except (LiveError, ApiError) as err:
                await session.send_error(err.code, version, **err.params)
            except (WebSocketDisconnect, asyncio.CancelledError):
                raise
            except Exception:  # a defect here: said to the client, and the session goes on
                log.exception("live message failed")
                await session.send_error("INTERNAL", version)
    except WebSocketDisconnect:
        pass
    finally:
        worker.cancel()
        with contextlib.suppress(asyncio.CancelledError):
            await worker
        await session.close()
