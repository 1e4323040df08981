"""Per-user / per-key / per-address rate limits: a sliding window of one minute, kept in memory.

Most budgets count every request (`hit`); the login budgets count only failed logins (`wait` before the
password is checked, `record` after a wrong one), per user name and per address, so that a class behind one
school address logs in freely while guessing one user's password or many users' passwords is refused.
The counts live in the server process; with several server processes each has its own.
"""

from __future__ import annotations

import math
import time
from collections import deque
from threading import Lock

WINDOW_SECONDS = 60.0


class RateLimiter:
    def __init__(self) -> None:
        self._hits: dict[tuple[str, str], deque[float]] = {}
        self._lock = Lock()

    def hit(self, bucket: str, who: str, per_minute: int) -> int:
        """Record one request; 0 if allowed, else the seconds until the next one would be."""
        if per_minute <= 0:
            return 0
        now = time.monotonic()
        with self._lock:
            wait = self._wait(bucket, who, per_minute, now)
            if not wait:
                self._record(bucket, who, now)
            return wait

    def wait(self, bucket: str, who: str, per_minute: int) -> int:
        """Like `hit`, without counting: for budgets that only failures use up (see `record`)."""
        if per_minute <= 0:
            return 0
        with self._lock:
            return self._wait(bucket, who, per_minute, time.monotonic())

    def record(self, bucket: str, who: str) -> None:
        """Count one event (a failed login) against `who`'s budget in `bucket`."""
        with self._lock:
            self._record(bucket, who, time.monotonic())

    def _wait(self, bucket: str, who: str, per_minute: int, now: float) -> int:
        q = self._hits.get((bucket, who))
        if q is None:
            return 0
        while q and now - q[0] >= WINDOW_SECONDS:
            q.popleft()
        return max(1, math.ceil(WINDOW_SECONDS - (now - q[0]))) if len(q) >= per_minute else 0

    def _record(self, bucket: str, who: str, now: float) -> None:
        self._hits.setdefault((bucket, who), deque()).append(now)
        if len(self._hits) > 100_000:
            self._hits = {k: v for k, v in self._hits.items() if v and now - v[-1] < WINDOW_SECONDS}

    def reset(self) -> None:
        with self._lock:
            self._hits.clear()


def login_name(username: str) -> str:
    """The key of a user name's failed-login budget: spelt in any case or padded, it is the same budget."""
    return "name:" + username.strip().casefold()[:200]
