"""The grader's lathe side: a turning exercise's programs turned on its blank and the turned parts compared.

Both programs are simulated on the exercise's bar or tube (core.sim.turning) at its resolution along Z;
the parts are compared sample by sample, outside (the outer radius) and inside (the bore), within a band
of `tolerance` mm radially and sideways the tolerance but at least one sample (a face on a sample's edge may
fall on either side of it). Volumes are the rings between the two parts where they leave the band.
The functions answer (passed, German, English, lines); core.grading turns that into a criterion's result.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from core.diagnostics import Diagnostic
from core.exercises import CuttingData, Exercise
from core.interpreter import Toolpath
from core.interpreter.state import RunSetup
from core.pipeline import run
from core.sim.turning import DEFAULT_LATHE_TOOLS, RevolvedProfile, TurningResult, simulate_turning
from core.toolpath import Move

# the turning simulation's events that make a program unsafe (SIM-E010, the work limit, is none of them)
LATHE_SAFETY_EVENTS = {"SIM-E001", "SIM-E006", "SIM-E008", "SIM-E011", "SIM-E012", "SIM-E013", "SIM-E014"}
ARC_CHORDS = 256  # chords of one arc where grading looks at its points
NAME_REACH = 3.0  # mm: material left standing names the block whose path passes this near it
Verdict = tuple[bool, str, str, list[int]]
Array = npt.NDArray[np.float64]


@dataclass(frozen=True, slots=True)
class Turned:
    toolpath: Toolpath
    sim: TurningResult


def execute_turning(exercise: Exercise, text: str) -> Turned:
    """`text` run and turned on the exercise's blank with its tools (the grader's view of a lathe exercise)."""
    assert exercise.blank is not None, "a turning exercise has a blank"
    tools = exercise.tool_table() if exercise.tools else DEFAULT_LATHE_TOOLS
    setup = RunSetup(tools=tools, zero_offsets=tuple(exercise.zero_offsets.items()),
                     subprograms=tuple(exercise.subprograms.items()))
    toolpath = run(text, exercise.dialect, setup)
    return Turned(toolpath, simulate_turning(toolpath, exercise.blank.blank(), tools, exercise.resolution))


@dataclass(frozen=True, slots=True)
class ProfileDeviation:
    """Where a turned part leaves the reference's band, per Z sample (radial mm, ≥ 0), and the volumes (mm³)."""

    part: RevolvedProfile  # the submitted part
    over_outer: Array  # outside: turned below the band (too much removed)
    left_outer: Array  # outside: above the band (material left)
    over_inner: Array  # bore: bored beyond the band
    left_inner: Array  # bore: not bored far enough
    over_volume: float
    left_volume: float


def _neighbourhood(a: Array, reach: int) -> tuple[Array, Array]:
    """The lowest and highest value of every sample and its neighbours up to `reach` samples along Z."""
    padded = np.pad(a, reach, mode="edge")
    n = len(a)
    lowest, highest = a.copy(), a.copy()
    for k in range(-reach, reach + 1):
        window = padded[reach + k:reach + k + n]
        np.minimum(lowest, window, out=lowest)
        np.maximum(highest, window, out=highest)
    return lowest, highest


def compare_profiles(ref: RevolvedProfile, sub: RevolvedProfile, tol: float) -> ProfileDeviation:
    """The submitted part against the reference (both on the same blank and samples)."""
    reach = max(1, math.ceil(tol / ref.dz - 1e-9))
    r_out, s_out = np.clip(ref.outer, 0, None), np.clip(sub.outer, 0, None)
    r_in, s_in = np.clip(ref.inner, 0, None), np.clip(sub.inner, 0, None)
    lo_out, hi_out = _neighbourhood(r_out, reach)
    lo_in, hi_in = _neighbourhood(r_in, reach)
    over_outer = np.clip(lo_out - tol - s_out, 0.0, None)
    left_outer = np.clip(s_out - hi_out - tol, 0.0, None)
    over_inner = np.clip(s_in - hi_in - tol, 0.0, None)
    left_inner = np.clip(lo_in - tol - s_in, 0.0, None)
    ring = math.pi * ref.dz
    over = ring * (np.where(over_outer > 0, np.clip(r_out ** 2 - np.maximum(s_out, r_in) ** 2, 0, None), 0.0)
                   + np.where(over_inner > 0, np.clip(np.minimum(s_in, r_out) ** 2 - r_in ** 2, 0, None), 0.0))
    left = ring * (np.where(left_outer > 0, np.clip(s_out ** 2 - np.maximum(r_out, s_in) ** 2, 0, None), 0.0)
                   + np.where(left_inner > 0, np.clip(np.minimum(r_in, s_out) ** 2 - s_in ** 2, 0, None), 0.0))
    return ProfileDeviation(sub, over_outer, left_outer, over_inner, left_inner, float(over.sum()),
                            float(left.sum()))


def turned_deviation(exercise: Exercise, program: str) -> ProfileDeviation:
    """The submitted turned part against the reference with the geometry criterion's tolerance (for the lathe's
    3D view: the deviation in colour on the revolved part)."""
    tol = next((c.tolerance for c in exercise.rubric if c.id == "geometry" and c.tolerance is not None), 0.05)
    ref, sub = execute_turning(exercise, exercise.reference), execute_turning(exercise, program)
    return compare_profiles(ref.sim.profile, sub.sim.profile, tol)


def _worst(dev: ProfileDeviation, ref: RevolvedProfile, over: bool) -> tuple[float, float, float, float, bool]:
    """The sample deviating most: (depth mm, z, submitted radius, reference radius, inside)."""
    outer, inner = (dev.over_outer, dev.over_inner) if over else (dev.left_outer, dev.left_inner)
    k_out, k_in = int(np.argmax(outer)), int(np.argmax(inner))
    inside = float(inner[k_in]) > float(outer[k_out])
    k = k_in if inside else k_out
    z = float(ref.zs[k])
    have, want = (float(dev.part.inner[k]), float(ref.inner[k])) if inside else \
        (float(dev.part.outer[k]), float(ref.outer[k]))
    return abs(have - want), z, have, want, inside


def line_near(tp: Toolpath, z: float, r: float, reach: float = math.inf, rapids: bool = True) -> int | None:
    """The block whose path (a move with a tool, arcs as chords) passes nearest to the point (z, r); on a tie the
    later one, which cut last."""
    best: tuple[float, int] | None = None
    for order, m in enumerate(tp.moves):
        if m.tool is None or (m.kind == "rapid" and not rapids):
            continue
        pts = m.points(0.05, max_chords=ARC_CHORDS)
        for a, b in itertools.pairwise(pts):
            d = _segment_distance((z, r), (a[2], abs(a[0])), (b[2], abs(b[0])))
            if d <= reach and (best is None or d <= best[0] + 1e-6):
                best = (d if best is None else min(d, best[0]), order)
    return tp.moves[best[1]].line if best is not None else None


def _segment_distance(p: tuple[float, float], a: tuple[float, float], b: tuple[float, float]) -> float:
    dz, dx = b[0] - a[0], b[1] - a[1]
    n = dz * dz + dx * dx
    t = 0.0 if n == 0 else max(0.0, min(1.0, ((p[0] - a[0]) * dz + (p[1] - a[1]) * dx) / n))
    return math.hypot(p[0] - a[0] - t * dz, p[1] - a[1] - t * dx)


def turned_geometry(ref: Turned, sub: Turned, tol: float) -> Verdict:
    """Too much removed and too much left, with volume, the largest deviation and the block that cut there."""
    rp = ref.sim.profile
    dev = compare_profiles(rp, sub.sim.profile, tol)
    # a ring of the band's width on two samples at the blank's surface: the band's edge, not a fault
    allowance = 2 * 2 * math.pi * (ref.sim.blank.diameter / 2) * tol * rp.dz
    gouge, left = dev.over_volume > allowance, dev.left_volume > allowance
    if not gouge and not left:
        return True, "Das Drehteil entspricht der Zeichnung.", "The turned part matches the drawing.", []
    de: list[str] = []
    en: list[str] = []
    lines: list[int] = []
    for over in (True, False):
        if not (gouge if over else left):
            continue
        depth, z, have, want, inside = _worst(dev, rp, over)
        # over-cut: the block whose cut left the surface there (the simulation's record, else the nearest path);
        # material left: the feed that should have cut it
        k = min(len(rp.zs) - 1, max(0, int((z - rp.z0) / rp.dz)))
        cutter = int((sub.sim.profile.cut_inner if inside else sub.sim.profile.cut_outer)[k])
        line: int | None = cutter if over and cutter > 0 else \
            line_near(sub.toolpath, z, have, math.inf, True) if over else \
            line_near(sub.toolpath, z, have, NAME_REACH, False)
        if line is not None:
            lines.append(line)
        where = f", Zeile {line}" if line is not None else ""
        where_en = f", line {line}" if line is not None else ""
        side, side_en = ("Bohrung ", "bore ") if inside else ("", "")
        at = f"bei Z{z:.2f} ({side}Ø{2 * have:.2f} statt Ø{2 * want:.2f}{where})"
        at_en = f"at Z{z:.2f} ({side_en}Ø{2 * have:.2f} instead of Ø{2 * want:.2f}{where_en})"
        if over:
            de.append(f"Zu viel Material abgetragen: {dev.over_volume:.1f} mm³; die größte Abweichung ist "
                      f"{depth:.2f} mm {at}.")
            en.append(f"Too much material removed: {dev.over_volume:.1f} mm³; the largest deviation is "
                      f"{depth:.2f} mm {at_en}.")
        else:
            de.append(f"{'Außerdem ' if gouge else ''}Material stehen gelassen: {dev.left_volume:.1f} mm³; die größte "
                      f"Abweichung ist {depth:.2f} mm {at}.")
            en.append(f"{'Also, m' if gouge else 'M'}aterial left standing: {dev.left_volume:.1f} mm³; the largest "
                      f"deviation is {depth:.2f} mm {at_en}.")
    return False, " ".join(de), " ".join(en), lines


def unsafe_events(sub: Turned) -> list[Diagnostic]:
    """The turning events that cost the safety criterion, in order (a retract sliding along the face it has just
    cut is no event of the simulation's: LatheMachine.face_tolerance)."""
    return [e for e in sub.sim.events if e.code in LATHE_SAFETY_EVENTS]


def may_cut_turning(m: Move, ex: Exercise) -> bool:
    """Whether a feed move can touch the blank: some point of it (widened by a nose) lies in the bar's envelope,
    in front of the chuck side and within its diameter. A feed in the air does not count."""
    if ex.blank is None or m.kind == "rapid":
        return False
    margin = 2.0  # mm: a nose radius and the cut it leaves
    pts = m.points(0.1, max_chords=ARC_CHORDS)
    return (min(p[2] for p in pts) < margin and max(p[2] for p in pts) > -ex.blank.length - margin
            and min(abs(p[0]) for p in pts) < ex.blank.diameter / 2 + margin)


def _speed_ok(m: Move, d: CuttingData, tol: float, top: float) -> bool:
    if d.speed is not None:
        return abs(m.spindle - d.speed) <= tol * d.speed
    assert d.cutting_speed is not None
    r = abs((m.programmed_end if m.programmed_end is not None else m.end)[0])
    v = 2 * math.pi * r * m.spindle / 1000  # m/min at the move's end, where its speed was taken
    clamped = v < d.cutting_speed and m.spindle >= top * (1 - 1e-6)  # G92 or the machine's top near the axis
    return clamped or abs(v - d.cutting_speed) <= tol * d.cutting_speed


def _fail(m: Move, de: str, en: str) -> Verdict:
    return False, f"Zeile {m.line}: {de}", f"Line {m.line}: {en}", [m.line]


def turning_technology(ex: Exercise, moves: list[Move], tol: float) -> Verdict:
    """Tool, V or S, and F per revolution (G95) of the feed moves that can cut, against the cutting data. A tool
    may have several entries (roughing and finishing feeds): a move passes when it matches one. A thread move's
    F is its pitch: only its speed is checked."""
    if not ex.cutting_data:
        return True, "Keine Schnittdaten vorgegeben.", "No cutting data prescribed.", []
    top = {t: max(m.spindle for m in moves if m.tool == t) for t in {m.tool for m in moves}}
    for m in moves:
        if m.tool is None:
            return False, f"Zeile {m.line}: kein Werkzeug eingewechselt.", f"Line {m.line}: no tool loaded.", [m.line]
        data = [d for d in ex.cutting_data if d.tool == m.tool]
        if not data:
            return (False, f"Zeile {m.line}: Werkzeug T{m.tool} ist in der Aufgabe nicht vorgesehen.",
                    f"Line {m.line}: tool T{m.tool} is not the one the task prescribes.", [m.line])
        if not m.thread and m.feed_unit != "mm/rev":
            de = f"F{m.feed:g} in mm/min (G94) statt F{data[0].feed:g} mm pro Umdrehung (G95) für T{m.tool}."
            en = f"F{m.feed:g} in mm/min (G94) instead of F{data[0].feed:g} mm per revolution (G95) for T{m.tool}."
            return _fail(m, de, en)
        if not any(_speed_ok(m, d, tol, top[m.tool]) for d in data):
            d = data[0]
            if d.speed is not None:
                return (False, f"Zeile {m.line}: S{m.spindle:g} statt S{d.speed:g} für T{m.tool}.",
                        f"Line {m.line}: S{m.spindle:g} instead of S{d.speed:g} for T{m.tool}.", [m.line])
            r = abs((m.programmed_end if m.programmed_end is not None else m.end)[0])
            v = 2 * math.pi * r * m.spindle / 1000
            return _fail(m, f"Schnittgeschwindigkeit {v:.0f} m/min statt V{d.cutting_speed:g} für T{m.tool}.",
                         f"cutting speed {v:.0f} m/min instead of V{d.cutting_speed:g} for T{m.tool}.")
        if m.thread:
            continue
        feeds = [d.feed for d in data if _speed_ok(m, d, tol, top[m.tool])]
        if not any(abs(m.feed - f) <= tol * f for f in feeds):
            want = " oder ".join(f"F{f:g}" for f in feeds)
            want_en = " or ".join(f"F{f:g}" for f in feeds)
            return (False, f"Zeile {m.line}: F{m.feed:g} statt {want} mm pro Umdrehung für T{m.tool}.",
                    f"Line {m.line}: F{m.feed:g} instead of {want_en} mm per revolution for T{m.tool}.", [m.line])
    return (True, "Werkzeug, Schnittgeschwindigkeit bzw. Drehzahl und Vorschub wie vorgegeben.",
            "Tool, cutting speed or spindle speed, and feed as prescribed.", [])
