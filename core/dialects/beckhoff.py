"""Beckhoff TwinCAT CNC (DIN 66025 milling): the code table, with chamfers and roundings G301/G302.

Source: ../shared/spec/beckhoff-chamfer-round.md and DECISIONS.md §14. `G301 I…` (chamfer) and
`G302 I…` (rounding) in a block of their own act on the corner between the motion blocks before
and after them; I is kept for the next G301/G302 and must not be 0 the first time. The extended
forms `G301=…`, `G302=…`, `#CHR=…` (chamfer width), `#CHF=…` (chamfer length) and `#RND=…`
(radius) go into the first of the two motion blocks and are not kept. `#FRC=…` is the feed in the
inserted element only. The element lies in the plane of the second motion block.
"""

from __future__ import annotations

from core.dialects.codes import Address, Code, CodeTable, Group

AXES = frozenset({"X", "Y", "Z"})
CENTRE = frozenset({"I", "J", "K"})
TRANSITIONS = frozenset({"G301", "G302", "#CHR", "#CHF", "#RND", "#FRC"})
VALUED_CODES = frozenset({"G301", "G302"})  # written G301=20 in a motion block

GROUPS = (
    Group("motion", "Wegbedingung", "motion", ("G0", "G1", "G2", "G3"), "G1"),
    Group("plane", "Ebene", "plane", ("G17", "G18", "G19"), "G17"),
    Group("compensation", "Werkzeugradiuskorrektur", "tool radius compensation", ("G40", "G41", "G42"), "G40"),
    Group("dimensions", "Maßangabe", "dimensions", ("G90", "G91"), "G90"),
    Group("spindle", "Spindel", "spindle", ("M3", "M4", "M5"), "M5"),
    Group("coolant", "Kühlmittel", "coolant", ("M8", "M9"), "M9"),
    Group("program_end", "Programmende", "end of program", ("M2", "M30"), None),
)


def _motion(name: str, de: str, en: str, words: frozenset[str]) -> Code:
    return Code(name, "motion", de, en, words=words | TRANSITIONS, owns_block=True)


TABLE = CodeTable(
    codes={c.name: c for c in [
        _motion("G0", "Eilgang", "rapid traverse", AXES | {"T"}),
        _motion("G1", "Geradeninterpolation", "linear interpolation", AXES | {"T"}),
        _motion("G2", "Kreis im Uhrzeigersinn", "circle clockwise", AXES | CENTRE | {"R"}),
        _motion("G3", "Kreis gegen den Uhrzeigersinn", "circle counter-clockwise", AXES | CENTRE | {"R"}),
        Code("G17", "plane", "Ebene X-Y", "plane X-Y"),
        Code("G18", "plane", "Ebene Z-X", "plane Z-X"),
        Code("G19", "plane", "Ebene Y-Z", "plane Y-Z"),
        Code("G40", "compensation", "Werkzeugradiuskorrektur aus", "tool radius compensation off"),
        Code("G41", "compensation", "Werkzeugradiuskorrektur links", "tool radius compensation left"),
        Code("G42", "compensation", "Werkzeugradiuskorrektur rechts", "tool radius compensation right"),
        Code("G90", "dimensions", "Absolutmaß", "absolute dimensions"),
        Code("G91", "dimensions", "Kettenmaß", "incremental dimensions"),
        Code("G301", None, "Fase zwischen zwei Verfahrsätzen einfügen (Breite I)",
             "insert a chamfer between two motion blocks (width I)", words=frozenset({"I", "#FRC"}),
             owns_block=True),
        Code("G302", None, "Radius zwischen zwei Verfahrsätzen einfügen (Radius I)",
             "insert a rounding between two motion blocks (radius I)", words=frozenset({"I", "#FRC"}),
             owns_block=True),
        Code("M2", "program_end", "Programmende", "end of program"),
        Code("M3", "spindle", "Spindel rechts", "spindle clockwise"),
        Code("M4", "spindle", "Spindel links", "spindle counter-clockwise"),
        Code("M5", "spindle", "Spindel halt (am Satzende)", "spindle stop (at block end)"),
        Code("M6", None, "Werkzeugwechsel", "tool change"),
        Code("M8", "coolant", "Kühlmittel ein", "coolant on"),
        Code("M9", "coolant", "Kühlmittel aus (am Satzende)", "coolant off (at block end)"),
        Code("M30", "program_end", "Programmende", "end of program"),
    ]},
    addresses={a.name: a for a in [
        Address("N", "Satznummer", "block number", integer=True),
        Address("G", "Wegbedingung", "preparatory function", integer=True),
        Address("M", "Zusatzfunktion", "miscellaneous function", integer=True),
        Address("F", "Vorschub", "feed"),
        Address("S", "Spindeldrehzahl", "spindle speed"),
        Address("T", "Werkzeug", "tool", integer=True),
        Address("X", "Endpunkt X", "end point X"),
        Address("Y", "Endpunkt Y", "end point Y"),
        Address("Z", "Endpunkt Z", "end point Z"),
        Address("I", "Kreismittelpunkt X (inkremental); bei G301/G302 Fasenbreite bzw. Radius",
                "centre X (incremental); with G301/G302 chamfer width or radius"),
        Address("J", "Kreismittelpunkt Y (inkremental)", "centre Y (incremental)"),
        Address("K", "Kreismittelpunkt Z (inkremental)", "centre Z (incremental)"),
        Address("R", "Radius", "radius"),
        Address("G301", "Fase mit Breite (G301=…, nicht haltend)", "chamfer of this width (G301=…, not kept)"),
        Address("G302", "Radius (G302=…, nicht haltend)", "rounding of this radius (G302=…, not kept)"),
        Address("#CHR", "Fasenbreite", "chamfer width"),
        Address("#CHF", "Fasenlänge", "chamfer length"),
        Address("#RND", "Radius", "rounding radius"),
        Address("#FRC", "Vorschub im eingefügten Element", "feed in the inserted element"),
    ]},
    groups=GROUPS,
    always_allowed=frozenset({"F", "S", "M"}),
)
