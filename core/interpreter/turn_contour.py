"""TRAUB TX 8 D turning: contour trains (Geometriezüge) and nose-radius compensation (SRK).

The turning sibling of `core.interpreter.contour`. The TRAUB block executor does not compute the
geometry of a motion block itself: it hands one `TurnItem` per motion block (and passes other
commands through) to `resolve`, which runs over them in order with the control's one-block
look-ahead:

1. contour trains: end points given only by angle A, or not at all, are found by intersecting
   with the next element (DECISIONS 12, 17); arcs by R, P/Q (centre), I/K (centre from the start);
   H0/H1 pick an intersection of a line and a circle; tangential line–arc, arc–line, arc–arc;
2. transition elements D (chamfer width along Z), D− (chamfer length), R / C (rounding) are put
   into the programmed contour as moves of the block that programs them;
3. SRK (G46, G41, G42; G40 off) turns the contour into the path of the nose-radius centre:
   intersections of the equidistants at inside corners, an inserted arc at outside corners
   (DECISIONS 16).

Frame (DECISIONS 15): points are given and returned as (x, z) with x = radius (X/2) and z = Z;
moves are `[x, 0, z]` in plane G18 (Z-X): an arc's `direction` is seen from +Y, i.e. in the
drawing view with Z to the right and X up, so G2 = "cw". Internally the plane point is (z, x),
which keeps that sense for the 2-D geometry of `core.geometry.elements`.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Literal

from core.diagnostics import Diagnostic
from core.syntax.blocks import Span
from core.toolpath import Dwell, Move, ToolChange

XZ = tuple[float, float]  # (x radius, z) in the workpiece frame
Command = Move | Dwell | ToolChange


@dataclass(frozen=True, slots=True)
class Nose:
    """The SRK state of a block and the set-up data of the tool's cutting edge.

    `mode`: "G40" off, "G46" on (side from the quadrant and the travel direction), "G41" tool left
    of the travel direction, "G42" right (drawing view Z right, X up). `radius`: nose radius R_s in
    mm (0 when the tool has none). `quadrant`: P1…P4 as DECISIONS 16 counts them (0: not set).
    """

    mode: Literal["G40", "G41", "G42", "G46"] = "G40"
    radius: float = 0.0
    quadrant: int = 0

    @property
    def active(self) -> bool:
        return self.mode != "G40"


@dataclass(frozen=True, slots=True)
class TransitionSpec:
    """A transition element at the end of the block, into the next motion block.

    kind "chamfer": D+ = chamfer width measured along Z (equal legs); "chamfer_length": D− = the
    chamfer's own length (the chord); "rounding": R in G1 or C in G2/G3. `size` > 0 in mm.
    `feed` is E (modal; the executor resolves it, None = the block's feed). `raw` is the text for
    messages ("D0.5", "D-2", "R2", "C3").
    """

    kind: Literal["chamfer", "chamfer_length", "rounding"]
    size: float
    raw: str
    feed: float | None = None


@dataclass(frozen=True, slots=True)
class TurnItem:
    """One motion block as programmed, in the output frame (x radius, z); unknown values are None.

    template: the block's Move carrying technology and origin (feed, feed_unit, spindle,
        spindle_direction, coolant, tool, span, exact_stop, source, call_stack). Its geometry
        (start, end, center, kind, …) is ignored and replaced.
    code: "G0" rapid line, "G1" / "G9" feed line (G9 = exact stop), "G2" / "G3" arc (G2 = cw).
    start: where the block starts, if the executor knows it (authoritative: it accounts for tool
        changes, G26, G53 …); None after a block whose end the executor could not compute (an
        unknown train point) — then the resolved end of the previous item is the start.
    x, z: absolute end point (X already halved); None where not programmed.
    dx, dz: incremental end (U radius, W) *only* when `start` is None (the executor resolves U/W
        itself when it knows the start). They are added to the resolved start.
    a: angle A in degrees as programmed (0° = +Z, counter-clockwise positive). For a line with a
        known start A is the travel direction; in the closing block of a train (after an unknown
        point) A points back from the known end point (DECISIONS 12). On a G0 while SRK is active
        A is the direction of the last contour element for the deselection (TX-28 case 3).
    radius: R of G2/G3 (the arc radius; a rounding of G1 is `transition`).
    centre: absolute arc centre from P/Q (x = P/2, z = Q).
    centre_offset: arc centre relative to the start from I/K (I radius, K), start may be unknown.
    h: H0 / H1 — which intersection of line and circle (0: nearer to the known point of the line).
    transition: D / D− / R / C at the end of the block.
    nose: SRK state while the block runs.
    spindle_at: optional; the spindle speed (1/min) for a move ending at radius x (G96 with the
        G92 limit). When given, every output move of the block carries spindle_at(end x).
    """

    template: Move
    code: Literal["G0", "G1", "G9", "G2", "G3"]
    start: XZ | None = None
    x: float | None = None
    z: float | None = None
    dx: float | None = None
    dz: float | None = None
    a: float | None = None
    radius: float | None = None
    centre: XZ | None = None
    centre_offset: XZ | None = None
    h: int | None = None
    transition: TransitionSpec | None = None
    nose: Nose = Nose()
    spindle_at: Callable[[float], float] | None = None

    @property
    def span(self) -> Span:
        return self.template.span

    @property
    def is_arc(self) -> bool:
        return self.code in ("G2", "G3")


@dataclass(frozen=True, slots=True)
class SrkSwitch:
    """Where G40 / G41 / G42 / G46 is programmed (for the selection and deselection rules and their
    messages); the motion blocks that follow carry the new state in `TurnItem.nose`."""

    code: Literal["G40", "G41", "G42", "G46"]
    span: Span
    nose: Nose = Nose()


Item = TurnItem | SrkSwitch | Command


def known_end(start: XZ | None, item: TurnItem) -> XZ | None:
    """The end point of `item` if the block alone fixes it from `start` (no look-ahead needed).

    The executor uses this to keep its position: None means the point is an unknown train point
    (found by `resolve` from the next block); blocks after it get `start=None` and U/W as dx/dz.
    """
    raise NotImplementedError


def resolve(items: Sequence[Item], diagnostics: list[Diagnostic]) -> list[Command]:
    """Turn the planned items into the toolpath, in order.

    Every `TurnItem` becomes one or more `Move`s with plane "G18", start/end `[x, 0, z]`
    (x = radius), arcs with center/direction/radius/angle; transition elements become moves of
    their block (feed = the transition's E). Without SRK `end` is the tool tip and equals
    `programmed_end`; with SRK `end` is the nose-radius centre and `programmed_end` the contour
    point (inserted corner arcs carry the corner as `programmed_end`). Dwell, ToolChange and
    already finished Moves (G24–G28, G53) pass through unchanged; a passed-through Move ends SRK
    like a rapid. `SrkSwitch` items produce no command.

    Errors never raise: a train without a solution is reported on its closing (known-point) block,
    a missing transition partner on the block with the transition; the affected block then runs
    as a straight move to whatever end point is known (or is dropped when none is) so that the
    rest of the program still gives a toolpath. Codes: TX-E2xx / TX-W2xx (core/diagnostics.py).
    """
    raise NotImplementedError
