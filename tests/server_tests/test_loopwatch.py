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
        if record.getMessage() == "event loop blocked":
            self.blocked.set()
        if record.getMessage() == "event loop free again":
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
        watch = LoopWatch(stall_seconds=0.3)
        watch.start()
        try:
            await asyncio.sleep(0.3)  # beats while free: nothing is logged
            assert not handler.blocked.is_set()
            hold_the_loop(handler.blocked)  # blocks until the watchdog has said so
            await asyncio.to_thread(handler.freed.wait, 60)
        finally:
            watch.stop()

    try:
        asyncio.run(scenario())
    finally:
        logger.removeHandler(handler)
        logger.setLevel(old_level)
    blocked = [r for r in handler.records if r.getMessage() == "event loop blocked"]
    freed = [r for r in handler.records if r.getMessage() == "event loop free again"]
    assert len(blocked) == 1 and len(freed) == 1
    assert "hold_the_loop" in blocked[0].job  # type: ignore[attr-defined]
    assert "until.wait(60)" in blocked[0].job  # type: ignore[attr-defined]
    assert freed[0].job.startswith("blocked about ")  # type: ignore[attr-defined]
    assert blocked[0].levelno == logging.WARNING
