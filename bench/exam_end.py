"""The end of an exam with a whole class: how fast the trainees' pages are answered while the server submits their
last drafts, and how long until every result is stored.

Run from the repository root:

    python bench/exam_end.py                 # 30 trainees, 2 worker processes
    python bench/exam_end.py --trainees 60

It starts `paltrainer serve` on 127.0.0.1 with a new SQLite database, makes an instructor, a course of N trainees
and an exam of one exercise that ends a few seconds later, and saves a draft for every trainee. At the end every
trainee's page does what the exam page does: it reads GET /api/v1/me/assignments every 2 s until the exam is no
longer "submitting"; meanwhile /healthz is asked every 0.5 s. Printed: the latency of every read (p50, p95, max),
/healthz's slowest answer, failed reads, and the seconds from the end until every trainee's draft was submitted.
Target (the exam-integrity issue, 30 trainees on the 2-core machine): every read answers in under 1 s, and each
draft is submitted once. This prints figures; it is a benchmark, not a test. Only 127.0.0.1 is contacted.
"""

from __future__ import annotations

import argparse
import asyncio
import os
import platform
import random
import statistics
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable, Coroutine
from datetime import UTC, datetime, timedelta
from pathlib import Path
from typing import Any

import httpx

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from bench.live_latency import pct, server

ROOT = Path(__file__).resolve().parent.parent
EXERCISE = "pal-01-g1-gerade"
REFERENCE = (ROOT / "exercises" / "pal-mill" / f"{EXERCISE}.nc").read_text(encoding="utf-8")
PASSWORD = "bench-exam-end-password"
TARGET_READ_MS = 1000.0
LEAD_SECONDS = 20  # the exam ends this long after it was made (time to log in and save every draft)


def make_teacher(data: str) -> None:
    env = {**os.environ, "PALTRAINER_DATA_DIR": data}
    subprocess.run(
        [
            sys.executable,
            "-m",
            "core.cli",
            "admin",
            "create-user",
            "bench-lehrer",
            "--role",
            "instructor",
            "--password",
            PASSWORD,
        ],
        cwd=ROOT,
        env=env,
        check=True,
        capture_output=True,
    )


async def setup(client: httpx.AsyncClient, trainees: int) -> tuple[list[dict[str, str]], int, datetime]:
    token = (await client.post("/auth/token", data={"username": "bench-lehrer", "password": PASSWORD})).json()
    teacher = {"Authorization": f"Bearer {token['access_token']}"}
    course = (await client.post("/courses", json={"name": "Bench-Klasse"}, headers=teacher)).json()
    headers = []
    for i in range(trainees):
        name = f"bench-azubi-{i}"
        r = await client.post(
            "/users", json={"username": name, "password": PASSWORD, "role": "student"}, headers=teacher
        )
        assert r.status_code == 201, r.text
        r = await client.post("/auth/token", data={"username": name, "password": PASSWORD})
        headers.append({"Authorization": f"Bearer {r.json()['access_token']}"})
        assert (
            await client.post("/courses/join", json={"code": course["join_code"]}, headers=headers[-1])
        ).status_code == 200
    end = datetime.now(UTC) + timedelta(seconds=LEAD_SECONDS)
    r = await client.post(
        f"/courses/{course['id']}/assignments",
        headers=teacher,
        json={
            "title": "Bench-Prüfung",
            "exercises": [EXERCISE],
            "mode": "exam",
            "duration_minutes": 1,
            "opens_at": (end - timedelta(minutes=1)).isoformat(),
        },
    )
    assert r.status_code == 201, r.text
    for i, h in enumerate(headers):
        r = await client.put(
            f"/exercises/{EXERCISE}/draft", json={"program": f"; Azubi {i}\n{REFERENCE}"}, headers=h
        )
        assert r.status_code == 200, r.text
    if datetime.now(UTC) >= end:
        raise SystemExit(f"setting up {trainees} trainees took longer than {LEAD_SECONDS} s; fewer trainees")
    return headers, int(r.json()["assignment"]), end


async def page(
    client: httpx.AsyncClient, headers: dict[str, str], exam: int, reads: list[float], failed: list[str]
) -> float:
    """One trainee's exam page after the end: reads its list every 2 s (the first time within 2 s of the end, as
    the pages' clocks differ) until the exam is no longer "submitting"; returns when (monotonic) it saw the
    submitted result."""
    await asyncio.sleep(random.uniform(0, 2))
    for _ in range(300):
        started = time.perf_counter()
        try:
            r = await client.get("/me/assignments", headers=headers)
        except httpx.HTTPError as err:
            failed.append(type(err).__name__)
            await asyncio.sleep(2)
            continue
        reads.append((time.perf_counter() - started) * 1000)
        if r.status_code != 200:
            failed.append(str(r.status_code))
        else:
            mine = next(a for a in r.json() if a["id"] == exam)
            if mine["status"] != "submitting" and all(i["submitted"] for i in mine["items"]):
                return time.monotonic()
        await asyncio.sleep(2)
    return float("nan")


async def health(client: httpx.AsyncClient, stop: asyncio.Event, answers: list[float]) -> None:
    while not stop.is_set():
        started = time.perf_counter()
        try:
            await client.get("/healthz")
            answers.append((time.perf_counter() - started) * 1000)
        except httpx.HTTPError:
            answers.append(float("inf"))
        await asyncio.sleep(0.5)


async def run(base: str, trainees: int) -> bool:
    limits = httpx.Limits(max_connections=trainees + 10)
    async with httpx.AsyncClient(base_url=f"{base}/api/v1", timeout=300, limits=limits) as client:
        headers, exam, end = await setup(client, trainees)
        await asyncio.sleep(max(0.0, (end - datetime.now(UTC)).total_seconds()))
        ended = time.monotonic()
        reads: list[float] = []
        failed: list[str] = []
        probes: list[float] = []
        stop = asyncio.Event()
        async with httpx.AsyncClient(base_url=base, timeout=300) as probe:
            prober = asyncio.create_task(health(probe, stop, probes))
            seen = await asyncio.gather(*(page(client, h, exam, reads, failed) for h in headers))
            stop.set()
            await prober
    done = max(seen) - ended
    print(
        f"trainees {trainees}: {len(reads)} reads, p50 {statistics.median(reads):.0f} ms, "
        f"p95 {pct(reads, 95):.0f} ms, max {max(reads):.0f} ms; failed {len(failed)} {sorted(set(failed))}"
    )
    print(
        f"/healthz slowest {max(probes):.0f} ms of {len(probes)}; every result stored {done:.1f} s after the end"
    )
    ok = max(reads) < TARGET_READ_MS and not failed
    print(f"target: every read < {TARGET_READ_MS:.0f} ms, none failed: {'PASS' if ok else 'FAIL'}")
    return ok


def main_with(
    doc: str, run_bench: Callable[[str, int], Coroutine[Any, Any, bool]], trainees: int, tag: str
) -> int:
    """The command line of a class-sized bench: --trainees and --workers, the machine in a header line, then
    `run_bench(base URL, trainees)` against a new `paltrainer serve` with an instructor made."""
    parser = argparse.ArgumentParser(description=doc.split("\n\n")[0])
    parser.add_argument("--trainees", type=int, default=trainees)
    parser.add_argument("--workers", type=int, default=2)
    args = parser.parse_args()
    print(
        f"{platform.python_implementation()} {platform.python_version()}, {os.cpu_count()} cores, "
        f"load {os.getloadavg()[0]:.1f}, {datetime.now(UTC):%Y-%m-%d %H:%M} UTC, {args.workers} workers"
    )
    data = tempfile.mkdtemp(prefix=f"paltrainer-bench-{tag}-")
    with server(args.workers, exercises=True, data=data) as url:
        base = url.replace("ws://", "http://").removesuffix("/api/v1/live")
        make_teacher(data)
        return 0 if asyncio.run(run_bench(base, args.trainees)) else 1


def main() -> int:
    return main_with(__doc__ or "", run, 30, "exam")


if __name__ == "__main__":
    raise SystemExit(main())
