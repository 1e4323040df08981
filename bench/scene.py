"""The 3D view's budgets, measured with a real client over the app's own port.

Run from the repository root:

    python bench/scene.py            # starts `paltrainer serve` on 127.0.0.1 (like live_latency.py)

For each built-in exercise (its reference program): a fresh session (`POST /api/v1/viz`), a WebSocket
client speaking viser's protocol through the bridge `/viz/{token}`, then `POST .../scene`. It prints the
time from asking for the scene until the client has received the whole picture (toolpath, stock, tool:
the bytes stop coming) and the bytes that took; then the bytes one playback step sends. Targets: first
picture under 1 s on loopback (the coarse level of detail of the stock and then the fine one are both in
it); a step while playing under 150 KB. The stock is a 0.5 mm height map sent as tiles of 20 mm (coarse:
6,000 triangles in all, fine: 40,000), and a step resends only the tiles whose mesh changed; the toolpath
is at most 20,000 segments. Only 127.0.0.1 is contacted.

Turning (TRAUB TX 8 D examples, a bar around each program): the turned part is revolved in 48 sections and
chunks of 10 mm along Z; the step measured is one playback step in the middle of the program (the chunks that
step changed), and the bytes of switching the half section on (the whole part once more, cut open).
"""

from __future__ import annotations

import asyncio
import http.cookiejar
import json
import sys
import time
import urllib.request
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import viser
import websockets

from bench.live_latency import server
from core.exercises import builtin_exercises

QUIET = 0.3  # s without a frame: the picture is complete
TRAUB_SEEDS = ROOT / "tests" / "seeds" / "traub"
TURNING = (
    "tx-17-g0-g1-g2-g3.nc",
    "tx-21-geometriezug.nc",
    "tx-30-g71-g88.nc",
    "tx-32-g72-g88.nc",
    "tx-36-g75.nc",
    "tx-40-g76.nc",
)


JAR = http.cookiejar.CookieJar()  # the 3D cookie: an anonymous browser's token drives only its own scene
OPENER = urllib.request.build_opener(urllib.request.HTTPCookieProcessor(JAR))


def post(url: str, body: dict[str, object] | None = None) -> dict[str, object]:
    data = json.dumps(body or {}).encode()
    req = urllib.request.Request(url, data=data, headers={"Content-Type": "application/json"}, method="POST")
    with OPENER.open(req, timeout=30) as r:
        return dict(json.loads(r.read()))


async def received(ws: websockets.ClientConnection, quiet: float = QUIET) -> int:
    """Bytes received until the connection has been quiet for `quiet` seconds."""
    total = 0
    while True:
        try:
            frame = await asyncio.wait_for(ws.recv(), timeout=quiet)
        except TimeoutError:
            return total
        total += len(frame)


async def measure(
    base: str, slug: str | None, program: str, dialect: str, lathe: bool = False
) -> tuple[float, int, int, int]:
    session = post(f"{base}/api/v1/viz")
    token = str(session["token"])
    ws_url = base.replace("http://", "ws://") + f"/viz/{token}"
    cookies = "; ".join(f"{c.name}={c.value}" for c in JAR)
    async with websockets.connect(
        ws_url,
        subprotocols=[f"viser-v{viser.__version__}"],  # type: ignore[list-item]
        additional_headers={"Cookie": cookies},
        max_size=None,
    ) as ws:
        await received(ws)  # the empty scene
        started = time.perf_counter()
        scene = await asyncio.to_thread(
            post,
            f"{base}/api/v1/viz/{token}/scene",
            {"program": program, "dialect": dialect, "exercise": slug},
        )
        picture = await received(ws)
        first = time.perf_counter() - started - QUIET
        half = 0
        if lathe:  # one step of playing, in the middle of the program (after a jump there)
            middle = len(scene["lines"]) // 2  # type: ignore[arg-type]
            await asyncio.to_thread(post, f"{base}/api/v1/viz/{token}/playhead", {"index": middle})
            await received(ws)
            await asyncio.to_thread(post, f"{base}/api/v1/viz/{token}/playhead", {"index": middle + 1})
            step = await received(ws)
            await asyncio.to_thread(post, f"{base}/api/v1/viz/{token}/section", {"half": True})
            half = await received(ws)
        else:
            await asyncio.to_thread(post, f"{base}/api/v1/viz/{token}/playhead", {"index": 3})
            step = await received(ws)
    return first, picture, step, half


def main() -> int:
    exercises = builtin_exercises()
    worst_first, worst_step = 0.0, 0
    with server(2, exercises=True) as live_url:
        base = live_url.replace("ws://", "http://").rsplit("/api/v1/live", 1)[0]
        # an account is not needed: the scene endpoints are free practice; exercises are read by slug
        print(f"{'exercise':32s} {'first picture':>14s} {'bytes':>10s} {'step bytes':>11s}")
        for slug, ex in exercises.items():
            first, picture, step, _ = asyncio.run(measure(base, slug, ex.reference, ex.dialect))
            worst_first, worst_step = max(worst_first, first), max(worst_step, step)
            print(f"{slug:32s} {first * 1000:11.0f} ms {picture:10,d} {step:11,d}")
        print(
            f"\n{'turning (TRAUB)':32s} {'first picture':>14s} {'bytes':>10s} {'step bytes':>11s} {'half section':>13s}"
        )
        for name in TURNING:
            program = (TRAUB_SEEDS / name).read_text(encoding="utf-8")
            first, picture, step, half = asyncio.run(measure(base, None, program, "traub-tx8d", lathe=True))
            worst_first, worst_step = max(worst_first, first), max(worst_step, step)
            print(f"{name:32s} {first * 1000:11.0f} ms {picture:10,d} {step:11,d} {half:13,d}")
    ok_first, ok_step = worst_first < 1.0, worst_step < 150_000
    print(
        f"slowest first picture {worst_first * 1000:.0f} ms (target < 1000 ms): {'PASS' if ok_first else 'FAIL'}"
    )
    print(f"largest playback step {worst_step:,d} B (target < 150 KB): {'PASS' if ok_step else 'FAIL'}")
    return 0 if ok_first and ok_step else 1


if __name__ == "__main__":
    sys.exit(main())
