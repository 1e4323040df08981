"""Holding the server's heavy work where it waits: a gate in front of every heavy worker job, so that a test can
look at the server while those jobs are held (and see that light requests still answer), then open it.

`held` runs inside the worker processes (they import this module by name: the forked processes get the
tests' sys.path), `Gate` on the test's side wraps the app's `Workers.call`."""

from __future__ import annotations

import os
import threading
import time
from collections.abc import Callable, Iterator
from concurrent.futures import ThreadPoolExecutor
from contextlib import contextmanager
from contextvars import ContextVar
from pathlib import Path
from typing import Any

from sqlalchemy import event

HOLD_SECONDS = 300.0  # a gate nobody opens lets its jobs go after this (a failing test must not hang forever)


def held(gate: str, fn: Callable[..., Any], *args: Any) -> Any:
    """In a worker process: wait until the file `gate` exists, then run the job."""
    arrived = Path(f"{gate}.{os.getpid()}.{time.monotonic_ns()}")
    arrived.touch()
    end = time.monotonic() + HOLD_SECONDS
    while not os.path.exists(gate) and time.monotonic() < end:
        time.sleep(0.01)
    return fn(*args)


class Gate:
    """Wraps `app.state.workers.call`: heavy jobs pass `held` first. `entered` counts the heavy calls that reached
    the workers (the request did all its work before them), `arrivals()` the jobs started in a process and waiting
    at the gate."""

    def __init__(self, app: Any, path: Path) -> None:
        self.workers = app.state.workers
        self.path = path
        self.entered = 0
        self.jobs: list[tuple[str, tuple[Any, ...]]] = []
        self._real = self.workers.call

    async def _call(self, fn: Any, *args: Any, affinity: int | None = None, heavy: bool | None = None) -> Any:
        heavy = self.workers.is_heavy(fn) if heavy is None else heavy
        self.jobs.append((getattr(fn, "__name__", "job"), args))
        if not heavy:
            return await self._real(fn, *args, affinity=affinity, heavy=False)
        self.entered += 1
        return await self._real(held, str(self.path), fn, *args, affinity=affinity, heavy=True)

    def install(self) -> None:
        self.workers.call = self._call

    def uninstall(self) -> None:
        self.open()
        self.workers.call = self._real

    def open(self) -> None:
        self.path.touch()

    def arrivals(self) -> int:
        return len(list(self.path.parent.glob(f"{self.path.name}.*")))


@contextmanager
def concurrently(gate: Gate, threads: int) -> Iterator[ThreadPoolExecutor]:
    """Threads for concurrent requests; when the block ends, however it ends, the gate opens first, so that no
    request waits for held work that nobody lets go."""
    pool = ThreadPoolExecutor(threads)
    try:
        yield pool
    finally:
        gate.open()
        pool.shutdown(wait=True)


def wait_until(predicate: Callable[[], bool], seconds: float, what: str) -> None:
    end = time.monotonic() + seconds
    while not predicate():
        if time.monotonic() > end:
            raise AssertionError(f"not within {seconds:g} s: {what}")
        time.sleep(0.02)


IN_REQUEST: ContextVar[str | None] = ContextVar("in_request", default=None)


class MarkRequests:
    """ASGI middleware: the request's path in IN_REQUEST while it is handled (the app's background tasks, started
    by its lifespan, have none)."""

    def __init__(self, app: Any) -> None:
        self.app = app

    async def __call__(self, scope: Any, receive: Any, send: Any) -> None:
        if scope["type"] not in ("http", "websocket"):
            await self.app(scope, receive, send)
            return
        token = IN_REQUEST.set(f"{scope.get('method', 'WS')} {scope['path']}")
        try:
            await self.app(scope, receive, send)
        finally:
            IN_REQUEST.reset(token)


class LoopQueries:
    """The SQL statements requests ran on the event loop's thread (they stop every other request while the
    database, or a free pooled connection, keeps them waiting), with the request's path."""

    def __init__(self, loop_thread: int) -> None:
        self.loop_thread = loop_thread
        self.statements: list[str] = []

    def __call__(self, conn: Any, cursor: Any, statement: str, *_: Any) -> None:
        request = IN_REQUEST.get()
        if request is not None and threading.get_ident() == self.loop_thread:
            self.statements.append(f"{request}: {' '.join(statement.split())[:160]}")


@contextmanager
def queries_on_the_loop(client: Any) -> Iterator[LoopQueries]:
    """Record the statements requests run on the event loop of a TestClient's app (with MarkRequests added)
    while the block runs."""
    engine = client.app.state.db.engine
    seen = LoopQueries(client.portal.call(threading.get_ident))
    event.listen(engine, "before_cursor_execute", seen)
    try:
        yield seen
    finally:
        event.remove(engine, "before_cursor_execute", seen)
