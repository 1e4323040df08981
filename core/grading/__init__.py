"""The grader: a submission against an exercise's reference, criterion by criterion (pure, deterministic).

Both programs run through the same pipeline (interpret, then simulate on the exercise's stock at its
resolution); the machined parts are compared cell by cell with a tolerance band, so equivalent
programs (arc by R instead of I/J, RN instead of an explicit arc, incremental instead of absolute)
score the same. Every criterion carries its points, a German and an English message and the lines
it concerns.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, Literal

import numpy as np
import numpy.typing as npt

from core.diagnostics import Diagnostic, Severity
from core.exercises import Criterion, Exercise
from core.grading.turning import (
    Turned,
    execute_turning,
    may_cut_turning,
    turned_geometry,
    turning_technology,
    unsafe_events,
)
from core.interpreter import Toolpath
from core.interpreter.state import RunSetup
from core.pipeline import DIALECTS, run
from core.sim import HeightMap, SimResult, simulate
from core.toolpath import Move

SAFETY_EVENTS = {"SIM-E001", "SIM-E002", "SIM-E003", "SIM-E004", "SIM-E005", "SIM-E006", "SIM-E007", "SIM-E008"}
SAFE_CLEARANCE = 10.0  # mm above the stock top counts as a safe end position
# chords of one arc where grading looks at its points: bounded before they are made, so that a loop of
# huge arcs (radius 50 m: 2,000 chords at 0.05 mm) costs no more than a loop of small ones
ARC_CHORDS = 256


@dataclass(frozen=True, slots=True)
class CriterionResult:
    id: str
    passed: bool
    points: int
    max_points: int
    message: str
    message_en: str
    lines: tuple[int, ...]
    hidden: bool

    def to_json(self) -> dict[str, Any]:
        return {"id": self.id, "status": "passed" if self.passed else "failed", "points": self.points,
                "max_points": self.max_points, "message": self.message, "message_en": self.message_en,
                "lines": list(self.lines), "hidden": self.hidden}


@dataclass(frozen=True, slots=True)
class GradeResult:
    exercise: str
    score: int
    max_score: int
    criteria: tuple[CriterionResult, ...]
    diagnostics: tuple[Diagnostic, ...]

    def to_json(self, view: Literal["instructor", "student"] = "instructor") -> dict[str, Any]:
        """The contract of `paltrainer grade --json`; students do not see hidden criteria."""
        shown = [c for c in self.criteria if view == "instructor" or not c.hidden]
        return {"exercise": self.exercise, "score": self.score, "max_score": self.max_score,
                "criteria": [c.to_json() for c in shown], "diagnostics": [d.to_json() for d in self.diagnostics]}


@dataclass(frozen=True, slots=True)
class Machined:
    toolpath: Toolpath
    sim: SimResult


def execute(exercise: Exercise, text: str) -> Machined:
    """`text` interpreted and simulated on the exercise's set-up and stock (the grader's view; the drawing's too)."""
    tools = exercise.tool_table()
    setup = RunSetup(tools=tools, zero_offsets=tuple(exercise.zero_offsets.items()),
                     subprograms=tuple(exercise.subprograms.items()))
    toolpath = run(text, exercise.dialect, setup)
    sim = simulate(toolpath, exercise.stock.stock(), tools, exercise.resolution)
    return Machined(toolpath, sim)


def grade(exercise: Exercise, program: str) -> GradeResult:
    """Grade `program` against `exercise`. The same inputs always give the same result. A lathe dialect's
    exercise turns both programs on its blank (core.grading.turning), a milling one mills its stock."""
    run_on: Callable[[Exercise, str], Machined | Turned] = (
        execute_turning if DIALECTS[exercise.dialect].lathe else execute)
    reference = run_on(exercise, exercise.reference)
    submission = run_on(exercise, program)
    results = [_judge(c, exercise, program, reference, submission) for c in exercise.rubric]
    score = sum(r.points for r in results)
    return GradeResult(exercise.id, score, sum(c.points for c in exercise.rubric), tuple(results),
                       tuple(submission.toolpath.diagnostics))


def _result(c: Criterion, passed: bool, de: str, en: str, lines: list[int] | tuple[int, ...] = ()) -> CriterionResult:
    return CriterionResult(c.id, passed, c.points if passed else 0, c.points, de, en,
                           tuple(sorted(set(lines))), c.hidden)


def _judge(c: Criterion, ex: Exercise, program: str, ref: Machined | Turned, sub: Machined | Turned) -> CriterionResult:
    tp = sub.toolpath
    cutting = [m for m in tp.moves if m.kind != "rapid"]
    if isinstance(ref, Turned) and isinstance(sub, Turned):
        lathe = _judge_turning(c, ex, ref, sub, cutting)
        if lathe is not None:
            return lathe
    assert isinstance(ref, Machined) or c.id not in ("geometry", "safety", "technology", "safe_position")
    if c.id == "syntax":
        errors = [d for d in tp.diagnostics if d.severity is Severity.ERROR]
        if not errors:
            return _result(c, True, "Das Programm ist fehlerfrei.", "The program has no errors.")
        first = errors[0]
        return _result(c, False, f"{len(errors)} Fehler im Programm, der erste in Zeile {first.span.line}: "
                       f"{first.message}", f"{len(errors)} errors in the program, the first in line "
                       f"{first.span.line}: {first.message_en}", [d.span.line for d in errors])
    if c.id == "geometry":
        assert isinstance(ref, Machined) and isinstance(sub, Machined)
        return _geometry(c, ref, sub)
    if c.id == "safety":
        events = [e for e in sub.sim.events if e.code in SAFETY_EVENTS]
        if not events:
            return _result(c, True, "Keine Kollision und kein gefährlicher Schnitt.", "No collision, no unsafe cut.")
        e = events[0]
        return _result(c, False, f"Zeile {e.span.line}: {e.message}", f"Line {e.span.line}: {e.message_en}",
                       [x.span.line for x in events if x.span.line])
    if c.id == "technology":
        return _technology(c, ex, [m for m in cutting if _may_cut(m, ex)])
    if c.id == "tool_change":
        first_cut = cutting[0].line if cutting else None
        changed = [t for t in tp.tool_changes if t.tool is not None]
        ok = bool(changed) and (first_cut is None or _before(tp, changed[0], cutting[0]))
        call = "T…" if ex.lathe else "T … M6"
        return _result(c, ok, "Werkzeug vor dem ersten Schnitt eingewechselt." if ok else
                       f"Kein Werkzeugwechsel ({call}) vor dem ersten Schnitt.",
                       "Tool changed before the first cut." if ok else f"No tool change ({call}) before the first cut.",
                       [] if ok or first_cut is None else [first_cut])
    if c.id == "spindle_on":
        stopped = [m.line for m in cutting if m.spindle == 0]
        return _result(c, not stopped, "Die Spindel läuft bei allen Vorschubbewegungen." if not stopped else
                       f"Vorschubbewegung bei stehender Spindel in Zeile {stopped[0]}.",
                       "The spindle turns during every feed move." if not stopped else
                       f"Feed move with the spindle stopped in line {stopped[0]}.", stopped)
    if c.id == "compensation_off":
        last = len(tp.line_states)
        state = tp.state_at(last)[0] if last else None
        ok = state is None or state.active("compensation") in ("G40", None)
        what, what_en = (("Schneidenradiuskompensation (SRK)", "Nose-radius compensation") if ex.lathe else
                         ("Fräserradiuskorrektur", "Cutter radius compensation"))
        return _result(c, ok, f"Die {what} ist am Ende abgewählt (G40)." if ok else
                       f"Die {what} ist am Programmende noch aktiv: G40 fehlt.",
                       f"{what_en} is off at the end (G40)." if ok else
                       f"{what_en} is still on at the end: G40 is missing.")
    if c.id == "safe_position":
        z = tp.final_position[2]
        top = ex.stock.max[2]
        ok = z >= top + SAFE_CLEARANCE
        return _result(c, ok, f"Das Werkzeug endet auf Z{z:g}, sicher über dem Werkstück." if ok else
                       f"Das Werkzeug endet auf Z{z:g}, weniger als {SAFE_CLEARANCE:g} mm über dem Werkstück.",
                       f"The tool ends at Z{z:g}, safely above the part." if ok else
                       f"The tool ends at Z{z:g}, less than {SAFE_CLEARANCE:g} mm above the part.")
    if c.id == "program_end":
        missing = any(d.code == "PAL-W102" for d in tp.diagnostics)
        return _result(c, not missing, "Das Programm endet mit M30." if not missing else "M30 (Programmende) fehlt.",
                       "The program ends with M30." if not missing else "M30 (end of program) is missing.")
    # locked_lines
    given = ex.start_program.splitlines()
    mine = program.splitlines()
    edited = [n for n in ex.locked_lines if n > len(mine) or mine[n - 1].strip() != given[n - 1].strip()]
    return _result(c, not edited, "Die vorgegebenen Zeilen sind unverändert." if not edited else
                   f"Vorgegebene Zeilen wurden geändert: {', '.join(map(str, edited))}.",
                   "The given lines are unchanged." if not edited else
                   f"Given lines were changed: {', '.join(map(str, edited))}.", edited)


def _judge_turning(c: Criterion, ex: Exercise, ref: Turned, sub: Turned, cutting: list[Move]) -> CriterionResult | None:
    """The criteria a lathe exercise judges its own way (the turned part, its events, V/S and F per revolution,
    the end position off the bar); None: as in milling."""
    verdict: tuple[bool, str, str, list[int]] | None = None
    if c.id == "geometry":
        verdict = turned_geometry(ref, sub, _tolerance(c))
    elif c.id == "safety":
        events = unsafe_events(sub)
        if not events:
            return _result(c, True, "Keine Kollision und kein gefährlicher Schnitt.", "No collision, no unsafe cut.")
        e = events[0]
        verdict = (False, f"Zeile {e.span.line}: {e.message}", f"Line {e.span.line}: {e.message_en}",
                   [x.span.line for x in events if x.span.line])
    elif c.id == "technology":
        verdict = turning_technology(ex, [m for m in cutting if may_cut_turning(m, ex)],
                                     c.tolerance if c.tolerance is not None else 0.1)
    elif c.id == "safe_position":
        assert ex.blank is not None
        x, _, z = sub.toolpath.final_position
        ok = z >= SAFE_CLEARANCE or abs(x) >= ex.blank.diameter / 2 + SAFE_CLEARANCE
        verdict = (ok, f"Das Werkzeug endet bei X{2 * x:g} Z{z:g}, frei vom Werkstück." if ok else
                   f"Das Werkzeug endet bei X{2 * x:g} Z{z:g}, weniger als {SAFE_CLEARANCE:g} mm vom Werkstück.",
                   f"The tool ends at X{2 * x:g} Z{z:g}, clear of the part." if ok else
                   f"The tool ends at X{2 * x:g} Z{z:g}, less than {SAFE_CLEARANCE:g} mm from the part.", [])
    if verdict is None:
        return None
    return _result(c, verdict[0], verdict[1], verdict[2], verdict[3])


def _before(tp: Toolpath, change: object, move: Move) -> bool:
    commands = tp.commands
    return commands.index(change) < commands.index(move)  # type: ignore[arg-type]


def _geometry(c: Criterion, ref: Machined, sub: Machined) -> CriterionResult:
    """Over-cut (material removed that must stay) and residual (material left that must go) outside the band."""
    tol = _tolerance(c)
    hr, hs = ref.sim.heightmap, sub.sim.heightmap
    grid = hr.grid
    area = grid.dx * grid.dy
    over, left = _outside_band(hr, hs, tol)
    over_volume, left_volume = float(over.sum()) * area, float(left.sum()) * area
    diff = hs.heights - hr.heights
    allowance = 4 * area * tol  # a few cells at the band's edge
    if over_volume <= allowance and left_volume <= allowance:
        return _result(c, True, "Das Werkstück entspricht der Zeichnung.", "The part matches the drawing.")
    gouge = over_volume > allowance  # a gouge is the graver fault: name it first
    worst = np.unravel_index(int(np.argmax(over if gouge else left)), diff.shape)
    j, i = int(worst[0]), int(worst[1])
    x, y = grid.x0 + (i + 0.5) * grid.dx, grid.y0 + (j + 0.5) * grid.dy
    depth = abs(float(diff[j, i]))  # against the reference cell itself
    line = _line_at(sub.toolpath, x, y) if gouge else None
    where, where_en = (f" (Zeile {line})", f" (line {line})") if line else ("", "")
    parts_de, parts_en = [], []
    if gouge:
        parts_de.append(f"Zu viel Material abgetragen: {over_volume:.1f} mm³; die größte Abweichung ist {depth:.2f} mm "
                        f"zu tief bei X{x:.1f} Y{y:.1f}{where}.")
        parts_en.append(f"Too much material removed: {over_volume:.1f} mm³; the largest deviation is {depth:.2f} mm "
                        f"too deep at X{x:.1f} Y{y:.1f}{where_en}.")
    if left_volume > allowance:
        if gouge:
            parts_de.append(f"Außerdem stehen {left_volume:.1f} mm³ Material, die weg müssen.")
            parts_en.append(f"Also, {left_volume:.1f} mm³ of material that must go are left standing.")
        else:
            parts_de.append(f"Material stehen gelassen: {left_volume:.1f} mm³; die größte Abweichung ist {depth:.2f} mm "
                            f"zu hoch bei X{x:.1f} Y{y:.1f}.")
            parts_en.append(f"Material left standing: {left_volume:.1f} mm³; the largest deviation is {depth:.2f} mm "
                            f"too high at X{x:.1f} Y{y:.1f}.")
    return _result(c, False, " ".join(parts_de), " ".join(parts_en), [line] if line else [])


def _tolerance(c: Criterion) -> float:
    return c.tolerance if c.tolerance is not None else 0.05


def _outside_band(hr: HeightMap, hs: HeightMap, tol: float) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]:
    """Per cell, how far the submitted part lies below (over-cut) and above (left standing) the band.

    The band: tol in height, and sideways tol but at least one cell (an edge that falls on a cell
    centre may land on either side of it). A cell is over-cut only if it lies deeper than every
    reference cell that near (along X and Y), and left standing only if it is higher than every one.
    """
    reach = max(1, math.ceil(tol / hr.grid.dx - 1e-9))
    lowest, highest = _neighbourhood(hr.heights, reach)
    return np.clip(lowest - tol - hs.heights, 0.0, None), np.clip(hs.heights - highest - tol, 0.0, None)


@dataclass(frozen=True, slots=True)
class Deviation:
    """Where a submitted part leaves the reference's tolerance band, cell by cell (mm, ≥ 0)."""

    part: HeightMap  # the submitted part
    over: npt.NDArray[np.float64]  # too much material removed: how far below the band
    left: npt.NDArray[np.float64]  # too little removed: how far above the band

    def points(self, which: Literal["over", "left"]) -> npt.NDArray[np.float32]:
        """The centres of those cells on the part's surface, (N, 3) mm."""
        g, hm = self.part.grid, self.part
        j, i = np.nonzero(self.over if which == "over" else self.left)
        z = np.clip(hm.heights[j, i], hm.base, hm.top)
        return np.stack([g.x0 + (i + 0.5) * g.dx, g.y0 + (j + 0.5) * g.dy, z], 1).astype(np.float32)


def deviation(exercise: Exercise, program: str) -> Deviation:
    """The submitted part against the reference, with the geometry criterion's tolerance (for the 3D view)."""
    tol = next((_tolerance(c) for c in exercise.rubric if c.id == "geometry"), 0.05)
    reference = execute(exercise, exercise.reference)
    submission = execute(exercise, program)
    over, left = _outside_band(reference.sim.heightmap, submission.sim.heightmap, tol)
    return Deviation(submission.sim.heightmap, over, left)


def _neighbourhood(h: npt.NDArray[np.float64], reach: int) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]:
    """The lowest and the highest height of every cell and its neighbours along X and Y up to `reach` cells.

    A cross, not a square: sideways the band is then at most `reach` cells wide in every direction
    (a square would let a diagonal edge move 1.4 cells).
    """
    padded = np.pad(h, reach, mode="edge")
    ny, nx = h.shape
    lowest, highest = h.copy(), h.copy()
    for k in range(1, reach + 1):
        for dj, di in ((k, 0), (-k, 0), (0, k), (0, -k)):
            window = padded[reach + dj:reach + dj + ny, reach + di:reach + di + nx]
            np.minimum(lowest, window, out=lowest)
            np.maximum(highest, window, out=highest)
    return lowest, highest


def _line_at(tp: Toolpath, x: float, y: float) -> int | None:
    """The block of the lowest cutting move that passes over (x, y) within the tool's reach."""
    best: tuple[float, int] | None = None
    for m in tp.moves:
        if m.kind == "rapid":
            continue
        reach = 20.0
        pts = m.points(0.05, max_chords=ARC_CHORDS)
        for a, b in itertools.pairwise(pts):
            d = _segment_distance((x, y), a, b)
            if d <= reach:
                z = min(a[2], b[2])
                key = (z + d * 1e-3, m.line)
                if best is None or key < best:
                    best = key
    return best[1] if best else None


def _segment_distance(p: tuple[float, float], a: tuple[float, float, float], b: tuple[float, float, float]) -> float:
    dx, dy = b[0] - a[0], b[1] - a[1]
    n = dx * dx + dy * dy
    t = 0.0 if n == 0 else max(0.0, min(1.0, ((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / n))
    return math.hypot(p[0] - a[0] - t * dx, p[1] - a[1] - t * dy)


def _may_cut(m: Move, ex: Exercise) -> bool:
    """Whether the tool can touch the blank on this move: some point of it, widened by the tool radius,
    lies inside the blank's box. A feed in the air (a plunge beside the blank, a move above it) cuts nothing."""
    s = ex.stock
    tool = ex.tool_table().get(m.tool) if m.tool is not None else None
    pts = m.points(0.1, max_chords=ARC_CHORDS)
    # the chords of a huge arc may cut inside its bulge by up to their sagitta: widen by it
    bulge = m.radius * (1 - math.cos(math.pi / ARC_CHORDS)) if m.kind == "arc" and m.radius is not None else 0.0
    r = (tool.radius if tool is not None else 0.0) + bulge
    if min(p[2] for p in pts) >= s.max[2]:
        return False
    return (min(p[0] for p in pts) - r < s.max[0] and max(p[0] for p in pts) + r > s.min[0]
            and min(p[1] for p in pts) - r < s.max[1] and max(p[1] for p in pts) + r > s.min[1])


def _technology(c: Criterion, ex: Exercise, cutting: list[Move]) -> CriterionResult:
    """Tool, S and F of the feed moves that can cut (not of the ones in the air) against the cutting data."""
    if not ex.cutting_data:
        return _result(c, True, "Keine Schnittdaten vorgegeben.", "No cutting data prescribed.")
    tol = c.tolerance if c.tolerance is not None else 0.1
    wanted = {d.tool: d for d in ex.cutting_data}
    for m in cutting:
        if m.tool is None:
            return _result(c, False, f"Zeile {m.line}: kein Werkzeug eingewechselt.",
                           f"Line {m.line}: no tool loaded.", [m.line])
        data = wanted.get(m.tool)
        if data is None:
            return _result(c, False, f"Zeile {m.line}: Werkzeug T{m.tool} ist in der Aufgabe nicht vorgesehen.",
                           f"Line {m.line}: tool T{m.tool} is not the one the task prescribes.", [m.line])
        for name, have, want in (("S", m.spindle, data.speed or 0.0), ("F", m.feed, data.feed)):
            if abs(have - want) > tol * want:
                return _result(c, False, f"Zeile {m.line}: {name}{have:g} statt {name}{want:g} für T{m.tool}.",
                               f"Line {m.line}: {name}{have:g} instead of {name}{want:g} for T{m.tool}.", [m.line])
    return _result(c, True, "Werkzeug, Drehzahl und Vorschub wie vorgegeben.",
                   "Tool, spindle speed and feed as prescribed.")
