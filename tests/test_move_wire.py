"""A move on the wire (`paltrainer run --json`, POST /api/v1/run, the live answers) is a contract schools'
scripts read: its JSON stays exactly what it is, and it is written once — core/toolpath.py's MoveJson, which
Move.to_json makes and server/schemas.py's MoveOut is. A field added to one and forgotten in another fails
here."""

from __future__ import annotations

import dataclasses
import json
import typing
from typing import Any

from pydantic import TypeAdapter

from core.syntax.blocks import Span
from core.toolpath import WIRE_RESHAPED, CycleJson, Move, MoveJson
from server.schemas import MoveOut, RunResponse

# the fields of a move's JSON as they are on the wire, in their order; the last three only where they apply
TODAY = [
    "line",
    "kind",
    "start",
    "end",
    "center",
    "direction",
    "radius",
    "angle",
    "feed",
    "feed_unit",
    "spindle",
    "spindle_direction",
    "coolant",
    "tool",
    "exact_stop",
    "plane",
    "programmed_end",
    "source",
    "call_stack",
]
OPTIONAL = ["cycle", "thread", "pitch"]

STRAIGHT = Move(
    "feed",
    (0.0, 0.0, 2.0),
    (10.0, 0.0, -1.0000004),
    300.0,
    "mm/min",
    2500.0,
    "cw",
    False,
    1,
    Span(7, 1, 7, 20),
    programmed_end=(10.0, 4.0, -1.0),
)
ARC = dataclasses.replace(
    STRAIGHT,
    kind="arc",
    center=(5.0, 0.0, 2.0),
    direction="ccw",
    radius=5.0,
    angle=180.0,
    plane="G18",
    programmed_end=None,
    source="L200",
    call_stack=(("L100", 12), (None, 3)),
)
CYCLE = dataclasses.replace(STRAIGHT, cycle=("G72", 2, 3), cycle_definition=4, cycle_point=(1, 6))
THREAD = dataclasses.replace(STRAIGHT, feed_unit="mm/rev", thread=True, pitch=1.25, cycle=("G76", 1, 1))


def test_a_straight_move_is_on_the_wire_as_it_always_was() -> None:
    data = STRAIGHT.to_json()
    assert list(data) == TODAY
    assert json.dumps(data) == json.dumps(
        {
            "line": 7,
            "kind": "feed",
            "start": [0.0, 0.0, 2.0],
            "end": [10.0, 0.0, -1.0],
            "center": None,
            "direction": None,
            "radius": None,
            "angle": None,
            "feed": 300.0,
            "feed_unit": "mm/min",
            "spindle": 2500.0,
            "spindle_direction": "cw",
            "coolant": False,
            "tool": 1,
            "exact_stop": False,
            "plane": "G17",
            "programmed_end": [10.0, 4.0, -1.0],
            "source": None,
            "call_stack": [],
        }
    )


def test_an_arc_a_cycle_and_a_thread_move_have_their_fields_where_they_apply() -> None:
    arc = ARC.to_json()
    assert list(arc) == TODAY
    assert (arc["center"], arc["direction"], arc["radius"], arc["angle"], arc["plane"]) == (
        [5.0, 0.0, 2.0],
        "ccw",
        5.0,
        180.0,
        "G18",
    )
    assert arc["programmed_end"] == arc["end"]  # no compensation: the end itself
    assert arc["source"] == "L200"
    assert arc["call_stack"] == [{"source": "L100", "line": 12}, {"source": None, "line": 3}]
    cycle = CYCLE.to_json()
    assert list(cycle) == [*TODAY, "cycle"]
    assert json.dumps(cycle["cycle"]) == json.dumps(
        {"code": "G72", "pass": 2, "of": 3, "defined_in_line": 4, "point": 1, "points": 6}
    )
    plain = dataclasses.replace(CYCLE, cycle_definition=None, cycle_point=None).to_json()
    assert json.dumps(plain["cycle"]) == json.dumps({"code": "G72", "pass": 2, "of": 3})
    thread = THREAD.to_json()
    assert list(thread) == [*TODAY, "cycle", "thread", "pitch"]
    assert (thread["thread"], thread["pitch"]) == (True, 1.25)


def test_the_wire_format_is_written_once() -> None:
    """MoveJson names today's fields and no other; every field of the Move dataclass is on the wire, under its
    own name or as core/toolpath.py's WIRE_RESHAPED says; MoveOut is MoveJson."""
    hints = typing.get_type_hints(MoveJson)
    assert list(hints) == TODAY + OPTIONAL
    assert MoveJson.__required_keys__ == frozenset(TODAY) and MoveJson.__optional_keys__ == frozenset(
        OPTIONAL
    )
    cycle = typing.get_type_hints(CycleJson)
    assert list(cycle) == ["code", "pass", "of", "defined_in_line", "point", "points"]
    for field in dataclasses.fields(Move):
        wire = WIRE_RESHAPED.get(field.name, (field.name,))
        assert set(wire) <= set(hints), f"Move.{field.name} is not on the wire: add it to MoveJson"
    assert set(hints) - {f.name for f in dataclasses.fields(Move)} == {"line"}  # span's
    assert issubclass(MoveOut, dict) and typing.get_type_hints(MoveOut) == hints
    schema = RunResponse.model_json_schema()["$defs"]["MoveOut"]
    assert list(schema["properties"]) == TODAY + OPTIONAL and schema["required"] == TODAY


def test_the_api_answers_a_move_exactly_as_to_json_makes_it() -> None:
    """The response model validates and serialises the moves without changing a byte (no field dropped, no
    null added for a field that does not apply, no number turned into another type)."""
    adapter: TypeAdapter[Any] = TypeAdapter(RunResponse)
    for move in (STRAIGHT, ARC, CYCLE, THREAD):
        data = {
            "moves": [move.to_json()],
            "dwells": [],
            "tool_changes": [],
            "diagnostics": [],
            "final": {"position": [0.0, 0.0, 0.0]},
        }
        out = adapter.dump_json(adapter.validate_python(data))
        assert json.loads(out)["moves"] == data["moves"]
        assert json.dumps(json.loads(out)["moves"]) == json.dumps(data["moves"])
