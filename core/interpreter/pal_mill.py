"""PAL milling: the execution of one block, (state, block) → (state, commands, diagnostics).

A block is a transaction in a fixed order: check every word (unknown, not allowed, missing,
duplicated, conflicting) → if anything is wrong, stop: the state stays as it was → otherwise
commit in the order of the spec: parameter assignments; F, S, tool change with TC/TR/TL; modal
G codes; switch-on M codes (M3, M4, M8 …); the motion or dwell; M5/M9 at the block end; M30.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from typing import Any, Literal

from core.diagnostics import Diagnostic, Severity, diag
from core.dialects.codes import Code, CodeTable, Support
from core.dialects.pal_mill import TABLE
from core.geometry.arcs import arc_solutions, choose_arc, sweep
from core.geometry.elements import angle_of
from core.geometry.planes import AXES, from_plane, to_plane
from core.interpreter import din_arcs, iso_cycles, pal_cycles
from core.interpreter.contour import Approach, Blend, Departure, Item, Planned, departure_ends, end_tangent_of
from core.interpreter.frames import Frame
from core.interpreter.params import evaluate
from core.interpreter.state import DrillData, ModalState, RunSetup
from core.interpreter.words import group_conflicts, missing_words, negative_values
from core.syntax.blocks import Block, Span, Word
from core.toolpath import Dwell, Move, MoveKind, ToolChange, Vec3

Command = Item

_AXES = (("X", "XI", "XA"), ("Y", "YI", "YA"), ("Z", "ZI", "ZA"))
_AXIS_WORDS = frozenset(a for spellings in _AXES for a in spellings)
_OWNER_DUPLICATES = {"G23": {"N"}, "G29": {"P"}}  # addresses a code takes twice
_GEOMETRY_WORDS = _AXIS_WORDS | {"I", "J", "IA", "JA", "R", "AO", "AS", "D", "RP", "AP", "AI", "K", "KA"}
_END_OF_BLOCK = {"M5": ("spindle", "M5"), "M9": ("coolant", "M9")}


@dataclass(slots=True)
class Outcome:
    """What one block did."""

    state: ModalState
    position: Vec3
    commands: list[Command] = field(default_factory=list)
    diagnostics: list[Diagnostic] = field(default_factory=list)
    ended: bool = False  # M30 executed
    sub_end: bool = False  # M17 executed
    flow: tuple[str, int, int] | None = None  # ("call", L, H) for G22, ("jump", N, 0) for a G29 taken
    repeat: tuple[int, int, int] | None = None  # G23: start N, end N, count H
    executed: bool = True  # False: an error stopped the block before it did anything
    stopped: bool = (
        False  # an error that stops decoding (Beckhoff's first G301/G302 without I): the run ends here
    )


def execute_block(
    setup: RunSetup,
    state: ModalState,
    position: Vec3,
    block: Block,
    params: dict[int, float],
    table: CodeTable = TABLE,
    cache: dict[Any, Any] | None = None,
) -> Outcome:
    """Execute `block` from `state` at `position`. `params` (P1…P999) is updated only on success."""
    out = Outcome(state, position)
    d = out.diagnostics
    new_params = _assign(setup, block, params, d) if block.assignments else params
    reading = _reading(setup, table, block, new_params, state.codes, cache)
    d.extend(reading.diagnostics)
    values = reading.values
    if table.din and values:
        units = dict(reading.activations).get("units") or state.codes.get("units")
        if units in _INCH:  # inch input (G20, Beckhoff G70): every length in mm from here on
            values = _in_mm(values, reading.cycle is not None)
    owner = reading.owner
    pal_cycle = (
        owner is not None
        and not table.din
        and (owner.name in pal_cycles.DEFINITIONS or owner.name in pal_cycles.CALLS)
    )
    step = _Step(setup, table, block, block.span, reading, values, new_params, pal_cycle, out)
    _check_in_state(step, state)
    if d and any(x.severity is Severity.ERROR for x in d):
        out.executed = False
        if pal_cycle and owner is not None and owner.name in pal_cycles.DEFINITIONS:
            # a rejected definition replaces the earlier one all the same: its calls must not run the old cycle
            out.state = dataclasses.replace(state, pal_cycle=None)
        return out  # the block is not executed; the state stays as it was
    if reading.planned and _skips_planned(step):
        out.executed = False
        return out
    before = state
    state = _commit(step, state, position)
    state, position = _act(step, before, state, position)
    if reading.ends or reading.ms:
        state = _block_end(step, state)
    if new_params is not params:
        params.clear()
        params.update(new_params)
    out.state, out.position = state, position
    return out


@dataclass(slots=True)
class _Step:
    """A block on its way through `execute_block`: what its phases share."""

    setup: RunSetup
    table: CodeTable
    block: Block
    span: Span  # the block's (made once)
    reading: Reading
    values: dict[str, float]  # in mm
    params: dict[int, float]  # after the block's assignments
    pal_cycle: bool  # a PAL cycle's definition or call
    out: Outcome


def _assign(setup: RunSetup, block: Block, params: dict[int, float], d: list[Diagnostic]) -> dict[int, float]:
    """The parameter assignments, left to right, into a copy."""
    if not block.assignments:
        return params
    new_params = dict(params)
    for asg in block.assignments:
        if not 1 <= asg.param <= 999:
            d.append(diag("PAL-E113", asg.span, number=asg.param))
            continue
        value = evaluate(asg.expr, new_params, asg.line, d)
        if value is not None and _in_range(value, f"P{asg.param}", asg.span, setup, d):
            new_params[asg.param] = value
    return new_params


def _reading(
    setup: RunSetup,
    table: CodeTable,
    block: Block,
    params: dict[int, float],
    codes: dict[str, str | None],
    cache: dict[Any, Any] | None,
) -> Reading:
    """Everything that depends on the block alone, kept in `cache` for blocks run again (loops)."""
    motion, plane, cycle = codes.get("motion"), codes.get("plane"), codes.get("cycle")
    if cache is None:
        return _read(block, table, setup, params, motion, plane, cycle)
    # the entry holds its block: while it is kept, no other block can have the block's id
    key = (id(block), motion, plane, cycle)
    hit: tuple[Block, Reading] | None = cache.get(key)
    if hit is not None and hit[0] is block:
        return hit[1]
    reading = _read(block, table, setup, params, motion, plane, cycle)
    if reading.cacheable:
        cache[key] = (block, reading)
    return reading


def _check_in_state(step: _Step, state: ModalState) -> None:
    """The rules that depend on the state: M6 without a tool, T words under compensation, the owners' own
    rules, the PAL cycles'."""
    r, values, d = step.reading, step.values, step.out.diagnostics
    ms, words, owner, owner_word = r.ms, r.words, r.owner, r.owner_word
    if ms and any(c.name == "M6" for _, c in ms) and "T" not in values and state.tool is None:
        d.append(diag("PAL-E308", next(w.span for w, c in ms if c.name == "M6")))
    if state.codes["compensation"] != "G40" and "G40" not in r.in_block:
        for a in ("T", "TC", "TR", "TL"):
            if a in words:
                d.append(diag("PAL-E216", words[a][0].span, address=a))
    if owner is not None and owner.name in _CHECKED_OWNERS:
        _check_owner(owner, owner_word or r.gs[0][0], r.in_block, words, values, state, d)
    if step.pal_cycle and owner is not None:
        if owner.name == "G73" and "RZ" in values:  # the boss form (Zapfen)
            d.append(
                _not_supported(
                    words["RZ"][0].span, "Zapfenfräsen mit G73 (RZ)", "Boss milling with G73 (RZ)", True
                )
            )
        pal_cycles.check_block(
            owner.name,
            owner_word.span if owner_word else step.span,
            words,
            values,
            state,
            [c.name for _, c in ms],
            d,
        )


def _skips_planned(step: _Step) -> bool:
    """Codes not supported yet: a note each; True when one owns the block, which then does nothing."""
    for w, code in step.reading.planned:
        if (
            code.support is Support.PLANNED and not step.table.din
        ):  # (DIN: a warning of the reading, the block runs)
            skips = code.owns_block
            step.out.diagnostics.append(_not_supported(w.span, code.feature_de, code.feature_en, skips))
            if skips:
                return True
    return False


_TECHNOLOGY = frozenset({"F", "S", "T", "TC", "TR", "TL", "D"})  # the words `_commit` takes (D: DIN's offset)
_FRAME_OWNERS = frozenset({"G50", "G58", "G59", "G66"})  # the codes that change the frame by their words


def _commit(step: _Step, state: ModalState, position: Vec3) -> ModalState:
    """Technology and modes at the block start: F, S, the tool change with TC/TR/TL, modal codes, the frame."""
    r, values, table, out = step.reading, step.values, step.table, step.out
    owner = r.owner
    codes = state.codes
    changes: dict[str, str] = {}
    for g, m in r.activations:  # (a loop, not a comprehension: this runs for every block)
        if codes.get(g) != m:
            changes[g] = m
    if (
        not changes
        and values.keys().isdisjoint(_TECHNOLOGY)
        and (owner is None or owner.name not in _FRAME_OWNERS)
    ):
        return _din_modes(state) if table.din else state  # nothing to commit: most moves
    feed, speed, tool, tc, tr, tl = state.feed, state.speed, state.tool, state.tc, state.tr, state.tl
    if "F" in values and not (
        step.pal_cycle and owner is not None and owner.name == "G84"
    ):  # (G84: F is the pitch)
        feed = values["F"]
    if "S" in values:
        speed = values["S"]
    if "T" in values:
        tool = r.new_tool or None
        tc, tr, tl = 1, 0.0, 0.0
        codes = {**codes, "spindle": "M5", "coolant": "M9"}  # a tool change stops spindle and coolant
    if "TC" in values:
        tc = int(values["TC"])
    if "TR" in values:
        tr = values["TR"]
    if "TL" in values:
        tl = values["TL"]
    if table.din and "D" in values:
        tc = int(values["D"])  # the tool offset D: its radius (D0: none)
    if changes:
        codes = {**codes, **changes}
    if (
        codes is not state.codes
        or feed != state.feed
        or speed != state.speed
        or tool != state.tool
        or tc != state.tc
        or tr != state.tr
        or tl != state.tl
    ):
        state = ModalState(
            codes,
            feed,
            speed,
            tool,
            tc,
            tr,
            tl,
            state.pole,
            state.frame,
            state.blend,
            state.tangent,
            state.arc_radius,
            state.drill,
            state.pal_cycle,
        )
    if table.din:
        state = _din_modes(state)
    if "zero_offset" in changes or (owner is not None and owner.name in _FRAME_OWNERS):
        frame = _frame(step.setup, state.frame, changes.get("zero_offset"), owner, r.words, values)
        if frame is not state.frame:
            state = dataclasses.replace(state, frame=frame)
    if "T" in values:
        out.commands.append(ToolChange(tool, tc, tr, tl, position, step.span))
    if changes.get("spindle") in ("M3", "M4") and speed == 0:
        span = next(w.span for w, c in r.ms if c.name in ("M3", "M4", "M13", "M14"))
        out.diagnostics.append(diag("PAL-E306", span))
    return state


def _act(step: _Step, before: ModalState, state: ModalState, position: Vec3) -> tuple[ModalState, Vec3]:
    """The motion, dwell, cycle or program flow of the block."""
    r, values, words, setup, out = step.reading, step.values, step.reading.words, step.setup, step.out
    owner, span, d = r.owner, step.span, out.diagnostics
    name = owner.name if owner is not None else None
    if name == "G4":
        out.commands.append(Dwell(position, _dwell_seconds(step, state), span))
    elif "#TIME" in values:  # Beckhoff's dwell in plain text
        out.commands.append(Dwell(position, values["#TIME"], span))
    elif "G28" in r.in_block or "G53" in r.in_block:
        position = _home(setup, state, position, values, words, "G28" in r.in_block, span, out.commands, d)
    elif r.cycle is not None:
        position, state = _drill(setup, state, position, r.cycle, values, words, span, out.commands, d)
    elif step.pal_cycle and name in pal_cycles.DEFINITIONS:
        assert name is not None
        ms = [c.name for _, c in r.ms]
        state = dataclasses.replace(
            state, pal_cycle=pal_cycles.define(name, values, step.block.line, state, ms)
        )
    elif step.pal_cycle and name is not None:
        position = _cycle_call(setup, state, position, name, values, span, out.commands, d)
    elif name in ("G45", "G47"):
        assert name is not None
        planned = _approach(setup, state, state.frame.to_program(position), name, words, values, span, d)
        planned.move = state.frame.map_move(planned.move)
        planned.side = -planned.side if state.frame.flips else planned.side
        out.commands.append(planned)
        position = planned.move.end
        if state.tangent is not None:  # the first contour element is not known yet
            state = dataclasses.replace(state, tangent=None)
    elif name in ("G46", "G48"):
        assert name is not None
        planned = _departure(setup, before, state, position, name, words, values, span, d)
        out.commands.append(planned)
        position = planned.move.end  # the tool centre: compensation is off from here on
    elif r.motion is not None and r.moves:
        state, position = _contour_motion(step, r.motion, state, position)
    elif name in ("G301", "G302"):
        state = _blend(step, state)
    else:
        _flow(step)
    return state, position


def _dwell_seconds(step: _Step, state: ModalState) -> float:
    values = step.values
    if "U" in values:
        seconds = values["U"]
    elif "X" in values:
        seconds = values["X"]  # DIN/ISO: X in seconds
    else:
        seconds = values["P"] / 1000  # ISO: P in milliseconds
    if int(values.get("O", 1)) == 2:  # U in spindle revolutions
        if state.speed == 0:
            owner_word = step.reading.owner_word
            step.out.diagnostics.append(diag("PAL-E305", owner_word.span if owner_word else step.span))
            return 0.0
        return values["U"] * 60.0 / state.speed
    return seconds


def _contour_motion(step: _Step, motion: Code, state: ModalState, position: Vec3) -> tuple[ModalState, Vec3]:
    """A G0–G3 move (a contour element under compensation, with its transition to the next one)."""
    r, values, setup, table, out = step.reading, step.values, step.setup, step.table, step.out
    words, span, d = r.words, step.span, out.diagnostics
    exact = "G9" in r.in_block or state.codes.get("path_mode") == "G61"
    frame = state.frame
    here = position if frame.identity else frame.to_program(position)
    if table.din and motion.name in ("G2", "G3"):
        move, radius = _din_motion(
            setup, state, here, motion.name, words, values, span, exact, r.arc_plane, r.alt_plane, table, d
        )
        pole = None
        if radius is not None and table.modal_radius and radius != state.arc_radius:
            state = dataclasses.replace(state, arc_radius=radius)
    else:
        move, pole = _motion(
            setup,
            state,
            here,
            motion.name,
            words,
            values,
            span,
            exact,
            r.arc_plane,
            table.strict_technology,
            d,
            table.din,
        )
    if pole is not None and pole != state.pole:
        state = dataclasses.replace(state, pole=pole)
    if move is None:
        return state, position
    if not frame.identity:
        move = frame.map_move(move)
    side, radius = _compensation(setup, state)
    rn, element, by_length = _transition(values, words)
    out.commands.append(
        Planned(
            move,
            rn,
            element,
            values.get("E") or values.get("#FRC"),
            -side if frame.flips else side,
            radius,
            None,
            None,
            by_length,
            "RN" not in values,
        )
    )
    if side and (move.kind == "arc" or move.start[:2] != move.end[:2]):
        state = dataclasses.replace(state, tangent=end_tangent_of(move))
    return state, move.end


def _blend(step: _Step, state: ModalState) -> ModalState:
    """Beckhoff G301/G302: rounding or chamfering of the corners from here on."""
    owner, owner_word, out = step.reading.owner, step.reading.owner_word, step.out
    assert owner is not None
    size = step.values.get("I", state.blend)
    if size <= 0:
        out.diagnostics.append(
            diag("PAL-E501", owner_word.span if owner_word else step.span, command=owner.name)
        )
        out.stopped = True  # an error that stops decoding
        return state
    element = f"{owner.name} I{size:g}"
    out.commands.append(
        Blend(
            size if owner.name == "G302" else -size,
            element,
            step.values.get("#FRC", state.feed),
            step.span,
        )
    )
    return dataclasses.replace(state, blend=size)


def _flow(step: _Step) -> None:
    """G22 call, G23 section repeat, G29 jump (when its condition holds)."""
    owner, words, values, out = step.reading.owner, step.reading.words, step.values, step.out
    if owner is None:
        return
    if owner.name == "G22":
        out.flow = ("call", int(values["L"]), int(values.get("H", 1)))
    elif owner.name == "G23":
        first_n, last_n = (int(n.value or 0) for n in words["N"])
        out.repeat = (first_n, last_n, int(values.get("H", 1)))
    elif owner.name == "G29" and ("P" not in words or _compare(step.params, words["P"], int(values["O"]))):
        out.flow = ("jump", int(values["N"]), 0)


def _block_end(step: _Step, state: ModalState) -> ModalState:
    """M5 and M9 at the block end; M30, M17 and M98 say where the program goes on."""
    out, ends = step.out, step.reading.ends
    if ends:
        state = ModalState(
            {**state.codes, **ends},
            state.feed,
            state.speed,
            state.tool,
            state.tc,
            state.tr,
            state.tl,
            state.pole,
            state.frame,
            state.blend,
            state.tangent,
            state.arc_radius,
            state.drill,
            state.pal_cycle,
        )
    for w, code in step.reading.ms:
        if code.name in ("M30", "M2"):
            out.ended = True
        elif code.name in ("M17", "M99"):
            out.sub_end = True
        elif code.name == "M98":
            out.flow = _subprogram_call(step.values, step.reading.words, w, out.diagnostics)
    return state


_SPELLINGS = frozenset({"XI", "YI", "ZI", "XA", "YA", "ZA"})
_CHECKED_OWNERS = frozenset({"G23", "G29", "G45", "G46", "G47", "G48", "G58", "G59"})


def _check_owner(
    owner: Code,
    owner_word: Word,
    in_block: frozenset[str],
    words: dict[str, list[Word]],
    values: dict[str, float],
    state: ModalState,
    d: list[Diagnostic],
) -> None:
    """The rules of the block-owning codes that a table of allowed words cannot say."""
    name, span = owner.name, owner_word.span
    needed = {"G45": ("G41", "G42"), "G47": ("G41", "G42"), "G46": ("G40",), "G48": ("G40",)}.get(name)
    if needed is not None:
        if not in_block.intersection(needed):
            d.append(diag("PAL-E219", span, command=name, needed=" oder ".join(needed)))
        if "R" in values and values["R"] <= 0:
            d.append(diag("PAL-E213", words["R"][0].span, address="R", raw=words["R"][0].raw))
    if name in ("G58", "G59") and (state.frame.mirror_x or state.frame.mirror_y):
        d.append(diag("PAL-E408", span, command=name))
    if name == "G58" and ("RP" in words) != ("AP" in words):
        d.append(diag("PAL-E102", span, address="AP" if "RP" in words else "RP", command="G58"))
    if name == "G29" and "P" in words:
        if len(words["P"]) != 2 or "O" not in values:
            d.append(diag("PAL-E102", span, address="P O P", command="G29"))
        elif values["O"] not in (1, 2, 3, 4):
            d.append(diag("PAL-E410", words["O"][0].span, value=words["O"][0].raw))
        for w in words["P"]:
            if w.value is not None and not 1 <= w.value <= 999:
                d.append(diag("PAL-E113", w.span, number=w.raw))
    if name == "G23" and len(words.get("N", ())) != 2:
        d.append(diag("PAL-E102", span, address="N N", command="G23"))


@dataclass(slots=True)
class Reading:
    """What a block says, before any state: its words sorted and checked. Not mutated once made."""

    gs: list[tuple[Word, Code]]
    ms: list[tuple[Word, Code]]
    words: dict[str, list[Word]]
    values: dict[str, float]
    owner: Code | None
    owner_word: Word | None
    motion: Code | None
    new_tool: int | None
    arc_plane: str
    diagnostics: list[Diagnostic]
    cacheable: bool
    in_block: frozenset[str]  # the names of its G codes
    planned: list[tuple[Word, Code]]  # codes not supported yet
    activations: list[tuple[str, str]]  # (modal group, code) switched at the block start
    ends: dict[str, str]  # modal group → code switched at the block end (M5, M9)
    moves: bool  # it has words of geometry  # no parameter expression: the same block always reads the same
    cycle: Code | None = None  # ISO: the drilling cycle that makes a hole in this block
    alt_plane: str | None = (
        None  # DIN: the plane of the end-point axes, for an R arc impossible in `arc_plane`
    )
    dropped: tuple[
        str, ...
    ] = ()  # DIN: the data words of a code not supported yet, which stay without effect


def _read(
    block: Block,
    table: CodeTable,
    setup: RunSetup,
    new_params: dict[int, float],
    modal_motion: str | None,
    modal_plane: str | None,
    modal_cycle: str | None = None,
) -> Reading:
    """Sort and check the words of `block` (`modal_motion`/`modal_plane`/`modal_cycle`: what is active before it)."""
    plain = _plain_reading(block, table, setup, modal_motion, modal_plane, modal_cycle)
    if plain is not None:
        return plain
    sorted_words = _sort_words(block, table, setup, new_params)
    return _checked(block, table, setup, sorted_words, modal_motion, modal_plane, modal_cycle)


def _checked(
    block: Block,
    table: CodeTable,
    setup: RunSetup,
    sorted_words: _Words,
    modal_motion: str | None,
    modal_plane: str | None,
    modal_cycle: str | None,
) -> Reading:
    """The reading of any block, its sorted words checked by every rule (the general path of `_read`)."""
    gs, ms, words, values = sorted_words.gs, sorted_words.ms, sorted_words.words, sorted_words.values
    flags, has_expr, d = sorted_words.flags, sorted_words.has_expr, sorted_words.d
    code_diags, unknown = sorted_words.code_diags, sorted_words.unknown
    # a cycle not supported yet, or a G code the dialect does not know, owns the block: which words it takes
    # is not known here, so the block gets the one diagnostic about its code and no follow-ups on its words
    unmodelled = next(((w, c) for w, c in gs if c.support is Support.PLANNED and c.owns_block), None)
    dropped: tuple[str, ...] = ()
    if unmodelled is not None and table.din and not any(x.code == "PAL-E105" for x in code_diags):
        # DIN/ISO: the code's data (every address but the technology) stay without effect, the rest of the block runs
        dropped = tuple(
            sorted({a for a in words if a not in table.technology_words} | {w.address for w in unknown})
        )
        words = {a: ws for a, ws in words.items() if a not in dropped}
        values = {a: v for a, v in values.items() if a not in dropped}
        flags = [w for w in flags if w.address not in dropped]
        gs = [(w, c) for w, c in gs if c is not unmodelled[1]]
        unknown = []
        d = [x for x in d if x.span.column not in {w.column for w in block.words if w.address in dropped}]
        code_diags.append(
            _not_supported_din(
                unmodelled[0].span, unmodelled[1].feature_de, unmodelled[1].feature_en, dropped
            )
        )
    elif unmodelled is not None or any(x.code == "PAL-E105" for x in code_diags):
        only = (
            [_not_supported(unmodelled[0].span, unmodelled[1].feature_de, unmodelled[1].feature_en, True)]
            if unmodelled is not None
            else code_diags
        )
        return Reading(
            gs,
            [],
            {},
            {},
            None,
            None,
            None,
            None,
            "G17",
            only,
            not has_expr,
            frozenset(c.name for _, c in gs),
            [],
            [],
            {},
            False,
        )
    d[:0] = code_diags + [diag("PAL-E003", w.address_span, address=w.address) for w in unknown]

    sorted_words.words, sorted_words.values, sorted_words.flags, sorted_words.gs = words, values, flags, gs
    sorted_words.d = d
    owner, owner_word = _owner(table, gs, ms, d)
    motion, cycle, names = _addresses(
        block, table, sorted_words, owner, owner_word, modal_motion, modal_cycle, d
    )
    new_tool, arc_plane, alt_plane = _tool_and_plane(
        table, setup, sorted_words, motion, cycle, names, modal_plane, d
    )
    activations, ends, planned = _switches(table, gs, ms, owner, motion, d)
    return Reading(
        gs,
        ms,
        words,
        values,
        owner,
        owner_word,
        motion,
        new_tool,
        arc_plane,
        d,
        not has_expr,
        names,
        planned,
        activations,
        ends,
        not words.keys().isdisjoint(_GEOMETRY_WORDS),
        cycle,
        alt_plane,
        dropped,
    )


@dataclass(slots=True)
class _Words:
    """A block's words sorted (the first step of `_read`)."""

    gs: list[tuple[Word, Code]]
    ms: list[tuple[Word, Code]]
    words: dict[str, list[Word]]
    values: dict[str, float]
    flags: list[Word]  # address words without a value
    has_expr: bool
    code_diags: list[Diagnostic]  # about the G and M words themselves
    unknown: list[Word]  # words of addresses the dialect does not have
    d: list[Diagnostic]


def _sort_words(block: Block, table: CodeTable, setup: RunSetup, new_params: dict[int, float]) -> _Words:
    """The block's G and M codes, its address words and their values, each word checked on its own."""
    d: list[Diagnostic] = []
    gs: list[tuple[Word, Code]] = []
    ms: list[tuple[Word, Code]] = []
    words: dict[str, list[Word]] = {}
    values: dict[str, float] = {}
    flags: list[Word] = []
    has_expr = False
    limit = setup.limits.max_abs_value
    addresses = table.addresses
    code_diags: list[Diagnostic] = []  # about the G and M words themselves
    unknown: list[Word] = []  # words of addresses the dialect does not have
    for w in block.words:
        a = w.address
        if a == "" and any(v.address == "G" and v.value == 4 for v in block.words):
            w = w._replace(address="X")  # Beckhoff: G04 3.0 is G04 X3.0
            a = "X"
        elif a == "":
            d.append(
                Diagnostic(
                    "PAL-E007",
                    Severity.ERROR,
                    w.span,
                    diag("PAL-E007", w.span, token=w.raw, expected="eine Adresse").message,
                    diag("PAL-E007", w.span, token=w.raw, expected="an address").message_en,
                )
            )
            continue
        if a == "G" or a == "M":
            code = _code_word(w, table, code_diags)
            if code is not None:
                (gs if a == "G" else ms).append((w, code))
            continue
        spec = addresses.get(a)
        if spec is None:
            if a.startswith(table.unsupported_prefixes) and table.unsupported_prefixes:
                text = w.raw if len(w.raw) <= 40 else w.raw[:39] + "…"
                code_diags.append(_not_supported_din(w.span, f"»{text}«", f"'{text}'", ()))
            else:
                unknown.append(w)
            continue
        words.setdefault(a, []).append(w)
        if w.expr is not None:
            has_expr = True
            v = evaluate(w.expr, new_params, w.line, d)
            if v is None:
                continue
        elif w.value is None:
            flags.append(w)  # a flag; checked below
            continue
        else:
            v = w.value
        if not -limit <= v <= limit:  # also catches NaN and infinity
            _in_range(v, a, w.span, setup, d)
            continue
        if spec.integer and v != int(v):
            d.append(diag("PAL-E108", w.span, address=a, raw=w.raw))
        values.setdefault(a, v)
    return _Words(gs, ms, words, values, flags, has_expr, code_diags, unknown, d)


_PLAIN_MOTIONS = frozenset({"G0", "G1", "G2", "G3"})
_PLAIN_WORDS = frozenset({"X", "Y", "Z", "I", "J", "K", "R", "F", "S", "RN"})


@dataclass(frozen=True, slots=True)
class _PlainLookups:
    """What `_plain_reading` asks of a dialect's table, made once per table: the plain words the table has, with
    their rules, and the written G0–G3 that may own a plain block, with what each switches and its G names."""

    rules: dict[str, tuple[bool, bool]]  # address → (a whole number, not negative)
    motions: dict[
        float, tuple[Code, list[tuple[str, str]], frozenset[str]]
    ]  # G number → code, switches, names


# id of a dialect's table → the table (kept, so that no other object gets its id) and its lookups
_PLAIN: dict[int, tuple[CodeTable, _PlainLookups]] = {}


def _plain_lookups(table: CodeTable) -> _PlainLookups:
    hit = _PLAIN.get(id(table))
    if hit is not None:
        return hit[1]
    rules = {
        a: (spec.integer, spec.non_negative)
        for a in _PLAIN_WORDS
        if (spec := table.addresses.get(a)) is not None
    }
    motions: dict[float, tuple[Code, list[tuple[str, str]], frozenset[str]]] = {}
    for number, code in table.numbered.get("G", _NO_CODES).items():
        if (
            code.name in _PLAIN_MOTIONS
            and code.group == "motion"
            and code.owns_block
            and not code.alone
            and code.support is Support.YES
            and table.max_g_words != 0
        ):
            switches = list(table.pairs[code.name])
            if table.has_cycles:
                switches.append(("cycle", "G80"))  # G00–G03 end a drilling cycle
            # (its readings share the switches and the names, and change nothing)
            motions[number] = (code, switches, frozenset((code.name,)))
    lookups = _PlainLookups(rules, motions)
    _PLAIN[id(table)] = (table, lookups)
    return lookups


def _plain_reading(
    block: Block,
    table: CodeTable,
    setup: RunSetup,
    modal_motion: str | None,
    modal_plane: str | None,
    modal_cycle: str | None,
) -> Reading | None:
    """The reading of the most common block, a move G0–G3 (written or modal) with plain words of the end
    point, the centre, the radius, F, S and RN — numbers, no expression — that breaks no rule; None for every
    other block, which the general path (`_sort_words`, then `_owner`, `_addresses`, `_tool_and_plane`,
    `_switches`) reads. It exists because most blocks are such moves, and they need none of the general path's
    cases: their words are sorted and checked here in one pass."""
    lookups = _plain_lookups(table)
    rules = lookups.rules
    written: tuple[Word, tuple[Code, list[tuple[str, str]], frozenset[str]]] | None = None
    words: dict[str, list[Word]] = {}
    values: dict[str, float] = {}
    limit = setup.limits.max_abs_value
    for w in block.words:
        a, v = w.address, w.value
        if v is None or w.expr is not None:
            return None
        if a == "G":
            motion_of = lookups.motions.get(v)
            if motion_of is None or written is not None:  # (another G code, or a second G word)
                return None
            written = (w, motion_of)
            continue
        rule = rules.get(a)
        if rule is None or a in words:  # (an M word, another address, an address given twice)
            return None
        if not -limit <= v <= limit or (rule[0] and v != int(v)) or (rule[1] and v < 0):
            return None  # (out of range, not a whole number, negative: the general path says so)
        words[a] = [w]
        values[a] = v
    gs: list[tuple[Word, Code]]
    if written is not None:
        owner_word, (owner, activations, names) = written
        motion = owner
        gs = [(owner_word, owner)]
    else:
        modal = table.codes.get(modal_motion or "G1")
        if (
            modal is None
            or modal.name not in _PLAIN_MOTIONS
            or modal_cycle not in (None, "G80")
            or words.keys() <= table.technology_words  # (a block of only F and S moves nothing)
        ):
            return None
        motion, owner, owner_word, activations, names, gs = modal, None, None, [], frozenset(), []
    if not words.keys() <= table.takes[motion.name]:
        return None
    for one_of in owner.required if owner is not None else ():
        if not any(a in words for a in one_of):  # a required address missing (PAL-E102): the general path
            return None
    arc_plane, alt_plane = "G17", None
    if motion.name in ("G2", "G3"):
        plane = modal_plane or "G17"
        if table.din:
            arc_plane, alt_plane = _din_arc_plane(plane, words)
        else:
            arc_plane = _arc_plane(plane, words, table)
        if not words.keys().isdisjoint(_FOREIGN_CENTRE_WORDS[arc_plane]):
            return None  # a centre word of another plane (PAL-E204)
    return Reading(
        gs,
        [],
        words,
        values,
        owner,
        owner_word,
        motion,
        None,
        arc_plane,
        [],
        True,  # (no expression: the same block always reads the same)
        names,
        [],
        activations,
        {},
        not words.keys().isdisjoint(_GEOMETRY_WORDS),
        None,
        alt_plane,
    )


def _owner(
    table: CodeTable, gs: list[tuple[Word, Code]], ms: list[tuple[Word, Code]], d: list[Diagnostic]
) -> tuple[Code | None, Word | None]:
    """G codes: their count, one member of each modal group, the code that owns the block."""
    if table.max_g_words is not None and len(gs) > table.max_g_words:
        d.append(diag("PAL-E104", gs[table.max_g_words][0].span, count=len(gs)))
    owner: Code | None = None
    owner_word: Word | None = None
    group_conflicts(table, gs + ms, d)
    for w, code in gs:
        if code.owns_block:
            if owner is not None and owner.group != code.group or (owner is not None and code.group is None):
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


def _addresses(
    block: Block,
    table: CodeTable,
    sorted_words: _Words,
    owner: Code | None,
    owner_word: Word | None,
    modal_motion: str | None,
    modal_cycle: str | None,
    d: list[Diagnostic],
) -> tuple[Code | None, Code | None, frozenset[str]]:
    """Which addresses the block may hold, which it must, and how often: (motion, drilling cycle, G names)."""
    gs, ms, words = sorted_words.gs, sorted_words.ms, sorted_words.words
    values, flags = sorted_words.values, sorted_words.flags
    motion = owner if owner is not None and owner.group == "motion" else None
    # the words that codes which do not own the block take (ISO: M98 P L, G28/G53 X Y Z; none in PAL)
    extra = frozenset().union(*(c.words for _, c in gs + ms if not c.owns_block))
    names = frozenset(c.name for _, c in gs)
    cycle: Code | None = owner if owner is not None and owner.group == "cycle" else None
    if (
        cycle is None
        and owner is None
        and modal_cycle not in (None, "G80")
        and "G80" not in names
        and names.isdisjoint(_HOMING)
        and not words.keys() <= table.technology_words | extra
    ):
        cycle = table.codes[modal_cycle]  # a block in cycle mode: the next hole
    if cycle is not None:
        allowed = cycle.words | extra
    elif owner is None and not words.keys() <= table.technology_words | extra:
        motion = table.codes[modal_motion or "G1"]
        allowed = motion.words | extra
    elif owner is not None:
        allowed = owner.words | extra
    else:
        allowed = table.tool_words | extra
    alone = owner is not None and owner.alone
    refused = words.keys() if alone else words.keys() - allowed - table.always_allowed
    if refused:
        command_name = str(owner_word) if owner is not None else f"{motion.name} (modal)" if motion else ""
        for a in [a for a in words if a in refused]:
            d.append(diag("PAL-E101", words[a][0].span, address=a, command=command_name))
    if len(words) < len(block.words) - len(gs) - len(ms):  # an address given twice
        twice = _OWNER_DUPLICATES.get(owner.name, set()) if owner is not None else set()
        for a, ws in words.items():
            if len(ws) > 1 and a not in refused and a not in twice:
                d.append(diag("PAL-E106", ws[1].span, address=a))
    for w in flags:
        if w.address not in refused and not (
            table.addresses[w.address].flag and owner and owner.name == "G66"
        ):
            d.append(diag("PAL-E111", w.span, address=w.address))
    if alone and len(gs) + len(ms) > 1:
        other = next(w for w, c in gs + ms if c is not owner)
        d.append(diag("PAL-E101", other.span, address=str(other), command=str(owner_word)))
    if not words.keys().isdisjoint(_SPELLINGS):  # an axis may be given in two spellings
        for spellings in _AXES:
            present = [s for s in spellings if s in words]
            if len(present) > 1:
                d.append(diag("PAL-E107", words[present[1]][0].span, first=present[0], second=present[1]))
    missing_words(gs + ms if table.din else gs, words, d)
    negative_values(table, values, lambda a: words[a][0], d)
    if "TC" in values and not 1 <= values["TC"] <= 9:
        d.append(diag("PAL-E112", words["TC"][0].span, value=words["TC"][0].raw))
    return motion, cycle, names


def _tool_and_plane(
    table: CodeTable,
    setup: RunSetup,
    sorted_words: _Words,
    motion: Code | None,
    cycle: Code | None,
    names: frozenset[str],
    modal_plane: str | None,
    d: list[Diagnostic],
) -> tuple[int | None, str, str | None]:
    """The tool called, the plane of an arc (its centre words), the dialect's own rules: (tool, plane, DIN's
    other plane)."""
    gs, ms, words, values = sorted_words.gs, sorted_words.ms, sorted_words.words, sorted_words.values
    new_tool: int | None = None
    if "T" in values:
        new_tool = int(values["T"])
        if new_tool != 0 and setup.tools.get(new_tool) is None:
            d.append(diag("PAL-E304", words["T"][0].span, tool=new_tool))
    arc_plane = "G17"
    alt_plane: str | None = None
    if motion is not None and motion.name in ("G2", "G3"):
        plane = next((c.name for _, c in gs if c.group == "plane"), None) or modal_plane
        if table.din:
            arc_plane, alt_plane = _din_arc_plane(plane or "G17", words)
        else:
            arc_plane = _arc_plane(plane or "G17", words, table)
        pw = PLANE_WORDS[arc_plane]
        for a in _FOREIGN_CENTRE_WORDS[arc_plane]:
            if a in words:
                d.append(
                    diag(
                        "PAL-E204",
                        words[a][0].span,
                        address=a,
                        plane=arc_plane,
                        centre="/".join(w for w in pw.centre_words if w in table.addresses),
                    )
                )
    if table.din:
        _check_din(table, gs, ms, words, values, cycle, d)
    else:
        if "D" in values or "AO" in values:
            for a in ("D", "AO"):
                if a in values and values[a] <= 0:
                    d.append(diag("PAL-E213", words[a][0].span, address=a, raw=words[a][0].raw))
        if (
            "H" in values
            and motion is not None
            and motion.name in ("G1", "G2", "G3")
            and values["H"] not in (1, 2)
        ):
            d.append(diag("PAL-E108", words["H"][0].span, address="H (1 oder 2)", raw=words["H"][0].raw))
    if "G70" in names and not table.din:
        d.append(diag("PAL-E309", next(w.span for w, c in gs if c.name == "G70")))
    return new_tool, arc_plane, alt_plane


def _switches(
    table: CodeTable,
    gs: list[tuple[Word, Code]],
    ms: list[tuple[Word, Code]],
    owner: Code | None,
    motion: Code | None,
    d: list[Diagnostic],
) -> tuple[list[tuple[str, str]], dict[str, str], list[tuple[Word, Code]]]:
    """What the codes switch at the block start and at its end, and the codes not supported yet."""
    activations: list[tuple[str, str]] = []
    ends: dict[str, str] = {}
    planned: list[tuple[Word, Code]] = []
    for w, c in gs + ms:
        for g, m in table.pairs[c.name]:
            if m in _END_OF_BLOCK:
                ends[g] = m
            else:
                activations.append((g, m))
        if c.support is Support.PLANNED:
            planned.append((w, c))
            if table.din:
                d.append(_not_supported_din(w.span, c.feature_de, c.feature_en, ()))
    if (
        motion is not None
        and owner is motion
        and "cycle" in table.group_of.values()
        and all(g != "cycle" for g, _ in activations)
    ):
        activations.append(("cycle", "G80"))  # G00–G03 end a drilling cycle
    return activations, ends, planned


def _compare(params: dict[int, float], operands: list[Word], op: int) -> bool:
    """The condition of G29 P<a> O<op> P<b>: O1 =, O2 ≠, O3 >, O4 <."""
    a, b = (params.get(int(w.value or 0), 0.0) for w in operands)
    return (a == b, a != b, a > b, a < b)[op - 1]


def _frame(
    setup: RunSetup,
    frame: Frame,
    zero: str | None,
    owner: Code | None,
    words: dict[str, list[Word]],
    values: dict[str, float],
) -> Frame:
    """The frame after this block's G53–G59, G50 and G66 (in that order)."""
    if zero is not None:
        # a zero point (G54–G57) or machine coordinates (G53) cancels shifts, rotations and mirroring
        g54 = setup.zero_offset("G54")
        base = setup.zero_offset(zero) if zero != "G53" else (0.0, 0.0, 0.0)
        new = Frame(base=(base[0] - g54[0], base[1] - g54[1], base[2] - g54[2]))
        frame = frame if new == frame else new
    if owner is None:
        return frame
    if owner.name == "G50":
        return Frame(base=frame.base)
    if owner.name == "G58":
        rp, ap = values.get("RP", 0.0), math.radians(values.get("AP", 0.0))
        return frame.shifted(
            rp * math.cos(ap), rp * math.sin(ap), values.get("ZA", 0.0), values.get("AR", 0.0)
        )
    if owner.name == "G59":
        return frame.shifted(
            values.get("XA", 0.0), values.get("YA", 0.0), values.get("ZA", 0.0), values.get("AR", 0.0)
        )
    if owner.name == "G66":
        # G66 X mirrors about the X axis: Y changes sign; G66 Y: X changes sign; G66 alone: off
        return dataclasses.replace(frame, mirror_x="Y" in words, mirror_y="X" in words)
    return frame


def _in_range(value: float, address: str, span: Span, setup: RunSetup, d: list[Diagnostic]) -> bool:
    limit = setup.limits.max_abs_value
    if -limit <= value <= limit:  # also False for NaN
        return True
    d.append(diag("PAL-E015", span, value=f"{value:.6g}", address=address, limit=f"{limit:g}"))
    return False


_NO_CODES: dict[float, Code] = {}


def _code_word(w: Word, table: CodeTable, d: list[Diagnostic]) -> Code | None:
    """The code table entry of a G or M word, or None after a diagnostic."""
    if w.expr is None and w.value is not None:  # the common case: a whole number the table has
        code = table.numbered.get(w.address, _NO_CODES).get(w.value)
        if code is not None:
            return code
    if w.value is None or w.expr is not None:
        d.append(
            diag("PAL-E111", w.span, address=w.address)
            if w.expr is None
            else diag("PAL-E115", w.span, address=w.address)
        )
        return None
    if not 0 <= w.value <= 9999 or w.value != int(w.value):
        decimal = f"{w.address}{w.value:g}"  # ISO: G50.1, G54.1
        if decimal in table.codes and 0 <= w.value <= 9999:
            return table.codes[decimal]
        d.append(diag("PAL-E108", w.span, address=w.address, raw=w.raw))
        return None
    name = f"{w.address}{int(w.value)}"
    code = table.codes.get(name)
    if code is None:
        if name in ("G18", "G19"):
            d.append(diag("PAL-E110", w.span, command=name))
        elif w.address == "G":
            d.append(diag("PAL-E105", w.span, code=name))
        else:
            d.append(diag("PAL-W103", w.span, code=int(w.value)))
    return code


def _not_supported(span: Span, de: str, en: str, skips: bool) -> Diagnostic:
    if skips:
        effect_de, effect_en = "der Satz wird nicht ausgeführt.", "the block is not executed."
    else:
        effect_de = "der Satz wird ohne diese Funktion ausgeführt."
        effect_en = "the block is executed without it."
    return diag("PAL-E901", span, feature=de, feature_en=en, effect=effect_de, effect_en=effect_en)


def _target(
    state: ModalState,
    position: Vec3,
    values: dict[str, float],
    words: dict[str, list[Word]],
    d: list[Diagnostic],
) -> Vec3:
    """The end point from X/XI/XA, Y/YI/YA, Z/ZI/ZA under G90 or G91."""
    incremental = state.codes.get("dimensions") == "G91"
    if values.keys().isdisjoint(_SPELLINGS):  # the common case, X Y Z only: no loop over the spellings
        x, y, z = position
        if "X" in values:
            x = x + values["X"] if incremental else values["X"]
        if "Y" in values:
            y = y + values["Y"] if incremental else values["Y"]
        if "Z" in values:
            z = z + values["Z"] if incremental else values["Z"]
        return (x, y, z)
    out = list(position)
    for i, (plain, inc, absolute) in enumerate(_AXES):
        if plain in values:
            out[i] = position[i] + values[plain] if incremental else values[plain]
        elif inc in values:
            out[i] = position[i] + values[inc]
            if incremental:
                d.append(diag("PAL-I101", words[inc][0].span, address=inc, mode="G91", meaning="Kettenmaß"))
        elif absolute in values:
            out[i] = values[absolute]
            if not incremental:
                d.append(
                    diag(
                        "PAL-I101",
                        words[absolute][0].span,
                        address=absolute,
                        mode="G90",
                        meaning="Absolutmaß",
                    )
                )
    return (out[0], out[1], out[2])


def _motion(
    setup: RunSetup,
    state: ModalState,
    position: Vec3,
    name: str,
    words: dict[str, list[Word]],
    values: dict[str, float],
    span: Span,
    exact: bool,
    arc_plane: str,
    strict: bool,
    d: list[Diagnostic],
    din: bool = False,
) -> tuple[Move | None, tuple[float, float] | None]:
    """The programmed move of a motion block, and the pole it programs (G10–G13)."""
    end = _target(state, position, values, words, d)
    spindle_code = state.codes.get("spindle")
    spindle_on = spindle_code in ("M3", "M4")
    pole: tuple[float, float] | None = None
    if name in ("G10", "G11", "G12", "G13"):
        pole = _pole(state, position, values)
        found = _polar_end(position, end, pole, name, values, span, d)
        if found is None:
            return None, pole
        end = found
        name = {"G10": "G0", "G11": "G1", "G12": "G2", "G13": "G3"}[name]
        if name in ("G2", "G3"):
            values = {**values, "IA": pole[0], "JA": pole[1], "X": end[0], "Y": end[1]}
            values.pop("I", None)
            values.pop("J", None)
            words = {**words, "X": words.get("AP") or words["AI"], "Y": words.get("AP") or words["AI"]}
    elif name == "G1" and not din and ("D" in values or "AS" in values):  # (DIN: D is the tool offset)
        found = _line_end(position, end, values, words, span, d)
        if found is None:
            return None, None
        end = found
    if name == "G0" or name == "G1":
        if end == position:
            return None, pole
        if name == "G0":
            return _move(state, "rapid", position, end, span, spindle_code, exact_stop=True), pole
        _check_cutting(state, spindle_on, span, d, strict)
        return _move(state, "feed", position, end, span, spindle_code, exact_stop=exact), pole
    clockwise = name == "G2"
    s_uvw, e_uvw = to_plane(position, arc_plane), to_plane(end, arc_plane)
    arc = _arc(setup, s_uvw, e_uvw, PLANE_WORDS[arc_plane], values, words, clockwise, name, span, d)
    if arc is None:
        return None, pole
    centre, arc_end, radius = arc
    end = from_plane((arc_end[0], arc_end[1], e_uvw[2]), arc_plane)
    angle = sweep((s_uvw[0], s_uvw[1]), arc_end, centre, clockwise)
    _check_cutting(state, spindle_on, span, d, strict)
    return _move(
        state,
        "arc",
        position,
        end,
        span,
        spindle_code,
        exact_stop=exact,
        center=from_plane((centre[0], centre[1], s_uvw[2]), arc_plane),
        direction="cw" if clockwise else "ccw",
        radius=radius,
        angle=angle,
        plane=arc_plane,
    ), pole


def _pole(state: ModalState, position: Vec3, values: dict[str, float]) -> tuple[float, float]:
    """The pole of a polar block: I/J from the start, IA/JA absolute, else the last pole (DECISIONS §5)."""
    px = values["IA"] if "IA" in values else position[0] + values["I"] if "I" in values else state.pole[0]
    py = values["JA"] if "JA" in values else position[1] + values["J"] if "J" in values else state.pole[1]
    return (px, py)


def _polar_end(
    position: Vec3,
    end: Vec3,
    pole: tuple[float, float],
    name: str,
    values: dict[str, float],
    span: Span,
    d: list[Diagnostic],
) -> Vec3 | None:
    start_angle = math.degrees(math.atan2(position[1] - pole[1], position[0] - pole[0]))
    angle = values["AP"] if "AP" in values else start_angle + values.get("AI", 0.0)
    if name in ("G10", "G11"):
        radius = values["RP"]
    else:
        radius = math.dist((position[0], position[1]), pole)
        if radius < 1e-6:
            d.append(diag("PAL-E221", span, command=name))
            return None
    a = math.radians(angle)
    return (pole[0] + radius * math.cos(a), pole[1] + radius * math.sin(a), end[2])


def _line_end(
    position: Vec3,
    end: Vec3,
    values: dict[str, float],
    words: dict[str, list[Word]],
    span: Span,
    d: list[Diagnostic],
) -> Vec3 | None:
    """G1 end point from two of X, Y, D (length in the plane), AS (angle to +X); H picks one of two."""
    has_x = any(a in words for a in _AXES[0])
    has_y = any(a in words for a in _AXES[1])
    given = [n for n, ok in (("X", has_x), ("Y", has_y), ("D", "D" in values), ("AS", "AS" in values)) if ok]
    if len(given) > 2:
        d.append(diag("PAL-E211", span))
        return None
    if len(given) < 2:
        d.append(diag("PAL-E212", span, address=given[0]))
        return None
    sx, sy = position[0], position[1]
    ex, ey = end[0], end[1]
    if "AS" in values:
        a = math.radians(values["AS"])
        ca, sa = math.cos(a), math.sin(a)
        if "D" in values:
            ex, ey = sx + values["D"] * ca, sy + values["D"] * sa
        elif has_x:
            if abs(ca) < 1e-9:
                d.append(
                    diag(
                        "PAL-E210",
                        span,
                        reason="die Gerade mit AS verläuft parallel zur Y-Achse",
                        reason_en="the line with AS runs parallel to the Y axis",
                    )
                )
                return None
            ey = sy + (ex - sx) * sa / ca
        else:
            if abs(sa) < 1e-9:
                d.append(
                    diag(
                        "PAL-E210",
                        span,
                        reason="die Gerade mit AS verläuft parallel zur X-Achse",
                        reason_en="the line with AS runs parallel to the X axis",
                    )
                )
                return None
            ex = sx + (ey - sy) * ca / sa
    else:
        length = values["D"]
        if has_x:
            h2 = length * length - (ex - sx) ** 2
            if h2 < -1e-9:
                d.append(
                    diag(
                        "PAL-E210",
                        span,
                        reason=f"D{length:g} ist kürzer als der X-Weg {abs(ex - sx):g}",
                        reason_en=f"D{length:g} is shorter than the X distance {abs(ex - sx):g}",
                    )
                )
                return None
            h = math.sqrt(max(h2, 0.0))
            candidates = [(ex, sy + h), (ex, sy - h)]
        else:
            h2 = length * length - (ey - sy) ** 2
            if h2 < -1e-9:
                d.append(
                    diag(
                        "PAL-E210",
                        span,
                        reason=f"D{length:g} ist kürzer als der Y-Weg {abs(ey - sy):g}",
                        reason_en=f"D{length:g} is shorter than the Y distance {abs(ey - sy):g}",
                    )
                )
                return None
            h = math.sqrt(max(h2, 0.0))
            candidates = [(sx + h, ey), (sx - h, ey)]
        # H1: the smaller rise angle (counter-clockwise from +X, in [0°, 360°)), H2 the larger (DECISIONS §4)
        pick = max if int(values.get("H", 1)) == 2 else min
        ex, ey = pick(candidates, key=lambda p: angle_of((p[0] - sx, p[1] - sy)))
    return (ex, ey, end[2])


def _move(
    state: ModalState,
    kind: MoveKind,
    start: Vec3,
    end: Vec3,
    span: Span,
    spindle_code: str | None,
    exact_stop: bool,
    center: Vec3 | None = None,
    direction: Literal["cw", "ccw"] | None = None,
    radius: float | None = None,
    angle: float | None = None,
    plane: str | None = None,
) -> Move:
    """A move carrying the technology active in `state`."""
    spindle_on = spindle_code == "M3" or spindle_code == "M4"
    codes = state.codes
    return Move(
        kind,
        start,
        end,
        state.feed,
        "mm/rev" if codes.get("feed_mode") == "G95" else "mm/min",
        state.speed if spindle_on else 0.0,
        ("cw" if spindle_code == "M3" else "ccw") if spindle_on else None,
        codes.get("coolant") in ("M7", "M8"),
        state.tool,
        span,
        center,
        direction,
        radius,
        angle,
        exact_stop,
        plane or codes.get("plane") or "G17",
    )


def _check_cutting(
    state: ModalState, spindle_on: bool, span: Span, d: list[Diagnostic], strict: bool = True
) -> None:
    """Feed 0 is always an error; a cut with no tool or a stopped spindle is one in PAL, a warning elsewhere."""
    if state.feed == 0:
        d.append(diag("PAL-E301", span))
    severity = None if strict else Severity.WARNING
    if state.tool is None:
        d.append(diag("PAL-E303", span, severity))
    elif not spindle_on:
        d.append(diag("PAL-E302", span, severity))


def _arc(
    setup: RunSetup,
    position: Vec3,
    end: Vec3,
    pw: PlaneWords,
    values: dict[str, float],
    words: dict[str, list[Word]],
    clockwise: bool,
    name: str,
    span: Span,
    d: list[Diagnostic],
) -> tuple[tuple[float, float], tuple[float, float], float] | None:
    """Centre, end and radius, in plane coordinates (u, v), of a G2/G3 arc from any three of the plane's two
    end-point axes, its two centre coordinates (incremental or absolute), R and AO; a fourth must agree.

    The centre alone (no end point) is a full circle. Of several solutions the sign of R (written out)
    or else O1/O2 picks the shorter or longer arc, then H1/H2 the smaller or larger start tangent angle.
    """
    s = (position[0], position[1])
    has_x = not words.keys().isdisjoint(pw.u)
    has_y = not words.keys().isdisjoint(pw.v)
    cx = _centre(values, pw.cu, s[0])
    cy = _centre(values, pw.cv, s[1])
    r_word = words["R"][0] if "R" in words else None
    radius = abs(values["R"]) if "R" in values else None
    ao = values.get("AO")
    given = has_x + has_y + (cx is not None) + (cy is not None) + (radius is not None) + (ao is not None)
    tol = setup.arc_tolerance
    full_circle = not has_x and not has_y and cx is not None and cy is not None and ao is None
    if given < 3 and not full_circle:
        d.append(diag("PAL-E203", span, command=name))
        return None
    if r_word is not None and (full_circle or (has_x and has_y and math.dist(s, (end[0], end[1])) < 1e-6)):
        d.append(diag("PAL-E205", r_word.span))
        return None
    if cx is not None and cy is not None and math.dist(s, (cx, cy)) < 1e-6:
        d.append(diag("PAL-E206", span))
        return None
    if has_x and has_y and cx is not None and cy is not None and radius is None and ao is None:
        # the usual form, end point and centre: the end must lie on the circle (Kreisendpunktfehler)
        r_s, r_e = math.dist(s, (cx, cy)), math.dist((end[0], end[1]), (cx, cy))
        if abs(r_s - r_e) > tol:
            d.append(diag("PAL-E202", span, r_start=round(r_s, 4), r_end=round(r_e, 4), tolerance=tol))
            return None
        return (cx, cy), (end[0], end[1]), r_s
    solutions = arc_solutions(
        s, clockwise, end[0] if has_x else None, end[1] if has_y else None, cx, cy, radius, ao, tol
    )
    if given >= 4 or full_circle:
        if len(solutions) == 1:
            c, e = solutions[0]
            return c, e, math.dist(s, c)
        if cx is not None and cy is not None and has_x and has_y and radius is None and ao is None:
            r_s, r_e = math.dist(s, (cx, cy)), math.dist((end[0], end[1]), (cx, cy))
            d.append(diag("PAL-E202", span, r_start=round(r_s, 4), r_end=round(r_e, 4), tolerance=tol))
        else:
            d.append(
                diag(
                    "PAL-E202",
                    span,
                    r_start=round(radius or math.dist(s, (cx or s[0], cy or s[1])), 4),
                    r_end="?",
                    tolerance=tol,
                )
            )
        return None
    if not solutions:
        if radius is not None and has_x and has_y:
            chord = math.dist(s, (end[0], end[1]))
            d.append(
                diag(
                    "PAL-E201",
                    r_word.span if r_word else span,
                    reason=f"Radius {radius:g} mm ist kleiner als die halbe Sehne {chord / 2:.3f} mm",
                    reason_en=f"radius {radius:g} mm is less than half the chord {chord / 2:.3f} mm",
                )
            )
        else:
            d.append(
                diag(
                    "PAL-E201",
                    span,
                    reason="die angegebenen Adressen passen zu keinem Kreisbogen",
                    reason_en="the given addresses fit no arc",
                )
            )
        return None
    # The sign of R written out wins over O; R+ (or O1) is the shorter arc, R- (or O2) the longer.
    if r_word is not None and r_word.raw[:1] in "+-":
        longer = r_word.raw.startswith("-")
    else:
        longer = int(values.get("O", 1)) == 2
    chosen = choose_arc(s, clockwise, solutions, longer, int(values.get("H", 1)) == 2)
    assert chosen is not None
    c, e = chosen
    return c, e, math.dist(s, c)


@dataclass(frozen=True, slots=True)
class PlaneWords:
    """The words of arcs in one plane: end-point axes u and v, centre words (incremental, absolute)."""

    u: tuple[str, ...]
    v: tuple[str, ...]
    cu: tuple[str, str]
    cv: tuple[str, str]
    centre_words: frozenset[str] = field(init=False)  # cu and cv

    def __post_init__(self) -> None:
        object.__setattr__(self, "centre_words", frozenset((*self.cu, *self.cv)))


PLANE_WORDS = {
    "G17": PlaneWords(_AXES[0], _AXES[1], ("I", "IA"), ("J", "JA")),
    "G18": PlaneWords(_AXES[2], _AXES[0], ("K", "KA"), ("I", "IA")),
    "G19": PlaneWords(_AXES[1], _AXES[2], ("J", "JA"), ("K", "KA")),
}
_CENTRE_WORDS = frozenset({"I", "J", "K", "IA", "JA", "KA"})
_IJK = frozenset({"I", "J", "K"})
# plane → the centre words of the other planes (PAL-E204)
_FOREIGN_CENTRE_WORDS = {name: _CENTRE_WORDS - pw.centre_words for name, pw in PLANE_WORDS.items()}
_PLANE_OF_AXES = {frozenset((i, j)): name for name, (i, j, _) in AXES.items()}  # {0, 1} → G17 …


def _axes_named(words: dict[str, list[Word]]) -> str | None:
    """The plane of the block's end-point axes when they are two (X and Y: G17), else None."""
    keys = words.keys()
    axes = frozenset(i for i in (0, 1, 2) if not keys.isdisjoint(_AXES[i]))
    return _PLANE_OF_AXES.get(axes)


def _arc_plane(plane: str, words: dict[str, list[Word]], table: CodeTable) -> str:
    """The plane of an arc: the selected one, unless the block's two end-point axes name another
    (an arc "outside the selected plane", where the dialect has more than one plane)."""
    if "G18" not in table.codes:
        return plane
    return _axes_named(words) or plane


def _centre(values: dict[str, float], words: tuple[str, str], start: float) -> float | None:
    incremental, absolute = words
    if absolute in values:
        return values[absolute]
    return start + values[incremental] if incremental in values else None


# the words that ask for a transition at the end of a motion block: (sign, chamfer by length)
_TRANSITION_WORDS = {
    "RN": (1.0, False),
    "G302": (1.0, False),
    "#RND": (1.0, False),
    "G301": (-1.0, False),
    "#CHR": (-1.0, False),
    "#CHF": (-1.0, True),
}


def _transition(values: dict[str, float], words: dict[str, list[Word]]) -> tuple[float, str, bool]:
    """RN (signed: + rounding, - chamfer), or Beckhoff's G301=/G302=/#CHR/#CHF/#RND: size, text, by length."""
    if values.keys().isdisjoint(_TRANSITION_WORDS):
        return 0.0, "", False
    for name, (sign, by_length) in _TRANSITION_WORDS.items():
        if name in values:
            w = words[name][0]
            return sign * values[name] if name != "RN" else values[name], f"{name}{w.raw}", by_length
    return 0.0, "", False


def _compensation(setup: RunSetup, state: ModalState) -> tuple[int, float]:
    """Side (+1 left, -1 right, 0 off) and effective tool radius (offset memory TC + TR) of `state`."""
    code = state.codes["compensation"]
    if code == "G40" or state.tc == 0:  # (DIN: D0 is no tool offset)
        return 0, 0.0
    side = 1 if code == "G41" else -1 if code == "G42" else 0
    tool = setup.tools.get(state.tool) if state.tool is not None else None
    return side, (tool.offset(state.tc).radius + state.tr) if tool is not None and side else 0.0


def _approach(
    setup: RunSetup,
    state: ModalState,
    position: Vec3,
    name: str,
    words: dict[str, list[Word]],
    values: dict[str, float],
    span: Span,
    d: list[Diagnostic],
) -> Planned:
    """G45/G47 (with G41/G42) to the first contour point, in program coordinates."""
    end = _target(state, position, values, words, d)
    z = end[2] if any(a in values for a in _AXES[2]) else None
    w = values.get("W")
    if z is None and w is not None:  # the tool rises or sinks to W and stays there
        end = (end[0], end[1], w)
    move = _move(
        state,
        "feed" if state.active("motion") != "G0" else "rapid",
        position,
        end,
        span,
        state.active("spindle"),
        exact_stop=False,
    )
    side, radius = _compensation(setup, state)
    oz = state.frame.origin[2]
    size = values["D"] if name == "G45" else values["R"]
    return Planned(
        move,
        side=side,
        radius=radius,
        approach=Approach(
            name, size, None if w is None else w + oz, values.get("E"), None if z is None else z + oz
        ),
    )


def _departure(
    setup: RunSetup,
    before: ModalState,
    state: ModalState,
    position: Vec3,
    name: str,
    words: dict[str, list[Word]],
    values: dict[str, float],
    span: Span,
    d: list[Diagnostic],
) -> Planned:
    """G46/G48 (with G40) off the last contour point: the move from `position` (the contour point, workpiece
    frame) to where the tool centre ends, at the height Z, then W, of the block."""
    frame = state.frame
    target = _target(state, frame.to_program(position), values, words, d)
    oz = frame.origin[2]
    z = target[2] + oz if any(a in values for a in _AXES[2]) else None
    w = values["W"] + oz if "W" in values else None
    side, radius = _compensation(setup, before)
    side = -side if frame.flips else side
    size = values["D"] if name == "G46" else values["R"]
    tangent = before.tangent if side else None
    height = w if w is not None else z if z is not None else position[2]
    if tangent is None:  # no departure in the plane: only the moves to Z and W
        tool_end, programmed = (position[0], position[1]), (position[0], position[1])
    else:
        tool_end, programmed = departure_ends(name, (position[0], position[1]), tangent, side, radius, size)
    move = _move(
        state,
        "feed",
        position,
        (tool_end[0], tool_end[1], height),
        span,
        state.active("spindle"),
        exact_stop=False,
    )
    return Planned(
        move, departure=Departure(name, size, w, z, tangent, (programmed[0], programmed[1], position[2]))
    )


# -- DIN 66025 / ISO (SINUMERIK ISO, Beckhoff): what PAL does not have ------------------------------------------

_INCH = frozenset({"G20", "G70"})
_HOMING = frozenset({"G28", "G53"})
_LENGTHS = ("X", "Y", "Z", "I", "J", "K", "R", "Q", "F", "#CHR", "#CHF", "#RND", "#FRC", "G301", "G302")


def _in_mm(values: dict[str, float], cycle: bool) -> dict[str, float]:
    """The values of an inch block in mm (and F in mm/min or mm/rev); K of a drilling cycle is a count."""
    return {a: v * 25.4 if a in _LENGTHS and not (cycle and a == "K") else v for a, v in values.items()}


def _not_supported_din(span: Span, de: str, en: str, dropped: tuple[str, ...]) -> Diagnostic:
    """A code the control knows and the product does not model: a warning, the rest of the block runs."""
    if dropped:
        listed = ", ".join(dropped)
        effect_de = f"seine Angaben ({listed}) bleiben ohne Wirkung, der Rest des Satzes wird ausgeführt."
        effect_en = f"its data ({listed}) have no effect, the rest of the block is executed."
    else:
        effect_de, effect_en = (
            "der Satz wird ohne diese Funktion ausgeführt.",
            "the block is executed without it.",
        )
    return diag("PAL-W901", span, feature=de, feature_en=en, effect=effect_de, effect_en=effect_en)


def _check_din(
    table: CodeTable,
    gs: list[tuple[Word, Code]],
    ms: list[tuple[Word, Code]],
    words: dict[str, list[Word]],
    values: dict[str, float],
    cycle: Code | None,
    d: list[Diagnostic],
) -> None:
    """The rules of the DIN/ISO words that a table of allowed words cannot say."""
    if cycle is not None:
        for a in ("K", "L"):
            if a in values and values[a] != int(values[a]):
                d.append(diag("PAL-E108", words[a][0].span, address=a, raw=words[a][0].raw))
    if (
        any(c.name == "M98" for _, c in ms)
        and "P" in values
        and (values["P"] != int(values["P"]) or values["P"] < 1)
    ):
        d.append(diag("PAL-E108", words["P"][0].span, address="P (Programmnummer)", raw=words["P"][0].raw))


def _din_arc_plane(plane: str, words: dict[str, list[Word]]) -> tuple[str, str | None]:
    """The plane of a DIN arc, and the plane of its end-point axes where an R arc may have to go there.

    The arc stays in the selected plane unless its centre words cannot belong to it: then it lies in the plane of
    its end-point axes if they hold the centre words, else in the plane that does (G17 X.. Z.. I.. J.. is a helix
    in G17, G17 Z.. X.. K.. I.. an arc in G18). An arc with R (its centre words then have no effect) leaves the
    plane only where R is impossible in it (decided with the geometry, core.interpreter.pal_mill._din_motion)."""
    named = _axes_named(words)
    centre: set[str] = set() if "R" in words else words.keys() & _IJK  # (with R: no centre)
    if not centre:
        return plane, named if named != plane else None
    if centre <= PLANE_WORDS[plane].centre_words:
        return plane, None
    if named is not None and centre <= PLANE_WORDS[named].centre_words:
        return named, None
    for name in ("G17", "G18", "G19"):
        if centre <= PLANE_WORDS[name].centre_words:
            return name, None
    return plane, None


def _din_motion(
    setup: RunSetup,
    state: ModalState,
    position: Vec3,
    name: str,
    words: dict[str, list[Word]],
    values: dict[str, float],
    span: Span,
    exact: bool,
    arc_plane: str,
    alt_plane: str | None,
    table: CodeTable,
    d: list[Diagnostic],
) -> tuple[Move | None, float | None]:
    """A G02/G03 block of a DIN dialect: the arc, and the radius it programs (Beckhoff keeps it for the next arcs)."""
    end = _target(state, position, values, words, d)
    clockwise = name == "G2"
    has_centre = not values.keys().isdisjoint(("I", "J", "K"))
    r_word = words["R"][0] if "R" in words else None
    radius = values.get("R")
    if radius is None and not has_centre and table.modal_radius:
        radius = state.arc_radius
    if radius is not None and has_centre:
        for a in ("I", "J", "K"):
            if a in words:
                d.append(diag("PAL-W105", words[a][0].span, address=a, command=f"{name} mit R"))
        has_centre = False
    if not has_centre and radius is None:
        pw = PLANE_WORDS[arc_plane]
        d.append(diag("DIN-E203", span, command=name, centre="/".join(pw.cu[:1] + pw.cv[:1])))
        return None, None
    if (
        table.modal_radius
        and r_word is not None
        and not has_centre
        and not any(a in words for spellings in _AXES for a in spellings)
    ):
        return None, radius  # Beckhoff: R alone programs the radius of the next arcs, no motion yet
    if has_centre:
        rules = (
            din_arcs.beckhoff_rules(state.codes.get("centre_correction") != "G164", setup.arc_tolerance)
            if table.centre_correction
            else din_arcs.ArcRules(setup.arc_tolerance, table.arc_tolerance_factor)
        )
    else:
        rules = din_arcs.ArcRules(setup.arc_tolerance, table.arc_tolerance_factor)
    absolute = state.codes.get("centre_mode") == "G161"
    planes = [arc_plane] + ([alt_plane] if alt_plane is not None and not has_centre else [])
    attempts: list[tuple[str, Any, list[Diagnostic], Vec3, Vec3]] = []
    for plane in planes:
        s_uvw, e_uvw = to_plane(position, plane), to_plane(end, plane)
        centre: tuple[float, float] | None = None
        if has_centre:
            pw = PLANE_WORDS[plane]
            cu, cv = values.get(pw.cu[0], 0.0), values.get(pw.cv[0], 0.0)
            if absolute:  # G161: I, J, K are the centre itself (an omitted one: the start point's coordinate)
                cu = cu if pw.cu[0] in values else s_uvw[0]
                cv = cv if pw.cv[0] in values else s_uvw[1]
                centre = (cu, cv)
            else:
                centre = (s_uvw[0] + cu, s_uvw[1] + cv)
        tried: list[Diagnostic] = []
        solved = din_arcs.din_arc(
            (s_uvw[0], s_uvw[1]), (e_uvw[0], e_uvw[1]), centre, r_word, radius, clockwise, rules, span, tried
        )
        attempts.append((plane, solved, tried, s_uvw, e_uvw))
        if solved is not None:
            break
    # the plane where the arc exists; where it exists in none, the findings of the selected plane
    arc_plane, found, tried, s_uvw, e_uvw = attempts[-1] if attempts[-1][1] is not None else attempts[0]
    d.extend(tried)
    if found is None:
        return None, radius
    centre_uv, arc_end, r = found
    end = from_plane((arc_end[0], arc_end[1], e_uvw[2]), arc_plane)
    angle = sweep((s_uvw[0], s_uvw[1]), arc_end, centre_uv, clockwise)
    spindle_code = state.active("spindle")
    _check_cutting(state, spindle_code in ("M3", "M4"), span, d, table.strict_technology)
    move = _move(
        state,
        "arc",
        position,
        end,
        span,
        spindle_code,
        exact_stop=exact,
        center=from_plane((centre_uv[0], centre_uv[1], s_uvw[2]), arc_plane),
        direction="cw" if clockwise else "ccw",
        radius=r,
        angle=angle,
        plane=arc_plane,
    )
    return move, radius if radius is not None and not has_centre else state.arc_radius


def _din_modes(state: ModalState) -> ModalState:
    """What a DIN block changes besides the modal groups: G80 (or G00–G03) ends the drilling cycle's data."""
    if state.drill is not None and state.codes.get("cycle") in (None, "G80"):
        return dataclasses.replace(state, drill=None)
    return state


def _drill(
    setup: RunSetup,
    state: ModalState,
    position: Vec3,
    cycle: Code,
    values: dict[str, float],
    words: dict[str, list[Word]],
    span: Span,
    commands: list[Command],
    d: list[Diagnostic],
) -> tuple[Vec3, ModalState]:
    """A block in cycle mode: the cycle's data, and the holes when it programs X, Y, Z or R."""
    frame = state.frame
    here = position if frame.identity else frame.to_program(position)
    data = state.drill if state.drill is not None else DrillData(initial=here[2])
    data = iso_cycles.update(data, values)
    if data != state.drill:
        state = dataclasses.replace(state, drill=data)
    if not iso_cycles.drills(values):
        return position, state
    if state.codes.get("plane", "G17") != "G17":
        d.append(
            _not_supported_din(
                span,
                f"Bohrzyklus {cycle.name} in der Ebene {state.codes.get('plane')}",
                f"Drilling cycle {cycle.name} in the plane {state.codes.get('plane')}",
                (),
            )
        )
        return position, state
    spindle_code = state.active("spindle")
    template = _move(state, "feed", here, here, span, spindle_code, exact_stop=False)
    _check_cutting(state, spindle_code in ("M3", "M4"), span, d, False)
    compensation = state.codes.get("compensation")
    if compensation in ("G41", "G42"):
        d.append(diag("ISO-W405", span, code=cycle.name, compensation=compensation))
    made = iso_cycles.holes(
        cycle.name,
        data,
        here,
        values,
        words,
        state.active("dimensions") == "G91",
        state.codes.get("cycle_return") != "G99",
        template,
        setup,
        span,
        d,
    )
    if made is None:
        return position, state
    items, end = made
    for item in items:
        if isinstance(item, Move):
            commands.append(Planned(frame.map_move(item)))
        else:
            commands.append(Dwell(frame.to_workpiece(item.position), item.seconds, item.span))
    return frame.to_workpiece(end), state


def _cycle_call(
    setup: RunSetup,
    state: ModalState,
    position: Vec3,
    name: str,
    values: dict[str, float],
    span: Span,
    commands: list[Command],
    d: list[Diagnostic],
) -> Vec3:
    """A PAL cycle call G76–G79: the active definition at the call's points (core.interpreter.pal_cycles)."""
    frame = state.frame
    here = position if frame.identity else frame.to_program(position)
    spindle_code = state.active("spindle")
    template = _move(state, "feed", here, here, span, spindle_code, exact_stop=False)
    definition = state.pal_cycle
    before = len(d)
    if definition is not None and definition.code == "G84":
        if spindle_code not in ("M3", "M4"):
            d.append(diag("PAL-W606", span))
        if state.tool is None:
            d.append(diag("PAL-E303", span))
    elif definition is not None:
        feed = definition.feed if definition.feed is not None else state.feed
        _check_cutting(dataclasses.replace(state, feed=feed), spindle_code in ("M3", "M4"), span, d)
    if any(x.severity is Severity.ERROR for x in d[before:]):
        return position
    made = pal_cycles.call(setup, state, here, name, values, template, span, d)
    if made is None:
        return position
    items, end = made
    for item in items:
        if isinstance(item, Move):
            commands.append(Planned(frame.map_move(item)))
        else:
            commands.append(Dwell(frame.to_workpiece(item.position), item.seconds, item.span))
    return frame.to_workpiece(end)


def _home(
    setup: RunSetup,
    state: ModalState,
    position: Vec3,
    values: dict[str, float],
    words: dict[str, list[Word]],
    g28: bool,
    span: Span,
    commands: list[Command],
    d: list[Diagnostic],
) -> Vec3:
    """ISO G28 (rapid to the intermediate point, then to the reference point) or G53 (rapid to machine
    coordinates, counted from the reference point), the programmed axes only."""
    frame = state.frame
    ref = setup.reference
    spindle_code = state.active("spindle")
    points: list[Vec3] = []
    if g28:
        here = frame.to_program(position)
        points.append(frame.to_workpiece(_target(state, here, values, words, d)))
        last = points[-1]
        points.append(_axes_from(last, {i: ref[i] for i in range(3) if _AXES[i][0] in values}))
    else:
        points.append(
            _axes_from(position, {i: ref[i] + values[_AXES[i][0]] for i in range(3) if _AXES[i][0] in values})
        )
    for p in points:
        if p != position:
            commands.append(Planned(_move(state, "rapid", position, p, span, spindle_code, exact_stop=True)))
            position = p
    return position


def _axes_from(p: Vec3, new: dict[int, float]) -> Vec3:
    """`p` with the coordinates `new` (axis index → value) replaced."""
    return (new.get(0, p[0]), new.get(1, p[1]), new.get(2, p[2]))


def _subprogram_call(
    values: dict[str, float], words: dict[str, list[Word]], w: Word, d: list[Diagnostic]
) -> tuple[str, int, int] | None:
    """M98 P…: the program (the last four digits of P) and the number of runs (the digits before them, or L)."""
    if "P" not in values:
        return None
    p = int(values["P"])
    number, runs = (p % 10000, p // 10000) if p > 9999 else (p, 1)
    if "L" in values:
        runs = int(values["L"])
    return ("call", number, runs)
