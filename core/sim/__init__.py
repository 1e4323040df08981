"""Milling stock simulation: a toolpath run against a box of stock held as a height map.

The public API (what the CLI and the server call); see docs/simulation.md:

    simulate(toolpath, stock, tools, resolution, machine, *, expected_diameters, limits) -> SimResult
    simulation_json(result) -> dict          # the shape of `paltrainer simulate --json`
    surface_mesh(heightmap, max_triangles)   # vertices, triangles for the 3D view
    stock_tiles(heightmap, max_triangles)    # the same as tiles with digests (only changed ones resent)
    stl_bytes(vertices, triangles), depth_png(heightmap, max_pixels)
    parse_tool_table(yaml_text) -> ToolTable, DEFAULT_SIM_TOOLS
"""

from core.sim.engine import (
    DEFAULT_RESOLUTION,
    HeightMap,
    Machine,
    SimLimits,
    SimResult,
    Stock,
    simulate,
)
from core.sim.export import depth_png, stl_bytes, stock_tiles, surface_mesh
from core.sim.report import simulation_json
from core.sim.tooltable import DEFAULT_SIM_TOOLS, ToolTableError, parse_tool_table, tool_table_yaml

__all__ = [
    "DEFAULT_RESOLUTION", "DEFAULT_SIM_TOOLS", "HeightMap", "Machine", "SimLimits", "SimResult", "Stock",
    "ToolTableError", "depth_png", "parse_tool_table", "simulate", "simulation_json", "stl_bytes", "stock_tiles",
    "surface_mesh", "tool_table_yaml",
]
