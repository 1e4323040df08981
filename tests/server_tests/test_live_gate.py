"""The live socket's access gate (server/live.py: Gate) shares the reads of a trainee's situation between
connections, so that a region of editors typing at once does not wait for one database read each, and still
reads afresh for every new connection."""

from __future__ import annotations

import asyncio
import threading
from types import SimpleNamespace
from typing import Any

from server import access
from server.live import Gate


class _Database:
    """Stands for the database: only the key of the gate's shared reads."""


def test_connections_share_situation_reads_and_keystrokes_do_not_wait_for_a_refresh() -> None:
    reads: list[str | None] = []
    release = threading.Event()
    nobody = SimpleNamespace(user=None, api_key=None)

    class Counted(Gate):
        refresh, stale = 60.0, 60.0

        def _situation(self, slug: str | None) -> access.Situation:
            reads.append(slug)
            if len(reads) > 2:  # the background read waits until the test lets it go
                assert release.wait(30)
            return access.Situation(None, (), frozenset())

    async def scenario() -> None:
        database: Any = _Database()
        first = Counted(database, nobody)
        await first.situation(None)
        second = Counted(database, nobody)
        await second.situation(None)
        assert len(reads) == 2  # each connection reads on connect: one made before it is not its own
        for gate in (first, second):  # within `refresh`: the connection's own or a later read serves
            await gate.situation(None)
        assert len(reads) == 2
        Counted.refresh = 0.0  # past `refresh`, within `stale`: the last read serves, one new read for both
        for _ in range(5):
            for gate in (first, second):
                await asyncio.wait_for(gate.situation(None), 30)  # (does not wait for the read held back)
        for _ in range(3000):  # (until the read held back has begun in its thread)
            if len(reads) == 3:
                break
            await asyncio.sleep(0.01)
        await asyncio.sleep(0.05)
        assert len(reads) == 3
        Counted.stale = 0.0  # past `stale` too: the message waits for the read under way
        waiting = asyncio.ensure_future(first.situation(None))
        await asyncio.sleep(0.05)
        assert not waiting.done()
        release.set()
        await asyncio.wait_for(waiting, 30)
        assert len(reads) == 3
        await Counted(database, nobody).situation("ex-1")  # a new connection, an exercise: its own read
        assert reads[-1] == "ex-1" and len(reads) == 4

    asyncio.run(scenario())
