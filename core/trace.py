"""The golden-trace printer: one line per canonical command, for the CLI and the corpus tests."""

from __future__ import annotations

from core.toolpath import Dwell, Move, Toolpath, Vec3


def _n(v: float) -> str:
    text = f"{v:.4f}".rstrip("0").rstrip(".")
    return "0" if text in ("-0", "") else text


def _p(p: Vec3) -> str:
    return f"X{_n(p[0])} Y{_n(p[1])} Z{_n(p[2])}"


def _lathe(p: Vec3) -> str:
    """A lathe point as the program writes it: X as a diameter, Z (the output's x is the radius)."""
    return f"X{_n(2 * p[0])} Z{_n(p[2])}"


def trace_lines(toolpath: Toolpath, lathe: bool = False) -> list[str]:
    """The commands in program order, e.g. `7 arc cw X70 Y23.6 Z-2 -> X56.4 Y10 Z-2 C X50 Y30 R20.999 A54.5107`.

    `lathe`: points as X diameter and Z (`8 feed X40 Z2 -> X40 Z-30 F0.1 S1989.4368`), centres likewise.
    """
    point = _lathe if lathe else _p
    out = []
    for c in toolpath.commands:
        if isinstance(c, Move):
            text = f"{c.span.line} {c.kind}"
            if c.direction:
                text += f" {c.direction}"
            text += f" {point(c.start)} -> {point(c.end)}"
            if c.center is not None and c.radius is not None and c.angle is not None:
                centre = point(c.center) if lathe else f"X{_n(c.center[0])} Y{_n(c.center[1])}"
                text += f" C {centre} R{_n(c.radius)} A{_n(c.angle)}"
            if c.kind != "rapid":
                text += f" F{_n(c.feed)} S{_n(c.spindle)}"
            out.append(text)
        elif isinstance(c, Dwell):
            out.append(f"{c.span.line} dwell {_n(c.seconds)}s at {point(c.position)}")
        else:
            out.append(
                f"{c.span.line} tool T{c.tool if c.tool is not None else 0} TC{c.tc} TR{_n(c.tr)} TL{_n(c.tl)}"
            )
    return out
