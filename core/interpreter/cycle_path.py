"""The moves of one cycle, built step by step: shared by the ISO drilling cycles (iso_cycles.py) and the PAL
milling cycles (pal_cycles.py).

A cycle's moves are the block's own move (the template: feed, spindle, tool, span) with another start and end,
tagged `cycle = (code, step, steps)` and, for PAL, the line of the defining block. Rapid moves stop exactly; the
spindle may be stopped or reversed for a move (tapping, boring)."""

from __future__ import annotations

import dataclasses
import math
from typing import Literal

from core.syntax.blocks import Span
from core.toolpath import Dwell, Move, MoveKind, Vec3

EPS = 1e-9
Spindle = Literal["on", "off", "reverse"]


class CyclePath:
    """Collects the moves and dwells of one cycle block or call (program coordinates) from `start`."""

    def __init__(
        self,
        code: str,
        template: Move,
        span: Span,
        start: Vec3,
        steps: int = 1,
        definition: int | None = None,
    ) -> None:
        self.code, self.template, self.span, self.definition = code, template, span, definition
        self.items: list[Move | Dwell] = []
        self.pos: Vec3 = start
        self.step, self.steps = 1, steps
        self.point: tuple[int, int] | None = None  # PAL calls: (point k, of n) the moves now belong to

    def go(
        self, kind: MoveKind, to: Vec3, spindle: Spindle = "on", feed: float | None = None, **arc: object
    ) -> None:
        """A move to `to` (nothing when it is already there, unless an arc's data make it a full circle)."""
        if math.dist(to, self.pos) < EPS and not arc:
            return
        t = self.template
        speed, direction = t.spindle, t.spindle_direction
        if spindle == "off":
            speed, direction = 0.0, None
        elif spindle == "reverse" and direction is not None:
            direction = "ccw" if direction == "cw" else "cw"
        self.items.append(
            dataclasses.replace(
                t,
                kind=kind,
                start=self.pos,
                end=to,
                spindle=speed,
                spindle_direction=direction,
                exact_stop=kind == "rapid",
                feed=t.feed if feed is None else feed,
                cycle=(self.code, self.step, self.steps),
                cycle_definition=self.definition,
                cycle_point=self.point,
                **arc,  # type: ignore[arg-type]
            )
        )
        self.pos = to

    def dwell(self, seconds: float) -> None:
        if seconds > 0:
            self.items.append(Dwell(self.pos, seconds, self.span))
