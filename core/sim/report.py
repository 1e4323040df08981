"""The JSON shape of a simulation result: what `paltrainer simulate --json` prints and the server returns."""

from __future__ import annotations

from typing import Any, Protocol

from core.diagnostics import Diagnostic
from core.sim.engine import SimResult


def _event(d: Diagnostic) -> dict[str, Any]:
    return {
        "code": d.code,
        "severity": d.severity.value,
        "line": d.span.line,
        "message": d.message,
        "message_en": d.message_en,
    }


class Simulated(Protocol):
    """What a milling and a turning simulation both report."""

    @property
    def removed_volume(self) -> float: ...

    @property
    def remaining_volume(self) -> float: ...

    @property
    def cycle_time(self) -> float: ...

    @property
    def resolution(self) -> float: ...

    @property
    def events(self) -> list[Diagnostic]: ...

    @property
    def time_per_tool(self) -> dict[int | None, float]: ...

    @property
    def cell_updates(self) -> int: ...

    @property
    def complete(self) -> bool: ...

    @property
    def diagnostics(self) -> list[Diagnostic]: ...


def report_json(result: Simulated, material: dict[str, Any]) -> dict[str, Any]:
    """Volumes in mm³ (3 decimals), times in s (2 decimals), events with line and both languages; `material`
    says what was cut (the stock box and grid, or the blank and profile)."""
    return {
        "removed_volume_mm3": round(result.removed_volume, 3),
        "remaining_volume_mm3": round(result.remaining_volume, 3),
        "cycle_time_s": round(result.cycle_time, 2),
        "resolution_mm": round(result.resolution, 6),
        "events": [_event(d) for d in result.events],
        "time_per_tool": [{"tool": t, "seconds": round(v, 2)} for t, v in result.time_per_tool.items()],
        **material,
        "cell_updates": result.cell_updates,
        "complete": result.complete,
        "diagnostics": [d.to_json() for d in result.diagnostics],
    }


def simulation_json(result: SimResult) -> dict[str, Any]:
    s = result.stock
    return report_json(
        result,
        {
            "stock": {"min": [s.x0, s.y0, s.z0], "max": [s.x1, s.y1, s.z1]},
            "grid": {"nx": result.heightmap.grid.nx, "ny": result.heightmap.grid.ny},
        },
    )
