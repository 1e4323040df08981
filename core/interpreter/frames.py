"""Coordinate frames: how the coordinates a program writes map into the workpiece frame of G54.

A frame is base zero point (G54–G57, or G53's machine zero) + programmable shift and rotation
(G58/G59) + mirroring (G66). Every move is reported in the workpiece frame, so consumers never
see a transform. program → workpiece: p_w = origin + R(rotation) · M(mirror) · p_p.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

from core.toolpath import Move, Vec3


@dataclass(frozen=True, slots=True)
class Frame:
    base: Vec3 = (0.0, 0.0, 0.0)  # origin of the selected zero point (G54–G57, G53) in the G54 frame
    shift: Vec3 = (0.0, 0.0, 0.0)  # programmable shift (G58/G59), accumulated, in the G54 frame
    rotation: float = 0.0  # degrees about Z, accumulated
    mirror_x: bool = False  # X coordinates change sign (G66 Y)
    mirror_y: bool = False  # Y coordinates change sign (G66 X)

    @property
    def identity(self) -> bool:
        return self is IDENTITY or self == IDENTITY

    @property
    def flips(self) -> bool:
        """An odd number of mirrored axes: arcs and compensation sides swap."""
        return self.mirror_x != self.mirror_y

    @property
    def origin(self) -> Vec3:
        return (self.base[0] + self.shift[0], self.base[1] + self.shift[1], self.base[2] + self.shift[2])

    def to_workpiece(self, p: Vec3) -> Vec3:
        x = -p[0] if self.mirror_x else p[0]
        y = -p[1] if self.mirror_y else p[1]
        if self.rotation:
            a = math.radians(self.rotation)
            x, y = x * math.cos(a) - y * math.sin(a), x * math.sin(a) + y * math.cos(a)
        o = self.origin
        return (o[0] + x, o[1] + y, o[2] + p[2])

    def to_program(self, p: Vec3) -> Vec3:
        o = self.origin
        x, y = p[0] - o[0], p[1] - o[1]
        if self.rotation:
            a = math.radians(-self.rotation)
            x, y = x * math.cos(a) - y * math.sin(a), x * math.sin(a) + y * math.cos(a)
        return (-x if self.mirror_x else x, -y if self.mirror_y else y, p[2] - o[2])

    def shifted(self, dx: float, dy: float, dz: float, rotate: float) -> Frame:
        """G58/G59: shift by (dx, dy) given in the current (rotated) frame, then rotate by `rotate`."""
        a = math.radians(self.rotation)
        wx, wy = dx * math.cos(a) - dy * math.sin(a), dx * math.sin(a) + dy * math.cos(a)
        s = self.shift
        return dataclasses.replace(
            self, shift=(s[0] + wx, s[1] + wy, s[2] + dz), rotation=self.rotation + rotate
        )

    def map_move(self, m: Move) -> Move:
        """`m`, written in this frame, in workpiece coordinates."""
        if self.identity:
            return m
        direction = m.direction
        if direction is not None and self.flips:
            direction = "ccw" if direction == "cw" else "cw"
        return dataclasses.replace(
            m,
            start=self.to_workpiece(m.start),
            end=self.to_workpiece(m.end),
            center=None if m.center is None else self.to_workpiece(m.center),
            direction=direction,
        )


IDENTITY = Frame()
