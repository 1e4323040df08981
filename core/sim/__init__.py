"""Milling stock simulation: a toolpath run against a box of stock held as a height map.

The public API (what the CLI and the server call); see docs/simulation.md:

    simulate(toolpath, stock, tools, resolution, machine, *, expected_diameters, limits) -> SimResult
    simulation_json(result) -> dict          # the shape of `paltrainer simulate --json`
    surface_mesh(heightmap, max_triangles)   # vertices, triangles for the 3D view
    stock_tiles(heightmap, max_triangles)    # the same as tiles with digests (only changed ones resent)
    stl_bytes(vertices, triangles), depth_png(heightmap, max_pixels)
    parse_tool_table(yaml_text) -> ToolTable, DEFAULT_SIM_TOOLS

Turning (a lathe dialect, core/sim/turning.py): the blank as a revolved profile.

    simulate_turning(toolpath, blank, tools, resolution, machine, *, limits) -> TurningResult
    turning_json(result) -> dict             # the same report shape, with the blank and the profile
    revolved_mesh(profile), half_section_png(profile, blank)
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
from core.sim.lathe_export import half_section_png, revolved_mesh
from core.sim.lathe_report import turning_json
from core.sim.report import simulation_json
from core.sim.tooltable import DEFAULT_SIM_TOOLS, ToolTableError, parse_tool_table, tool_table_yaml
from core.sim.turning import (
    DEFAULT_LATHE_TOOLS,
    DEFAULT_TURNING_RESOLUTION,
    Blank,
    LatheLimits,
    LatheMachine,
    RevolvedProfile,
    TurningResult,
    simulate_turning,
)

__all__ = [
    "DEFAULT_LATHE_TOOLS",
    "DEFAULT_RESOLUTION",
    "DEFAULT_SIM_TOOLS",
    "DEFAULT_TURNING_RESOLUTION",
    "Blank",
    "HeightMap",
    "LatheLimits",
    "LatheMachine",
    "Machine",
    "RevolvedProfile",
    "SimLimits",
    "SimResult",
    "Stock",
    "ToolTableError",
    "TurningResult",
    "depth_png",
    "half_section_png",
    "parse_tool_table",
    "revolved_mesh",
    "simulate",
    "simulate_turning",
    "simulation_json",
    "stl_bytes",
    "stock_tiles",
    "surface_mesh",
    "tool_table_yaml",
    "turning_json",
]
