"""The event loop's watchdog: every request, live socket and 3D session of the server waits while one piece of
code blocks the loop (a synchronous database call waiting for SQLite's lock, a computation that belongs in a
worker). A thread beside the loop notices when the loop's heartbeat is late by `stall_seconds` and logs a
warning with the stack the loop is stuck in, then how long the stall lasted once it ends: the operator (and a
failing test's report) sees the cause, not only slow requests."""

from __future__ import annotations

import asyncio
import contextlib
import logging
import sys
import threading
import time
import traceback

log = logging.getLogger("paltrainer.server")
BEAT_SECONDS = 0.25  # how often the loop says it is alive


class LoopWatch:
    def __init__(self, stall_seconds: float) -> None:
        self.stall_seconds = stall_seconds
        self.beat = time.monotonic()
        self._stop = threading.Event()
        self._task: asyncio.Task[None] | None = None
        self._thread: threading.Thread | None = None
        self._loop_thread = threading.get_ident()

    def start(self) -> None:
        """Called in the loop's thread, with the loop running."""
        self._loop_thread = threading.get_ident()
        self.beat = time.monotonic()
        self._task = asyncio.create_task(self._heartbeat())
        self._thread = threading.Thread(target=self._watch, name="loop-watch", daemon=True)
        self._thread.start()

    def stop(self) -> None:
        self._stop.set()
        if self._task is not None:
            self._task.cancel()
        if self._thread is not None:
            self._thread.join(timeout=2)

    async def _heartbeat(self) -> None:
        while True:
            self.beat = time.monotonic()
            await asyncio.sleep(BEAT_SECONDS)

    def stack(self) -> str:
        """Where the loop's thread is now (innermost call last)."""
        frame = sys._current_frames().get(self._loop_thread)
        return "".join(traceback.format_stack(frame, limit=25)) if frame is not None else "(no frame)"

    def _watch(self) -> None:
        stalled_since: float | None = None
        while not self._stop.wait(BEAT_SECONDS):
            late = time.monotonic() - self.beat - BEAT_SECONDS
            if stalled_since is None and late >= self.stall_seconds:
                stalled_since = self.beat
                with contextlib.suppress(Exception):  # the watchdog itself never takes the server down
                    log.warning(
                        "event loop blocked",
                        extra={"job": f"{late:.1f} s so far, in:\n{self.stack()}"},
                    )
            elif stalled_since is not None and late < BEAT_SECONDS:
                log.warning(
                    "event loop free again",
                    extra={"job": f"blocked about {self.beat - stalled_since - BEAT_SECONDS:.1f} s"},
                )
                stalled_since = None
