"""Throughput of 1, 2 and 3 replicas behind HAProxy on this machine (issue 21): submissions per second and live
keystrokes answered per second, so that the scaling curve is visible (docs/deploy.md quotes it).

Run from the repository root (needs PostgreSQL, redis-server and haproxy: `bash .ci/run` sets them up):

    python bench/scale.py                     # 1, 2 and 3 replicas, 15 s per measurement
    python bench/scale.py --seconds 30 --replicas 1,3
    python bench/scale.py --database-url postgresql://user:pw@127.0.0.1:5432/db

Each replica is `paltrainer serve` with --workers worker processes (default 1) and REPLICA_ID r1…r3, behind
deploy/haproxy.cfg, sharing one PostgreSQL database (a schema of its own) and one Redis (bench/cluster.py).
Submissions: --clients clients (default 16) submit a graded PAL exercise program as fast as they are
answered. Live: --sessions WebSocket sessions (default 60) each edit one line of a 200-block program, send the
next keystroke as soon as the previous one is answered (closed loop: the figure is what the replicas can
answer, not what typists ask), and count the keystrokes answered. Then, with Debian's Chromium, the practice
page's 3D view on three replicas: its replica is killed, and the seconds until the page shows a scene of another
replica (target < 2 s) and the program in it are printed. Only 127.0.0.1 is contacted; the script ends by itself.
"""

from __future__ import annotations

import argparse
import asyncio
import json
import os
import platform
import random
import sys
import time
import uuid
from pathlib import Path

import httpx
from websockets.asyncio.client import connect

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from bench.cluster import CHROMIUM, ROOT, Cluster, binaries_missing, own_schema, scene_failover

EXERCISE = "pal-01-g1-gerade"
SUBMISSION = (ROOT / "exercises" / "pal-mill" / f"{EXERCISE}.nc").read_text(encoding="utf-8")
USERS = 8
PASSWORD = "bench-scale-password"
FAILOVER_TARGET = 2.0  # s: the 3D view opens a scene on another replica (issue 21)


def live_program(blocks: int = 200) -> list[str]:
    lines = ["N10 T1 TC1 M6", "N20 S1200 F150 M3", "N30 G0 X0 Y0 Z2", "N40 G1 Z-2"]
    for i in range(blocks - 5):
        lines.append(f"N{50 + 10 * i} G1 X{(i * 7) % 90 + 5} Y{(i * 13) % 60 + 5}")
    lines.append(f"N{50 + 10 * (blocks - 5)} G0 Z50 M30")
    return lines


async def submissions(url: str, tokens: list[str], clients: int, seconds: float) -> float:
    done = 0
    deadline = time.monotonic() + seconds

    async def client(n: int, http: httpx.AsyncClient) -> None:
        nonlocal done
        headers = {"Authorization": f"Bearer {tokens[n % len(tokens)]}"}
        while time.monotonic() < deadline:
            r = await http.post(
                f"{url}/api/v1/submissions",
                json={"exercise": EXERCISE, "program": SUBMISSION},
                headers={**headers, "Idempotency-Key": uuid.uuid4().hex},
            )
            if r.status_code in (200, 201) and time.monotonic() <= deadline:
                done += 1

    async with httpx.AsyncClient(timeout=60, limits=httpx.Limits(max_connections=clients * 2)) as http:
        started = time.monotonic()
        await asyncio.gather(*(client(n, http) for n in range(clients)))
        return done / (time.monotonic() - started)


async def live(url: str, sessions: int, seconds: float) -> float:
    answered = unanswered = 0
    ws_url = url.replace("http", "ws", 1) + "/api/v1/live"
    deadline = time.monotonic() + seconds

    async def session(n: int) -> None:
        nonlocal answered, unanswered
        rng = random.Random(n)
        lines = live_program()
        async with connect(ws_url, open_timeout=30, max_size=None) as ws:
            version = 0
            await ws.send(json.dumps({"type": "open", "version": version, "text": "\n".join(lines) + "\n"}))
            while True:
                try:
                    msg = json.loads(await asyncio.wait_for(ws.recv(), 30))
                except TimeoutError:
                    unanswered += 1  # counted and reported: a keystroke the replicas never answered
                    return
                if msg.get("version", -1) < version:
                    continue  # an older update: the answer to this keystroke follows
                if version and time.monotonic() <= deadline:
                    answered += 1
                if time.monotonic() > deadline:
                    return
                version += 1
                line = rng.randrange(5, len(lines))
                text = f"N{line * 10} G1 X{rng.randrange(5, 95)} Y{rng.randrange(5, 65)}"
                await ws.send(json.dumps({"type": "edit", "version": version, "line": line, "text": text}))

    started = time.monotonic()
    await asyncio.gather(*(session(n) for n in range(sessions)))
    if unanswered:
        print(f"# {unanswered} live session(s) waited 30 s for an answer and gave up", file=sys.stderr)
    return answered / (time.monotonic() - started)


async def login(url: str) -> list[str]:
    async with httpx.AsyncClient(timeout=30) as http:
        tokens = []
        for i in range(USERS):
            r = await http.post(
                f"{url}/api/v1/auth/token", data={"username": f"bench{i}", "password": PASSWORD}
            )
            r.raise_for_status()
            tokens.append(r.json()["access_token"])
        return tokens


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--replicas", default="1,2,3", help="comma-separated counts (at most 3)")
    p.add_argument("--seconds", type=float, default=15.0, help="length of each measurement")
    p.add_argument("--workers", type=int, default=1, help="worker processes per replica")
    p.add_argument("--clients", type=int, default=16, help="concurrent submitting clients")
    p.add_argument("--sessions", type=int, default=60, help="concurrent live sessions")
    p.add_argument(
        "--database-url",
        default=os.environ.get(
            "PALTRAINER_TEST_POSTGRES_URL",
            "postgresql://paltrainer:paltrainer@127.0.0.1:5432/paltrainer_test",
        ),
    )
    args = p.parse_args()
    missing = binaries_missing()
    if missing:
        print(f"needs {', '.join(missing)} (Debian's packages; bash .ci/run installs them)", file=sys.stderr)
        return 2
    counts = [int(n) for n in args.replicas.split(",")]
    print(
        f"# {platform.platform()}, {os.cpu_count()} cores, Python {platform.python_version()}; "
        f"{args.workers} worker process(es) per replica, {args.seconds:g} s per figure"
    )
    print(f"{'replicas':>8}  {'submissions/s':>13}  {'live keystrokes/s':>17}  {'load average':>12}")
    env = {
        **{f"PALTRAINER_RATE_{k}_PER_MINUTE": "1000000" for k in ("SUBMIT", "CHECK", "LOGIN")},
        "PALTRAINER_LIVE_CONNECTIONS_PER_ADDRESS": "100000",
        "PALTRAINER_HEAVY_JOBS_PER_USER": "100000",
    }  # a few bench users stand for a class: no per-user cap
    for n in counts:
        users = "".join(f"bench{i};{PASSWORD}\n" for i in range(USERS))
        with Cluster(own_schema(args.database_url, "bench_scale"), n, args.workers, env, users) as c:
            tokens = asyncio.run(login(c.url))
            asyncio.run(submissions(c.url, tokens, args.clients, 3))  # warm-up: workers, caches, connections
            subs = asyncio.run(submissions(c.url, tokens, args.clients, args.seconds))
            keys = asyncio.run(live(c.url, args.sessions, args.seconds))
        # the machine's load over the last minute: other work on it lowers the figures
        print(f"{n:>8}  {subs:>13.1f}  {keys:>17.0f}  {os.getloadavg()[0]:>12.1f}", flush=True)
    if CHROMIUM is None:
        print("3D view failover: skipped (needs Debian's chromium)")
        return 0
    with Cluster(own_schema(args.database_url, "bench_scale"), 3, args.workers, env, "") as c:
        moved, shown = scene_failover(c, SUBMISSION)
    verdict = "PASS" if moved < FAILOVER_TARGET else "FAIL"
    print(
        f"3D view in Chromium after its replica was killed: a new scene after {moved:.2f} s "
        f"(target < {FAILOVER_TARGET:g} s) {verdict}, showing the program after {shown:.2f} s"
    )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
