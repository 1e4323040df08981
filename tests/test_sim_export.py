"""Simulation exports and the tool table: a closed mesh of the right volume, STL and PNG bytes, YAML tools."""

from __future__ import annotations

import math
import struct
import zlib
from collections import Counter
from pathlib import Path

import numpy as np
import pytest

from core.interpreter.state import RunSetup
from core.pipeline import run
from core.sim import (
    DEFAULT_SIM_TOOLS,
    Stock,
    ToolTableError,
    depth_png,
    parse_tool_table,
    simulate,
    stl_bytes,
    stock_tiles,
    surface_mesh,
    tool_table_yaml,
)
from core.tools import KIND_NAMES_DE, ToolOffset

STOCK = Stock(0, 0, -30, 80, 70, 0)
POCKET = "T1 TC1 M6\nS1200 F150 M3\nG0 X40 Y35 Z2\nG1 Z-5\nG0 Z50\nM30"  # a Ø25 hole 5 deep


def _volume(vertices: np.ndarray, triangles: np.ndarray) -> float:
    t = vertices[triangles].astype(np.float64)
    return float(np.einsum("ij,ij->i", t[:, 0], np.cross(t[:, 1], t[:, 2])).sum() / 6)


def test_mesh_is_closed_outward_and_holds_the_remaining_volume() -> None:
    result = simulate(run(POCKET), STOCK, resolution=0.5)
    v, f = surface_mesh(result.heightmap, 10**7)
    edges = Counter(
        (int(a), int(b)) for tri in f for a, b in ((tri[0], tri[1]), (tri[1], tri[2]), (tri[2], tri[0]))
    )
    assert all(edges[(b, a)] == 1 for (a, b), n in edges.items() if n == 1)  # every edge once each way
    assert all(n == 1 for n in edges.values())
    # vertices sit on cell centres, so the hole's rim is a little soft; the volume still matches
    assert _volume(v, f) == pytest.approx(80 * 70 * 30 - math.pi * 12.5**2 * 5, rel=0.002)


def test_mesh_decimation_keeps_to_the_triangle_budget() -> None:
    result = simulate(run(POCKET), STOCK)
    for budget in (200_000, 20_000, 2_000, 100):
        _, f = surface_mesh(result.heightmap, budget)
        assert len(f) <= budget
    v, f = surface_mesh(result.heightmap, 20_000)
    assert _volume(v, f) == pytest.approx(result.remaining_volume, rel=0.01)


def test_stock_tiles_hold_the_volume_and_only_cut_tiles_change() -> None:
    uncut = stock_tiles(simulate(run("G0 X0 Y0 Z50\nM30"), STOCK, resolution=0.5).heightmap, 6_000)
    result = simulate(run(POCKET), STOCK, resolution=0.5)
    coarse, fine = stock_tiles(result.heightmap, 6_000), stock_tiles(result.heightmap, 40_000)
    # 80 × 70 mm at 0.5 mm in tiles of 40 cells: 4 × 4 tiles, each closed, together the remaining volume
    assert len(coarse) == len(fine) == 16
    assert sum(_volume(v, f) for _, v, f in fine.values()) == pytest.approx(result.remaining_volume, rel=0.01)
    assert sum(len(f) for _, _, f in coarse.values()) <= 6_000
    # the Ø25 hole at X40 Y35 touches the four middle tiles only: the others stay as they were
    changed = {key for key in uncut if uncut[key][0] != coarse[key][0]}
    assert changed == {"1_1", "1_2", "2_1", "2_2"}
    # a level tile is the same box at every level of detail (not sent twice)
    assert coarse["0_0"][0] == fine["0_0"][0] and coarse["1_1"][0] != fine["1_1"][0]


def test_stl_is_binary_stl_of_the_mesh() -> None:
    v, f = surface_mesh(simulate(run(POCKET), STOCK, resolution=1.0).heightmap)
    data = stl_bytes(v, f)
    (count,) = struct.unpack("<I", data[80:84])
    assert count == len(f) and len(data) == 84 + 50 * count
    normal = struct.unpack("<3f", data[84:96])
    assert math.isclose(math.hypot(*normal), 1.0, rel_tol=1e-5)


def _png_pixels(data: bytes) -> np.ndarray:
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    pos, chunks = 8, {}
    while pos < len(data):
        (length,) = struct.unpack(">I", data[pos : pos + 4])
        kind = data[pos + 4 : pos + 8]
        chunks[kind] = chunks.get(kind, b"") + data[pos + 8 : pos + 8 + length]
        assert struct.unpack(">I", data[pos + 8 + length : pos + 12 + length])[0] == zlib.crc32(
            kind + data[pos + 8 : pos + 8 + length]
        )
        pos += 12 + length
    w, h = struct.unpack(">II", chunks[b"IHDR"][:8])
    raw = np.frombuffer(zlib.decompress(chunks[b"IDAT"]), dtype=np.uint8).reshape(h, w + 1)
    assert (raw[:, 0] == 0).all()
    return raw[:, 1:]


def test_depth_png_is_white_on_top_and_black_in_the_hole() -> None:
    result = simulate(run(POCKET), STOCK, resolution=0.5)
    px = _png_pixels(depth_png(result.heightmap))
    assert px.shape == (140, 160)
    assert px[0, 0] == 255 and px[70, 80] == 0  # image row 70 is Y 35 (rows run from +Y down)
    small = _png_pixels(depth_png(result.heightmap, max_pixels=40))
    assert max(small.shape) <= 40


def test_default_table_file_matches_the_built_in_table() -> None:
    path = Path(__file__).parents[1] / "core" / "sim" / "default_tools.yaml"
    assert parse_tool_table(path.read_text(encoding="utf-8")) == DEFAULT_SIM_TOOLS


def test_default_table_has_the_seed_tools_and_every_kind() -> None:
    t = DEFAULT_SIM_TOOLS.tools
    assert (t[1].kind, t[1].diameter) == ("end_mill", 25.0)
    assert (t[2].kind, t[2].diameter) == ("slot_drill", 6.0)
    assert (t[4].kind, t[4].diameter) == ("end_mill", 20.0)
    assert {x.kind for x in t.values()} == set(KIND_NAMES_DE)
    assert any(not x.centre_cutting for x in t.values())


def test_tool_table_round_trip_with_offsets() -> None:
    text = """tools:
  - number: 12
    kind: torus
    diameter: 16
    corner_radius: 2
    cutting_length: 30
    overall_length: 90
    shank_diameter: 16
    centre_cutting: false
    tc:
      1: {radius: 8, length: 90}
      2: {radius: 8.2, length: 90.5}
"""
    table = parse_tool_table(text)
    tool = table.tools[12]
    assert tool.offset(2) == ToolOffset(2, 8.2, 90.5)
    assert tool.offset(3) == ToolOffset(3, 8.0, 90.0)  # not stored: the tool's own radius and length
    assert parse_tool_table(tool_table_yaml(table)) == table


@pytest.mark.parametrize(
    "text,fragment",
    [
        ("tools: [{number: 1, kind: end_mill}]", "diameter"),
        ("tools: [{number: 1, kind: drill, diameter: 5}]", "kind"),
        ("tools: [{number: 1, kind: end_mill, diameter: 5, colour: red}]", "colour"),
        ("tools: [{number: 1, kind: end_mill, diameter: 5}, {number: 1, kind: end_mill, diameter: 6}]", "T1"),
        (
            "tools: [{number: 1, kind: end_mill, diameter: 5, cutting_length: 20, overall_length: 10}]",
            "overall_length",
        ),
        ("tools: [{number: 1, kind: torus, diameter: 5}]", "corner_radius"),
        ("tools: [{number: 1, kind: end_mill, diameter: 5, tc: {10: {radius: 2, length: 50}}}]", "TC10"),
        ("tools: [{number: 1, kind: end_mill, diameter: -5}]", "diameter"),
        ("tools: [1, 2]", "Eintrag 1"),
        ("[a", "YAML"),
        ("tool: []", "tools"),
    ],
)
def test_bad_tool_tables_say_what_is_wrong(text: str, fragment: str) -> None:
    with pytest.raises(ToolTableError) as err:
        parse_tool_table(text)
    assert fragment in str(err.value)


def test_tool_table_reaches_the_interpreter_and_the_simulation() -> None:
    table = parse_tool_table("tools: [{number: 9, kind: ball_nose, diameter: 10, cutting_length: 20}]")
    tp = run(
        "T9 TC1 M6\nS1200 F150 M3\nG0 X-10 Y35 Z2\nG1 Z-5\nG1 X90\nG0 Z50\nM30", setup=RunSetup(tools=table)
    )
    assert not [d for d in tp.diagnostics if d.severity.value == "error"]
    assert simulate(tp, STOCK, table).removed_volume == pytest.approx(math.pi * 25 / 2 * 80, rel=0.01)
