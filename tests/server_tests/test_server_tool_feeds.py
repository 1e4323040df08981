"""What the Werkzeuge tab of a turning exercise needs from GET /exercises/{slug} beyond the cutting data: which of a
tool's feeds are the reduced feed E (what the reference writes as E), as the printed sheet tells them apart
(core.sheet.tool_feeds); nothing of the kind for milling. Free practice gets a turning example's blank (bar or
tube) from GET /examples."""

from __future__ import annotations

from server_helpers import Api, builtin_as_read

from core.exercises import EXERCISES_DIR, load_exercise
from core.sheet import _tool_rows, tool_feeds


def test_a_turning_tool_s_reduced_feed_is_told_apart() -> None:
    doc = load_exercise(EXERCISES_DIR / "traub-tx8d" / "traub-10-schruppen-g71-g88.yaml")
    feeds = tool_feeds(doc)
    assert feeds[4] == {"feed": [0.35], "reduced": [0.12], "spindle": "M4"}
    assert feeds[5] == {
        "feed": [0.15, 0.1],
        "reduced": [0.1],
        "spindle": "M4",
    }  # E0,1 at the chamfer, F0,1 on the cone
    _, rows = _tool_rows(doc, "de")  # the sheet prints the same
    assert [row[5:7] for row in rows] == [["0,35", "0,12"], ["0,15 / 0,1", "0,1"]]


def test_the_exercise_page_gets_the_feeds_of_a_turning_exercise(api: Api) -> None:
    turning = builtin_as_read(api, "traub-tx8d/traub-10-schruppen-g71-g88.yaml")
    assert turning["tool_feeds"] == {
        "4": {"feed": [0.35], "reduced": [0.12], "spindle": "M4"},
        "5": {"feed": [0.15, 0.1], "reduced": [0.1], "spindle": "M4"},
    }
    first = builtin_as_read(api, "traub-tx8d/traub-01-srk-fase.yaml")
    assert first["tool_feeds"]["1"]["reduced"] == [0.1] and first["tool_feeds"]["1"]["feed"] == [0.2]
    milling = builtin_as_read(api, "pal-mill/pal-13-g41-aussenkontur.yaml")
    assert milling["tool_feeds"] == {}


def test_free_practice_gets_a_turning_example_s_blank(api: Api) -> None:
    bar = builtin_as_read(api, "traub-tx8d/traub-10-schruppen-g71-g88.yaml")["slug"]
    tube = builtin_as_read(api, "traub-tx8d/traub-11-innen-g71-g89.yaml")["slug"]
    milled = builtin_as_read(api, "pal-mill/pal-13-g41-aussenkontur.yaml")["slug"]
    examples = {e["slug"]: e for e in api.client.get("/api/v1/examples").json()}
    assert {
        k: examples[bar]["blank"][k] for k in ("diameter", "inner_diameter", "length", "chuck_length")
    } == {"diameter": 100, "inner_diameter": 0, "length": 160, "chuck_length": 30}
    assert examples[tube]["blank"]["inner_diameter"] == 30 and examples[tube]["blank"]["length"] == 100
    assert examples[milled]["blank"] is None
