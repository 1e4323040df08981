"""Heavy work never stalls the server: a request waiting for a worker holds no pooled database connection and runs
no database query on the event loop, heavy jobs leave one worker process to the light ones (check, run, live), and
one user has at most `PALTRAINER_HEAVY_JOBS_PER_USER` heavy requests at a time (more: 429 TOO_MANY_JOBS).

The app here has a pool of two database connections and two worker processes. The heavy jobs are held at a gate
in front of the workers (tests/server_tests/load_helpers.py) while the test looks at the server, so what is shown
is structural: nothing here depends on how fast this machine is."""

from __future__ import annotations

import functools
from collections.abc import Callable, Iterator
from concurrent.futures import Future, ThreadPoolExecutor
from pathlib import Path
from typing import Any

import pytest
import sqlalchemy
from exam_helpers import assign, course_with
from fastapi.testclient import TestClient
from load_helpers import Gate, MarkRequests, concurrently, queries_on_the_loop, wait_until
from server_helpers import GOOD, Api, auth, builtin_exercise, error_code, make_settings, reference_of, unique
from test_server_lms import exercise_file

import server.db
from server.app import create_app
from server.config import Settings

POOL = 2  # pooled database connections of the app under load
ANSWER_SECONDS = 120.0  # the longest wait for any answer: a regression fails here instead of hanging


def small_pool(create_engine: Callable[..., Any]) -> Callable[..., Any]:
    """sqlalchemy.create_engine with a pool of POOL connections and no overflow, for SQLite and PostgreSQL alike; a
    request that finds none free gives up after 10 s (a 500) instead of waiting 30 s."""

    @functools.wraps(create_engine)
    def make(url: Any, **kwargs: Any) -> Any:
        return create_engine(
            url,
            **kwargs,
            poolclass=sqlalchemy.pool.QueuePool,
            pool_size=POOL,
            max_overflow=0,
            pool_timeout=10,
        )

    return make


@pytest.fixture(scope="module")
def loaded(api: Api, tmp_path_factory: pytest.TempPathFactory) -> Iterator[Api]:
    """An app of its own on the backend of `api` (PostgreSQL: the same database, which `api` keeps alive), with a
    pool of two connections, two workers, the default caps on heavy requests, and a time limit that a held job
    does not reach."""
    database = {"database_url": api.settings.database_url} if api.settings.database_url else {}
    caps = {
        name: Settings.model_fields[name].default
        for name in ("heavy_jobs_per_user", "heavy_jobs_per_address")
    }
    settings = make_settings(
        tmp_path_factory.mktemp("load"),
        "sqlite",
        workers=2,
        job_seconds=600,
        rate_picture_per_minute=1000,
        rate_viz_per_minute=1000,
        rate_viz_scene_per_minute=1000,
        **caps,
        **database,
    )
    app = create_app(settings)
    app.add_middleware(MarkRequests)
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(server.db, "create_engine", small_pool(server.db.create_engine))
        with TestClient(app, base_url="http://127.0.0.1", raise_server_exceptions=False) as client:
            assert client.app.state.db.engine.pool.size() == POOL  # type: ignore[attr-defined]
            client.app.state.workers.queue_seconds = 600  # type: ignore[attr-defined]  # held jobs wait long
            yield Api(client)


@pytest.fixture()
def gate(loaded: Api, tmp_path: Path) -> Iterator[Gate]:
    held = Gate(loaded.app, tmp_path / "gate")
    held.install()
    try:
        yield held
    finally:
        held.uninstall()


def answer(future: Future[Any]) -> Any:
    return future.result(timeout=ANSWER_SECONDS)


def light_requests_answer(api: Api, student: dict[str, str], slug: str, pool: ThreadPoolExecutor) -> None:
    """While the heavy work is held: /healthz, /readyz and another user's light /check (for an exercise: it reads
    the database, and runs in a worker) answer."""
    assert answer(pool.submit(api.client.get, "/healthz")).status_code == 200
    assert answer(pool.submit(api.client.get, "/readyz")).status_code == 200
    r = answer(
        pool.submit(
            api.client.post, "/api/v1/check", json={"program": GOOD, "exercise": slug}, headers=auth(student)
        )
    )
    assert r.status_code == 200, r.text
    assert "diagnostics" in r.json()


def viz_token(api: Api, who: dict[str, str] | None) -> str:
    r = api.client.post("/api/v1/viz", headers=auth(who) if who else {})
    assert r.status_code == 201, r.text
    return str(r.json()["token"])


def heavy_requests(api: Api) -> list[tuple[str, Callable[[], Any]]]:
    """Two of every kind of heavy request, each by a user (or address) of its own and each on content of its own
    (no two of them could share one job)."""
    teacher = api.user("instructor")
    students = [api.user() for _ in range(24)]
    course = course_with(api, teacher, *students)
    client = api.client
    calls: list[tuple[str, Callable[[], Any]]] = []
    s = iter(students)
    for _ in range(2):
        sheets = assign(api, teacher, course, [builtin_exercise(api), builtin_exercise(api)], exam=False)
        calls.append(
            (
                "assignment sheets",
                functools.partial(
                    client.get, f"/api/v1/assignments/{sheets}/sheets.pdf", headers=auth(next(s))
                ),
            )
        )
        for kind, path in (("sheet", "sheet.pdf"), ("picture", "picture.png"), ("drawing", "drawing.svg")):
            calls.append(
                (
                    kind,
                    functools.partial(
                        client.get, f"/api/v1/exercises/{builtin_exercise(api)}/{path}", headers=auth(next(s))
                    ),
                )
            )
        calls.append(
            (
                "submission",
                functools.partial(
                    client.post,
                    "/api/v1/submissions",
                    json={"exercise": builtin_exercise(api), "program": reference_of()},
                    headers=auth(next(s)),
                ),
            )
        )
        calls.append(
            (
                "simulate",
                functools.partial(
                    client.post, "/api/v1/simulate", json={"program": GOOD}, headers=auth(next(s))
                ),
            )
        )
        who = next(s)
        calls.append(
            (
                "scene",
                functools.partial(
                    client.post,
                    f"/api/v1/viz/{viz_token(api, who)}/scene",
                    json={"program": GOOD},
                    headers=auth(who),
                ),
            )
        )
        who = next(s)
        calls.append(
            (
                "deviation",
                functools.partial(
                    client.post,
                    f"/api/v1/viz/{viz_token(api, who)}/deviation",
                    json={"program": reference_of(), "exercise": builtin_exercise(api)},
                    headers=auth(who),
                ),
            )
        )
        calls.append(
            (
                "3d picture",
                functools.partial(
                    client.post, "/api/v1/viz/picture.png", json={"program": GOOD}, headers=auth(next(s))
                ),
            )
        )
    calls.append(
        (
            "example drawing",
            functools.partial(client.get, f"/api/v1/examples/{builtin_exercise(api)}/drawing.svg"),
        )
    )  # anonymous: counted per address
    calls.append(
        ("anonymous simulate", functools.partial(client.post, "/api/v1/simulate", json={"program": GOOD}))
    )
    calls.append(
        (
            "import",
            functools.partial(
                client.post,
                "/api/v1/exercises/import",
                content=exercise_file(unique("load-")).encode(),
                headers={**auth(teacher), "Content-Type": "application/yaml"},
            ),
        )
    )
    return calls


def test_heavy_requests_held_in_the_workers_leave_the_server_answering(loaded: Api, gate: Gate) -> None:
    """21 heavy requests of every kind (each by a user or address of its own) and 6 task sheets of one greedy
    student at once, all held in front of the workers, with a pool of 2 connections: /healthz, /readyz and a light
    /check still answer; none of the held requests holds a connection, none answers 5xx once the work goes on;
    the greedy student gets 429 beyond the cap."""
    api = loaded
    cap = api.settings.heavy_jobs_per_user
    requests = heavy_requests(api)
    greedy = api.user()
    teacher = api.user("instructor")
    course = course_with(api, teacher, greedy)
    for _ in range(cap + 2):
        sheets = assign(api, teacher, course, [builtin_exercise(api)], exam=False)
        requests.append(
            (
                "greedy sheets",
                functools.partial(
                    api.client.get, f"/api/v1/assignments/{sheets}/sheets.pdf", headers=auth(greedy)
                ),
            )
        )
    other, slug = api.user(), builtin_exercise(api)
    with concurrently(gate, len(requests) + 4) as pool:
        futures = [(name, pool.submit(call)) for name, call in requests]
        admitted = len(requests) - 2  # the greedy student's two beyond the cap are answered at once
        wait_until(
            lambda: gate.entered == admitted, ANSWER_SECONDS, "every admitted request waits for a worker"
        )
        wait_until(lambda: gate.arrivals() == 1, ANSWER_SECONDS, "a worker process holds one heavy job")
        refused = [(name, f.result()) for name, f in futures if f.done()]
        assert [name for name, _ in refused] == ["greedy sheets"] * 2
        for _, r in refused:
            assert r.status_code == 429 and error_code(r) == "TOO_MANY_JOBS"
            assert "Sie" in r.json()["error"]["message"] and r.headers["Retry-After"]
        assert gate.arrivals() == 1  # heavy jobs never take the last process: it stays free for light ones
        light_requests_answer(api, other, slug, pool)
        gate.open()
        answers = [(name, answer(f)) for name, f in futures]
    failed = [
        (name, r.status_code, r.text[:300]) for name, r in answers if r.status_code not in (200, 201, 429)
    ]
    assert failed == []
    assert sum(r.status_code == 429 for _, r in answers) == 2


def test_sixteen_sheets_of_one_student_are_capped_and_the_server_goes_on(loaded: Api, gate: Gate) -> None:
    """The issue's case: 16 concurrent GET /assignments/{id}/sheets.pdf of one student. At most the cap of them
    wait for a worker, the others are answered 429 at once; /healthz and another user's /check answer meanwhile."""
    api = loaded
    cap = api.settings.heavy_jobs_per_user
    student, other = api.user(), api.user()
    teacher = api.user("instructor")
    course = course_with(api, teacher, student)
    sheets = assign(api, teacher, course, [builtin_exercise(api) for _ in range(3)], exam=False)
    slug = builtin_exercise(api)
    with concurrently(gate, 20) as pool:
        futures = [
            pool.submit(api.client.get, f"/api/v1/assignments/{sheets}/sheets.pdf", headers=auth(student))
            for _ in range(16)
        ]
        wait_until(
            lambda: sum(f.done() for f in futures) == 16 - cap, ANSWER_SECONDS, "the refused ones answered"
        )
        wait_until(lambda: gate.entered >= 1, ANSWER_SECONDS, "a sheet waits for a worker")
        refused = [f.result() for f in futures if f.done()]
        assert {r.status_code for r in refused} == {429}
        error = refused[0].json()["error"]
        assert error["code"] == "TOO_MANY_JOBS" and error["details"]["limit"] == cap
        assert "rechenintensive" in error["message"] and "heavy" in error["message_en"]
        light_requests_answer(api, other, slug, pool)
        gate.open()
        answers = [answer(f) for f in futures]
    ok = [r for r in answers if r.status_code == 200]
    assert len(ok) == cap and all(r.content.startswith(b"%PDF-") for r in ok)


# --- no query on the event loop --------------------------------------------------------------------------------


def _routes(api: Api) -> dict[str, Callable[[], Any]]:
    """One request of each route that computes in a worker (and the light ones beside them)."""
    teacher, student = api.user("instructor"), api.user()
    course = course_with(api, teacher, student)
    slug = builtin_exercise(api)
    sheets = assign(api, teacher, course, [slug], exam=False)
    client, who = api.client, auth(student)
    return {
        "check": lambda: client.post("/api/v1/check", json={"program": GOOD, "exercise": slug}, headers=who),
        "run": lambda: client.post("/api/v1/run", json={"program": GOOD, "exercise": slug}, headers=who),
        "simulate": lambda: client.post(
            "/api/v1/simulate", json={"program": GOOD, "exercise": slug}, headers=who
        ),
        "picture": lambda: client.get(f"/api/v1/exercises/{slug}/picture.png", headers=who),
        "drawing": lambda: client.get(f"/api/v1/exercises/{slug}/drawing.svg", headers=who),
        "sheet": lambda: client.get(f"/api/v1/exercises/{slug}/sheet.pdf", headers=who),
        "assignment sheets": lambda: client.get(f"/api/v1/assignments/{sheets}/sheets.pdf", headers=who),
        "example drawing": lambda: client.get(f"/api/v1/examples/{slug}/drawing.svg"),
        "scene": lambda: client.post(
            f"/api/v1/viz/{viz_token(api, student)}/scene",
            json={"program": GOOD, "exercise": slug},
            headers=who,
        ),
        "deviation": lambda: client.post(
            f"/api/v1/viz/{viz_token(api, student)}/deviation",
            json={"program": reference_of(), "exercise": slug},
            headers=who,
        ),
        "3d picture": lambda: client.post(
            "/api/v1/viz/picture.png", json={"program": GOOD, "exercise": slug}, headers=who
        ),
        "results": lambda: client.get("/api/v1/results", headers=auth(teacher)),
        "insights": lambda: client.get(f"/api/v1/assignments/{sheets}/insights", headers=auth(teacher)),
        "submission": lambda: client.post(
            "/api/v1/submissions", json={"exercise": slug, "program": GOOD}, headers=who
        ),
        "import": lambda: client.post(
            "/api/v1/exercises/import",
            content=exercise_file(unique("loop-")).encode(),
            headers={**auth(teacher), "Content-Type": "application/yaml"},
        ),
    }


# services.create_submission and services.import_exercise still read and write on the event loop around their
# worker call (their split into a threadpool part before and after is with the services' owners)
ON_THE_LOOP_STILL: set[str] = set()
ROUTES = [
    "check",
    "run",
    "simulate",
    "picture",
    "drawing",
    "sheet",
    "assignment sheets",
    "example drawing",
    "scene",
    "deviation",
    "3d picture",
    "results",
    "insights",
    "submission",
    "import",
]


@pytest.mark.parametrize(
    "route",
    [
        pytest.param(
            r, marks=pytest.mark.xfail(strict=True, reason="queries on the event loop in server/services.py")
        )
        if r in ON_THE_LOOP_STILL
        else r
        for r in ROUTES
    ],
)
def test_no_request_queries_the_database_on_the_event_loop(loaded: Api, route: str) -> None:
    """A synchronous query on the event loop stops every other request while it waits for the database or for a
    free pooled connection (the issue: /healthz took 119.5 s). Async routes do their database work in the
    threadpool; plain `def` routes run there anyway."""
    call = _routes(loaded)[route]
    with queries_on_the_loop(loaded.client) as seen:
        r = call()
    assert r.status_code in (200, 201), r.text
    assert seen.statements == []
