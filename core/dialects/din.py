"""The DIN 66025 core that the ISO dialects share (SINUMERIK 808D ISO, Beckhoff TwinCAT): codes and addresses.

Each dialect's table takes these and adds or replaces what is its own. What differs from PAL (the interpreter
reads `CodeTable.din`): an arc's omitted end-point axis is the current position (G90) or 0 (G91), an omitted
centre offset I/J/K is 0 (shared/spec/iso-808d-arcs.md §2, Beckhoff "Circular interpolation (G02/G03)"); D
selects the tool offset (the radius of the active tool's offset memory D, D0 none); a code the control knows
but the product does not model gives one "not supported yet" warning and the rest of its block runs.
"""

from __future__ import annotations

from dataclasses import replace

from core.dialects.codes import Address, Code, Group, Support

P = Support.PLANNED

AXES = frozenset({"X", "Y", "Z"})
CENTRE = frozenset({"I", "J", "K"})
TARGET = ("X", "Y", "Z")

GROUPS = (
    Group("motion", "Wegbedingung", "motion", ("G0", "G1", "G2", "G3"), "G1"),
    Group("plane", "Ebene", "plane", ("G17", "G18", "G19"), "G17"),
    Group(
        "compensation", "Werkzeugradiuskorrektur", "tool radius compensation", ("G40", "G41", "G42"), "G40"
    ),
    Group("dimensions", "Maßangabe", "dimensions", ("G90", "G91"), "G90"),
    Group("spindle", "Spindel", "spindle", ("M3", "M4", "M5"), "M5"),
    Group("coolant", "Kühlmittel", "coolant", ("M8", "M9"), "M9"),
    Group("program_end", "Programmende", "end of program", ("M2", "M30"), None),
)

ARC_DE = (
    "Endpunkt (weggelassene Achse: aktuelle Position) und Mittelpunkt I/J/K (weggelassen: 0) oder Radius R"
)
ARC_EN = "end point (an omitted axis: the current position) and centre I/J/K (omitted: 0) or radius R"


def motion_codes(extra: frozenset[str] = frozenset()) -> list[Code]:
    """G0–G3, each allowing `extra` words besides its own."""

    def motion(name: str, de: str, en: str, words: frozenset[str], **kw: object) -> Code:
        return Code(name, "motion", de, en, words=words | extra, owns_block=True, **kw)  # type: ignore[arg-type]

    return [
        motion(
            "G0",
            "Eilgang",
            "rapid traverse",
            AXES | {"T"},
            example="N30 G00 X-20 Y10 Z2",
            mandatory=(TARGET,),
            rule_de="mindestens eine Koordinate; Eilgang, nie ins Material",
            rule_en="at least one coordinate; rapid, never into the material",
        ),
        motion(
            "G1",
            "Geradeninterpolation",
            "linear interpolation",
            AXES | {"T"},
            example="N40 G01 Z-2 F150",
            mandatory=(TARGET,),
        ),
        motion(
            "G2",
            "Kreis im Uhrzeigersinn",
            "circle clockwise",
            AXES | CENTRE | {"R"},
            example="N80 G02 X80 Y70 I20 J0",
            mandatory=(("I", "J", "K", "R"),),
            rule_de=ARC_DE,
            rule_en=ARC_EN,
        ),
        motion(
            "G3",
            "Kreis gegen den Uhrzeigersinn",
            "circle counter-clockwise",
            AXES | CENTRE | {"R"},
            example="N60 G03 X60 Y30 R20",
            mandatory=(("I", "J", "K", "R"),),
            rule_de=ARC_DE,
            rule_en=ARC_EN,
        ),
    ]


CODES = [
    Code("G17", "plane", "Ebene X-Y (Mittelpunkt I, J)", "plane X-Y (centre I, J)", example="N10 G17"),
    Code("G18", "plane", "Ebene Z-X (Mittelpunkt K, I)", "plane Z-X (centre K, I)", example="N10 G18"),
    Code("G19", "plane", "Ebene Y-Z (Mittelpunkt J, K)", "plane Y-Z (centre J, K)", example="N10 G19"),
    Code(
        "G40",
        "compensation",
        "Werkzeugradiuskorrektur aus",
        "tool radius compensation off",
        example="N90 G40",
    ),
    Code(
        "G41",
        "compensation",
        "Werkzeugradiuskorrektur links",
        "tool radius compensation left",
        example="N40 G41 G1 X10 Y20",
        rule_de="Werkzeug links der Kontur, in Vorschubrichtung gesehen",
        rule_en="tool left of the contour, seen in the feed direction",
    ),
    Code(
        "G42",
        "compensation",
        "Werkzeugradiuskorrektur rechts",
        "tool radius compensation right",
        example="N40 G42 G1 X10 Y20",
        rule_de="Werkzeug rechts der Kontur, in Vorschubrichtung gesehen",
        rule_en="tool right of the contour, seen in the feed direction",
    ),
    Code("G90", "dimensions", "Absolutmaß", "absolute dimensions", example="N10 G90"),
    Code("G91", "dimensions", "Kettenmaß", "incremental dimensions", example="N10 G91"),
    Code(
        "M0",
        None,
        "Programmierter Halt (ohne Wirkung auf die Bahn)",
        "programmed stop (no effect on the path)",
        example="N50 M00",
    ),
    Code(
        "M1",
        None,
        "Wahlweiser Halt (ohne Wirkung auf die Bahn)",
        "optional stop (no effect on the path)",
        example="N50 M01",
    ),
    Code("M2", "program_end", "Programmende", "end of program", example="N200 M02"),
    Code("M3", "spindle", "Spindel rechts", "spindle clockwise", example="N20 S1200 M03"),
    Code("M4", "spindle", "Spindel links", "spindle counter-clockwise", example="N20 S800 M04"),
    Code("M5", "spindle", "Spindel halt (am Satzende)", "spindle stop (at block end)", example="N190 M05"),
    Code("M6", None, "Werkzeugwechsel", "tool change", example="N10 T1 M06"),
    Code("M8", "coolant", "Kühlmittel ein", "coolant on", example="N20 M08"),
    Code("M9", "coolant", "Kühlmittel aus (am Satzende)", "coolant off (at block end)", example="N190 M09"),
    Code("M30", "program_end", "Programmende", "end of program", example="N200 M30"),
]

ADDRESSES = [
    Address("N", "Satznummer", "block number", integer=True),
    Address("G", "Wegbedingung", "preparatory function", integer=True),
    Address("M", "Zusatzfunktion", "miscellaneous function", integer=True),
    Address(
        "F",
        "Vorschub",
        "feed",
        unit="mm/min",
        rule_de="mm/min unter G94, mm pro Umdrehung unter G95",
        rule_en="mm/min under G94, mm per revolution under G95",
    ),
    Address("S", "Spindeldrehzahl", "spindle speed", unit="1/min"),
    Address("T", "Werkzeug", "tool", integer=True),
    Address(
        "D",
        "Werkzeugkorrektur: Radius aus dem Korrekturspeicher D des Werkzeugs (D0: keine)",
        "tool offset: the radius from the tool's offset memory D (D0: none)",
        integer=True,
    ),
    Address(
        "X",
        "Endpunkt X (G90 absolut, G91 inkremental)",
        "end point X (G90 absolute, G91 incremental)",
        unit="mm",
    ),
    Address("Y", "Endpunkt Y", "end point Y", unit="mm"),
    Address("Z", "Endpunkt Z", "end point Z", unit="mm"),
    Address(
        "I",
        "Abstand Startpunkt – Kreismittelpunkt in X (weggelassen: 0)",
        "distance start point – centre in X (omitted: 0)",
        unit="mm",
    ),
    Address(
        "J",
        "Abstand Startpunkt – Kreismittelpunkt in Y (weggelassen: 0)",
        "distance start point – centre in Y (omitted: 0)",
        unit="mm",
    ),
    Address(
        "K",
        "Abstand Startpunkt – Kreismittelpunkt in Z (weggelassen: 0)",
        "distance start point – centre in Z (omitted: 0)",
        unit="mm",
    ),
    Address(
        "R",
        "Radius (R+ bis 180°, R- über 180°)",
        "radius (R+ up to 180°, R- over 180°)",
        unit="mm",
        rule_de="+ Bogen bis 180°, − Bogen über 180°",
        rule_en="+ arc up to 180°, − arc over 180°",
    ),
]
# values that must not be negative (PAL-E109): feed, speed, the tool offset, K of a drilling cycle (its count)
ADDRESSES = [replace(a, non_negative=True) if a.name in ("F", "S", "D", "K") else a for a in ADDRESSES]


def planned(
    name: str,
    de: str,
    en: str,
    group: str | None = None,
    owns: bool = True,
    words: frozenset[str] = frozenset(),
) -> Code:
    """A code the control knows and the product does not model yet: one warning, the rest of its block runs.

    `owns`: the block's coordinates are the code's data (G92 X0 Y0: no motion), not a target to move to."""
    return Code(
        name,
        group,
        de,
        en,
        words=words,
        owns_block=owns,
        support=P,
        feature_de=f"{de} {name}",
        feature_en=f"{en[0].upper()}{en[1:]} {name}",
    )
