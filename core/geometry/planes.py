"""Working planes: (x, y, z) ↔ (u, v, w) with u, v in the plane and w the axis perpendicular to it.

G17 X-Y (w = Z), G18 Z-X (w = Y), G19 Y-Z (w = X); each (u, v, w) is right-handed, so "clockwise"
in the plane is seen from +w towards the origin (DIN 66025, DECISIONS §13).
"""

from __future__ import annotations

Vec3 = tuple[float, float, float]

AXES: dict[str, tuple[int, int, int]] = {"G17": (0, 1, 2), "G18": (2, 0, 1), "G19": (1, 2, 0)}
NAMES = {"G17": "X-Y", "G18": "Z-X", "G19": "Y-Z"}


def to_plane(p: Vec3, plane: str) -> Vec3:
    i, j, k = AXES[plane]
    return (p[i], p[j], p[k])


def from_plane(q: Vec3, plane: str) -> Vec3:
    i, j, k = AXES[plane]
    out = [0.0, 0.0, 0.0]
    out[i], out[j], out[k] = q
    return (out[0], out[1], out[2])
