"""The turned part in the lathe's 3D view: the bar revolved from the turning simulation's profile, the chuck
that holds it, and the deviation bands after grading.

The profile r_out(z)/r_in(z) (core/sim/turning.py) is revolved in chunks of CHUNK_MM along Z, each a mesh with
a digest, so that a playback step resends only the chunks whose part of the profile changed (VISER.md:
revolved meshes). Scene coordinates as core/scene/payload.py's LATHE_AXES: Z to the right, the radius up
(θ = 0) and towards the back (+y); scene mm.
"""

from __future__ import annotations

import itertools
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any, NamedTuple

import numpy as np
import numpy.typing as npt

from core.geometry.polyline import simplified
from core.scene.meshes import Mesh, Tiles, box, digest, merge, revolve
from core.sim.turning import Blank, RevolvedProfile
from core.toolpath import Toolpath

TURNED_RESOLUTION = 0.1  # mm along Z: the view's profile (radii are exact)
CHUNK_MM = 10.0  # along Z; at most MAX_CHUNKS chunks (longer ones for a long bar)
MAX_CHUNKS = 40
PROFILE_TOLERANCE = 0.01  # mm: the outline simplified within this (the exam's radial tolerance)
CORNER = np.radians(35)  # the outline turning by more than this is an edge (its own normals)
CUT_OFFSET = 0.05  # mm: the cut face a little behind the plane of the toolpath, which stays visible on it
BAND_LIFT = 0.08  # mm: a deviation band lies just outside the turned surface (inside the bore), not in it


@dataclass(frozen=True, eq=False)
class TurnedProfile:
    """The turned part as the view keeps it (float32 radii: it crosses from the worker and back): sample k
    covers z0 + k·dz … z0 + (k+1)·dz with material between inner[k] and outer[k]."""

    z0: float
    dz: float
    outer: npt.NDArray[np.float32]
    inner: npt.NDArray[np.float32]

    @classmethod
    def of(cls, profile: RevolvedProfile) -> TurnedProfile:
        return cls(
            float(profile.z0),
            float(profile.dz),
            np.asarray(profile.outer, np.float32),
            np.asarray(profile.inner, np.float32),
        )


@dataclass(frozen=True, slots=True)
class ViewBlank:
    """The blank the view turns and the chuck holds (mm); the 3D answer names it (POST /viz/{token}/scene)."""

    diameter: float
    inner_diameter: float
    length: float
    clamp: float  # the jaws hold the last `clamp` mm
    jaw_radius: float

    @classmethod
    def of(cls, blank: Blank) -> ViewBlank:
        return cls(
            float(blank.diameter),
            float(blank.bore),
            float(blank.length),
            float(blank.clamp),
            float(blank.jaw_radius),
        )


def view_blank(given: Mapping[str, Any] | None, toolpath: Toolpath) -> Blank:
    """The blank the lathe view turns: `given` (the request's or the exercise's: diameter, length,
    inner_diameter, chuck_length, jaw_diameter), else a bar around the program (Ø the largest diameter of its
    cutting moves, long enough that the chuck stays clear of them)."""
    if given:
        return Blank(
            float(given["diameter"]),
            float(given["length"]),
            float(given.get("inner_diameter") or 0.0),
            given.get("chuck_length"),
            given.get("jaw_diameter"),
        )
    cutting = [m for m in toolpath.moves if m.kind != "rapid"]
    points = np.array(
        [p for m in cutting for p in (m.start, m.end)] or [(10.0, 0.0, -10.0)], dtype=np.float64
    )
    diameter = max(10.0, float(np.ceil(2 * np.max(np.abs(points[:, 0])) - 1e-6)))
    depth = max(5.0, -float(np.min(points[:, 2])))
    length = max(20.0, 5 * float(np.ceil(1.5 * (depth + 5) / 5)))  # the chuck holds at most a third
    return Blank(min(diameter, 2000.0), min(length, 5000.0))


def _pieces(points: npt.NDArray[np.float64]) -> list[npt.NDArray[np.float64]]:
    """A polyline (z, r) cut at its corners: each piece is revolved with its own normals."""
    if len(points) < 3:
        return [points]
    d = np.diff(points, axis=0)
    angle = np.arctan2(d[:, 1], d[:, 0])
    turn = np.abs((np.diff(angle) + np.pi) % (2 * np.pi) - np.pi)
    cuts = np.flatnonzero(turn > CORNER) + 1
    return [points[a : b + 1] for a, b in itertools.pairwise([0, *cuts.tolist(), len(points) - 1])]


def _section(zz: npt.NDArray[np.float64], ro: npt.NDArray[Any], ri: npt.NDArray[Any]) -> list[Mesh]:
    """The cut face of a half section between the radii `ri` and `ro` over `zz`: its upper and lower half."""
    faces = []
    for sign in (1.0, -1.0):
        top = np.stack([zz, np.full_like(zz, CUT_OFFSET), sign * ro], -1)
        bottom = np.stack([zz, np.full_like(zz, CUT_OFFSET), sign * ri], -1)
        count = len(zz)
        q = np.arange(count - 1)
        tris = np.concatenate(
            [np.stack([q, q + 1, count + q + 1], -1), np.stack([q, count + q + 1, count + q], -1)]
        )
        faces.append((np.vstack([top, bottom]).astype(np.float32), tris.astype(np.uint32)))
    return faces


def turned_chunks(profile: TurnedProfile, half: bool) -> Tiles:
    """The turned part as chunks along Z: {"z<k>": its revolved surface} and, in a half section, {"z<k>_cut":
    the cut face} (digest, vertices, triangles). Faces across the axis are drawn only where the material
    really ends (the front face, the parted-off end) or its radius steps (a shoulder on the border of two
    chunks), not between chunks: the chunks together are one closed surface."""
    z0, dz = profile.z0, profile.dz
    outer = np.asarray(profile.outer, np.float64)
    inner = np.clip(np.asarray(profile.inner, np.float64), 0.0, None)
    n = len(outer)
    solid = outer - inner > 1e-6
    per = max(1, round(max(CHUNK_MM, n * dz / MAX_CHUNKS) / dz))
    zs = z0 + (np.arange(n) + 0.5) * dz
    chunks: Tiles = {}
    for k, a in enumerate(range(0, n, per)):
        b = min(n, a + per)
        edges = np.flatnonzero(np.diff(np.concatenate([[0], solid[a:b].astype(np.int8), [0]])))
        surface: list[Mesh] = []
        cut: list[Mesh] = []
        for i, j in zip(a + edges[::2], a + edges[1::2], strict=True):
            lo, hi = z0 + i * dz, z0 + j * dz
            z = np.concatenate([[lo], zs[i:j], [hi]])
            o = np.concatenate([[outer[i]], outer[i:j], [outer[j - 1]]])
            m = np.concatenate([[inner[i]], inner[i:j], [inner[j - 1]]])
            ko, ki = simplified(z, o, PROFILE_TOLERANCE), simplified(z, m, PROFILE_TOLERANCE)
            outline = [np.stack([z[ko], o[ko]], -1)]
            if np.any(m > 1e-9):
                outline.append(np.stack([z[ki], m[ki]], -1))
            if i == 0 or not solid[i - 1]:  # the material ends here: the face across
                outline.append(np.array([[lo, inner[i]], [lo, outer[i]]]))
            else:  # it goes on from the chunk before: a shoulder (or a bore's) on the border between them
                outline += [
                    np.array([[lo, r[i - 1]], [lo, r[i]]]) for r in (outer, inner) if r[i] != r[i - 1]
                ]
            if j == n or not solid[j]:
                outline.append(np.array([[hi, inner[j - 1]], [hi, outer[j - 1]]]))
            for line in outline:
                surface += [revolve(piece, half) for piece in _pieces(line) if len(piece) >= 2]
            if half:
                zz = np.union1d(z[ko], z[ki])
                cut += _section(zz, np.interp(zz, z[ko], o[ko]), np.interp(zz, z[ki], m[ki]))
        for key, parts in ((f"z{k}", surface), (f"z{k}_cut", cut)):
            if parts:
                v, t = merge(parts)
                chunks[key] = (digest(v, t), v, t)
    return chunks


class ChuckMeshes(NamedTuple):
    body: Mesh
    jaws: Mesh


def chuck_meshes(blank: ViewBlank, half: bool) -> ChuckMeshes:
    """The chuck at the bar's back end (left) and its three jaws holding the last `clamp` mm; in a half section
    only the back half of the chuck and the jaws behind the cut."""
    r = blank.diameter / 2
    jaw_r = max(blank.jaw_radius, r + 5.0)
    back = -blank.length
    body_r, depth = jaw_r + 4.0, float(np.clip(0.4 * jaw_r, 12.0, 40.0))  # the chuck's face, behind the jaws
    outline = np.array([[back, 0.0], [back, body_r], [back - depth, body_r], [back - depth, 0.0]])
    body = merge([revolve(piece, half, 64) for piece in (outline[:2], outline[1:3], outline[2:])])
    width = float(np.clip(0.5 * r, 8.0, 30.0))
    jaws = []
    for theta in np.radians([0.0, 120.0, 240.0]):
        if half and np.sin(theta) < -1e-9:  # in front of the cut: left out
            continue
        u = np.array([0.0, np.sin(theta), np.cos(theta)])  # radial (scene y, z)
        v = np.array([0.0, np.cos(theta), -np.sin(theta)])  # tangential
        corners = np.array(
            [
                [z, 0.0, 0.0] + t * v + rr * u
                for rr in (r, jaw_r)
                for t in (-width / 2, width / 2)
                for z in (back, back + blank.clamp)
            ]
        )
        jaws.append(box(corners))
    return ChuckMeshes(body, merge(jaws))


def deviation_band(
    part: RevolvedProfile, outside: npt.NDArray[np.bool_], inside: npt.NDArray[np.bool_], half: bool
) -> Mesh:
    """Revolved strips over the runs of marked Z samples: on the outside surface (lifted by BAND_LIFT) and in
    the bore (lowered by it)."""
    z0, dz = float(part.z0), float(part.dz)
    outer = np.asarray(part.outer, np.float64)
    inner = np.clip(np.asarray(part.inner, np.float64), 0.0, None)
    zs = z0 + (np.arange(len(outer)) + 0.5) * dz
    parts = []
    for marked, radius, lift in ((outside, outer, BAND_LIFT), (inside, inner, -BAND_LIFT)):
        mask = marked & (outer - inner > 1e-6)
        edges = np.flatnonzero(np.diff(np.concatenate([[0], mask.astype(np.int8), [0]])))
        for i, j in zip(edges[::2], edges[1::2], strict=True):
            z = np.concatenate([[z0 + i * dz], zs[i:j], [z0 + j * dz]])
            r = np.clip(np.concatenate([[radius[i]], radius[i:j], [radius[j - 1]]]) + lift, 0.0, None)
            keep = simplified(z, r, PROFILE_TOLERANCE)
            parts.append(revolve(np.stack([z[keep], r[keep]], -1), half))
    return merge(parts)
