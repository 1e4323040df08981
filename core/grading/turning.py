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
import re
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from core.diagnostics import Diagnostic
from core.exercises import CuttingData, Exercise
from core.grading.causes import file_line
from core.grading.features import Feature
from core.grading.numbers import de as de_num
from core.grading.numbers import en as en_num
from core.grading.numbers import mm, word
from core.grading.technology import direction_fault, in_effect, spindle_set_where, spindle_wanted
from core.interpreter.state import RunSetup
from core.pipeline import run as run_program
from core.sim.turning import DEFAULT_LATHE_TOOLS, RevolvedProfile, TurningResult, simulate_turning
from core.toolpath import Move, Toolpath

# the turning simulation's events that make a program unsafe (SIM-E010, the work limit, is none of them)
LATHE_SAFETY_EVENTS = {"SIM-E001", "SIM-E006", "SIM-E008", "SIM-E011", "SIM-E012", "SIM-E013", "SIM-E014"}
ARC_CHORDS = 256  # chords of one arc where grading looks at its points
NAME_REACH = 3.0  # mm: material left standing names the block whose path passes this near it
Verdict = tuple[bool, str, str, list[int], str]  # passed, German, English, lines, the cause's code
Array = npt.NDArray[np.float64]


@dataclass(frozen=True, slots=True)
class Turned:
    toolpath: Toolpath
    sim: TurningResult


def execute_turning(exercise: Exercise, text: str) -> Turned:
    """`text` run and turned on the exercise's blank with its tools (the grader's view of a lathe exercise)."""
    assert exercise.blank is not None, "a turning exercise has a blank"
    tools = exercise.tool_table() if exercise.tools else DEFAULT_LATHE_TOOLS
    setup = RunSetup(
        tools=tools,
        zero_offsets=tuple(exercise.zero_offsets.items()),
        subprograms=tuple(exercise.subprograms.items()),
    )
    toolpath = run_program(text, exercise.dialect, setup)
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
        window = padded[reach + k : reach + k + n]
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
    over = ring * (
        np.where(over_outer > 0, np.clip(r_out**2 - np.maximum(s_out, r_in) ** 2, 0, None), 0.0)
        + np.where(over_inner > 0, np.clip(np.minimum(s_in, r_out) ** 2 - r_in**2, 0, None), 0.0)
    )
    left = ring * (
        np.where(left_outer > 0, np.clip(s_out**2 - np.maximum(r_out, s_in) ** 2, 0, None), 0.0)
        + np.where(left_inner > 0, np.clip(np.minimum(r_in, s_out) ** 2 - s_in**2, 0, None), 0.0)
    )
    return ProfileDeviation(
        sub, over_outer, left_outer, over_inner, left_inner, float(over.sum()), float(left.sum())
    )


def turned_deviation(exercise: Exercise, program: str) -> ProfileDeviation:
    """The submitted turned part against the reference with the geometry criterion's tolerance (for the lathe's
    3D view: the deviation in colour on the revolved part)."""
    tol = next((c.tolerance for c in exercise.rubric if c.id == "geometry" and c.tolerance is not None), 0.05)
    ref, sub = execute_turning(exercise, exercise.reference), execute_turning(exercise, program)
    return compare_profiles(ref.sim.profile, sub.sim.profile, tol)


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


@dataclass(frozen=True, slots=True)
class Run:
    """A stretch of the reference profile (samples k0 … k1 − 1) of one kind: diameter, taper, radius, the blank's
    own surface (not machined) or no material."""

    kind: str  # diameter, taper, radius, blank, empty
    k0: int
    k1: int


@dataclass(frozen=True, slots=True)
class Face:
    """A face between the runs `before` and `after` (indices into the runs) at the samples' border k."""

    k: int
    before: int
    after: int


JUMP = (
    0.5  # mm: a radius step between two samples larger than this (and than thrice the step before) is a face
)
FLAT = 0.05  # |dr/dz| below this: a diameter
BEND = 0.004  # change of dr/dz from one sample to the next above this: a curve (a radius up to ~25 mm at 0.05 mm)
FILLET = 1.0  # mm: a curved stretch this short next to a face is the nose's fillet of the face


def profile_runs(  # noqa: C901
    r: Array,
    cut: npt.NDArray[np.int64],
    empty: npt.NDArray[np.bool_],
    dz: float,
    blank_r: float,
) -> tuple[list[Run], list[Face]]:
    """The reference's profile (one side: outer or inner radius per sample) cut into runs and faces.

    A face is a step between two samples larger than JUMP that does not continue a steepening curve (the end
    of a quarter circle); the samples between faces are the blank's own surface (never cut), no material, a
    diameter (flat), a taper (constant slope) or a radius (changing slope); stretches of fewer than three
    samples join a neighbour, and a short curve against a face (the fillet a nose radius leaves in the
    corner) joins the stretch on its other side."""
    n = len(r)
    if n == 0:
        return [], []
    step = np.zeros(n)
    step[1:] = np.diff(r)
    faces_at: list[int] = []
    for k in range(1, n):
        if empty[k] or empty[k - 1]:
            if empty[k] != empty[k - 1]:
                faces_at.append(k)
            continue
        before = abs(step[k - 1]) if k > 1 and k - 1 not in faces_at else 0.0
        after = abs(step[k + 1]) if k + 1 < n else 0.0
        if abs(step[k]) > JUMP and abs(step[k]) > 3 * max(before, after):
            faces_at.append(k)
    face_set = set(faces_at)
    slope = np.zeros(n)
    for k in range(n):
        if k + 1 < n and (k + 1) not in face_set and (k == 0 or k in face_set):
            slope[k] = step[k + 1] / dz
        elif k > 0 and k not in face_set:
            slope[k] = step[k] / dz
    kinds: list[str] = []
    for k in range(n):
        if empty[k]:
            kinds.append("empty")
        elif cut[k] <= 0 or abs(r[k] - blank_r) < 1e-3:
            kinds.append("blank")
        else:
            kinds.append("diameter" if abs(slope[k]) < FLAT else "sloped")
    runs: list[list[Any]] = []
    for k in range(n):
        if runs and runs[-1][0] == kinds[k] and k not in face_set:
            runs[-1][2] = k + 1
        else:
            runs.append([kinds[k], k, k + 1])
    # fewer than three samples: join the neighbour on the side without a face (the one before first)
    changed = True
    while changed and len(runs) > 1:
        changed = False
        for i, (kind, k0, k1) in enumerate(runs):
            if k1 - k0 >= 3 or kind in ("empty",):
                continue
            if i > 0 and k0 not in face_set and runs[i - 1][0] != "empty":
                runs[i - 1][2] = k1
            elif i + 1 < len(runs) and k1 not in face_set and runs[i + 1][0] != "empty":
                runs[i + 1][1] = k0
            else:
                continue
            del runs[i]
            changed = True
            break
    out: list[Run] = []
    for kind, k0, k1 in runs:
        out += _fitted(r, dz, k0, k1) if kind == "sloped" else [Run(kind, k0, k1)]
    # a short curve against a face: the fillet a nose radius leaves in the corner, part of its other neighbour
    keep: list[Run] = []
    pending: Run | None = None
    for run in out:
        if pending is not None:
            run = Run(run.kind, pending.k0, run.k1)
            pending = None
        short = (run.k1 - run.k0) * dz < FILLET and run.kind in ("radius", "taper")
        if short and run.k1 in face_set and keep and run.k0 not in face_set and keep[-1].kind != "empty":
            keep[-1] = Run(keep[-1].kind, keep[-1].k0, run.k1)
            continue
        if short and run.k0 in face_set and run.k1 not in face_set:
            pending = run
            continue
        keep.append(run)
    if pending is not None:
        keep.append(pending)
    out = _joined(keep, faces_at)
    faces = []
    for k in faces_at:
        before_i = next((i for i, x in enumerate(out) if x.k0 <= k - 1 < x.k1), None)
        after_i = next((i for i, x in enumerate(out) if x.k0 <= k < x.k1), None)
        if (
            before_i is not None
            and after_i is not None
            and before_i != after_i
            and (out[before_i].kind not in ("blank", "empty") or out[after_i].kind not in ("blank", "empty"))
        ):
            faces.append(Face(k, before_i, after_i))
    return out, faces


LINE_FIT = 0.03  # mm: samples this close to a straight line are a taper
ARC_FIT = 0.05  # mm: samples this close to a circle are a radius


def _fitted(r: Array, dz: float, k0: int, k1: int) -> list[Run]:
    """A sloped stretch as tapers and radii: one taper if a line fits it, one radius if a circle does, else split
    where it leaves the chord between its ends furthest and each part fitted again."""
    z = np.arange(k0, k1, dtype=np.float64) * dz
    v = r[k0:k1]
    if k1 - k0 < 6:
        return [Run("taper" if k1 - k0 < 3 or _line_gap(z, v) <= LINE_FIT else "radius", k0, k1)]
    if _line_gap(z, v) <= LINE_FIT:
        return [Run("taper", k0, k1)]
    if _circle_gap(z, v) <= ARC_FIT:
        return [Run("radius", k0, k1)]
    chord = (v[-1] - v[0]) / (z[-1] - z[0]) if z[-1] != z[0] else 0.0
    far = np.abs(v - (v[0] + chord * (z - z[0])))
    m = k0 + int(np.clip(np.argmax(far), 3, k1 - k0 - 3))
    parts = _fitted(r, dz, k0, m) + _fitted(r, dz, m, k1)
    out: list[Run] = []
    for part in parts:  # neighbours of one kind that one fit covers together
        if out and out[-1].kind == part.kind:
            zz = np.arange(out[-1].k0, part.k1, dtype=np.float64) * dz
            vv = r[out[-1].k0 : part.k1]
            gap = _line_gap(zz, vv) if part.kind == "taper" else _circle_gap(zz, vv)
            if gap <= (LINE_FIT if part.kind == "taper" else ARC_FIT):
                out[-1] = Run(part.kind, out[-1].k0, part.k1)
                continue
        out.append(part)
    return out


def _line_gap(z: Array, v: Array) -> float:
    fit = np.polyfit(z, v, 1)
    return float(np.max(np.abs(np.polyval(fit, z) - v)))


def _circle_gap(z: Array, v: Array) -> float:
    """The largest distance of the points from the circle fitted to them (algebraic least squares)."""
    a = np.stack([z, v, np.ones_like(z)], 1)
    b = z * z + v * v
    try:
        sol, *_ = np.linalg.lstsq(a, b, rcond=None)
    except np.linalg.LinAlgError:
        return math.inf
    cz, cv = sol[0] / 2, sol[1] / 2
    rad2 = sol[2] + cz * cz + cv * cv
    if rad2 <= 0:
        return math.inf
    return float(np.max(np.abs(np.hypot(z - cz, v - cv) - math.sqrt(rad2))))


def _joined(runs: list[Run], faces_at: list[int]) -> list[Run]:
    """Neighbouring runs of one kind without a face between them as one run."""
    out: list[Run] = []
    for run in runs:
        if out and out[-1].kind == run.kind and run.k0 not in faces_at and out[-1].k1 == run.k0:
            out[-1] = Run(run.kind, out[-1].k0, run.k1)
        else:
            out.append(run)
    return out


@dataclass(frozen=True, slots=True)
class TurnedVerdict:
    passed: bool
    features: list[Feature]
    over_volume: float
    left_volume: float


def _d(r: float) -> str:
    return f"Ø{word(2 * r, 1)}"


def _run_names(run: Run, r: Array, zs: Array, inside: bool) -> tuple[str, str]:
    """`Ø40 (Z-2 … Z-30.75)`, `Kegel/Fase Ø36 → Ø40 (Z0 … Z-2)`, `Radius R10 (Z-15.4 … Z-25)` from the samples."""
    dz = float(zs[1] - zs[0]) if len(zs) > 1 else 0.0
    z_hi, z_lo = float(zs[run.k1 - 1]) + dz / 2, float(zs[run.k0]) - dz / 2
    span = f"Z{word(z_hi, 2)} … Z{word(z_lo, 2)}"
    bore, bore_en = ("Bohrung ", "bore ") if inside else ("", "")
    v = r[run.k0 : run.k1]
    z = zs[run.k0 : run.k1]
    if run.kind == "diameter":
        d = _d(float(np.median(v)))
        return f"{bore}{d} ({span})", f"{bore_en}{d} ({span})"
    if run.kind == "taper" and len(v) > 1:
        fit = np.polyfit(z, v, 1)
        a, b = _d(float(np.polyval(fit, z_hi))), _d(float(np.polyval(fit, z_lo)))
        return f"{bore}Kegel/Fase {a} → {b} ({span})", f"{bore_en}taper/chamfer {a} → {b} ({span})"
    if run.kind == "radius":
        radius = _circle_radius(z, v)
        rr = f"R{word(radius, 1)} " if math.isfinite(radius) else ""
        return f"{bore}Radius {rr}({span})", f"{bore_en}radius {rr}({span})"
    return f"{bore}Rohteil ({span})", f"{bore_en}blank ({span})"


def _circle_radius(z: Array, v: Array) -> float:
    if len(z) < 3:
        return math.inf
    a = np.stack([z, v, np.ones_like(z)], 1)
    sol, *_ = np.linalg.lstsq(a, z * z + v * v, rcond=None)
    rad2 = float(sol[2] + (sol[0] / 2) ** 2 + (sol[1] / 2) ** 2)
    return math.sqrt(rad2) if rad2 > 0 else math.inf


def _face_names(face: Face, runs: list[Run], r: Array, zs: Array, inside: bool) -> tuple[str, str]:
    z = float(zs[face.k]) - 0.5 * (zs[1] - zs[0]) if len(zs) > 1 else float(zs[face.k])
    a, b = float(r[face.k - 1]), float(r[face.k])
    lo, hi = min(a, b), max(a, b)
    empty = runs[face.after].kind == "empty" or runs[face.before].kind == "empty"
    if empty:
        return f"Stirnfläche Z{word(z, 2)}", f"face Z{word(z, 2)}"
    what, what_en = ("Bohrungsabsatz", "bore shoulder") if inside else ("Planfläche", "shoulder")
    return (f"{what} Z{word(z, 2)} ({_d(lo)} → {_d(hi)})", f"{what_en} Z{word(z, 2)} ({_d(lo)} → {_d(hi)})")


def _blocks(bad: npt.NDArray[np.bool_], k0: int, k1: int) -> list[tuple[int, int]]:
    """The stretches of consecutive bad samples in k0 … k1 − 1."""
    out: list[tuple[int, int]] = []
    k = k0
    while k < k1:
        if bad[k]:
            j = k
            while j < k1 and bad[j]:
                j += 1
            out.append((k, j))
            k = j
        else:
            k += 1
    return out


def turned_geometry(
    ref: Turned, sub: Turned, tol: float, name_line: Callable[[float, float], int | None] | None = None
) -> TurnedVerdict:
    """The turned part feature by feature: each diameter, taper, radius and face (shoulder, the front) of the
    reference, outside and in the bore. A sample off the band belongs to the stretch it lies in; a stretch is lost
    when half of it or more is off, or when what is off lies in its middle; a deviation that only reaches in from
    one of its ends, where a face is, moves that face (the shoulder at another Z): the face is lost instead. A
    deviation on the blank's own surface is the face's next to it, or the nearest machined stretch's.
    `name_line(z, r)` names the submission's block that should have cut material left standing at a place."""
    rp, sp = ref.sim.profile, sub.sim.profile
    dev = compare_profiles(rp, sp, tol)
    # a ring of the band's width on two samples at the blank's surface: the band's edge, not a fault
    allowance = 2 * 2 * math.pi * (ref.sim.blank.diameter / 2) * tol * rp.dz
    gouge, left = dev.over_volume > allowance, dev.left_volume > allowance
    blank = ref.sim.blank
    zs = rp.zs
    features: list[Feature] = []
    for inside in (False, True):
        r_ref = np.clip(rp.inner if inside else rp.outer, 0, None)
        r_sub = np.clip(sp.inner if inside else sp.outer, 0, None)
        cut = rp.cut_inner if inside else rp.cut_outer
        empty = np.clip(rp.outer, 0, None) <= np.clip(rp.inner, 0, None) + 1e-6
        blank_r = blank.bore / 2 if inside else blank.diameter / 2
        if inside and not bool(((cut > 0) & ~empty).any()):
            continue  # no bore machined
        runs, faces = profile_runs(r_ref, cut, empty, rp.dz, blank_r)
        over = dev.over_inner if inside else dev.over_outer
        lft = dev.left_inner if inside else dev.left_outer
        bad = ((over > 0) | (lft > 0)) if (gouge or left) else np.zeros(len(r_ref), dtype=bool)
        face_lost: dict[int, list[tuple[int, int]]] = {}
        run_lost: dict[int, list[tuple[int, int]]] = {}
        face_of = {f.k: i for i, f in enumerate(faces)}
        slack = 1 + max(1, math.ceil(tol / rp.dz - 1e-9))  # a block this near a stretch's end touches it
        for ri, run in enumerate(runs):
            blocks = _blocks(bad, run.k0, run.k1)
            if not blocks or sum(b - a for a, b in blocks) < 3:
                continue
            length = run.k1 - run.k0
            for a, b in blocks:
                if b - a < 3 and len(blocks) > 1:
                    continue
                target: int | None = ri if run.kind not in ("blank", "empty") else _nearest_machined(runs, ri)
                if (b - a) * 2 < length or run.kind in ("blank", "empty"):
                    start, end = a - run.k0 <= slack, run.k1 - b <= slack
                    if start and run.k0 in face_of:
                        face_lost.setdefault(face_of[run.k0], []).append((a, b))
                        continue
                    if end and run.k1 in face_of:
                        face_lost.setdefault(face_of[run.k1], []).append((a, b))
                        continue
                    # a deviation reaching in from the neighbour's side (no face between): the neighbour's
                    near = ri - 1 if start and not end else ri + 1 if end and not start else None
                    if (
                        near is not None
                        and 0 <= near < len(runs)
                        and runs[near].kind not in ("blank", "empty")
                        and _blocks(bad, runs[near].k0, runs[near].k1)
                    ):
                        target = near
                if target is not None:
                    run_lost.setdefault(target, []).append((a, b))
        for ri, run in enumerate(runs):
            if run.kind in ("blank", "empty"):
                continue
            name, name_en = _run_names(run, r_ref, zs, inside)
            features.append(
                _lathe_feature(
                    run.kind,
                    name,
                    name_en,
                    run_lost.get(ri),
                    r_ref,
                    r_sub,
                    over,
                    zs,
                    sub,
                    inside,
                    None,
                    name_line,
                )
            )
        for fi, face in enumerate(faces):
            name, name_en = _face_names(face, runs, r_ref, zs, inside)
            features.append(
                _lathe_feature(
                    "face",
                    name,
                    name_en,
                    face_lost.get(fi),
                    r_ref,
                    r_sub,
                    over,
                    zs,
                    sub,
                    inside,
                    face,
                    name_line,
                )
            )
    passed = not gouge and not left
    if not passed and all(f.ok for f in features) and features:
        # off the band beyond the allowance but nowhere enough for one feature: the largest stretch is lost
        features = _worst_lost(features, dev, rp, sp, zs, sub, name_line)
    return TurnedVerdict(
        passed, features, dev.over_volume if gouge else 0.0, dev.left_volume if left else 0.0
    )


def _nearest_machined(runs: list[Run], ri: int) -> int | None:
    best: tuple[int, int] | None = None
    for i, run in enumerate(runs):
        if run.kind in ("blank", "empty"):
            continue
        gap = abs(i - ri)
        if best is None or gap < best[0]:
            best = (gap, i)
    return best[1] if best else None


def _lathe_feature(
    kind: str,
    name: str,
    name_en: str,
    blocks: list[tuple[int, int]] | None,
    r_ref: Array,
    r_sub: Array,
    over: Array,
    zs: Array,
    sub: Turned,
    inside: bool,
    face: Face | None = None,
    name_line: Callable[[float, float], int | None] | None = None,
) -> Feature:
    if not blocks:
        return Feature(kind, name, name_en)
    ks = np.concatenate([np.arange(a, b) for a, b in blocks])
    dz = float(zs[1] - zs[0]) if len(zs) > 1 else 1.0
    inner = ks[(ks - ks.min() >= FILLET / dz) & (ks.max() - ks >= FILLET / dz)] if face is None else ks
    if len(inner):
        ks = inner  # the stretch's middle, away from the corners' fillets
    diff = np.abs(r_sub[ks] - r_ref[ks])
    k = int(ks[int(np.argmax(diff))])
    too_much = bool(over[k] > 0)
    z = float(zs[k])
    line = _line_for(sub, k, z, float(r_sub[k]), too_much, inside)
    if not too_much and name_line is not None:
        line = name_line(z, float(r_ref[k])) or line
    if face is not None:
        z_face = float(zs[face.k]) - dz / 2
        found = _face_in(r_sub, r_ref, face.k, blocks)
        if found is None:
            detail, detail_en, extent = "fehlt", "is missing", 0.0
        else:
            moved = float(zs[found]) - dz / 2
            extent = abs(moved - z_face)
            detail = f"liegt bei Z{word(moved, 2)} statt Z{word(z_face, 2)} ({mm(extent)} verschoben)"
            detail_en = f"lies at Z{word(moved, 2)} instead of Z{word(z_face, 2)} (moved {mm(extent, 'en')})"
        return Feature(kind, name, name_en, False, extent, False, too_much, "", line, detail, detail_en)
    have, want = float(r_sub[k]), float(r_ref[k])
    detail = (
        f"{_d(have)} statt {_d(want)} ({mm(abs(have - want))} {'zu viel' if too_much else 'zu wenig'} "
        f"abgetragen)"
    )
    detail_en = (
        f"{_d(have)} instead of {_d(want)} ({mm(abs(have - want), 'en')} too "
        f"{'much' if too_much else 'little'} removed)"
    )
    return Feature(
        kind,
        name,
        name_en,
        False,
        abs(have - want),
        False,
        too_much,
        f"Z{word(z, 2)}",
        line,
        detail,
        detail_en,
    )


def _face_in(r_sub: Array, r_ref: Array, k: int, blocks: list[tuple[int, int]]) -> int | None:
    """Where the submitted part has the face the reference has at sample border `k`: the border nearest to it,
    around the deviating samples, across which the submitted radius steps over the face's middle the same way."""
    mid = (float(r_ref[k - 1]) + float(r_ref[k])) / 2
    up = float(r_ref[k]) > mid
    lo = max(1, min(a for a, _ in blocks) - 3)
    hi = min(len(r_sub) - 1, max(b for _, b in blocks) + 3)
    best: int | None = None
    for j in range(lo, hi + 1):
        crosses = (float(r_sub[j - 1]) > mid) != up and (float(r_sub[j]) > mid) == up
        if crosses and (best is None or abs(j - k) < abs(best - k)):
            best = j
    return best


def _line_for(sub: Turned, k: int, z: float, r: float, over: bool, inside: bool) -> int | None:
    """Over-cut: the block whose cut left the surface there (the simulation's record, else the nearest path);
    material left: the feed that should have cut it."""
    cutter = int((sub.sim.profile.cut_inner if inside else sub.sim.profile.cut_outer)[k])
    if over:
        return cutter if cutter > 0 else line_near(sub.toolpath, z, r, math.inf, True)
    return line_near(sub.toolpath, z, r, NAME_REACH, False)


def _worst_lost(
    features: list[Feature],
    dev: ProfileDeviation,
    rp: RevolvedProfile,
    sp: RevolvedProfile,
    zs: Array,
    sub: Turned,
    name_line: Callable[[float, float], int | None] | None = None,
) -> list[Feature]:
    """When the deviation is spread too thin for any one feature, the feature at its largest point is lost."""
    amount = np.maximum.reduce([dev.over_outer, dev.left_outer, dev.over_inner, dev.left_inner])
    k = int(np.argmax(amount))
    z = float(zs[k])
    best = min(range(len(features)), key=lambda i: _feature_gap(features[i].name, z))
    f = features[best]
    inside = float(max(dev.over_inner[k], dev.left_inner[k])) > float(
        max(dev.over_outer[k], dev.left_outer[k])
    )
    have = float((sp.inner if inside else sp.outer)[k])
    want = float((rp.inner if inside else rp.outer)[k])
    too_much = float((dev.over_inner if inside else dev.over_outer)[k]) > 0
    line = _line_for(sub, k, z, have, too_much, inside)
    if not too_much and name_line is not None:
        line = name_line(z, want) or line
    detail = f"{_d(have)} statt {_d(want)}"
    detail_en = f"{_d(have)} instead of {_d(want)}"
    lost = Feature(
        f.kind,
        f.name,
        f.name_en,
        False,
        abs(have - want),
        False,
        too_much,
        f"Z{word(z, 2)}",
        line,
        detail,
        detail_en,
    )
    return features[:best] + [lost] + features[best + 1 :]


def _feature_gap(name: str, z: float) -> float:
    """How far `z` lies from the Z range written in a feature's name."""
    found = [float(x) for x in re.findall(r"Z(-?\d+(?:\.\d+)?)", name)]
    if not found:
        return math.inf
    lo, hi = min(found), max(found)
    return 0.0 if lo <= z <= hi else min(abs(z - lo), abs(z - hi))


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
    return (
        min(p[2] for p in pts) < margin
        and max(p[2] for p in pts) > -ex.blank.length - margin
        and min(abs(p[0]) for p in pts) < ex.blank.diameter / 2 + margin
    )


def _speed_ok(m: Move, d: CuttingData, tol: float, top: float) -> bool:
    if d.speed is not None:
        return abs(m.spindle - d.speed) <= tol * d.speed
    assert d.cutting_speed is not None
    r = abs((m.programmed_end if m.programmed_end is not None else m.end)[0])
    v = 2 * math.pi * r * m.spindle / 1000  # m/min at the move's end, where its speed was taken
    clamped = v < d.cutting_speed and m.spindle >= top * (1 - 1e-6)  # G92 or the machine's top near the axis
    return clamped or abs(v - d.cutting_speed) <= tol * d.cutting_speed


def _fail(m: Move, code: str, de: str, en: str, more: list[int] | None = None) -> Verdict:
    line = file_line(m)
    return False, f"Zeile {line}: {de}", f"Line {line}: {en}", [line] + (more or []), code


def turning_technology(
    ex: Exercise, moves: list[Move], tol: float, program: str = "", reference: Toolpath | None = None
) -> Verdict:
    """Tool, spindle direction, V or S, and F per revolution (G95) of the feed moves that can cut, against the
    cutting data. A tool may have several entries (roughing and finishing feeds): a move passes when it matches
    one. A thread move's F is its pitch: only its speed is checked. A wrong value is named with the word in
    effect and where it was set (`E0.12 aus Zeile 5`)."""
    if not ex.cutting_data:
        return True, "Keine Schnittdaten vorgegeben.", "No cutting data prescribed.", [], ""
    top = {t: max(m.spindle for m in moves if m.tool == t) for t in {m.tool for m in moves}}
    direction = (
        spindle_wanted(ex, reference)
        if reference is not None
        else {d.tool: d.spindle for d in ex.cutting_data if d.spindle is not None}
    )
    first_of_cycle: dict[tuple[int, str], Move] = {}
    for m in moves:
        if m.cycle is not None:
            first_of_cycle.setdefault((m.line, m.cycle[0]), m)
    for m in moves:
        line = file_line(m)
        if m.tool is None:
            return _fail(m, "no_tool", "kein Werkzeug eingewechselt.", "no tool loaded.")
        data = [d for d in ex.cutting_data if d.tool == m.tool]
        if not data:
            return _fail(
                m,
                "tool",
                f"Werkzeug T{m.tool} ist in der Aufgabe nicht vorgesehen.",
                f"tool T{m.tool} is not the one the task prescribes.",
            )
        # a cycle's moves after its first may turn the spindle back (G82 taps out reversed)
        fault = (
            None
            if m.cycle is not None and m is not first_of_cycle.get((m.line, m.cycle[0]), m)
            else direction_fault(m, direction.get(m.tool), program, line)
        )
        if fault is not None:
            where = spindle_set_where(program, line)
            return _fail(m, "spindle_direction", fault[0], fault[1], [where] if where else [])
        if not m.thread and m.feed_unit != "mm/rev":
            have, have_en, at = in_effect(program, line, m.feed, "FE")
            de = f"{have} in mm/min (G94) statt F{word(data[0].feed)} mm pro Umdrehung (G95) für T{m.tool}."
            en = f"{have_en} in mm/min (G94) instead of F{word(data[0].feed)} mm per revolution (G95) for T{m.tool}."
            return _fail(m, "feed_unit", de, en, [at] if at else [])
        if not any(_speed_ok(m, d, tol, top[m.tool]) for d in data):
            d = data[0]
            if d.speed is not None:
                have, have_en, at = in_effect(program, line, m.spindle, "S")
                return _fail(
                    m,
                    "speed",
                    f"{have} statt S{word(d.speed)} für T{m.tool}.",
                    f"{have_en} instead of S{word(d.speed)} for T{m.tool}.",
                    [at] if at else [],
                )
            r = abs((m.programmed_end if m.programmed_end is not None else m.end)[0])
            v = 2 * math.pi * r * m.spindle / 1000
            assert d.cutting_speed is not None
            return _fail(
                m,
                "cutting_speed",
                f"Schnittgeschwindigkeit {de_num(v, 0)} m/min statt V{word(d.cutting_speed)} für T{m.tool}.",
                f"cutting speed {en_num(v, 0)} m/min instead of V{word(d.cutting_speed)} for T{m.tool}.",
            )
        if m.thread:
            continue
        feeds = [d.feed for d in data if _speed_ok(m, d, tol, top[m.tool])]
        if not any(abs(m.feed - f) <= tol * f for f in feeds):
            want = " oder ".join(f"F{word(f)}" for f in feeds)
            want_en = " or ".join(f"F{word(f)}" for f in feeds)
            have, have_en, at = in_effect(program, line, m.feed, "FE")
            more = [at] if at else []
            if have.startswith("F"):
                return _fail(
                    m,
                    "feed",
                    f"{have} statt {want} mm pro Umdrehung für T{m.tool}.",
                    f"{have_en} instead of {want_en} mm per revolution for T{m.tool}.",
                    more,
                )
            return _fail(
                m,
                "feed",
                f"Vorschub {de_num(m.feed, 3)} mm/U statt {want} für T{m.tool} – hier gilt {have}.",
                f"feed {en_num(m.feed, 3)} mm/rev instead of {want_en} for T{m.tool} – {have_en} is in "
                f"effect here.",
                more,
            )
    return (
        True,
        "Werkzeug, Drehrichtung, Schnittgeschwindigkeit bzw. Drehzahl und Vorschub wie vorgegeben.",
        "Tool, spindle direction, cutting speed or spindle speed, and feed as prescribed.",
        [],
        "",
    )
