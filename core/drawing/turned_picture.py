"""The turned part as a picture in the drawing's view (RGB pixels): what the page shows of a lathe program while
the 3D view is off. Z to the right with the front face (Z0) on the right, X up; the upper half cut open and
hatched like a section (bores and grooves show), the lower half the part as seen, shaded as a cylinder; the
material the program removed from the blank faint, the spindle axis dash-dotted."""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

from core.sim.turning import Blank

BACKGROUND = (198, 205, 215)  # the 3D view's background (server/viz.py)
REMOVED = (226, 230, 236)  # inside the blank's outline, cut away
SECTION = (222, 184, 135)  # the cut face, as the 3D view's half section
HATCH = (120, 86, 52)  # its hatching
VIEW = (184, 190, 201)  # the part as seen (the 3D view's stock colour), shaded towards its silhouette
OUTLINE = (40, 44, 52)
AXIS = (70, 76, 86)
HATCH_PITCH = 7  # pixels between the 45° hatching lines
MARGIN = 0.07  # of the picture on every side


def half_section_image(
    outer: npt.NDArray[np.float64],
    inner: npt.NDArray[np.float64],
    z0: float,
    dz: float,
    blank: Blank,
    size: tuple[int, int] = (480, 320),
) -> npt.NDArray[np.uint8]:
    """The picture (height × width × 3) of a revolved profile: sample k covers z0 + k·dz … z0 + (k+1)·dz with
    material between inner[k] and outer[k] (radii, mm)."""
    width, height = size
    radius = blank.diameter / 2
    span_z, span_r = blank.length, 2 * radius
    scale = (1 - 2 * MARGIN) * min(width / span_z, height / span_r)  # pixels per mm
    zc = (np.arange(width) + 0.5 - width / 2) / scale - blank.length / 2  # the Z of each column (centred)
    rc = (height / 2 - (np.arange(height) + 0.5)) / scale  # the signed radius of each row
    k = np.clip(((zc - z0) / dz).astype(np.int64), 0, len(outer) - 1)
    on = (zc >= z0) & (zc <= z0 + len(outer) * dz)
    o = np.where(on, np.clip(outer[k], 0, None), -1.0)[None, :]
    i = np.where(on, np.clip(inner[k], 0, None), 0.0)[None, :]
    r = rc[:, None]
    a = np.abs(r)
    image = np.empty((height, width, 3), dtype=np.uint8)
    image[:] = BACKGROUND
    in_blank = on[None, :] & (a <= radius) & (a >= blank.bore / 2)
    image[in_blank] = REMOVED
    section = (r >= 0) & (r >= i) & (r <= o)
    image[section] = SECTION
    rows, cols = np.indices((height, width))
    image[section & ((rows + cols) % HATCH_PITCH == 0)] = HATCH
    view = (r < 0) & (a <= o)
    shade = np.sqrt(np.clip(1 - (a / np.maximum(o, 1e-9)) ** 2, 0, 1))
    tone = (0.72 + 0.28 * shade)[..., None] * np.asarray(VIEW, dtype=np.float64)
    image[view] = np.broadcast_to(tone, (height, width, 3))[view].astype(np.uint8)
    solid = section | view
    edge = np.zeros_like(solid)
    edge[1:, :] |= solid[1:, :] != solid[:-1, :]
    edge[:, 1:] |= solid[:, 1:] != solid[:, :-1]
    image[edge] = OUTLINE
    axis = int(np.argmin(np.abs(rc)))
    dash = (np.arange(width) % 22) < 14
    dash |= (np.arange(width) % 22 >= 17) & (np.arange(width) % 22 < 19)
    image[axis, dash] = AXIS
    return image
