"""Every route that takes an exercise or a submission, driven through the moments of an exercise — practice, an
exam of the course upcoming, running, ended and held, released — by every kind of caller, with one expected
answer per cell (server/access.py decides them all; docs/server.md, "Exams", states the rules).

Callers: S a student of the course; O a student of another course; T the course's instructor; I an account whose
role is instructor (as every platform user once launched as Instructor) sitting the course as a student; A nobody
logged in (free practice on); K the API key of another student of the course (acting for that student); X the
operator's key (no owner) naming a platform's learner, a trainee the server cannot know.

The exam is an exam of the defaults: no live messages, no 3D, no hints, no solution, no free practice, one
submission. A cell reads "200", "403:CODE", "201:graded" (score shown), "201:withheld" (stored, no score while
an exam withholds the exercise), "201:held" (an exam's: nothing but "handed in"), "update" / "4403:CODE" (the live
socket), "-" (nothing to ask yet)."""

from __future__ import annotations

import json
from typing import Any

import pytest
from exam_helpers import assign, course_with, finalize, release, shift
from server_helpers import GOOD, Api, auth, builtin_exercise
from starlette.websockets import WebSocketDisconnect

from server import repository as repo
from server.models import SCOPES

CALLERS = ("S", "O", "T", "I", "A", "K", "X")
ROUTES = ("submit", "hints", "solution", "draft", "check", "deviation", "live", "exam_grade")
OK = {c: "200" for c in CALLERS}


def row(**cells: str) -> dict[str, str]:
    assert set(cells) == set(CALLERS)
    return dict(cells)


# who the exam concerns: S, I and K (course students); A and X are not known, so every unreleased exam counts
# practice and released: nothing of this exam restricts anybody
FREE: dict[str, dict[str, str]] = {
    "hints": row(S="200", O="200", T="200", I="200", A="401", K="200", X="200"),
    "solution": row(S="200", O="200", T="200", I="200", A="401", K="200", X="403:SOLUTION_AFTER_SUBMISSION"),
    "draft": row(
        S="200:practice",
        O="200:practice",
        T="200:practice",
        I="200:practice",
        A="401",
        K="403:DRAFTS_USERS_ONLY",
        X="403:DRAFTS_USERS_ONLY",
    ),
    "submit": row(
        S="201:graded",
        O="201:graded",
        T="201:graded",
        I="201:graded",
        A="401",
        K="201:graded",
        X="201:graded",
    ),
    "check": OK,
    "deviation": OK,
    "live": {c: "update" for c in CALLERS},
}
# upcoming and held: the exam withholds the exercise's reference from the course's students (and the unknown)
WITHHELD: dict[str, dict[str, str]] = {
    "hints": row(
        S="403:EXAM_WITHHELD",
        O="200",
        T="200",
        I="403:EXAM_WITHHELD",
        A="401",
        K="403:EXAM_WITHHELD",
        X="403:EXAM_WITHHELD",
    ),
    "solution": row(
        S="403:EXAM_WITHHELD",
        O="200",
        T="200",
        I="403:EXAM_WITHHELD",
        A="401",
        K="403:EXAM_WITHHELD",
        X="403:EXAM_WITHHELD",
    ),
    "draft": FREE["draft"],
    "submit": row(
        S="201:withheld",
        O="201:graded",
        T="201:graded",
        I="201:withheld",
        A="401",
        K="201:withheld",
        X="201:withheld",
    ),
    "check": OK,
    "deviation": row(
        S="403:EXAM_WITHHELD",
        O="200",
        T="200",
        I="403:EXAM_WITHHELD",
        A="403:EXAM_WITHHELD",
        K="403:EXAM_WITHHELD",
        X="403:EXAM_WITHHELD",
    ),
    "live": FREE["live"],
}
NONE_YET = {c: "-" for c in CALLERS}
HELD = row(S="held", O="404", T="graded", I="404", A="401", K="404", X="404")  # S's exam submission
EXPECTED: dict[str, dict[str, dict[str, str]]] = {
    "practice": {**FREE, "exam_grade": NONE_YET},
    "upcoming": {**WITHHELD, "exam_grade": NONE_YET},
    "running": {
        "hints": row(
            S="403:EXAM_RUNNING",
            O="200",
            T="200",
            I="403:EXAM_RUNNING",
            A="401",
            K="403:EXAM_RUNNING",
            X="403:EXAM_EXERCISE_LOCKED",
        ),
        "solution": row(
            S="403:EXAM_RUNNING",
            O="200",
            T="200",
            I="403:EXAM_RUNNING",
            A="401",
            K="403:EXAM_RUNNING",
            X="403:EXAM_EXERCISE_LOCKED",
        ),
        "draft": row(
            S="200:exam",
            O="200:practice",
            T="200:practice",
            I="200:exam",
            A="401",
            K="403:DRAFTS_USERS_ONLY",
            X="403:DRAFTS_USERS_ONLY",
        ),
        "submit": row(
            S="201:held",
            O="201:graded",
            T="201:graded",
            I="201:held",
            A="401",
            K="201:held",
            X="403:EXAM_EXERCISE_LOCKED",
        ),
        "check": row(
            S="403:EXAM_RUNNING",
            O="200",
            T="200",
            I="403:EXAM_RUNNING",
            A="403:EXAM_EXERCISE_LOCKED",
            K="403:EXAM_RUNNING",
            X="403:EXAM_EXERCISE_LOCKED",
        ),
        "deviation": row(
            S="403:EXAM_RUNNING",
            O="200",
            T="200",
            I="403:EXAM_RUNNING",
            A="403:EXAM_EXERCISE_LOCKED",
            K="403:EXAM_RUNNING",
            X="403:EXAM_EXERCISE_LOCKED",
        ),
        "live": row(
            S="4403:EXAM_RUNNING",
            O="update",
            T="update",
            I="4403:EXAM_RUNNING",
            A="4403:EXAM_EXERCISE_LOCKED",
            K="4403:EXAM_RUNNING",
            X="4403:EXAM_EXERCISE_LOCKED",
        ),
        "exam_grade": HELD,  # the one S made in this moment
    },
    "held": {**WITHHELD, "exam_grade": HELD},
    "released": {
        **FREE,
        "exam_grade": row(S="graded", O="404", T="graded", I="404", A="401", K="404", X="404"),
    },
}


class Callers:
    """The seven callers: their request headers, 3D tokens, and what they answer per route."""

    def __init__(self, api: Api, slug: str) -> None:
        self.api, self.slug = api, slug
        self.teacher = api.user("instructor")
        s, k_owner, other = api.user(), api.user(), api.user()
        inst = api.user("instructor")  # an instructor account …
        self.course = course_with(api, self.teacher, s, k_owner)
        with api.app.state.db.session() as db:  # … that a platform launch made a student of this course
            user = repo.user_by_name(db, inst["name"])
            assert user is not None
            repo.add_member(db, self.course, user.id, "student")
        course_with(api, api.user("instructor"), other)
        self.headers: dict[str, dict[str, str]] = {
            "S": auth(s),
            "O": auth(other),
            "T": auth(self.teacher),
            "I": auth(inst),
            "A": {},
            "K": api.api_key(list(SCOPES), k_owner),
            "X": api.api_key(list(SCOPES)),
        }
        self.tokens = {c: self._viz_token(c) for c in CALLERS}
        self.exam_submission: int | None = None

    def _viz_token(self, caller: str) -> str:
        r = self.api.client.post("/api/v1/viz", headers=self.headers[caller])
        assert r.status_code == 201, r.text
        return str(r.json()["token"])

    @staticmethod
    def _code(r: Any) -> str:
        if r.status_code < 300:
            return str(r.status_code)
        body = r.json()
        return f"{r.status_code}:{body['error']['code']}" if r.status_code == 403 else str(r.status_code)

    def answer(self, route: str, caller: str) -> str:
        client, h, slug = self.api.client, self.headers[caller], self.slug
        if route == "hints":
            return self._code(client.get(f"/api/v1/exercises/{slug}/hints/1", headers=h))
        if route == "solution":
            return self._code(client.get(f"/api/v1/exercises/{slug}/solution", headers=h))
        if route == "draft":
            r = client.put(f"/api/v1/exercises/{slug}/draft", json={"program": GOOD}, headers=h)
            return (
                f"200:{'practice' if r.json()['assignment'] is None else 'exam'}"
                if r.is_success
                else self._code(r)
            )
        if route == "submit":
            body: dict[str, Any] = {"exercise": slug, "program": GOOD}
            if caller == "X":
                body["external_user"] = "moodle-4711"
            r = client.post("/api/v1/submissions", json=body, headers=h)
            if not r.is_success:
                return self._code(r)
            out = r.json()
            if caller == "S" and out["held"]:
                self.exam_submission = out["id"]
            return "201:held" if out["held"] else "201:graded" if out["score"] is not None else "201:withheld"
        if route == "check":
            return self._code(
                client.post("/api/v1/check", json={"program": GOOD, "exercise": slug}, headers=h)
            )
        if route == "deviation":
            return self._code(
                client.post(
                    f"/api/v1/viz/{self.tokens[caller]}/deviation",
                    json={"program": GOOD, "exercise": slug},
                    headers=h,
                )
            )
        if route == "live":
            return self._live(h)
        if route == "exam_grade":
            if self.exam_submission is None:
                return "-"
            r = client.get(f"/api/v1/submissions/{self.exam_submission}", headers=h)
            if not r.is_success:
                return self._code(r)
            return "held" if r.json()["held"] else "graded" if r.json()["score"] is not None else "withheld"
        raise AssertionError(route)

    def _live(self, headers: dict[str, str]) -> str:
        query = f"?token={headers['Authorization'].split()[1]}" if "Authorization" in headers else ""
        extra = {k: v for k, v in headers.items() if k != "Authorization"}
        try:
            with self.api.client.websocket_connect(f"/api/v1/live{query}", headers=extra) as ws:
                ws.send_text(json.dumps({"type": "open", "version": 0, "text": GOOD, "exercise": self.slug}))
                while True:  # an error frame comes before the close
                    msg = json.loads(ws.receive_text())
                    if msg["type"] == "update":
                        return "update"
        except WebSocketDisconnect as closed:
            return f"{closed.code}:{closed.reason}"

    def table(self) -> dict[str, dict[str, str]]:
        return {route: {c: self.answer(route, c) for c in CALLERS} for route in ROUTES}


def test_every_route_in_every_moment_for_every_caller(api: Api) -> None:
    slug = builtin_exercise(api, hints=[{"de": "Erst Z, dann X.", "en": "Z first, then X."}])
    callers = Callers(api, slug)
    seen: dict[str, dict[str, dict[str, str]]] = {"practice": callers.table()}
    exam = assign(api, callers.teacher, callers.course, [slug], start=60, minutes=90)
    seen["upcoming"] = callers.table()
    shift(api, exam, 61)
    seen["running"] = callers.table()
    shift(api, exam, 91)
    finalize(api)  # everybody in the exam submitted by hand: nothing left to submit
    seen["held"] = callers.table()
    release(api, callers.teacher, exam)
    seen["released"] = callers.table()
    for moment, expected in EXPECTED.items():
        assert seen[moment] == expected, moment


@pytest.mark.parametrize("moment", ["upcoming", "held"])
def test_withheld_practice_grades_come_back_with_the_release(api: Api, moment: str) -> None:
    """Rule 3 withholds, it does not drop: the practice submissions made while the exam withheld the exercise show
    their score once the results are released."""
    slug = builtin_exercise(api)
    teacher, student, admin = api.user("instructor"), api.user(), api.user("admin")
    course = course_with(api, teacher, student)
    exam = assign(api, teacher, course, [slug], start=60 if moment == "upcoming" else -100, minutes=90)
    if moment == "held":
        finalize(api)
    r = api.client.post(
        "/api/v1/submissions", json={"exercise": slug, "program": GOOD}, headers=auth(student)
    )
    assert r.status_code == 201 and r.json()["score"] is None and r.json()["grading"] is None
    history = api.client.get(f"/api/v1/me/submissions?exercise={slug}", headers=auth(student)).json()
    assert history[0]["score"] is None and history[0]["criteria"] == []
    # it is graded all along (an admin sees it; the course's instructor does not see practice outside the course)
    assert (
        api.client.get(f"/api/v1/submissions/{r.json()['id']}", headers=auth(admin)).json()["score"]
        is not None
    )
    if moment == "upcoming":
        shift(api, exam, 151)
        finalize(api)
    release(api, teacher, exam)
    assert (
        api.client.get(f"/api/v1/submissions/{r.json()['id']}", headers=auth(student)).json()["score"]
        is not None
    )
