"""Every operation of our OpenAPI document, fed generated valid and invalid requests (schemathesis) as an admin,
against a server on 127.0.0.1 (on PostgreSQL when PALTRAINER_TEST_POSTGRES_URL is set, else on SQLite): no
request is answered with a 5xx server error."""

from __future__ import annotations

import json
import os
import socket
import subprocess
import sys
import tempfile
import time
import urllib.parse
import urllib.request
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
import schemathesis
from hypothesis import HealthCheck, Phase, settings
from schemathesis.checks import not_a_server_error
from schemathesis.core.transport import Response
from server_helpers import POSTGRES_URL
from sqlalchemy import create_engine, text

from server.app import create_app
from server.config import Settings

ROOT = Path(__file__).parents[2]
PASSWORD = "ein langes Passwort"
# per operation ("a few hundred": about 2.5 minutes on a 2-core machine); a deep run sets 1000
EXAMPLES = int(os.environ.get("PALTRAINER_SCHEMATHESIS_EXAMPLES", "200"))
# Logging out would revoke the token the run acts with; it has no input to vary.
SKIPPED = ("/api/v1/auth/logout",)


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def own_postgres_schema(url: str, name: str) -> str:
    """A fresh schema of its own in the test database (the other server tests use the public one at the same
    time), and the URL whose connections work in it."""
    engine = create_engine(url.replace("postgresql://", "postgresql+psycopg://", 1))
    with engine.begin() as conn:
        conn.execute(text(f"DROP SCHEMA IF EXISTS {name} CASCADE"))
        conn.execute(text(f"CREATE SCHEMA {name}"))
    engine.dispose()
    return f"{url}{'&' if '?' in url else '?'}options=-csearch_path%3D{name}"


# PostgreSQL when the tests have one (it refuses more than SQLite: NUL in text, integers beyond 32 bits)
BACKEND = "postgresql" if POSTGRES_URL else "sqlite"


@pytest.fixture(scope="module")
def server(tmp_path_factory: pytest.TempPathFactory) -> Iterator[tuple[str, dict[str, str]]]:
    """A server on a free port of 127.0.0.1 with its own database, and an admin's Authorization header."""
    data = tmp_path_factory.mktemp("schemathesis")
    env = {
        **os.environ,
        "PALTRAINER_DATA_DIR": str(data),
        "PALTRAINER_WORKERS": "2",
        "PALTRAINER_EXERCISES_DIR": str(ROOT / "exercises"),
        "PALTRAINER_LOG_LEVEL": "WARNING",
        **{
            f"PALTRAINER_RATE_{name}_PER_MINUTE": "1000000"
            for name in ("LOGIN", "CHECK", "SIMULATE", "SUBMIT")
        },
    }
    env.pop("DATABASE_URL", None)
    env.pop("PALTRAINER_DATABASE_URL", None)
    if BACKEND == "postgresql":
        assert POSTGRES_URL
        env["PALTRAINER_DATABASE_URL"] = own_postgres_schema(POSTGRES_URL, "schemathesis")
    subprocess.run(
        [
            sys.executable,
            "-m",
            "core.cli",
            "admin",
            "create-user",
            "admin",
            "--role",
            "admin",
            "--password",
            PASSWORD,
        ],
        cwd=ROOT,
        env=env,
        check=True,
        capture_output=True,
    )
    port = free_port()
    url = f"http://127.0.0.1:{port}"
    proc = subprocess.Popen(
        [sys.executable, "-m", "core.cli", "serve", "--host", "127.0.0.1", "--port", str(port)],
        cwd=ROOT,
        env=env,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
    )
    try:
        for _ in range(300):
            try:
                with urllib.request.urlopen(f"{url}/readyz", timeout=1):
                    break
            except OSError:
                time.sleep(0.1)
        else:
            pytest.fail("the server did not start")
        form = urllib.parse.urlencode({"username": "admin", "password": PASSWORD}).encode()
        with urllib.request.urlopen(
            urllib.request.Request(f"{url}/api/v1/auth/token", data=form), timeout=30
        ) as r:
            token = json.loads(r.read())["access_token"]
        yield url, {"Authorization": f"Bearer {token}"}
    finally:
        proc.terminate()
        proc.wait(timeout=20)


def openapi_document() -> dict[str, Any]:
    """The document the server serves (made without starting it: no database, no workers)."""
    settings = Settings(secret_key="only-for-the-openapi-document-" * 2, data_dir=Path(tempfile.mkdtemp()))
    return dict(create_app(settings).openapi())


schema = schemathesis.openapi.from_dict(openapi_document()).exclude(path=list(SKIPPED))
schema.config.generation.update(
    modes=[schemathesis.GenerationMode.POSITIVE, schemathesis.GenerationMode.NEGATIVE], max_examples=EXAMPLES
)


@schema.parametrize()
@settings(
    max_examples=EXAMPLES,
    deadline=None,
    derandomize=True,
    database=None,
    phases=[Phase.explicit, Phase.generate],
    suppress_health_check=list(HealthCheck),
)
def test_no_request_is_a_server_error(case: schemathesis.Case, server: tuple[str, dict[str, str]]) -> None:
    url, admin = server
    response: Response = case.call(base_url=url, headers=admin, timeout=60)
    case.validate_response(response, checks=[not_a_server_error])
