"""The JSON shape of a simulation result: what `paltrainer simulate --json` prints and the server returns."""

from __future__ import annotations

from typing import Any

from core.diagnostics import Diagnostic
from core.sim.engine import SimResult


def _event(d: Diagnostic) -> dict[str, Any]:
    return {"code": d.code, "severity": d.severity.value, "line": d.span.line,
            "message": d.message, "message_en": d.message_en}


def simulation_json(result: SimResult) -> dict[str, Any]:
    """Volumes in mm³ (3 decimals), times in s (2 decimals), events with line and both languages."""
    s = result.stock
    return {
        "removed_volume_mm3": round(result.removed_volume, 3),
        "remaining_volume_mm3": round(result.remaining_volume, 3),
        "cycle_time_s": round(result.cycle_time, 2),
        "resolution_mm": round(result.resolution, 6),
        "events": [_event(d) for d in result.events],
        "time_per_tool": [{"tool": t, "seconds": round(v, 2)} for t, v in result.time_per_tool.items()],
        "stock": {"min": [s.x0, s.y0, s.z0], "max": [s.x1, s.y1, s.z1]},
        "grid": {"nx": result.heightmap.grid.nx, "ny": result.heightmap.grid.ny},
        "cell_updates": result.cell_updates,
        "complete": result.complete,
        "diagnostics": [d.to_json() for d in result.diagnostics],
    }
