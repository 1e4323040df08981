"""Helpers of the server tests: settings per database backend, programs, and acting as users of each role."""

from __future__ import annotations

import itertools
import os
from pathlib import Path
from typing import Any

import pytest
from fastapi.testclient import TestClient
from sqlalchemy import create_engine, text

from bench.cluster import own_schema
from server import repository as repo
from server.config import Settings
from server.security import hash_password, make_token

POSTGRES_URL = os.environ.get("PALTRAINER_TEST_POSTGRES_URL")
BACKENDS = [
    "sqlite",
    pytest.param(
        "postgresql",
        marks=pytest.mark.skipif(not POSTGRES_URL, reason="PALTRAINER_TEST_POSTGRES_URL not set"),
    ),
]
PASSWORD = "correct horse battery"
_HASH: list[str] = []
_names = itertools.count(1)

GOOD = "N10 T1 TC1 M6\nN20 S1200 F150 M3\nN30 G0 X0 Y0 Z2\nN40 G1 Z-2\nN50 G1 X20\nN60 G0 Z50 M30\n"
BAD = "N10 T1 TC1 M6\nN20 G1 X1,5\nN30 M30\n"


def unique(prefix: str) -> str:
    return f"{prefix}{next(_names)}"


# the schema of this test process in the PostgreSQL test database, fresh for every app made on it: its own, so
# that parallel test workers (pytest -n) and other test runs on the same database never share tables
SCHEMA = f"tests_{os.environ.get('PYTEST_XDIST_WORKER', 'main')}_{os.getpid()}"


def drop_schema(url: str, name: str) -> None:
    engine = create_engine(url.replace("postgresql://", "postgresql+psycopg://", 1))
    with engine.begin() as conn:
        conn.execute(text(f"DROP SCHEMA IF EXISTS {name} CASCADE"))
    engine.dispose()


def make_settings(tmp: Path, backend: str, **overrides: Any) -> Settings:
    exercises = tmp / "exercises"
    exercises.mkdir(exist_ok=True)
    values: dict[str, Any] = {
        "data_dir": tmp / "data",
        "exercises_dir": exercises,
        "secret_key": "test-secret-of-at-least-thirty-two-bytes",
        "workers": 2,
        "rate_login_per_minute": 1000,
        "rate_check_per_minute": 1000,
        "rate_simulate_per_minute": 1000,
        "rate_submit_per_minute": 1000,
        # races of one user's concurrent requests are tested as such, not capped
        "heavy_jobs_per_user": 1000,
        "heavy_jobs_per_address": 1000,
        "finalize_seconds": 3600,
    }  # the tests run the finaliser's rounds themselves
    if backend == "postgresql":
        assert POSTGRES_URL
        values["database_url"] = own_schema(POSTGRES_URL, SCHEMA)
    values.update(overrides)
    return Settings(**values)


class Api:
    """A TestClient plus helpers to make users and act as them."""

    def __init__(self, client: TestClient) -> None:
        self.client = client
        self.app: Any = client.app

    @property
    def settings(self) -> Settings:
        settings: Settings = self.app.state.settings
        return settings

    def user(self, role: str = "student", name: str | None = None) -> dict[str, str]:
        """A new user of `role`; returns its name and the Authorization header acting as it."""
        if not _HASH:
            _HASH.append(hash_password(PASSWORD))
        name = name or unique(role)
        with self.app.state.db.session() as db:
            user = repo.create_user(db, name, _HASH[0], role)
        token = make_token(self.settings.jwt_secret(), user.id, user.role, 60)
        return {"name": name, "Authorization": f"Bearer {token}"}

    def api_key(self, scopes: list[str], owner: dict[str, str] | None = None) -> dict[str, str]:
        from server import services

        with self.app.state.db.session() as db:
            user = repo.user_by_name(db, owner["name"]) if owner else None
            _, secret = services.create_api_key(db, unique("key"), scopes, user)
        return {"X-API-Key": secret}

    def exercise(self, instructor: dict[str, str], **fields: Any) -> dict[str, Any]:
        body = {
            "slug": unique("ex-"),
            "title_de": "Nuten",
            "title_en": "Slots",
            "task_de": "Fräse die Nuten.",
            "reference_program": GOOD,
            "hidden_criteria": {"max_depth": 2},
            "rubric": {"points": 10},
            "tools": [{"number": 1, "diameter": 25}],
            **fields,
        }
        r = self.client.post("/api/v1/exercises", json=body, headers=auth(instructor))
        assert r.status_code == 201, r.text
        return dict(r.json())


def auth(who: dict[str, str]) -> dict[str, str]:
    return {k: v for k, v in who.items() if k != "name"}


def error_code(response: Any) -> str:
    body = response.json()
    assert set(body["error"]) >= {"code", "message", "message_en"}, body
    assert body["error"]["message"] and body["error"]["message_en"]
    return str(body["error"]["code"])


def builtin_exercise(api: Api, path: str = "pal-mill/pal-01-g1-gerade.yaml", **changes: Any) -> str:
    """A new built-in exercise (as if loaded from exercises/): the file `path` of exercises/ (PAL example G1 no. 1)
    under a new id, with `changes` to its document (hints, solution, order …); returns its slug."""
    from core.exercises import EXERCISES_DIR, load_exercise
    from server.seed import exercise_fields

    doc = load_exercise(EXERCISES_DIR / path)
    # without the file's place in its set unless `changes` give one
    doc = type(doc).model_validate({**doc.model_dump(), "id": unique("builtin-"), "order": None, **changes})
    with api.app.state.db.session() as db:
        repo.create_exercise(db, exercise_fields(doc), owner_id=None, builtin=True)
    return doc.id


def builtin_as_read(api: Api, path: str) -> dict[str, Any]:
    """The built-in exercise file `path` of exercises/ under a new id, as a student reads it."""
    slug = builtin_exercise(api, path)
    r = api.client.get(f"/api/v1/exercises/{slug}", headers=auth(api.user()))
    assert r.status_code == 200, r.text
    return dict(r.json())


def reference_of(slug: str = "pal-01-g1-gerade") -> str:
    """The reference program of a built-in exercise file (full marks for exercises made by builtin_exercise)."""
    from core.exercises import EXERCISES_DIR

    return (EXERCISES_DIR / "pal-mill" / f"{slug}.nc").read_text(encoding="utf-8")
