"""`paltrainer admin …` against the configured database, and `paltrainer serve` on a real socket (127.0.0.1)."""

from __future__ import annotations

import json
import os
import signal
import socket
import subprocess
import sys
import time
from collections.abc import Iterator
from pathlib import Path

import httpx
import pytest
from server_helpers import GOOD
from websockets.exceptions import ConnectionClosed
from websockets.sync.client import connect

from core.cli import main

ROOT = Path(__file__).parents[2]


@pytest.fixture
def data_dir(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    monkeypatch.setenv("PALTRAINER_DATA_DIR", str(tmp_path / "data"))
    monkeypatch.delenv("DATABASE_URL", raising=False)
    return tmp_path / "data"


def test_admin_create_user_and_api_key(data_dir: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["admin", "create-user", "lehrer", "--role", "instructor", "--password", "geheim123"]) == 0
    assert (data_dir / "paltrainer.sqlite3").exists()
    assert main(["admin", "create-user", "lehrer", "--role", "instructor", "--password", "geheim123"]) == 1
    assert main(["admin", "create-user", "kurz", "--password", "short"]) == 2
    capsys.readouterr()
    assert (
        main(
            [
                "admin",
                "create-api-key",
                "moodle",
                "--scope",
                "practice,exercises:read",
                "--scope",
                "submissions:write",
                "--user",
                "lehrer",
            ]
        )
        == 0
    )
    key = capsys.readouterr().out.strip()
    assert key.startswith("pal_")
    assert main(["admin", "create-api-key", "x", "--scope", "everything"]) == 2
    assert main(["admin", "create-api-key", "x", "--scope", "practice", "--user", "nobody"]) == 1
    capsys.readouterr()
    assert main(["admin", "list-api-keys"]) == 0
    listing = capsys.readouterr().out
    prefix = key.split("_")[1]
    assert prefix in listing and key not in listing and "active" in listing
    assert main(["admin", "revoke-api-key", prefix]) == 0
    assert main(["admin", "revoke-api-key", "ffffffff"]) == 1
    capsys.readouterr()
    main(["admin", "list-api-keys"])
    assert "revoked" in capsys.readouterr().out


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port: int = s.getsockname()[1]
        return port


@pytest.fixture
def served(tmp_path: Path) -> Iterator[str]:
    port = _free_port()
    env = {**os.environ, "PALTRAINER_DATA_DIR": str(tmp_path / "data"), "PALTRAINER_WORKERS": "1"}
    env.pop("DATABASE_URL", None)
    proc = subprocess.Popen(
        [sys.executable, "-m", "core.cli", "serve", "--host", "127.0.0.1", "--port", str(port)],
        cwd=ROOT,
        env=env,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    base = f"http://127.0.0.1:{port}"
    try:
        deadline = time.monotonic() + 30
        while True:
            try:
                if httpx.get(f"{base}/readyz", timeout=1).status_code == 200:
                    break
            except httpx.TransportError:
                pass
            assert proc.poll() is None and time.monotonic() < deadline, "server did not start"
            time.sleep(0.2)
        yield base
    finally:
        proc.send_signal(signal.SIGINT)
        try:
            _, err = proc.communicate(timeout=15)
        except subprocess.TimeoutExpired:
            proc.kill()
            _, err = proc.communicate()
        assert "N10 T1" not in err and "tok-3f9a" not in err  # program text and tokens never reach the log
        assert '"path": "/api/v1/check"' in err


def test_serve_answers_http_and_websocket(served: str) -> None:
    r = httpx.post(f"{served}/api/v1/check", json={"program": GOOD}, timeout=10)
    assert r.status_code == 200 and r.json() == {"diagnostics": []}
    with connect(served.replace("http", "ws") + "/api/v1/live", open_timeout=10) as ws:
        ws.send(json.dumps({"type": "open", "version": 0, "text": GOOD}))
        update = json.loads(ws.recv(timeout=10))
        assert update["type"] == "update" and update["version"] == 0
        ws.send(json.dumps({"type": "edit", "version": 1, "line": 2, "text": "N20 X1,5"}))
        update = json.loads(ws.recv(timeout=10))
        assert update["version"] == 1 and update["diagnostics"][0]["line"] == 2
    with (
        pytest.raises(ConnectionClosed) as closed,
        connect(served.replace("http", "ws") + "/api/v1/live?token=tok-3f9a", open_timeout=10) as ws,
    ):
        ws.recv(timeout=10)
    assert closed.value.rcvd is not None and closed.value.rcvd.code == 4401
