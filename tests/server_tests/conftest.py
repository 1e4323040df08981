"""Fixtures of the server tests: one app per database backend (SQLite always, PostgreSQL when
PALTRAINER_TEST_POSTGRES_URL is set, in a schema of this test process that is dropped at the end), each made once
per test process and kept until its end."""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import ExitStack

import pytest
from fastapi.testclient import TestClient
from server_helpers import BACKENDS, POSTGRES_URL, SCHEMA, Api, drop_schema, make_settings

from server.app import create_app


class _Apps:
    """The app of each backend, made when a test first asks for it (a test file's tests run on one backend after
    the other, and under pytest-xdist a worker runs file after file: no app is made twice)."""

    def __init__(self, stack: ExitStack, tmp_path_factory: pytest.TempPathFactory) -> None:
        self.stack, self.tmp_path_factory = stack, tmp_path_factory
        self.made: dict[str, Api] = {}

    def get(self, backend: str) -> Api:
        if backend not in self.made:
            settings = make_settings(self.tmp_path_factory.mktemp(backend), backend)
            if backend == "postgresql":
                assert POSTGRES_URL
                self.stack.callback(drop_schema, POSTGRES_URL, SCHEMA)
            client = self.stack.enter_context(TestClient(create_app(settings), base_url="http://127.0.0.1"))
            self.made[backend] = Api(client)
        return self.made[backend]


@pytest.fixture(scope="session")
def _apps(tmp_path_factory: pytest.TempPathFactory) -> Iterator[_Apps]:
    with ExitStack() as stack:
        yield _Apps(stack, tmp_path_factory)


@pytest.fixture(scope="module", params=BACKENDS)
def api(request: pytest.FixtureRequest, _apps: _Apps) -> Api:
    return _apps.get(request.param)


@pytest.fixture(autouse=True)
def _fresh_limits(request: pytest.FixtureRequest) -> None:
    if "api" in request.fixturenames:
        request.getfixturevalue("api").app.state.limiter.reset()
