"""Exports of the turned part: the revolved profile as a closed triangle mesh (for STL) and a half-section
drawing as PNG (upper half cut open, lower half the view, the chuck's jaws at the left).

Both return values; writing files is the CLI's business. The spindle axis is the mesh's Z axis.
"""

from __future__ import annotations

import math
import struct
import zlib

import numpy as np
import numpy.typing as npt

from core.sim.export import Triangles, Vertices
from core.sim.turning import Blank, RevolvedProfile

SECTIONS = 64  # the revolved mesh's sections around the axis


def _runs(profile: RevolvedProfile) -> list[tuple[int, int]]:
    """The Z ranges (sample index from, to) where material is left: each one a separate solid."""
    solid = np.concatenate([[False], profile.outer - np.clip(profile.inner, 0, None) > 1e-6, [False]])
    edges = np.flatnonzero(np.diff(solid.astype(np.int8)))
    return [(int(a), int(b)) for a, b in zip(edges[::2], edges[1::2], strict=True)]


def _simplify(points: list[tuple[float, float]]) -> list[tuple[float, float]]:
    """Drop points on a straight line between their neighbours (a long cylinder is 2 points, not 2000)."""
    out: list[tuple[float, float]] = []
    for p in points:
        while len(out) >= 2:
            (az, ar), (bz, br) = out[-2], out[-1]
            cross = (bz - az) * (p[1] - ar) - (br - ar) * (p[0] - az)
            if abs(cross) > 1e-7 * max(1.0, math.hypot(p[0] - az, p[1] - ar)):
                break
            out.pop()
        out.append(p)
    return out


def _loop(profile: RevolvedProfile, a: int, b: int) -> list[tuple[float, float]]:
    """The closed outline (z, r) of the solid over samples a … b−1: front face, outside, back face, bore."""
    z = profile.zs[a:b]
    lo, hi = profile.z0 + a * profile.dz, profile.z0 + b * profile.dz
    outer = np.clip(profile.outer[a:b], 0, None)
    inner = np.clip(profile.inner[a:b], 0, None)
    out = [(hi, float(outer[-1]))] + [
        (float(zz), float(r)) for zz, r in zip(z[::-1], outer[::-1], strict=True)
    ]
    out += [(lo, float(outer[0]))]
    inn = [(lo, float(inner[0]))] + [(float(zz), float(r)) for zz, r in zip(z, inner, strict=True)]
    inn += [(hi, float(inner[-1]))]
    return _simplify(out) + _simplify(inn)


def revolved_mesh(
    profile: RevolvedProfile, sections: int = SECTIONS, max_triangles: int = 500_000
) -> tuple[Vertices, Triangles]:
    """The part as a closed, outward-oriented triangle mesh (axis = Z). Points on the axis are one vertex.
    Over `max_triangles`, first fewer sections (down to 16), then every k-th point of the outline."""
    loops = [_loop(profile, a, b) for a, b in _runs(profile)]
    points = sum(len(loop) for loop in loops)
    if 2 * points * sections > max_triangles:
        sections = max(16, min(sections, max_triangles // max(1, 2 * points)))
    if 2 * points * sections > max_triangles:
        k = math.ceil(2 * points * sections / max_triangles)
        loops = [loop[::k] if len(loop) > 2 * k + 4 else loop for loop in loops]
    angles = np.linspace(0, 2 * math.pi, sections, endpoint=False)
    cos, sin = np.cos(angles), np.sin(angles)
    verts: list[npt.NDArray[np.float64]] = []
    tris: list[npt.NDArray[np.int64]] = []
    base = 0
    for loop in loops:
        ids: list[npt.NDArray[np.int64]] = []
        for z, r in loop:
            if r <= 1e-9:
                verts.append(np.array([[0.0, 0.0, z]]))
                ids.append(np.full(sections, base, dtype=np.int64))
                base += 1
            else:
                verts.append(np.stack([r * cos, r * sin, np.full(sections, z)], axis=1))
                ids.append(base + np.arange(sections, dtype=np.int64))
                base += sections
        m = len(loop)
        for i in range(m):
            p, q = ids[i], ids[(i + 1) % m]
            pn, qn = np.roll(p, -1), np.roll(q, -1)
            for t in (np.stack([p, q, qn], 1), np.stack([p, qn, pn], 1)):
                keep = (t[:, 0] != t[:, 1]) & (t[:, 1] != t[:, 2]) & (t[:, 0] != t[:, 2])
                tris.append(t[keep])
    if not verts:
        return np.zeros((0, 3), dtype=np.float32), np.zeros((0, 3), dtype=np.int32)
    v = np.concatenate(verts)
    t = np.concatenate(tris)
    if _signed_volume(v, t) < 0:  # the loop's sense decides the winding: make the normals point outwards
        t = t[:, ::-1]
    return v.astype(np.float32), t.astype(np.int32)


def _signed_volume(v: npt.NDArray[np.float64], t: npt.NDArray[np.int64]) -> float:
    a, b, c = v[t[:, 0]], v[t[:, 1]], v[t[:, 2]]
    return float(np.sum(np.einsum("ij,ij->i", a, np.cross(b, c)))) / 6


def _chunk(kind: bytes, payload: bytes) -> bytes:
    return struct.pack(">I", len(payload)) + kind + payload + struct.pack(">I", zlib.crc32(kind + payload))


MATERIAL = (150, 150, 150)  # the cut-open upper half
VIEW = (215, 215, 215)  # the lower half as seen
BLANK = (238, 238, 238)  # what was removed, inside the blank's outline
JAWS = (70, 90, 140)
AXIS = (200, 40, 40)


def half_section_png(profile: RevolvedProfile, blank: Blank, max_pixels: int = 1200) -> bytes:
    """The drawing view (Z to the right, X up): upper half cut open, lower half the view, RGB 8 bit."""
    jaw_r = blank.jaw_radius
    width_mm = blank.length + 10.0
    height_mm = 2 * jaw_r + 10.0
    scale = min(20.0, max_pixels / max(width_mm, height_mm))  # pixels per mm
    w, h = max(2, round(width_mm * scale)), max(2, round(height_mm * scale))
    zc = -blank.length - 5.0 + (np.arange(w) + 0.5) / scale  # the Z of each column
    xc = jaw_r + 5.0 - (np.arange(h) + 0.5) / scale  # the radius (signed) of each row
    k = np.clip(((zc - profile.z0) / profile.dz).astype(np.int64), 0, len(profile.outer) - 1)
    inside = (zc >= profile.z0) & (zc <= profile.z0 + len(profile.outer) * profile.dz)
    outer = np.where(inside, np.clip(profile.outer[k], 0, None), -1.0)[None, :]
    inner = np.where(inside, np.clip(profile.inner[k], 0, None), 0.0)[None, :]
    x = xc[:, None]
    img = np.full((h, w, 3), 255, dtype=np.uint8)
    blank_zone = inside[None, :] & (np.abs(x) <= blank.diameter / 2) & (np.abs(x) >= blank.bore / 2)
    img[blank_zone] = BLANK
    img[(x >= 0) & (x >= inner) & (x <= outer)] = MATERIAL
    img[(x < 0) & (-x <= outer)] = VIEW
    jaw_z = (zc >= -blank.length) & (zc <= -blank.length + blank.clamp)
    jaws = jaw_z[None, :] & (np.abs(x) >= blank.diameter / 2) & (np.abs(x) <= jaw_r)
    img[jaws] = JAWS
    axis_row = int(np.argmin(np.abs(xc)))
    img[axis_row, ::4] = AXIS
    rows = np.concatenate([np.zeros((h, 1), dtype=np.uint8), img.reshape(h, w * 3)], axis=1)
    ihdr = struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0)
    return (
        b"\x89PNG\r\n\x1a\n"
        + _chunk(b"IHDR", ihdr)
        + _chunk(b"IDAT", zlib.compress(rows.tobytes(), 6))
        + _chunk(b"IEND", b"")
    )
