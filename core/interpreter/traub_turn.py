"""TRAUB TX 8 D turning: the run of a program, block by block, (state, block) → planned items and diagnostics.

The sibling of `core.interpreter.pal_mill` for the lathe. A block is a transaction: check every word
→ if anything is wrong the block is not executed and the state stays as it was → otherwise commit
L-parameter assignments, technology (F, E, S, V, T, G92, G94–G97), modal codes, M functions, the zero
point, then the motion, dwell, tool-change-point move or program flow (G22, macros G201–G299, M99).

Motion blocks become `TurnItem`s carrying the programmed geometry and the raw contour-train words;
`core.interpreter.turn_contour.resolve` (contour trains, transition elements, SRK) turns them into
moves once the whole run is planned — the only call site is `run_program`.

Frames (DECISIONS §15): X is a diameter, U a radius increment. Internally the run keeps positions in
machine coordinates (x = radius from the spindle axis, z = machine Z including the zero point); after
`resolve` every output is moved into the workpiece frame, the zero point active at the first motion
(normally the G59 of the program head).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

from core.diagnostics import Diagnostic, Severity, diag
from core.dialects.codes import Code, Support
from core.dialects.traub_tx8d import TABLE
from core.interpreter import traub_cycles, turn_contour
from core.interpreter.checkpoints import LineMap, Unmappable
from core.interpreter.loop import FlowCodes, Machine, Step
from core.interpreter.params import evaluate as evaluate_expression
from core.interpreter.run import Unit, finish_toolpath, split_programs
from core.interpreter.state import ModalState, RunSetup, switch_on_state
from core.interpreter.turn_contour import XZ, Nose, SrkSwitch, TransitionSpec, TurnItem
from core.interpreter.words import group_conflicts, missing_words, negative_values
from core.syntax.blocks import Block, Expr, ParamRef, Program, Span, Word
from core.toolpath import Dwell, Move, ToolChange, Toolpath, Vec3
from core.tools import ToolTable

Item = turn_contour.Item

MAX_SPINDLE = 6000.0  # 1/min: the machine's highest speed when no G92 limits it (SET UP-Bild 5 #5)
_GEOMETRY = frozenset({"X", "U", "Z", "W", "A", "R", "P", "Q", "I", "K", "D", "C", "H"})
_AXES = frozenset({"X", "U", "Z", "W"})
# (the sets the block's names are tested against, made once: a set written in the test is made at every block)
_STOPS = frozenset({"M0", "M1", "M30"})
_DRIVEN_ON = frozenset({"M21", "M22"})
_DRIVEN_DIRECTION = frozenset({"M23", "M24"})
_ZERO_POINTS = frozenset({"G54", "G55", "G56", "G57"})


# -- the state of a run --------------------------------------------------------------------


@dataclass(slots=True)
class Turn:
    """What is active besides the modal codes: technology, tool, zero point, L parameters."""

    codes: dict[str, str | None]
    feed: float = 0.0
    transition_feed: float | None = None  # E
    speed: float = 0.0  # S of G97 (1/min)
    cutting_speed: float = 0.0  # V of G96 (m/min)
    limit: float | None = None  # G92 S
    tool: int | None = None  # turret station
    offset: int = 0
    tool_called: bool = False  # a T word since the start or the last G24–G28/G53
    deselected_by: str | None = None  # G24–G28/G53 that deselected the tool data
    first_after_t: bool = False  # the next motion is the first after a T word
    driven_on: bool = False  # M21/M22
    driven_direction: bool = False  # M23/M24
    zero_base: tuple[float, float] = (0.0, 0.0)  # G54–G57: X diameter, Z (machine)
    zero_shift: tuple[float, float] = (0.0, 0.0)  # G59: X diameter, Z
    skip_on: bool = False  # "/" blocks are executed

    def zero(self) -> XZ:
        """The workpiece zero in machine coordinates (x radius, z)."""
        return ((self.zero_base[0] + self.zero_shift[0]) / 2, self.zero_base[1] + self.zero_shift[1])

    def spindle_at(self, x: float) -> float:
        """The speed (1/min) at radius x: G96 V at that diameter, clamped by G92; else S."""
        if not self.spindle_on:
            return 0.0
        if self.codes.get("spindle_mode") != "G96":
            return self.speed
        return _rpm(self.cutting_speed, self.limit, x)

    @property
    def spindle_on(self) -> bool:
        return self.codes.get("spindle") in ("M3", "M4")


# -- L parameters ---------------------------------------------------------------------------


def _l_valid(n: int) -> bool:
    return 1 <= n <= 48 or 101 <= n <= 148


def evaluate(
    expr: Expr, params: dict[int, float], line: int, d: list[Diagnostic], reads: set[int] | None = None
) -> float | None:
    """The value of an L-parameter expression, or None after an error (DECISIONS §21); `reads` collects
    the numbers of the parameters it reads. The arithmetic is PAL's (core/interpreter/params.py)."""

    def resolve(ref: ParamRef, span: Span) -> float | None:
        if not _l_valid(ref.number):
            d.append(diag("TX-E110", span, number=ref.number))
            return None
        if reads is not None:
            reads.add(ref.number)
        if ref.number not in params:
            d.append(diag("TX-W101", span, number=ref.number))
            return 0.0
        return params[ref.number]

    return evaluate_expression(expr, params, line, d, resolve)


# -- one block --------------------------------------------------------------------------------


@dataclass(slots=True)
class Outcome:
    """What one block did."""

    items: list[Item] = field(default_factory=list)
    diagnostics: list[Diagnostic] = field(default_factory=list)
    ended: bool = False  # M30
    sub_end: bool = False  # M99
    call: tuple[int | None, int | None, int | None, int] | None = None  # G22/macro: program, P, Q, H


@dataclass(slots=True)
class _Reading:
    gs: list[tuple[Word, Code]]
    ms: list[tuple[Word, Code]]
    words: dict[str, Word]
    values: dict[str, float]
    owner: Code | None
    owner_word: Word | None
    g_names: frozenset[str] = frozenset()
    m_names: frozenset[str] = frozenset()
    speed_code: Code | None = None  # G92, G96 or G97 (codes.Code.speed)
    cacheable: bool = True  # no parameter expression: the same block always reads the same


def _read(
    block: Block,
    params: dict[int, float],
    d: list[Diagnostic],
    reads: set[int] | None = None,
    limit: float = 1e9,
    modal_motion: str = "G1",
) -> _Reading:
    """Sort and check the words of `block`: codes, addresses, values, what the block may hold."""
    gs, ms, words, values, cacheable = _sort(block, params, d, reads, limit)
    owner, owner_word = _owner(gs, ms, d)
    speed_code = _check_words(gs, ms, words, values, owner, owner_word, modal_motion, d)
    return _Reading(
        gs,
        ms,
        words,
        values,
        owner,
        owner_word,
        _names(gs),
        _names(ms),
        speed_code,
        cacheable,
    )


_NO_NAMES: frozenset[str] = frozenset()
_NUMBERED = {a: TABLE.numbered.get(a, {}) for a in ("G", "M")}
# a plain block (`_plain_read`): its G code by number, a motion that owns the block (no cycle, no speed code),
# with its names; its addresses with their rules (a whole number, not negative)
_PLAIN_MOTIONS = {
    number: (code, frozenset((code.name,)))
    for number, code in _NUMBERED["G"].items()
    if code.group == "motion"
    and code.owns_block
    and not code.alone
    and code.support is Support.YES
    and not code.cycle
    and not code.speed
}
_PLAIN_RULES = {
    a: (spec.integer, a in TABLE.non_negative)
    for a, spec in TABLE.addresses.items()
    if a not in ("G", "M", "O", "T")  # (codes, a program number, a tool call: the general path)
}


def _plain_read(block: Block, limit: float, modal_motion: str) -> _Reading | None:
    """The reading of the most common block, a move (a G0-G3 written or modal) of address words with numbers
    that breaks no rule, as `_read` makes it; None for every other block, which `_read` reads. Most blocks are
    such moves, and they need none of the general path's cases: their words are sorted and checked in one
    pass. tests/test_plain_reading.py checks both paths agree."""
    written: tuple[Word, Code, frozenset[str]] | None = None
    words: dict[str, Word] = {}
    values: dict[str, float] = {}
    for w in block.words:
        a, v = w.address, w.value
        if v is None or w.expr is not None:
            return None
        if a == "G":
            motion = _PLAIN_MOTIONS.get(v)
            if motion is None or written is not None:  # (another G code, or a second G word)
                return None
            written = (w, *motion)
            continue
        rule = _PLAIN_RULES.get(a)
        if rule is None or a in words:  # (an M word, an unknown address, an address given twice)
            return None
        if not math.isfinite(v) or abs(v) > limit or (rule[0] and v != int(v)) or (rule[1] and v < 0):
            return None  # (out of range, not a whole number, negative: the general path says so)
        words[a] = w
        values[a] = v
    if written is None:
        if not words.keys() <= TABLE.always_allowed and not words.keys() <= TABLE.takes[modal_motion]:
            return None  # a word the modal motion does not take (PAL-E101)
        return _Reading([], [], words, values, None, None)
    owner_word, owner, names = written
    if not words.keys() <= TABLE.takes[owner.name]:
        return None
    for one_of in owner.required:
        if not any(a in words for a in one_of):  # a required address missing (PAL-E102)
            return None
    return _Reading([(owner_word, owner)], [], words, values, owner, owner_word, names)


def _names(codes: list[tuple[Word, Code]]) -> frozenset[str]:
    return frozenset([c.name for _, c in codes]) if codes else _NO_NAMES


def _sort(
    block: Block, params: dict[int, float], d: list[Diagnostic], reads: set[int] | None, limit: float
) -> tuple[list[tuple[Word, Code]], list[tuple[Word, Code]], dict[str, Word], dict[str, float], bool]:
    """The G and M codes of the block, its address words and their values (each checked on its own), and
    whether it has no parameter expression."""
    cacheable = True
    gs: list[tuple[Word, Code]] = []
    ms: list[tuple[Word, Code]] = []
    words: dict[str, Word] = {}
    values: dict[str, float] = {}
    for w in block.words:
        a = w.address
        if a in ("G", "M"):
            code = (
                _NUMBERED[a].get(w.value) if w.value is not None and w.expr is None else None
            )  # (one lookup)
            if code is not None:
                (gs if a == "G" else ms).append((w, code))
                continue
            if w.value is None or w.value != int(w.value) or not 0 <= w.value <= 9999:
                d.append(diag("PAL-E108", w.span, address=a, raw=w.raw))
                continue
            name = f"{a}{int(w.value)}"
            code = TABLE.codes.get(name)
            if code is None:
                if a == "G":
                    d.append(diag("PAL-E105", w.span, code=name))
                else:
                    d.append(diag("PAL-W103", w.span, code=int(w.value)))
                continue
            (gs if a == "G" else ms).append((w, code))
            continue
        spec = TABLE.addresses.get(a)
        if spec is None or a == "O":
            d.append(diag("PAL-E003", w.address_span, address=a))
            continue
        if a in words:
            d.append(diag("PAL-E106", w.span, address=a))
            continue
        words[a] = w
        if w.expr is not None:
            cacheable = False
            v = evaluate(w.expr, params, w.line, d, reads)
            if v is None:
                continue
        else:
            assert w.value is not None
            v = w.value
        if not math.isfinite(v) or abs(v) > limit:
            d.append(diag("PAL-E015", w.span, value=f"{v:.6g}", address=a, limit=f"{limit:g}"))
            continue
        if spec.integer and v != int(v):
            d.append(diag("PAL-E108", w.span, address=a, raw=w.raw))
            continue
        values[a] = v
    return gs, ms, words, values, cacheable


def _owner(
    gs: list[tuple[Word, Code]], ms: list[tuple[Word, Code]], d: list[Diagnostic]
) -> tuple[Code | None, Word | None]:
    """One member of each modal group, and the code that owns the block (its address words)."""
    if len(ms) > 3:
        d.append(diag("TX-E104", ms[3][0].span, count=len(ms)))
    group_conflicts(TABLE, gs + ms, d)
    owner: Code | None = None
    owner_word: Word | None = None
    for w, code in gs:
        if code.owns_block:
            if owner is not None and not (owner.group == "motion" and code.group == "motion"):
                d.append(
                    diag(
                        "PAL-E103",
                        w.span,
                        first=str(owner_word),
                        second=str(w),
                        group="Satzfunktion",
                        group_en="block function",
                    )
                )
            owner, owner_word = code, w
    return owner, owner_word


def _check_words(
    gs: list[tuple[Word, Code]],
    ms: list[tuple[Word, Code]],
    words: dict[str, Word],
    values: dict[str, float],
    owner: Code | None,
    owner_word: Word | None,
    modal_motion: str,
    d: list[Diagnostic],
) -> Code | None:
    """Which addresses the block may hold, which it must, and the rules of single words; the speed code."""
    speed_code: Code | None = None
    for _, c in gs:  # (a loop, not next() over a generator: this runs for every block)
        if c.speed:
            speed_code = c
            break
    if owner is not None:
        allowed = owner.words | TABLE.always_allowed
        if speed_code is not None:
            allowed = allowed | {"V"}
    elif speed_code is not None and words.keys() & {"X", "Z", "Q"}:
        allowed = speed_code.words | TABLE.always_allowed  # G97 V… X…, G92 S… X… Z… Q…
    elif words.keys() <= TABLE.always_allowed:
        allowed = TABLE.always_allowed
    else:
        allowed = TABLE.codes[modal_motion].words | TABLE.always_allowed  # a motion of the modal code
    for a, w in words.items():
        if a not in allowed:
            command = (
                str(owner_word)
                if owner_word is not None
                else speed_code.name
                if speed_code is not None
                else f"{modal_motion} (modal)"
            )
            d.append(diag("PAL-E101", w.span, address=a, command=command))
    missing_words(gs, words, d)
    negative_values(TABLE, values, words.__getitem__, d)
    # M functions that must stand alone, or need a T (L1160–1190)
    for w, code in ms:
        if code.alone and (len(ms) > 1 or gs or words):
            d.append(diag("TX-E105", w.span, code=code.name))
        if code.needs_tool and "T" not in words:
            d.append(diag("TX-E106", w.span, code=code.name))
    if "T" in values:
        station = int(values["T"]) // 100
        if not (0 <= station <= 16 or 21 <= station <= 36):
            d.append(diag("TX-E111", words["T"].span, station=station))
    return speed_code


class TurnRun:
    """One run of a TRAUB program: executes blocks and collects planned items."""

    def __init__(self, setup: RunSetup) -> None:
        self.setup = setup
        self.turn = Turn(dict(switch_on_state(TABLE).codes))
        self.turn.skip_on = setup.skip_blocks is False
        tcp = setup.tool_change_point
        self.position: XZ | None = (tcp[0] / 2, tcp[1])  # machine (x radius, z); None: an unknown train point
        self.last_known: XZ = self.position
        self.params: dict[int, float] = {}
        self.nose = Nose()
        self.reference: XZ | None = None  # the workpiece zero of the output frame (set at the first motion)
        self.early: set[int] = set()  # ids of tool changes and dwells made before the reference was known
        self.program: str | None = None  # the called program running now (None: the main program)
        self.srk_window: list[bool] = []  # under SRK: was each block since G46 a motion block
        self.readings: dict[tuple[int, str], tuple[_Reading, list[Diagnostic]]] = {}
        self.srk_reported = False
        self.callee_reads: dict[int, tuple[float, str]] = {}  # L read by a called program: value, program
        self.late: dict[int, tuple[Span, str]] = {}  # L assigned another value after such a read
        self._state: ModalState | None = None
        self.programs: list[Unit] = []  # the main program and every O program of the run (cycle contours)
        self.cycles = traub_cycles.CycleState()
        self.read: list[tuple[int, int]] = []  # program-file lines lo < line ≤ hi a cycle read (checkpoints)

    # -- helpers ------------------------------------------------------------------------------

    def contour_reader(self, cycles: traub_cycles.CycleState) -> TurnRun:
        """A copy of this run that reads a cycle's contour blocks (traub_cycles): the same position, frame,
        parameters and programs, no tools (the contour is the programmed one, without nose radius) and `cycles`
        as its own cycle state. It shares the readings of blocks: a reading depends on the block and the modal
        motion alone, and the run executes the contour's blocks itself as well."""
        scratch = TurnRun(dataclasses.replace(self.setup, tools=ToolTable({})))
        scratch.readings = self.readings
        scratch.turn = dataclasses.replace(self.turn)
        scratch.position, scratch.last_known = self.position, self.last_known
        scratch.reference = self.reference
        scratch.params = dict(self.params)
        scratch.programs = self.programs
        scratch.program = self.program
        scratch.cycles = cycles
        return scratch

    def modal_state(self) -> ModalState:
        """The state after the block that ran last (shared with the block before when nothing changed)."""
        t = self.turn
        speed = t.spindle_at(self.last_known[0]) if t.spindle_on else t.speed
        last = self._state
        if (
            last is None
            or last.codes is not t.codes
            or last.feed != t.feed
            or last.speed != speed
            or last.tool != t.tool
            or last.tc != t.offset
        ):
            last = self._state = ModalState(t.codes, t.feed, speed, t.tool, t.offset)
        return last

    def ref(self) -> XZ:
        """The workpiece zero of the output frame: the zero point active at the first motion."""
        if self.reference is None:
            self.reference = self.turn.zero()
        return self.reference

    def _out(self, p: XZ) -> Vec3:
        """Machine (x radius, z) → output [x, 0, z] in the workpiece frame (the reference must be known)."""
        ref = self.reference
        assert ref is not None
        return (p[0] - ref[0], 0.0, p[1] - ref[1])

    def template(self, kind: str, span: Span, exact: bool = False) -> Move:
        t = self.turn
        p = self.last_known
        pos: Vec3 = self._out(p)
        spindle_code = t.codes.get("spindle")
        on = spindle_code in ("M3", "M4")
        return Move(
            kind,  # type: ignore[arg-type]
            pos,
            pos,
            t.feed,
            "mm/rev" if t.codes.get("feed_mode") == "G95" else "mm/min",
            t.spindle_at(p[0]) if on else 0.0,
            ("cw" if spindle_code == "M3" else "ccw") if on else None,
            t.codes.get("coolant") in ("M7", "M8"),
            t.tool,
            span,
            exact_stop=exact,
            plane="G18",
        )

    def _nose_for(self, mode: str) -> Nose:
        tool = self.setup.tools.get(self.turn.tool) if self.turn.tool is not None else None
        r = tool.nose_radius if tool is not None else 0.0
        q = tool.quadrant if tool is not None else 0
        return Nose(mode, r, q)  # type: ignore[arg-type]

    # -- the block ----------------------------------------------------------------------------

    def execute(self, block: Block) -> Outcome:
        """Run one block: a transaction (module docstring). The phases are the methods below."""
        out = Outcome()
        d = out.diagnostics
        t = self.turn
        reads: set[int] | None = set() if self.program is not None else None
        params = self._assign(block, d, reads)
        r = self._reading(block, params, d, reads)
        motion, moving = self._check(block, r, d)
        if (d and any(x.severity is Severity.ERROR for x in d)) or self._planned(r, d):
            return out  # the block is not executed
        self.params = params
        if (
            reads
        ):  # what a called program read: an assignment of another value afterwards comes too late (T27)
            for n in reads:
                if n in params:
                    self.callee_reads[n] = (params[n], self.program or "")
                self.late.pop(n, None)
        srk = t.codes.get("compensation")
        span = block.span
        self._technology(span, r, motion, moving, out)
        self._act(block, span, r, motion, moving, out)
        self._srk_window(srk, moving, span, d)
        # -- block end
        mnames = r.m_names
        if not mnames.isdisjoint(_STOPS):  # they include M05 and M09 (L1178)
            t.codes = {**t.codes, "spindle": "M5", "coolant": "M9"}
        out.ended = "M30" in mnames
        out.sub_end = "M99" in mnames
        return out

    def _assign(self, block: Block, d: list[Diagnostic], reads: set[int] | None) -> dict[int, float]:
        """The L-parameter assignments, left to right, into a copy of the parameters."""
        params = self.params
        if block.assignments:
            params = dict(params)
            for asg in block.assignments:
                if not _l_valid(asg.param):
                    d.append(diag("TX-E110", asg.span, number=asg.param))
                    continue
                v = evaluate(asg.expr, params, asg.line, d, reads)
                if v is not None:
                    params[asg.param] = v
                    seen = self.callee_reads.get(asg.param)
                    if seen is not None and seen[0] != v and self.program is None:
                        self.late[asg.param] = (asg.span, seen[1])
        return params

    def _reading(
        self, block: Block, params: dict[int, float], d: list[Diagnostic], reads: set[int] | None
    ) -> _Reading:
        """The block's words sorted and checked; kept for a block without expressions (sections, subprograms)."""
        modal = self.turn.codes.get("motion") or "G1"
        known = self.readings.get((id(block), modal))
        if known is None:
            found: list[Diagnostic] = []
            limit = self.setup.limits.max_abs_value
            r = _plain_read(block, limit, modal) or _read(block, params, found, reads, limit, modal)
            if r.cacheable:
                self.readings[(id(block), modal)] = (r, found)
            d.extend(found)
            return r
        d.extend(known[1])
        return known[0]

    def _check(self, block: Block, r: _Reading, d: list[Diagnostic]) -> tuple[Code | None, bool]:
        """The rules that depend on the state (SRK, the spindle, driven tools, the tool call); the block's
        motion code and whether it moves."""
        t = self.turn
        gs, ms, words, values, owner = r.gs, r.ms, r.words, r.values, r.owner
        mnames = r.m_names
        srk = t.codes.get("compensation")
        if srk != "G40" and "G40" not in r.g_names:
            for w, c in gs:
                if not c.with_srk:
                    d.append(diag("TX-E103", w.span, command=c.name, srk=srk))
        if "M17" in mnames and t.spindle_on and "M5" not in mnames:
            d.append(diag("TX-E109", next(w.span for w, c in ms if c.name == "M17")))
        if "B" in values and int(values["B"]) // 10000 == 6:
            on = t.driven_on or not mnames.isdisjoint(_DRIVEN_ON)
            direction = t.driven_direction or not mnames.isdisjoint(_DRIVEN_DIRECTION)
            if not (on and direction):
                d.append(diag("TX-E107", words["B"].span))
        motion: Code | None = owner if owner is not None and owner.group == "motion" else None
        if owner is None and r.speed_code is None and not words.keys().isdisjoint(_GEOMETRY):
            motion = TABLE.codes[t.codes.get("motion") or "G1"]
        moving = motion is not None and not words.keys().isdisjoint(_GEOMETRY)
        if moving and not t.tool_called and t.deselected_by is not None and "T" not in values:
            d.append(diag("TX-E102", block.span, command=t.deselected_by))
        if moving and (t.first_after_t or "T" in values):
            for a in ("U", "W"):
                if a in words:
                    d.append(diag("TX-E101", words[a].span, address=a))
                    break
        return motion, moving

    @staticmethod
    def _planned(r: _Reading, d: list[Diagnostic]) -> bool:
        """Codes not supported yet: a note each; True when one owns the block, which is then not executed."""
        for w, c in r.gs + r.ms:
            if c.support is Support.PLANNED:
                skips = c.owns_block
                d.append(
                    diag(
                        "PAL-E901",
                        w.span,
                        feature=c.feature_de,
                        feature_en=c.feature_en,
                        effect="der Satz wird nicht ausgeführt."
                        if skips
                        else "der Satz wird ohne diese Funktion ausgeführt.",
                        effect_en="the block is not executed."
                        if skips
                        else "the block is executed without it.",
                    )
                )
                if skips:
                    return True
        return False

    def _technology(self, span: Span, r: _Reading, motion: Code | None, moving: bool, out: Outcome) -> None:
        """Technology and modes at the block start: feed, modal codes, speed, driven tools, tool, zero point, SRK."""
        t = self.turn
        d = out.diagnostics
        gs, ms, words, values, owner = r.gs, r.ms, r.words, r.values, r.owner
        names, mnames = r.g_names, r.m_names
        if "F" in values:
            t.feed = values["F"]
        if "E" in values:
            t.transition_feed = values["E"]
        for _, c in gs + ms:
            if c.group is not None and c.group != "program_end" and t.codes.get(c.group) != c.name:
                t.codes = {**t.codes, c.group: c.name}
        self._speed(span, r, d)
        if not mnames.isdisjoint(_DRIVEN_ON):
            t.driven_on = True
        if not mnames.isdisjoint(_DRIVEN_DIRECTION):
            t.driven_direction = True
        if "M25" in mnames:
            t.driven_on = t.driven_direction = False
        if "M31" in mnames:
            t.skip_on = False
        if "T" in values:
            value = int(values["T"])
            station = value // 100
            if (
                motion is not None
                and motion.name == "G0"
                and moving
                and t.tool is not None
                and station != t.tool
                and abs(station - t.tool) != 20
            ):  # in G00 only the grooving tool's second edge (L1505)
                d.append(diag("TX-W108", words["T"].span, tool=f"T{station:02d}", current=f"T{t.tool:02d}"))
            t.tool = value // 100 or None
            t.offset = value % 100
            t.tool_called, t.deselected_by, t.first_after_t = True, None, True
            if owner is None or not owner.change_point:  # else at the change point, below
                out.items.append(self._early(ToolChange(t.tool, t.offset, 0.0, 0.0, self._vec(), span)))
        if not names.isdisjoint(_ZERO_POINTS):
            zero = next(c.name for _, c in gs if c.name in ("G54", "G55", "G56", "G57"))
            base = self.setup.zero_offset(zero)
            t.zero_base = (base[0], base[2])
        if owner is not None and owner.name == "G59":  # replaces the previous shift (DECISIONS §21)
            t.zero_shift = (values.get("X", 0.0), values.get("Z", 0.0))
        for w, c in gs:
            if c.name in ("G40", "G41", "G42", "G46"):
                self.nose = self._nose_for(c.name)
                out.items.append(SrkSwitch(c.name, w.span, self.nose))  # type: ignore[arg-type]

    def _speed(self, span: Span, r: _Reading, d: list[Diagnostic]) -> None:
        """G92 speed limit, G96 constant cutting speed, G97 constant speed, or S/V alone."""
        t = self.turn
        names, words, values = r.g_names, r.words, r.values
        if "G92" in names:
            if "S" in values:
                t.limit = values["S"]
            for a in ("X", "Z", "Q"):
                if a in words:
                    d.append(diag("TX-W102", words[a].span, address=a))
        elif "G96" in names:
            t.cutting_speed = values["V"]
            if "S" in values:
                t.speed = values["S"]
        elif "G97" in names:
            if "S" in values:
                t.speed = values["S"]
            elif "V" in values:
                x = values.get("X", 0.0)
                if x <= 0:
                    d.append(diag("TX-E112", r.owner_word.span if r.owner_word else span))
                else:
                    t.speed = values["V"] * 1000.0 / (math.pi * x)
        elif "S" in values:
            t.speed = values["S"]
        elif "V" in values:
            t.cutting_speed = values["V"]

    def _act(
        self, block: Block, span: Span, r: _Reading, motion: Code | None, moving: bool, out: Outcome
    ) -> None:
        """The motion, dwell, change point or call of the block."""
        t = self.turn
        d = out.diagnostics
        words, values, owner = r.words, r.values, r.owner
        cycle = (
            motion
            if moving and motion is not None and motion.cycle
            else (owner if owner is not None and owner.cycle else None)
        )
        if cycle is not None:  # cycles and threads: core.interpreter.traub_cycles
            out.items.extend(traub_cycles.execute(self, block, cycle, words, values, d))
            t.first_after_t = False
        elif moving and motion is not None:
            self._motion(motion.name, words, values, span, out)
            t.first_after_t = False
        elif owner is None:
            return
        elif owner.name == "G4":
            seconds = values.get("X", values.get("U", 0.0))
            if not 0.001 <= seconds <= 999.99:
                d.append(diag("TX-E108", (words.get("X") or words["U"]).span, value=seconds))
            else:
                out.items.append(self._early(Dwell(self._vec(), seconds, span)))
        elif owner.change_point:
            self._change_point(owner.name, words, values, span, out)
            if "T" in values:
                out.items.append(self._early(ToolChange(t.tool, t.offset, 0.0, 0.0, self._vec(), span)))
        elif owner.name == "G22":
            out.call = (
                int(values["A"]) if "A" in values else None,
                int(values["P"]) if "P" in values else None,
                int(values["Q"]) if "Q" in values else None,
                int(values.get("H", 1)),
            )
        elif 201 <= int(owner.name[1:]) <= 299:
            out.call = (9600 + int(owner.name[1:]), None, None, 1)

    def _srk_window(self, srk: str | None, moving: bool, span: Span, d: list[Diagnostic]) -> None:
        """Under SRK, of 5 blocks in a row at least 3 move (L2544–2566)."""
        now = self.turn.codes.get("compensation")
        if srk == "G40" and now != "G40":
            self.srk_window, self.srk_reported = [], False
        elif srk != "G40" and now != "G40":
            self.srk_window.append(moving)
            if len(self.srk_window) >= 5 and sum(self.srk_window[-5:]) < 3 and not self.srk_reported:
                d.append(diag("TX-E113", span, count=sum(self.srk_window[-5:])))
                self.srk_reported = True

    def _vec(self) -> Vec3:
        """Where the tool stands, in the output frame once it is known (else machine, fixed at the end)."""
        p = self.last_known
        return (p[0], 0.0, p[1]) if self.reference is None else self._out(p)

    def _early(self, item: Dwell | ToolChange) -> Dwell | ToolChange:
        if self.reference is None:
            self.early.add(id(item))
        return item

    def _motion(
        self, code: str, words: dict[str, Word], values: dict[str, float], span: Span, out: Outcome
    ) -> None:
        t = self.turn
        rx, rz = self.ref()
        zx, zz = t.zero()
        zx, zz = zx - rx, zz - rz  # the active zero point in the output frame
        start = None if self.position is None else (self.position[0] - rx, self.position[1] - rz)
        x = values["X"] / 2 + zx if "X" in values else None
        z = values["Z"] + zz if "Z" in values else None
        dx, dz = values.get("U"), values.get("W")
        if start is not None:
            if dx is not None:
                x, dx = start[0] + dx, None
            if dz is not None:
                z, dz = start[1] + dz, None
        is_arc = code in ("G2", "G3")
        transition: TransitionSpec | None = None
        if "D" in values and values["D"] != 0:
            w = words["D"]
            transition = TransitionSpec(
                "chamfer" if values["D"] > 0 else "chamfer_length",
                abs(values["D"]),
                str(w),
                t.transition_feed,
            )
        elif not is_arc and "R" in values:
            transition = TransitionSpec("rounding", abs(values["R"]), str(words["R"]), t.transition_feed)
        elif is_arc and "C" in values:
            transition = TransitionSpec("rounding", abs(values["C"]), str(words["C"]), t.transition_feed)
        if code == "G9" and transition is not None:
            out.diagnostics.append(
                diag("TX-W104", words["D" if "D" in words else "R"].span, address=transition.raw)
            )
        if code != "G0":
            if t.feed == 0:
                out.diagnostics.append(diag("PAL-E301", span))
                return
            if t.tool is None:
                out.diagnostics.append(diag("TX-W106", span))
            elif not t.spindle_on and not t.driven_on:  # a driven tool cuts with the main spindle at rest
                out.diagnostics.append(diag("PAL-E302", span, Severity.WARNING))
        if (
            t.codes.get("spindle_mode") == "G96"
            and t.spindle_on
            and t.limit is None
            and x is not None
            and x + rx <= 1e-9
        ):
            out.diagnostics.append(diag("TX-W105", span, limit=f"{MAX_SPINDLE:g} 1/min"))
        kind = "rapid" if code == "G0" else "arc" if is_arc else "feed"
        template = self.template(kind, span, exact=code in ("G0", "G9"))
        item = TurnItem(
            template,
            code,  # type: ignore[arg-type]
            start,
            x,
            z,
            dx,
            dz,
            a=values.get("A"),
            radius=abs(values["R"]) if is_arc and "R" in values else None,
            centre=(values["P"] / 2 + zx, values["Q"] + zz)
            if is_arc and "P" in values and "Q" in values
            else None,
            centre_offset=(values.get("I", 0.0), values.get("K", 0.0))
            if is_arc and ("I" in values or "K" in values)
            else None,
            h=int(values["H"]) if "H" in values else None,
            transition=transition,
            nose=self.nose,
            spindle_at=_constant_cutting_speed(t.cutting_speed, t.limit, rx)
            if t.codes.get("spindle_mode") == "G96" and t.spindle_on
            else None,
        )
        out.items.append(item)
        end = self._known_end(start, item, has_axis=not words.keys().isdisjoint(_AXES))
        self.position = None if end is None else (end[0] + rx, end[1] + rz)
        if self.position is not None:
            self.last_known = self.position

    def _known_end(self, start: XZ | None, item: TurnItem, has_axis: bool) -> XZ | None:
        """Where the block ends, when the block alone fixes it; None for an unknown train point."""
        if item.a is None and has_axis:
            if start is not None:
                return (
                    item.x if item.x is not None else start[0],
                    item.z if item.z is not None else start[1],
                )
            if item.x is not None and item.z is not None:
                return (item.x, item.z)
            return None
        if item.a is None and item.is_arc and item.centre_offset is None and item.centre is None:
            return None
        return turn_contour.known_end(start, item)

    def _change_point(
        self, name: str, words: dict[str, Word], values: dict[str, float], span: Span, out: Outcome
    ) -> None:
        """G24–G27 to the tool-change point, G28 (via X/Z) to the reference point, G53 in machine coordinates."""
        t = self.turn
        tcp = self.setup.tool_change_point
        target = (tcp[0] / 2, tcp[1])
        here = self.last_known
        points: list[XZ] = []
        if name == "G24":
            points = [(target[0], here[1])]
        elif name == "G25":
            points = [(here[0], target[1])]
        elif name == "G26":
            points = [(target[0], here[1]), target]
        elif name == "G27":
            points = [(here[0], target[1]), target]
        elif name == "G28":
            zx, zz = t.zero()
            if not words.keys().isdisjoint(_AXES):
                ax = values["X"] / 2 + zx if "X" in values else here[0] + values.get("U", 0.0)
                az = values["Z"] + zz if "Z" in values else here[1] + values.get("W", 0.0)
                points = [(ax, az)]
            points.append(target)
        else:  # G53: machine coordinates
            points = [(values["X"] / 2 if "X" in values else here[0], values.get("Z", here[1]))]
        self.ref()
        for p in points:
            if p == here:
                continue
            template = self.template("rapid", span, exact=True)
            out.items.append(dataclasses.replace(template, start=self._out(here), end=self._out(p)))
            here = p
        self.position = self.last_known = here
        if "T" not in values:  # a T in the same block calls the tool at the change point
            t.tool_called, t.deselected_by, t.first_after_t = False, name, False


def _constant_cutting_speed(v: float, limit: float | None, axis: float = 0.0) -> Callable[[float], float]:
    """The speed (1/min) at x under G96 V`v`, clamped by G92 S`limit` (or the machine's highest); x + `axis` is
    the radius (distance from the spindle axis)."""

    def at(x: float) -> float:
        return _rpm(v, limit, x + axis)

    return at


def _rpm(v: float, limit: float | None, radius: float) -> float:
    """The speed (1/min) of cutting speed `v` (m/min) at `radius`, clamped by `limit` or the machine's highest."""
    top = limit if limit is not None else MAX_SPINDLE
    d = 2 * abs(radius)
    return top if d < 1e-9 else min(top, v * 1000.0 / (math.pi * d))


def resolve(items: list[Item], diagnostics: list[Diagnostic]) -> list[turn_contour.Command]:
    """The one call of the contour stage (contour trains, transitions, SRK): core.interpreter.turn_contour."""
    return turn_contour.resolve(items, diagnostics)


def _to_workpiece(c: turn_contour.Command, dx: float, dz: float) -> turn_contour.Command:
    """`c` moved from machine coordinates into the workpiece frame whose zero is (dx, dz)."""

    def shift(p: Vec3) -> Vec3:
        return (p[0] - dx, p[1], p[2] - dz)

    if isinstance(c, Move):
        return dataclasses.replace(
            c,
            start=shift(c.start),
            end=shift(c.end),
            center=None if c.center is None else shift(c.center),
            programmed_end=None if c.programmed_end is None else shift(c.programmed_end),
        )
    return dataclasses.replace(c, position=shift(c.position))


# -- the run: programs, calls, sections --------------------------------------------------------


# the program flow's diagnostics of TRAUB programs
FLOW = FlowCodes(
    "TX-E301", "TX-E303", "TX-E302", "TX-E304", "TX-E305", "TX-W302", "TX-E306", "TX-W301", True, True, True
)


class TurnMachine(Machine):
    """TRAUB turning for the run loop (core/interpreter/loop.py): a `TurnRun` and its state as a value."""

    codes = FLOW
    resolves_numbers = True  # the cycles find their contours by block number
    carries_as_is = False  # the contour cache of a later step: this run's and what the previous run added

    def __init__(self, setup: RunSetup, readings: dict[Any, Any] | None = None) -> None:
        self.setup = self.identity = setup
        self.run = TurnRun(setup)
        self.initial = self.run.modal_state()
        self.marks = self.run.early
        self._contours: dict[Any, Any] | None = None  # the cycles' contour cache as the last snap kept it
        self._ref: XZ = (0.0, 0.0)

    def units(
        self, program: Program, library: dict[int, Program], diags: list[Diagnostic]
    ) -> tuple[Unit, dict[int, Unit], list[Unit]]:
        main, others = split_programs(program)
        units: dict[int, Unit] = {}
        for u in others:
            assert u.number is not None
            units.setdefault(u.number, u)
            if not 8000 <= u.number <= 9999:
                diags.append(diag("TX-W103", Span(u.line, 1, u.line, 2), number=u.number))
        for number, prog in library.items():
            lib_main, lib_others = split_programs(prog, f"O{number}")
            lib_main.number = lib_main.number or number
            for u in (lib_main, *lib_others):
                if u.number is not None:
                    units.setdefault(u.number, u)
        self.run.programs = [main, *units.values()]
        return main, units, [main, *others]

    def step(self, block: Block, unit: Unit, program: str | None) -> Step:
        run = self.run
        run.program = program
        out = run.execute(block)
        reads = None
        if run.read:
            reads = list(run.read)
            run.read.clear()
        moves = sum(type(c) is TurnItem or type(c) is Move for c in out.items)
        call = None if out.call is None else (*out.call, False)
        return Step(out.items, out.diagnostics, moves, call, None, out.sub_end, out.ended, False, reads)

    def commit(self) -> tuple[ModalState, Vec3]:
        p = self.run.last_known
        return self.run.modal_state(), (p[0], 0.0, p[1])

    def skipped(self, block: Block) -> bool:
        return block.skip is not None and not self.run.turn.skip_on

    def stamp(self, items: list[Any], source: str | None, stack: tuple[tuple[str | None, int], ...]) -> None:
        for k, it in enumerate(items):
            if isinstance(it, TurnItem):
                items[k] = dataclasses.replace(
                    it, template=it.template.with_fields(source=source, call_stack=stack)
                )
            elif isinstance(it, Move):
                items[k] = it.with_fields(source=source, call_stack=stack)

    # -- checkpoints: the run's state and the cycles' contour cache ---------------------------------

    def snap(self) -> tuple[tuple[Any, ...], dict[Any, Any]]:
        contours = self.run.cycles.contours  # it only grows: a copy when it has
        kept = self._contours
        if kept is None or len(kept) != len(contours):
            kept = self._contours = dict(contours)
        return snapshot(self.run), kept

    def restore(self, snap: tuple[tuple[Any, ...], dict[Any, Any]]) -> None:
        _restore(self.run, snap[0], snap[1])
        self._contours = snap[1]

    def shift(self, lm: LineMap, snap: Any, done: dict[int, Any]) -> Any:
        return _shift_run(lm, snap[0]), map_contours(lm, snap[1], done)

    def same(self, lm: LineMap, old: Any, now: Any) -> bool:
        if _shift_run(lm, old[0]) != now[0]:
            return False
        then, contours = old[1], now[1]
        return then is contours or {(k[0], lm.line(k[1], k[0]) if k[1] else 0, *k[2:]) for k in then} == set(
            contours
        )

    def carry(self, lm: LineMap, base: Any, now: Any, later: Any, done: dict[int, Any]) -> Any:
        return _shift_run(lm, later[0]), carry_contours(lm, base[1], now[1], later[1], done)

    # -- the end -------------------------------------------------------------------------------

    def commands(self, items: list[Any], diags: list[Diagnostic]) -> list[Any]:
        run = self.run
        for n, (late_span, late_program) in run.late.items():
            diags.append(diag("TX-W107", late_span, number=n, program=late_program))
        dx, dz = self._ref = run.ref()
        early = run.early
        return [_to_workpiece(c, dx, dz) if early and id(c) in early else c for c in resolve(items, diags)]

    def finish(self, result: Toolpath, states: list[ModalState | None], positions: list[Vec3 | None]) -> None:
        dx, dz = self._ref
        if not self.setup.answer_only:
            # the lines' positions in the workpiece frame (the run kept the machine's)
            for i, ps in enumerate(positions):
                if ps is not None:
                    positions[i] = (ps[0] - dx, 0.0, ps[2] - dz)
        tcp = self.setup.tool_change_point  # where the run starts
        finish_toolpath(
            result, states, positions, (tcp[0] / 2 - dx, 0.0, tcp[1] - dz), self.setup.answer_only
        )
        result.params = dict(self.run.params)
        final = self.run.last_known
        result.final_position = (final[0] - dx, 0.0, final[1] - dz)


# -- the run's state as a value (checkpoints) ---------------------------------------------------


def snapshot(run: TurnRun) -> tuple[Any, ...]:
    """What of the run's state the rest of the run depends on (the contour cache apart: `_take_over`)."""
    c = run.cycles
    return (
        dataclasses.replace(run.turn),
        run.position,
        run.last_known,
        dict(run.params),
        run.nose,
        run.reference,
        run.program,
        tuple(run.srk_window),
        run.srk_reported,
        dict(run.callee_reads),
        dict(run.late),
        c.pitch,
        c.repeatable,
        c.work,
        c.in_contour,
        len(c.contours),
    )


def _shift_run(lm: LineMap, snap: tuple[Any, ...]) -> tuple[Any, ...]:
    if snap[10] and not lm.identity:
        raise Unmappable  # a late L assignment's line (TX-W107): rare, run on
    return snap


def _restore(run: TurnRun, snap: tuple[Any, ...], contours: dict[Any, Any]) -> None:
    (
        turn,
        run.position,
        run.last_known,
        params,
        run.nose,
        run.reference,
        run.program,
        window,
        run.srk_reported,
        reads,
        late,
        pitch,
        repeatable,
        work,
        in_contour,
        _,
    ) = snap
    run.turn = dataclasses.replace(turn)
    run.params, run.callee_reads, run.late, run.srk_window = (
        dict(params),
        dict(reads),
        dict(late),
        list(window),
    )
    run.cycles.pitch, run.cycles.repeatable, run.cycles.work = pitch, repeatable, work
    run.cycles.in_contour, run.cycles.contours = in_contour, dict(contours)
    run._state = None


def map_contours(lm: LineMap, contours: dict[Any, Any], done: dict[int, dict[Any, Any]]) -> dict[Any, Any]:
    """The cycles' contour cache in the new numbering (its keys and points name lines); `done` by id."""
    if lm.identity or not contours:
        return contours
    found = done.get(id(contours))
    if found is None:
        found = done[id(contours)] = {
            (k[0], lm.line(k[1], k[0]) if k[1] else 0, *k[2:]): [(p, lm.line(ln, k[0])) for p, ln in v]
            for k, v in contours.items()
        }
    return found


def carry_contours(
    lm: LineMap,
    base: dict[Any, Any],
    now: dict[Any, Any],
    later: dict[Any, Any],
    done: dict[int, dict[Any, Any]],
) -> dict[Any, Any]:
    """The cache of the previous run at a later step (`later`, which grew from `base` where this run met it
    with `now`) as this run has it there: `now` and what the previous run added, in the new numbering."""
    if later is base:
        return now
    found = done.get(id(later))
    if found is None:
        found = done[id(later)] = dict(now)
        for k, v in later.items():
            if k not in base:
                found[(k[0], lm.line(k[1], k[0]) if k[1] else 0, *k[2:])] = [
                    (p, lm.line(ln, k[0])) for p, ln in v
                ]
    return found
