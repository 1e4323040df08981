"""Swept envelopes: the lowest point a cutter reaches over each cell of a window during one move.

Straight moves (any direction, Z may change) are exact: with s the along-track and q the cross-track
coordinate of a cell relative to the start, and the tool axis at along-track offset w from the cell
(w = s − t·L for t in 0…1), the tool's lowest point over the cell is z_a + m·(s − w) + f(√(w² + q²)),
m = dZ/L. For a convex profile that is convex in w; its minimiser depends on q and m only
(shapes.best_offset) and is clipped to the move's extent [s − L, s]. A flat tool at constant Z
sweeps a capsule, whose cut with each row of cells is one x interval.
Planar arcs are exact too: the distance of a cell from an arc is its radial distance when it lies
within the swept angle and the distance to the nearer end point otherwise. Helices are split into
chords whose sagitta stays below a quarter of a cell (core/sim/engine.py).

Every function works on the cells of one window (a slice of the height map under the move's
bounding box); cells the tool does not cover get +inf.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from core.sim.shapes import Array, Cutter, best_offset, profile
from core.toolpath import Vec3

INF = math.inf


@dataclass(frozen=True, slots=True)
class Grid:
    """Cell centres of the height map: column i at x0 + (i + ½)·dx, row j at y0 + (j + ½)·dy."""

    x0: float
    y0: float
    dx: float
    dy: float
    nx: int
    ny: int

    def xs(self, i0: int, i1: int) -> Array:
        return self.x0 + (np.arange(i0, i1, dtype=np.float64) + 0.5) * self.dx

    def ys(self, j0: int, j1: int) -> Array:
        return self.y0 + (np.arange(j0, j1, dtype=np.float64) + 0.5) * self.dy

    def window(self, xmin: float, xmax: float, ymin: float, ymax: float) -> tuple[int, int, int, int] | None:
        """Rows j0:j1 and columns i0:i1 whose centres lie in the box; None if there are none."""
        i0 = max(0, math.ceil((xmin - self.x0) / self.dx - 0.5))
        i1 = min(self.nx, math.floor((xmax - self.x0) / self.dx - 0.5) + 1)
        j0 = max(0, math.ceil((ymin - self.y0) / self.dy - 0.5))
        j1 = min(self.ny, math.floor((ymax - self.y0) / self.dy - 0.5) + 1)
        if i0 >= i1 or j0 >= j1:
            return None
        return j0, j1, i0, i1


def _finish(c: Cutter, r2: Array, base: Array | float) -> Array:
    """base + f(r) where r ≤ radius, +inf elsewhere."""
    inside = r2 <= c.radius * c.radius * (1 + 1e-9) + 1e-12  # the ramp minimiser sits on the rim exactly
    if c.profile == "flat":
        return np.where(inside, base, INF)
    return np.where(inside, base + profile(c, r2), INF)


def line_envelope(grid: Grid, win: tuple[int, int, int, int], c: Cutter, a: Vec3, b: Vec3) -> Array:
    """Lowest tool point over each cell of `win` while the tip moves straight from `a` to `b`."""
    j0, j1, i0, i1 = win
    x = grid.xs(i0, i1) - a[0]
    y = grid.ys(j0, j1) - a[1]
    ddx, ddy, ddz = b[0] - a[0], b[1] - a[1], b[2] - a[2]
    length = math.hypot(ddx, ddy)
    if length < 1e-9:  # vertical: the lowest of the two tips
        r2 = x[None, :] ** 2 + y[:, None] ** 2
        return _finish(c, r2, min(a[2], b[2]))
    ux, uy = ddx / length, ddy / length
    m = ddz / length
    if abs(uy) < 1e-12 or abs(ux) < 1e-12:  # along an axis: s and q are one-dimensional
        if abs(uy) < 1e-12:
            s1, q1 = x * ux, y
            s, q2 = s1[None, :], (q1 * q1)[:, None]
        else:
            s1, q1 = y * uy, x
            s, q2 = s1[:, None], (q1 * q1)[None, :]
        if m == 0:
            w1 = s1 - np.clip(s1, 0.0, length)
            r2 = (w1[None, :] ** 2 + q2) if abs(uy) < 1e-12 else (w1[:, None] ** 2 + q2)
            return _finish(c, r2, a[2])
        s = np.broadcast_to(s, (j1 - j0, i1 - i0))
        q2 = np.broadcast_to(q2, (j1 - j0, i1 - i0))
    else:
        if m == 0 and c.profile == "flat":
            lo, hi = _capsule_rows(y, c.radius, ddx, ddy, length)
            inside = (x[None, :] >= lo[:, None]) & (x[None, :] <= hi[:, None])
            return np.where(inside, a[2], INF)
        s = x[None, :] * ux + y[:, None] * uy
        q = y[:, None] * ux - x[None, :] * uy
        q2 = q * q
        if m == 0:
            w = s - np.clip(s, 0.0, length)
            return _finish(c, w * w + q2, a[2])
    w = np.clip(best_offset(c, q2, m), s - length, s)
    return _finish(c, w * w + q2, a[2] + m * (s - w))


def _capsule_rows(y: Array, radius: float, ddx: float, ddy: float, length: float) -> tuple[Array, Array]:
    """Per row (offset `y` from the start), the x range (relative to the start) of the capsule swept by a
    disc of `radius` from (0, 0) to (ddx, ddy); empty rows get lo > hi. Neither ddx nor ddy is 0.

    The capsule is convex and the union of the two end discs and the band between them, so its cut
    with a row is the span of the three pieces' cuts.
    """
    radius = radius * (1 + 5e-10) + 1e-12  # the same rim tolerance as _finish
    r2 = radius * radius
    lo = np.full(y.shape, INF)
    hi = np.full(y.shape, -INF)
    for cy, cx in ((0.0, 0.0), (ddy, ddx)):
        dy2 = (y - cy) ** 2
        ok = dy2 <= r2
        half = np.sqrt(np.maximum(r2 - dy2, 0.0))
        lo = np.where(ok, np.minimum(lo, cx - half), lo)
        hi = np.where(ok, np.maximum(hi, cx + half), hi)
    ux, uy = ddx / length, ddy / length
    # band: |x·uy − y·ux| ≤ r (across) and 0 ≤ x·ux + y·uy ≤ L (along), each an x interval as uy, ux ≠ 0
    a1 = (y * ux - radius) / uy
    a2 = (y * ux + radius) / uy
    b1 = (0.0 - y * uy) / ux
    b2 = (length - y * uy) / ux
    band_lo = np.maximum(np.minimum(a1, a2), np.minimum(b1, b2))
    band_hi = np.minimum(np.maximum(a1, a2), np.maximum(b1, b2))
    ok = band_lo <= band_hi
    lo = np.where(ok, np.minimum(lo, band_lo), lo)
    hi = np.where(ok, np.maximum(hi, band_hi), hi)
    return lo, hi


def arc_envelope(
    grid: Grid,
    win: tuple[int, int, int, int],
    c: Cutter,
    start: Vec3,
    end: Vec3,
    center: Vec3,
    ccw: bool,
    sweep_rad: float,
) -> Array:
    """Lowest tool point over each cell of `win` along a planar arc at Z = start Z."""
    j0, j1, i0, i1 = win
    x = (grid.xs(i0, i1) - center[0])[None, :]
    y = (grid.ys(j0, j1) - center[1])[:, None]
    radius = math.hypot(start[0] - center[0], start[1] - center[1])
    rp = np.sqrt(x * x + y * y)
    r2_arc = (rp - radius) ** 2
    if sweep_rad >= 2 * math.pi - 1e-9:
        return _finish(c, r2_arc, start[2])
    theta0 = math.atan2(start[1] - center[1], start[0] - center[0])
    phi = np.arctan2(y, x)
    rel = np.mod((phi - theta0) if ccw else (theta0 - phi), 2 * math.pi)
    sx, sy = start[0] - center[0], start[1] - center[1]
    ex, ey = end[0] - center[0], end[1] - center[1]
    r2_ends = np.minimum((x - sx) ** 2 + (y - sy) ** 2, (x - ex) ** 2 + (y - ey) ** 2)
    r2 = np.where(rel <= sweep_rad + 1e-12, r2_arc, r2_ends)
    return _finish(c, r2, start[2])
