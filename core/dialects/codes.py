"""The shape of a dialect's code table: what each G/M code and each address means.

One table per dialect drives the interpreter's checks (allowed and mandatory words, modal
groups, order of execution), and later the API's help endpoint and the editor's hover text.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from enum import Enum


class Support(str, Enum):
    """How far the interpreter implements a code or address."""

    YES = "yes"
    PLANNED = "planned"  # parses and is checked; executing it yields "not supported yet"


@dataclass(frozen=True, slots=True)
class Code:
    """A G or M code: its modal group, the words it takes and its help texts."""

    name: str  # "G1", "M3"
    group: str | None  # modal group; None for a non-modal code
    help_de: str
    help_en: str
    words: frozenset[str] = frozenset()  # addresses the code allows in its block
    required: tuple[tuple[str, ...], ...] = ()  # each inner tuple: one of these is mandatory
    owns_block: bool = False  # the block's address words belong to this code (motion, G4, G22 …)
    alone: bool = False  # must stand alone in its block (G50, G53)
    sets: tuple[str, ...] = ()  # modal codes it activates, when not just itself (M13 = M3 + M8)
    support: Support = Support.YES
    feature_de: str = ""  # the feature's name in "not supported yet" diagnostics
    feature_en: str = ""
    # help only (hover, completion, docs): one example block, the rule to remember, and what the block needs
    # when that says more than `required` (G2: an end point and a centre or radius)
    example: str = ""
    rule_de: str = ""
    rule_en: str = ""
    mandatory: tuple[tuple[str, ...], ...] | None = None
    # how the interpreter treats it, where a dialect's manual sets rules of its own (TRAUB TX 8 D)
    needs_tool: bool = False  # only with a T word in its block (TRAUB M6, M13: L1160–1190)
    with_srk: bool = False  # allowed while the cutting-edge radius compensation is on (TRAUB L2544–2566)
    change_point: bool = (
        False  # goes to the tool change point and deselects the tool data (TRAUB G24–G28, G53)
    )
    speed: bool = (
        False  # sets the spindle speed or its limit and takes X/Z/Q of its own (TRAUB G92, G96, G97)
    )
    cycle: str = ""  # the family of cycles that executes it (core/interpreter/traub_cycles.py: FAMILIES)

    def help_mandatory(self) -> tuple[tuple[str, ...], ...]:
        """Groups of addresses of which the block needs one each (for the help; the checks use `required`)."""
        return self.required if self.mandatory is None else self.mandatory

    def help_optional(self) -> tuple[str, ...]:
        """The other addresses the code takes, in alphabetical order."""
        needed = {a for group in self.help_mandatory() for a in group}
        return tuple(sorted(self.words - needed))


@dataclass(frozen=True, slots=True)
class Address:
    """An address letter (or letter pair) and what its value means."""

    name: str
    help_de: str
    help_en: str
    integer: bool = False  # the value must be a whole number
    flag: bool = False  # may be written without a value (G66 X Y)
    unit: str = ""  # of the value, for the help ("mm", "mm/min", "°"); "" for numbers and choices
    non_negative: bool = False  # a value below zero is an error (PAL-E109)
    rule_de: str = ""  # the rule to remember (RN: "+ Rundung, − Fase")
    rule_en: str = ""


@dataclass(frozen=True, slots=True)
class Group:
    """A modal group: at most one member per block; the last one programmed stays active."""

    name: str
    label_de: str
    label_en: str
    members: tuple[str, ...]
    switch_on: str | None  # active at program start


@dataclass(frozen=True)
class CodeTable:
    """Everything the interpreter needs to know about the words of one dialect."""

    codes: dict[str, Code]
    addresses: dict[str, Address]
    groups: tuple[Group, ...]
    always_allowed: frozenset[str]  # addresses allowed in every block
    tool_words: frozenset[str] = frozenset({"T"})  # the words of a tool change
    max_g_words: int | None = None  # G words allowed in one block (PAL: 2)
    strict_technology: bool = False  # a cut with no tool or a stopped spindle is an error (else a warning)
    # DIN 66025 / ISO rules (SINUMERIK ISO, Beckhoff) instead of PAL's: an arc's omitted end-point axis is the
    # current position (G90) or 0 (G91) and an omitted centre offset 0; the plane of an arc is left only when its
    # centre words (or R) cannot belong to it; D selects the tool offset; a code the control knows but the product
    # does not model is a warning, and the rest of its block runs
    din: bool = False
    # the arc end-point check: start and end radius may differ by max(RunSetup.arc_tolerance, factor × radius)
    arc_tolerance_factor: float = 0.0
    centre_correction: bool = False  # Beckhoff G165: the centre is moved onto the arc within limits
    modal_radius: bool = (
        False  # Beckhoff: R is kept for the next arcs (R alone in a G02/G03 block: no motion)
    )
    program_prefix: str = "L"  # subprograms: L<n> (PAL, `%L<n>` headers) or O<n> (ISO, `O<n>` lines)
    unsupported_prefixes: tuple[
        str, ...
    ] = ()  # words of the control the product does not model (#HSC, V.P.X)
    group_of: dict[str, str] = field(init=False)
    technology_words: frozenset[str] = field(init=False)  # a block of only these moves nothing
    pairs: dict[str, tuple[tuple[str, str], ...]] = field(init=False)  # code → (group, member) it switches
    non_negative: tuple[str, ...] = field(init=False)  # the addresses whose values must not be negative
    # the interpreter's lookups, built once per table instead of once per block:
    numbered: dict[str, dict[float, Code]] = field(init=False)  # "G"/"M" → whole number → code (G1: 1)
    takes: dict[str, frozenset[str]] = field(init=False)  # code → the addresses allowed in its block
    has_cycles: bool = field(init=False)  # a modal group "cycle" (ISO drilling cycles), which G0–G3 end

    def __post_init__(self) -> None:
        group_of = {m: g.name for g in self.groups for m in g.members}
        object.__setattr__(self, "group_of", group_of)
        object.__setattr__(self, "technology_words", self.always_allowed | self.tool_words)
        object.__setattr__(
            self, "non_negative", tuple(a for a, spec in self.addresses.items() if spec.non_negative)
        )
        object.__setattr__(
            self,
            "pairs",
            {
                name: tuple((group_of[m], m) for m in self.activates(code))
                for name, code in self.codes.items()
            },
        )
        numbered: dict[str, dict[float, Code]] = {}
        for name, code in self.codes.items():
            # (G50.1 and other decimal codes are looked up by their name)
            if name[1:].isdigit() and name == f"{name[0]}{int(name[1:])}":
                numbered.setdefault(name[0], {})[int(name[1:])] = code
        object.__setattr__(self, "numbered", numbered)
        object.__setattr__(
            self, "takes", {name: code.words | self.always_allowed for name, code in self.codes.items()}
        )
        object.__setattr__(self, "has_cycles", "cycle" in group_of.values())

    def activates(self, code: Code) -> tuple[str, ...]:
        """The modal group members that `code` switches on."""
        return code.sets or ((code.name,) if code.name in self.group_of else ())

    def group(self, name: str) -> Group:
        return next(g for g in self.groups if g.name == name)
