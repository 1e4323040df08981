"""The JSON shape of a turning simulation: the milling report's fields (`paltrainer simulate --json`) with the
blank and the profile in place of the stock box and the grid."""

from __future__ import annotations

from typing import Any

from core.sim.report import _event
from core.sim.turning import TurningResult


def turning_json(result: TurningResult) -> dict[str, Any]:
    """Volumes in mm³ (3 decimals), times in s (2 decimals), events with line and both languages."""
    b = result.blank
    p = result.profile
    return {
        "removed_volume_mm3": round(result.removed_volume, 3),
        "remaining_volume_mm3": round(result.remaining_volume, 3),
        "cycle_time_s": round(result.cycle_time, 2),
        "resolution_mm": round(result.resolution, 6),
        "events": [_event(d) for d in result.events],
        "time_per_tool": [{"tool": t, "seconds": round(v, 2)} for t, v in result.time_per_tool.items()],
        "blank": {"diameter": b.diameter, "bore": b.bore, "length": b.length, "clamp": round(b.clamp, 3),
                  "jaw_diameter": round(2 * b.jaw_radius, 3)},
        "profile": {"z0": p.z0, "dz": round(p.dz, 6), "samples": len(p.outer),
                    "min_diameter": round(2 * float(p.outer.min()), 4) if len(p.outer) else 0.0},
        "cell_updates": result.cell_updates,
        "complete": result.complete,
        "diagnostics": [d.to_json() for d in result.diagnostics],
    }
