"""The technology criterion's words: which spindle direction a task asks for, and which word of a program is in
effect at a cut and where it was set (`E0.12 aus Zeile 5`), for milling and turning alike."""

from __future__ import annotations

import re

from core.exercises import Exercise
from core.grading.numbers import word
from core.toolpath import Move, Toolpath


def spindle_wanted(ex: Exercise, reference: Toolpath) -> dict[int, str]:
    """Tool → the spindle direction the task asks for ("M3" or "M4"): the cutting data's `spindle`, else the
    direction the reference turns the spindle in for that tool's cuts."""
    wanted: dict[int, str] = {}
    for m in reference.moves:
        if m.kind != "rapid" and m.tool is not None and m.spindle_direction is not None:
            wanted.setdefault(m.tool, "M3" if m.spindle_direction == "cw" else "M4")
    for d in ex.cutting_data:
        if d.spindle is not None:
            wanted[d.tool] = d.spindle
    return wanted


_COMMENT = re.compile(r"\(.*?\)|;.*$")


def set_where(program: str, line: int, addresses: str, value: float | None = None) -> tuple[str, int] | None:
    """The word that is in effect at `line` and where it was set: the last word of one of `addresses` (with
    `value`, if given) at or before that line, e.g. ("E0.12", 5). A program's text order, comments left out."""
    lines = program.splitlines()
    for n in range(min(line, len(lines)), 0, -1):
        text = _COMMENT.sub("", lines[n - 1]).upper()
        found = [
            (mt.group(1), mt.group(2))
            for mt in re.finditer(r"(?<![A-Z])([A-Z])\s*=?\s*([+-]?(?:\d+\.?\d*|\.\d+))", text)
            if mt.group(1) in addresses
        ]
        for address, raw in reversed(found):
            try:
                number = float(raw)
            except ValueError:
                continue
            if value is None or abs(number - value) <= 1e-9 * max(1.0, abs(value)):
                return f"{address}{raw}", n
    return None


def spindle_set_where(program: str, line: int) -> int | None:
    """The line of the last M3/M4 (M13/M14) at or before `line`."""
    lines = program.splitlines()
    for n in range(min(line, len(lines)), 0, -1):
        if re.search(r"(?<![A-Z0-9])M0*(3|4|13|14)(?![0-9])", _COMMENT.sub("", lines[n - 1]).upper()):
            return n
    return None


def direction_fault(m: Move, want: str | None, program: str, line: int) -> tuple[str, str] | None:
    """`M3 statt M4` for a cut whose spindle turns against the task's direction; None if it turns as asked."""
    if want is None or m.spindle_direction is None:
        return None
    have = "M3" if m.spindle_direction == "cw" else "M4"
    if have == want:
        return None
    names = {"M3": ("Rechtslauf", "clockwise"), "M4": ("Linkslauf", "counter-clockwise")}
    where = spindle_set_where(program, line)
    at, at_en = (
        (f" (gesetzt in Zeile {where})", f" (set in line {where})") if where and where != line else ("", "")
    )
    return (
        f"Spindel {have} ({names[have][0]}){at} statt {want} ({names[want][0]}) für T{m.tool}.",
        f"spindle {have} ({names[have][1]}){at_en} instead of {want} ({names[want][1]}) for T{m.tool}.",
    )


def in_effect(program: str, line: int, value: float, addresses: str = "F") -> tuple[str, str, int | None]:
    """How a cut at `line` got its value, for a message: `F300` when its own block says so, else `F300 (gesetzt in
    Zeile 3)`, or for a word of another address (a modal E in effect) `E0.12 aus Zeile 5`; and that other line."""
    found = set_where(program, line, addresses, value)
    if found is None:
        return f"{addresses[0]}{word(value)}", f"{addresses[0]}{word(value)}", None
    text, where = found
    if where == line and text[0] == addresses[0]:
        return text, text, None
    if text[0] == addresses[0]:
        return f"{text} (gesetzt in Zeile {where})", f"{text} (set in line {where})", where
    return f"{text} aus Zeile {where}", f"{text} from line {where}", where
