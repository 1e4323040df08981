"""A class asking for heavy work at once: how fast /healthz and a light /check answer meanwhile, what the heavy
requests get, and how long an assignment's task sheets take the first time and the next.

Run from the repository root:

    python bench/heavy_load.py                  # 16 trainees, 2 worker processes
    python bench/heavy_load.py --trainees 30 --workers 4

It starts `paltrainer serve` on 127.0.0.1 with a new SQLite database and the built-in exercises, makes an
instructor, a course of N trainees and a practice assignment of every built-in exercise (about 30). Then, all at
once: every trainee asks for 4 heavy things (the assignment's task sheets, an exercise's picture, its drawing and
a submission), and one more trainee asks for the task sheets 16 times (the issue's case); meanwhile /healthz and
another user's /check are asked every 0.25 s. Printed: the latency of /healthz and of /check during the storm
(p50, p95, max), the heavy requests' answers by status (429: the per-user cap), and the seconds until the
assignment's sheets were ready the first time (every exercise rendered) and the next time (from the cache).
Target (the security-and-load issue): /healthz and /check answer within 1 s throughout, nothing answers 5xx. This
prints figures; it is a benchmark, not a test. Only 127.0.0.1 is contacted.
"""

from __future__ import annotations

import asyncio
import statistics
import sys
import time
from collections import Counter
from datetime import UTC, datetime, timedelta
from pathlib import Path

import httpx

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from bench.exam_end import PASSWORD, main_with
from bench.live_latency import pct

ROOT = Path(__file__).resolve().parent.parent
EXERCISE = "pal-01-g1-gerade"
REFERENCE = (ROOT / "exercises" / "pal-mill" / f"{EXERCISE}.nc").read_text(encoding="utf-8")
TARGET_MS = 1000.0
PROBE_EVERY = 0.25  # s


async def login(client: httpx.AsyncClient, name: str) -> dict[str, str]:
    r = await client.post("/auth/token", data={"username": name, "password": PASSWORD})
    assert r.status_code == 200, r.text
    return {"Authorization": f"Bearer {r.json()['access_token']}"}


async def setup(
    client: httpx.AsyncClient, trainees: int
) -> tuple[list[dict[str, str]], dict[str, str], int, int]:
    """The trainees (the last one is the greedy one), a user for the light /check, the assignment and its size."""
    teacher = await login(client, "bench-lehrer")
    course = (await client.post("/courses", json={"name": "Bench-Klasse"}, headers=teacher)).json()
    headers = []
    for i in range(trainees + 2):
        name = f"bench-last-{i}"
        r = await client.post(
            "/users", json={"username": name, "password": PASSWORD, "role": "student"}, headers=teacher
        )
        assert r.status_code == 201, r.text
        headers.append(await login(client, name))
        if i <= trainees:
            assert (
                await client.post("/courses/join", json={"code": course["join_code"]}, headers=headers[-1])
            ).status_code == 200
    exercises = [
        e["slug"] for e in (await client.get("/exercises", headers=teacher)).json() if e.get("gradable")
    ]
    exercises = exercises[:32]
    now = datetime.now(UTC)
    r = await client.post(
        f"/courses/{course['id']}/assignments",
        headers=teacher,
        json={
            "title": "Bench-Aufgabenblätter",
            "exercises": exercises,
            "mode": "practice",
            "opens_at": (now - timedelta(minutes=1)).isoformat(),
            "deadline": (now + timedelta(hours=2)).isoformat(),
        },
    )
    assert r.status_code == 201, r.text
    return headers[:-1], headers[-1], int(r.json()["id"]), len(exercises)


async def probe(
    client: httpx.AsyncClient,
    stop: asyncio.Event,
    method: str,
    path: str,
    answers: list[float],
    failed: list[str],
    **kwargs: object,
) -> None:
    while not stop.is_set():
        started = time.perf_counter()
        try:
            r = await client.request(method, path, **kwargs)  # type: ignore[arg-type]
            answers.append((time.perf_counter() - started) * 1000)
            if r.status_code != 200:
                failed.append(f"{path} {r.status_code}")
        except httpx.HTTPError as err:
            answers.append(float("inf"))
            failed.append(f"{path} {type(err).__name__}")
        await asyncio.sleep(PROBE_EVERY)


async def heavy(
    client: httpx.AsyncClient, kind: str, method: str, path: str, **kwargs: object
) -> tuple[str, str, float]:
    """One heavy request: its kind, its answer's status (or the error) and its seconds."""
    started = time.perf_counter()
    try:
        r = await client.request(method, path, **kwargs)  # type: ignore[arg-type]
        status = str(r.status_code)
    except httpx.HTTPError as err:
        status = type(err).__name__
    return kind, status, time.perf_counter() - started


def line(name: str, values: list[float]) -> str:
    return (
        f"{name:<8} n={len(values):>4}  p50 {statistics.median(values):7.1f} ms  p95 {pct(values, 95):7.1f} ms  "
        f"max {max(values):7.1f} ms"
    )


async def run(base: str, trainees: int) -> bool:
    limits = httpx.Limits(max_connections=trainees * 4 + 40)
    async with httpx.AsyncClient(base_url=f"{base}/api/v1", timeout=600, limits=limits) as client:
        students, light, assignment, size = await setup(client, trainees)
        *class_, greedy = students
        sheets = f"/assignments/{assignment}/sheets.pdf"
        health: list[float] = []
        checks: list[float] = []
        failed: list[str] = []
        stop = asyncio.Event()
        async with httpx.AsyncClient(base_url=base, timeout=600) as prober:
            probes = [
                asyncio.create_task(probe(prober, stop, "GET", "/healthz", health, failed)),
                asyncio.create_task(
                    probe(
                        prober,
                        stop,
                        "POST",
                        "/api/v1/check",
                        checks,
                        failed,
                        json={"program": REFERENCE, "exercise": EXERCISE},
                        headers=light,
                    )
                ),
            ]
            await asyncio.sleep(1)
            started = time.perf_counter()
            jobs = []
            for h in class_:
                jobs += [
                    heavy(client, "sheets", "GET", sheets, headers=h),
                    heavy(client, "picture", "GET", f"/exercises/{EXERCISE}/picture.png", headers=h),
                    heavy(client, "drawing", "GET", f"/exercises/{EXERCISE}/drawing.svg", headers=h),
                    heavy(
                        client,
                        "submission",
                        "POST",
                        "/submissions",
                        headers=h,
                        json={"exercise": EXERCISE, "program": REFERENCE},
                    ),
                ]
            jobs += [
                heavy(client, "sheets (one trainee 16x)", "GET", sheets, headers=greedy) for _ in range(16)
            ]
            answers = await asyncio.gather(*jobs)
            storm = time.perf_counter() - started
            _, status, again = await heavy(client, "sheets", "GET", sheets, headers=class_[0])
            stop.set()
            await asyncio.gather(*probes)
    statuses = Counter(f"{kind} {status}" for kind, status, _ in answers)
    first = min(seconds for kind, status, seconds in answers if kind == "sheets" and status == "200")
    print(
        f"{len(class_)} trainees x 4 heavy requests + 16 task sheets of one trainee; assignment of {size} "
        f"exercises; all answered after {storm:.1f} s"
    )
    print(line("/healthz", health))
    print(line("/check", checks))
    print("heavy answers: " + ", ".join(f"{k}: {v}" for k, v in sorted(statuses.items())))
    print(
        f"task sheets of {size} exercises: the first after {first:.1f} s (every exercise rendered while the rest "
        f"of the storm ran), asked for again {again * 1000:.0f} ms ({status}, from the cache)"
    )
    errors = [k for k in statuses if not k.split()[-1].isdigit() or k.split()[-1].startswith("5")]
    ok = max(health) < TARGET_MS and max(checks) < TARGET_MS and not failed and not errors
    print(
        f"target: /healthz and /check < {TARGET_MS:.0f} ms throughout, no 5xx: {'PASS' if ok else 'FAIL'}"
        + (f" ({sorted(set(failed))[:5]} {errors})" if not ok else "")
    )
    return ok


def main() -> int:
    return main_with(__doc__ or "", run, 16, "heavy")


if __name__ == "__main__":
    raise SystemExit(main())
