"""The trainee's day: drafts per user and exercise, "Meine Abgaben", progress per exercise, hints one at a time,
the reference solution as the exercise allows, and the list in the order of its sets with the dialects' names."""

from __future__ import annotations

from server_helpers import GOOD, Api, auth, builtin_exercise, error_code, reference_of

from server import repository as repo

DRAFT = "N10 T1 TC1 M6\nN20 S1200 F150 M3\n"


def test_draft_round_trip_per_user(api: Api) -> None:
    slug = builtin_exercise(api)
    alice, bob = api.user(), api.user()
    r = api.client.get(f"/api/v1/exercises/{slug}/draft", headers=auth(alice))
    assert r.status_code == 200 and r.json() == {
        "exercise": slug,
        "assignment": None,
        "program": None,
        "updated_at": None,
    }
    r = api.client.put(f"/api/v1/exercises/{slug}/draft", json={"program": DRAFT}, headers=auth(alice))
    assert r.status_code == 200 and r.json()["program"] == DRAFT and r.json()["updated_at"]
    # the same text again is the same state; a newer text replaces it
    assert (
        api.client.put(
            f"/api/v1/exercises/{slug}/draft", json={"program": DRAFT}, headers=auth(alice)
        ).json()["program"]
        == DRAFT
    )
    api.client.put(
        f"/api/v1/exercises/{slug}/draft", json={"program": DRAFT + "N30 M30\n"}, headers=auth(alice)
    )
    assert (
        api.client.get(f"/api/v1/exercises/{slug}/draft", headers=auth(alice)).json()["program"]
        == DRAFT + "N30 M30\n"
    )
    # Bob sees only his own (none)
    assert api.client.get(f"/api/v1/exercises/{slug}/draft", headers=auth(bob)).json()["program"] is None
    # "Zurücksetzen": forget it
    assert api.client.delete(f"/api/v1/exercises/{slug}/draft", headers=auth(alice)).status_code == 204
    assert api.client.get(f"/api/v1/exercises/{slug}/draft", headers=auth(alice)).json()["program"] is None
    assert api.client.delete(f"/api/v1/exercises/{slug}/draft", headers=auth(alice)).status_code == 204


def test_draft_errors(api: Api) -> None:
    slug = builtin_exercise(api)
    student = api.user()
    r = api.client.get("/api/v1/exercises/no-such-exercise/draft", headers=auth(student))
    assert r.status_code == 404 and error_code(r) == "EXERCISE_NOT_FOUND"
    r = api.client.put(
        "/api/v1/exercises/no-such-exercise/draft", json={"program": "x"}, headers=auth(student)
    )
    assert r.status_code == 404 and error_code(r) == "EXERCISE_NOT_FOUND"
    for method in ("get", "put", "delete"):
        r = api.client.request(method, f"/api/v1/exercises/{slug}/draft", json={"program": "x"})
        assert r.status_code == 401 and error_code(r) == "NOT_AUTHENTICATED"
    key = api.api_key(["submissions:write", "submissions:read"], owner=student)
    r = api.client.put(f"/api/v1/exercises/{slug}/draft", json={"program": "x"}, headers=key)
    assert r.status_code == 403 and error_code(r) == "DRAFTS_USERS_ONLY"
    too_long = "N10 G0 X0\n" * (api.settings.max_program_chars // 10 + 1)
    r = api.client.put(f"/api/v1/exercises/{slug}/draft", json={"program": too_long}, headers=auth(student))
    assert r.status_code == 413 and error_code(r) == "PROGRAM_TOO_LARGE"
    r = api.client.put(f"/api/v1/exercises/{slug}/draft", json={"program": "a\x00b"}, headers=auth(student))
    assert r.status_code == 422 and error_code(r) == "VALIDATION"


def test_draft_saves_are_rate_limited(api: Api) -> None:
    slug = builtin_exercise(api)
    student = api.user()
    old = api.settings.rate_draft_per_minute
    api.settings.rate_draft_per_minute = 3
    try:
        codes = [
            api.client.put(
                f"/api/v1/exercises/{slug}/draft", json={"program": str(i)}, headers=auth(student)
            ).status_code
            for i in range(4)
        ]
    finally:
        api.settings.rate_draft_per_minute = old
    assert codes == [200, 200, 200, 429]
    # reading is not limited by it
    assert api.client.get(f"/api/v1/exercises/{slug}/draft", headers=auth(student)).json()["program"] == "2"


def test_history_and_progress(api: Api) -> None:
    first, second = builtin_exercise(api), builtin_exercise(api)
    student, other = api.user(), api.user()
    bad = api.client.post(
        "/api/v1/submissions", json={"exercise": first, "program": GOOD}, headers=auth(student)
    )
    good = api.client.post(
        "/api/v1/submissions", json={"exercise": first, "program": reference_of()}, headers=auth(student)
    )
    assert bad.status_code == good.status_code == 201
    api.client.post("/api/v1/submissions", json={"exercise": first, "program": GOOD}, headers=auth(other))
    api.client.put(f"/api/v1/exercises/{second}/draft", json={"program": DRAFT}, headers=auth(student))

    r = api.client.get(f"/api/v1/me/submissions?exercise={first}", headers=auth(student))
    assert r.status_code == 200
    history = r.json()
    assert [h["id"] for h in history] == [good.json()["id"], bad.json()["id"]]  # newest first, only mine
    assert (
        history[0]["score"] == 100
        and history[0]["max_score"] == 100
        and history[0]["program"] == reference_of()
    )
    assert history[1]["score"] < 100 and history[1]["program"] == GOOD
    assert {c["id"] for c in history[1]["criteria"]} >= {"geometry", "syntax"}
    assert all("lines" in c for c in history[1]["criteria"])
    r = api.client.get("/api/v1/me/submissions?exercise=no-such-exercise", headers=auth(student))
    assert r.status_code == 404 and error_code(r) == "EXERCISE_NOT_FOUND"

    progress = {p["exercise"]: p for p in api.client.get("/api/v1/me/progress", headers=auth(student)).json()}
    assert progress[first]["status"] == "submitted" and progress[first]["best_score"] == 100
    assert progress[first]["best_submission"] == good.json()["id"] and progress[first]["submissions"] == 2
    assert progress[second]["status"] == "draft" and progress[second]["best_score"] is None
    assert progress[second]["draft_updated_at"]
    third = builtin_exercise(api)
    progress = {p["exercise"]: p for p in api.client.get("/api/v1/me/progress", headers=auth(student)).json()}
    assert progress[third]["status"] == "not_started" and progress[third]["submissions"] == 0
    assert api.client.get("/api/v1/me/progress").status_code == 401


def test_hints_one_at_a_time(api: Api) -> None:
    hints = [
        {"de": "Zuerst das Werkzeug einwechseln.", "en": "Change the tool in first."},
        {"de": "G42 vor dem Anfahren.", "en": "G42 before the approach."},
    ]
    slug = builtin_exercise(api, hints=hints)
    student = api.user()
    listed = api.client.get(f"/api/v1/exercises/{slug}", headers=auth(student)).json()
    assert listed["hint_count"] == 2 and "hints" not in listed
    r = api.client.get(f"/api/v1/exercises/{slug}/hints/2", headers=auth(student))
    assert r.status_code == 200 and r.json() == {
        "exercise": slug,
        "number": 2,
        "count": 2,
        "text": "G42 vor dem Anfahren.",
        "text_en": "G42 before the approach.",
    }
    r = api.client.get(f"/api/v1/exercises/{slug}/hints/3", headers=auth(student))
    assert (
        r.status_code == 404
        and error_code(r) == "HINT_NOT_FOUND"
        and "Tipp 3" in r.json()["error"]["message"]
    )
    assert api.client.get(f"/api/v1/exercises/{slug}/hints/0", headers=auth(student)).status_code == 422
    assert api.client.get(f"/api/v1/exercises/{slug}/hints/1").status_code == 401


def test_solution_as_the_exercise_allows(api: Api) -> None:
    after_submission = builtin_exercise(api)  # the default
    never = builtin_exercise(api, solution="never")
    full_marks = builtin_exercise(api, solution="after_full_marks")
    student, instructor, admin = api.user(), api.user("instructor"), api.user("admin")

    def solution(slug: str, who: dict[str, str]) -> tuple[int, str]:
        r = api.client.get(f"/api/v1/exercises/{slug}/solution", headers=auth(who))
        return r.status_code, r.json()["program"] if r.status_code == 200 else error_code(r)

    assert solution(after_submission, student) == (403, "SOLUTION_AFTER_SUBMISSION")
    r = api.client.get(f"/api/v1/exercises/{after_submission}/solution", headers=auth(student))
    assert r.json()["error"]["message"] == "Die Musterlösung gibt es nach der ersten Abgabe."
    assert solution(never, student) == (403, "SOLUTION_NEVER")
    assert solution(full_marks, student) == (403, "SOLUTION_AFTER_FULL_MARKS")
    for slug in (after_submission, never, full_marks):
        assert solution(slug, admin) == (200, reference_of())
    # an instructor gets it like a student until a course of theirs sets the exercise, then always
    assert solution(never, instructor) == (403, "SOLUTION_NEVER")
    assert solution(after_submission, instructor) == (403, "SOLUTION_AFTER_SUBMISSION")
    course = api.client.post("/api/v1/courses", json={"name": "K"}, headers=auth(instructor)).json()["id"]
    r = api.client.post(
        f"/api/v1/courses/{course}/assignments",
        headers=auth(instructor),
        json={
            "title": "Übung",
            "exercises": [after_submission, never, full_marks],
            "opens_at": "2026-01-01T00:00:00Z",
            "deadline": "2099-01-01T00:00:00Z",
        },
    )
    assert r.status_code == 201, r.text
    for slug in (after_submission, never, full_marks):
        assert solution(slug, instructor) == (200, reference_of())

    for slug in (after_submission, never, full_marks):
        api.client.post(
            "/api/v1/submissions", json={"exercise": slug, "program": GOOD}, headers=auth(student)
        )
    assert solution(after_submission, student) == (200, reference_of())
    assert solution(never, student) == (403, "SOLUTION_NEVER")
    assert solution(full_marks, student) == (403, "SOLUTION_AFTER_FULL_MARKS")
    api.client.post(
        "/api/v1/submissions", json={"exercise": full_marks, "program": reference_of()}, headers=auth(student)
    )
    assert solution(full_marks, student) == (200, reference_of())
    assert solution(never, student) == (403, "SOLUTION_NEVER")
    r = api.client.get("/api/v1/exercises/no-such-exercise/solution", headers=auth(student))
    assert r.status_code == 404


def test_list_sorted_by_order_then_title_with_dialect_names(api: Api) -> None:
    student = api.user()
    late = builtin_exercise(api, order=20, title={"de": "A zuletzt", "en": "A last"})
    early = builtin_exercise(api, order=10, title={"de": "Z zuerst", "en": "Z first"})
    untitled_b = builtin_exercise(api, title={"de": "Ohne Platz G23", "en": "No place G23"})
    untitled_a = builtin_exercise(api, title={"de": "Ohne Platz G3", "en": "No place G3"})
    listed = api.client.get("/api/v1/exercises", headers=auth(student)).json()
    mine = [e["slug"] for e in listed if e["slug"] in {late, early, untitled_a, untitled_b}]
    assert mine == [early, late, untitled_a, untitled_b]  # numbers in titles compare as numbers
    one = next(e for e in listed if e["slug"] == early)
    assert one["order"] == 10 and one["dialect"] == "pal-mill"
    assert one["dialect_title"] == "PAL Fräsen" and one["dialect_title_en"] == "PAL milling"
    assert one["solution"] == "after_submission" and one["hint_count"] == 0


def test_deleting_an_exercise_takes_its_drafts(api: Api) -> None:
    owner, student = api.user("instructor"), api.user()
    slug = api.exercise(owner)["slug"]
    assert (
        api.client.put(
            f"/api/v1/exercises/{slug}/draft", json={"program": DRAFT}, headers=auth(student)
        ).status_code
        == 200
    )
    assert api.client.delete(f"/api/v1/exercises/{slug}", headers=auth(owner)).status_code == 204
    r = api.client.get(f"/api/v1/exercises/{slug}/draft", headers=auth(student))
    assert r.status_code == 404 and error_code(r) == "EXERCISE_NOT_FOUND"
    with api.app.state.db.session() as db:
        user = repo.user_by_name(db, student["name"])
        assert user is not None and list(repo.drafts_of(db, user.id)) == []
