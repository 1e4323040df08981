"""PAL milling: the execution of one block, (state, block) → (state, commands, diagnostics).

A block is a transaction in a fixed order: check every word (unknown, not allowed, missing,
duplicated, conflicting) → if anything is wrong, stop: the state stays as it was → otherwise
commit in the order of the spec: parameter assignments; F, S, tool change with TC/TR/TL; modal
G codes; switch-on M codes (M3, M4, M8 …); the motion or dwell; M5/M9 at the block end; M30.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Literal

from core.diagnostics import Diagnostic, Severity, diag
from core.dialects.codes import Code, Support
from core.dialects.pal_mill import CONTOUR_WORDS, TABLE, TOOL_WORDS
from core.geometry.arcs import centre_by_radius, centre_on_bisector, centres_from_radius, sweep
from core.interpreter.params import evaluate
from core.interpreter.state import ModalState, RunSetup
from core.syntax.blocks import Block, Span, Word
from core.toolpath import Dwell, Move, MoveKind, ToolChange, Vec3

Command = Move | Dwell | ToolChange

_AXES = (("X", "XI", "XA"), ("Y", "YI", "YA"), ("Z", "ZI", "ZA"))
_AXIS_WORDS = frozenset(a for spellings in _AXES for a in spellings)
_OWNER_DUPLICATES = {"G23": {"N"}, "G29": {"P"}}  # addresses a code takes twice
_TECHNOLOGY_WORDS = TABLE.always_allowed | TOOL_WORDS  # a block of only these moves nothing
_END_OF_BLOCK = {"M5": ("spindle", "M5"), "M9": ("coolant", "M9")}


@dataclass(slots=True)
class Outcome:
    """What one block did."""

    state: ModalState
    position: Vec3
    commands: list[Command] = field(default_factory=list)
    diagnostics: list[Diagnostic] = field(default_factory=list)
    ended: bool = False  # M30 executed


def execute_block(
    setup: RunSetup, state: ModalState, position: Vec3, block: Block, params: dict[int, float]
) -> Outcome:
    """Execute `block` from `state` at `position`. `params` (P1…P999) is updated only on success."""
    out = Outcome(state, position)
    d = out.diagnostics
    span = block.span

    # -- parameter assignments, left to right, into a copy --------------------------------
    new_params = params
    if block.assignments:
        new_params = dict(params)
        for asg in block.assignments:
            if not 1 <= asg.param <= 999:
                d.append(diag("PAL-E113", asg.span, number=asg.param))
                continue
            value = evaluate(asg.expr, new_params, asg.line, d)
            if value is not None and _in_range(value, f"P{asg.param}", asg.span, setup, d):
                new_params[asg.param] = value

    # -- sort the words ----------------------------------------------------------------------
    gs: list[tuple[Word, Code]] = []
    ms: list[tuple[Word, Code]] = []
    words: dict[str, list[Word]] = {}
    values: dict[str, float] = {}
    limit = setup.limits.max_abs_value
    for w in block.words:
        a = w.address
        if a == "G" or a == "M":
            code = _code_word(w, d)
            if code is not None:
                (gs if a == "G" else ms).append((w, code))
            continue
        spec = TABLE.addresses.get(a)
        if spec is None:
            d.append(diag("PAL-E003", w.address_span, address=a))
            continue
        words.setdefault(a, []).append(w)
        if w.expr is not None:
            v = evaluate(w.expr, new_params, w.line, d)
            if v is None:
                continue
        elif w.value is None:
            continue  # a flag; checked below
        else:
            v = w.value
        if not -limit <= v <= limit:  # also catches NaN and infinity
            _in_range(v, a, w.span, setup, d)
            continue
        if spec.integer and v != int(v):
            d.append(diag("PAL-E108", w.span, address=a, raw=w.raw))
        values.setdefault(a, v)

    # -- G codes: count, groups, the code that owns the block -------------------------------
    if len(gs) > 2:
        d.append(diag("PAL-E104", gs[2][0].span, count=len(gs)))
    owner: Code | None = None
    owner_word: Word | None = None
    seen_groups: dict[str, Word] = {}
    for w, code in gs + ms:
        for member in TABLE.activates(code):
            g = TABLE.group_of[member]
            if g in seen_groups:
                first = seen_groups[g]
                label = TABLE.group(g)
                d.append(diag("PAL-E103", w.span, first=str(first), second=str(w), group=label.label_de,
                              group_en=label.label_en))
            seen_groups[g] = w
        if code.owns_block:
            if owner is not None and owner.group != code.group or (owner is not None and code.group is None):
                d.append(diag("PAL-E103", w.span, first=str(owner_word), second=str(w), group="Satzfunktion",
                              group_en="block function"))
            owner, owner_word = code, w

    # -- which addresses the block may hold -----------------------------------------------
    motion = owner if owner is not None and owner.group == "motion" else None
    if owner is None and not words.keys() <= _TECHNOLOGY_WORDS:
        motion = TABLE.codes[state.active("motion") or "G1"]
        allowed = motion.words
        command_name = f"{motion.name} (modal)"
    elif owner is not None:
        allowed = owner.words
        command_name = str(owner_word)
    else:
        allowed = TOOL_WORDS
        command_name = ""  # every word is allowed here, so no message names it
    for a, ws in words.items():
        if owner is not None and owner.alone:
            d.append(diag("PAL-E101", ws[0].span, address=a, command=command_name))
            continue
        if a not in allowed and a not in TABLE.always_allowed:
            d.append(diag("PAL-E101", ws[0].span, address=a, command=command_name))
            continue
        if len(ws) > 1 and not (owner is not None and a in _OWNER_DUPLICATES.get(owner.name, ())):
            d.append(diag("PAL-E106", ws[1].span, address=a))
        for w in ws:
            if w.value is None and w.expr is None and not (TABLE.addresses[a].flag and owner and owner.name == "G66"):
                d.append(diag("PAL-E111", w.span, address=a))
    if owner is not None and owner.alone and len(gs) + len(ms) > 1:
        other = next(w for w, c in gs + ms if c is not owner)
        d.append(diag("PAL-E101", other.span, address=str(other), command=command_name))
    for spellings in _AXES:
        present = [s for s in spellings if s in words]
        if len(present) > 1:
            d.append(diag("PAL-E107", words[present[1]][0].span, first=present[0], second=present[1]))
    for w, code in gs:
        for one_of in code.required:
            if not any(a in words for a in one_of):
                d.append(diag("PAL-E102", w.span, address="/".join(one_of), command=str(w)))
    for a in ("F", "S", "U", "H", "D"):
        if a in values and values[a] < 0:
            d.append(diag("PAL-E109", words[a][0].span, address=a, raw=words[a][0].raw))
    if "TC" in values and not 1 <= values["TC"] <= 9:
        d.append(diag("PAL-E112", words["TC"][0].span, value=words["TC"][0].raw))
    new_tool: int | None = None
    if "T" in values:
        new_tool = int(values["T"])
        if new_tool != 0 and setup.tools.get(new_tool) is None:
            d.append(diag("PAL-E304", words["T"][0].span, tool=new_tool))
    if motion is not None and motion.name in ("G2", "G3"):
        for a in ("K", "KA"):
            if a in words:
                d.append(diag("PAL-E204", words[a][0].span, address=a))
    if any(c.name == "M6" for _, c in ms) and "T" not in values and state.tool is None:
        d.append(diag("PAL-E308", next(w.span for w, c in ms if c.name == "M6")))
    if any(c.name == "G70" for _, c in gs):
        d.append(diag("PAL-E309", next(w.span for w, c in gs if c.name == "G70")))

    if any(x.severity is Severity.ERROR for x in d):
        return out  # the block is not executed; the state stays as it was

    # -- what is not implemented yet -------------------------------------------------------
    for w, code in gs + ms:
        if code.support is Support.PLANNED:
            skips = code.owns_block
            d.append(_not_supported(w.span, code.feature_de, code.feature_en, skips))
            if skips:
                return out
    if motion is not None:
        for a, (de, en) in CONTOUR_WORDS.items():
            if a in words:
                skips = a != "RN"
                d.append(_not_supported(words[a][0].span, de, en, skips))
                if skips:
                    return out

    # -- commit: technology and modes at block start ------------------------------------------
    codes = state.codes
    changes = {TABLE.group_of[m]: m for _, c in gs + ms for m in TABLE.activates(c) if m not in _END_OF_BLOCK}
    feed, speed, tool, tc, tr, tl = state.feed, state.speed, state.tool, state.tc, state.tr, state.tl
    if "F" in values:
        feed = values["F"]
    if "S" in values:
        speed = values["S"]
    if "T" in values:
        tool = new_tool or None
        tc, tr, tl = 1, 0.0, 0.0
        codes = {**codes, "spindle": "M5", "coolant": "M9"}  # a tool change stops spindle and coolant
    if "TC" in values:
        tc = int(values["TC"])
    if "TR" in values:
        tr = values["TR"]
    if "TL" in values:
        tl = values["TL"]
    if changes:
        codes = {**codes, **changes}
    if (codes is not state.codes or feed != state.feed or speed != state.speed or tool != state.tool
            or tc != state.tc or tr != state.tr or tl != state.tl):
        state = ModalState(codes, feed, speed, tool, tc, tr, tl)
    if "T" in values:
        out.commands.append(ToolChange(tool, tc, tr, tl, position, span))
    if changes.get("spindle") in ("M3", "M4") and speed == 0:
        d.append(diag("PAL-E306", next(w.span for w, c in ms if c.name in ("M3", "M4", "M13", "M14"))))

    # -- the motion or the dwell -----------------------------------------------------------------
    if owner is not None and owner.name == "G4":
        seconds = values["U"]
        if int(values.get("O", 1)) == 2:
            if state.speed == 0:
                d.append(diag("PAL-E305", owner_word.span if owner_word else span))
                seconds = 0.0
            else:
                seconds = values["U"] * 60.0 / state.speed
        out.commands.append(Dwell(position, seconds, span))
    elif motion is not None and any(a in _AXIS_WORDS or a in ("I", "J", "IA", "JA", "R") for a in words):
        exact = any(c.name == "G9" for _, c in gs)
        move = _motion(setup, state, position, motion.name, words, values, span, exact, d)
        if move is not None:
            out.commands.append(move)
            position = move.end

    # -- block end: M5, M9, M30 ---------------------------------------------------------------
    ends = {g: m for _, c in ms for m in TABLE.activates(c) if (g := TABLE.group_of[m]) and m in _END_OF_BLOCK}
    if ends:
        state = ModalState({**state.codes, **ends}, state.feed, state.speed, state.tool, state.tc, state.tr,
                           state.tl)
    for w, code in ms:
        if code.name == "M30":
            out.ended = True
    if new_params is not params:
        params.clear()
        params.update(new_params)
    out.state, out.position = state, position
    return out


def _in_range(value: float, address: str, span: Span, setup: RunSetup, d: list[Diagnostic]) -> bool:
    limit = setup.limits.max_abs_value
    if -limit <= value <= limit:  # also False for NaN
        return True
    d.append(diag("PAL-E015", span, value=f"{value:.6g}", address=address, limit=f"{limit:g}"))
    return False


def _code_word(w: Word, d: list[Diagnostic]) -> Code | None:
    """The code table entry of a G or M word, or None after a diagnostic."""
    if w.value is None or w.expr is not None:
        d.append(diag("PAL-E111", w.span, address=w.address) if w.expr is None
                 else diag("PAL-E115", w.span, address=w.address))
        return None
    if not 0 <= w.value <= 9999 or w.value != int(w.value):
        d.append(diag("PAL-E108", w.span, address=w.address, raw=w.raw))
        return None
    name = f"{w.address}{int(w.value)}"
    code = TABLE.codes.get(name)
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


def _target(state: ModalState, position: Vec3, values: dict[str, float],
            words: dict[str, list[Word]], d: list[Diagnostic]) -> Vec3:
    """The end point from X/XI/XA, Y/YI/YA, Z/ZI/ZA under G90 or G91."""
    incremental = state.active("dimensions") == "G91"
    out = list(position)
    for i, (plain, inc, absolute) in enumerate(_AXES):
        if plain in values:
            out[i] = position[i] + values[plain] if incremental else values[plain]
        elif inc in values:
            out[i] = position[i] + values[inc]
            if incremental:
                d.append(diag("PAL-I101", words[inc][0].span, address=inc, mode="G91",
                              meaning="Kettenmaß"))
        elif absolute in values:
            out[i] = values[absolute]
            if not incremental:
                d.append(diag("PAL-I101", words[absolute][0].span, address=absolute, mode="G90",
                              meaning="Absolutmaß"))
    return (out[0], out[1], out[2])


def _motion(setup: RunSetup, state: ModalState, position: Vec3, name: str, words: dict[str, list[Word]],
            values: dict[str, float], span: Span, exact: bool, d: list[Diagnostic]) -> Move | None:
    end = _target(state, position, values, words, d)
    spindle_code = state.active("spindle")
    spindle_on = spindle_code in ("M3", "M4")
    if name == "G0" or name == "G1":
        if end == position:
            return None
        if name == "G0":
            return _move(state, "rapid", position, end, span, spindle_code, exact_stop=True)
        _check_cutting(state, spindle_on, span, d)
        return _move(state, "feed", position, end, span, spindle_code, exact_stop=exact)
    # G2 / G3 in the plane X-Y
    clockwise = name == "G2"
    arc = _arc_centre(setup, position, end, values, words, clockwise, name, span, d)
    if arc is None:
        return None
    centre, radius = arc
    angle = sweep((position[0], position[1]), (end[0], end[1]), centre, clockwise)
    _check_cutting(state, spindle_on, span, d)
    return _move(state, "arc", position, end, span, spindle_code, exact_stop=exact,
                 center=(centre[0], centre[1], position[2]), direction="cw" if clockwise else "ccw",
                 radius=radius, angle=angle)


def _move(state: ModalState, kind: MoveKind, start: Vec3, end: Vec3, span: Span, spindle_code: str | None,
          exact_stop: bool, center: Vec3 | None = None, direction: Literal["cw", "ccw"] | None = None,
          radius: float | None = None, angle: float | None = None) -> Move:
    """A move carrying the technology active in `state`."""
    spindle_on = spindle_code == "M3" or spindle_code == "M4"
    return Move(kind, start, end, state.feed, "mm/rev" if state.active("feed_mode") == "G95" else "mm/min",
                state.speed if spindle_on else 0.0,
                ("cw" if spindle_code == "M3" else "ccw") if spindle_on else None,
                state.active("coolant") == "M8", state.tool, span, center, direction, radius, angle, exact_stop)


def _check_cutting(state: ModalState, spindle_on: bool, span: Span, d: list[Diagnostic]) -> None:
    if state.feed == 0:
        d.append(diag("PAL-E301", span))
    if state.tool is None:
        d.append(diag("PAL-E303", span))
    elif not spindle_on:
        d.append(diag("PAL-E302", span))


def _arc_centre(setup: RunSetup, position: Vec3, end: Vec3, values: dict[str, float],
                words: dict[str, list[Word]], clockwise: bool, name: str, span: Span,
                d: list[Diagnostic]) -> tuple[tuple[float, float], float] | None:
    """Centre and radius of a G2/G3 arc from end point plus I/J, IA/JA or R (and over-determined forms)."""
    s = (position[0], position[1])
    e = (end[0], end[1])
    has_x = any(a in values for a in _AXES[0])
    has_y = any(a in values for a in _AXES[1])
    cx = values["IA"] if "IA" in values else (s[0] + values["I"] if "I" in values else None)
    cy = values["JA"] if "JA" in values else (s[1] + values["J"] if "J" in values else None)
    r_word = words["R"][0] if "R" in words else None
    tol = setup.arc_tolerance
    present = [has_x, has_y, cx is not None, cy is not None, r_word is not None]
    if not has_x and not has_y and cx is not None and cy is not None and r_word is None:
        e = s  # full circle about the centre (helix if Z moves)
    elif not (has_x and has_y):
        if sum(present) >= 3:
            d.append(_not_supported(span, "Diese Kombination von Kreisadressen",
                                    "This combination of arc addresses", True))
        else:
            d.append(diag("PAL-E203", span, command=name))
        return None
    elif sum(present) < 3:
        d.append(diag("PAL-E203", span, command=name))
        return None

    full = math.dist(s, e) < 1e-6
    if r_word is not None:
        radius = abs(values["R"])
        if full:
            d.append(diag("PAL-E205", r_word.span))
            return None
        # The sign of R written out wins over O; R+ (or O1) is the shorter arc, R- (or O2) the longer.
        longer = r_word.raw.startswith("-") or (not r_word.raw.startswith("+") and int(values.get("O", 1)) == 2)
        if cx is None and cy is None:
            centre = centre_by_radius(s, e, radius, clockwise, longer)
            if centre is None:
                chord = math.dist(s, e)
                d.append(diag("PAL-E201", r_word.span,
                              reason=f"Radius {radius:g} mm ist kleiner als die halbe Sehne {chord / 2:.3f} mm",
                              reason_en=f"radius {radius:g} mm is less than half the chord {chord / 2:.3f} mm"))
                return None
            return centre, radius
        # over-determined: R plus centre data must match one of the radius solutions
        for c in centres_from_radius(s, e, radius):
            if (cx is None or abs(c[0] - cx) <= tol) and (cy is None or abs(c[1] - cy) <= tol):
                return c, radius
        r_s = math.dist(s, (cx if cx is not None else s[0], cy if cy is not None else s[1]))
        d.append(diag("PAL-E202", span, r_start=radius, r_end=r_s, tolerance=tol))
        return None
    if cx is not None and cy is not None:
        centre = (cx, cy)
    else:
        found = centre_on_bisector(s, e, cx, cy)
        if found is None:
            d.append(diag("PAL-E201", span, reason="kein Mittelpunkt liegt gleich weit von Start- und Endpunkt",
                              reason_en="no centre lies equally far from start and end point"))
            return None
        centre = found
    r_start, r_end = math.dist(s, centre), math.dist(e, centre)
    if r_start < 1e-6:
        d.append(diag("PAL-E206", span))
        return None
    if abs(r_start - r_end) > tol:
        d.append(diag("PAL-E202", span, r_start=round(r_start, 4), r_end=round(r_end, 4), tolerance=tol))
        return None
    return centre, r_start
