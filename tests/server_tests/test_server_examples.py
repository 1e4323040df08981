"""GET /api/v1/examples: the built-in examples free practice loads without an account, and their drawings."""

from __future__ import annotations

from server_helpers import Api, auth, builtin_exercise, error_code, unique
from test_server_lms import exercise_file

START = "N10 T1 TC1 M6\nN20 S1200 F150 M3\n"


def test_builtin_examples_without_an_account(api: Api) -> None:
    write = builtin_exercise(api)
    complete = builtin_exercise(api, kind="complete", start_program=START, locked_lines=[1])
    secret = builtin_exercise(api, solution="never")
    owner = api.user("instructor")
    own = unique("eigene-")
    assert (
        api.client.post(
            "/api/v1/exercises/import", content=exercise_file(own).encode(), headers=auth(owner)
        ).status_code
        == 201
    )
    r = api.client.get("/api/v1/examples")
    assert r.status_code == 200
    examples = {e["slug"]: e for e in r.json()}
    # a published seed example: its reference program, with the stock and tools to set up free practice
    assert examples[write]["program_is"] == "reference" and "N70 G1 Y84" in examples[write]["program"]
    assert examples[write]["stock"]["max"] == [80, 70, 0] and examples[write]["tools"]
    # "complete" gives only the start, never the answer; nor does an exercise whose solution is "never"
    assert examples[complete]["program"] == START and examples[complete]["program_is"] == "start"
    assert secret not in examples
    assert own not in examples  # an instructor's exercise is not public


def test_example_drawing_without_an_account(api: Api) -> None:
    slug = builtin_exercise(api)
    r = api.client.get(f"/api/v1/examples/{slug}/drawing.svg")
    assert r.status_code == 200 and r.headers["content-type"].startswith("image/svg+xml")
    assert "Draufsicht" in r.text
    owner = api.user("instructor")
    own = unique("eigene-")
    api.client.post("/api/v1/exercises/import", content=exercise_file(own).encode(), headers=auth(owner))
    missing = api.client.get(f"/api/v1/examples/{own}/drawing.svg")
    assert missing.status_code == 404 and error_code(missing) == "EXERCISE_NOT_FOUND"
