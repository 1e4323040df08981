"""What a trainee's submissions may store: at most 200 diagnostics per submission (with the count of all of them),
full detail for the newest 50 per user and exercise and for the best one (of practice and of each assignment),
older ones summarised — their diagnostics dropped, their program, counts and grade kept, which is what the history,
the results tables and the class insights show. The results tables and the insights read only the columns they
show."""

from __future__ import annotations

import json
import threading
from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any

from exam_helpers import assign, course_with
from server_helpers import BAD, Api, auth, builtin_exercise
from sqlalchemy import event

from server import repository as repo
from server.jobs import STORED_DIAGNOSTICS

# one PAL-E010 (decimal comma) in every line: the interpreter stops at its 1,000 diagnostics
FLOOD = "N10 T1 TC1 M6\n" + "G1 X1,5\n" * 1500 + "M30\n"


def test_a_submission_stores_at_most_200_diagnostics_and_how_many_there_were(api: Api) -> None:
    student, slug = api.user(), builtin_exercise(api)
    assert len(FLOOD) < api.settings.max_program_chars
    r = api.client.post(
        "/api/v1/submissions", json={"exercise": slug, "program": FLOOD}, headers=auth(student)
    )
    assert r.status_code == 201, r.text
    body = r.json()
    assert body["error_count"] >= 999  # the counts are of every diagnostic of the run
    assert len(body["diagnostics"]) == STORED_DIAGNOSTICS == 200
    assert [d["line"] for d in body["diagnostics"][:3]] == [2, 3, 4]  # the first ones, in program order
    with api.app.state.db.session() as db:
        stored = repo.submission_by_id(db, body["id"])
        assert stored is not None
        assert len(stored.result["diagnostics"]) == 200
        assert stored.result["summary"]["diagnostics"] == 1000  # the interpreter's 1,000 of them
        assert len(json.dumps(stored.result)) < 150_000  # was 0.55 MB
    detail = api.client.get(f"/api/v1/submissions/{body['id']}", headers=auth(student)).json()
    assert len(detail["diagnostics"]) == 200 and detail["summary"]["moves"] == body["summary"]["moves"]


def _stored(api: Api, user: str, slug: str, score: int, assignment: int | None = None) -> int:
    """A graded submission with three diagnostics, stored as the server stores one (without grading it)."""
    diagnostics = [
        {
            "code": "PAL-E010",
            "severity": "error",
            "line": 2,
            "column": 1,
            "message": "Komma",
            "message_en": "comma",
        }
        for _ in range(3)
    ]
    grading = {
        "score": score,
        "max_score": 100,
        "criteria": [
            {
                "id": "geometry",
                "status": "passed" if score == 100 else "failed",
                "points": score,
                "max_points": 100,
                "lines": [2],
                "message": "Geometrie",
                "message_en": "geometry",
            }
        ],
    }
    with api.app.state.db.session() as db:
        u, e = repo.user_by_name(db, user), repo.exercise_by_slug(db, slug)
        assert u is not None and e is not None
        s = repo.create_submission(
            db,
            exercise_id=e.id,
            user_id=u.id,
            program=BAD,
            dialect="pal-mill",
            error_count=3,
            warning_count=0,
            assignment_id=assignment,
            result={
                "diagnostics": diagnostics,
                "summary": {"moves": 1, "rapid": 0, "feed": 1, "arc": 0, "tool_changes": 1, "dwells": 0},
            },
            grading=grading,
        )
        return s.id


def _diagnostics(api: Api, submission: int) -> int:
    with api.app.state.db.session() as db:
        s = repo.submission_by_id(db, submission)
        assert s is not None
        return len(s.result["diagnostics"])


def test_older_submissions_are_summarised_the_newest_50_and_the_best_keep_their_detail(api: Api) -> None:
    keep = api.settings.submissions_with_details
    assert keep == 50
    teacher, student = api.user("instructor"), api.user()
    slug = builtin_exercise(api)
    course = course_with(api, teacher, student)
    # a practice assignment that has ended: the new submissions below are practice (an open one would take them)
    assignment = assign(api, teacher, course, [slug], exam=False, start=-120, minutes=60)
    best = _stored(api, student["name"], slug, 90)  # the best practice submission, the oldest of all
    best_in_assignment = _stored(api, student["name"], slug, 70, assignment)
    old = [_stored(api, student["name"], slug, 40) for _ in range(5)]
    newer = [_stored(api, student["name"], slug, 40) for _ in range(keep - 1)]
    other_exercise = builtin_exercise(api)  # another exercise's submissions count on their own
    elsewhere = [_stored(api, student["name"], other_exercise, 10) for _ in range(3)]

    r = api.client.post("/api/v1/submissions", json={"exercise": slug, "program": BAD}, headers=auth(student))
    assert r.status_code == 201 and r.json()["score"] < 90
    # the newest 50 (49 stored + this one) keep everything; of the older ones the best of practice and the best of
    # the assignment keep their detail, the others are summarised
    assert [_diagnostics(api, s) for s in old] == [0] * 5
    assert _diagnostics(api, best) == 3 and _diagnostics(api, best_in_assignment) == 3
    assert {_diagnostics(api, s) for s in newer} == {3}
    assert {_diagnostics(api, s) for s in elsewhere} == {3}
    with api.app.state.db.session() as db:
        summarised = repo.submission_by_id(db, old[0])
        assert summarised is not None
        assert (
            summarised.error_count == 3
            and summarised.grading is not None
            and summarised.grading["score"] == 40
        )
        assert summarised.program == BAD and summarised.result["summary"]["diagnostics"] == 3
        assert summarised.result["summary"]["moves"] == 1

    # the history, the results matrices and the insights show what they showed
    history = api.client.get(f"/api/v1/me/submissions?exercise={slug}", headers=auth(student)).json()
    assert len(history) == keep + 7
    summarised_entry = next(h for h in history if h["id"] == old[0])
    assert summarised_entry["score"] == 40 and summarised_entry["error_count"] == 3
    assert summarised_entry["program"] == BAD and summarised_entry["criteria"][0]["id"] == "geometry"
    detail = api.client.get(f"/api/v1/submissions/{old[0]}", headers=auth(student)).json()
    assert detail["diagnostics"] == [] and detail["error_count"] == 3 and detail["score"] == 40
    matrix = api.client.get("/api/v1/results", headers=auth(api.user("admin"))).json()
    row = next(t for t in matrix["trainees"] if t["username"] == student["name"])
    assert row["results"][slug]["best_score"] == 90 and row["results"][slug]["best_submission"] == best
    assert len(row["results"][slug]["submissions"]) == keep + 7
    table = api.client.get(f"/api/v1/assignments/{assignment}/results", headers=auth(teacher)).json()
    (trainee,) = table["trainees"]
    assert (
        trainee["results"][slug]["submission"] == best_in_assignment
        and trainee["results"][slug]["score"] == 70
    )
    seen = api.client.get(f"/api/v1/assignments/{assignment}/insights", headers=auth(teacher)).json()
    (exercise,) = seen["exercises"]
    assert exercise["diagnostics"][0]["code"] == "PAL-E010" and exercise["diagnostics"][0]["students"] == 1

    # one more: the submission that now falls out of the newest 50 is summarised, nothing else changes
    r = api.client.post("/api/v1/submissions", json={"exercise": slug, "program": BAD}, headers=auth(student))
    assert r.status_code == 201
    assert _diagnostics(api, newer[0]) == 0 and {_diagnostics(api, s) for s in newer[1:]} == {3}
    assert _diagnostics(api, best) == 3


@contextmanager
def statements(api: Api) -> Iterator[list[str]]:
    """The SQL the app runs while the block runs (any thread)."""
    seen: list[str] = []
    lock = threading.Lock()

    def record(conn: Any, cursor: Any, statement: str, *_: Any) -> None:
        with lock:
            seen.append(" ".join(statement.split()))

    engine = api.app.state.db.engine
    event.listen(engine, "before_cursor_execute", record)
    try:
        yield seen
    finally:
        event.remove(engine, "before_cursor_execute", record)


def test_results_and_insights_read_only_the_columns_they_show(api: Api) -> None:
    teacher, students = api.user("instructor"), [api.user() for _ in range(3)]
    slug = builtin_exercise(api)
    course = course_with(api, teacher, *students)
    assignment = assign(api, teacher, course, [slug], exam=False)
    for s in students:
        for score in (20, 60, 40):
            _stored(api, s["name"], slug, score, assignment)
    with statements(api) as seen:
        for path in (
            "/api/v1/results",
            "/api/v1/results.csv",
            f"/api/v1/assignments/{assignment}/results",
            f"/api/v1/assignments/{assignment}/results.csv",
        ):
            assert api.client.get(path, headers=auth(teacher)).status_code == 200, path
    reads = [s for s in seen if "FROM submissions" in s]
    assert reads and not [s for s in reads if "submissions.program" in s or "submissions.result" in s]

    with statements(api) as seen:
        r = api.client.get(f"/api/v1/assignments/{assignment}/insights", headers=auth(teacher))
    assert r.status_code == 200 and r.json()["exercises"][0]["students"] == 3
    heavy = [s for s in seen if "submissions.program" in s or "submissions.result" in s]
    # program and diagnostics are read for each student's best submission only, by id
    assert heavy and all("submissions.id IN" in s for s in heavy)


def test_a_learning_platforms_learners_are_counted_each_on_their_own(api: Api) -> None:
    """Submissions through an operator's key for learners of a learning platform (no account): the quota is per
    key, learner and exercise."""
    key, slug = api.api_key(["submissions:write", "submissions:read"]), builtin_exercise(api)
    made: dict[str, list[int]] = {"lms-a": [], "lms-b": []}
    for learner in ("lms-a", "lms-b", "lms-a", "lms-a"):
        r = api.client.post(
            "/api/v1/submissions",
            json={"exercise": slug, "program": BAD, "external_user": learner},
            headers=key,
        )
        assert r.status_code == 201, r.text
        made[learner].append(r.json()["id"])
    with api.app.state.db.session() as db:
        newest = repo.submission_by_id(db, made["lms-a"][-1])
        assert newest is not None
        # with room for one: learner a's two older ones (equal scores: the newest is the best) are summarised
        assert repo.summarise_submissions(db, newest, keep=1) == 2
        assert repo.summarise_submissions(db, newest, keep=1) == 0  # once
    assert [_diagnostics(api, s) > 0 for s in made["lms-a"]] == [False, False, True]
    assert _diagnostics(api, made["lms-b"][0]) > 0
