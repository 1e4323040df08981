"""Several PAL Trainer replicas behind HAProxy on 127.0.0.1, sharing one PostgreSQL database and one Redis, as
docs/deploy.md describes: for the scale test (tests/scale/) and the throughput benchmark (bench/scale.py).

Redis and HAProxy (Debian's packages `redis-server` and `haproxy`) are started here on free ports, in a
temporary directory; PostgreSQL is the one the tests use (PALTRAINER_TEST_POSTGRES_URL; `bash .ci/run`
starts it), in a schema of its own. HAProxy runs the repository's deploy/haproxy.cfg, with the `server` lines
of the replicas not started left out. Each replica is a `paltrainer serve` in a process group of its own, so
that `kill` ends it with its worker processes as a crashed machine would (SIGKILL). Only 127.0.0.1 is used.
"""

from __future__ import annotations

import os
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time
import urllib.request
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Self

from sqlalchemy import create_engine, text

ROOT = Path(__file__).resolve().parent.parent
HAPROXY_CFG = ROOT / "deploy" / "haproxy.cfg"
SECRET = "scale-test-secret-key-of-at-least-thirty-two-bytes"
REPLICAS = ("r1", "r2", "r3")


def binaries_missing() -> list[str]:
    return [name for name in ("redis-server", "haproxy") if not _which(name)]


def _which(name: str) -> str | None:
    return shutil.which(name) or next(
        (str(p) for p in (Path("/usr/sbin") / name, Path("/usr/bin") / name) if p.exists()), None
    )


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def own_schema(url: str, name: str) -> str:
    """A fresh schema `name` in the PostgreSQL database at `url`, and the URL whose connections use it."""
    engine = create_engine(url.replace("postgresql://", "postgresql+psycopg://", 1))
    with engine.begin() as conn:
        conn.execute(text(f"DROP SCHEMA IF EXISTS {name} CASCADE"))
        conn.execute(text(f"CREATE SCHEMA {name}"))
    engine.dispose()
    return f"{url}{'&' if '?' in url else '?'}options=-csearch_path%3D{name}"


def wait_http(url: str, seconds: float) -> None:
    deadline = time.monotonic() + seconds
    while True:
        try:
            with urllib.request.urlopen(url, timeout=2) as r:
                if r.status == 200:
                    return
        except OSError:
            pass
        if time.monotonic() > deadline:
            raise TimeoutError(f"{url} did not answer within {seconds:.0f} s")
        time.sleep(0.1)


def haproxy_config(replicas: int) -> str:
    """deploy/haproxy.cfg without the lines of the replicas beyond the first `replicas`."""
    dropped = REPLICAS[replicas:]
    return "".join(
        line
        for line in HAPROXY_CFG.read_text(encoding="utf-8").splitlines(keepends=True)
        if not any(line.strip().startswith((f"server {r} ", f"use-server {r} ")) for r in dropped)
    )


@dataclass
class Cluster:
    database_url: str  # postgresql://… (its own schema)
    replicas: int = 3
    workers: int = 1  # worker processes per replica
    env: dict[str, str] = field(default_factory=dict)  # more settings for every replica
    users: str = ""  # a class list ("name;password" lines) made while the replicas start
    tmp: Path = field(default_factory=lambda: Path(tempfile.mkdtemp(prefix="paltrainer-cluster-")))
    ports: dict[str, int] = field(default_factory=dict)
    processes: dict[str, subprocess.Popen[bytes]] = field(default_factory=dict)
    url: str = ""  # HAProxy's
    redis_url: str = ""
    startup_seconds: float = 0.0  # until every replica was ready

    def replica_url(self, name: str) -> str:
        return f"http://127.0.0.1:{self.ports[name]}"

    def base_env(self) -> dict[str, str]:
        env = {
            k: v
            for k, v in os.environ.items()
            if not k.startswith(("PALTRAINER_", "REPLICA_ID", "REDIS_URL")) and k != "DATABASE_URL"
        }
        return {
            **env,
            "PALTRAINER_DATABASE_URL": self.database_url,
            "PALTRAINER_SECRET_KEY": SECRET,
            "REDIS_URL": self.redis_url,
            "PALTRAINER_WORKERS": str(self.workers),
            "PALTRAINER_EXERCISES_DIR": str(ROOT / "exercises"),
            "PALTRAINER_LOG_LEVEL": "WARNING",
            "FORWARDED_ALLOW_IPS": "127.0.0.1",
            **self.env,
        }

    def start(self) -> None:
        redis_port = free_port()
        self.redis_url = f"redis://127.0.0.1:{redis_port}/0"
        self._spawn(
            "redis",
            [
                _which("redis-server") or "redis-server",
                "--port",
                str(redis_port),
                "--bind",
                "127.0.0.1",
                "--save",
                "",
                "--appendonly",
                "no",
                "--dir",
                str(self.tmp),
            ],
        )
        # the schema and the exercises once, before the replicas (as the Kubernetes Job does)
        self.admin("migrate")
        for name in REPLICAS[: self.replicas]:
            self.ports[name] = free_port()
            self.start_replica(name)
        started = time.monotonic()
        if self.users:
            self.admin("import-users", "-", stdin=self.users.encode())
        for name in REPLICAS[: self.replicas]:
            wait_http(f"{self.replica_url(name)}/readyz", 90)
        self.startup_seconds = time.monotonic() - started
        port = free_port()
        self.url = f"http://127.0.0.1:{port}"
        config = self.tmp / "haproxy.cfg"
        config.write_text(haproxy_config(self.replicas), encoding="utf-8")
        env = {
            **os.environ,
            "PALTRAINER_BIND": f"127.0.0.1:{port}",
            **{f"PALTRAINER_{r.upper()}": f"127.0.0.1:{self.ports.get(r, 9)}" for r in REPLICAS},
        }
        self._spawn("haproxy", [_which("haproxy") or "haproxy", "-db", "-f", str(config)], env=env)
        wait_http(f"{self.url}/readyz", 20)

    def admin(self, *args: str, stdin: bytes = b"") -> str:
        """`paltrainer admin …` against the cluster's database."""
        done = subprocess.run(
            [sys.executable, "-m", "core.cli", "admin", *args],
            cwd=ROOT,
            env=self.base_env(),
            input=stdin,
            capture_output=True,
            check=False,
        )
        if done.returncode:
            raise RuntimeError(f"paltrainer admin {args[0]}: {done.stderr.decode(errors='replace')[-2000:]}")
        return done.stdout.decode()

    def start_replica(self, name: str) -> None:
        data = self.tmp / name
        data.mkdir(exist_ok=True)
        # the exercises were loaded by `admin migrate` (as the Kubernetes Job does): the replicas start faster
        env = {
            **self.base_env(),
            "REPLICA_ID": name,
            "PALTRAINER_DATA_DIR": str(data),
            "PALTRAINER_LOAD_EXERCISES": "false",
        }
        self._spawn(
            name,
            [
                sys.executable,
                "-m",
                "core.cli",
                "serve",
                "--host",
                "127.0.0.1",
                "--port",
                str(self.ports[name]),
                "--proxy-headers",
            ],
            env=env,
        )

    def _spawn(self, name: str, argv: list[str], env: dict[str, str] | None = None) -> None:
        log = (self.tmp / f"{name}.log").open("ab")
        self.processes[name] = subprocess.Popen(
            argv,
            cwd=ROOT,
            env=env,
            stdout=log,
            stderr=subprocess.STDOUT,
            stdin=subprocess.DEVNULL,
            start_new_session=True,
        )

    def kill(self, name: str) -> None:
        """SIGKILL to the replica and its worker processes: no shutdown, no goodbye to its sockets."""
        proc = self.processes.pop(name)
        os.killpg(proc.pid, signal.SIGKILL)
        proc.wait(timeout=10)

    def log(self, name: str) -> str:
        path = self.tmp / f"{name}.log"
        return path.read_text(encoding="utf-8", errors="replace")[-4000:] if path.exists() else ""

    def stop(self) -> None:
        for name in list(self.processes):
            proc = self.processes.pop(name)
            if proc.poll() is None:
                os.killpg(proc.pid, signal.SIGTERM)
                try:
                    proc.wait(timeout=15)
                except subprocess.TimeoutExpired:
                    os.killpg(proc.pid, signal.SIGKILL)
                    proc.wait(timeout=10)
        if not os.environ.get("PALTRAINER_KEEP_CLUSTER"):  # set: the logs stay for a look
            shutil.rmtree(self.tmp, ignore_errors=True)

    def __enter__(self) -> Self:
        try:
            self.start()
            return self
        except BaseException:
            self.stop()
            raise

    def __exit__(self, *exc: object) -> None:
        self.stop()


CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")


def scene_failover(cluster: Cluster, program: str, bound: float = 30.0) -> tuple[float, float]:
    """In Chromium (Debian's package): the practice page's 3D view shows `program`; its replica is killed.
    Answers the seconds until the frame shows a scene of another replica and until that scene shows the
    program (issue 21's target: a new scene within 2 s; bench/scale.py prints it). AssertionError when either
    takes longer than `bound` seconds: the page did not recover."""
    from playwright.sync_api import sync_playwright

    assert CHROMIUM is not None, "Chromium is not installed"
    with sync_playwright() as p:
        browser = p.chromium.launch(
            executable_path=CHROMIUM, args=["--headless", "--no-sandbox", "--disable-gpu"]
        )
        try:
            page = browser.new_page(viewport={"width": 1366, "height": 768})
            page.goto(f"{cluster.url}/practice")
            page.wait_for_selector(".cm-content")
            page.click(".cm-content")
            page.keyboard.press("Control+a")
            page.keyboard.insert_text(program)
            page.click("#viz-on", timeout=30000)  # off by itself in a headless browser (software WebGL)
            segments = "Number(document.getElementById('viz-frame')?.dataset.segments || 0) > 5"
            poll(page, segments, bound)
            replica = page.evaluate("document.getElementById('viz-frame').getAttribute('src')").split("/")[2]
            replica = replica.split(".")[0]
            cluster.kill(replica)
            killed = time.monotonic()
            moved_away = (
                f"!document.getElementById('viz-frame').getAttribute('src').startsWith('/viz/{replica}.')"
            )
            poll(page, moved_away, bound)
            moved = time.monotonic() - killed
            poll(page, segments, bound)
            shown = time.monotonic() - killed
        finally:
            browser.close()
    return moved, shown


def poll(page: Any, expression: str, seconds: float) -> None:
    """Wait for a JavaScript expression (the pages' Content-Security-Policy forbids Playwright's eval)."""
    deadline = time.monotonic() + seconds
    while not page.evaluate(expression):
        assert time.monotonic() < deadline, f"not within {seconds} s: {expression}"
        time.sleep(0.05)
