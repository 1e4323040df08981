"""Exams a school can trust (the exam-integrity issue): a retake on the same exercise, drafts that belong to their
exam, the end of an exam with a whole class, side doors that another route left open, and the submission limit
held by the database. Each test reproduces the defect as a trainee or instructor met it."""

from __future__ import annotations

import json
import threading
import time
from collections import Counter
from concurrent.futures import ThreadPoolExecutor
from datetime import UTC, datetime, timedelta
from typing import Any

import anyio
import pytest
from exam_helpers import assign, course_with, finalize, iso, release, shift
from server_helpers import BAD, GOOD, Api, auth, builtin_exercise, error_code, reference_of
from starlette.websockets import WebSocketDisconnect

from server import repository as repo
from server.courses import finalize_ended_exams
from server.jobs import HAS_SIM, job_submission
from server.models import SCOPES

REFERENCE = reference_of()


def _draft(
    api: Api, who: dict[str, str], slug: str, program: str | None = None, assignment: int | None = None
) -> Any:
    url = f"/api/v1/exercises/{slug}/draft" + (f"?assignment={assignment}" if assignment else "")
    if program is None:
        return api.client.get(url, headers=auth(who))
    return api.client.put(url, json={"program": program}, headers=auth(who))


def _submit(api: Api, who: dict[str, str], slug: str, program: str = GOOD, **extra: Any) -> Any:
    return api.client.post(
        "/api/v1/submissions", json={"exercise": slug, "program": program, **extra}, headers=auth(who)
    )


def _auto_programs(api: Api, exam: int) -> dict[int | None, str]:
    with api.app.state.db.session() as db:
        return {s.user_id: s.program for s in repo.assignment_submissions(db, exam) if s.auto}


def test_a_retake_on_the_same_exercise_stores_and_submits_its_own_drafts(api: Api) -> None:
    """Point 1: exam 1 (G1) ended, not released; exam 2 (G1 and another) runs. The new program is stored in exam 2
    and exam 2's end submits it — not exam 1's draft."""
    teacher, student = api.user("instructor"), api.user()
    course = course_with(api, teacher, student)
    g1, g2 = builtin_exercise(api), builtin_exercise(api)
    first = assign(api, teacher, course, [g1], minutes=60)
    assert _draft(api, student, g1, "N10 (Prüfung 1)\nN20 M30\n").json()["assignment"] == first
    shift(api, first, 61)  # exam 1 is over, its results held
    second = assign(api, teacher, course, [g1, g2], minutes=60)
    r = _draft(api, student, g1)
    assert r.status_code == 200 and r.json() == {**r.json(), "assignment": second, "program": None}
    r = _draft(
        api, student, g1, REFERENCE
    )  # the page saves without naming the exam: the running one takes it
    assert r.status_code == 200 and r.json()["assignment"] == second
    r = _draft(api, student, g1, assignment=first)  # while exam 2 runs, the exercise's work is exam 2's only
    assert r.status_code == 403 and error_code(r) == "EXAM_ELSEWHERE"
    shift(api, second, 61)
    finalize(api)
    user_id = _user_id(api, student)
    assert _auto_programs(api, second)[user_id] == REFERENCE
    assert _auto_programs(api, first)[user_id] == "N10 (Prüfung 1)\nN20 M30\n"
    mine = {a["id"]: a for a in api.client.get("/api/v1/me/assignments", headers=auth(student)).json()}
    assert mine[first]["status"] == "submitted" and mine[second]["status"] == "closed"  # g2 was not tried
    assert [i["auto"] for i in mine[second]["items"]] == [True, False]


def _user_id(api: Api, who: dict[str, str]) -> int:
    with api.app.state.db.session() as db:
        user = repo.user_by_name(db, who["name"])
        assert user is not None
        return user.id


def test_practice_drafts_never_enter_an_exam_and_exam_drafts_never_leave_it(api: Api) -> None:
    """Point 2: the model solution prepared in practice the day before is not the exam's start, nor submitted at
    its end; what is typed in the exam does not replace the practice draft."""
    teacher, student, empty = api.user("instructor"), api.user(), api.user()
    course = course_with(api, teacher, student, empty)
    slug = builtin_exercise(api)
    assert _draft(api, student, slug, REFERENCE).json()["assignment"] is None  # the day before
    assert _draft(api, empty, slug, REFERENCE).status_code == 200
    exam = assign(api, teacher, course, [slug])
    r = _draft(api, student, slug)
    assert r.json()["assignment"] == exam and r.json()["program"] is None  # the page starts the start program
    assert _draft(api, student, slug, assignment=exam).json()["program"] is None
    item = api.client.get("/api/v1/me/assignments", headers=auth(student)).json()[0]["items"][0]
    assert item["draft"] is False  # the practice draft is not the exam's
    assert _draft(api, student, slug, "N10 (in der Prüfung)\nN20 M30\n").json()["assignment"] == exam
    item = api.client.get("/api/v1/me/assignments", headers=auth(student)).json()[0]["items"][0]
    assert item["draft"] is True and item["submitted"] is False
    shift(api, exam, 91)
    finalize(api)
    autos = _auto_programs(api, exam)
    assert autos == {_user_id(api, student): "N10 (in der Prüfung)\nN20 M30\n"}  # `empty` typed nothing
    assert _draft(api, student, slug).json() == {
        **_draft(api, student, slug).json(),
        "assignment": None,
        "program": REFERENCE,
    }
    progress = {p["exercise"]: p for p in api.client.get("/api/v1/me/progress", headers=auth(student)).json()}
    assert progress[slug]["status"] == "draft"  # the practice draft; the exam's submission is held


def test_the_end_of_an_exam_with_a_class_grades_each_draft_once_and_reads_never_wait(
    api: Api, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Point 3: 30 trainees end at once. The pages' reads answer while the drafts are still being graded (they
    never grade: status "submitting"), two finalisers (two replicas) grade each draft exactly once."""
    teacher = api.user("instructor")
    students = [api.user() for _ in range(30)]
    course = course_with(api, teacher, *students)
    slug = builtin_exercise(api)
    exam = assign(api, teacher, course, [slug], minutes=60)
    for i, s in enumerate(students):
        assert _draft(api, s, slug, f"N10 (Azubi {i})\n{REFERENCE}").status_code == 200
    shift(api, exam, 61)

    workers = api.app.state.workers
    original = workers.call
    calls: Counter[str] = Counter()
    graded = Counter[str]()
    hold = threading.Event()

    async def counting(fn: Any, *args: Any, **kwargs: Any) -> Any:
        calls[fn.__name__] += 1
        if fn is job_submission:
            graded[args[0]] += 1
            await anyio.to_thread.run_sync(hold.wait)  # grading takes its time
        return await original(fn, *args, **kwargs)

    monkeypatch.setattr(workers, "call", counting)
    portal = api.client.portal
    assert portal is not None
    replicas = [portal.start_task_soon(finalize_ended_exams, api.app.state.db, workers) for _ in range(2)]
    try:
        deadline = time.monotonic() + 60
        while not calls["job_submission"] and time.monotonic() < deadline:
            time.sleep(0.05)  # a finaliser has begun to grade
        before = sum(calls.values())
        answers: list[Any] = []

        def read(who: dict[str, str]) -> None:
            answers.append(api.client.get("/api/v1/me/assignments", headers=auth(who)))

        readers = [threading.Thread(target=read, args=(s,)) for s in students]
        for t in readers:
            t.start()
        for t in readers:
            t.join(timeout=120)
        assert len(answers) == 30, "a read waited for the grading"
        assert all(r.status_code == 200 and r.json()[0]["status"] == "submitting" for r in answers)
        assert sum(calls.values()) == before  # the reads started no work
    finally:
        hold.set()
    made = sorted(f.result(timeout=300) for f in replicas)
    assert made == [0, 30]  # one replica took the exam, the other found it taken
    assert len(graded) == 30 and set(graded.values()) == {1}  # every draft graded exactly once
    assert len(_auto_programs(api, exam)) == 30
    assert {
        a["status"]
        for s in students[:3]
        for a in api.client.get("/api/v1/me/assignments", headers=auth(s)).json()
    } == {"submitted"}


def test_a_stopped_finaliser_is_taken_over_when_its_lease_runs_out(api: Api) -> None:
    teacher, student = api.user("instructor"), api.user()
    exam = assign(api, teacher, course_with(api, teacher, student), [builtin_exercise(api)], minutes=30)
    assert _draft(api, student, _exercise_of(api, exam), GOOD).status_code == 200
    shift(api, exam, 31)
    now = datetime.now(UTC)
    with api.app.state.db.session() as db:  # a replica claimed it and was killed
        assert repo.claim_finalizing(db, exam, now, now + timedelta(minutes=10))
    assert finalize(api) == 0
    with api.app.state.db.session() as db:
        a = repo.assignment_by_id(db, exam)
        assert a is not None
        a.finalizing_until = now - timedelta(seconds=1)
        db.commit()
    assert finalize(api) == 1


def _exercise_of(api: Api, assignment: int) -> str:
    with api.app.state.db.session() as db:
        a = repo.assignment_by_id(db, assignment)
        assert a is not None
        return str(a.exercises[0])


def test_naming_a_practice_assignment_is_no_way_around_the_exam(api: Api) -> None:
    """Point 4: while the exam runs, and after its end before the release, a practice assignment with the same
    exercise does not grade at once."""
    teacher, student = api.user("instructor"), api.user()
    course = course_with(api, teacher, student)
    slug = builtin_exercise(api)
    practice = assign(api, teacher, course, [slug], exam=False, start=-5, minutes=600)
    exam = assign(api, teacher, course, [slug])
    for _ in range(3):
        r = _submit(api, student, slug, assignment=practice)
        assert r.status_code == 403 and error_code(r) == "EXAM_ELSEWHERE"
        assert "laufenden Prüfung" in r.json()["error"]["message"]
    shift(api, exam, 91)
    finalize(api)
    r = _submit(api, student, slug, assignment=practice)
    assert r.status_code == 201 and r.json()["score"] is None and r.json()["grading"] is None
    release(api, teacher, exam)
    r = _submit(api, student, slug, assignment=practice)
    assert r.status_code == 201 and r.json()["score"] is not None


@pytest.mark.skipif(not HAS_SIM, reason="the simulation (numpy) is not installed")
def test_the_3d_view_its_picture_and_the_deviation_follow_the_exam(api: Api) -> None:
    """Point 5: with 3D off, neither a new 3D session, nor the picture of the stock, nor the deviation from the
    hidden reference (which could be driven to zero); with 3D on, the deviation still waits for the release."""
    teacher, student, other = api.user("instructor"), api.user(), api.user()
    course = course_with(api, teacher, student, other)
    slug = builtin_exercise(api)
    token = api.client.post("/api/v1/viz", headers=auth(student)).json()["token"]  # opened before the exam
    exam = assign(api, teacher, course, [slug])
    body = {"program": GOOD, "exercise": slug}
    for r in (
        api.client.post("/api/v1/viz", headers=auth(student)),
        api.client.post("/api/v1/viz/picture.png", json=body, headers=auth(student)),
        api.client.post(f"/api/v1/viz/{token}/deviation", json=body, headers=auth(student)),
        api.client.post(f"/api/v1/viz/{token}/layers", json={"rapid": False}, headers=auth(student)),
    ):
        assert r.status_code == 403 and error_code(r) == "EXAM_RUNNING", r.text
    api.client.patch(f"/api/v1/assignments/{exam}", json={"settings": {"viz": True}}, headers=auth(teacher))
    assert api.client.post("/api/v1/viz/picture.png", json=body, headers=auth(student)).status_code == 200
    r = api.client.post(f"/api/v1/viz/{token}/deviation", json=body, headers=auth(student))
    assert r.status_code == 403 and error_code(r) == "EXAM_WITHHELD"
    assert "freigegeben" in r.json()["error"]["message"]


def test_a_live_socket_opened_before_the_exam_stops_at_its_start(api: Api) -> None:
    """Point 6: the socket was asked on connect only; now every message is, at its moment."""
    teacher, student = api.user("instructor"), api.user()
    course = course_with(api, teacher, student)
    slug = builtin_exercise(api)
    starts = datetime.now(UTC) + timedelta(seconds=3)
    r = api.client.post(
        f"/api/v1/courses/{course}/assignments",
        headers=auth(teacher),
        json={
            "title": "Prüfung",
            "exercises": [slug],
            "mode": "exam",
            "opens_at": starts.isoformat(),
            "duration_minutes": 30,
        },
    )
    assert r.status_code == 201
    token = auth(student)["Authorization"].split()[1]
    with (
        pytest.raises(WebSocketDisconnect) as closed,
        api.client.websocket_connect(f"/api/v1/live?token={token}") as ws,
    ):
        ws.send_text(json.dumps({"type": "open", "version": 0, "text": GOOD, "exercise": slug}))
        assert json.loads(ws.receive_text())["type"] == "update"
        while datetime.now(UTC) < starts + timedelta(milliseconds=200):
            time.sleep(0.1)
        ws.send_text(json.dumps({"type": "edit", "version": 1, "line": 1, "text": "N10 G0 X1"}))
        error = json.loads(ws.receive_text())
        assert error["type"] == "error" and error["code"] == "EXAM_RUNNING" and "Uhr" in error["message"]
        ws.receive_text()
    assert closed.value.code == 4403 and closed.value.reason == "EXAM_RUNNING"


def test_nobody_logged_in_gets_an_exercise_of_a_running_exam(api: Api) -> None:
    """Point 7: free practice is for anyone, but not for an exercise a class sits an exam on right now."""
    teacher, student = api.user("instructor"), api.user()
    slug = builtin_exercise(api)
    assign(api, teacher, course_with(api, teacher, student), [slug], live_diagnostics=True, viz=True)
    body = {"program": GOOD, "exercise": slug}
    paths = ["check", "run", "viz/picture.png", *(["simulate"] if HAS_SIM else [])]
    for path in paths:
        r = api.client.post(f"/api/v1/{path}", json=body)
        assert r.status_code == 403 and error_code(r) == "EXAM_EXERCISE_LOCKED", path
        assert api.client.post(f"/api/v1/{path}", json={"program": GOOD}).status_code == 200, path
    token = api.client.post("/api/v1/viz").json()["token"]
    r = api.client.post(f"/api/v1/viz/{token}/scene", json=body)
    assert r.status_code == 403 and error_code(r) == "EXAM_EXERCISE_LOCKED"
    operator = api.api_key(list(SCOPES))
    r = api.client.post("/api/v1/submissions", json={**body, "external_user": "lms-1"}, headers=operator)
    assert r.status_code == 403 and error_code(r) == "EXAM_EXERCISE_LOCKED"


def test_a_submission_limit_holds_against_parallel_submissions(api: Api) -> None:
    """Point 8: 6 parallel submissions with a limit of 1: one is stored, five are refused with 409."""
    teacher, student = api.user("instructor"), api.user()
    slug = builtin_exercise(api)
    exam = assign(api, teacher, course_with(api, teacher, student), [slug], max_submissions=1)
    with ThreadPoolExecutor(6) as pool:
        answers = list(pool.map(lambda _: _submit(api, student, slug), range(6)))
    assert sorted(r.status_code for r in answers) == [201, 409, 409, 409, 409, 409]
    assert {error_code(r) for r in answers if r.status_code == 409} == {"ASSIGNMENT_SUBMITTED"}
    with api.app.state.db.session() as db:
        assert len(repo.assignment_submissions(db, exam)) == 1
    # a limit of 2: two stored
    other, slug2 = api.user(), builtin_exercise(api)
    exam2 = assign(api, teacher, course_with(api, teacher, other), [slug2], max_submissions=2)
    with ThreadPoolExecutor(6) as pool:
        answers = list(pool.map(lambda _: _submit(api, other, slug2), range(6)))
    assert sorted(r.status_code for r in answers) == [201, 201, 409, 409, 409, 409]
    with api.app.state.db.session() as db:
        assert sorted(s.attempt or 0 for s in repo.assignment_submissions(db, exam2)) == [1, 2]


def test_an_upcoming_exam_keeps_its_exercises_and_their_reference_to_itself(api: Api) -> None:
    """Point 9: the exercises of an upcoming exam are not listed to its trainees, and a throw-away submission
    does not unlock the reference."""
    teacher, student = api.user("instructor"), api.user()
    course = course_with(api, teacher, student)
    slug = builtin_exercise(api, hints=[{"de": "Erst Z.", "en": "Z first."}])
    exam = assign(api, teacher, course, [slug], start=24 * 60)
    mine = api.client.get("/api/v1/me/assignments", headers=auth(student)).json()[0]
    assert mine["status"] == "upcoming" and mine["exercises"] == [] and mine["items"] == []
    assert 24 * 3600 - 60 < mine["seconds_to_start"] <= 24 * 3600 and mine["seconds_left"] is None
    assert api.client.get(f"/api/v1/assignments/{exam}", headers=auth(student)).json()["exercises"] == []
    assert (
        api.client.get(f"/api/v1/courses/{course}/assignments", headers=auth(student)).json()[0]["exercises"]
        == []
    )
    assert api.client.get(f"/api/v1/assignments/{exam}", headers=auth(teacher)).json()["exercises"] == [slug]
    assert _submit(api, student, slug, BAD).status_code == 201  # the throw-away submission
    for path in ("solution", "hints/1"):
        r = api.client.get(f"/api/v1/exercises/{slug}/{path}", headers=auth(student))
        assert r.status_code == 403 and error_code(r) == "EXAM_WITHHELD", path


def test_the_role_in_the_course_decides_not_the_accounts(api: Api) -> None:
    """Point 10: an account that is an instructor elsewhere sits this course's exam as a student: no reference,
    its held grade hidden from itself."""
    teacher, sitter = api.user("instructor"), api.user("instructor")
    course = course_with(api, teacher)
    with api.app.state.db.session() as db:
        repo.add_member(db, course, _user_id(api, sitter), "student")
    slug = builtin_exercise(api)
    exam = assign(api, teacher, course, [slug])
    r = api.client.get(f"/api/v1/exercises/{slug}/solution", headers=auth(sitter))
    assert r.status_code == 403 and error_code(r) == "EXAM_RUNNING"
    r = _submit(api, sitter, slug, REFERENCE)
    assert r.status_code == 201 and r.json()["held"] is True and r.json()["score"] is None
    assert (
        api.client.get(f"/api/v1/submissions/{r.json()['id']}", headers=auth(sitter)).json()["grading"]
        is None
    )
    assert (
        api.client.get(f"/api/v1/submissions/{r.json()['id']}", headers=auth(teacher)).json()["score"] == 100
    )
    shift(api, exam, 91)
    mine = api.client.get("/api/v1/me/assignments", headers=auth(sitter)).json()[0]
    assert mine["items"][0]["score"] is None and mine["items"][0]["program"] is None


def test_a_held_submission_says_handed_in_and_nothing_else_through_any_route(api: Api) -> None:
    """Point 11: a student's API key submits into the exam (held); its answer has no diagnostics, counts or
    summary, nor has the stored submission until the release."""
    teacher, student = api.user("instructor"), api.user()
    slug = builtin_exercise(api)
    exam = assign(api, teacher, course_with(api, teacher, student), [slug])
    key = api.api_key(list(SCOPES), student)
    r = api.client.post("/api/v1/submissions", json={"exercise": slug, "program": BAD}, headers=key)
    assert r.status_code == 201, r.text
    held = r.json()
    assert held["held"] is True
    assert {
        k: held[k]
        for k in ("grading", "score", "diagnostics", "error_count", "warning_count", "summary", "lms")
    } == dict.fromkeys(("grading", "score", "diagnostics", "error_count", "warning_count", "summary", "lms"))
    for who in (key, auth(student)):
        again = api.client.get(f"/api/v1/submissions/{held['id']}", headers=who).json()
        assert again["held"] is True and again["error_count"] is None and again["diagnostics"] is None
        listed = [
            s for s in api.client.get("/api/v1/submissions", headers=who).json() if s["id"] == held["id"]
        ]
        assert listed[0]["summary"] is None and listed[0]["score"] is None
    history = api.client.get(f"/api/v1/me/submissions?exercise={slug}", headers=auth(student)).json()
    assert history[0]["held"] is True and history[0]["error_count"] is None and history[0]["criteria"] == []
    r = api.client.post("/api/v1/check", json={"program": GOOD, "exercise": slug}, headers=key)
    assert r.status_code == 403 and error_code(r) == "EXAM_RUNNING"
    teacher_view = api.client.get(f"/api/v1/submissions/{held['id']}", headers=auth(teacher)).json()
    assert teacher_view["error_count"] == 1 and teacher_view["diagnostics"]
    shift(api, exam, 91)
    finalize(api)
    release(api, teacher, exam)
    after = api.client.get(f"/api/v1/submissions/{held['id']}", headers=key).json()
    assert after["held"] is False and after["error_count"] == 1 and after["diagnostics"]


def test_exam_times_in_messages_are_german(api: Api) -> None:
    teacher, student = api.user("instructor"), api.user()
    assign(api, teacher, course_with(api, teacher, student), [builtin_exercise(api)])
    r = api.client.post("/api/v1/check", json={"program": GOOD}, headers=auth(student))
    message = r.json()["error"]["message"]
    assert r.status_code == 403 and "T" not in message.split("bis ")[1][:16] and " Uhr" in message
    assert iso(0)[:4] in message  # the year, in a German date (TT.MM.JJJJ HH:MM)


def test_migration_0009_keeps_one_practice_draft_and_adds_exam_drafts(tmp_path: Any) -> None:
    """Drafts made before 0009 are practice drafts; the database holds one practice draft per user and exercise
    and one per exam besides; going back drops the exam drafts only."""
    from alembic import command
    from sqlalchemy import create_engine, text
    from sqlalchemy.exc import IntegrityError

    from server.db import alembic_config

    url = f"sqlite:///{tmp_path / 'm.db'}"
    cfg = alembic_config(url)
    command.upgrade(cfg, "0008_lti_scores")
    engine = create_engine(url)
    insert = (
        "INSERT INTO drafts (user_id, exercise_id, {cols} program, updated_at) VALUES (1, 1, {vals} :p, "
        "'2026-01-01')"
    )
    with engine.begin() as conn:
        conn.execute(
            text(
                "INSERT INTO users (id, username, password_hash, role, created_at, token_version) "
                "VALUES (1, 'anna', 'x', 'student', '2026-01-01', 0)"
            )
        )
        conn.execute(
            text(
                "INSERT INTO exercises (id, slug, title_de, title_en, task_de, task_en, dialect, "
                "reference_program, builtin, created_at, updated_at) VALUES (1, 'g1', 'G1', '', '', '', "
                "'pal-mill', '', 1, '2026-01-01', '2026-01-01')"
            )
        )
        conn.execute(text(insert.format(cols="", vals="")), {"p": "N10 (geübt)"})
    command.upgrade(cfg, "head")
    with engine.begin() as conn:
        conn.execute(
            text("INSERT INTO courses (id, name, join_code, created_at) VALUES (1, 'K', 'ABC', '2026-01-01')")
        )
        conn.execute(
            text(
                "INSERT INTO assignments (id, course_id, title, exercises, mode, late, opens_at, deadline, "
                "settings, created_at) VALUES (7, 1, 'P', '[\"g1\"]', 'exam', 'refuse', '2026-01-01', "
                "'2026-01-02', '{}', '2026-01-01')"
            )
        )
        conn.execute(text(insert.format(cols="assignment_id,", vals="7,")), {"p": "N10 (Prüfung)"})
        assert conn.execute(text("SELECT assignment_id, program FROM drafts ORDER BY id")).all() == [
            (None, "N10 (geübt)"),
            (7, "N10 (Prüfung)"),
        ]
    for cols, vals in (("", ""), ("assignment_id,", "7,")):
        with pytest.raises(IntegrityError), engine.begin() as conn:
            conn.execute(text(insert.format(cols=cols, vals=vals)), {"p": "zweiter"})
    command.downgrade(cfg, "0008_lti_scores")
    with engine.begin() as conn:
        assert conn.execute(text("SELECT program FROM drafts")).all() == [("N10 (geübt)",)]
    command.upgrade(cfg, "head")
    engine.dispose()


def test_free_practice_examples_do_not_hand_out_an_exams_reference(api: Api) -> None:
    """ "Beispiel laden" (GET /examples, no account) gives the published reference of a built-in exercise — not
    while the exercise is in an exam whose results are not released; then its start program, if it has one."""
    teacher, student = api.user("instructor"), api.user()
    slug = builtin_exercise(api)
    course = course_with(api, teacher, student)

    def example() -> dict[str, Any] | None:
        return next((e for e in api.client.get("/api/v1/examples").json() if e["slug"] == slug), None)

    assert example() is not None and example()["program"] == REFERENCE  # type: ignore[index]
    exam = assign(api, teacher, course, [slug], start=24 * 60)
    assert example() is None  # G1 has no start program: nothing to load while the exam withholds it
    assert api.client.get(f"/api/v1/examples/{slug}/drawing.svg").status_code == 404
    shift(api, exam, 24 * 60 + 91)
    finalize(api)
    assert example() is None
    release(api, teacher, exam)
    assert example()["program_is"] == "reference"  # type: ignore[index]
