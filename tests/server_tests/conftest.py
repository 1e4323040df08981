"""Fixtures of the server tests: one app per database backend (SQLite always, PostgreSQL when
PALTRAINER_TEST_POSTGRES_URL is set)."""

from __future__ import annotations

from collections.abc import Iterator

import pytest
from fastapi.testclient import TestClient
from server_helpers import BACKENDS, Api, make_settings

from server.app import create_app


@pytest.fixture(scope="session", params=BACKENDS)
def api(request: pytest.FixtureRequest, tmp_path_factory: pytest.TempPathFactory) -> Iterator[Api]:
    settings = make_settings(tmp_path_factory.mktemp(request.param), request.param)
    with TestClient(create_app(settings), base_url="http://127.0.0.1") as client:
        yield Api(client)


@pytest.fixture(autouse=True)
def _fresh_limits(request: pytest.FixtureRequest) -> None:
    if "api" in request.fixturenames:
        request.getfixturevalue("api").app.state.limiter.reset()
