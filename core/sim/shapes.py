"""Tool shapes for the height map: the lower envelope of a tool's cutting part, as a profile f(r).

A `Cutter` is a solid of revolution about the tool axis; `f(r)` is the height of its lowest point
above the tip at distance r ≤ radius from the axis. Every profile here is convex and
non-decreasing in r (flat, ball, torus, cone), which is what makes the swept envelope of a
straight move exact (see core/sim/sweep.py): along a line, the lowest point the tool reaches over
a cell is the minimum of a convex function of one variable.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

import numpy as np
import numpy.typing as npt

from core.tools import Tool

Array = npt.NDArray[np.float64]
Profile = Literal["flat", "ball", "torus", "cone"]

DEFAULT_POINT_ANGLE = {"twist_drill": 118.0, "spot_drill": 90.0}


@dataclass(frozen=True, slots=True)
class Cutter:
    """A cutting part: `radius` mm; `corner` the corner radius (torus, ball); `slope` mm of height per
    mm of radius (cone: 1 / tan(half the point angle))."""

    radius: float
    profile: Profile
    corner: float = 0.0
    slope: float = 0.0

    @property
    def height(self) -> float:
        """f(radius): how far above the tip the profile reaches its full radius."""
        if self.profile == "cone":
            return self.slope * self.radius
        return self.corner if self.profile in ("ball", "torus") else 0.0


def cutter_of(tool: Tool) -> Cutter:
    """The cutting part of `tool` as a profile."""
    r = tool.radius
    if tool.kind in ("twist_drill", "spot_drill"):
        angle = tool.point_angle or DEFAULT_POINT_ANGLE[tool.kind]
        return Cutter(r, "cone", slope=1 / math.tan(math.radians(angle) / 2))
    corner = r if tool.kind == "ball_nose" else min(max(tool.corner_radius, 0.0), r)
    if corner <= 0:
        return Cutter(r, "flat")
    if corner >= r:
        return Cutter(r, "ball", corner=r)
    return Cutter(r, "torus", corner=corner)


def flat(radius: float) -> Cutter:
    return Cutter(radius, "flat")


def profile(c: Cutter, r2: Array) -> Array:
    """f(r) for squared distances `r2` (values above radius² are treated as radius²)."""
    r2 = np.minimum(r2, c.radius * c.radius)
    if c.profile == "flat":
        return np.zeros_like(r2)
    if c.profile == "cone":
        return c.slope * np.sqrt(r2)
    if c.profile == "ball":
        return c.radius - np.sqrt(np.maximum(c.radius * c.radius - r2, 0.0))
    flat_r = c.radius - c.corner
    e = np.maximum(np.sqrt(r2) - flat_r, 0.0)
    return c.corner - np.sqrt(np.maximum(c.corner * c.corner - e * e, 0.0))


def best_offset(c: Cutter, q2: Array, m: float) -> Array:
    """The along-track offset w of a cell from the tool axis that minimises m·(−w) + f(√(w² + q²)).

    `q2` is the squared distance of the cell from the line of the move, `m` the move's slope dZ/dXY.
    The result is limited to |w| ≤ √(radius² − q²), the cells the tool covers.
    """
    rho = np.sqrt(np.maximum(c.radius * c.radius - q2, 0.0))
    if m == 0:
        return np.zeros_like(q2)
    sign = 1.0 if m > 0 else -1.0
    am = abs(m)
    if c.profile == "flat":
        return sign * rho
    if c.profile == "ball":
        return sign * rho * (am / math.sqrt(1 + am * am))
    if c.profile == "cone":
        if am >= c.slope:
            return sign * rho
        w = np.sqrt(q2) * (am / math.sqrt(c.slope * c.slope - am * am))
        return sign * np.minimum(w, rho)
    # torus: bisection on the derivative f'(r)·w/r − |m|, which grows with w
    lo = np.zeros_like(q2)
    hi = rho.copy()
    flat_r = c.radius - c.corner
    for _ in range(30):
        mid = (lo + hi) / 2
        r = np.sqrt(mid * mid + q2)
        e = np.maximum(r - flat_r, 0.0)
        slope = e / np.sqrt(np.maximum(c.corner * c.corner - e * e, 1e-12))
        grad = np.where(r > 0, slope * mid / np.maximum(r, 1e-12), 0.0) - am
        below = grad < 0
        lo = np.where(below, mid, lo)
        hi = np.where(below, hi, mid)
    return sign * (lo + hi) / 2
