"""ISO drilling cycles (SINUMERIK 808D ISO mode, milling): G73, G74, G76, G81–G89 expanded into canonical moves.

Source: the fixed cycles of the manufacturer's ISO programming manual (808D "Programming (ISO dialects)",
6FC5398-4DP10-0BA0; SINUMERIK ISO Milling 6FC5398-7BP10-1BA0, "Fixed cycles"), which follow the common ISO
definition. A cycle is modal (group 09) until G80 or a G00–G03: every block in cycle mode that programs X, Y,
Z or R drills a hole. Its data stay until G80: the bottom Z, the R plane, Q and P (core.interpreter.state
.DrillData). In the plane G17 (the only one modelled), a hole is:

1. rapid in X/Y to the hole position at the current height;
2. rapid down to the R plane (G90: Z = R; G91: R is the distance from the initial level, Z the distance from
   the R plane to the bottom);
3. the cycle's own motion to the bottom and back (below);
4. back to the initial level (G98, the height when the cycle was selected) or to the R plane (G99).

| Code | into the hole | at the bottom | out of the hole |
|---|---|---|---|
| G81 | feed | – | rapid |
| G82 | feed | dwell P | rapid |
| G73 | feed by Q, back off d at rapid after each step | – | rapid |
| G83 | feed by Q, rapid to R after each step, rapid back to d above the last depth | – | rapid |
| G74 | feed, spindle as programmed (M04) | dwell P | feed to R, spindle reversed |
| G84 | feed, spindle as programmed (M03) | dwell P | feed to R, spindle reversed |
| G85 | feed | – | feed to R |
| G86 | feed | spindle stop | rapid, spindle stopped |
| G88 | feed | dwell P, spindle stop | by hand on the machine: shown as a rapid, spindle stopped (ISO-I406) |
| G89 | feed | dwell P | feed to R |
| G76 | feed | dwell P, oriented stop, shift Q in +X | rapid, spindle stopped, shift back |
| G87 | (back boring) oriented stop, shift Q in +X, rapid to the R plane below the part, shift back, spindle on | – | feed up to Z, oriented stop, shift Q, rapid to the initial level, shift back |

P is the dwell in milliseconds; K (or L) repeats the hole (G91: shifted by X/Y each time; K0 stores the data
and drills nothing). d (the back-off of G73, the clearance of G83) is machine data: `RunSetup.peck_retract`.
Every move carries `cycle = (code, step, steps)`: the pecks of a G73/G83 hole are its steps, the other cycles
make one step per hole; the positioning and return moves belong to the first and last step.
"""

from __future__ import annotations

import dataclasses
import math

from core.diagnostics import Diagnostic, diag
from core.interpreter.cycle_path import EPS, CyclePath
from core.interpreter.state import DrillData, RunSetup
from core.syntax.blocks import Span, Word
from core.toolpath import Dwell, Move, Vec3

PECKING = frozenset({"G73", "G83"})
SHIFTING = frozenset({"G76", "G87"})
OUT_AT_FEED = frozenset({"G74", "G84", "G85", "G89"})
DWELLING = frozenset({"G74", "G76", "G82", "G84", "G88", "G89"})


def update(data: DrillData, values: dict[str, float]) -> DrillData:
    """The cycle data after a block that programs some of Z, R, Q, P."""
    return dataclasses.replace(
        data,
        z=values.get("Z", data.z),
        r=values.get("R", data.r),
        q=values.get("Q", data.q),
        p=values.get("P", data.p),
    )


def drills(values: dict[str, float]) -> bool:
    """Whether a block in cycle mode makes a hole: it programs the position X/Y, the bottom Z or the R plane."""
    return any(a in values for a in ("X", "Y", "Z", "R"))


def holes(
    code: str,
    data: DrillData,
    here: Vec3,
    values: dict[str, float],
    words: dict[str, list[Word]],
    incremental: bool,
    to_initial: bool,
    template: Move,
    setup: RunSetup,
    span: Span,
    d: list[Diagnostic],
) -> tuple[list[Move | Dwell], Vec3] | None:
    """The moves and dwells of the holes of one cycle block from `here` (program coordinates, plane G17) and
    where the tool ends; None after an error (nothing moves). `template` carries the block's technology."""
    if data.z is None or data.r is None:
        missing = (
            ("R", "die R-Ebene", "the R plane")
            if data.r is None
            else ("Z", "der Bohrungsgrund", "the bottom of the hole")
        )
        d.append(diag("ISO-E401", span, code=code, address=missing[0], what=missing[1], what_en=missing[2]))
        return None
    q = data.q
    if code in PECKING:
        if q is None:
            d.append(
                diag("ISO-E401", span, code=code, address="Q", what="die Zustellung", what_en="the infeed")
            )
            return None
        if q <= 0:
            w = words.get("Q")
            d.append(diag("PAL-E213", w[0].span if w else span, address="Q", raw=w[0].raw if w else f"{q:g}"))
            return None
    initial = data.initial
    r_level = initial + data.r if incremental else data.r
    bottom = r_level + data.z if incremental else data.z
    if code == "G87" and bottom <= r_level + EPS:
        d.append(
            diag(
                "ISO-E402",
                span,
                code=code,
                bottom=round(bottom, 4),
                r=round(r_level, 4),
                relation="unter",
                relation_en="below",
            )
        )
        return None
    if code != "G87" and bottom >= r_level - EPS:
        d.append(
            diag(
                "ISO-E402",
                span,
                code=code,
                bottom=round(bottom, 4),
                r=round(r_level, 4),
                relation="über",
                relation_en="above",
            )
        )
        return None
    repeats = int(values.get("K", values.get("L", 1)))
    if repeats <= 0:
        return [], here  # K0: the data are stored, nothing is drilled
    steps = math.ceil((r_level - bottom) / q - 1e-9) if code in PECKING and q is not None else 1
    limit = setup.limits.max_cycle_passes
    if steps * repeats > limit:
        d.append(diag("ISO-E404", span, code=code, count=steps * repeats, limit=limit))
        return None
    out = _Holes(code, template, span, steps)
    ret = initial if to_initial or code == "G87" else r_level
    pos = here
    for i in range(repeats):
        if incremental:
            x, y = here[0] + values.get("X", 0.0) * (i + 1), here[1] + values.get("Y", 0.0) * (i + 1)
        else:
            x, y = values.get("X", here[0]), values.get("Y", here[1])
        pos = out.hole(
            pos, x, y, r_level, bottom, ret, initial, q or 0.0, (data.p or 0.0) / 1000, setup.peck_retract
        )
    if code == "G88":
        d.append(diag("ISO-I406", span))
    return out.items, pos


class _Holes(CyclePath):
    """Collects the moves of one cycle block (program coordinates)."""

    def __init__(self, code: str, template: Move, span: Span, steps: int) -> None:
        super().__init__(code, template, span, template.start, steps)

    def hole(
        self,
        pos: Vec3,
        x: float,
        y: float,
        r: float,
        bottom: float,
        ret: float,
        initial: float,
        q: float,
        dwell: float,
        d: float,
    ) -> Vec3:
        code = self.code
        self.pos, self.step = pos, 1
        self.go("rapid", (x, y, pos[2]))
        if code == "G87":  # back boring: the R plane lies below the part, the bore is cut upwards
            self.go("rapid", (x + q, y, pos[2]), "off")
            self.go("rapid", (x + q, y, r), "off")
            self.go("rapid", (x, y, r), "off")
            self.go("feed", (x, y, bottom))
            self.go("rapid", (x + q, y, bottom), "off")
            self.go("rapid", (x + q, y, initial), "off")
            self.go("rapid", (x, y, initial), "off")
            return self.pos
        self.go("rapid", (x, y, r))
        if code in PECKING:
            depth = r
            while True:
                nxt = max(depth - q, bottom)
                if code == "G83" and depth < r:  # back into the hole to d above the last depth
                    self.go("rapid", (x, y, depth + d))
                self.go("feed", (x, y, nxt))
                if nxt <= bottom + EPS:
                    break
                self.go("rapid", (x, y, r if code == "G83" else min(nxt + d, r)))
                depth = nxt
                self.step += 1
            self.go("rapid", (x, y, ret))
            return self.pos
        self.go("feed", (x, y, bottom))
        if code in DWELLING:
            self.dwell(dwell)
        if code in OUT_AT_FEED:
            self.go("feed", (x, y, r), "reverse" if code in ("G74", "G84") else "on")
            self.go("rapid", (x, y, ret))
        elif code == "G76":
            self.go("rapid", (x + q, y, bottom), "off")
            self.go("rapid", (x + q, y, ret), "off")
            self.go("rapid", (x, y, ret), "off")
        else:
            self.go("rapid", (x, y, ret), "off" if code in ("G86", "G88") else "on")
        return self.pos
