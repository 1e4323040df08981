"""SINUMERIK 808D in ISO mode (milling): the code table.

Source: ../shared/spec/iso-808d-arcs.md and DECISIONS.md §13. Planes G17 (X-Y, centre I J),
G18 (Z-X, centre K I) and G19 (Y-Z, centre J K); G02/G03 with the end point and R (R+ at most
180°, R- the longer arc) or the centre offsets, which are always incremental from the start point.
An arc whose two end-point axes name another plane than the selected one lies in that plane. The
optional fifth linear axes U, V, W are not part of the trainer's 3-axis machine.
"""

from __future__ import annotations

from core.dialects.codes import Address, Code, CodeTable, Group

AXES = frozenset({"X", "Y", "Z"})
CENTRE = frozenset({"I", "J", "K"})

GROUPS = (
    Group("motion", "Wegbedingung", "motion", ("G0", "G1", "G2", "G3"), "G1"),
    Group("plane", "Ebene", "plane", ("G17", "G18", "G19"), "G17"),
    Group("compensation", "Werkzeugradiuskorrektur", "tool radius compensation", ("G40", "G41", "G42"), "G40"),
    Group("dimensions", "Maßangabe", "dimensions", ("G90", "G91"), "G90"),
    Group("feed_mode", "Vorschubart", "feed mode", ("G94", "G95"), "G94"),
    Group("spindle", "Spindel", "spindle", ("M3", "M4", "M5"), "M5"),
    Group("coolant", "Kühlmittel", "coolant", ("M8", "M9"), "M9"),
    Group("program_end", "Programmende", "end of program", ("M2", "M30"), None),
)


def _motion(name: str, de: str, en: str, words: frozenset[str]) -> Code:
    return Code(name, "motion", de, en, words=words, owns_block=True)


TABLE = CodeTable(
    codes={c.name: c for c in [
        _motion("G0", "Eilgang", "rapid traverse", AXES | {"T"}),
        _motion("G1", "Geradeninterpolation", "linear interpolation", AXES | {"T"}),
        _motion("G2", "Kreis im Uhrzeigersinn", "circle clockwise", AXES | CENTRE | {"R"}),
        _motion("G3", "Kreis gegen den Uhrzeigersinn", "circle counter-clockwise", AXES | CENTRE | {"R"}),
        Code("G17", "plane", "Ebene X-Y (Mittelpunkt I, J)", "plane X-Y (centre I, J)"),
        Code("G18", "plane", "Ebene Z-X (Mittelpunkt K, I)", "plane Z-X (centre K, I)"),
        Code("G19", "plane", "Ebene Y-Z (Mittelpunkt J, K)", "plane Y-Z (centre J, K)"),
        Code("G40", "compensation", "Werkzeugradiuskorrektur aus", "tool radius compensation off"),
        Code("G41", "compensation", "Werkzeugradiuskorrektur links", "tool radius compensation left"),
        Code("G42", "compensation", "Werkzeugradiuskorrektur rechts", "tool radius compensation right"),
        Code("G90", "dimensions", "Absolutmaß", "absolute dimensions"),
        Code("G91", "dimensions", "Kettenmaß", "incremental dimensions"),
        Code("G94", "feed_mode", "Vorschub in mm/min", "feed in mm/min"),
        Code("G95", "feed_mode", "Vorschub in mm/Umdrehung", "feed in mm per revolution"),
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
        Address("X", "Endpunkt X (G90 absolut, G91 inkremental)", "end point X (G90 absolute, G91 incremental)"),
        Address("Y", "Endpunkt Y", "end point Y"),
        Address("Z", "Endpunkt Z", "end point Z"),
        Address("I", "Abstand Startpunkt – Kreismittelpunkt in X", "distance start point – centre in X"),
        Address("J", "Abstand Startpunkt – Kreismittelpunkt in Y", "distance start point – centre in Y"),
        Address("K", "Abstand Startpunkt – Kreismittelpunkt in Z", "distance start point – centre in Z"),
        Address("R", "Radius (R+ bis 180°, R- über 180°)", "radius (R+ up to 180°, R- over 180°)"),
    ]},
    groups=GROUPS,
    always_allowed=frozenset({"F", "S", "M"}),
)
