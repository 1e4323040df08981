"""Per-user / per-key / per-address rate limits: a moving window of one minute (the `limits` library).

Most budgets count every request (`hit`); the login budgets count only failed logins (`wait` before the
password is checked, `record` after a wrong one), per user name and per address, so that a class behind one
school address logs in freely while guessing one user's password or many users' passwords is refused.

Where the counts live: with `REDIS_URL` set, in Redis, shared by every server process (replicas behind a
load balancer: a user cannot get a replica's budget from each of them); without it, in this process (the
one-command start needs no Redis). While Redis cannot be reached, the counts are kept in this process
until it answers again (a log line says so): the limits then hold per replica rather than not at all.
"""

from __future__ import annotations

import logging
import math
import time
from threading import Lock
from typing import Any

from limits import RateLimitItemPerMinute
from limits.errors import StorageError
from limits.storage import MemoryStorage, storage_from_string
from limits.strategies import MovingWindowRateLimiter

log = logging.getLogger("paltrainer.server")
KEY_PREFIX = "paltrainer"  # the Redis keys: paltrainer:LIMITS/<bucket>/<who>/… (one Redis may serve more)
RETRY_REDIS_SECONDS = 5.0  # after a Redis error, the in-process counts are used this long before trying again


class RateLimiter:
    def __init__(self, redis_url: str | None = None) -> None:
        self.shared = bool(redis_url)
        self._local = MovingWindowRateLimiter(MemoryStorage())
        self._remote: MovingWindowRateLimiter | None = None
        if redis_url:
            storage = storage_from_string(
                redis_url,
                key_prefix=KEY_PREFIX,
                wrap_exceptions=True,
                socket_timeout=1.0,
                socket_connect_timeout=1.0,
            )
            self._remote = MovingWindowRateLimiter(storage)
        self._down_until = 0.0
        self._lock = Lock()

    def hit(self, bucket: str, who: str, per_minute: int) -> int:
        """Record one request; 0 if allowed, else the seconds until the next one would be."""
        if per_minute <= 0:
            return 0
        item = RateLimitItemPerMinute(per_minute)
        return 0 if self._call("hit", item, bucket, who) else self._wait(item, bucket, who)

    def wait(self, bucket: str, who: str, per_minute: int) -> int:
        """Like `hit`, without counting: for budgets that only failures use up (see `record`)."""
        if per_minute <= 0:
            return 0
        item = RateLimitItemPerMinute(per_minute)
        return 0 if self._call("test", item, bucket, who) else self._wait(item, bucket, who)

    def record(self, bucket: str, who: str, per_minute: int) -> None:
        """Count one event (a failed login) against `who`'s budget of `per_minute` in `bucket`."""
        if per_minute > 0:
            self._call("hit", RateLimitItemPerMinute(per_minute), bucket, who)

    def reset(self) -> None:
        self._local.storage.reset()
        if self._remote is not None:
            self._remote.storage.reset()

    def _wait(self, item: RateLimitItemPerMinute, bucket: str, who: str) -> int:
        reset_time: float = self._call("get_window_stats", item, bucket, who).reset_time
        return max(1, math.ceil(reset_time - time.time()))

    def _call(self, method: str, item: RateLimitItemPerMinute, bucket: str, who: str) -> Any:
        if self._remote is not None and time.monotonic() >= self._down_until:
            try:
                return getattr(self._remote, method)(item, bucket, who)
            except StorageError as err:
                with self._lock:
                    self._down_until = time.monotonic() + RETRY_REDIS_SECONDS
                log.warning("rate limits: Redis does not answer (%s); counting in this process for now", err)
        return getattr(self._local, method)(item, bucket, who)


def login_name(username: str) -> str:
    """The key of a user name's failed-login budget: spelt in any case or padded, it is the same budget."""
    return "name:" + username.strip().casefold()[:200]
