"""The 3D view's preset views: from which direction each looks at the part, and where the camera stands so that
the part's box is centred in the picture and fills it but for a margin (scene mm, Z up)."""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

Box = tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]  # (lo, hi) mm

VIEWS = ("iso", "top", "front", "reset")
VIEW_MARGIN = 0.08  # every preset view leaves this much of the picture free around the part, on every side
FOV = float(np.radians(35))  # a narrow lens: the part looks as drawn, not bulging (viser's default is 75°)
# the direction from the part to the camera of each view (Z up; "front" looks along +Y as PAL drawings do)
VIEW_DIRECTIONS = {"iso": (0.55, -0.8, 0.65), "top": (0.0, -1e-3, 1.0), "front": (0.0, -1.0, 0.12)}
# the lathe's front view is the drawing itself: straight from the front, not from a little above
LATHE_DIRECTIONS = {**VIEW_DIRECTIONS, "front": (0.0, -1.0, 0.0)}
# a lathe program is shown in the lathe's drawing view (DECISIONS §15): a move's (x = radius, y, z) becomes the
# scene's (z, -y, x): Z (the spindle axis) to the right, the chuck side on the left, X up; the front camera
# stands at the lathe's +Y, so G2 is clockwise in the picture as in the manual
LATHE_AXES = np.array([[0.0, 0.0, 1.0], [0.0, -1.0, 0.0], [1.0, 0.0, 0.0]])


def home(lathe: bool) -> str:
    """The view a scene starts with (and goes back to on "reset"): iso for milling, the drawing for turning."""
    return "front" if lathe else "iso"


def camera_for(
    bounds: Box,
    view: str,
    aspect: float,
    fov: float = np.radians(50),
    lathe: bool = False,
    margin: float = VIEW_MARGIN,
) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]:
    """Eye and target (mm) so that the box is centred in the picture and fills it but for `margin` (a fraction
    of the picture's width and height) on every side: the distance at which the box's farthest-out corner just
    fits, in width and in height, the target moved until the box's picture has as much room left as right and
    above as below (perspective makes the near corners larger)."""
    lo, hi = bounds
    directions = LATHE_DIRECTIONS if lathe else VIEW_DIRECTIONS
    back = np.asarray(directions.get(view, directions["iso"]), dtype=np.float64)
    back /= np.linalg.norm(back)
    right = np.cross(np.array([0.0, 0.0, 1.0]), back)
    right = right / np.linalg.norm(right) if np.linalg.norm(right) > 1e-9 else np.array([1.0, 0.0, 0.0])
    up = np.cross(back, right)
    tan_v = np.tan(fov / 2) * (1 - 2 * margin)  # the box within the middle of the picture
    tan_h = np.tan(fov / 2) * max(aspect, 0.2) * (1 - 2 * margin)
    corners = np.array(np.meshgrid(*zip(lo, hi, strict=True))).T.reshape(-1, 3)
    target = (lo + hi) / 2
    distance = 1.0
    for _ in range(8):
        p = corners - target
        x, y, z = p @ right, p @ up, p @ back
        distance = max(float(np.max(np.maximum(np.abs(x) / tan_h, np.abs(y) / tan_v) + z)), 1.0)
        depth = distance - z
        u, v = x / (depth * tan_h), y / (depth * tan_v)  # where each corner lands, -1…1 across the picture
        shift_u, shift_v = (u.max() + u.min()) / 2, (v.max() + v.min()) / 2
        if abs(shift_u) < 1e-3 and abs(shift_v) < 1e-3:
            break
        target = target + right * shift_u * distance * tan_h + up * shift_v * distance * tan_v
    return target + back * distance, target
