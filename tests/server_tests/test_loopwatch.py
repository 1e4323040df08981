"""The event loop's watchdog names the code that blocks the loop, and says when the loop is free again."""

from __future__ import annotations

import asyncio
import logging
import threading

from server.loopwatch import LoopWatch


class Records(logging.Handler):
    def __init__(self) -> None:
        super().__init__()
        self.records: list[logging.LogRecord] = []
        self.blocked = threading.Event()
        self.freed = threading.Event()

    def emit(self, record: logging.LogRecord) -> None:
        self.records.append(record)
        # (a loaded machine may delay the loop before the test blocks it: only the stall it made counts)
        if record.getMessage() == "event loop blocked" and "hold_the_loop" in getattr(record, "job", ""):
            self.blocked.set()
        if record.getMessage() == "event loop free again" and self.blocked.is_set():
            self.freed.set()


def hold_the_loop(until: threading.Event) -> None:
    """A synchronous call in the loop's thread (as a database call waiting for SQLite's lock would be)."""
    until.wait(60)


def test_a_blocked_loop_is_logged_with_the_blocking_code_and_its_end() -> None:
    handler = Records()
    logger = logging.getLogger("paltrainer.server")
    logger.addHandler(handler)
    old_level = logger.level
    logger.setLevel(logging.INFO)

    async def scenario() -> None:
        watch = LoopWatch(stall_seconds=1.0)
        watch.start()
        try:
            hold_the_loop(handler.blocked)  # blocks until the watchdog has said so
            await asyncio.to_thread(handler.freed.wait, 60)
        finally:
            watch.stop()

    try:
        asyncio.run(scenario())
    finally:
        logger.removeHandler(handler)
        logger.setLevel(old_level)
    blocked = [
        r
        for r in handler.records
        if r.getMessage() == "event loop blocked" and "hold_the_loop" in r.job  # type: ignore[attr-defined]
    ]
    assert len(blocked) == 1  # one warning per stall, however long it lasts
    assert "until.wait(60)" in blocked[0].job  # type: ignore[attr-defined]
    assert blocked[0].levelno == logging.WARNING
    after = handler.records[handler.records.index(blocked[0]) + 1 :]
    freed = [r for r in after if r.getMessage() == "event loop free again"]
    assert freed and freed[0].job.startswith("blocked about ")  # type: ignore[attr-defined]
