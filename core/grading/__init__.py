"""The grader: a submission against an exercise's reference, criterion by criterion (pure, deterministic).

Both programs run through the same pipeline (interpret, then simulate on the exercise's stock at its
resolution); the machined parts are compared cell by cell with a tolerance band, so equivalent
programs (arc by R instead of I/J, RN instead of an explicit arc, incremental instead of absolute)
score the same. The geometry criterion gives the share of the reference's features the submission made
within the band (core.grading.features) and names the likely cause of a deviation from the two programmed
contours (core.grading.causes). Every criterion carries its points, a German and an English message and the
lines it concerns; numbers in the texts are formatted by core.grading.numbers.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, Literal

import numpy as np
import numpy.typing as npt

from core.diagnostics import Diagnostic, Severity, catalogue_code
from core.exercises import Criterion, Exercise
from core.grading.causes import Cause, Comparison, compare, file_line, nearest_line
from core.grading.features import Feature, cutters, deviation_text, judge_milled, milled_features, share
from core.grading.numbers import de as de_num
from core.grading.numbers import en as en_num
from core.grading.numbers import volume, word
from core.grading.technology import direction_fault, in_effect, spindle_set_where, spindle_wanted
from core.grading.turning import (
    NAME_REACH,
    Turned,
    execute_turning,
    may_cut_turning,
    turned_geometry,
    turning_technology,
    unsafe_events,
)
from core.interpreter.state import RunSetup
from core.pipeline import DIALECTS, run
from core.sim import HeightMap, SimResult, simulate
from core.toolpath import Move, Toolpath

SAFETY_EVENTS = {
    "SIM-E001",
    "SIM-E002",
    "SIM-E003",
    "SIM-E004",
    "SIM-E005",
    "SIM-E006",
    "SIM-E007",
    "SIM-E008",
}
SAFE_CLEARANCE = 10.0  # mm above the stock top counts as a safe end position
# chords of one arc where grading looks at its points: bounded before they are made, so that a loop of
# huge arcs (radius 50 m: 2,000 chords at 0.05 mm) costs no more than a loop of small ones
ARC_CHORDS = 256
COMPENSATING = ("G41", "G42", "G46")  # the codes that select cutter or nose-radius compensation
Status = Literal["passed", "partial", "failed"]


@dataclass(frozen=True, slots=True)
class CriterionResult:
    """One criterion's verdict. `passed`: all its points; `points` may lie between 0 and `max_points` (the
    geometry criterion's share of kept features): `status` is then "partial"."""

    id: str
    passed: bool
    points: int
    max_points: int
    message: str
    message_en: str
    lines: tuple[int, ...]
    hidden: bool
    causes: tuple[Cause, ...] = ()  # the likely causes of a lost criterion, the likeliest first
    features: tuple[Feature, ...] | None = None  # geometry: the reference's features, kept or not

    @property
    def status(self) -> Status:
        if self.passed:
            return "passed"
        return "partial" if self.points > 0 else "failed"

    @property
    def cause(self) -> Cause | None:
        return self.causes[0] if self.causes else None

    def to_json(self) -> dict[str, Any]:
        data: dict[str, Any] = {
            "id": self.id,
            "status": self.status,
            "points": self.points,
            "max_points": self.max_points,
            "message": self.message,
            "message_en": self.message_en,
            "lines": list(self.lines),
            "hidden": self.hidden,
            "cause": None if self.cause is None else self.cause.to_json(),
            "causes": [c.to_json() for c in self.causes],
        }
        if self.features is not None:
            data["features"] = [f.to_json() for f in self.features]
        return data


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
        return {
            "exercise": self.exercise,
            "score": self.score,
            "max_score": self.max_score,
            "criteria": [c.to_json() for c in shown],
            "diagnostics": [d.to_json() for d in self.diagnostics],
        }


@dataclass(frozen=True, slots=True)
class Machined:
    toolpath: Toolpath
    sim: SimResult


def execute(exercise: Exercise, text: str) -> Machined:
    """`text` interpreted and simulated on the exercise's set-up and stock (the grader's view; the drawing's too)."""
    tools = exercise.tool_table()
    setup = RunSetup(
        tools=tools,
        zero_offsets=tuple(exercise.zero_offsets.items()),
        subprograms=tuple(exercise.subprograms.items()),
    )
    toolpath = run(text, exercise.dialect, setup)
    sim = simulate(toolpath, exercise.stock.stock(), tools, exercise.resolution)
    return Machined(toolpath, sim)


def grade(exercise: Exercise, program: str) -> GradeResult:
    """Grade `program` against `exercise`. The same inputs always give the same result. A lathe dialect's
    exercise turns both programs on its blank (core.grading.turning), a milling one mills its stock."""
    run_on: Callable[[Exercise, str], Machined | Turned] = (
        execute_turning if DIALECTS[exercise.dialect].lathe else execute
    )
    reference = run_on(exercise, exercise.reference)
    submission = run_on(exercise, program)
    results = [_judge(c, exercise, program, reference, submission) for c in exercise.rubric]
    score = sum(r.points for r in results)
    return GradeResult(
        exercise.id,
        score,
        sum(c.points for c in exercise.rubric),
        tuple(results),
        tuple(submission.toolpath.diagnostics),
    )


def _result(
    c: Criterion, passed: bool, de: str, en: str, lines: list[int] | tuple[int, ...] = (), code: str = ""
) -> CriterionResult:
    """A criterion with all or none of its points; a lost one names its cause (`code`, the first line)."""
    causes = () if passed or not code else (Cause(code, lines[0] if lines else 0, de, en),)
    return CriterionResult(
        c.id, passed, c.points if passed else 0, c.points, de, en, tuple(sorted(set(lines))), c.hidden, causes
    )


def tool_radii(ex: Exercise) -> dict[int | None, float]:
    """Tool number → radius (milling: the cutter's; turning: the nose radius) of the exercise's tool table."""
    table = ex.tool_table() if ex.tools or not ex.lathe else None
    if table is None:
        from core.sim.turning import DEFAULT_LATHE_TOOLS

        table = DEFAULT_LATHE_TOOLS
    return {n: (t.nose_radius if ex.lathe else t.radius) for n, t in table.tools.items()}


def cutting_moves(ex: Exercise, tp: Toolpath) -> list[int]:
    """Indices of the moves that can cut the workpiece (feed moves with a tool reaching into the stock or bar;
    turning: cycles' passes aside, their finishing contour counts)."""
    if ex.lathe:
        return [
            k
            for k, m in enumerate(tp.moves)
            if m.kind != "rapid" and m.tool is not None and m.cycle is None and may_cut_turning(m, ex)
        ]
    radius = tool_radii(ex)
    return [
        k
        for k, m in enumerate(tp.moves)
        if m.kind != "rapid" and m.tool is not None and _may_cut(m, ex, radius)
    ]


def _judge(
    c: Criterion, ex: Exercise, program: str, ref: Machined | Turned, sub: Machined | Turned
) -> CriterionResult:
    tp = sub.toolpath
    cutting = [m for m in tp.moves if m.kind != "rapid"]
    if isinstance(ref, Turned) and isinstance(sub, Turned):
        lathe = _judge_turning(c, ex, program, ref, sub, cutting)
        if lathe is not None:
            return lathe
    assert isinstance(ref, Machined) or c.id not in ("geometry", "safety", "technology", "safe_position")
    if c.id == "syntax":
        errors = [d for d in tp.diagnostics if d.severity is Severity.ERROR]
        if not errors:
            return _result(c, True, "Keine Syntax- und Programmfehler.", "No syntax or program errors.")
        first = errors[0]
        count = (
            "1 Syntax- oder Programmfehler"
            if len(errors) == 1
            else f"{len(errors)} Syntax- oder Programmfehler"
        )
        count_en = (
            "1 syntax or program error" if len(errors) == 1 else f"{len(errors)} syntax or program errors"
        )
        return _result(
            c,
            False,
            f"{count}, {'der' if len(errors) == 1 else 'der erste'} in Zeile "
            f"{first.span.line}: {first.message}",
            f"{count_en}, {'' if len(errors) == 1 else 'the first '}"
            f"in line {first.span.line}: {first.message_en}",
            [first.span.line] + [d.span.line for d in errors],
            first.code,
        )
    if c.id == "geometry":
        assert isinstance(ref, Machined) and isinstance(sub, Machined)
        return _geometry(c, ex, program, ref, sub)
    if c.id == "safety":
        events = [e for e in sub.sim.events if e.code in SAFETY_EVENTS]
        if not events:
            return _result(
                c, True, "Keine Kollision und kein gefährlicher Schnitt.", "No collision, no unsafe cut."
            )
        e = events[0]
        return _result(
            c,
            False,
            f"Zeile {e.span.line}: {e.message}",
            f"Line {e.span.line}: {e.message_en}",
            [e.span.line] + [x.span.line for x in events if x.span.line],
            e.code,
        )
    if c.id == "technology":
        radius = tool_radii(ex)
        return _technology(c, ex, program, ref.toolpath, [m for m in cutting if _may_cut(m, ex, radius)])
    if c.id == "tool_change":
        first_cut = cutting[0].line if cutting else None
        changed = [t for t in tp.tool_changes if t.tool is not None]
        ok = bool(changed) and (first_cut is None or _before(tp, changed[0], cutting[0]))
        call = "T…" if ex.lathe else "T … M6"
        return _result(
            c,
            ok,
            "Werkzeug vor dem ersten Schnitt eingewechselt."
            if ok
            else f"Kein Werkzeugwechsel ({call}) vor dem ersten Schnitt.",
            "Tool changed before the first cut." if ok else f"No tool change ({call}) before the first cut.",
            [] if ok or first_cut is None else [first_cut],
            "tool_change_missing",
        )
    if c.id == "spindle_on":
        stopped = [m.line for m in cutting if m.spindle == 0]
        return _result(
            c,
            not stopped,
            "Die Spindel läuft bei allen Vorschubbewegungen."
            if not stopped
            else f"Vorschubbewegung bei stehender Spindel in Zeile {stopped[0]}.",
            "The spindle turns during every feed move."
            if not stopped
            else f"Feed move with the spindle stopped in line {stopped[0]}.",
            stopped,
            "spindle_stopped",
        )
    if c.id == "compensation_off":
        return _compensation(c, ex, ref.toolpath, tp)
    if c.id == "safe_position":
        z = tp.final_position[2]
        top = ex.stock.max[2]
        ok = z >= top + SAFE_CLEARANCE
        return _result(
            c,
            ok,
            f"Das Werkzeug endet auf Z{word(z)}, sicher über dem Werkstück."
            if ok
            else f"Das Werkzeug endet auf Z{word(z)}, weniger als {de_num(SAFE_CLEARANCE)} mm über dem "
            f"Werkstück.",
            f"The tool ends at Z{word(z)}, safely above the part."
            if ok
            else f"The tool ends at Z{word(z)}, less than {en_num(SAFE_CLEARANCE)} mm above the part.",
            [],
            "end_position",
        )
    if c.id == "program_end":
        missing = [d for d in tp.diagnostics if catalogue_code(d.code) == "PAL-W102"]
        end = missing[0].span.line if missing else 0
        return _result(
            c,
            not missing,
            "Das Programm endet mit M30."
            if not missing
            else f"M30 (Programmende) fehlt: das Programm endet in Zeile {end}.",
            "The program ends with M30."
            if not missing
            else f"M30 (end of program) is missing: the program ends in line {end}.",
            [d.span.line for d in missing],
            "program_end_missing",
        )
    # locked_lines
    given = ex.start_program.splitlines()
    mine = program.splitlines()
    edited = [n for n in ex.locked_lines if n > len(mine) or mine[n - 1].strip() != given[n - 1].strip()]
    return _result(
        c,
        not edited,
        "Die vorgegebenen Zeilen sind unverändert."
        if not edited
        else f"Vorgegebene Zeilen wurden geändert: {', '.join(map(str, edited))}.",
        "The given lines are unchanged."
        if not edited
        else f"Given lines were changed: {', '.join(map(str, edited))}.",
        edited,
        "locked_lines_changed",
    )


def _compensation(c: Criterion, ex: Exercise, ref: Toolpath, tp: Toolpath) -> CriterionResult:
    """Where the reference uses cutter (nose-radius) compensation: the submission selects it and has it off at the
    end (G40). Where the reference does not use it, the criterion passes with a neutral text unless the submission
    leaves a compensation on at the end."""
    what, what_en = (
        ("Schneidenradiuskompensation (SRK)", "Nose-radius compensation")
        if ex.lathe
        else ("Fräserradiuskorrektur", "Cutter radius compensation")
    )
    select = "G46" if ex.lathe else "G41/G42"
    last = len(tp.line_states)
    state = tp.state_at(last)[0] if last else None
    off = state is None or state.active("compensation") in ("G40", None)
    wanted = any(s.active("compensation") in COMPENSATING for s in ref.line_states)
    selected = any(s.active("compensation") in COMPENSATING for s in tp.line_states)
    if not off:
        return _result(
            c,
            False,
            f"Die {what} ist am Programmende noch aktiv: G40 fehlt.",
            f"{what_en} is still on at the end: G40 is missing.",
            [],
            "compensation_left_on",
        )
    if not wanted:
        if selected:
            return _result(
                c, True, f"Die {what} ist am Ende abgewählt (G40).", f"{what_en} is off at the end (G40)."
            )
        return _result(
            c,
            True,
            f"Die Aufgabe verlangt keine {what}; am Programmende ist keine aktiv.",
            f"The task needs no {what_en[0].lower()}{what_en[1:]}; none is on at the end.",
        )
    if not selected:
        return _result(
            c,
            False,
            f"Die {what} wird nie angewählt ({select} fehlt); die Aufgabe verlangt sie.",
            f"{what_en} is never selected ({select} is missing); the task needs it.",
            [],
            "compensation_never_selected",
        )
    return _result(
        c,
        True,
        f"Die {what} ist angewählt und am Ende abgewählt (G40).",
        f"{what_en} is selected and off at the end (G40).",
    )


def _judge_turning(
    c: Criterion, ex: Exercise, program: str, ref: Turned, sub: Turned, cutting: list[Move]
) -> CriterionResult | None:
    """The criteria a lathe exercise judges its own way (the turned part, its events, V/S and F per revolution,
    the end position off the bar); None: as in milling."""
    verdict: tuple[bool, str, str, list[int], str] | None = None
    if c.id == "geometry":
        return _turned_geometry(c, ex, program, ref, sub)
    if c.id == "safety":
        events = unsafe_events(sub)
        if not events:
            return _result(
                c, True, "Keine Kollision und kein gefährlicher Schnitt.", "No collision, no unsafe cut."
            )
        e = events[0]
        verdict = (
            False,
            f"Zeile {e.span.line}: {e.message}",
            f"Line {e.span.line}: {e.message_en}",
            [e.span.line] + [x.span.line for x in events if x.span.line],
            e.code,
        )
    elif c.id == "technology":
        verdict = turning_technology(
            ex,
            [m for m in cutting if may_cut_turning(m, ex)],
            c.tolerance if c.tolerance is not None else 0.1,
            program,
            ref.toolpath,
        )
    elif c.id == "safe_position":
        assert ex.blank is not None
        x, _, z = sub.toolpath.final_position
        ok = z >= SAFE_CLEARANCE or abs(x) >= ex.blank.diameter / 2 + SAFE_CLEARANCE
        verdict = (
            ok,
            f"Das Werkzeug endet bei X{word(2 * x)} Z{word(z)}, frei vom Werkstück."
            if ok
            else f"Das Werkzeug endet bei X{word(2 * x)} Z{word(z)}, weniger als {de_num(SAFE_CLEARANCE)} mm vom "
            f"Werkstück.",
            f"The tool ends at X{word(2 * x)} Z{word(z)}, clear of the part."
            if ok
            else f"The tool ends at X{word(2 * x)} Z{word(z)}, less than {en_num(SAFE_CLEARANCE)} mm from the part.",
            [],
            "end_position",
        )
    if verdict is None:
        return None
    return _result(c, verdict[0], verdict[1], verdict[2], verdict[3], verdict[4])


def geometry_result(
    c: Criterion,
    features: list[Feature],
    causes: list[Cause],
    over_volume: float,
    left_volume: float,
    extra_lines: list[int] | None = None,
) -> CriterionResult:
    """The geometry criterion from the judged features: the share of kept ones, the causes, what deviates."""
    kept = sum(1 for f in features if f.ok)
    total = len(features)
    points = share(c.points, kept, total) if total else 0
    lost = [f for f in features if not f.ok]
    de = [f"{kept} von {total} Formelementen maßhaltig."] if total else []
    en = [f"{kept} of {total} features made to size."] if total else []
    if causes:
        de.append(f"Ursache: {causes[0].message}")
        en.append(f"Cause: {causes[0].message_en}")
        for more in causes[1:3]:
            de.append(f"Außerdem: {more.message}")
            en.append(f"Also: {more.message_en}")
    if lost:
        shown = lost[:4]
        rest = len(lost) - len(shown)
        de.append(
            "Abweichend: "
            + "; ".join(deviation_text(f) for f in shown)
            + (f"; und {rest} weitere" if rest else "")
            + "."
        )
        en.append(
            "Off: "
            + "; ".join(deviation_text(f, "en") for f in shown)
            + (f"; and {rest} more" if rest else "")
            + "."
        )
    amounts_de, amounts_en = [], []
    if over_volume > 0:
        amounts_de.append(f"Zu viel Material abgetragen: {volume(over_volume)}")
        amounts_en.append(f"Too much material removed: {volume(over_volume, 'en')}")
    if left_volume > 0:
        amounts_de.append(f"Material stehen gelassen: {volume(left_volume)}")
        amounts_en.append(f"{'m' if amounts_en else 'M'}aterial left standing: {volume(left_volume, 'en')}")
    if amounts_de:
        de.append("; ".join(amounts_de) + ".")
        en.append("; ".join(amounts_en) + ".")
    lines = [x.line for x in causes if x.line] + [f.line for f in lost if f.line] + (extra_lines or [])
    return CriterionResult(
        c.id,
        points == c.points and total > 0,
        points,
        c.points,
        " ".join(de),
        " ".join(en),
        tuple(sorted(set(lines))),
        c.hidden,
        tuple(causes),
        tuple(features),
    )


def _before(tp: Toolpath, change: object, move: Move) -> bool:
    commands = tp.commands
    return commands.index(change) < commands.index(move)  # type: ignore[arg-type]


def _geometry(c: Criterion, ex: Exercise, program: str, ref: Machined, sub: Machined) -> CriterionResult:
    """The milled part feature by feature (core.grading.features), with the likely causes of what deviates."""
    tol = _tolerance(c)
    hr, hs = ref.sim.heightmap, sub.sim.heightmap
    grid = hr.grid
    area = grid.dx * grid.dy
    over, left = _outside_band(hr, hs, tol)
    over_volume, left_volume = float(over.sum()) * area, float(left.sum()) * area
    allowance = 4 * area * tol  # a few cells at the band's edge
    radius = tool_radii(ex)
    ref_cut = cutting_moves(ex, ref.toolpath)
    shapes, levels = milled_features(ref.toolpath, ref_cut, radius)
    if over_volume <= allowance and left_volume <= allowance:
        features = [s.feature for s in shapes] + [
            Feature("floor", f"Boden Z{word(z)}", f"floor Z{word(z)}") for z in levels
        ]
        return CriterionResult(
            c.id,
            True,
            c.points,
            c.points,
            "Das Werkstück entspricht der Zeichnung.",
            "The part matches the drawing.",
            (),
            c.hidden,
            (),
            tuple(features),
        )
    cmp = compare(
        ref.toolpath, ref_cut, sub.toolpath, cutting_moves(ex, sub.toolpath), False, radius, program
    )

    def line_at(x: float, y: float, too_much: bool) -> int | None:
        return (
            _line_at(sub.toolpath, x, y)
            if too_much
            else nearest_line(cmp.submission, (x, y), 2 * max(radius.values(), default=0.0) + 1.0)
        )

    feature_of = {s.element: n for n, s in enumerate(shapes) if s.element is not None}
    counterpart = {si: feature_of[ri] for ri, si in cmp.counterparts() if ri in feature_of}
    judged = judge_milled(
        shapes,
        levels,
        hr,
        hs,
        over,
        left,
        tol,
        line_at,
        cutters(sub.toolpath, cmp.submission, radius, counterpart),
    )
    features = [_named_line(f, s.element, cmp) for f, s in zip(judged.features, shapes, strict=False)]
    depth = next((x for x in cmp.causes if x.code == "depth"), None)
    features += [
        f
        if f.ok or depth is None
        else Feature(
            f.kind, f.name, f.name_en, f.ok, f.deviation, f.sideways, f.too_much, f.where, depth.line
        )
        for f in judged.features[len(shapes) :]
    ]
    return geometry_result(
        c,
        features,
        cmp.causes,
        over_volume if over_volume > allowance else 0.0,
        left_volume if left_volume > allowance else 0.0,
    )


def _named_line(f: Feature, element: int | None, cmp: Comparison) -> Feature:
    """A lost feature's line: the submission's element made in its place, else the block cutting there."""
    if f.ok or element is None:
        return f
    partner = cmp.partner(element)
    if partner is None:
        return f
    return Feature(
        f.kind, f.name, f.name_en, f.ok, f.deviation, f.sideways, f.too_much, f.where, partner.line
    )


def _turned_geometry(c: Criterion, ex: Exercise, program: str, ref: Turned, sub: Turned) -> CriterionResult:
    """The turned part feature by feature (core.grading.turning), with the likely causes of what deviates."""
    radius = tool_radii(ex)
    compared: list[Comparison] = []

    def comparison() -> Comparison:
        if not compared:
            compared.append(
                compare(
                    ref.toolpath,
                    cutting_moves(ex, ref.toolpath),
                    sub.toolpath,
                    cutting_moves(ex, sub.toolpath),
                    True,
                    radius,
                    program,
                )
            )
        return compared[0]

    def name_line(z: float, r: float) -> int | None:
        return nearest_line(comparison().submission, (z, r), NAME_REACH)

    judged = turned_geometry(ref, sub, _tolerance(c), name_line)
    if judged.passed:
        return CriterionResult(
            c.id,
            True,
            c.points,
            c.points,
            "Das Drehteil entspricht der Zeichnung.",
            "The turned part matches the drawing.",
            (),
            c.hidden,
            (),
            tuple(judged.features),
        )
    return geometry_result(c, judged.features, comparison().causes, judged.over_volume, judged.left_volume)


def _tolerance(c: Criterion) -> float:
    return c.tolerance if c.tolerance is not None else 0.05


def _outside_band(
    hr: HeightMap, hs: HeightMap, tol: float
) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]:
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


def _neighbourhood(
    h: npt.NDArray[np.float64], reach: int
) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]:
    """The lowest and the highest height of every cell and its neighbours along X and Y up to `reach` cells.

    A cross, not a square: sideways the band is then at most `reach` cells wide in every direction
    (a square would let a diagonal edge move 1.4 cells).
    """
    padded = np.pad(h, reach, mode="edge")
    ny, nx = h.shape
    lowest, highest = h.copy(), h.copy()
    for k in range(1, reach + 1):
        for dj, di in ((k, 0), (-k, 0), (0, k), (0, -k)):
            window = padded[reach + dj : reach + dj + ny, reach + di : reach + di + nx]
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


def _segment_distance(
    p: tuple[float, float], a: tuple[float, float, float], b: tuple[float, float, float]
) -> float:
    dx, dy = b[0] - a[0], b[1] - a[1]
    n = dx * dx + dy * dy
    t = 0.0 if n == 0 else max(0.0, min(1.0, ((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / n))
    return math.hypot(p[0] - a[0] - t * dx, p[1] - a[1] - t * dy)


def _may_cut(m: Move, ex: Exercise, radius: dict[int | None, float] | None = None) -> bool:
    """Whether the tool can touch the blank on this move: some point of it, widened by the tool radius,
    lies inside the blank's box. A feed in the air (a plunge beside the blank, a move above it) cuts nothing.
    `radius`: the exercise's tool radii (tool_radii), when the caller has them already."""
    s = ex.stock
    if m.plane == "G17" and min(m.start[2], m.end[2]) >= s.max[2]:
        return False  # above the stock all the way (an arc of G17 changes Z linearly)
    if radius is None:
        tool = ex.tool_table().get(m.tool) if m.tool is not None else None
        tool_r = tool.radius if tool is not None else 0.0
    else:
        tool_r = radius.get(m.tool, 0.0)
    if m.kind == "arc" and m.center is not None and m.radius is not None and m.plane == "G17":
        reach = m.radius + tool_r  # the whole circle's box first: most arcs far from the stock end here
        if (
            m.center[0] - reach >= s.max[0]
            or m.center[0] + reach <= s.min[0]
            or m.center[1] - reach >= s.max[1]
            or m.center[1] + reach <= s.min[1]
        ):
            return False
    pts = m.points(0.1, max_chords=ARC_CHORDS)
    # the chords of a huge arc may cut inside its bulge by up to their sagitta: widen by it
    bulge = (
        m.radius * (1 - math.cos(math.pi / ARC_CHORDS)) if m.kind == "arc" and m.radius is not None else 0.0
    )
    r = tool_r + bulge
    if min(p[2] for p in pts) >= s.max[2]:
        return False
    return (
        min(p[0] for p in pts) - r < s.max[0]
        and max(p[0] for p in pts) + r > s.min[0]
        and min(p[1] for p in pts) - r < s.max[1]
        and max(p[1] for p in pts) + r > s.min[1]
    )


def _technology(
    c: Criterion, ex: Exercise, program: str, reference: Toolpath, cutting: list[Move]
) -> CriterionResult:
    """Tool, spindle direction, S and F of the feed moves that can cut (not of the ones in the air) against the
    cutting data."""
    if not ex.cutting_data:
        return _result(c, True, "Keine Schnittdaten vorgegeben.", "No cutting data prescribed.")
    tol = c.tolerance if c.tolerance is not None else 0.1
    wanted = {d.tool: d for d in ex.cutting_data}
    direction = spindle_wanted(ex, reference)
    for m in cutting:
        line = file_line(m)
        if m.tool is None:
            return _result(
                c,
                False,
                f"Zeile {line}: kein Werkzeug eingewechselt.",
                f"Line {line}: no tool loaded.",
                [line],
                "no_tool",
            )
        data = wanted.get(m.tool)
        if data is None:
            return _result(
                c,
                False,
                f"Zeile {line}: Werkzeug T{m.tool} ist in der Aufgabe nicht vorgesehen.",
                f"Line {line}: tool T{m.tool} is not the one the task prescribes.",
                [line],
                "tool",
            )
        # a tapping cycle (G84) feeds out of the thread with the spindle reversed: that is the task's direction
        tapping_out = m.cycle is not None and m.cycle[0] == "G84" and m.end[2] > m.start[2]
        fault = None if tapping_out else direction_fault(m, direction.get(m.tool), program, line)
        if fault is not None:
            where = spindle_set_where(program, line)
            return _result(
                c,
                False,
                f"Zeile {line}: {fault[0]}",
                f"Line {line}: {fault[1][0].upper()}{fault[1][1:]}",
                [line] + ([where] if where else []),
                "spindle_direction",
            )
        if abs(m.spindle - (data.speed or 0.0)) > tol * (data.speed or 0.0):
            have, have_en, at = in_effect(program, line, m.spindle, "S")
            return _result(
                c,
                False,
                f"Zeile {line}: {have} statt S{word(data.speed or 0.0)} für T{m.tool}.",
                f"Line {line}: {have_en} instead of S{word(data.speed or 0.0)} for T{m.tool}.",
                [line] + ([at] if at else []),
                "speed",
            )
        if abs(m.feed - data.feed) > tol * data.feed:
            have, have_en, at = in_effect(program, line, m.feed, "FE")
            return _result(
                c,
                False,
                f"Zeile {line}: {have} statt F{word(data.feed)} für T{m.tool}.",
                f"Line {line}: {have_en} instead of F{word(data.feed)} for T{m.tool}.",
                [line] + ([at] if at else []),
                "feed",
            )
    return _result(
        c,
        True,
        "Werkzeug, Drehrichtung, Drehzahl und Vorschub wie vorgegeben.",
        "Tool, spindle direction, spindle speed and feed as prescribed.",
    )
