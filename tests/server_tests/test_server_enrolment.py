"""Who may enrol whom, and what an instructor then sees (the security issue, points 1, 8 and 10): an instructor adds
only the students they manage — nobody else, never an instructor or admin as a student, and the answer does not
tell an existing name from a missing one; joining with a code is rate-limited and fails alike for every reason;
an instructor sees their courses' work and their managed students' practice, not a student's work elsewhere; the
reference of another instructor's exercise follows its policy."""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any

from exam_helpers import assign, course_with, shift
from server_helpers import GOOD, Api, auth, builtin_exercise, error_code, unique


@contextmanager
def _setting(api: Api, name: str, value: Any) -> Iterator[None]:
    old = getattr(api.settings, name)
    setattr(api.settings, name, value)
    try:
        yield
    finally:
        setattr(api.settings, name, old)


def _managed(api: Api, instructor: dict[str, str]) -> dict[str, str]:
    """A student the instructor makes (and so manages)."""
    name = unique("eigen")
    r = api.client.post(
        "/api/v1/users",
        json={"username": name, "password": "geheim-genug", "role": "student"},
        headers=auth(instructor),
    )
    assert r.status_code == 201, r.text
    r = api.client.post("/api/v1/auth/token", data={"username": name, "password": "geheim-genug"})
    return {"name": name, "Authorization": f"Bearer {r.json()['access_token']}"}


def _enrol(api: Api, instructor: dict[str, str], course: int, name: str, role: str = "student") -> Any:
    return api.client.post(
        f"/api/v1/courses/{course}/members", json={"username": name, "role": role}, headers=auth(instructor)
    )


def test_an_instructor_enrols_only_the_students_they_manage(api: Api) -> None:
    mallory, other_teacher, admin = api.user("instructor"), api.user("instructor"), api.user("admin")
    victim = api.user()
    other_course = course_with(api, other_teacher, victim)
    slug = builtin_exercise(api)
    exam = assign(api, other_teacher, other_course, [slug])
    held = api.client.post(
        "/api/v1/submissions", json={"exercise": slug, "program": GOOD}, headers=auth(victim)
    )
    assert held.status_code == 201 and held.json()["held"] is True
    shift(api, exam, 91)  # over, its results not released yet
    course = course_with(api, mallory)
    assign(
        api, mallory, course, [builtin_exercise(api)], minutes=24 * 60
    )  # a 24-hour exam to lock people out

    answers = {
        who: _enrol(api, mallory, course, name)
        for who, name in (
            ("another course's student", victim["name"]),
            ("another instructor", other_teacher["name"]),
            ("an admin", admin["name"]),
            ("nobody", unique("gibt-es-nicht")),
        )
    }
    for who, r in answers.items():
        assert r.status_code == 404 and error_code(r) == "USER_NOT_FOUND", who
    # one answer whether the name exists or not: the same shape, only the name differs
    shapes = {
        r.json()["error"]["message"].replace(n, "…")
        for n, r in zip(
            (victim["name"], other_teacher["name"], admin["name"]), list(answers.values())[:3], strict=True
        )
    }
    assert len(shapes) == 1
    # so mallory sees nothing of the victim's, and the victim works on
    assert (
        api.client.get(f"/api/v1/submissions/{held.json()['id']}", headers=auth(mallory)).status_code == 404
    )
    assert api.client.post("/api/v1/check", json={"program": GOOD}, headers=auth(victim)).status_code == 200
    assert api.client.post("/api/v1/check", json={"program": GOOD}, headers=auth(admin)).status_code == 200
    # the instructor's own student is fine; an admin adds any student account, never an instructor or admin
    own = _managed(api, mallory)
    assert _enrol(api, mallory, course, own["name"]).status_code == 201
    assert _enrol(api, admin, course, victim["name"]).status_code == 201
    for name in (other_teacher["name"], admin["name"]):
        r = _enrol(api, admin, course, name)
        assert r.status_code == 422 and error_code(r) == "NOT_A_STUDENT"
    # now in mallory's course: still nothing of what the victim did in the other course (its exam included)
    assert (
        api.client.get(f"/api/v1/submissions/{held.json()['id']}", headers=auth(mallory)).status_code == 404
    )
    listed = {s["id"] for s in api.client.get("/api/v1/submissions", headers=auth(mallory)).json()}
    assert held.json()["id"] not in listed


def test_an_instructor_sees_course_work_and_managed_practice_only(api: Api) -> None:
    teacher = api.user("instructor")
    managed, joined = _managed(api, teacher), api.user()
    course = course_with(api, teacher, joined)
    assert _enrol(api, teacher, course, managed["name"]).status_code == 201
    set_, free = builtin_exercise(api), builtin_exercise(api)
    assign(api, teacher, course, [set_], exam=False, start=-1, minutes=600)

    def submit(who: dict[str, str], slug: str) -> int:
        r = api.client.post(
            "/api/v1/submissions", json={"exercise": slug, "program": GOOD}, headers=auth(who)
        )
        assert r.status_code == 201, r.text
        return int(r.json()["id"])

    seen = {
        (who, slug): api.client.get(
            f"/api/v1/submissions/{submit(s, slug)}", headers=auth(teacher)
        ).status_code
        for who, s in (("managed", managed), ("joined", joined))
        for slug in (set_, free)
    }
    assert seen == {
        ("managed", set_): 200,
        ("managed", free): 200,
        ("joined", set_): 200,
        ("joined", free): 404,
    }


def test_enrolling_by_name_is_rate_limited(api: Api) -> None:
    teacher = api.user("instructor")
    course = course_with(api, teacher)
    with _setting(api, "rate_enrol_per_minute", 3):
        codes = [_enrol(api, teacher, course, unique("rate")).status_code for _ in range(4)]
    assert codes == [404, 404, 404, 429]


def test_joining_fails_alike_and_is_rate_limited(api: Api) -> None:
    teacher, student, other_teacher = api.user("instructor"), api.user(), api.user("instructor")
    r = api.client.post("/api/v1/courses", json={"name": "Klasse"}, headers=auth(teacher))
    code = r.json()["join_code"]
    wrong = api.client.post("/api/v1/courses/join", json={"code": "NOPE1234"}, headers=auth(student))
    valid_but_not_a_student = api.client.post(
        "/api/v1/courses/join", json={"code": code}, headers=auth(other_teacher)
    )
    assert wrong.status_code == valid_but_not_a_student.status_code == 404
    assert wrong.json() == valid_but_not_a_student.json()
    with _setting(api, "rate_join_per_minute", 5):
        codes = [
            api.client.post(
                "/api/v1/courses/join", json={"code": f"NOPE{i:04d}"}, headers=auth(student)
            ).status_code
            for i in range(6)
        ]
    assert codes == [404] * 5 + [429]
    # per address, whoever asks (a class of accounts guessing together)
    guessers = [api.user() for _ in range(4)]
    with _setting(api, "rate_join_address_per_minute", 3):
        codes = [
            api.client.post("/api/v1/courses/join", json={"code": "NOPE9999"}, headers=auth(g)).status_code
            for g in guessers
        ]
    assert codes == [404, 404, 404, 429]
    api.app.state.limiter.reset()
    assert (
        api.client.post("/api/v1/courses/join", json={"code": code}, headers=auth(student)).status_code == 200
    )


def test_another_instructors_reference_follows_its_policy(api: Api) -> None:
    owner, other, admin = api.user("instructor"), api.user("instructor"), api.user("admin")
    slug = api.exercise(owner)["slug"]
    assert api.client.patch(
        f"/api/v1/exercises/{slug}", json={"title_de": "Geheim"}, headers=auth(owner)
    ).is_success

    def status(who: dict[str, str]) -> tuple[int, str | None]:
        r = api.client.get(f"/api/v1/exercises/{slug}/solution", headers=auth(who))
        return r.status_code, None if r.is_success else error_code(r)

    assert status(owner) == (200, None) and status(admin) == (200, None)
    assert status(other) == (403, "SOLUTION_AFTER_SUBMISSION")  # as for a student: after their own submission
    assert (
        api.client.get(f"/api/v1/exercises/{slug}", headers=auth(other)).json()["reference_program"] is None
    )
