"""server/ratelimit.py against a real Redis (redis-server from Debian's package, started here on a free port of
127.0.0.1): two server processes' limiters are one budget; when Redis stops they go on counting each for
itself (no 500, no unlimited requests); when it is back they share again."""

from __future__ import annotations

import os
import subprocess
import tempfile
import time
from collections.abc import Iterator

import pytest
import redis

from bench.cluster import _which, free_port
from server.ratelimit import RETRY_REDIS_SECONDS, RateLimiter

REDIS = _which("redis-server")
if REDIS is None and os.environ.get("CI"):
    raise RuntimeError("the Redis tests need redis-server in CI (bash .ci/run installs it)")
pytestmark = pytest.mark.skipif(REDIS is None, reason="needs redis-server (bash .ci/run installs it)")


def start(port: int, folder: str) -> subprocess.Popen[bytes]:
    assert REDIS
    proc = subprocess.Popen(
        [
            REDIS,
            "--port",
            str(port),
            "--bind",
            "127.0.0.1",
            "--save",
            "",
            "--appendonly",
            "no",
            "--dir",
            folder,
        ],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    client = redis.Redis(port=port)
    for _ in range(100):
        try:
            client.ping()
            return proc
        except redis.ConnectionError:
            time.sleep(0.05)
    raise AssertionError("redis-server did not start")


@pytest.fixture
def redis_url() -> Iterator[tuple[str, int, str]]:
    port = free_port()
    folder = tempfile.mkdtemp()
    proc = start(port, folder)
    try:
        yield f"redis://127.0.0.1:{port}/0", port, folder
    finally:
        proc.terminate()
        proc.wait(timeout=10)


def test_two_processes_share_one_budget(redis_url: tuple[str, int, str]) -> None:
    url, _, _ = redis_url
    one, two = RateLimiter(url), RateLimiter(url)
    waits = [(one if i % 2 else two).hit("submit", "user:7", 4) for i in range(8)]
    assert waits[:4] == [0, 0, 0, 0] and all(55 <= w <= 60 for w in waits[4:])
    assert two.hit("submit", "user:8", 4) == 0  # another user, another budget
    for _ in range(2):  # failed logins: counted in one process, refused in the other
        one.record("login-failures", "name:eva", 2)
    assert two.wait("login-failures", "name:eva", 2) > 0


def test_without_redis_each_counts_for_itself_until_it_is_back(redis_url: tuple[str, int, str]) -> None:
    url, port, folder = redis_url
    limiter = RateLimiter(url)
    assert limiter.hit("check", "user:1", 2) == 0
    redis.Redis(port=port).shutdown(nosave=True)
    # Redis gone: the process's own counts (this one starts empty), never an error
    started = time.monotonic()
    assert limiter.hit("check", "user:1", 2) == 0
    assert limiter.hit("check", "user:1", 2) == 0
    assert limiter.hit("check", "user:1", 2) > 0
    assert time.monotonic() - started < RETRY_REDIS_SECONDS  # one refused connection, not one per request
    proc = start(port, folder)  # back (empty): after the pause the counts are Redis's again
    try:
        time.sleep(RETRY_REDIS_SECONDS + 0.2)
        other = RateLimiter(url)
        assert limiter.hit("check", "user:1", 2) == 0
        assert other.hit("check", "user:1", 2) == 0
        assert limiter.hit("check", "user:1", 2) > 0  # the third of the shared budget of 2
    finally:
        proc.terminate()
        proc.wait(timeout=10)
