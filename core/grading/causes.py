"""Why a part deviates: the submission's programmed contour and tool-centre path against the reference's.

Both toolpaths are read as contour elements: the programmed geometry of every cutting move in the plane (the
contour point before compensation, `Move.programmed_end`), with the tool-centre path's offset from it (the
cutter radius left or right under G41/G42, the nose radius under SRK, 0 without), its depth and its tool.
Equivalent programs give the same elements (R or I/J, RN or the element written out, incremental or absolute,
loops or the blocks written out). The two element lists are aligned (longest common subsequence of equal
elements); what differs between aligned elements, and what stays unaligned, is a cause with the submission's
line: compensation missing or on the wrong side, the compensation selected without an approach move, an arc's
direction, end point or radius, a depth, a tool, an element missing or extra. The functions are pure.
"""

from __future__ import annotations

import itertools
import math
import re
from dataclasses import dataclass, field
from typing import Any, Literal

from core.diagnostics import catalogue_code
from core.grading.numbers import de, en, mm, word
from core.toolpath import Move, ToolChange, Toolpath

Point = tuple[float, float]
SAME = 0.01  # mm: programmed points this close are the same point
MAX_ELEMENTS = 400  # elements compared per program (a loop of thousands of moves is cut short)
APPROACH_WARNING = "PAL-W222"


@dataclass(frozen=True, slots=True)
class Element:
    """One programmed contour element and how the tool centre followed it. Coordinates in the plane of the
    contour: milling (X, Y), turning (Z, radius)."""

    kind: Literal["line", "arc", "plunge"]
    start: Point
    end: Point
    center: Point | None
    cw: bool
    depth: float  # milling: Z of the element; turning: 0
    offset: (
        float  # the tool centre's distance from the programmed element, > 0 left of the direction of travel
    )
    ramp: bool  # the offset builds up along the element (the first move after G41/G42)
    line: int  # the block's line in the program file (the calling line for a library subprogram)
    tool: int | None
    moves: tuple[int, ...]  # indices of its moves in the toolpath
    joint: bool = False  # a transition element (RN, D, #CHF …) the control put in at the corner of its block

    @property
    def transition(self) -> str:
        return "Rundung" if self.kind == "arc" else "Fase"

    @property
    def transition_en(self) -> str:
        return "rounding" if self.kind == "arc" else "chamfer"

    @property
    def radius(self) -> float:
        return math.dist(self.start, self.center) if self.center is not None else 0.0


@dataclass(frozen=True, slots=True)
class Cause:
    """A likely cause of a deviation, with the submission's line it concerns (0: none)."""

    code: str  # approach, compensation_missing, compensation_side, tool, depth, arc_direction, arc_end,
    # arc_radius, end_point, element_kind, element_missing, element_extra
    line: int
    message: str
    message_en: str
    reference: int | None = None  # the index of the reference element concerned

    def to_json(self) -> dict[str, Any]:
        return {
            "code": self.code,
            "line": self.line or None,
            "message": self.message,
            "message_en": self.message_en,
        }


@dataclass(slots=True)
class Comparison:
    """The aligned element lists: pairs (reference index, submission index) and the causes found."""

    reference: list[Element]
    submission: list[Element]
    pairs: list[tuple[int, int]] = field(default_factory=list)
    causes: list[Cause] = field(default_factory=list)

    def counterparts(self) -> list[tuple[int, int]]:
        """Reference and submission elements that stand for each other: the aligned pairs, and between them the
        elements in the same place of a gap (the first reference element there with the first submission one …)."""
        out = list(self.pairs)
        anchors = [(-1, -1)] + self.pairs + [(len(self.reference), len(self.submission))]
        for (r0, s0), (r1, s1) in itertools.pairwise(anchors):
            out += list(zip(range(r0 + 1, r1), range(s0 + 1, s1), strict=False))
        return sorted(out)

    def partner(self, ref_index: int) -> Element | None:
        return next((self.submission[s] for r, s in self.counterparts() if r == ref_index), None)


def file_line(m: Move) -> int:
    """The line of the program file a move belongs to: its own, or the call of the library subprogram."""
    if m.source is None:
        return m.line
    return next((line for source, line in m.call_stack if source is None), m.line)


def _uv(p: tuple[float, float, float], lathe: bool) -> Point:
    return (p[2], p[0]) if lathe else (p[0], p[1])


def _offset_at(kind: str, start: Point, end: Point, center: Point | None, cw: bool, q: Point) -> float:
    """The signed distance of the tool-centre point `q` from the programmed element (> 0 left of travel)."""
    if kind == "arc" and center is not None:
        radial = math.dist(q, center) - math.dist(start, center)
        return radial if cw else -radial
    dx, dy = end[0] - start[0], end[1] - start[1]
    n = math.hypot(dx, dy)
    if n < 1e-12:
        return 0.0
    return (dx * (q[1] - start[1]) - dy * (q[0] - start[0])) / n


def elements(tp: Toolpath, cutting: list[int], lathe: bool) -> list[Element]:
    """The contour elements of the moves `cutting` (indices into tp.moves, in order): consecutive moves of one
    programmed element (a compensated element and the arc about its outer corner) are one element, collinear
    lines and arcs of one circle that follow each other are merged."""
    chosen = set(cutting)
    out: list[Element] = []
    before: Point | None = None  # the programmed end of the move before
    for k, m in enumerate(tp.moves):
        target = m.programmed_end if m.programmed_end is not None else m.end
        p_end = _uv(target, lathe)
        p_start = before if before is not None else _uv(m.start, lathe)
        before = p_end
        if k not in chosen or (not lathe and m.kind == "arc" and m.plane != "G17"):
            continue
        if math.dist(p_start, p_end) <= SAME and m.kind != "arc":
            if not lathe and m.end[2] < m.start[2] - SAME:  # a plunge: a hole, or the start of a slot
                out.append(
                    Element(
                        "plunge", p_end, p_end, None, False, m.end[2], 0.0, False, file_line(m), m.tool, (k,)
                    )
                )
            continue  # no programmed extent in the plane: an infeed
        arc = m.kind == "arc" and m.center is not None
        if (
            arc
            and math.dist(p_start, p_end) <= SAME
            and out
            and out[-1].moves[-1] == k - 1
            and out[-1].line == file_line(m)
        ):
            last = out[-1]  # the arc about an outer corner under compensation: part of the element before
            out[-1] = Element(
                last.kind,
                last.start,
                last.end,
                last.center,
                last.cw,
                last.depth,
                last.offset,
                last.ramp,
                last.line,
                last.tool,
                last.moves + (k,),
                last.joint,
            )
            continue
        center = _uv(m.center, lathe) if arc and m.center is not None else None
        cw = m.direction == "cw"
        kind: Literal["line", "arc"] = "arc" if arc else "line"
        pts = m.points(0.05, max_chords=64)
        mid = (
            _uv(pts[len(pts) // 2], lathe)
            if kind == "arc"
            else _uv(tuple((a + b) / 2 for a, b in zip(m.start, m.end, strict=True)), lathe)  # type: ignore[arg-type]
        )
        off = _offset_at(kind, p_start, p_end, center, cw, mid)
        off_a = _offset_at(kind, p_start, p_end, center, cw, _uv(m.start, lathe))
        off_b = _offset_at(kind, p_start, p_end, center, cw, _uv(m.end, lathe))
        ramp = abs(off_a - off_b) > max(0.05, 0.25 * max(abs(off_a), abs(off_b)))
        depth = 0.0 if lathe else min(m.start[2], m.end[2]) if kind == "line" else m.end[2]
        joint = (
            bool(out)
            and out[-1].kind != "plunge"
            and out[-1].moves[-1] == k - 1
            and file_line(tp.moves[k - 1]) == file_line(m)
            and math.dist(out[-1].end, p_start) <= SAME
        )
        element = Element(
            kind, p_start, p_end, center, cw, depth, off, ramp, file_line(m), m.tool, (k,), joint
        )
        merged = _merge(out[-1], element) if out and out[-1].moves[-1] == k - 1 else None
        if merged is not None:
            out[-1] = merged
        else:
            out.append(element)
        if len(out) > MAX_ELEMENTS:
            break
    return out


def _merge(a: Element, b: Element) -> Element | None:
    """One element of two that continue each other (collinear lines, arcs of one circle), else None."""
    if (
        a.kind != b.kind
        or a.kind == "plunge"
        or b.joint
        or math.dist(a.end, b.start) > SAME
        or abs(a.depth - b.depth) > SAME
        or abs(a.offset - b.offset) > SAME
        or a.tool != b.tool
        or a.ramp
        or b.ramp
    ):
        return None
    if a.kind == "line":
        da = (a.end[0] - a.start[0], a.end[1] - a.start[1])
        db = (b.end[0] - b.start[0], b.end[1] - b.start[1])
        na, nb = math.hypot(*da), math.hypot(*db)
        if (
            na < 1e-9
            or nb < 1e-9
            or abs(da[0] * db[1] - da[1] * db[0]) > 1e-6 * na * nb
            or da[0] * db[0] + da[1] * db[1] <= 0
        ):
            return None
    elif (
        a.center is None
        or b.center is None
        or math.dist(a.center, b.center) > SAME
        or a.cw != b.cw
        or abs(a.radius - b.radius) > SAME
        or math.dist(b.end, a.start) <= SAME
    ):
        return None  # not one circle, or the two would close it
    return Element(
        a.kind,
        a.start,
        b.end,
        a.center,
        a.cw,
        a.depth,
        a.offset,
        False,
        a.line,
        a.tool,
        a.moves + b.moves,
        a.joint,
    )


def same(a: Element, b: Element) -> bool:
    """The same programmed element (its depth, offset and tool aside)."""
    if a.kind != b.kind or math.dist(a.end, b.end) > SAME:
        return False
    if a.kind == "plunge":
        return True
    if math.dist(a.start, b.start) > SAME:
        return False
    if a.kind == "arc":
        assert a.center is not None and b.center is not None
        return a.cw == b.cw and math.dist(a.center, b.center) <= SAME
    return True


def align(ref: list[Element], sub: list[Element]) -> list[tuple[int, int]]:
    """The longest common subsequence of equal elements, as pairs of indices in order."""
    n, m = len(ref), len(sub)
    eq = [[same(ref[i], sub[j]) for j in range(m)] for i in range(n)]
    table = [[0] * (m + 1) for _ in range(n + 1)]
    for i in range(n - 1, -1, -1):
        row, below = table[i], table[i + 1]
        for j in range(m - 1, -1, -1):
            row[j] = below[j + 1] + 1 if eq[i][j] else max(below[j], row[j + 1])
    pairs: list[tuple[int, int]] = []
    i = j = 0
    while i < n and j < m:
        if eq[i][j]:
            pairs.append((i, j))
            i += 1
            j += 1
        elif table[i + 1][j] >= table[i][j + 1]:
            i += 1
        else:
            j += 1
    return pairs


def _pt(p: Point, lathe: bool) -> str:
    return f"X{word(2 * p[1])} Z{word(p[0])}" if lathe else f"X{word(p[0])} Y{word(p[1])}"


def describe(e: Element, lathe: bool, lang: str = "de") -> str:
    """`Gerade X70 Y84 → X70 Y23.6`, `Kreisbogen G2 X70 Y23.6 → X56.4 Y10 (R21)`, a transition element `Rundung R20
    X50 Y10 → X70 Y30` (turning: X as the diameter)."""
    if e.joint:
        name = e.transition if lang == "de" else e.transition_en
        size = f" R{word(e.radius, 2)}" if e.kind == "arc" else ""
        return f"{name}{size} {_pt(e.start, lathe)} → {_pt(e.end, lathe)}"
    if e.kind == "plunge":
        return f"{'Eintauchen' if lang == 'de' else 'plunge'} {_pt(e.end, lathe)} Z{word(e.depth)}"
    if e.kind == "arc":
        name = "Kreisbogen" if lang == "de" else "arc"
        return f"{name} {'G2' if e.cw else 'G3'} {_pt(e.start, lathe)} → {_pt(e.end, lathe)} (R{word(e.radius, 2)})"
    return f"{'Gerade' if lang == 'de' else 'line'} {_pt(e.start, lathe)} → {_pt(e.end, lathe)}"


def _side_code(offset: float, lathe: bool) -> str:
    """The compensation that puts the tool centre on this side: left of the travel G41, right G42 (turning: the
    tool-centre side of G41/G42 in the drawing's view, as G46 chooses it)."""
    return "G41" if offset > 0 else "G42"


def compare(
    ref_tp: Toolpath,
    ref_cut: list[int],
    sub_tp: Toolpath,
    sub_cut: list[int],
    lathe: bool,
    tool_radius: dict[int | None, float],
    program: str = "",
) -> Comparison:
    """The reference's and the submission's elements aligned, and the causes of their differences in the order of
    their likelihood (a missing compensation before the arc it also spoils)."""
    ref, sub = elements(ref_tp, ref_cut, lathe), elements(sub_tp, sub_cut, lathe)
    cmp = Comparison(ref, sub, align(ref, sub))
    found: dict[str, Cause] = {}

    def add(c: Cause) -> None:
        found.setdefault(c.code, c)

    comp_name, comp_en = (
        ("die Schneidenradiuskompensation (SRK)", "nose-radius compensation (SRC)")
        if lathe
        else ("die Fräserradiuskorrektur", "cutter radius compensation")
    )
    warned = [
        d for d in sub_tp.diagnostics if catalogue_code(d.code) == APPROACH_WARNING and d.source is None
    ]
    if warned:
        d = warned[0]
        add(
            Cause(
                "approach",
                d.span.line,
                f"Zeile {d.span.line}: {d.message.split(':')[0]}.",
                f"Line {d.span.line}: {d.message_en.split(':')[0]}.",
            )
        )
    warned_lines = {d.span.line for d in warned}
    for ri, si in cmp.pairs:
        r, s = ref[ri], sub[si]
        radius = tool_radius.get(r.tool, 0.0)
        if r.kind == "plunge" or s.line in warned_lines:
            pass  # a plunge has no side; the block that selects the compensation on the contour is named already
        elif abs(r.offset) > 0.5 * max(radius, 0.01):
            if s.ramp and abs(abs(r.offset) - abs(s.offset)) > 0.2 * abs(r.offset):
                what = "SRK" if lathe else "Fräserradiuskorrektur"
                what_en = "nose-radius compensation" if lathe else "cutter radius compensation"
                add(
                    Cause(
                        "approach",
                        s.line,
                        f"Zeile {s.line}: Die {what} wird ohne Anfahrbewegung angewählt – "
                        f"dieser Satz ist schon ein Konturelement ({describe(r, lathe)}).",
                        f"Line {s.line}: the {what_en} is selected without an approach move – this block is "
                        f"already a contour element ({describe(r, lathe, 'en')}).",
                        ri,
                    )
                )
            elif abs(s.offset) < 0.25 * abs(r.offset):
                line = _selection_line(sub_tp, sub, si, lathe)
                if lathe:
                    add(
                        Cause(
                            "compensation_missing",
                            line,
                            f"Die Schneidenradiuskompensation (SRK) fehlt: ohne G46 fährt die theoretische "
                            f"Schneidenspitze die Kontur, und an Fasen, Kegeln, Radien und Schultern weicht das "
                            f"Drehteil um bis zu den Schneidenradius {mm(abs(r.offset))} ab (G46 vor Zeile {line}).",
                            f"Nose-radius compensation (SRC) is missing: without G46 the theoretical tool tip follows "
                            f"the contour, and on chamfers, tapers, radii and shoulders the part is off by up to the "
                            f"nose radius {mm(abs(r.offset), 'en')} (G46 before line {line}).",
                            ri,
                        )
                    )
                else:
                    code = _side_code(r.offset, lathe)
                    add(
                        Cause(
                            "compensation_missing",
                            line,
                            f"Die Fräserradiuskorrektur fehlt: die Werkzeugmitte fährt auf der programmierten "
                            f"Kontur, {mm(abs(r.offset))} zu weit ins Werkstück ({code} in Zeile {line}).",
                            f"Cutter radius compensation is missing: the tool centre travels on the programmed "
                            f"contour, {mm(abs(r.offset), 'en')} too far into the part ({code} in line {line}).",
                            ri,
                        )
                    )
            elif r.offset * s.offset < 0:
                line = _code_line(sub_tp, s.line, _side_code(s.offset, lathe)) or _selection_line(
                    sub_tp, sub, si, lathe
                )
                want, got = _side_code(r.offset, lathe), _side_code(s.offset, lathe)
                add(
                    Cause(
                        "compensation_side",
                        line,
                        f"Zeile {line}: {comp_name[0].upper()}{comp_name[1:]} liegt auf der falschen Seite der "
                        f"Kontur ({got} statt {want}).",
                        f"Line {line}: {comp_en} is on the wrong side of the contour ({got} instead of {want}).",
                        ri,
                    )
                )
            elif abs(abs(s.offset) - abs(r.offset)) > 0.02:
                add(_tool_cause(sub_tp, s, r, tool_radius, lathe, abs(s.offset), abs(r.offset)))
        elif abs(s.offset) > 0.5 * max(tool_radius.get(s.tool, 0.0), 0.01) and not lathe:
            line = _selection_line(sub_tp, sub, si, lathe)
            add(
                Cause(
                    "compensation_extra",
                    line,
                    f"Zeile {line}: Die Aufgabe fährt diese Bahn mit der Werkzeugmitte; die Fräserradiuskorrektur "
                    f"({_side_code(s.offset, lathe)}) versetzt sie um {mm(abs(s.offset))}.",
                    f"Line {line}: the task runs this path with the tool centre; cutter radius compensation "
                    f"({_side_code(s.offset, lathe)}) shifts it by {mm(abs(s.offset), 'en')}.",
                    ri,
                )
            )
        if s.tool != r.tool:
            add(_tool_cause(sub_tp, s, r, tool_radius, lathe, None, None))
        if not lathe and abs(s.depth - r.depth) > 0.02:
            line = _depth_line(sub_tp, s)
            deeper = s.depth < r.depth
            add(
                Cause(
                    "depth",
                    line,
                    f"Zeile {line}: Tiefe Z{word(s.depth)} statt Z{word(r.depth)} – {mm(abs(s.depth - r.depth))} "
                    f"zu {'tief' if deeper else 'hoch'}.",
                    f"Line {line}: depth Z{word(s.depth)} instead of Z{word(r.depth)} – "
                    f"{mm(abs(s.depth - r.depth), 'en')} too {'deep' if deeper else 'high'}.",
                    ri,
                )
            )
    for cause in _gaps(cmp, lathe, program):
        add(cause)
    order = [
        "approach",
        "compensation_missing",
        "compensation_side",
        "compensation_extra",
        "tool",
        "depth",
        "arc_direction",
        "arc_radius",
        "arc_end",
        "end_point",
        "element_kind",
        "element_missing",
        "element_extra",
    ]
    cmp.causes = [found[c] for c in order if c in found]
    return cmp


def _tool_cause(
    tp: Toolpath,
    s: Element,
    r: Element,
    tool_radius: dict[int | None, float],
    lathe: bool,
    have: float | None,
    want: float | None,
) -> Cause:
    line = _tool_change_line(tp, s) or s.line
    rs, rr = tool_radius.get(s.tool, 0.0), tool_radius.get(r.tool, 0.0)
    if s.tool == r.tool and have is not None and want is not None:
        return Cause(
            "tool",
            line,
            f"Zeile {line}: Die Werkzeugmitte liegt {mm(have)} statt {mm(want)} neben der "
            f"Kontur – Werkzeugradius oder Korrekturwert (TR) stimmt nicht.",
            f"Line {line}: the tool centre runs {mm(have, 'en')} instead of {mm(want, 'en')} beside the "
            f"contour – the tool radius or the correction (TR) is wrong.",
        )
    size = "Schneidenradius" if lathe else "Ø"
    size_en = "nose radius" if lathe else "Ø"

    def desc(t: int | None, radius: float, lang: str) -> str:
        if t is None:
            return "kein Werkzeug" if lang == "de" else "no tool"
        value = radius if lathe else 2 * radius
        num = de(value) if lang == "de" else en(value)
        return f"T{t} ({size if lang == 'de' else size_en} {num} mm)" if lathe else f"T{t} (Ø{num} mm)"

    return Cause(
        "tool",
        line,
        f"Zeile {line}: Werkzeug {desc(s.tool, rs, 'de')} statt {desc(r.tool, rr, 'de')}.",
        f"Line {line}: tool {desc(s.tool, rs, 'en')} instead of {desc(r.tool, rr, 'en')}.",
    )


def _tool_change_line(tp: Toolpath, s: Element) -> int | None:
    """The line of the tool change in effect at the element's first move (the last one before it)."""
    first = tp.moves[s.moves[0]]
    line = None
    for c in tp.commands:
        if c is first:
            return line
        if isinstance(c, ToolChange):
            line = c.span.line
    return line


def _selection_line(tp: Toolpath, sub: list[Element], si: int, lathe: bool) -> int:
    """The submission's line where the compensation is (or should be) selected for element `si`: the block that
    moved in the plane to the element's start (the approach), else the element's own."""
    first = sub[si].moves[0]
    start = sub[si].start

    def programmed(k: int) -> Point:
        m = tp.moves[k]
        return _uv(m.programmed_end if m.programmed_end is not None else m.end, lathe)

    for k in range(first - 1, -1, -1):
        if math.dist(programmed(k), start) > SAME:
            break
        before = programmed(k - 1) if k > 0 else _uv(tp.moves[k].start, lathe)
        if math.dist(before, start) > SAME:
            return file_line(tp.moves[k])
    return sub[si].line


def _code_line(tp: Toolpath, upto: int, code: str) -> int | None:
    """The last line at or before `upto` where the compensation `code` was selected (from the run's states)."""
    found = None
    before = tp.initial.active("compensation") if tp.initial is not None else None
    for n, state in enumerate(tp.line_states[:upto], start=1):
        now = state.active("compensation")
        if now == code and before != code:
            found = n
        before = now
    return found


def _depth_line(tp: Toolpath, s: Element) -> int:
    """The block that took the tool to the element's depth: the last move before it that changed Z."""
    for k in range(s.moves[0], -1, -1):
        m = tp.moves[k]
        if abs(m.end[2] - s.depth) <= SAME and abs(m.start[2] - m.end[2]) > SAME:
            return file_line(m)
    return s.line


_LOOP = re.compile(r"(?<![0-9A-Z])G0*2[39](?![0-9])", re.IGNORECASE)


def _loop_line(program: str) -> int | None:
    """The first line of a program that repeats a section or loops (G23, G29)."""
    for n, text in enumerate(program.splitlines(), 1):
        if _LOOP.search(text.split(";")[0]):
            return n
    return None


def _gaps(cmp: Comparison, lathe: bool, program: str = "") -> list[Cause]:
    """Causes from the elements between aligned pairs: a replaced element (arc direction, end point, radius,
    kind), a missing or an extra one; in each gap the first difference, which the later ones follow from."""
    ref, sub = cmp.reference, cmp.submission
    anchors = [(-1, -1)] + cmp.pairs + [(len(ref), len(sub))]
    out: list[Cause] = []
    for (r0, s0), (r1, s1) in itertools.pairwise(anchors):
        rs, ss = list(range(r0 + 1, r1)), list(range(s0 + 1, s1))
        if not rs and not ss:
            continue
        joints = [r for r in rs if ref[r].joint and not any(sub[x].joint for x in ss)]
        if joints and len(rs) > len(ss):
            r = ref[joints[0]]
            line = sub[ss[0]].line if ss else sub[s0].line if s0 >= 0 else 0
            at, at_en = (
                (f"Zeile {line}: ", f"Line {line}: ") if line else ("", "")
            )  # 0: no block of the submission
            out.append(
                Cause(
                    "element_missing",
                    line,
                    f"{at}Es fehlt das Übergangselement {describe(r, lathe)}.",
                    f"{at_en}The transition element {describe(r, lathe, 'en')} is missing.",
                    joints[0],
                )
            )
            continue
        if rs and ss:
            cylinder = _diameter(ref, sub, rs, ss) if lathe else None
            if cylinder is not None:
                out.append(cylinder)
                continue
            found = [_replaced(ref[r], sub[s], lathe, r) for r, s in zip(rs, ss, strict=False)]
            out.append(min(found, key=lambda c: (SPECIFIC.index(c.code), found.index(c))))
            continue
        if rs:
            r = ref[rs[0]]
            after = sub[s0].line if s0 >= 0 else 0
            where, where_en = (f" (nach Zeile {after})", f" (after line {after})") if after else ("", "")
            repeated = {ref[x].line for x in range(rs[0])} >= {ref[x].line for x in rs}
            loop = _loop_line(program) if repeated else None
            if loop is not None:  # the reference made these in a repeat: a repeat or loop too few
                after = loop
                where = f" – die Wiederholung in Zeile {loop} läuft zu selten"
                where_en = f" – the repeat in line {loop} runs too few times"
            if len(rs) > 1:
                text = f"Es fehlen {len(rs)} Konturelemente ab {describe(r, lathe)}{where}."
                text_en = (
                    f"{len(rs)} contour elements from {describe(r, lathe, 'en')} on are missing{where_en}."
                )
            else:
                text = f"Es fehlt das Konturelement {describe(r, lathe)}{where}."
                text_en = f"The contour element {describe(r, lathe, 'en')} is missing{where_en}."
            out.append(Cause("element_missing", after, text, text_en, rs[0]))
        else:
            s = sub[ss[0]]
            repeated = {sub[x].line for x in range(ss[0])} >= {sub[x].line for x in ss}
            loop = _loop_line(program) if repeated else None
            if loop is not None:  # made by a repeat of the submission: a repeat or loop too many
                out.append(
                    Cause(
                        "element_extra",
                        loop,
                        f"Zeile {loop}: Die Wiederholung läuft zu oft – das "
                        f"Konturelement {describe(s, lathe)} gehört nicht zur Kontur der Zeichnung.",
                        f"Line {loop}: the repeat runs too many times – the contour element "
                        f"{describe(s, lathe, 'en')} is not part of the drawing's contour.",
                    )
                )
                continue
            out.append(
                Cause(
                    "element_extra",
                    s.line,
                    f"Zeile {s.line}: Das Konturelement {describe(s, lathe)} "
                    f"gehört nicht zur Kontur der Zeichnung.",
                    f"Line {s.line}: the contour element {describe(s, lathe, 'en')} is not part of the "
                    f"drawing's contour.",
                )
            )
    return out


def _diameter(ref: list[Element], sub: list[Element], rs: list[int], ss: list[int]) -> Cause | None:
    """Turning: the diameter of a cylinder of the gap, turned at another diameter, with the line that set it (the
    element before the cylinder, whose end point is the diameter's X); None if no cylinder of the gap is that."""
    for ri, si in zip(rs, ss, strict=False):
        r, s = ref[ri], sub[si]
        flat_r = r.kind == "line" and abs(r.start[1] - r.end[1]) <= SAME and abs(r.start[0] - r.end[0]) > 1.0
        flat_s = s.kind == "line" and abs(s.start[1] - s.end[1]) <= SAME
        if not (flat_r and flat_s) or abs(s.start[1] - r.start[1]) <= SAME:
            continue
        before = sub[si - 1] if si > 0 and math.dist(sub[si - 1].end, s.start) <= SAME else None
        line = before.line if before is not None else s.line
        return Cause(
            "end_point",
            line,
            f"Zeile {line}: Ø{word(2 * s.start[1])} statt Ø{word(2 * r.start[1])} "
            f"(der Zylinder Z{word(r.start[0])} … Z{word(r.end[0])}).",
            f"Line {line}: Ø{word(2 * s.start[1])} instead of Ø{word(2 * r.start[1])} (the cylinder "
            f"Z{word(r.start[0])} … Z{word(r.end[0])}).",
            ri,
        )
    return None


SPECIFIC = ["arc_direction", "arc_radius", "arc_end", "element_kind", "end_point"]  # the most telling first


def _replaced(r: Element, s: Element, lathe: bool, ri: int) -> Cause:
    """What differs between the reference's element `r` and the submission's `s` in its place."""
    line = s.line
    starts = math.dist(r.start, s.start) <= SAME
    ends = math.dist(r.end, s.end) <= SAME
    if r.kind == "arc" and s.kind == "arc":
        if s.cw != r.cw and (
            ends or (r.center is not None and s.center is not None and math.dist(r.center, s.center) <= SAME)
        ):
            return Cause(
                "arc_direction",
                line,
                f"Zeile {line}: Der Kreisbogen läuft in die falsche Richtung – {'G2' if s.cw else 'G3'} "
                f"statt {'G2' if r.cw else 'G3'} ({'im' if r.cw else 'gegen den'} Uhrzeigersinn).",
                f"Line {line}: the arc runs the wrong way – {'G2' if s.cw else 'G3'} instead of "
                f"{'G2' if r.cw else 'G3'} ({'clockwise' if r.cw else 'counter-clockwise'}).",
                ri,
            )
        if s.cw == r.cw and abs(s.radius - r.radius) > SAME:
            what, what_en = ("Rundung", "rounding") if r.joint else ("Kreisbogen mit Radius", "arc of radius")
            return Cause(
                "arc_radius",
                line,
                f"Zeile {line}: {what} R{word(s.radius, 2)} statt R{word(r.radius, 2)}.",
                f"Line {line}: {what_en} R{word(s.radius, 2)} instead of R{word(r.radius, 2)}.",
                ri,
            )
        if starts:
            return Cause(
                "arc_end",
                line,
                f"Zeile {line}: Der Kreisbogen endet bei {_pt(s.end, lathe)} statt bei {_pt(r.end, lathe)}.",
                f"Line {line}: the arc ends at {_pt(s.end, lathe)} instead of {_pt(r.end, lathe)}.",
                ri,
            )
    if r.kind != s.kind and starts:
        kinds = ("Gerade", "Kreisbogen") if s.kind == "line" else ("Kreisbogen", "Gerade")
        kinds_en = ("a line", "an arc") if s.kind == "line" else ("an arc", "a line")
        return Cause(
            "element_kind",
            line,
            f"Zeile {line}: {kinds[0]} statt {kinds[1]} ({describe(r, lathe)}).",
            f"Line {line}: {kinds_en[0]} instead of {kinds_en[1]} ({describe(r, lathe, 'en')}).",
            ri,
        )
    if lathe:
        dz, dx = abs(s.end[0] - r.end[0]), abs(s.end[1] - r.end[1])
        if dx > SAME and dz <= SAME:
            return Cause(
                "end_point",
                line,
                f"Zeile {line}: Ø{word(2 * s.end[1])} statt Ø{word(2 * r.end[1])}.",
                f"Line {line}: Ø{word(2 * s.end[1])} instead of Ø{word(2 * r.end[1])}.",
                ri,
            )
        if dz > SAME and dx <= SAME:
            return Cause(
                "end_point",
                line,
                f"Zeile {line}: endet bei Z{word(s.end[0])} statt bei Z{word(r.end[0])}.",
                f"Line {line}: ends at Z{word(s.end[0])} instead of Z{word(r.end[0])}.",
                ri,
            )
    if ends and not starts:
        return Cause(
            "end_point",
            line,
            f"Zeile {line}: Das Konturelement beginnt bei {_pt(s.start, lathe)} statt bei "
            f"{_pt(r.start, lathe)}.",
            f"Line {line}: the contour element starts at {_pt(s.start, lathe)} "
            f"instead of {_pt(r.start, lathe)}.",
            ri,
        )
    return Cause(
        "end_point",
        line,
        f"Zeile {line}: Das Konturelement endet bei {_pt(s.end, lathe)} statt bei {_pt(r.end, lathe)}.",
        f"Line {line}: the contour element ends at {_pt(s.end, lathe)} instead of {_pt(r.end, lathe)}.",
        ri,
    )


def distance(e: Element, p: Point) -> float:
    """The distance of `p` from the programmed element `e` (a segment, or an arc with its ends)."""
    ends = min(math.dist(p, e.start), math.dist(p, e.end))
    if e.kind == "arc" and e.center is not None:
        c = e.center
        d = math.dist(p, c)
        if d < 1e-12:
            return ends
        a0 = math.atan2(e.start[1] - c[1], e.start[0] - c[0])
        a1 = math.atan2(e.end[1] - c[1], e.end[0] - c[0])
        ap = math.atan2(p[1] - c[1], p[0] - c[0])
        span = (a0 - a1) % (2 * math.pi) if e.cw else (a1 - a0) % (2 * math.pi)
        at = (a0 - ap) % (2 * math.pi) if e.cw else (ap - a0) % (2 * math.pi)
        return min(ends, abs(d - e.radius)) if at <= span + 1e-9 else ends
    dx, dy = e.end[0] - e.start[0], e.end[1] - e.start[1]
    n2 = dx * dx + dy * dy
    t = 0.0 if n2 < 1e-18 else max(0.0, min(1.0, ((p[0] - e.start[0]) * dx + (p[1] - e.start[1]) * dy) / n2))
    return math.hypot(p[0] - e.start[0] - t * dx, p[1] - e.start[1] - t * dy)


def nearest_line(elems: list[Element], p: Point, reach: float = math.inf) -> int | None:
    """The line of the element nearest to `p` (within `reach`), None if there is none."""
    best: tuple[float, int] | None = None
    for e in elems:
        d = distance(e, p)
        if d <= reach and (best is None or d < best[0]):
            best = (d, e.line)
    return best[1] if best is not None else None
