"""Worker processes: a worker that dies (kill -9, the out-of-memory killer) is replaced and its job retried,
/readyz says so while no worker can take a job, and the time limit counts from the start of a job."""

from __future__ import annotations

import asyncio
import os
import signal
import time
from collections.abc import Iterator
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path
from typing import Any

import pytest
from fastapi.testclient import TestClient
from server_helpers import GOOD, Api, auth, make_settings

from server.app import create_app
from server.errors import ApiError
from server.workers import Workers


@pytest.fixture(scope="module")
def own(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Api]:
    """An app of its own (its workers are killed here), answering 500s as responses, not exceptions."""
    settings = make_settings(tmp_path_factory.mktemp("workers"), "sqlite", workers=2)
    with TestClient(
        create_app(settings), base_url="http://127.0.0.1", raise_server_exceptions=False
    ) as client:
        yield Api(client)


def wait_for(predicate: Any, seconds: float) -> bool:
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        if predicate():
            return True
        time.sleep(0.01)
    return False


def test_a_worker_killed_under_load_is_replaced_and_every_request_is_answered(own: Api) -> None:
    workers = own.app.state.workers
    before = workers.pids()
    assert len(before) == 2
    exercise, student = own.exercise(own.user("instructor"))["slug"], auth(own.user())
    requests = [
        ("/api/v1/check", {"program": GOOD * 40}),
        ("/api/v1/run", {"program": GOOD * 40}),
        ("/api/v1/simulate", {"program": GOOD}),
        ("/api/v1/submissions", {"exercise": exercise, "program": GOOD * 20}),
    ]

    def call(k: int) -> tuple[str, int]:
        path, body = requests[k % len(requests)]
        return path, own.client.post(path, json=body, headers=student).status_code

    with ThreadPoolExecutor(6) as pool:
        first = [pool.submit(call, k) for k in range(24)]
        time.sleep(0.2)  # jobs are running in both workers
        os.kill(before[0], signal.SIGKILL)
        later = [pool.submit(call, k) for k in range(36)]
        answers = [f.result(timeout=120) for f in first + later]
    assert [a for a in answers if a[1] not in (200, 201)] == []
    assert wait_for(lambda: len(set(workers.pids()) - set(before)) == 1, 30)
    assert own.client.get("/readyz").status_code == 200


def test_readyz_fails_while_no_worker_can_take_a_job(tmp_path: Path) -> None:
    settings = make_settings(tmp_path, "sqlite", workers=1)
    with TestClient(create_app(settings), base_url="http://127.0.0.1") as client:
        workers = client.app.state.workers  # type: ignore[attr-defined]
        assert client.get("/readyz").status_code == 200
        (pid,) = workers.pids()
        os.kill(pid, signal.SIGKILL)
        assert wait_for(lambda: client.get("/readyz").status_code == 503, 10)
        r = client.get("/readyz")
        if r.status_code == 503:
            assert r.json()["error"]["code"] == "NOT_READY"
        assert wait_for(lambda: client.get("/readyz").status_code == 200, 60)
        assert workers.pids() != [pid]
        assert client.post("/api/v1/check", json={"program": GOOD}).status_code == 200


def test_a_job_that_kills_its_worker_twice_is_503_not_500(own: Api) -> None:
    """os._exit in the job stands for a program that makes the out-of-memory killer strike each time."""
    workers = own.app.state.workers

    async def main() -> ApiError:
        with pytest.raises(ApiError) as err:
            await workers.call(os._exit, 9)
        return err.value

    error = own.client.portal.call(main)  # type: ignore[union-attr]
    assert error.status == 503 and error.code == "WORKER_FAILED"
    assert error.message and error.message_en
    assert own.client.post("/api/v1/check", json={"program": GOOD}).status_code == 200


def run_with(processes: int, seconds: float, body: Any) -> Any:
    async def main() -> Any:
        workers = Workers(processes, seconds)
        workers.start()
        try:
            return await body(workers)
        finally:
            workers.stop()

    return asyncio.run(main())


def test_the_time_limit_counts_from_the_start_of_a_job_not_from_its_queueing() -> None:
    async def body(workers: Workers) -> list[Any]:
        # three jobs of 0.6 s on one worker: the last waits 1.2 s, longer than the limit, but runs 0.6 s
        return await asyncio.gather(
            *(workers.call(time.sleep, 0.6) for _ in range(3)), return_exceptions=True
        )

    assert run_with(1, 1.5, body) == [None, None, None]


def test_a_job_over_the_time_limit_does_not_take_other_jobs_with_it() -> None:
    async def body(workers: Workers) -> list[Any]:
        slow = asyncio.ensure_future(workers.call(time.sleep, 30))
        await asyncio.sleep(0.1)
        queued = [asyncio.ensure_future(workers.call(abs, -k)) for k in range(4)]
        return await asyncio.gather(slow, *queued, return_exceptions=True)

    slow, *others = run_with(1, 1.0, body)
    assert isinstance(slow, ApiError) and slow.code == "TIME_LIMIT"  # (not the 30 s sleep's None)
    assert others == [0, 1, 2, 3]


def test_an_abandoned_job_is_still_held_to_the_time_limit() -> None:
    """A request whose client went away must not keep its worker busy beyond the limit."""

    async def body(workers: Workers) -> tuple[float, Any]:
        slow = asyncio.ensure_future(workers.call(time.sleep, 30))
        await asyncio.sleep(0.2)
        slow.cancel()
        started = time.monotonic()
        result = await workers.call(abs, -5)
        return time.monotonic() - started, result

    waited, result = run_with(1, 1.0, body)
    assert result == 5 and waited < 15


def test_a_request_from_another_event_loop_is_served(own: Api) -> None:
    """A client without its own lifespan (each request on a loop of its own) still reaches the workers."""
    other = TestClient(own.app, base_url="http://127.0.0.1", raise_server_exceptions=False)
    with ThreadPoolExecutor(6) as pool:  # both kinds at once, so that jobs wait for a free worker
        answers = [
            pool.submit(client.post, "/api/v1/check", json={"program": GOOD * 40})
            for _ in range(6)
            for client in (own.client, other)
        ]
        assert [f.result(timeout=120).status_code for f in answers] == [200] * 12
