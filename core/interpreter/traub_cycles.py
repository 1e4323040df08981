"""TRAUB TX 8 D turning cycles: roughing, grooving, drilling and threads expanded into ordinary moves.

Every cycle becomes rapid and feed moves of the cycle block (so that the 3D view, the stock and the grader
need nothing special), each carrying `cycle = (code, pass, passes)`; thread moves are feeds with
`thread=True` and the pitch. The geometry follows spec §11–§12 and DECISIONS 20:

- the start point bounds the blank; contour roughing G71 (levels in X) and G72 (levels in Z) cut first at
  start − depth, the stock is spread equally over ceil(stock / D) passes, every pass feeds along its level
  until it meets the contour plus the allowances I (X, radius) and K (Z) and then on along that contour up to
  the level of the pass before (a shoulder, a step between two levels, a rounding), so that only the
  allowance is left for finishing — the manual's tool "turns the shoulder" and lifts from it (L2856); a
  step between two levels left standing would meet the next pass's rapid approach. Infeed, lift and return
  are rapid. G89 skips falling contour sections (a pass stops at their crest), G88 follows them (down each
  falling flank with the reduced feed E);
- G74 (levels in X, depth I, chip breaking every K) and G75 (levels in Z, depth K, chip breaking every I)
  with the lift D (negative: from the second cut on); without X/U (G74) or Z/W (G75) they drill;
- G83: first depth D, then H equal sections of the rest; G84: rapid distance D, first depth I, each further
  depth K, the remainder last; retract to the start and re-approach at rapid to a safety distance;
- G70 as G71 with every cut at the full depth D (what D leaves stays on the allowance, TX-W419); the
  effect of the setting angle J is not in the text (TX-W418);
- G33 a single thread move (pitch F/E modal); G76: X/Z the root at the end, H passes at constant chip
  area (K − D)·√(i/(H−1)), the last at K, infeed along the flank A, taper J; G86 the same for a face
  thread (infeed in Z, the thread along X); G82 tapping in and out with
  the spindle reversed; G78 a single thread pass, G77/G79 chamfer passes, G81 repeats them.

Coordinates here are machine (x radius, z) as the executor keeps them; `core.interpreter.traub_turn`
calls `execute` for a cycle block and passes the contour of P/Q or A through its own block executor.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Protocol

from core.diagnostics import Diagnostic, diag
from core.interpreter.checkpoints import INF as INF_LINE
from core.syntax.blocks import Block, Span, Word
from core.toolpath import Dwell, Move, MoveKind

if TYPE_CHECKING:
    from core.dialects.codes import Code
    from core.interpreter import turn_contour
    from core.interpreter.run import Unit
    from core.interpreter.state import RunSetup

XZ = tuple[float, float]
EPS = 1e-7
CHORD = 0.01  # mm: arcs of a contour become chords straying at most this much
MAX_CHORDS = 90  # … or at most this many chords per arc
WORK = 300_000  # passes × contour points of one roughing cycle: beyond it the cycle is refused (TX-E406)
RUN_WORK = 1_000_000  # the same for all roughing cycles of a run (a program of many cycles): TX-E420


@dataclass(frozen=True, slots=True)
class CycleSetup:
    """The set-up data the cycles read (SET UP-Bild 6); the manual gives no defaults, these are typical."""

    lift: float = 0.5  # #9 lift-off after a pass / a falling section (≤ 0.999 mm)
    back_off: float = 0.5  # #4 back-off for chip breaking (G74, G75)
    # #6 (minimum cut depth of G71/G72) is not a setting: the passes are equal, none is a thin remainder
    safety: float = 0.5  # #7 safety distance of the drilling cycles (≤ 0.999 mm)


@dataclass(slots=True)
class CycleState:
    """What the cycles keep between blocks: the modal thread pitch and the last pass G81 repeats."""

    pitch: float | None = None
    repeatable: tuple[str, XZ, XZ, float, float, float | None] | None = None  # code, start, end, I, K, pitch
    work: int = 0  # contour points × passes of the run's roughing cycles so far (RUN_WORK)
    contours: dict[object, list[tuple[XZ, int]]] = field(
        default_factory=dict
    )  # contours read (no parameters)
    in_contour: bool = False  # a run that only reads a P/Q contour: cycles inside it are not expanded
    setup: CycleSetup = field(default_factory=CycleSetup)


# -- what a cycle sees of the run (core/interpreter/traub_turn.py: TurnRun, Turn, Outcome) ------------------


class Technology(Protocol):
    """The technology and modes active at the cycle block."""

    codes: dict[str, str | None]
    feed: float
    skip_on: bool

    def zero(self) -> XZ: ...
    def spindle_at(self, x: float) -> float: ...
    @property
    def spindle_on(self) -> bool: ...


class BlockResult(Protocol):
    """What one block of a contour did (read by `CycleRun.execute`)."""

    @property
    def items(self) -> Sequence[turn_contour.Item]: ...
    @property
    def diagnostics(self) -> list[Diagnostic]: ...
    @property
    def ended(self) -> bool: ...
    @property
    def sub_end(self) -> bool: ...


class CycleRun(Protocol):
    """The run as a cycle sees it: where the tool is, the technology, the programs (for a contour of P/Q or A),
    and a copy of the run that executes a contour's blocks. Never more."""

    setup: RunSetup
    cycles: CycleState
    position: XZ | None  # machine (x radius, z); None: unknown
    last_known: XZ
    reference: XZ | None
    programs: list[Unit]
    read: list[tuple[int, int]]  # program-file lines lo < line ≤ hi a cycle read (checkpoints)

    @property
    def turn(self) -> Technology: ...
    def ref(self) -> XZ: ...
    def template(self, kind: str, span: Span, exact: bool = False) -> Move: ...
    def contour_reader(self, cycles: CycleState) -> CycleRun: ...
    def execute(self, block: Block) -> BlockResult: ...


class _Out:
    """Collects the moves of one cycle block in the output frame."""

    def __init__(self, run: CycleRun, code: str, span: Span, start: XZ) -> None:
        self.run = run
        self.code = code
        self.span = span
        self.ref = run.ref()  # a cycle may be the first motion of the run
        self.template = run.template("feed", span)
        self.items: list[Move | Dwell] = []
        self.pos = start
        self.passes = 1

    def _v(self, p: XZ) -> tuple[float, float, float]:
        return (p[0] - self.ref[0], 0.0, p[1] - self.ref[1])

    def move(
        self,
        kind: MoveKind,
        to: XZ,
        n: int,
        feed: float | None = None,
        pitch: float | None = None,
        reverse: bool = False,
    ) -> None:
        if abs(to[0] - self.pos[0]) < 1e-9 and abs(to[1] - self.pos[1]) < 1e-9:
            return
        t = self.template
        direction = t.spindle_direction
        if reverse and direction is not None:
            direction = "ccw" if direction == "cw" else "cw"
        # under G96 the speed follows the radius, as for the contour moves (at the end of the move)
        spindle = self.run.turn.spindle_at(to[0]) if t.spindle else 0.0
        self.items.append(
            Move(
                kind,
                self._v(self.pos),
                self._v(to),
                t.feed if feed is None else feed,
                "mm/rev" if pitch is not None else t.feed_unit,
                spindle,
                direction,
                t.coolant,
                t.tool,
                self.span,
                exact_stop=kind == "rapid",
                plane="G18",
                cycle=(self.code, n, self.passes),
                thread=pitch is not None,
                pitch=pitch,
            )
        )
        self.pos = to

    def rapid(self, to: XZ, n: int) -> None:
        self.move("rapid", to, n)

    def feed(self, to: XZ, n: int, feed: float | None = None) -> None:
        self.move("feed", to, n, feed)

    def dwell(self, seconds: float) -> None:
        if seconds > 0:
            self.items.append(Dwell(self._v(self.pos), seconds, self.span))


def _target(run: CycleRun, values: dict[str, float], start: XZ) -> tuple[float | None, float | None]:
    """X/U and Z/W of the block in machine coordinates (X a diameter, U a radius increment)."""
    zx, zz = run.turn.zero()
    x = values["X"] / 2 + zx if "X" in values else start[0] + values["U"] if "U" in values else None
    z = values["Z"] + zz if "Z" in values else start[1] + values["W"] if "W" in values else None
    return x, z


def _equal(total: float, depth: float) -> int:
    """How many equal passes take `total` with at most `depth` each."""
    return max(1, math.ceil(total / depth - 1e-9))


@dataclass(slots=True)
class _Call:
    """One cycle block as the families below see it."""

    run: CycleRun
    block: Block
    code: str
    words: dict[str, Word]
    values: dict[str, float]
    out: _Out
    limit: int  # passes (max_cycle_passes)
    d: list[Diagnostic]
    span: Span  # the cycle's G word


def _thread_motion(c: _Call) -> None:
    _g33(c.run, c.out, c.values, c.words, c.d, c.span)


def _contour_roughing(c: _Call) -> None:
    state = c.run.cycles
    if state.work > RUN_WORK:
        c.d.append(diag("TX-E420", c.span, code=c.code))
        return
    if c.code == "G70" and "J" in c.words:  # the setting angle's effect on the cuts is on the lost page 112
        c.d.append(diag("TX-W418", c.words["J"].span))
    contour = _contour(c.run, c.block, c.code, c.values, c.d, c.span)
    if contour is not None:
        falling = c.run.turn.codes.get("falling") == "G88"
        _rough_contour(c.out, c.code, contour, c.values, c.words, falling, state.setup, c.limit, c.d, c.span)


def _rectangle_roughing(c: _Call) -> None:
    _rough_rect(c.run, c.out, c.code, c.values, c.words, c.run.cycles.setup, c.limit, c.d, c.span)


def _drilling(c: _Call) -> None:
    _drill(c.run, c.out, c.code, c.values, c.words, c.run.cycles.setup, c.limit, c.d, c.span)


def _thread(c: _Call) -> None:
    if c.code != "G82" and c.run.turn.codes.get("runout") == "M35":
        c.d.append(diag("TX-W421", c.span, code=c.code))
    _thread_cycle(c.run, c.out, c.code, c.values, c.words, c.limit, c.d, c.span)


def _single_cut(c: _Call) -> None:
    if c.code == "G78" and c.run.turn.codes.get("runout") == "M35":
        c.d.append(diag("TX-W421", c.span, code=c.code))
    _chamfer(c.run, c.out, c.code, c.values, c.words, c.limit, c.d, c.span)


# the code table's `cycle` column → what executes the family
FAMILIES: dict[str, Callable[[_Call], None]] = {
    "thread_motion": _thread_motion,
    "contour_roughing": _contour_roughing,
    "rectangle_roughing": _rectangle_roughing,
    "drilling": _drilling,
    "thread": _thread,
    "single_cut": _single_cut,
}


def execute(
    run: CycleRun,
    block: Block,
    cycle: Code,
    words: dict[str, Word],
    values: dict[str, float],
    d: list[Diagnostic],
) -> list[Move | Dwell]:
    """The moves and dwells of the cycle `cycle` of `block` (its findings into `d`); the tool ends where the
    cycle leaves it."""
    code = cycle.name
    span = block.span
    state = run.cycles
    if state.in_contour and code != "G33":
        return []  # a cycle inside a contour that a roughing cycle reads: it runs when the program gets there
    start = run.position
    if start is None:
        d.append(diag("TX-E401", span, code=code))
        return []
    o = _Out(run, code, span, start)
    word = next(
        (w for w in block.words if w.address == "G" and w.value is not None and f"G{int(w.value)}" == code),
        None,
    )
    cspan = word.span if word is not None else span
    FAMILIES[cycle.cycle](
        _Call(run, block, code, words, values, o, run.setup.limits.max_cycle_passes, d, cspan)
    )
    run.position = run.last_known = o.pos
    return o.items


# -- the contour of P/Q or A --------------------------------------------------------------------


def _unit_of(run: CycleRun, block: Block) -> Unit | None:
    for u in run.programs:
        if any(b is block for b in u.blocks):
            return u
    return None


def _contour(
    run: CycleRun, block: Block, code: str, values: dict[str, float], d: list[Diagnostic], span: Span
) -> list[tuple[XZ, int]] | None:
    """The finished contour as points (machine x radius, z) with the line of the block that made each, resolved
    by a copy of the run that executes the contour blocks (forward references and subprograms included)."""
    from core.interpreter import turn_contour

    blocks: list[Block]
    if "A" in values:
        number = int(values["A"])
        unit = next((u for u in run.programs if u.number == number), None)
        if unit is None:
            d.append(diag("TX-E301", span, number=number))
            return None
        blocks = unit.blocks
    else:
        unit = _unit_of(run, block)
        if unit is None or "P" not in values or "Q" not in values:
            d.append(diag("TX-E409", span, code=code))
            return None
        first, last = int(values["P"]), int(values["Q"])
        for n in (first, last):
            if n not in unit.numbers:
                d.append(diag("TX-E304", span, number=n, program=unit.name))
                return None
        i, j = unit.numbers[first], unit.numbers[last]
        if j < i:
            d.append(diag("TX-E305", span, start=first, end=last))
            return None
        blocks = unit.blocks[i : j + 1]
    # the same contour read again from the same state gives the same points (a cycle repeated by G22)
    plain = all(w.expr is None for b in blocks for w in b.words) and all(not b.assignments for b in blocks)
    if unit.source is None and blocks:  # the lines it reads (checkpoints: core/interpreter/checkpoints.py)
        run.read.append((unit.line, INF_LINE) if "A" in values else (blocks[0].line - 1, blocks[-1].line))
    key = (
        unit.source,
        blocks[0].line if blocks else 0,
        len(blocks),
        run.position,
        run.reference,
        run.turn.zero(),
    )
    if plain and key in run.cycles.contours:
        return run.cycles.contours[key]
    run.cycles.work += 20 * len(blocks)  # reading a contour block costs about as much as twenty pass points
    # the contour is the programmed one: no nose radius (the finishing pass compensates it)
    scratch = run.contour_reader(CycleState(in_contour=True, setup=run.cycles.setup))
    items: list[turn_contour.Item] = []
    found: list[Diagnostic] = []
    for b in blocks:
        if b.is_empty or (b.skip is not None and not scratch.turn.skip_on):
            continue
        if b is block:
            d.append(diag("TX-E409", span, code=code))
            return None
        res = scratch.execute(b)
        items.extend(res.items)
        found.extend(res.diagnostics)
        if res.sub_end or res.ended:
            break
    moves = [c for c in turn_contour.resolve(items, found) if isinstance(c, Move)]
    errors = [x for x in found if x.severity.value == "error"]
    if errors:
        d.extend(errors)
        d.append(diag("TX-E410", span, code=code, second=errors[0].span.line))
        return None
    k = 0
    while k < len(moves) and moves[k].kind == "rapid":
        k += 1
    if k == len(moves):
        d.append(diag("TX-E409", span, code=code))
        return None
    ref = run.ref()
    first_move = moves[k]
    points: list[tuple[XZ, int]] = [
        ((first_move.start[0] + ref[0], first_move.start[2] + ref[1]), first_move.line)
    ]
    for m in moves[k:]:
        for p in m.points(CHORD, MAX_CHORDS)[1:]:
            points.append(((p[0] + ref[0], p[2] + ref[1]), m.line))
    if plain:
        run.cycles.contours[key] = points
    return points


# -- G71 / G72 contour roughing -------------------------------------------------------------------


def _walls(poly: list[tuple[float, float]]) -> dict[float, float]:
    """The highest boundary value u at each v of the contour's points (a step's top)."""
    walls: dict[float, float] = {}
    for u, v in poly:
        key = round(v, 7)
        walls[key] = max(u, walls.get(key, -math.inf))
    return walls


def _free(
    poly: list[tuple[float, float]], level: float, v_start: float, walls: dict[float, float]
) -> list[tuple[float, float]]:
    """The stretches (v_high, v_low) of v ≤ v_start where the boundary u(v) lies below `level`; `poly` runs with
    v non-increasing, before its first point everything is free, after its last point nothing."""
    spans: list[tuple[float, float]] = [(math.inf, poly[0][1])]
    for (u0, v0), (u1, v1) in itertools.pairwise(poly):
        if v0 - v1 < 1e-12:
            continue
        lo0, lo1 = u0 < level + EPS, u1 < level + EPS
        if lo0 and lo1:
            spans.append((v0, v1))
        elif lo0 or lo1:
            t = (level - u0) / (u1 - u0)
            vc = v0 + (v1 - v0) * t
            spans.append((v0, vc) if lo0 else (vc, v1))
    merged: list[tuple[float, float]] = []
    for hi, lo in spans:
        if merged and abs(merged[-1][1] - hi) < 1e-9:
            wall = walls.get(round(hi, 7), -math.inf)
            if wall < level + EPS:
                merged[-1] = (merged[-1][0], lo)
                continue
        merged.append((hi, lo))
    clipped = [(min(hi, v_start), lo) for hi, lo in merged if lo < v_start - 1e-9]
    return [(hi, lo) for hi, lo in clipped if hi - lo > 1e-9]


def _reach(
    poly: list[tuple[float, float]], level: float, v_start: float, ahead: list[float]
) -> tuple[float, float] | None:
    """G89: the one stretch a pass at `level` cuts from v_start until it meets the contour anywhere (falling and
    undercut sections behind that point stay uncut). `ahead[k]`: the highest v of poly[k:]."""
    end = poly[-1][1]
    for k, ((u0, v0), (u1, v1)) in enumerate(itertools.pairwise(poly)):
        if ahead[k] <= end:  # nothing further on can stop the pass earlier
            break
        if max(u0, u1) <= level + EPS:  # below the level, or on it: the pass runs along
            continue
        if min(u0, u1) > level + EPS:
            end = max(end, v0, v1)
            continue
        t = (level - u0) / (u1 - u0)
        vc = v0 + (v1 - v0) * t
        end = max(end, vc, v0 if u0 > u1 else v1)
    end = min(end, v_start)
    return (v_start, end) if v_start - end > 1e-9 else None


def _u_at(poly: list[tuple[float, float]], v: float) -> list[float]:
    """The boundary values u at v (several at a vertical step)."""
    found = [u for u, pv in poly if abs(pv - v) < 1e-9]
    for (u0, v0), (u1, v1) in itertools.pairwise(poly):
        if v0 - v1 > 1e-12 and v1 < v < v0:
            found.append(u0 + (u1 - u0) * (v - v0) / (v1 - v0))
    return found


def _entry(
    poly: list[tuple[float, float]], level: float, upper: float, v_in: float
) -> list[tuple[float, float]]:
    """The falling flank into a pocket, from the lower of `upper` and the crest before it down to (level, v_in)."""
    k = next(
        (
            i
            for i, ((u0, v0), (u1, v1)) in enumerate(itertools.pairwise(poly))
            if v0 - v1 > 1e-12 and v1 - 1e-9 <= v_in <= v0 + 1e-9 and u1 < u0
        ),
        None,
    )
    if k is None:
        return [(level, v_in)]
    path = [(level, v_in)]
    j = k
    while j >= 0:
        u, v = poly[j]
        pu, pv = path[-1]
        if u >= upper - 1e-9:  # the flank reaches the level of the previous pass: enter there
            t = (upper - pu) / (u - pu) if abs(u - pu) > 1e-12 else 0.0
            path.append((upper, pv + (v - pv) * t))
            break
        if u <= pu + 1e-9:  # at the crest (its flat top was cut by the passes above)
            break
        path.append((u, v))
        j -= 1
    return path[::-1]


def _band(
    poly: list[tuple[float, float]], level: float, upper: float, v_start: float
) -> list[list[tuple[float, float]]]:
    """G88: the runs of one pass between `level` and the previous pass at `upper`. The tool stays at the lower of
    the level and the contour wherever the contour lies below `upper`: along the level where the contour is
    lower, on the contour (up a shoulder, over a step, down a falling flank) where it lies between the two, so
    that no step is left above the allowance; where the contour rises above `upper` a run ends (lift) and the
    next one begins where it comes down through `upper` again. `poly` runs with v non-increasing; before its
    first point everything is free, after its last point nothing."""
    low = min(level, min(u for u, _ in poly)) - 1.0
    ext = [(low, max(v_start, poly[0][1]) + 1.0), (low, poly[0][1]), *poly]
    runs: list[list[tuple[float, float]]] = []
    run: list[tuple[float, float]] = []

    def add(p: tuple[float, float]) -> None:
        if not run or abs(run[-1][0] - p[0]) > 1e-9 or abs(run[-1][1] - p[1]) > 1e-9:
            run.append(p)

    for (u0, v0), (u1, v1) in itertools.pairwise(ext):
        if v1 > v_start + 1e-9:
            continue
        if v0 > v_start + 1e-9:  # clip to the blank's side of the start point
            t = (v0 - v_start) / (v0 - v1)
            u0, v0 = u0 + (u1 - u0) * t, v_start
        cuts = sorted(
            {
                0.0,
                1.0,
                *(
                    (b - u0) / (u1 - u0)
                    for b in (level, upper)
                    if abs(u1 - u0) > 1e-12 and 0 < (b - u0) / (u1 - u0) < 1
                ),
            }
        )
        for t0, t1 in itertools.pairwise(cuts):
            a = (u0 + (u1 - u0) * t0, v0 + (v1 - v0) * t0)
            b = (u0 + (u1 - u0) * t1, v0 + (v1 - v0) * t1)
            mid = (a[0] + b[0]) / 2
            if mid > upper + 1e-9:  # above the previous pass: nothing to cut, the run ends here
                if run:
                    runs.append(run)
                run = []
            elif mid < level:
                add((level, a[1]))
                add((level, b[1]))
            else:
                add(a)
                add(b)
    if run:
        runs.append(run)
    return [_straight(r) for r in runs if len(r) > 1]


def _straight(path: list[tuple[float, float]]) -> list[tuple[float, float]]:
    """`path` without the points inside straight stretches (one move per straight piece)."""
    out = path[:1]
    for k in range(1, len(path)):
        p = path[k]
        if k + 1 < len(path) and len(out) >= 1:
            a, c = out[-1], path[k + 1]
            d1, d2 = (p[0] - a[0], p[1] - a[1]), (c[0] - p[0], c[1] - p[1])
            if abs(d1[0] * d2[1] - d1[1] * d2[0]) < 1e-12 and d1[0] * d2[0] + d1[1] * d2[1] > 0:
                continue
        out.append(p)
    return out


def _climb(
    poly: list[tuple[float, float]], level: float, upper: float, v_end: float
) -> list[tuple[float, float]]:
    """G89: from where a pass meets the contour at (level, v_end), along the rising contour up to the previous
    pass at `upper` (a shoulder, a step, a rising cone); it stops at a crest (the falling section behind it is
    skipped) and at an undercut. The path starts with (level, v_end)."""
    path = [(level, v_end)]
    for k, ((u0, v0), (u1, v1)) in enumerate(itertools.pairwise(poly)):  # noqa: B007 - k is read after the loop
        if u1 < u0 - 1e-12:
            continue
        if abs(v0 - v1) < 1e-12:
            hit = abs(v0 - v_end) < 1e-9 and u0 - 1e-9 <= level <= u1 + 1e-9
        else:
            t = (v_end - v0) / (v1 - v0)
            hit = -1e-9 <= t <= 1 + 1e-9 and abs(u0 + (u1 - u0) * t - level) < 1e-6
        if hit:
            break
    else:
        return path
    for u, v in poly[k + 1 :]:
        pu, pv = path[-1]
        if u < pu - 1e-9 or v > pv + 1e-9:
            break
        if u >= upper - 1e-9:
            t = (upper - pu) / (u - pu) if u - pu > 1e-12 else 0.0
            path.append((upper, pv + (v - pv) * t))
            break
        path.append((u, v))
    return _straight(path)


def _rough_contour(
    o: _Out,
    code: str,
    contour: list[tuple[XZ, int]],
    values: dict[str, float],
    words: dict[str, Word],
    follow: bool,
    setup: CycleSetup,
    limit: int,
    d: list[Diagnostic],
    span: Span,
) -> None:
    depth = values.get("D")
    if depth is None or depth <= 0:
        w = words.get("D")
        d.append(diag("TX-E402", w.span if w else span, code=code, address="D", value=f"{depth or 0:g}"))
        return
    level_axis = 1 if code == "G72" else 0
    o.run.cycles.work += 2 * len(contour)  # reading the contour's points once
    cut_axis = 1 - level_axis
    allow = (values.get("I", 0.0), values.get("K", 0.0))  # x (radius), z
    start = o.pos
    pts = [p for p, _ in contour]
    lu = [p[level_axis] for p in pts]
    lv = [p[cut_axis] for p in pts]
    su = 1.0 if start[level_axis] - min(lu) >= max(lu) - start[level_axis] else -1.0
    sv = 1.0 if start[cut_axis] - min(lv) >= max(lv) - start[cut_axis] else -1.0

    def norm(p: XZ) -> tuple[float, float]:
        return (su * p[level_axis], sv * p[cut_axis])

    def back(u: float, v: float) -> XZ:
        q = [0.0, 0.0]
        q[level_axis], q[cut_axis] = su * u, sv * v
        return (q[0], q[1])

    raw = [(norm(p), line) for p, line in contour]
    if raw[0][0][1] < raw[-1][0][1]:
        raw.reverse()
    for (a, _), (b, line) in itertools.pairwise(raw):
        if (
            follow and b[1] > a[1] + 1e-6
        ):  # G89 passes stop where they meet the contour: undercuts are skipped
            d.append(diag("TX-E404", span, code=code, second=line))
            return
    u_s, v_s = norm(start)
    if raw[-1][0][0] > u_s + 1e-6:
        d.append(diag("TX-W405", span, code=code, second=raw[-1][1]))
    au, av = allow[level_axis], allow[cut_axis]
    poly = [(u + au, v + av) for (u, v), _ in raw]
    entry = [u for u, v in poly[:2] if abs(v - poly[0][1]) < 1e-9] if v_s > poly[0][1] else _u_at(poly, v_s)
    if follow:  # noqa: SIM108 - the two cases read apart
        bottom = min([u for u, v in poly if v <= v_s] + entry)
    else:
        bottom = min(entry) if entry else u_s
    stock = u_s - bottom
    if stock <= 1e-6:
        d.append(diag("TX-W413", span, code=code))
        return
    n = _equal(stock, depth)
    if n > limit or n * len(poly) > WORK:
        d.append(diag("TX-E406", span, code=code, count=n, limit=min(limit, max(1, WORK // len(poly)))))
        return
    if depth > stock + 1e-9:
        d.append(diag("TX-W403", words["D"].span, code=code, depth=f"{depth:g}", stock=round(stock, 3)))
    o.run.cycles.work += n * len(poly)
    walls = _walls(poly)
    ahead = list(itertools.accumulate((v for _, v in reversed(poly)), max))[::-1]
    step = stock / n
    if code == "G70":  # every cut with the full D (L2790): what D does not divide stays on the allowance
        n = max(1, math.floor(stock / depth + 1e-6))
        step = min(depth, stock)
        rest = stock - n * step
        if rest > 1e-3:
            d.append(diag("TX-W419", words["D"].span, depth=f"{depth:g}", rest=round(rest, 3)))
        bottom = u_s - n * step
    lift = min(setup.lift, step)
    reduced = values.get("E")
    o.passes = n
    if code != "G70":  # G70's tools (setting angle J < 90°) cannot turn up a shoulder: its passes stay level
        _follow_passes(o, poly, n, u_s, v_s, step, bottom, lift, reduced, follow, ahead, norm, back)
        return
    for i in range(1, n + 1):
        level = u_s - i * step if i < n else bottom
        upper = level + step
        spans = _free(poly, level, v_s, walls) if follow else []
        main = (
            (spans[0] if spans and spans[0][0] >= v_s - 1e-9 else None)
            if follow
            else _reach(poly, level, v_s, ahead)
        )
        if main is not None:
            o.rapid(back(level, v_s), i)
            o.feed(back(level, main[1]), i)
            o.rapid(back(level + lift, main[1]), i)
        top = level + lift
        for hi, lo in spans[1:] if follow else []:
            path = _entry(poly, level, upper, hi)
            top = u_s + lift
            o.rapid(back(top, sv * o.pos[cut_axis]), i)
            o.rapid(back(top, path[0][1]), i)
            o.rapid(back(path[0][0] + lift, path[0][1]), i)
            o.feed(back(*path[0]), i, reduced)
            for p in path[1:]:
                o.feed(back(*p), i, reduced)
            o.feed(back(level, lo), i)
            o.rapid(back(level + lift, lo), i)
            o.rapid(back(top, lo), i)
        o.rapid(back(top, v_s), i)
    o.rapid(start, n)


def _follow_passes(
    o: _Out,
    poly: list[tuple[float, float]],
    n: int,
    u_s: float,
    v_s: float,
    step: float,
    bottom: float,
    lift: float,
    reduced: float | None,
    falling: bool,
    ahead: list[float],
    norm: Callable[[XZ], tuple[float, float]],
    back: Callable[[float, float], XZ],
) -> None:
    """G71/G72: n passes at equal levels; each runs along its level and then on the contour up to the level of the
    pass before, so that after the last one only the allowance is left (G88: also down the falling flanks)."""
    start = o.pos
    for i in range(1, n + 1):
        level = u_s - i * step if i < n else bottom
        upper = u_s - (i - 1) * step
        if falling:
            runs = _band(poly, level, upper, v_s)
        else:
            main = _reach(poly, level, v_s, ahead)
            if main is not None:
                runs = [[(level, v_s), *_climb(poly, level, upper, main[1])]]
            else:  # the contour rises through the level before the start point: on it from the start on
                on = [u for u in _u_at(poly, v_s) if level - 1e-9 <= u <= upper + 1e-9]
                runs = [_climb(poly, min(on), upper, v_s)] if on else []
            runs = [r for r in runs if len(r) > 1]
        top = u_s + lift  # between runs: above the blank
        for k, path in enumerate(runs):
            first = path[0]
            if k == 0 and abs(first[1] - v_s) < 1e-9:
                o.rapid(back(*first), i)  # the infeed at the start point
            else:
                o.rapid(back(top, norm(o.pos)[1]), i)
                o.rapid(back(top, first[1]), i)
                o.rapid(back(first[0] + lift, first[1]), i)
                o.feed(back(*first), i, reduced)
            for a, b in itertools.pairwise(path):
                o.feed(back(*b), i, reduced if b[0] < a[0] - 1e-9 else None)
            o.rapid(back(path[-1][0] + lift, path[-1][1]), i)
        if len(runs) == 1 and abs(runs[0][0][1] - v_s) < 1e-9:
            top = max(u for u, _ in runs[0]) + lift  # back above what this pass left
        o.rapid(back(top, norm(o.pos)[1]), i)
        o.rapid(back(top, v_s), i)
    o.rapid(start, n)


# -- G74 / G75 roughing, grooving and drilling with chip breaking --------------------------------------


def _cut_line(o: _Out, a: XZ, b: XZ, axis: int, every: float | None, back_off: float, n: int) -> None:
    """Feed from a to b along `axis`, backing off by `back_off` at rapid after every `every` mm (chip breaking)."""
    length = abs(b[axis] - a[axis])
    sign = 1.0 if b[axis] >= a[axis] else -1.0
    if every is None or every <= 0 or every >= length - 1e-9:
        o.feed(b, n)
        return
    done = 0.0
    while done < length - 1e-9:
        done = min(length, done + every)
        p = list(b)
        p[axis] = a[axis] + sign * done
        o.feed((p[0], p[1]), n)
        if done < length - 1e-9:
            q = list(p)
            q[axis] -= sign * back_off
            o.rapid((q[0], q[1]), n)


def _few_pieces(
    run: CycleRun, length: float, every: float | None, passes: int, code: str, d: list[Diagnostic], span: Span
) -> bool:
    """Chip breaking every `every` mm makes pieces; more than the run's move budget is refused before any is made."""
    pieces = passes * (_equal(length, every) if every is not None and every > 0 else 1)
    if 2 * pieces > run.setup.limits.max_moves:
        d.append(diag("TX-E406", span, code=code, count=pieces, limit=run.setup.limits.max_moves // 2))
        return False
    return True


def _rough_rect(
    run: CycleRun,
    o: _Out,
    code: str,
    values: dict[str, float],
    words: dict[str, Word],
    setup: CycleSetup,
    limit: int,
    d: list[Diagnostic],
    span: Span,
) -> None:
    start = o.pos
    x, z = _target(run, values, start)
    # G74: levels in X (depth I), cut along Z (chip breaking K); G75 the other way round
    level_axis, cut_axis = (0, 1) if code == "G74" else (1, 0)
    depth_addr, break_addr = ("I", "K") if code == "G74" else ("K", "I")
    level_end = x if code == "G74" else z
    cut_end = z if code == "G74" else x
    if cut_end is None:
        d.append(diag("PAL-E102", span, address="Z/W" if code == "G74" else "X/U", command=code))
        return
    every = values.get(break_addr)
    if level_end is None:  # drilling: along the cut axis only
        bad = [a for a in ((("X", "U") if code == "G74" else ("Z", "W")) + (depth_addr, "D")) if a in words]
        if bad:
            d.append(diag("TX-E411", words[bad[0]].span, code=code, address=bad[0]))
            return
        if not _few_pieces(run, abs(cut_end - start[cut_axis]), every, 1, code, d, span):
            return
        target = list(start)
        target[cut_axis] = cut_end
        _cut_line(o, start, (target[0], target[1]), cut_axis, every, setup.back_off, 1)
        o.rapid(start, 1)
        return
    depth = values.get(depth_addr)
    total = abs(level_end - start[level_axis])
    if depth is None or depth <= 0:
        w = words.get(depth_addr)
        d.append(
            diag("TX-E402", w.span if w else span, code=code, address=depth_addr, value=f"{depth or 0:g}")
        )
        return
    if total <= 1e-9:
        d.append(diag("TX-W413", span, code=code))
        return
    n = _equal(total, depth)
    if n > limit:
        d.append(diag("TX-E406", span, code=code, count=n, limit=limit))
        return
    if not _few_pieces(run, abs(cut_end - start[cut_axis]), every, n, code, d, span):
        return
    step = total / n
    s = 1.0 if level_end > start[level_axis] else -1.0
    lift = values.get("D", 0.0)
    o.passes = n

    def at(level: float, cut: float) -> XZ:
        q = [0.0, 0.0]
        q[level_axis], q[cut_axis] = level, cut
        return (q[0], q[1])

    for i in range(1, n + 1):
        level = start[level_axis] + s * step * i if i < n else level_end
        o.rapid(at(level, start[cut_axis]), i)
        _cut_line(o, o.pos, at(level, cut_end), cut_axis, every, setup.back_off, i)
        off = abs(lift) if lift > 0 or (lift < 0 and i > 1) else 0.0
        o.rapid(at(level - s * off, cut_end), i)
        o.rapid(at(level - s * off, start[cut_axis]), i)
    o.rapid(start, n)


# -- G83 / G84 deep-hole drilling -----------------------------------------------------------------


def _drill(
    run: CycleRun,
    o: _Out,
    code: str,
    values: dict[str, float],
    words: dict[str, Word],
    setup: CycleSetup,
    limit: int,
    d: list[Diagnostic],
    span: Span,
) -> None:
    start = o.pos
    x, z = _target(run, values, start)
    axis, end = (1, z) if z is not None else (0, x)
    if end is None:
        d.append(diag("PAL-E102", span, address="Z/W", command=code))
        return
    total = abs(end - start[axis])
    s = 1.0 if end >= start[axis] else -1.0

    def at(depth: float) -> XZ:
        q = list(start)
        q[axis] = start[axis] + s * min(depth, total)
        return (q[0], q[1])

    if total <= 1e-9:
        d.append(diag("TX-W413", span, code=code))
        return
    depths: list[float] = []
    rapid_to = 0.0
    if code == "G83":
        first = values.get("D", total)
        if first <= 0:
            d.append(diag("TX-E402", words["D"].span, code=code, address="D", value=f"{first:g}"))
            return
        first = min(first, total)
        h = int(values.get("H", 1)) or 1
        if h > limit:
            d.append(diag("TX-E406", span, code=code, count=h + 1, limit=limit))
            return
        depths = [first] + (
            [first + (total - first) * k / h for k in range(1, h + 1)] if total - first > 1e-9 else []
        )
        safety = setup.safety
    else:
        rapid_to = max(0.0, values.get("D", 0.0))
        given_first, given_further = values.get("I"), values.get("K")
        for a, v in (("I", given_first), ("K", given_further)):
            if v is not None and v <= 0:
                d.append(diag("TX-E402", words[a].span, code=code, address=a, value=f"{v:g}"))
                return
        first = given_first if given_first is not None else max(total - rapid_to, EPS)
        further = given_further if given_further is not None else first
        count = 1 + max(0, math.ceil((total - rapid_to - first) / further - 1e-9))
        if count > limit:
            d.append(diag("TX-E406", span, code=code, count=count, limit=limit))
            return
        depths = [min(total, rapid_to + first)]
        while depths[-1] < total - 1e-9:
            depths.append(min(total, depths[-1] + further))
        safety = values.get("A", setup.safety)
    o.passes = len(depths)
    reached = 0.0
    for i, depth in enumerate(depths, 1):
        if i == 1:
            if rapid_to > 0:
                o.rapid(at(rapid_to), i)
        else:
            o.rapid(at(max(0.0, reached - safety)), i)
        o.feed(at(depth), i)
        reached = depth
        o.dwell(values.get("Q", 0.0) if code == "G84" else 0.0)
        o.rapid(start, i)
        if code == "G84" and i < len(depths):
            o.dwell(values.get("R", 0.0))


# -- threads --------------------------------------------------------------------------------------


def _pitch(
    run: CycleRun, values: dict[str, float], d: list[Diagnostic], span: Span, code: str
) -> float | None:
    state = run.cycles
    p = values.get("F", values.get("E"))
    if p is None:
        p = state.pitch
    if p is None or p <= 0:
        d.append(diag("TX-E407", span, code=code))
        return None
    state.pitch = p
    return p


def _g33(
    run: CycleRun, o: _Out, values: dict[str, float], words: dict[str, Word], d: list[Diagnostic], span: Span
) -> None:
    pitch = _pitch(run, values, d, span, "G33")
    if pitch is None:
        return
    x, z = _target(run, values, o.pos)
    o.passes = 1
    o.move("feed", (o.pos[0] if x is None else x, o.pos[1] if z is None else z), 1, pitch, pitch)


def _thread_cycle(
    run: CycleRun,
    o: _Out,
    code: str,
    values: dict[str, float],
    words: dict[str, Word],
    limit: int,
    d: list[Diagnostic],
    span: Span,
) -> None:
    start = o.pos
    x, z = _target(run, values, start)
    if code == "G82":
        if z is None:
            d.append(diag("PAL-E102", span, address="Z/W", command=code))
            return
        if not run.turn.spindle_on:
            d.append(diag("TX-E417", span))
            return
        pitch = values.get("F", run.turn.feed)
        if pitch <= 0:
            d.append(diag("TX-E407", span, code=code))
            return
        o.move("feed", (start[0], z), 1, pitch, pitch)
        o.move("feed", start, 1, pitch, pitch, reverse=True)
        return
    # G76
    if "I" in words:
        d.append(diag("TX-E412", words["I"].span, code=code, address="I"))
        return
    if x is None or z is None:
        d.append(diag("PAL-E102", span, address="X/U, Z/W", command=code))
        return
    thread_pitch = _pitch(run, values, d, span, code)
    if thread_pitch is None:
        return
    pitch = thread_pitch
    k = values.get("K", 0.0)
    if k <= 0:
        w = words.get("K")
        d.append(diag("TX-E402", w.span if w else span, code=code, address="K", value=f"{k:g}"))
        return
    h = int(values.get("H", 1))
    if h < 1:
        d.append(diag("TX-E402", words["H"].span, code=code, address="H", value=f"{h:g}"))
        return
    if h > limit:
        d.append(diag("TX-E406", span, code=code, count=h, limit=limit))
        return
    j = values.get("J", 0.0)
    if abs(j) > 45:
        d.append(diag("TX-E416", words["J"].span, value=f"{j:g}"))
        return
    last = min(max(values.get("D", 0.0), 0.0), k)
    # G76: infeed in X, the thread along Z; G86 (face thread): infeed in Z, the thread along X
    ia, ta = (0, 1) if code == "G76" else (1, 0)

    def at(a: float, b: float) -> XZ:
        return (a, b) if ia == 0 else (b, a)

    end_a, end_b = (x, z) if ia == 0 else (z, x)
    start_a, start_b = start[ia], start[ta]
    outer = start_a >= end_a
    side = 1.0 if outer else -1.0
    s = 1.0 if end_b <= start_b else -1.0  # +1: the thread runs towards -Z (G86: towards the axis)
    length = abs(end_b - start_b)
    root_start = end_a - math.tan(math.radians(j)) * length * (1.0 if outer else -1.0)
    crest = max(end_a, root_start) + k if outer else min(end_a, root_start) - k
    if (outer and start_a < crest - 1e-9) or (
        not outer and (start_a > crest + 1e-9 or (ia == 0 and crest < -1e-9))
    ):
        d.append(diag("TX-E408", span, code=code, depth=f"{k:g}", diameter=f"{2 * start[0]:g}"))
        return
    depths = [k] if h == 1 else [(k - last) * math.sqrt(i / (h - 1)) for i in range(1, h)] + [k]
    flank = math.tan(math.radians(values.get("A", 0.0)))
    o.passes = h
    for i, depth in enumerate(depths, 1):
        shift = (
            s * depth * flank
        )  # infeed along the flank: the pass starts and ends that much nearer the start
        bs, be = start_b + shift, end_b + shift
        rest = side * (k - depth)
        o.rapid(at(start_a, bs), i)
        o.rapid(at(root_start + rest, bs), i)
        o.move("feed", at(end_a + rest, be), i, pitch, pitch)
        o.rapid(at(start_a, be), i)
        o.rapid(start, i)


# -- G77 / G79 chamfer passes, G78 special-thread pass, G81 repeats ------------------------------------


def _chamfer_pass(
    o: _Out, code: str, start: XZ, end: XZ, i_val: float, k_val: float, pitch: float | None, n: int
) -> None:
    """One pass of G77/G78/G79 from `start` to the target `end` and back to `start`."""
    outer = start[0] >= end[0]
    s = 1.0 if end[1] <= start[1] else -1.0
    side = 1.0 if outer else -1.0
    if code == "G79":  # facing: infeed in Z, face over I in X, then chamfer out over K in Z to the target X
        o.rapid((start[0], end[1]), n)
        if i_val or k_val:
            o.feed((start[0] - side * i_val, end[1]), n)
            o.feed((end[0], end[1] + s * k_val), n)
        else:
            o.feed(end, n)
        o.rapid((end[0], start[1]), n)
        o.rapid(start, n)
        return
    # G77 / G78: infeed in X, along Z to the chamfer start K, chamfer out over I in X to the target Z
    o.rapid((end[0], start[1]), n)
    if k_val or i_val:
        o.move("feed", (end[0], start[1] - s * k_val), n, pitch, pitch)
        o.move("feed", (end[0] + side * i_val, end[1]), n, pitch, pitch)
        o.rapid((start[0], end[1]), n)
    else:
        o.move("feed", end, n, pitch, pitch)
        o.rapid((start[0], end[1]), n)
    o.rapid(start, n)


def _chamfer(
    run: CycleRun,
    o: _Out,
    code: str,
    values: dict[str, float],
    words: dict[str, Word],
    limit: int,
    d: list[Diagnostic],
    span: Span,
) -> None:
    state = run.cycles
    start = o.pos
    if code != "G81":
        x, z = _target(run, values, start)
        if x is None or z is None:
            d.append(diag("PAL-E102", span, address="X/U, Z/W", command=code))
            return
        pitch = _pitch(run, values, d, span, code) if code == "G78" else None
        if code == "G78" and pitch is None:
            return
        i_val, k_val = values.get("I", 0.0), values.get("K", 0.0)
        _chamfer_pass(o, code, start, (x, z), i_val, k_val, pitch, 1)
        state.repeatable = (code, start, (x, z), i_val, k_val, pitch)
        return
    if state.repeatable is None:
        d.append(diag("TX-E414", span))
        return
    h = int(values.get("H", 0))
    if h < 1:
        d.append(
            diag("TX-E402", words["H"].span if "H" in words else span, code=code, address="H", value=f"{h:g}")
        )
        return
    if h > limit:
        d.append(diag("TX-E406", span, code=code, count=h, limit=limit))
        return
    kind, _first, end, i_val, k_val, pitch = state.repeatable
    du, dw = values.get("U", 0.0), values.get("W", 0.0)
    # with G78 the last infeed is split into U/2, U/4, U/8, U/8 (L3419)
    shifts = [float(k) for k in range(1, h + 1)]
    if kind == "G78" and h >= 1:
        shifts = shifts[:-1] + [h - 1 + f for f in (0.5, 0.75, 0.875, 1.0)]
    o.passes = len(shifts)
    for n, f in enumerate(shifts, 1):
        moved = (end[0] + du * f, end[1] + dw * f)
        _chamfer_pass(o, kind, start, moved, i_val, k_val, pitch, n)
