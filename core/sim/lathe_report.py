"""The JSON shape of a turning simulation: the milling report's fields (`paltrainer simulate --json`) with the
blank and the profile in place of the stock box and the grid."""

from __future__ import annotations

from typing import Any

from core.sim.report import report_json
from core.sim.turning import TurningResult


def turning_json(result: TurningResult) -> dict[str, Any]:
    b = result.blank
    p = result.profile
    return report_json(
        result,
        {
            "blank": {
                "diameter": b.diameter,
                "bore": b.bore,
                "length": b.length,
                "clamp": round(b.clamp, 3),
                "jaw_diameter": round(2 * b.jaw_radius, 3),
            },
            "profile": {
                "z0": p.z0,
                "dz": round(p.dz, 6),
                "samples": len(p.outer),
                "min_diameter": round(2 * float(p.outer.min()), 4) if len(p.outer) else 0.0,
            },
        },
    )
