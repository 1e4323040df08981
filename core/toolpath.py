"""The canonical commands the interpreter emits — the contract between interpreter and consumers.

Coordinates are workpiece coordinates in mm; angles in degrees. A `Move` is a straight rapid
move, a straight feed move or an arc (helix when Z changes). `end` is where the tool centre goes; `programmed_end` the contour
point the program gave before cutter radius compensation (the same without compensation). Arcs stay arcs: linearising them
is the consumer's job. For an arc, `center` is the centre at the start's height along the plane's
third axis, `direction` is "cw" or "ccw" as seen from that axis (+Z for the plane G17; `plane` says
which), `radius` is the distance start–centre in the plane and
`angle` the swept angle (360 for a full circle). `feed` is in mm/min under G94 and mm per
revolution under G95 (`feed_unit`). `spindle` is the programmed speed S while the spindle
turns and 0 while it stands. Every command carries the span of the block that made it.
"""

from __future__ import annotations

import copy
import math
import operator
from dataclasses import dataclass, field, fields
from typing import TYPE_CHECKING, Any, Literal, NotRequired

# pydantic (server/schemas.py: MoveOut) reads the wire's TypedDicts, and wants typing_extensions' before Python 3.12
from typing_extensions import TypedDict

from core.diagnostics import Diagnostic
from core.limits import DEFAULT_LIMITS, Limits
from core.syntax.blocks import Span
from core.values import value

if TYPE_CHECKING:  # the interpreter's package imports this module
    from core.interpreter.state import ModalState

Vec3 = tuple[float, float, float]
MoveKind = Literal["rapid", "feed", "arc"]


def _r(v: float) -> float:
    """Round for output: 6 decimals is 1 nm, far below any machine's resolution."""
    r = round(v, 6)
    return 0.0 if r == 0 else r


def _v(p: Vec3) -> list[float]:
    return [_r(p[0]), _r(p[1]), _r(p[2])]


class CallJson(TypedDict):
    """A calling block of a move: its source (None: the program file) and line."""

    source: str | None
    line: int


# "pass" is a keyword: the functional form
CycleJson = TypedDict(
    "CycleJson",
    {
        "code": str,  # the cycle's code, e.g. "G71"
        "pass": int,  # this move's pass …
        "of": int,  # … of this many
        "defined_in_line": NotRequired[int],  # PAL: the line of the block that defined the cycle
        "point": NotRequired[int],  # PAL cycle calls: the move belongs to point `point` …
        "points": NotRequired[int],  # … of `points`
    },
)


class _MoveFields(TypedDict):
    """The fields every move has on the wire (MoveJson)."""

    line: int
    kind: MoveKind
    start: list[float]
    end: list[float]
    center: list[float] | None
    direction: Literal["cw", "ccw"] | None
    radius: float | None
    angle: float | None
    feed: float
    feed_unit: Literal["mm/min", "mm/rev"]
    spindle: float
    spindle_direction: Literal["cw", "ccw"] | None
    coolant: bool
    tool: int | None
    exact_stop: bool
    plane: str
    programmed_end: list[float]  # the end itself when the move has no compensation
    source: str | None
    call_stack: list[CallJson]


class MoveJson(_MoveFields, total=False):
    """A move on the wire (`paltrainer run --json`, POST /api/v1/run, the live answers): the contract schools'
    scripts read, written once here (`Move.to_json` makes it, server/schemas.py's MoveOut is it). Points are
    [x, y, z] mm rounded to 6 decimals; `line` is the span's line. The fields below only where they apply
    (`total=False` rather than NotRequired: so they are optional at run time too, for pydantic and
    introspection, whatever the annotations' evaluation)."""

    cycle: CycleJson
    thread: Literal[True]
    pitch: float | None


# the Move's fields that are on the wire under another shape (everything else under its own name):
# span → line, cycle_definition → cycle.defined_in_line, cycle_point → cycle.point and cycle.points
WIRE_RESHAPED = {"span": ("line",), "cycle_definition": ("cycle",), "cycle_point": ("cycle",)}


@value
class Move:
    kind: MoveKind
    start: Vec3
    end: Vec3
    feed: float
    feed_unit: Literal["mm/min", "mm/rev"]
    spindle: float
    spindle_direction: Literal["cw", "ccw"] | None
    coolant: bool
    tool: int | None
    span: Span
    center: Vec3 | None = None
    direction: Literal["cw", "ccw"] | None = None
    radius: float | None = None
    angle: float | None = None
    exact_stop: bool = False
    plane: str = "G17"  # the arc's plane: G17 X-Y, G18 Z-X, G19 Y-Z (direction seen from its third axis)
    programmed_end: Vec3 | None = None  # the contour point before compensation (None: same as end)
    source: str | None = None  # the library subprogram of the block ("L200"); None: the program file
    call_stack: tuple[tuple[str | None, int], ...] = ()  # calling blocks (source, line), outermost first
    cycle: tuple[str, int, int] | None = None  # made by a cycle: (code "G71", pass n, of m passes)
    cycle_definition: int | None = (
        None  # PAL cycles: the line of the block that defined the cycle (span: the call)
    )
    cycle_point: tuple[int, int] | None = None  # PAL cycle calls: (point k, of n points) the move belongs to
    thread: bool = False  # a thread-cutting feed: the feed per revolution is the pitch
    pitch: float | None = None  # mm per revolution of a thread move

    @property
    def line(self) -> int:
        return self.span.line

    def with_fields(self, **changes: Any) -> Move:
        """`dataclasses.replace(self, **changes)` for the interpreter's hot paths (a move made from its block's
        template): the same move, about five times as fast, because the fields are read at once and passed by
        position, without `replace`'s keyword handling. Unknown field names raise TypeError as there."""
        values = list(_move_values(self))
        for name, v in changes.items():
            i = _MOVE_INDEX.get(name)
            if i is None:
                raise TypeError(f"Move has no field {name}")
            values[i] = v
        return Move(*values)

    def with_path(
        self,
        kind: MoveKind,
        start: Vec3,
        end: Vec3,
        center: Vec3 | None,
        direction: Literal["cw", "ccw"] | None,
        radius: float | None,
        angle: float | None,
        plane: str,
        programmed_end: Vec3 | None,
        feed: float,
        spindle: float,
    ) -> Move:
        """This move's technology and origin on another path: `with_fields` of the geometry, the feed and the
        speed, for the moves a contour stage makes from their block's template (one or more per block), passed
        by position: a third of `with_fields`' time. tests/test_move_copy.py checks the two agree."""
        return Move(
            kind,
            start,
            end,
            feed,
            self.feed_unit,
            spindle,
            self.spindle_direction,
            self.coolant,
            self.tool,
            self.span,
            center,
            direction,
            radius,
            angle,
            self.exact_stop,
            plane,
            programmed_end,
            self.source,
            self.call_stack,
            self.cycle,
            self.cycle_definition,
            self.cycle_point,
            self.thread,
            self.pitch,
        )

    def chords(self, tolerance: float) -> int:
        """How many segments `points(tolerance)` makes: 1 for a straight move. Computed, not drawn, so that a
        consumer can keep within a budget before it builds a point."""
        if self.kind != "arc" or self.radius is None or self.angle is None:
            return 1
        r = self.radius
        step = 2 * math.acos(max(-1.0, min(1.0, 1 - tolerance / r))) if r > tolerance else math.pi / 2
        return max(1, math.ceil(math.radians(self.angle) / max(step, 1e-6)))

    def points(self, tolerance: float, max_chords: int | None = None) -> list[Vec3]:
        """Points along the move from start to end; an arc as chords that stray at most `tolerance` mm
        (or as `max_chords` equal chords where that tolerance would need more)."""
        if self.kind != "arc" or self.center is None or self.radius is None or self.angle is None:
            return [self.start, self.end]
        from core.geometry.planes import from_plane, to_plane

        s, e, c = (to_plane(p, self.plane) for p in (self.start, self.end, self.center))
        r = self.radius
        n = self.chords(tolerance)
        if max_chords is not None:
            n = max(1, min(n, max_chords))
        a0 = math.atan2(s[1] - c[1], s[0] - c[0])
        sweep = math.radians(self.angle) * (-1 if self.direction == "cw" else 1)
        pts = [
            from_plane(
                (
                    c[0] + r * math.cos(a0 + sweep * k / n),
                    c[1] + r * math.sin(a0 + sweep * k / n),
                    s[2] + (e[2] - s[2]) * k / n,
                ),
                self.plane,
            )
            for k in range(n)
        ]
        return pts + [self.end]

    def cycle_json(self) -> CycleJson | None:
        """The cycle that made the move, as on the wire; None: no cycle."""
        if self.cycle is None:
            return None
        code, number, count = self.cycle
        cycle: CycleJson = {"code": code, "pass": number, "of": count}
        if self.cycle_definition is not None:
            cycle["defined_in_line"] = self.cycle_definition
        if self.cycle_point is not None:
            cycle["point"], cycle["points"] = self.cycle_point
        return cycle

    def to_json(self) -> MoveJson:
        data: MoveJson = {
            "line": self.span.line,
            "kind": self.kind,
            "start": _v(self.start),
            "end": _v(self.end),
            "center": None if self.center is None else _v(self.center),
            "direction": self.direction,
            "radius": None if self.radius is None else _r(self.radius),
            "angle": None if self.angle is None else _r(self.angle),
            "feed": self.feed,
            "feed_unit": self.feed_unit,
            "spindle": self.spindle,
            "spindle_direction": self.spindle_direction,
            "coolant": self.coolant,
            "tool": self.tool,
            "exact_stop": self.exact_stop,
            "plane": self.plane,
            "programmed_end": _v(self.programmed_end if self.programmed_end is not None else self.end),
            "source": self.source,
            "call_stack": [{"source": src, "line": line} for src, line in self.call_stack],
        }
        cycle = self.cycle_json()
        if cycle is not None:
            data["cycle"] = cycle
        if self.thread:
            data["thread"], data["pitch"] = True, self.pitch
        return data


@dataclass(frozen=True, slots=True)
class Dwell:
    """The tool stands still at `position` for `seconds` (G4)."""

    position: Vec3
    seconds: float
    span: Span

    def to_json(self) -> dict[str, Any]:
        return {"line": self.span.line, "position": _v(self.position), "seconds": _r(self.seconds)}


@dataclass(frozen=True, slots=True)
class ToolChange:
    """Tool `tool` (None: spindle emptied with T0) is loaded with offset memory `tc` and corrections."""

    tool: int | None
    tc: int
    tr: float
    tl: float
    position: Vec3
    span: Span

    def to_json(self) -> dict[str, Any]:
        return {
            "line": self.span.line,
            "tool": self.tool,
            "tc": self.tc,
            "tr": self.tr,
            "tl": self.tl,
            "position": _v(self.position),
        }


@dataclass(slots=True)
class Toolpath:
    """The interpreter's result: canonical commands, diagnostics and the state after every line."""

    commands: list[Move | Dwell | ToolChange] = field(default_factory=list)  # in execution order
    moves: list[Move] = field(default_factory=list)
    dwells: list[Dwell] = field(default_factory=list)
    tool_changes: list[ToolChange] = field(default_factory=list)
    diagnostics: list[Diagnostic] = field(default_factory=list)
    final_position: Vec3 = (0.0, 0.0, 0.0)
    initial: ModalState | None = None
    # index = line - 1: the state and position after that line (lines not executed repeat the previous)
    line_states: list[ModalState] = field(default_factory=list)
    line_positions: list[Vec3] = field(default_factory=list)
    params: dict[int, float] = field(default_factory=dict)
    limits: Limits = DEFAULT_LIMITS  # the limits of the run (an answer shows at most max_answer_commands)
    code_prefix: str = "PAL"  # the dialect's prefix of diagnostics (core.diagnostics.in_dialect)
    # the work the run did: blocks executed, evaluation steps, programmed moves (core/limits.py Budget); tests
    # bound a program's cost by these counters, never by seconds
    work: tuple[int, int, int] = (0, 0, 0)

    def state_at(self, line: int) -> tuple[ModalState, Vec3]:
        """What is active, and where the tool is, after line `line` (1-based) has run."""
        if line < 1 or not self.line_states:
            assert self.initial is not None
            return self.initial, self.line_positions[0] if self.line_positions else (0.0, 0.0, 0.0)
        i = min(line, len(self.line_states)) - 1
        return self.line_states[i], self.line_positions[i]

    def until_move(self, moves: int) -> Toolpath:
        """The run as far as its first `moves` moves (for the stock after a block during playback)."""
        commands: list[Move | Dwell | ToolChange] = []
        count = 0
        for c in self.commands:
            if isinstance(c, Move):
                if count >= moves:
                    break
                count += 1
            commands.append(c)
        partial = copy.copy(self)
        partial.commands = commands
        return partial


_MOVE_FIELDS = tuple(f.name for f in fields(Move))
_MOVE_INDEX = {name: i for i, name in enumerate(_MOVE_FIELDS)}
_move_values = operator.attrgetter(*_MOVE_FIELDS)  # a move's fields in order, read in one call
