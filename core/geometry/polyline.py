"""Thinning a sampled profile: the turned part's outline r(z) drawn with few points (the 2D picture, the 3D view)."""

from __future__ import annotations

import numpy as np
import numpy.typing as npt


def simplified(z: npt.NDArray[np.float64], r: npt.NDArray[np.float64], tol: float) -> npt.NDArray[np.int64]:
    """The indices of a polyline r(z) kept so that the dropped points are within `tol` of it (Ramer–Douglas–
    Peucker, measured along r: r is a function of z)."""
    keep = np.zeros(len(z), dtype=bool)
    keep[[0, -1]] = True
    stack = [(0, len(z) - 1)]
    while stack:
        a, b = stack.pop()
        if b - a < 2:
            continue
        t = (z[a + 1 : b] - z[a]) / max(z[b] - z[a], 1e-12)
        err = np.abs(r[a + 1 : b] - (r[a] + t * (r[b] - r[a])))
        k = int(np.argmax(err))
        if err[k] > tol:
            keep[a + 1 + k] = True
            stack += [(a, a + 1 + k), (a + 1 + k, b)]
    return np.flatnonzero(keep)
