"""Three replicas behind HAProxy sharing PostgreSQL and Redis (issue 21, docs/deploy.md), one of them killed with
SIGKILL in the middle of the load: 100 live-checking sessions and 300 submissions through the balancer.

- every acknowledged submission is in the database exactly once (the clients retry with their Idempotency-Key
  until they get an answer, as a browser that lost its connection does);
- every live session that lost its replica reconnects, and every session gets answers after the kill;
- a 3D view on the killed replica is replaced by a new scene on another one within 2 s (its watch socket
  closes, a new session is made through the balancer, the new scene answers);
- the rate limits hold across replicas: hitting the three replicas directly gives one budget, not three.

Needs `redis-server` and `haproxy` (Debian's packages; `bash .ci/run` installs them) and PostgreSQL
(PALTRAINER_TEST_POSTGRES_URL); without them it is skipped here, and fails in CI (CI=true).
"""

from __future__ import annotations

import asyncio
import json
import os
import random
import time
from collections import Counter
from collections.abc import Iterator
from dataclasses import dataclass, field

import httpx
import pytest
from sqlalchemy import create_engine, text
from websockets.asyncio.client import connect
from websockets.exceptions import ConnectionClosed, InvalidStatus

from bench.cluster import CHROMIUM, ROOT, Cluster, binaries_missing, own_schema, scene_failover

POSTGRES_URL = os.environ.get("PALTRAINER_TEST_POSTGRES_URL")
MISSING = binaries_missing() + ([] if POSTGRES_URL else ["PostgreSQL (PALTRAINER_TEST_POSTGRES_URL)"])
if MISSING and os.environ.get("CI"):
    raise RuntimeError(f"the scale test needs {', '.join(MISSING)} in CI (bash .ci/run installs them)")
pytestmark = pytest.mark.skipif(
    bool(MISSING), reason=f"needs {', '.join(MISSING)} (bash .ci/run installs them)"
)

USERS, PER_USER = 6, 50  # 300 submissions (few users: making one hashes its password, ~1 s)
LIVE_SESSIONS = 100
CHECK_LIMIT = 30  # per user and minute, on every replica
PASSWORD = "scale-test-password"
EXERCISE = "pal-01-g1-gerade"
PROGRAM = (ROOT / "exercises" / "pal-mill" / f"{EXERCISE}.nc").read_text(encoding="utf-8")
VICTIM = "r2"
RUN_ERRORS = {"TIME_LIMIT", "WORKER_FAILED", "BUSY", "RUN_FAILED"}  # server/live.py


@pytest.fixture(scope="module")
def cluster() -> Iterator[Cluster]:
    assert POSTGRES_URL
    env = {
        "PALTRAINER_RATE_CHECK_PER_MINUTE": str(CHECK_LIMIT),
        "PALTRAINER_RATE_SUBMIT_PER_MINUTE": "1000",
        "PALTRAINER_HEAVY_JOBS_PER_USER": "1000",  # a few test users stand for a class: no per-user cap
        "PALTRAINER_LIVE_CONNECTIONS_PER_ADDRESS": "1000",
    }
    users = "".join(f"scale{i};{PASSWORD}\n" for i in range(USERS + 1))
    with Cluster(own_schema(POSTGRES_URL, "scale"), replicas=3, workers=1, env=env, users=users) as c:
        yield c


@dataclass
class Tally:
    acknowledged: dict[str, int] = field(default_factory=dict)  # Idempotency-Key → submission id
    retries: int = 0
    killed_at: float = 0.0


async def token_of(client: httpx.AsyncClient, base: str, name: str) -> str:
    r = await client.post(f"{base}/api/v1/auth/token", data={"username": name, "password": PASSWORD})
    assert r.status_code == 200, r.text
    return str(r.json()["access_token"])


async def submit(client: httpx.AsyncClient, base: str, token: str, key: str, tally: Tally) -> None:
    """POST until acknowledged, with the same Idempotency-Key each time (a lost answer is asked for again)."""
    for _ in range(60):
        try:
            r = await client.post(
                f"{base}/api/v1/submissions",
                json={"exercise": EXERCISE, "program": PROGRAM},
                headers={"Authorization": f"Bearer {token}", "Idempotency-Key": key},
            )
        except httpx.TransportError:
            r = None
        if r is not None and r.status_code in (200, 201):
            tally.acknowledged[key] = int(r.json()["id"])
            return
        assert r is None or r.status_code in (502, 503, 504), (
            r.text
        )  # the balancer lost the replica mid-request
        tally.retries += 1
        await asyncio.sleep(0.2)
    raise AssertionError(f"submission {key} was never acknowledged")


@dataclass
class LiveResult:
    connections: int = 0
    answered_after_kill: bool = False


async def live_session(
    ws_url: str, n: int, killed: asyncio.Event, done: asyncio.Event, rng: random.Random, result: LiveResult
) -> None:
    """Types a line every ~0.5 s and waits for the update that answers it; reconnects (and opens its text again)
    when the socket goes; ends once the load is over and it has had an answer after the kill."""
    lines = PROGRAM.splitlines()
    version = 0
    while not (done.is_set() and result.answered_after_kill):
        try:
            async with connect(ws_url, open_timeout=5, close_timeout=1) as ws:
                result.connections += 1
                version += 1
                await ws.send(
                    json.dumps(
                        {
                            "type": "open",
                            "version": version,
                            "text": "\n".join(lines) + "\n",
                            "dialect": "pal-mill",
                        }
                    )
                )
                while True:
                    while True:  # the update (or error) that answers `version`
                        msg = json.loads(await asyncio.wait_for(ws.recv(), 15))
                        # a run refused under load is answered too (the protocol's run errors); nothing else
                        assert msg["type"] == "update" or msg.get("code") in RUN_ERRORS, msg
                        if (msg.get("version") or 0) >= version:
                            break
                    if killed.is_set() and msg["type"] == "update":
                        result.answered_after_kill = True
                    if done.is_set() and result.answered_after_kill:
                        return
                    await asyncio.sleep(rng.uniform(0.25, 0.75))
                    version += 1
                    line = rng.randrange(6, 8)  # a G1 line: its X or Y word changes
                    lines[line - 1] = (
                        f"N{line}0 G1 X{rng.randrange(40, 80)}"
                        if line == 6
                        else f"N70 G1 Y{rng.randrange(60, 90)}"
                    )
                    await ws.send(
                        json.dumps(
                            {"type": "edit", "version": version, "line": line, "text": lines[line - 1]}
                        )
                    )
        except (ConnectionClosed, OSError, InvalidStatus, TimeoutError):
            await asyncio.sleep(0.2 + rng.random() * 0.3)


async def viz_failover(
    client: httpx.AsyncClient, cluster: Cluster, killed: asyncio.Event
) -> tuple[float, float]:
    """A 3D view on the victim: seconds from the kill until the page has opened a new scene on another replica
    (noticed, asked for a new session, got its token), and until that scene's viewer is up and shows the
    program (a viser server started and a run in a worker, behind the load's)."""
    for _ in range(10):  # round-robin: one of the next three sessions is on the victim
        r = await client.post(f"{cluster.url}/api/v1/viz")
        assert r.status_code == 201, r.text
        token = r.json()["token"]
        if token.startswith(f"{VICTIM}."):
            break
    else:
        raise AssertionError("no 3D session landed on the victim")
    r = await client.post(f"{cluster.url}/api/v1/viz/{token}/scene", json={"program": PROGRAM})
    assert r.status_code == 200, r.text
    ws_url = cluster.url.replace("http", "ws", 1)
    async with connect(f"{ws_url}/viz/{token}/alive", open_timeout=5) as watch:
        await killed.wait()
        started = time.monotonic()
        with pytest.raises(ConnectionClosed):
            await asyncio.wait_for(watch.recv(), 5)  # what the page's watch socket sees
    # the page: a new session through the balancer (which may still try the dead replica first)
    r = await client.post(f"{cluster.url}/api/v1/viz")
    assert r.status_code == 201, r.text
    token = r.json()["token"]
    opened = time.monotonic() - started  # the page has a new scene's token and points its frame at it
    assert not token.startswith(f"{VICTIM}.")
    r = await client.get(f"{cluster.url}/viz/{token}/")  # the frame's page: the new scene's viser is up
    assert r.status_code == 200, r.text
    r = await client.post(f"{cluster.url}/api/v1/viz/{token}/scene", json={"program": PROGRAM})
    assert r.status_code == 200 and r.json()["segments"] > 0, r.text
    return opened, time.monotonic() - started


def test_replicas_survive_a_killed_one(cluster: Cluster) -> None:
    asyncio.run(asyncio.wait_for(scenario(cluster), 150))


async def scenario(cluster: Cluster) -> None:
    rng = random.Random(21)
    tally = Tally()
    killed, done = asyncio.Event(), asyncio.Event()
    limits = httpx.Limits(max_connections=200, max_keepalive_connections=50)
    started = time.monotonic()
    async with httpx.AsyncClient(timeout=30, limits=limits) as client:
        tokens = [await token_of(client, cluster.url, f"scale{i}") for i in range(USERS)]
        ws_url = cluster.url.replace("http", "ws", 1) + "/api/v1/live"
        results = [LiveResult() for _ in range(LIVE_SESSIONS)]
        live = [
            asyncio.create_task(live_session(ws_url, n, killed, done, random.Random(n), results[n]))
            for n in range(LIVE_SESSIONS)
        ]
        viz = asyncio.create_task(viz_failover(client, cluster, killed))
        jobs = [(tokens[u], f"scale-{u}-{k}") for k in range(PER_USER) for u in range(USERS)]
        queue: asyncio.Queue[tuple[str, str]] = asyncio.Queue()
        for job in jobs:
            queue.put_nowait(job)

        async def submitter() -> None:
            while not queue.empty():
                token, key = queue.get_nowait()
                await submit(client, cluster.url, token, key, tally)
                if len(tally.acknowledged) >= len(jobs) // 3 and not killed.is_set():
                    await asyncio.sleep(rng.random() * 0.2)  # in the middle of some requests
                    if not killed.is_set():
                        cluster.kill(VICTIM)
                        tally.killed_at = time.monotonic()
                        killed.set()

        await asyncio.gather(*(submitter() for _ in range(12)))
        done.set()
        await asyncio.wait_for(asyncio.gather(*live), 60)
        loaded = time.monotonic() - started
        opened, shown = await viz
        await rate_limits_hold(client, cluster, tokens[0])

    # every acknowledged submission once in the database, and nothing else of this test's
    assert killed.is_set() and len(tally.acknowledged) == len(jobs)
    engine = create_engine(cluster.database_url.replace("postgresql://", "postgresql+psycopg://", 1))
    with engine.connect() as conn:
        rows = conn.execute(
            text("SELECT id, idempotency_key FROM submissions WHERE idempotency_key LIKE :pattern"),
            {"pattern": "%:scale-%"},
        ).all()
    engine.dispose()
    stored = Counter(key.split(":", 1)[1] for _, key in rows)
    assert not [k for k, n in stored.items() if n != 1], "a submission stored twice"
    assert set(stored) == set(tally.acknowledged)
    assert {i for i, _ in rows} == set(tally.acknowledged.values())
    # every live session answered after the kill; the victim's sessions (about a third) came back elsewhere
    assert all(r.answered_after_kill for r in results)
    reconnected = sum(r.connections > 1 for r in results)
    assert LIVE_SESSIONS // 10 <= reconnected <= LIVE_SESSIONS * 2 // 3, reconnected
    # (how fast the 3D view is back, issue 21's 2 s, is bench/scale.py's figure: here it only has to come back)
    assert 0 < opened <= shown
    print(
        f"\nscale: {len(jobs)} submissions ({tally.retries} retried) and {LIVE_SESSIONS} live sessions "
        f"({reconnected} reconnected) in {loaded:.1f} s; 3D view open again after {opened:.2f} s, "
        f"showing the program after {shown:.2f} s"
    )


async def rate_limits_hold(client: httpx.AsyncClient, cluster: Cluster, token: str) -> None:
    """The check budget and the failed-login budget are one across the (two living) replicas, hit directly."""
    living = [cluster.replica_url(r) for r in ("r1", "r3")]
    body = {"program": "N10 G0 X0 Y0 Z2\nN20 M30\n"}
    statuses = Counter()
    for i in range(CHECK_LIMIT * 2):
        r = await client.post(
            f"{living[i % 2]}/api/v1/check", json=body, headers={"Authorization": f"Bearer {token}"}
        )
        statuses[r.status_code] += 1
    assert statuses == {200: CHECK_LIMIT, 429: CHECK_LIMIT}, statuses
    logins = Counter()
    for i in range(8):  # 5 wrong passwords per user name and minute, wherever they are tried
        r = await client.post(
            f"{living[i % 2]}/api/v1/auth/token",
            data={"username": f"scale{USERS}", "password": "wrong-password"},
        )
        logins[r.status_code] += 1
    assert logins == {401: 5, 429: 3}, logins


@pytest.mark.skipif(CHROMIUM is None, reason="Chromium not installed (.ci/run installs Debian's package)")
def test_the_page_opens_a_new_scene_when_its_replica_dies(cluster: Cluster) -> None:
    """In Chromium: the practice page's 3D view; its replica is killed; without a click the frame shows a scene
    of another replica, which then shows the program. Runs after the test above, on the two replicas left. How
    fast (issue 21: within 2 s) is bench/scale.py's figure: this test only bounds the wait."""
    moved, shown = scene_failover(cluster, PROGRAM, bound=30.0)
    assert 0 < moved <= shown
    print(f"\n3D view in the browser: new scene after {moved:.2f} s, showing the program after {shown:.2f} s")
