"""Beckhoff TwinCAT CNC (DIN 66025 milling): the code table, with chamfers and roundings G301/G302.

Sources: ../shared/spec/beckhoff-chamfer-round.md and DECISIONS.md §14 for G301/G302; for the rest Beckhoff's
public TwinCAT CNC programming manual (infosys.beckhoff.com, "TF5200 | TwinCAT 3 CNC, Programming manual"):
circular interpolation G02/G03 with G161/G162 (centre absolute or relative) and the centre point correction
G164/G165 with its limits P-CHAN-00059/00060 (2 mm, 5 % of the radius) and P-CHAN-00171/00172, radius
programming with a modal R ("Radius programming (R, G163)"), dwell G04 X… / #TIME, zero offsets G53–G59, units
G70/G71, comments in parentheses. docs/dialects.md names what is modelled and what is "not supported yet".

`G301 I…` (chamfer) and `G302 I…` (rounding) in a block of their own act on the corner between the motion blocks
before and after them; I is kept for the next G301/G302 and must not be 0 the first time. The extended forms
`G301=…`, `G302=…`, `#CHR=…` (chamfer width), `#CHF=…` (chamfer length) and `#RND=…` (radius) go into the first
of the two motion blocks and are not kept. `#FRC=…` is the feed in the inserted element only. The element lies in
the plane of the second motion block. Other `#…` commands, `V.…` variables and `$…` control statements are out
of scope: one "not supported yet" warning each.
"""

from __future__ import annotations

from core.dialects import din
from core.dialects.codes import Address, Code, CodeTable, Group

TRANSITIONS = frozenset({"G301", "G302", "#CHR", "#CHF", "#RND", "#FRC"})
VALUED_CODES = frozenset({"G301", "G302"})  # written G301=20 in a motion block

GROUPS = (
    *din.GROUPS,
    Group(
        "zero_offset",
        "Nullpunktverschiebung",
        "zero offset",
        ("G53", "G54", "G55", "G56", "G57", "G58", "G59"),
        "G54",
    ),
    Group("units", "Maßeinheit", "units", ("G70", "G71"), "G71"),
    Group("feed_mode", "Vorschubart", "feed mode", ("G93", "G94", "G95"), "G94"),
    Group("spindle_mode", "Drehzahlart", "spindle mode", ("G96", "G97"), "G97"),
    Group("centre_mode", "Kreismittelpunkt", "circle centre", ("G161", "G162"), "G162"),
    Group("centre_correction", "Mittelpunktskorrektur", "centre point correction", ("G164", "G165"), "G165"),
    Group("mirror", "Spiegeln", "mirroring", ("G20", "G21", "G22", "G23"), "G20"),
)

_NO_PATH_DE, _NO_PATH_EN = " (ohne Wirkung auf die Bahn)", " (no effect on the path)"

_PLANNED = [
    din.planned(
        "G5",
        "Tangentiale An-/Abwahl der Werkzeugradiuskorrektur",
        "tangential selection of tool radius compensation",
        owns=False,
    ),
    din.planned("G21", "Spiegeln an der Y-Achse", "mirroring about the Y axis", group="mirror", owns=False),
    din.planned("G22", "Spiegeln an der X-Achse", "mirroring about the X axis", group="mirror", owns=False),
    din.planned(
        "G23", "Spiegeln an X- und Y-Achse", "mirroring about the X and Y axes", group="mirror", owns=False
    ),
    din.planned(
        "G25",
        "Geradenübergänge bei der Werkzeugradiuskorrektur",
        "linear transitions of the tool radius compensation",
        owns=False,
    ),
    din.planned(
        "G26",
        "Kreisübergänge bei der Werkzeugradiuskorrektur",
        "circular transitions of the tool radius compensation",
        owns=False,
    ),
    din.planned("G33", "Gewindeschneiden", "thread cutting"),
    din.planned("G51", "Durchmesserprogrammierung", "diameter programming", owns=False),
    din.planned("G52", "Durchmesserprogrammierung aus", "diameter programming off", owns=False),
    din.planned("G61", "Polynomüberschleifen", "polynomial contouring", owns=False),
    din.planned("G260", "Polynomüberschleifen aus", "polynomial contouring off", owns=False),
    din.planned("G261", "Polynomüberschleifen ein", "polynomial contouring on", owns=False),
    *(
        din.planned(
            f"G{n}",
            "An-/Abwahlverfahren der Werkzeugradiuskorrektur",
            "selection method of the tool radius compensation",
            owns=False,
        )
        for n in (138, 139, 237, 238, 239)
    ),
    din.planned("G63", "Gewindebohren", "tapping", owns=False),
    din.planned("G74", "Referenzpunktfahrt", "homing"),
    *(
        din.planned(f"G{n}", "Impliziter Unterprogrammaufruf", "implicit subprogram call")
        for n in range(80, 90)
    ),
    din.planned("G92", "Bezugspunktverschiebung", "coordinate preset"),
    din.planned(
        "G93",
        "Bearbeitungszeit statt Vorschub (F)",
        "machining time instead of feed (F)",
        group="feed_mode",
        owns=False,
    ),
    din.planned(
        "G96", "Konstante Schnittgeschwindigkeit", "constant cutting speed", group="spindle_mode", owns=False
    ),
    din.planned("G98", "Negativen Software-Endschalter setzen", "setting the negative software limit switch"),
    din.planned("G99", "Positiven Software-Endschalter setzen", "setting the positive software limit switch"),
    din.planned("G100", "Messen", "measuring"),
]

TABLE = CodeTable(
    codes={
        c.name: c
        for c in [
            *din.motion_codes(TRANSITIONS),
            *din.CODES,
            Code(
                "G4",
                None,
                "Verweilzeit (X in Sekunden)",
                "dwell (X in seconds)",
                words=frozenset({"X"}),
                required=(("X",),),
                owns_block=True,
                example="N10 G04 X4.13",
                rule_de="allein im Satz; oder #TIME 4.13",
                rule_en="alone in its block; or #TIME 4.13",
            ),
            Code(
                "G8",
                None,
                "Beschleunigung am Satzanfang" + _NO_PATH_DE,
                "acceleration at block start" + _NO_PATH_EN,
                example="N10 G08 G01 X50",
            ),
            Code(
                "G9",
                None,
                "Verzögerung am Satzende (Genauhalt)",
                "deceleration at block end (exact stop)",
                example="N10 G09 G01 X50",
            ),
            Code(
                "G10",
                None,
                "Konstanter Vorschub bei Werkzeugradiuskorrektur" + _NO_PATH_DE,
                "constant feed with tool radius compensation" + _NO_PATH_EN,
                example="N10 G10",
            ),
            Code(
                "G11",
                None,
                "Angepasster Vorschub bei Werkzeugradiuskorrektur" + _NO_PATH_DE,
                "adapted feed with tool radius compensation" + _NO_PATH_EN,
                example="N10 G11",
            ),
            Code(
                "G12",
                None,
                "Eckenverzögerung aus" + _NO_PATH_DE,
                "corner deceleration off" + _NO_PATH_EN,
                example="N10 G12",
            ),
            Code(
                "G13",
                None,
                "Eckenverzögerung ein" + _NO_PATH_DE,
                "corner deceleration on" + _NO_PATH_EN,
                example="N10 G13",
            ),
            Code("G20", "mirror", "Spiegeln aus", "mirroring off", example="N10 G20"),
            Code(
                "G53",
                "zero_offset",
                "Nullpunktverschiebungen abwählen",
                "deselect the zero offsets",
                example="N10 G53",
            ),
            *(
                Code(
                    f"G{n}",
                    "zero_offset",
                    f"Nullpunktverschiebung {n - 53} anwählen",
                    f"select zero offset {n - 53}",
                    example=f"N10 G{n}",
                )
                for n in range(54, 60)
            ),
            Code(
                "G60", None, "Genauhalt" + _NO_PATH_DE, "exact stop" + _NO_PATH_EN, example="N10 G60 G01 X50"
            ),
            Code(
                "G359",
                None,
                "Genauhalt modal aus" + _NO_PATH_DE,
                "modal exact stop off" + _NO_PATH_EN,
                example="N10 G359",
            ),
            Code(
                "G360",
                None,
                "Genauhalt modal ein" + _NO_PATH_DE,
                "modal exact stop on" + _NO_PATH_EN,
                example="N10 G360",
            ),
            Code(
                "G163",
                None,
                "Radiusprogrammierung (der Radius R gilt für die Kreise)",
                "radius programming (the radius R applies to the arcs)",
                example="N10 G163 G02 X100 R50",
            ),
            Code(
                "G70",
                "units",
                "Eingaben in Zoll (in mm umgerechnet)",
                "input in inches (converted to mm)",
                example="N10 G70",
            ),
            Code("G71", "units", "Eingaben metrisch", "metric input", example="N10 G71"),
            Code("G94", "feed_mode", "Vorschub in mm/min", "feed in mm/min", example="N10 G94 F200"),
            Code(
                "G95",
                "feed_mode",
                "Vorschub in mm/Umdrehung",
                "feed in mm per revolution",
                example="N10 G95 F0.1",
            ),
            Code(
                "G97", "spindle_mode", "Drehzahl in 1/min", "spindle speed in 1/min", example="N10 G97 S1200"
            ),
            Code(
                "G161",
                "centre_mode",
                "Kreismittelpunkt I, J, K absolut",
                "circle centre I, J, K absolute",
                example="N10 G161 G02 X40 Y0 I20 J0",
            ),
            Code(
                "G162",
                "centre_mode",
                "Kreismittelpunkt I, J, K relativ zum Startpunkt",
                "circle centre I, J, K relative to the start point",
                example="N10 G162",
            ),
            Code(
                "G164",
                "centre_correction",
                "Mittelpunktskorrektur aus",
                "centre point correction off",
                example="N10 G164",
            ),
            Code(
                "G165",
                "centre_correction",
                "Mittelpunktskorrektur ein",
                "centre point correction on",
                example="N10 G165",
                rule_de="der Mittelpunkt wird höchstens um 2 mm bzw. 5 % des Radius verschoben",
                rule_en="the centre moves at most 2 mm or 5 % of the radius",
            ),
            Code(
                "G301",
                None,
                "Fase zwischen zwei Verfahrsätzen einfügen (Breite I)",
                "insert a chamfer between two motion blocks (width I)",
                words=frozenset({"I", "#FRC"}),
                owns_block=True,
                example="N30 G301 I20",
                rule_de="I wird gespeichert und gilt für die nächsten G301/G302",
                rule_en="I is kept for the next G301/G302",
            ),
            Code(
                "G302",
                None,
                "Radius zwischen zwei Verfahrsätzen einfügen (Radius I)",
                "insert a rounding between two motion blocks (radius I)",
                words=frozenset({"I", "#FRC"}),
                owns_block=True,
                example="N30 G302 I5",
                rule_de="I wird gespeichert und gilt für die nächsten G301/G302",
                rule_en="I is kept for the next G301/G302",
            ),
            *_PLANNED,
        ]
    },
    addresses={
        a.name: a
        for a in [
            *(a for a in din.ADDRESSES if a.name not in ("I", "R")),
            Address(
                "I",
                "Kreismittelpunkt X (G162 relativ, G161 absolut); bei G301/G302 Fasenbreite bzw. Radius",
                "centre X (G162 relative, G161 absolute); with G301/G302 chamfer width or radius",
                unit="mm",
            ),
            Address(
                "R",
                "Radius (R+ bis 180°, R- über 180°); selbsthaltend für die nächsten Kreise",
                "radius (R+ up to 180°, R- over 180°); kept for the next arcs",
                unit="mm",
                rule_de="R=50 allein: noch keine Bewegung, der nächste Kreis nimmt R50",
                rule_en="R=50 alone: no motion yet, the next arc takes R50",
            ),
            Address(
                "G301",
                "Fase mit Breite (G301=…, nicht haltend)",
                "chamfer of this width (G301=…, not kept)",
                unit="mm",
            ),
            Address(
                "G302",
                "Radius (G302=…, nicht haltend)",
                "rounding of this radius (G302=…, not kept)",
                unit="mm",
            ),
            Address("#CHR", "Fasenbreite", "chamfer width", unit="mm"),
            Address("#CHF", "Fasenlänge", "chamfer length", unit="mm"),
            Address("#RND", "Radius", "rounding radius", unit="mm"),
            Address("#FRC", "Vorschub im eingefügten Element", "feed in the inserted element", unit="mm/min"),
            Address("#TIME", "Verweilzeit", "dwell time", unit="s"),
        ]
    },
    groups=GROUPS,
    always_allowed=frozenset({"F", "S", "M", "D", "#TIME"}),
    din=True,
    centre_correction=True,
    modal_radius=True,
    unsupported_prefixes=("#", "V.", "$"),
)
