"""What the browser tests share: Debian's Chromium, a PAL Trainer server started on 127.0.0.1 with its own data
folder, the built-in exercises and the users a test module needs (made as the admin CLI makes them, before it
starts), and calls of its API to set a scene up."""

from __future__ import annotations

import json
import os
import shutil
import socket
import subprocess
import sys
import time
import urllib.parse
import urllib.request
from collections.abc import Iterable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import pytest
from pwdlib.hashers.argon2 import Argon2Hasher

ROOT = Path(__file__).parents[2]
CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")
BUNDLE = ROOT / "server" / "static" / "app.js"
PASSWORD = "ein langes Passwort"
CHROMIUM_ARGS = [
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
]
NEEDS_CHROMIUM = pytest.mark.skipif(
    CHROMIUM is None, reason="Chromium not installed (.ci/run installs Debian's package)"
)


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


_HASHES: dict[str, str] = {}  # password → its argon2 hash, made once per test process
# The users made here carry an argon2 hash of the lightest parameters (1 MiB, one pass, one lane): the server
# verifies it with the parameters written in the hash, by the same code as any other, in a millisecond instead of
# a quarter of a second of CPU — once for each of the browser tests' hundred and more logins. What a login costs
# is not what these tests check; users made through the product (sign-up, class lists, the admin page, the CLI)
# get the full parameters.
_LIGHT_HASHER = Argon2Hasher(time_cost=1, memory_cost=1024, parallelism=1)


def create_users(env: dict[str, str], users: Iterable[tuple[str, str]], password: str = PASSWORD) -> None:
    """The users ((name, role) pairs) made in the data folder of `env` (PALTRAINER_DATA_DIR), the rows the admin
    CLI makes (`paltrainer admin create-user`, tested in tests/server_tests/test_server_cli.py), in this
    process: a process of its own would import the whole server again for each test module. The users of one
    password share its hash (argon2 salts each hash: the server verifies any of them alike)."""
    from server import repository
    from server.app import prepare_database
    from server.config import Settings

    users = list(users)
    if not users:
        return
    settings = Settings(data_dir=Path(env["PALTRAINER_DATA_DIR"]), load_exercises=False)
    database = prepare_database(settings)
    try:
        with database.session() as db:
            if password not in _HASHES:
                _HASHES[password] = _LIGHT_HASHER.hash(password)
            for name, role in users:
                repository.create_user(db, name, _HASHES[password], role, None)
    finally:
        database.engine.dispose()


SERVER_LOGS: list[Path] = []  # the logs of the servers running now


def server_log_tails(lines: int = 120) -> str:
    """The last `lines` lines of each running server's log."""
    parts = []
    for log in SERVER_LOGS:
        text = log.read_text("utf-8", errors="replace").splitlines()[-lines:] if log.exists() else []
        parts.append(f"--- {log} (last {len(text)} lines)\n" + "\n".join(text))
    return "\n".join(parts)


@contextmanager
def running_server(data: Path, users: Iterable[tuple[str, str]] = (), workers: int = 1) -> Iterator[str]:
    """`paltrainer serve` on a free loopback port with `users` ((name, role) pairs, password PASSWORD); its URL.
    Its log (one JSON line per request, with its duration) goes to data/server.log: a failing test's report
    shows the end of it (conftest.py). With KEEP_SERVER_LOGS=<folder> in the environment each log is kept there,
    named by the server's port (to look for slow requests and stalls of a whole run)."""
    assert BUNDLE.exists(), "the editor is not built: npm --prefix web ci && npm --prefix web run build"
    port = free_port()
    env = {
        **os.environ,
        "PALTRAINER_DATA_DIR": str(data),
        "PALTRAINER_WORKERS": str(workers),
        "PALTRAINER_EXERCISES_DIR": str(ROOT / "exercises"),
    }
    create_users(env, users)
    log = data / "server.log"
    with log.open("ab") as out:
        proc = subprocess.Popen(
            [sys.executable, "-m", "core.cli", "serve", "--host", "127.0.0.1", "--port", str(port)],
            cwd=ROOT,
            env=env,
            stdout=out,
            stderr=subprocess.STDOUT,
        )
    url = f"http://127.0.0.1:{port}"
    SERVER_LOGS.append(log)
    try:
        for _ in range(600):  # up to a minute: on a busy CI machine the first start imports slowly
            try:
                with urllib.request.urlopen(f"{url}/readyz", timeout=1):
                    break
            except OSError:
                time.sleep(0.1)
        else:
            pytest.fail("the server did not start")
        yield url
    finally:
        SERVER_LOGS.remove(log)
        if os.environ.get("KEEP_SERVER_LOGS"):
            shutil.copy(log, Path(os.environ["KEEP_SERVER_LOGS"]) / f"{port}.log")
        proc.terminate()
        proc.wait(timeout=10)


@contextmanager
def chromium() -> Iterator[Any]:
    """Debian's Chromium, headless, driven by Playwright (which downloads no browser of its own)."""
    from playwright.sync_api import sync_playwright

    with sync_playwright() as p:
        b = p.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)
        try:
            yield b
        finally:
            b.close()


def log_in(page: Any, server: str, user: str, password: str = PASSWORD) -> None:
    """Log `user` in on the login page and wait until the page has left it: the login's request is answered and
    the session cookie set (a page opened sooner would be anonymous, and land on the login page again)."""
    page.goto(f"{server}/login")
    page.fill("input[name=username]", user)
    page.fill("input[name=password]", password)
    page.click("button[type=submit]")
    page.wait_for_url(lambda url: urllib.parse.urlsplit(url).path != "/login", timeout=60000)


def call(
    server: str,
    method: str,
    path: str,
    token: str | None = None,
    body: Any = None,
    form: dict[str, str] | None = None,
) -> Any:
    """One API call of the server at `server` (its origin): a JSON body or a form, the answer's JSON."""
    headers = {"Authorization": f"Bearer {token}"} if token else {}
    data = None
    if form is not None:
        data, headers["Content-Type"] = (
            urllib.parse.urlencode(form).encode(),
            "application/x-www-form-urlencoded",
        )
    elif body is not None:
        data, headers["Content-Type"] = json.dumps(body).encode(), "application/json"
    request = urllib.request.Request(f"{server}/api/v1{path}", data=data, headers=headers, method=method)
    with urllib.request.urlopen(request, timeout=120) as r:
        return json.loads(r.read() or b"null")


def completion_labels(page: Any) -> list[str]:
    """The labels of the editor's open completion list (it follows the last key after a short delay)."""
    page.wait_for_timeout(400)
    page.wait_for_selector(".cm-tooltip-autocomplete li", timeout=5000)
    return [
        str(x)
        for x in page.eval_on_selector_all(
            ".cm-tooltip-autocomplete li .cm-completionLabel", "els => els.map(e => e.textContent)"
        )
    ]


def steady_picture(page: Any, selector: str = "#viz-frame", timeout: float = 60.0) -> bytes:
    """The element's picture once it has stopped changing: three screenshots in a row alike, with something drawn
    (not one colour). The 3D view draws with software WebGL here, in its own time: waiting for a steady picture
    replaces a fixed pause, and takes as long as the drawing does, whatever the machine's load."""
    import io

    from PIL import Image

    deadline = time.monotonic() + timeout
    shots: list[bytes] = []
    while True:
        left = max(1.0, deadline - time.monotonic())
        shot = page.locator(selector).screenshot(timeout=left * 1000)
        shots = [*shots[-2:], shot]
        if len(shots) == 3 and shots[0] == shots[1] == shots[2]:
            image = Image.open(io.BytesIO(shot)).convert("L")
            low, high = image.crop(
                (3, 3, image.width - 3, image.height - 3)
            ).getextrema()  # inside the border
            if low != high:
                return shot
        assert time.monotonic() < deadline, f"{selector}: no steady picture within {timeout} s"
        time.sleep(0.2)
