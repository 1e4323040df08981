"""Exports of the machined stock: a closed triangle mesh, binary STL and a top-view depth image (PNG).

All three return values (arrays or bytes); writing files is the CLI's business. The mesh is the
height map's top surface on a regular vertex grid, closed by four walls and a bottom; decimation
takes every k-th cell with the smallest k that keeps the mesh under the triangle budget.
"""

from __future__ import annotations

import hashlib
import math
import struct
import zlib

import numpy as np
import numpy.typing as npt

from core.sim.engine import HeightMap

Vertices = npt.NDArray[np.float32]
Triangles = npt.NDArray[np.int32]


def _triangles(cx: int, cy: int) -> int:
    return 2 * (cx - 1) * (cy - 1) + 6 * ((cx - 1) + (cy - 1))


def _samples(n: int, k: int) -> npt.NDArray[np.int64]:
    idx = np.arange(0, n, k, dtype=np.int64)
    return idx if idx[-1] == n - 1 else np.append(idx, n - 1)


def surface_mesh(hm: HeightMap, max_triangles: int = 200_000) -> tuple[Vertices, Triangles]:
    """A closed, outward-oriented mesh of the stock with at most `max_triangles` (at least 2×2 vertices)."""
    g = hm.grid
    k = 1
    while _triangles(
        len(_samples(g.nx, k)) if g.nx > 1 else 2, len(_samples(g.ny, k)) if g.ny > 1 else 2
    ) > max_triangles and (k < g.nx or k < g.ny):
        k = max(k + 1, int(k * 1.25))
    ix = _samples(g.nx, k) if g.nx > 1 else np.array([0, 0])
    iy = _samples(g.ny, k) if g.ny > 1 else np.array([0, 0])
    cx, cy = len(ix), len(iy)
    xs = g.x0 + (ix + 0.5) * g.dx
    ys = g.y0 + (iy + 0.5) * g.dy
    xs[0], xs[-1] = g.x0, g.x0 + g.nx * g.dx
    ys[0], ys[-1] = g.y0, g.y0 + g.ny * g.dy
    top = np.clip(hm.heights[np.ix_(iy, ix)], hm.base, hm.top)
    gx, gy = np.meshgrid(xs, ys)
    n = cx * cy
    verts = np.empty((2 * n, 3), dtype=np.float32)
    verts[:n, 0], verts[:n, 1], verts[:n, 2] = gx.ravel(), gy.ravel(), top.ravel()
    verts[n:, 0], verts[n:, 1], verts[n:, 2] = gx.ravel(), gy.ravel(), hm.base

    def vid(j: npt.NDArray[np.int64] | int, i: npt.NDArray[np.int64] | int) -> npt.NDArray[np.int64]:
        out: npt.NDArray[np.int64] = np.asarray(j, dtype=np.int64) * cx + np.asarray(i, dtype=np.int64)
        return out

    jj, ii = np.meshgrid(np.arange(cy - 1), np.arange(cx - 1), indexing="ij")
    v00, v10, v01, v11 = (
        vid(jj, ii).ravel(),
        vid(jj, ii + 1).ravel(),
        vid(jj + 1, ii).ravel(),
        vid(jj + 1, ii + 1).ravel(),
    )
    faces = [np.stack([v00, v10, v11], 1), np.stack([v00, v11, v01], 1)]
    i = np.arange(cx - 1)
    j = np.arange(cy - 1)
    t0, t1 = vid(0, i), vid(0, i + 1)  # front wall y = y0, normal −Y
    faces += [np.stack([t0 + n, t1 + n, t1], 1), np.stack([t0 + n, t1, t0], 1)]
    t0, t1 = vid(cy - 1, i), vid(cy - 1, i + 1)  # back wall, normal +Y
    faces += [np.stack([t1 + n, t0 + n, t0], 1), np.stack([t1 + n, t0, t1], 1)]
    t0, t1 = vid(j, 0), vid(j + 1, 0)  # left wall x = x0, normal −X
    faces += [np.stack([t1 + n, t0 + n, t0], 1), np.stack([t1 + n, t0, t1], 1)]
    t0, t1 = vid(j, cx - 1), vid(j + 1, cx - 1)  # right wall, normal +X
    faces += [np.stack([t0 + n, t1 + n, t1], 1), np.stack([t0 + n, t1, t0], 1)]
    ring = (
        np.concatenate(
            [
                vid(0, np.arange(cx - 1)),
                vid(np.arange(cy - 1), cx - 1),
                vid(cy - 1, np.arange(cx - 1, 0, -1)),
                vid(np.arange(cy - 1, 0, -1), 0),
            ]
        )
        + n
    )
    centre = np.full(len(ring), 2 * n, dtype=np.int64)
    faces.append(np.stack([centre, np.roll(ring, -1), ring], 1))  # bottom, normal −Z
    verts = np.vstack(
        [verts, np.array([[(xs[0] + xs[-1]) / 2, (ys[0] + ys[-1]) / 2, hm.base]], dtype=np.float32)]
    )
    tris = np.concatenate(faces).astype(np.int64)
    used, remap = np.unique(tris, return_inverse=True)
    return verts[used], remap.reshape(tris.shape).astype(np.int32)


TILE_CELLS = 40  # cells along each side of a stock tile (20 mm at the 3D view's 0.5 mm)


def stock_tiles(
    hm: HeightMap, max_triangles: int, tile_cells: int = TILE_CELLS
) -> dict[str, tuple[str, Vertices, Triangles]]:
    """The stock as square tiles, each a closed mesh: {key: (digest, vertices, triangles)}.

    The 3D view resends only the tiles whose digest changed, so a playback step that cuts in one
    corner costs one tile. A tile that is level everywhere is a plain box at every triangle budget
    (its digest then stays the same between a coarse and a fine level of detail).
    """
    g = hm.grid
    columns, rows = math.ceil(g.nx / tile_cells), math.ceil(g.ny / tile_cells)
    budget = max(16, max_triangles // (columns * rows))
    tiles: dict[str, tuple[str, Vertices, Triangles]] = {}
    for tj in range(rows):
        for ti in range(columns):
            j0, i0 = tj * tile_cells, ti * tile_cells
            heights = hm.heights[j0 : j0 + tile_cells, i0 : i0 + tile_cells]
            ny, nx = heights.shape
            part = HeightMap(
                type(g)(g.x0 + i0 * g.dx, g.y0 + j0 * g.dy, g.dx, g.dy, nx, ny), hm.base, hm.top, heights
            )
            level = float(np.ptp(np.clip(heights, hm.base, hm.top))) == 0.0
            vertices, triangles = surface_mesh(part, 1 if level else budget)
            digest = hashlib.blake2b(vertices.tobytes() + triangles.tobytes(), digest_size=12).hexdigest()
            tiles[f"{tj}_{ti}"] = (digest, vertices, triangles)
    return tiles


def stl_bytes(vertices: Vertices, triangles: Triangles, name: str = "PAL Trainer stock") -> bytes:
    """Binary STL of a triangle mesh (normals computed from the vertex order)."""
    tri = vertices[triangles].astype(np.float32)
    normal = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    length = np.linalg.norm(normal, axis=1, keepdims=True)
    normal = np.divide(normal, length, out=np.zeros_like(normal), where=length > 0)
    record = np.dtype([("n", "<f4", (3,)), ("v", "<f4", (3, 3)), ("a", "<u2")])
    data = np.zeros(len(tri), dtype=record)
    data["n"], data["v"] = normal, tri
    header = name.encode("ascii", "replace")[:80].ljust(80, b" ")
    return header + struct.pack("<I", len(tri)) + data.tobytes()


def _chunk(kind: bytes, payload: bytes) -> bytes:
    return struct.pack(">I", len(payload)) + kind + payload + struct.pack(">I", zlib.crc32(kind + payload))


def depth_png(hm: HeightMap, max_pixels: int = 1024) -> bytes:
    """Top view, 8-bit grey: white at the stock's top, black at the deepest point machined (the base when
    nothing was removed); +Y up; one pixel per cell, or every k-th cell to stay within `max_pixels`."""
    g = hm.grid
    k = max(1, math.ceil(max(g.nx, g.ny) / max_pixels))
    h = np.clip(hm.heights[::k, ::k], hm.base, hm.top)
    low = float(h.min())
    if low >= hm.top:
        low = hm.base
    grey = np.rint((h - low) / (hm.top - low) * 255).astype(np.uint8)[::-1]
    rows = np.hstack([np.zeros((grey.shape[0], 1), dtype=np.uint8), grey])
    ihdr = struct.pack(">IIBBBBB", grey.shape[1], grey.shape[0], 8, 0, 0, 0, 0)
    return (
        b"\x89PNG\r\n\x1a\n"
        + _chunk(b"IHDR", ihdr)
        + _chunk(b"IDAT", zlib.compress(rows.tobytes(), 6))
        + _chunk(b"IEND", b"")
    )
