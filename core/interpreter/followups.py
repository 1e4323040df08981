"""Follow-up errors: a diagnostic that only follows from a dropped block says so (core.diagnostics.FOLLOW_UPS).

The interpreter tells the tracker about every block it meets: rejected by the parser, or executed with or
without an error. The tracker keeps what dropped blocks may have left wrong — the axes they would have
moved, F, S, the spindle start, the tool, their block number — each with the dropped block's line, until
a block that runs sets it again; and it notes that per executed block, so that the diagnostics of the
later contour stage are judged by their line too. At the end, `finish` names the follow-ups and folds a
finding repeated on many feed moves (no feed, spindle stopped, no tool) into one note.
"""

from __future__ import annotations

import dataclasses
import re
from collections.abc import Iterable
from typing import Any

from core.diagnostics import FOLLOW_UPS, REPEATED, Diagnostic, Severity, as_follow_up, diag
from core.syntax.blocks import Block

_AXES = {"X": "X", "XI": "X", "XA": "X", "Y": "Y", "YI": "Y", "YA": "Y", "Z": "Z", "ZI": "Z", "ZA": "Z"}
_ABSOLUTE = frozenset({"XA", "YA", "ZA"})
_PLANE_WORDS = frozenset({"RP", "AP", "AI", "AS", "D"})  # end points in the plane without X/Y (polar, D/AS)
_SPINDLE_ON = frozenset({3, 4, 13, 14})
_DEPENDS = {
    "position": ("X", "Y"),
    "feed": ("F",),
    "speed": ("S",),
    "spindle": ("M3",),
    "tool": ("T",),
    "cycle": ("cycle",),
}
_CYCLE_DEFINITIONS = frozenset(
    {72, 73, 74, 75, 81, 82, 83, 84, 85, 86, 87}
)  # PAL: G72–G75, G81–G87 define a cycle
_RAW_WORD = re.compile(r"([A-Z]+)\s*=?\s*([-+]?\d*)")
# what the note says the later blocks also are, for each repeated finding
_REPEATED_WHAT = {
    "PAL-E301": ("Vorschubbewegung mit Vorschub F0", "Feed move with feed F0"),
    "PAL-E302": ("Vorschubbewegung bei stehender Spindel", "Feed move with the spindle stopped"),
    "PAL-E303": ("Vorschubbewegung ohne Werkzeug", "Feed move with no tool"),
}


def _keys(words: Iterable[tuple[str, float | None]]) -> set[str]:
    """What a block with these (address, value) words sets: axes X/Y/Z, F, S, M3 (spindle on), T, N<n>, the
    PAL cycle definition."""
    keys: set[str] = set()
    for a, v in words:
        if a in _AXES:
            keys.add(_AXES[a])
        elif a in _PLANE_WORDS:
            keys.update(("X", "Y"))
        elif a in ("F", "S", "T"):
            keys.add(a)
        elif a == "M" and v is not None and int(v) in _SPINDLE_ON:
            keys.add("M3")
        elif a == "M" and v == 6:
            keys.add("T")
        elif a == "N" and v is not None:
            keys.add(f"N{int(v)}")
        elif a == "G" and v is not None and v in _CYCLE_DEFINITIONS:
            keys.add("cycle")
    return keys


def _raw_words(raw: str) -> list[tuple[str, float | None]]:
    """The words a rejected line seems to hold, read loosely from its text (comments left out)."""
    text = re.sub(r"\(.*?\)", " ", raw.split(";", 1)[0]).upper()
    return [(a, float(v) if v.lstrip("+-") else None) for a, v in _RAW_WORD.findall(text)]


class FollowUps:
    """What dropped blocks left unknown, while a run goes on (one per run of the interpreter)."""

    def __init__(self) -> None:
        self.unknown: dict[str, int] = {}  # key (see _keys) → line of the dropped block
        self.at: dict[tuple[str | None, int], dict[str, int]] = {}  # (source, line) → unknown before it ran

    def dropped(self, block: Block) -> None:
        """`block` was rejected by the parser: whatever it seems to set is unknown from here on."""
        lost = _keys(_raw_words(block.text)) | ({f"N{block.number}"} if block.number is not None else set())
        if lost:  # a new dict: the notes in `at` share the old one
            self.unknown = {**self.unknown, **dict.fromkeys(lost, block.line)}

    def ran(
        self,
        block: Block,
        source: str | None,
        diagnostics: list[Diagnostic],
        executed: bool,
        moved: bool,
        absolute: bool,
    ) -> None:
        """`block` was executed (`executed` False: it stopped at an error before doing anything)."""
        before = self.unknown
        if before:
            self.at.setdefault((source, block.line), before)  # never mutated: changes make a new dict
        words = [(w.address, w.value) for w in block.words]
        keys = _keys(words)
        errors = [d for d in diagnostics if d.severity is Severity.ERROR]
        if errors:
            origins = [self._origin(d, before) for d in errors]
            origin = block.line if None in origins else max(o for o in origins if o is not None)
            lost = keys if not executed else {k for k in keys if k in ("X", "Y", "Z")} if not moved else set()
            if lost:
                self.unknown = {**self.unknown, **dict.fromkeys(lost, origin)}
            if not executed:
                return
        known = {k for k in keys if k in ("F", "S", "M3", "T", "cycle")}
        if not errors or moved:  # axes written absolutely are known again
            known |= {_AXES[a] for a, _ in words if a in _ABSOLUTE or (absolute and a in ("X", "Y", "Z"))}
        if known & self.unknown.keys():
            self.unknown = {k: v for k, v in self.unknown.items() if k not in known}

    def _origin(self, d: Diagnostic, unknown: dict[str, int]) -> int | None:
        """The line of the dropped block `d` follows from, or None: `d` is an error of its own."""
        rule = FOLLOW_UPS.get(d.code)
        if rule is None or not unknown:
            return None
        keys = (f"N{d.params.get('number')}",) if rule[0] == "number" else _DEPENDS.get(rule[0], ())
        lines = [unknown[k] for k in keys if k in unknown]
        return max(lines) if lines else None

    def finish(self, diags: list[Diagnostic]) -> None:
        """Name the follow-ups among `diags` (in place), then fold each repeated finding into one note."""
        for i, d in enumerate(diags):
            if d.code in FOLLOW_UPS and d.follows_from is None:
                unknown = self.at.get((d.source, d.span.line))
                origin = self._origin(d, unknown) if unknown else None
                if origin is not None and origin != d.span.line:
                    diags[i] = as_follow_up(d, origin)
        _fold_repeated(diags)


def _fold_repeated(diags: list[Diagnostic]) -> None:
    """The first feed move without feed (spindle, tool) is the error; the later ones become one note."""
    groups: dict[str, list[int]] = {}
    for i, d in enumerate(diags):
        if d.code in REPEATED:
            groups.setdefault(d.code, []).append(i)
    drop: set[int] = set()
    for code, where in groups.items():
        if len(where) < 2:
            continue
        first, rest = diags[where[0]], [diags[i] for i in where[1:]]
        lines = ", ".join(f"{d.source}:{d.span.line}" if d.source else str(d.span.line) for d in rest)
        what, what_en = _REPEATED_WHAT[code]
        params: dict[str, Any] = {"what": what, "what_en": what_en, "count": len(rest), "lines": lines}
        note = as_follow_up(diag("PAL-I301", rest[0].span, **params), first.follows_from or first.span.line)
        diags[where[1]] = dataclasses.replace(note, source=rest[0].source)
        drop.update(where[2:])
    if drop:
        diags[:] = [d for i, d in enumerate(diags) if i not in drop]
