"""Move.with_fields, the interpreter's fast copy of a move, makes exactly what dataclasses.replace makes; moves are values."""

from __future__ import annotations

import dataclasses
import pickle

import pytest

from core.pipeline import run
from core.syntax.blocks import Span
from core.toolpath import Move


def test_with_fields_is_dataclasses_replace() -> None:
    m = Move("feed", (0, 0, 0), (1, 1, 1), 100, "mm/min", 1000, "cw", False, 1, Span(3, 1, 3, 9))
    changes = {"kind": "arc", "end": (2, 0, 1), "center": (1, 0, 1), "radius": 1.0, "plane": "G18"}
    copied = m.with_fields(**changes)
    assert copied == dataclasses.replace(m, **changes)  # type: ignore[arg-type]
    assert copied.span == m.span and copied.tool == 1 and m.kind == "feed"  # the original stays
    with pytest.raises(TypeError):
        m.with_fields(colour="red")


def test_with_path_is_with_fields_of_the_path() -> None:
    """with_path keeps every other field: a move with all of them set, made again on another path."""
    m = Move(
        "feed", (0, 0, 0), (1, 1, 1), 100, "mm/rev", 1000, "cw", True, 1, Span(3, 1, 3, 9), None, None, None,
        None, True, "G17", (1, 1, 1), "L12", (("L1", 4),), ("G71", 2, 5), 7, (1, 3), True, 1.5,
    )  # fmt: skip
    path = {
        "kind": "arc",
        "start": (2, 0, 1),
        "end": (3, 0, 2),
        "center": (2, 0, 2),
        "direction": "ccw",
        "radius": 1.0,
        "angle": 90.0,
        "plane": "G18",
        "programmed_end": (3, 0, 2),
        "feed": 0.3,
        "spindle": 800.0,
    }
    kept = [f for f in dataclasses.fields(m) if f.name not in path]
    assert all(
        getattr(m, f.name) != f.default for f in kept
    )  # (every kept field is set: none is lost unseen)
    assert m.with_path(**path) == m.with_fields(**path)  # type: ignore[arg-type]


def test_a_turned_contour_keeps_its_technology_on_every_move() -> None:
    tp = run(
        "%\nO1\nN10 G59 Z100\nN20 G96 V200 T0101 M4\nN30 G92 S3000\nN40 G0 X40 Z2\n"
        "N50 G1 Z-20 F0.2\nN60 G2 X50 Z-25 R5\nN70 G0 X100 Z100\nN80 M30\n",
        "traub-tx8d",
    )
    feeds = [m for m in tp.moves if m.kind in ("feed", "arc")]
    assert [m.kind for m in feeds] == ["feed", "arc"]
    assert all(m.feed == 0.2 and m.tool == 1 and m.plane == "G18" for m in feeds)
    assert round(feeds[0].spindle) == round(200_000 / (3.141592653589793 * 40))  # G96 at Ø40: 1592 1/min


def test_value_classes_compare_hash_and_travel_by_value() -> None:
    """Moves are plain slots classes at run time (frozen for the type checker, `core.values`): equal moves
    are one key of a set, and a move survives the pickling that carries it from a worker unchanged."""
    a = Move("feed", (0, 0, 0), (1, 1, 1), 100, "mm/min", 1000, "cw", False, 1, Span(3, 1, 3, 9))
    b = Move("feed", (0, 0, 0), (1, 1, 1), 100, "mm/min", 1000, "cw", False, 1, Span(3, 1, 3, 9))
    assert a == b and len({a, b}) == 1
    assert a != a.with_fields(end=(1, 1, 2))
    assert pickle.loads(pickle.dumps(a)) == a
