"""The DIN 66025 core that the ISO dialects share (SINUMERIK 808D ISO, Beckhoff TwinCAT): codes and addresses.

Each dialect's table takes these and adds or replaces what is its own.
"""

from __future__ import annotations

from core.dialects.codes import Address, Code, Group

AXES = frozenset({"X", "Y", "Z"})
CENTRE = frozenset({"I", "J", "K"})

GROUPS = (
    Group("motion", "Wegbedingung", "motion", ("G0", "G1", "G2", "G3"), "G1"),
    Group("plane", "Ebene", "plane", ("G17", "G18", "G19"), "G17"),
    Group("compensation", "Werkzeugradiuskorrektur", "tool radius compensation", ("G40", "G41", "G42"), "G40"),
    Group("dimensions", "Maßangabe", "dimensions", ("G90", "G91"), "G90"),
    Group("spindle", "Spindel", "spindle", ("M3", "M4", "M5"), "M5"),
    Group("coolant", "Kühlmittel", "coolant", ("M8", "M9"), "M9"),
    Group("program_end", "Programmende", "end of program", ("M2", "M30"), None),
)


def motion_codes(extra: frozenset[str] = frozenset()) -> list[Code]:
    """G0–G3, each allowing `extra` words besides its own."""
    def motion(name: str, de: str, en: str, words: frozenset[str]) -> Code:
        return Code(name, "motion", de, en, words=words | extra, owns_block=True)

    return [
        motion("G0", "Eilgang", "rapid traverse", AXES | {"T"}),
        motion("G1", "Geradeninterpolation", "linear interpolation", AXES | {"T"}),
        motion("G2", "Kreis im Uhrzeigersinn", "circle clockwise", AXES | CENTRE | {"R"}),
        motion("G3", "Kreis gegen den Uhrzeigersinn", "circle counter-clockwise", AXES | CENTRE | {"R"}),
    ]


CODES = [
    Code("G17", "plane", "Ebene X-Y (Mittelpunkt I, J)", "plane X-Y (centre I, J)"),
    Code("G18", "plane", "Ebene Z-X (Mittelpunkt K, I)", "plane Z-X (centre K, I)"),
    Code("G19", "plane", "Ebene Y-Z (Mittelpunkt J, K)", "plane Y-Z (centre J, K)"),
    Code("G40", "compensation", "Werkzeugradiuskorrektur aus", "tool radius compensation off"),
    Code("G41", "compensation", "Werkzeugradiuskorrektur links", "tool radius compensation left",
         example="N40 G41 G1 X10 Y20", rule_de="Werkzeug links der Kontur, in Vorschubrichtung gesehen",
         rule_en="tool left of the contour, seen in the feed direction"),
    Code("G42", "compensation", "Werkzeugradiuskorrektur rechts", "tool radius compensation right",
         example="N40 G42 G1 X10 Y20", rule_de="Werkzeug rechts der Kontur, in Vorschubrichtung gesehen",
         rule_en="tool right of the contour, seen in the feed direction"),
    Code("G90", "dimensions", "Absolutmaß", "absolute dimensions"),
    Code("G91", "dimensions", "Kettenmaß", "incremental dimensions"),
    Code("M2", "program_end", "Programmende", "end of program"),
    Code("M3", "spindle", "Spindel rechts", "spindle clockwise"),
    Code("M4", "spindle", "Spindel links", "spindle counter-clockwise"),
    Code("M5", "spindle", "Spindel halt (am Satzende)", "spindle stop (at block end)"),
    Code("M6", None, "Werkzeugwechsel", "tool change"),
    Code("M8", "coolant", "Kühlmittel ein", "coolant on"),
    Code("M9", "coolant", "Kühlmittel aus (am Satzende)", "coolant off (at block end)"),
    Code("M30", "program_end", "Programmende", "end of program"),
]

ADDRESSES = [
    Address("N", "Satznummer", "block number", integer=True),
    Address("G", "Wegbedingung", "preparatory function", integer=True),
    Address("M", "Zusatzfunktion", "miscellaneous function", integer=True),
    Address("F", "Vorschub", "feed", unit="mm/min"),
    Address("S", "Spindeldrehzahl", "spindle speed", unit="1/min"),
    Address("T", "Werkzeug", "tool", integer=True),
    Address("X", "Endpunkt X (G90 absolut, G91 inkremental)", "end point X (G90 absolute, G91 incremental)", unit="mm"),
    Address("Y", "Endpunkt Y", "end point Y", unit="mm"),
    Address("Z", "Endpunkt Z", "end point Z", unit="mm"),
    Address("I", "Abstand Startpunkt – Kreismittelpunkt in X", "distance start point – centre in X", unit="mm"),
    Address("J", "Abstand Startpunkt – Kreismittelpunkt in Y", "distance start point – centre in Y", unit="mm"),
    Address("K", "Abstand Startpunkt – Kreismittelpunkt in Z", "distance start point – centre in Z", unit="mm"),
    Address("R", "Radius (R+ bis 180°, R- über 180°)", "radius (R+ up to 180°, R- over 180°)", unit="mm",
            rule_de="+ Bogen bis 180°, − Bogen über 180°", rule_en="+ arc up to 180°, − arc over 180°"),
]
