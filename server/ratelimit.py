"""Per-user / per-key / per-address rate limits: a sliding window of one minute, kept in memory.

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
            q = self._hits.setdefault((bucket, who), deque())
            while q and now - q[0] >= WINDOW_SECONDS:
                q.popleft()
            if len(q) >= per_minute:
                return max(1, math.ceil(WINDOW_SECONDS - (now - q[0])))
            q.append(now)
            if len(self._hits) > 100_000:
                self._hits = {k: v for k, v in self._hits.items() if v and now - v[-1] < WINDOW_SECONDS}
            return 0

    def reset(self) -> None:
        with self._lock:
            self._hits.clear()
