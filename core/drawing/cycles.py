"""What a drawing dimensions of the parts PAL milling cycles make, from the cycles' own words.

A cycle's moves are the tool centre's rings and pecks; a drawing shows what the cycle makes instead: a pocket
(G72 rectangle LP × BP with corner radius RN, G73 circle of radius R, G74 slot LP × BP with round ends, G75 arc
slot of width BP on the radius RP from AN through AO) at the centre the call gives, rotated by AR; drilled,
bored and tapped holes (G81–G87) at the call's points, a pitch circle (G77: IA, JA, R, AN, AI) or a line of holes
(G76: AS, D). The words are read from the reference program's defining and calling blocks (each cycle move
points to both: `Move.cycle_definition`, `Move.span`); the depth is where the cycle's moves went. A centring (a
spot drill) where another hole is drilled is not dimensioned apart; a tapped hole is "M8", its size from the
tool's name (Gewindebohrer M8 × 1,25) or its diameter.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass

from core.drawing.features import Hole
from core.pipeline import parse
from core.syntax.blocks import Block
from core.toolpath import Move
from core.tools import ToolTable

POCKETS = ("G72", "G73", "G74", "G75")
DRILLING = ("G81", "G82", "G83", "G84", "G85", "G86", "G87")
EPS = 1e-6
_THREAD = re.compile(r"\bM\s*(\d+(?:[.,]\d+)?)")


@dataclass(frozen=True)
class Pocket:
    """A pocket or slot a cycle made: `code`, its centre (the arc slot's: the arc's centre), floor z and the
    defining words (length, width, corner or end radius, rotation; the arc slot's radius and angles)."""

    code: str
    x: float
    y: float
    z: float
    length: float = 0.0  # G72, G74: LP; G73: the diameter
    width: float = 0.0  # G72, G74, G75: BP
    radius: float = 0.0  # G72: RN; G73: R; G74, G75: BP / 2
    angle: float = 0.0  # AR
    arc_radius: float = 0.0  # G75: RP
    start: float = 0.0  # G75: AN
    sweep: float = 0.0  # G75: AO (or AP − AN)
    line: int = 0


@dataclass(frozen=True)
class Pattern:
    """The holes one call makes at several points: a pitch circle (G77) or a line (G76)."""

    code: str
    points: tuple[tuple[float, float], ...]
    centre: tuple[float, float] = (0.0, 0.0)  # G77
    radius: float = 0.0  # G77: R
    start: float = 0.0  # G77: AN; G76: AS
    step: float = 0.0  # G77: AI; G76: D


@dataclass
class Cycles:
    pockets: list[Pocket]
    holes: list[Hole]
    patterns: list[Pattern]
    handled: set[int]  # ids of the moves these stand for (left out of the contour and plunge features)
    drilled: list[Hole]  # every drilling, centring and tapping at every point (what the tools cut there)


def _words(block: Block | None) -> dict[str, float]:
    if block is None:
        return {}
    return {w.address.upper(): w.value for w in block.words if w.value is not None}


def _xy(m: Move) -> tuple[float, float]:
    return (m.end[0], m.end[1])


def _rot(d: tuple[float, float], degrees: float) -> tuple[float, float]:
    a = math.radians(degrees)
    return (d[0] * math.cos(a) - d[1] * math.sin(a), d[0] * math.sin(a) + d[1] * math.cos(a))


# ISO metric coarse threads (DIN 13-1): nominal diameter → pitch; a tap with another pitch cuts a fine thread
COARSE = {
    1.6: 0.35,
    2.0: 0.4,
    2.5: 0.45,
    3.0: 0.5,
    4.0: 0.7,
    5.0: 0.8,
    6.0: 1.0,
    8.0: 1.25,
    10.0: 1.5,
    12.0: 1.75,
    14.0: 2.0,
    16.0: 2.0,
    20.0: 2.5,
    24.0: 3.0,
    30.0: 3.5,
}


def _number(v: float, lang: str) -> str:
    text = f"{v:.2f}".rstrip("0").rstrip(".")
    return text.replace(".", ",") if lang == "de" else text


def thread_name(name: str, diameter: float, pitch: float | None = None, lang: str = "de") -> str:
    """A tap's thread: "M8" from its name where it says M…, else from its diameter; "M8 × 1" where the pitch F
    is not the coarse thread's."""
    found = _THREAD.search(name or "")
    size = float(found.group(1).replace(",", ".")) if found else diameter
    out = "M" + _number(size, lang)
    coarse = COARSE.get(round(size, 1))
    if pitch is not None and pitch > 0 and (coarse is None or abs(pitch - coarse) > 1e-6):
        out += " × " + _number(pitch, lang)
    return out


def _pocket(
    code: str, df: dict[str, float], call: dict[str, float], moves: list[Move], line: int
) -> Pocket | None:
    cut = [m for m in moves if m.kind in ("feed", "arc")]
    if not cut:
        return None
    z = min(m.end[2] for m in cut)
    ar = call.get("AR", df.get("AR", 0.0))
    # the call's point; where the call leaves out X or Y, where the tool stood (the cycle's first move starts there)
    x, y = call.get("X", moves[0].start[0]), call.get("Y", moves[0].start[1])
    dx = dy = 0.0
    if int(df.get("EP", 0)) == 1:
        if code == "G72":
            dx, dy = df.get("LP", 0.0) / 2, df.get("BP", 0.0) / 2
        elif code == "G74":
            dx = df.get("LP", 0.0) / 2 - df.get("BP", 0.0) / 2
        elif code == "G75":
            an = math.radians(df.get("AN", 0.0))
            dx, dy = -df.get("RP", 0.0) * math.cos(an), -df.get("RP", 0.0) * math.sin(an)
    u, v = _rot((dx, dy), ar)
    x, y = x + u, y + v
    if code == "G72" and "LP" in df and "BP" in df:
        return Pocket(code, x, y, z, df["LP"], df["BP"], df.get("RN", 0.0), ar, line=line)
    if code == "G73" and "R" in df:
        return Pocket(code, x, y, z, 2 * df["R"], 0.0, df["R"], ar, line=line)
    if code == "G74" and "LP" in df and "BP" in df:
        return Pocket(code, x, y, z, df["LP"], df["BP"], df["BP"] / 2, ar, line=line)
    if code == "G75" and "BP" in df and "RP" in df and "AN" in df and ("AO" in df or "AP" in df):
        sweep = df["AO"] if "AO" in df else df["AP"] - df["AN"]
        return Pocket(
            code, x, y, z, 0.0, df["BP"], df["BP"] / 2, ar, df["RP"], df["AN"] + ar, sweep, line=line
        )
    return None


def _plunge_points(moves: list[Move]) -> list[tuple[float, float, float]]:
    """The points a drilling call went down at (in call order), each with the deepest z it reached there; a
    bore milled on a helix (G87): the helix's centre."""
    out: dict[tuple[float, float], float] = {}
    for m in moves:
        if (
            m.kind == "feed"
            and math.dist(_xy(m), (m.start[0], m.start[1])) < EPS
            and m.end[2] < m.start[2] - EPS
        ):
            key = (round(m.end[0], 6), round(m.end[1], 6))
            out[key] = min(out.get(key, math.inf), m.end[2])
        elif m.kind == "arc" and m.center is not None and m.cycle is not None and m.cycle[0] == "G87":
            key = (round(m.center[0], 6), round(m.center[1], 6))
            out[key] = min(out.get(key, math.inf), m.end[2], m.start[2])
    return [(x, y, z) for (x, y), z in out.items()]


def _pattern(code: str, call: dict[str, float], points: list[tuple[float, float, float]]) -> Pattern | None:
    pts = tuple((p[0], p[1]) for p in points)
    if code == "G77" and "R" in call and len(pts) > 1:
        centre = (call.get("IA", pts[0][0]), call.get("JA", pts[0][1]))
        step = call.get("AI", 360.0 / len(pts) if "AP" not in call else 0.0)
        if "AI" not in call and "AP" in call:
            step = (call["AP"] - call.get("AN", 0.0)) / max(len(pts) - 1, 1)
        return Pattern(code, pts, centre, call["R"], call.get("AN", 0.0), step)
    if code == "G76" and "D" in call and len(pts) > 1:
        return Pattern(code, pts, start=call.get("AS", 0.0), step=call["D"])
    return None


def cycles(
    text: str,
    dialect: str,
    moves: list[Move],
    tools: ToolTable,
    names: dict[int, str] | None = None,
    lang: str = "de",
) -> Cycles:
    """The pockets, holes and hole patterns the PAL cycles of the reference `text` made (its `moves`); `names`:
    the tools the exercise names (a tap's thread size is read from its name)."""
    out = Cycles([], [], [], set(), [])
    if not any(m.cycle is not None and m.cycle_definition is not None for m in moves):
        return out
    program, _ = parse(text, dialect)
    blocks = {b.line: b for b in program.blocks}
    calls: dict[tuple[int, int, str], list[Move]] = {}
    for m in moves:
        if m.cycle is None or m.cycle_definition is None or m.source is not None or m.call_stack:
            continue
        if m.cycle[0] in POCKETS + DRILLING:
            calls.setdefault((m.cycle_definition, m.span.line, m.cycle[0]), []).append(m)
    drilled: dict[tuple[float, float], list[tuple[str, Move, float, float | None, float | None]]] = {}
    patterns: dict[tuple[tuple[float, float], ...], Pattern] = {}
    for (definition, line, code), group in calls.items():
        df, call = _words(blocks.get(definition)), _words(blocks.get(line))
        call_code = next(
            (
                f"G{int(w.value)}"
                for w in (blocks[line].words if line in blocks else ())
                if w.address.upper() == "G" and w.value is not None and 76 <= w.value <= 79
            ),
            "",
        )
        if code in POCKETS:
            # a pocket called at one point (G79); one called on a line or circle of points stays drawn from its moves
            pocket = _pocket(code, df, call, group, definition) if call_code == "G79" else None
            if pocket is None:
                continue
            out.pockets.append(pocket)
        else:
            points = _plunge_points(group)
            if not points:
                continue
            tool = tools.get(group[0].tool) if group[0].tool is not None else None
            size = 2 * df["R"] if code == "G87" and "R" in df else None
            for x, y, z in points:
                if tool is not None:
                    out.drilled.append(Hole(x, y, z, size or tool.diameter, tool.number, line))
                drilled.setdefault((round(x, 6), round(y, 6)), []).append(
                    (code, group[0], z, df.get("F"), size)
                )
            pattern = _pattern(call_code, call, points)
            if pattern is not None:
                patterns.setdefault(
                    tuple(sorted((round(p[0], 6), round(p[1], 6)) for p in pattern.points)), pattern
                )
        out.handled.update(id(m) for m in group)
    for (x, y), ops in drilled.items():
        out.holes.append(_finished(x, y, ops, tools, names or {}, lang))
    out.patterns = list(patterns.values())
    return out


def _finished(
    x: float,
    y: float,
    ops: list[tuple[str, Move, float, float | None, float | None]],
    tools: ToolTable,
    names: dict[int, str],
    lang: str,
) -> Hole:
    """The hole the operations at one point leave: the thread where one is tapped, else the deepest drilling
    that is no centring (a spot drill's only where nothing else drills there)."""
    for code, m, z, pitch, _ in ops:
        tool = tools.get(m.tool) if m.tool is not None else None
        if code == "G84" and tool is not None:
            return Hole(
                x,
                y,
                z,
                tool.diameter,
                m.tool,
                m.span.line,
                thread_name(names.get(tool.number, ""), tool.diameter, pitch, lang),
            )
    drills = [o for o in ops if _kind(tools, o[1].tool) not in ("spot_drill", None)]
    _, m, z, _, size = min(drills or ops, key=lambda o: o[2])
    tool = tools.get(m.tool) if m.tool is not None else None
    if size is None:  # drilled: the drill's diameter; milled on a helix (G87): the bore's, 2 × R
        size = tool.diameter if tool is not None else 0.0
    return Hole(x, y, z, size, m.tool, m.span.line)


def _kind(tools: ToolTable, number: int | None) -> str | None:
    tool = tools.get(number) if number is not None else None
    return tool.kind if tool is not None else None
