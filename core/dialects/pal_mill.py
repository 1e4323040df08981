"""PAL milling (PAL-Codierung Fräsen, 3-axis, plane G17): the code table.

Source: ../shared/spec/pal-milling.md and the rulings of ../shared/spec/DECISIONS.md. Codes
marked PLANNED parse and are checked for their words, and executing them yields a "not
supported yet" diagnostic until their issue lands.
"""

from __future__ import annotations

from dataclasses import replace

from core.dialects.codes import Address, Code, CodeTable, Group, Support

P = Support.PLANNED

LINEAR = frozenset({"X", "Y", "Z", "XI", "YI", "ZI", "XA", "YA", "ZA"})
Z_ONLY = frozenset({"Z", "ZI", "ZA"})
CENTRE = frozenset({"I", "J", "K", "IA", "JA", "KA"})
POLE = frozenset({"I", "J", "IA", "JA"})
TOOL_WORDS = frozenset({"T", "TC", "TR", "TL"})

GROUPS = (
    Group("motion", "Wegbedingung", "motion", ("G0", "G1", "G2", "G3", "G10", "G11", "G12", "G13"), "G1"),
    Group("plane", "Ebene", "plane", ("G17",), "G17"),
    Group(
        "compensation", "Fräserradiuskorrektur", "cutter radius compensation", ("G40", "G41", "G42"), "G40"
    ),
    Group("dimensions", "Maßangabe", "dimensions", ("G90", "G91"), "G90"),
    Group("zero_offset", "Nullpunkt", "zero offset", ("G53", "G54", "G55", "G56", "G57"), "G54"),
    Group("units", "Maßeinheit", "units", ("G70", "G71"), "G71"),
    Group("feed_mode", "Vorschubart", "feed mode", ("G94", "G95"), "G94"),
    Group("spindle_mode", "Drehzahlart", "spindle mode", ("G96", "G97"), "G97"),
    Group("spindle", "Spindel", "spindle", ("M3", "M4", "M5"), "M5"),
    Group("coolant", "Kühlmittel", "coolant", ("M8", "M9"), "M9"),
    Group("workpiece_change", "M60", "M60", ("M60",), "M60"),
    Group("program_end", "Programmende", "end of program", ("M17", "M30"), None),
)


def _motion(name: str, de: str, en: str, words: frozenset[str], **kw: object) -> Code:
    return Code(name, "motion", de, en, words=words, owns_block=True, **kw)  # type: ignore[arg-type]


_CODES = [
    _motion("G0", "Gerade im Eilgang", "straight line at rapid traverse", LINEAR | TOOL_WORDS | {"E"}),
    _motion(
        "G1",
        "Geradeninterpolation mit Vorschub",
        "linear interpolation at feed",
        LINEAR | TOOL_WORDS | {"D", "AS", "RN", "H", "E"},
    ),
    _motion(
        "G2",
        "Kreisinterpolation im Uhrzeigersinn",
        "circular interpolation clockwise",
        LINEAR | CENTRE | {"R", "AO", "RN", "O", "H", "E"},
    ),
    _motion(
        "G3",
        "Kreisinterpolation gegen den Uhrzeigersinn",
        "circular interpolation counter-clockwise",
        LINEAR | CENTRE | {"R", "AO", "RN", "O", "H", "E"},
    ),
    Code(
        "G4", None, "Verweilzeit", "dwell", words=frozenset({"U", "O"}), required=(("U",),), owns_block=True
    ),
    Code("G9", None, "Genauhalt für diesen Satz", "exact stop for this block"),
    _motion(
        "G10",
        "Gerade im Eilgang in Polarkoordinaten",
        "rapid straight line in polar coordinates",
        POLE | Z_ONLY | TOOL_WORDS | {"RP", "AP", "AI", "E"},
        required=(("RP",), ("AP", "AI")),
    ),
    _motion(
        "G11",
        "Gerade mit Vorschub in Polarkoordinaten",
        "feed straight line in polar coordinates",
        POLE | Z_ONLY | TOOL_WORDS | {"RP", "AP", "AI", "RN", "E"},
        required=(("RP",), ("AP", "AI")),
    ),
    _motion(
        "G12",
        "Kreisbogen im Uhrzeigersinn in Polarkoordinaten",
        "clockwise arc in polar coordinates",
        POLE | Z_ONLY | {"AP", "AI", "RN", "E"},
        required=(("AP", "AI"),),
    ),
    _motion(
        "G13",
        "Kreisbogen gegen den Uhrzeigersinn in Polarkoordinaten",
        "counter-clockwise arc in polar coordinates",
        POLE | Z_ONLY | {"AP", "AI", "RN", "E"},
        required=(("AP", "AI"),),
    ),
    Code("G17", "plane", "Arbeitsebene X-Y", "working plane X-Y"),
    Code(
        "G22",
        None,
        "Unterprogrammaufruf",
        "subprogram call",
        words=frozenset({"L", "H"}),
        required=(("L",),),
        owns_block=True,
    ),
    Code(
        "G23",
        None,
        "Programmabschnittswiederholung",
        "repeat a program section",
        words=frozenset({"N", "H"}),
        required=(("N",),),
        owns_block=True,
    ),
    Code(
        "G29",
        None,
        "Programmsprung",
        "program jump",
        words=frozenset({"N", "P", "O"}),
        required=(("N",),),
        owns_block=True,
    ),
    Code("G40", "compensation", "Fräserradiuskorrektur aus", "cutter radius compensation off"),
    Code("G41", "compensation", "Fräserradiuskorrektur links der Kontur", "cutter radius compensation left"),
    Code(
        "G42", "compensation", "Fräserradiuskorrektur rechts der Kontur", "cutter radius compensation right"
    ),
    Code(
        "G45",
        None,
        "Lineares tangentiales Anfahren",
        "linear tangential approach",
        words=LINEAR | {"D", "W", "E"},
        required=(("D",), ("X", "XI", "XA"), ("Y", "YI", "YA")),
        owns_block=True,
    ),
    Code(
        "G46",
        None,
        "Lineares tangentiales Abfahren",
        "linear tangential departure",
        words=Z_ONLY | {"D", "W"},
        required=(("D",),),
        owns_block=True,
    ),
    Code(
        "G47",
        None,
        "Tangentiales Anfahren im Viertelkreis",
        "tangential approach on a quarter circle",
        words=LINEAR | {"R", "W", "E"},
        required=(("R",), ("X", "XI", "XA"), ("Y", "YI", "YA")),
        owns_block=True,
    ),
    Code(
        "G48",
        None,
        "Tangentiales Abfahren im Viertelkreis",
        "tangential departure on a quarter circle",
        words=Z_ONLY | {"R", "W"},
        required=(("R",),),
        owns_block=True,
    ),
    Code(
        "G50",
        None,
        "Inkrementelle Verschiebungen und Drehungen aufheben",
        "cancel incremental shifts and rotations",
        owns_block=True,
        alone=True,
    ),
    Code(
        "G53",
        "zero_offset",
        "Alle Nullpunktverschiebungen aufheben (Maschinenkoordinaten)",
        "cancel all zero offsets (machine coordinates)",
        owns_block=True,
        alone=True,
    ),
    Code("G54", "zero_offset", "Einstellbare Nullpunktverschiebung 1", "settable zero offset 1"),
    *(
        Code(
            f"G{n}",
            "zero_offset",
            f"Einstellbare Nullpunktverschiebung {n - 53}",
            f"settable zero offset {n - 53}",
        )
        for n in (55, 56, 57)
    ),
    Code(
        "G58",
        None,
        "Verschiebung und Drehung in Polarkoordinaten",
        "polar zero shift and rotation",
        words=frozenset({"RP", "AP", "ZA", "AR"}),
        owns_block=True,
    ),
    Code(
        "G59",
        None,
        "Verschiebung und Drehung kartesisch",
        "Cartesian zero shift and rotation",
        words=frozenset({"XA", "YA", "ZA", "AR"}),
        owns_block=True,
    ),
    Code(
        "G66",
        None,
        "Spiegeln an X und/oder Y; G66 allein hebt auf",
        "mirror about X and/or Y; G66 alone cancels",
        words=frozenset({"X", "Y"}),
        owns_block=True,
    ),
    Code(
        "G67",
        None,
        "Skalieren",
        "scaling",
        owns_block=True,
        support=P,
        feature_de="Skalieren G67",
        feature_en="Scaling G67",
    ),
    Code("G70", "units", "Maßangaben in Zoll", "dimensions in inches"),
    Code("G71", "units", "Maßangaben in Millimetern", "dimensions in millimetres"),
    Code("G90", "dimensions", "Absolutmaß", "absolute dimensions"),
    Code("G91", "dimensions", "Kettenmaß (inkremental)", "incremental dimensions"),
    Code("G94", "feed_mode", "Vorschub in mm/min", "feed in mm/min"),
    Code("G95", "feed_mode", "Vorschub in mm pro Umdrehung", "feed in mm per revolution"),
    Code("G96", "spindle_mode", "Konstante Schnittgeschwindigkeit", "constant cutting speed"),
    Code("G97", "spindle_mode", "Konstante Drehzahl", "constant spindle speed"),
    Code("M3", "spindle", "Spindel ein im Uhrzeigersinn", "spindle on clockwise"),
    Code("M4", "spindle", "Spindel ein gegen den Uhrzeigersinn", "spindle on counter-clockwise"),
    Code("M5", "spindle", "Spindel aus (am Satzende)", "spindle stop (at block end)"),
    Code("M6", None, "Werkzeugwechsel", "tool change"),
    Code("M8", "coolant", "Kühlmittel ein", "coolant on"),
    Code("M9", "coolant", "Kühlmittel aus (am Satzende)", "coolant off (at block end)"),
    Code(
        "M13",
        None,
        "Spindel ein im Uhrzeigersinn und Kühlmittel ein",
        "spindle clockwise and coolant on",
        sets=("M3", "M8"),
    ),
    Code(
        "M14",
        None,
        "Spindel ein gegen den Uhrzeigersinn und Kühlmittel ein",
        "spindle counter-clockwise and coolant on",
        sets=("M4", "M8"),
    ),
    Code(
        "M15",
        None,
        "Spindel aus und Kühlmittel aus (am Satzende)",
        "spindle and coolant off (at block end)",
        sets=("M5", "M9"),
    ),
    Code("M17", "program_end", "Unterprogrammende", "end of subprogram"),
    Code("M30", "program_end", "Programmende", "end of program"),
    Code("M60", "workpiece_change", "Ohne Wirkung (Einschaltzustand)", "no effect (switch-on state)"),
]

# The PAL cycles (not in the seeds, DECISIONS §11): recognised so that a block with one says "not supported
# yet" under the cycle's name, once, and nothing about its parameter words (ZA, V, W, LP, BP, D …).
CYCLES = {
    "G34": ("Eröffnung des Konturtaschenzyklus", "opening of the contour pocket cycle"),
    "G35": ("Schrupptechnologie des Konturtaschenzyklus", "roughing technology of the contour pocket cycle"),
    "G36": (
        "Restmaterialtechnologie des Konturtaschenzyklus",
        "residual material technology of the contour pocket cycle",
    ),
    "G37": (
        "Schlichttechnologie des Konturtaschenzyklus",
        "finishing technology of the contour pocket cycle",
    ),
    "G38": ("Konturbeschreibung des Konturtaschenzyklus", "contour description of the contour pocket cycle"),
    "G39": ("Konturtaschenzyklus", "contour pocket cycle"),
    "G72": ("Rechtecktaschenfräszyklus", "rectangular pocket milling cycle"),
    "G73": ("Kreistaschen- und Zapfenfräszyklus", "circular pocket and spigot milling cycle"),
    "G74": ("Nutenfräszyklus", "slot milling cycle"),
    "G75": ("Kreisbogennut-Fräszyklus", "circular slot milling cycle"),
    "G76": ("Mehrfachzyklusaufruf auf einer Geraden", "multiple cycle call on a straight line"),
    "G77": ("Mehrfachzyklusaufruf auf einem Teilkreis", "multiple cycle call on a pitch circle"),
    "G78": ("Zyklusaufruf an einem Punkt (Polarkoordinaten)", "cycle call at a point (polar coordinates)"),
    "G79": (
        "Zyklusaufruf an einem Punkt (kartesische Koordinaten)",
        "cycle call at a point (Cartesian coordinates)",
    ),
    "G80": ("Abschluss einer Konturbeschreibung", "end of a contour description"),
    "G81": ("Bohrzyklus", "drilling cycle"),
    "G82": ("Tiefbohrzyklus mit Spanbruch", "deep-hole drilling cycle with chip breaking"),
    "G83": (
        "Tiefbohrzyklus mit Spanbruch und Entspänen",
        "deep-hole drilling cycle with chip breaking and removal",
    ),
    "G84": ("Gewindebohrzyklus", "tapping cycle"),
    "G85": ("Reibzyklus", "reaming cycle"),
    "G86": ("Ausdrehzyklus", "boring cycle"),
    "G87": ("Bohrfräszyklus", "helical drill milling cycle"),
    "G88": ("Innengewindefräszyklus", "internal thread milling cycle"),
    "G89": ("Außengewindefräszyklus", "external thread milling cycle"),
}
# The cycles the product runs (../shared/spec/pal-cycles.md, reconstructed: core/interpreter/pal_cycles.py): the
# definitions G72–G75, G81–G87 and the calls G76–G79, with their words; the others say "not supported yet".
DEPTH = ("ZA", "ZI")
_CYCLE_WORDS: dict[str, tuple[frozenset[str], tuple[tuple[str, ...], ...]]] = {
    "G72": (
        frozenset({"ZA", "ZI", "LP", "BP", "D", "V", "W", "RN", "AK", "AL", "EP", "DB", "E", "H", "O", "Q"}),
        (DEPTH, ("LP",), ("BP",), ("D",), ("V",)),
    ),
    "G73": (
        frozenset({"ZA", "ZI", "R", "D", "V", "W", "AK", "AL", "DB", "E", "H", "O", "Q", "RZ"}),
        (DEPTH, ("R",), ("D",), ("V",)),
    ),
    "G74": (
        frozenset({"ZA", "ZI", "LP", "BP", "D", "V", "W", "AK", "AL", "EP", "DB", "E", "H", "O", "Q"}),
        (DEPTH, ("LP",), ("BP",), ("D",), ("V",)),
    ),
    "G75": (
        frozenset(
            {
                "ZA",
                "ZI",
                "BP",
                "RP",
                "AN",
                "AO",
                "AP",
                "D",
                "V",
                "W",
                "AK",
                "AL",
                "EP",
                "DB",
                "E",
                "H",
                "O",
                "Q",
            }
        ),
        (DEPTH, ("BP",), ("RP",), ("AN",), ("AO", "AP"), ("D",), ("V",)),
    ),
    "G76": (
        frozenset({"X", "XI", "XA", "Y", "YI", "YA", "Z", "ZI", "ZA", "AS", "D", "O", "AR"}),
        (("D",), ("O",)),
    ),
    "G77": (
        frozenset({"IA", "JA", "I", "J", "R", "AN", "AI", "AP", "O", "Z", "ZI", "ZA", "AR"}),
        (("R",), ("O",)),
    ),
    "G78": (frozenset({"IA", "JA", "I", "J", "RP", "AP", "Z", "ZI", "ZA", "AR"}), (("RP",), ("AP",))),
    "G79": (frozenset({"X", "XI", "XA", "Y", "YI", "YA", "Z", "ZI", "ZA", "AR"}), ()),
    "G81": (frozenset({"ZA", "ZI", "V", "W"}), (DEPTH, ("V",))),
    "G82": (frozenset({"ZA", "ZI", "D", "V", "W", "DA", "DR", "DM", "VB", "U"}), (DEPTH, ("D",), ("V",))),
    "G83": (frozenset({"ZA", "ZI", "D", "V", "W", "DA", "DR", "DM", "VB", "U"}), (DEPTH, ("D",), ("V",))),
    "G84": (frozenset({"ZA", "ZI", "V", "W"}), (DEPTH, ("V",))),
    "G85": (frozenset({"ZA", "ZI", "V", "W", "E"}), (DEPTH, ("V",))),
    "G86": (frozenset({"ZA", "ZI", "V", "W", "DR"}), (DEPTH, ("V",))),
    "G87": (frozenset({"ZA", "ZI", "R", "D", "V", "W"}), (DEPTH, ("R",), ("D",), ("V",))),
}
_CODES += [
    Code(name, None, de, en, words=_CYCLE_WORDS[name][0], required=_CYCLE_WORDS[name][1], owns_block=True)
    if name in _CYCLE_WORDS
    else Code(
        name,
        None,
        de,
        en,
        owns_block=True,
        support=P,
        feature_de=f"{de} {name}",
        feature_en=f"{en[0].upper()}{en[1:]} {name}",
    )
    for name, (de, en) in CYCLES.items()
]

_ADDRESSES = [
    Address("N", "Satznummer", "block number", integer=True),
    Address("G", "Wegbedingung (G-Befehl)", "preparatory function (G code)", integer=True),
    Address("M", "Zusatzfunktion (M-Befehl)", "miscellaneous function (M code)", integer=True),
    Address("F", "Vorschub", "feed"),
    Address("S", "Spindeldrehzahl", "spindle speed"),
    Address("T", "Werkzeugspeicherplatz", "tool place in the magazine", integer=True),
    Address("TC", "Korrekturschalter (Korrekturspeicher 1 bis 9)", "offset memory 1 to 9", integer=True),
    Address("TR", "Zusätzliche Radiuskorrektur (inkremental)", "additional radius correction"),
    Address("TL", "Zusätzliche Längenkorrektur (inkremental)", "additional length correction"),
    Address("X", "X-Koordinate des Zielpunkts", "X coordinate of the target", flag=True),
    Address("Y", "Y-Koordinate des Zielpunkts", "Y coordinate of the target", flag=True),
    Address("Z", "Z-Koordinate des Zielpunkts", "Z coordinate of the target"),
    Address("XI", "X-Weg inkremental (nur dieser Satz)", "X distance, incremental (this block only)"),
    Address("YI", "Y-Weg inkremental (nur dieser Satz)", "Y distance, incremental (this block only)"),
    Address("ZI", "Z-Weg inkremental (nur dieser Satz)", "Z distance, incremental (this block only)"),
    Address("XA", "X-Koordinate absolut (nur dieser Satz)", "X coordinate, absolute (this block only)"),
    Address("YA", "Y-Koordinate absolut (nur dieser Satz)", "Y coordinate, absolute (this block only)"),
    Address("ZA", "Z-Koordinate absolut (nur dieser Satz)", "Z coordinate, absolute (this block only)"),
    Address("I", "Mittelpunkt X, inkremental vom Startpunkt", "centre X, incremental from the start point"),
    Address("J", "Mittelpunkt Y, inkremental vom Startpunkt", "centre Y, incremental from the start point"),
    Address("K", "Mittelpunkt Z, inkremental (nicht in G17)", "centre Z, incremental (not in G17)"),
    Address("IA", "Mittelpunkt X, absolut", "centre X, absolute"),
    Address("JA", "Mittelpunkt Y, absolut", "centre Y, absolute"),
    Address("KA", "Mittelpunkt Z, absolut (nicht in G17)", "centre Z, absolute (not in G17)"),
    Address("R", "Radius (R+ kürzerer, R- längerer Bogen)", "radius (R+ shorter, R- longer arc)"),
    Address("AO", "Öffnungswinkel des Kreisbogens", "opening angle of the arc"),
    Address("AS", "Anstiegswinkel der Geraden", "rise angle of the line"),
    Address(
        "D",
        "Länge der Geraden bzw. der An-/Abfahrbewegung; in Zyklen: Zustelltiefe je Ebene bzw. Schritt "
        "(G87: Steigung, G76: Punktabstand)",
        "length of the line or of the approach; in cycles: infeed per level or step (G87: pitch, G76: spacing)",
    ),
    Address(
        "H",
        "Lösungsauswahl bzw. Anzahl der Durchläufe; in Taschenzyklen: H1 Schruppen, H4 Schlichten, "
        "H14 beides",
        "solution choice or number of runs; in pocket cycles: H1 roughing, H4 finishing, H14 both",
        integer=True,
    ),
    Address(
        "O",
        "Auswahl (Bogenlänge, Vergleich, Einheit); G76/G77: Anzahl der Punkte; Taschen: O1 senkrecht, "
        "O2 schraubenförmig eintauchen",
        "selection (arc length, comparison, unit); G76/G77: number of points; pockets: O1 vertical, "
        "O2 helical plunge",
        integer=True,
    ),
    Address("RN", "Übergangselement: RN+ Verrundung, RN- Fase", "transition: RN+ rounding, RN- chamfer"),
    Address(
        "E", "Vorschub für Übergangselemente bzw. Eintauchvorschub", "feed on transitions or plunge feed"
    ),
    Address("U", "Verweilzeit (Sekunden oder Umdrehungen)", "dwell (seconds or revolutions)"),
    Address("L", "Unterprogrammnummer", "subprogram number", integer=True),
    Address("P", "Parameter P1 bis P999", "parameter P1 to P999", integer=True),
    Address("RP", "Polarradius", "polar radius"),
    Address("AP", "Polarwinkel (absolut)", "polar angle (absolute)"),
    Address("AI", "Polarwinkel inkremental", "polar angle increment"),
    Address("AR", "Drehwinkel des Koordinatensystems", "rotation angle of the coordinate system"),
    Address("W", "Rückzugsebene in der Zustellachse (absolut)", "infeed-axis clearance plane (absolute)"),
    # the words of the cycles (reconstructed, ../shared/spec/pal-cycles.md)
    Address(
        "V", "Zyklen: Sicherheitsabstand über der Oberfläche", "cycles: safety distance above the surface"
    ),
    Address(
        "LP", "Zyklen: Länge der Tasche bzw. Nut (in X)", "cycles: length of the pocket or slot (along X)"
    ),
    Address(
        "BP", "Zyklen: Breite der Tasche bzw. Nut (in Y)", "cycles: width of the pocket or slot (along Y)"
    ),
    Address("AK", "Zyklen: Aufmaß auf den Wänden", "cycles: allowance on the walls"),
    Address("AL", "Zyklen: Aufmaß auf dem Boden", "cycles: allowance on the bottom"),
    Address(
        "EP",
        "Zyklen: Bezugspunkt (EP0 Mitte, EP1 Ecke bzw. Anfangsbogen)",
        "cycles: reference point (EP0 centre, EP1 corner or start arc)",
        integer=True,
    ),
    Address(
        "DB",
        "Zyklen: Bahnüberdeckung in % des Fräserdurchmessers",
        "cycles: path overlap in % of the tool diameter",
    ),
    Address(
        "Q",
        "Zyklen: Fräsrichtung (Q1 Gleichlauf, Q2 Gegenlauf)",
        "cycles: milling direction (Q1 climb, Q2 conventional)",
        integer=True,
    ),
    Address("DA", "G82/G83: erste Bohrtiefe", "G82/G83: first drilling depth"),
    Address(
        "DR",
        "G82/G83: Verringerung je Bohrschritt; G86: Abhebebetrag",
        "G82/G83: reduction per step; G86: retraction from the wall",
    ),
    Address("DM", "G82/G83: kleinster Bohrschritt", "G82/G83: smallest step"),
    Address("VB", "G82/G83: Rückzugsbetrag nach jedem Bohrschritt", "G82/G83: retraction after each step"),
    Address(
        "AN",
        "G75/G77: Winkel des ersten Punkts bzw. Anfangswinkel",
        "G75/G77: angle of the first point or start angle",
    ),
    Address(
        "RZ",
        "G73: Zapfenradius (Zapfenform noch nicht unterstützt)",
        "G73: boss radius (boss form not supported yet)",
    ),
]

# -- help for the editor and the docs: an example block per code, the rules to remember, the units ----------
TARGET = ("X", "XI", "XA", "Y", "YI", "YA", "Z", "ZI", "ZA")
_POLAR_PLANE = ("AP", "AI")
RECONSTRUCTED_DE = "nach der PAL-Syntax rekonstruiert (nicht aus der Vorlage), siehe docs/pal-milling.md"
RECONSTRUCTED_EN = "reconstructed from the PAL syntax (not from the source), see docs/pal-milling.md"
LEFT_DE, LEFT_EN = (
    "Werkzeug links der Kontur, in Vorschubrichtung gesehen",
    "tool left of the contour, seen in the feed direction",
)
RIGHT_DE, RIGHT_EN = (
    "Werkzeug rechts der Kontur, in Vorschubrichtung gesehen",
    "tool right of the contour, seen in the feed direction",
)
ARC_DE = "Endpunkt (oder Öffnungswinkel AO) und Mittelpunkt I/J (IA/JA) oder Radius R"
ARC_EN = "end point (or opening angle AO) and centre I/J (IA/JA) or radius R"
ARC = ((*TARGET[:6], "AO"), ("I", "J", "IA", "JA", "R"))
_HELP: dict[str, dict[str, object]] = {
    "G0": {
        "example": "N30 G0 X-25 Y-15 Z2",
        "mandatory": (TARGET,),
        "rule_de": "mindestens eine Koordinate; Eilgang, nie ins Material",
        "rule_en": "at least one coordinate; rapid, never into the material",
    },
    "G1": {
        "example": "N60 G1 X70 Y10 RN20",
        "mandatory": ((*TARGET, "D", "AS"),),
        "rule_de": "höchstens zwei von X, Y, D, AS (dazu Z)",
        "rule_en": "at most two of X, Y, D, AS (plus Z)",
    },
    "G2": {"example": "N40 G2 X56.4 Y10 I-20 J6.4", "mandatory": ARC, "rule_de": ARC_DE, "rule_en": ARC_EN},
    "G3": {"example": "N50 G3 X30 Y40 R15", "mandatory": ARC, "rule_de": ARC_DE, "rule_en": ARC_EN},
    "G4": {"example": "N70 G4 U2", "rule_de": "U in Sekunden", "rule_en": "U in seconds"},
    "G9": {"example": "N80 G9 G1 X50"},
    "G10": {
        "example": "N20 G10 IA40 JA35 RP30 AP45",
        "rule_de": "Pol I/J (IA/JA), ohne Pol: aktuelle Position",
        "rule_en": "pole I/J (IA/JA), without one: the current position",
    },
    "G11": {"example": "N30 G11 IA40 JA35 RP30 AP90"},
    "G12": {"example": "N40 G12 IA40 JA35 AP180", "mandatory": (_POLAR_PLANE,)},
    "G13": {"example": "N40 G13 IA40 JA35 AP0", "mandatory": (_POLAR_PLANE,)},
    "G17": {"example": "N10 G17"},
    "G22": {
        "example": "N50 G22 L100 H2",
        "rule_de": "H: Anzahl der Durchläufe",
        "rule_en": "H: number of runs",
    },
    "G23": {
        "example": "N110 G23 N40 N100 H2",
        "rule_de": "erstes N: Anfang, zweites N: Ende des Abschnitts",
        "rule_en": "first N: start, second N: end of the section",
    },
    "G29": {"example": "N60 G29 P12 O3 P2 N200"},
    "G40": {"example": "N80 G40"},
    "G41": {"example": "N40 G41 G0 X70 Y84", "rule_de": LEFT_DE, "rule_en": LEFT_EN},
    "G42": {"example": "N40 G42 G0 X-14 Y10", "rule_de": RIGHT_DE, "rule_en": RIGHT_EN},
    "G45": {
        "example": "N40 G41 G45 D10 X10 Y20",
        "rule_de": "nur im selben Satz wie G41 oder G42",
        "rule_en": "only in the same block as G41 or G42",
    },
    "G46": {
        "example": "N90 G40 G46 D10",
        "rule_de": "nur im selben Satz wie G40",
        "rule_en": "only in the same block as G40",
    },
    "G47": {
        "example": "N40 G41 G47 R10 X10 Y20",
        "rule_de": "nur im selben Satz wie G41 oder G42",
        "rule_en": "only in the same block as G41 or G42",
    },
    "G48": {
        "example": "N90 G40 G48 R10",
        "rule_de": "nur im selben Satz wie G40",
        "rule_en": "only in the same block as G40",
    },
    "G50": {"example": "N100 G50", "rule_de": "allein im Satz", "rule_en": "alone in its block"},
    "G53": {"example": "N10 G53", "rule_de": "allein im Satz", "rule_en": "alone in its block"},
    **{f"G{n}": {"example": f"N10 G{n}"} for n in (54, 55, 56, 57)},
    "G58": {
        "example": "N20 G58 RP20 AP30 AR45",
        "rule_de": "addiert sich zu früheren G58/G59; G50 hebt auf",
        "rule_en": "adds to earlier G58/G59; G50 cancels",
    },
    "G59": {
        "example": "N20 G59 XA50 YA40 AR30",
        "rule_de": "addiert sich zu früheren G58/G59; G50 hebt auf",
        "rule_en": "adds to earlier G58/G59; G50 cancels",
    },
    "G66": {
        "example": "N30 G66 X",
        "rule_de": "X: an der X-Achse, Y: an der Y-Achse spiegeln; G66 allein hebt auf",
        "rule_en": "X: about the X axis, Y: about the Y axis; G66 alone cancels",
    },
    "G70": {"example": "N10 G70"},
    "G71": {"example": "N10 G71"},
    "G90": {
        "example": "N10 G90",
        "rule_de": "jede Koordinate vom Werkstücknullpunkt aus",
        "rule_en": "every coordinate from the workpiece zero",
    },
    "G91": {
        "example": "N10 G91",
        "rule_de": "jede Koordinate als Weg vom letzten Punkt",
        "rule_en": "every coordinate as the distance from the last point",
    },
    "G94": {"example": "N10 G94 F200"},
    "G95": {"example": "N10 G95 F0.1"},
    "G96": {"example": "N10 G96 S150", "rule_de": "S in m/min", "rule_en": "S in m/min"},
    "G97": {"example": "N10 G97 S1200", "rule_de": "S in 1/min", "rule_en": "S in 1/min"},
    "M3": {"example": "N20 S1200 F150 M3"},
    "M4": {"example": "N20 S800 F100 M4"},
    "M5": {"example": "N190 M5"},
    "M6": {"example": "N10 T1 TC1 M6"},
    "M8": {"example": "N20 M8"},
    "M9": {"example": "N190 M9"},
    "M13": {"example": "N20 S1200 F150 M13"},
    "M14": {"example": "N20 S800 F100 M14"},
    "M15": {"example": "N190 M15"},
    "M17": {
        "example": "N150 M17",
        "rule_de": "letzter Satz eines Unterprogramms",
        "rule_en": "last block of a subprogram",
    },
    "M30": {"example": "N200 G0 X250 Y150 Z250 M30"},
    "M60": {"example": "N10 M60"},
    **{
        name: {
            "example": example,
            "rule_de": f"{rule_de}; {RECONSTRUCTED_DE}",
            "rule_en": f"{rule_en}; {RECONSTRUCTED_EN}",
        }
        for name, (example, rule_de, rule_en) in {
            "G72": (
                "N50 G72 ZI-5 LP40 BP30 RN5 D2.5 V2 W5",
                "definiert die Rechtecktasche, fährt nicht; Aufruf mit G79",
                "defines the rectangular pocket, moves nothing; call with G79",
            ),
            "G73": (
                "N50 G73 ZI-6 R15 D3 V2",
                "definiert die Kreistasche, fährt nicht; Aufruf mit G79",
                "defines the circular pocket, moves nothing; call with G79",
            ),
            "G74": (
                "N50 G74 ZI-4 LP50 BP10 D2 V2",
                "definiert die Nut (LP einschließlich der Rundungen)",
                "defines the slot (LP including the round ends)",
            ),
            "G75": (
                "N50 G75 ZI-3 BP8 RP30 AN0 AO90 D1.5 V2",
                "definiert die Kreisbogennut um den Aufrufpunkt",
                "defines the arc slot about the call point",
            ),
            "G76": (
                "N60 G76 X10 Y10 Z0 AS0 D20 O4",
                "O Aufrufpunkte auf einer Geraden im Abstand D",
                "O call points on a line, D apart",
            ),
            "G77": (
                "N60 G77 IA50 JA40 R25 AN0 AI90 O4 Z0",
                "O Aufrufpunkte auf dem Teilkreis R um IA/JA",
                "O call points on the pitch circle R about IA/JA",
            ),
            "G78": (
                "N60 G78 IA50 JA40 RP25 AP45 Z0",
                "ein Aufrufpunkt in Polarkoordinaten",
                "one call point in polar coordinates",
            ),
            "G79": (
                "N60 G79 X50 Y40 Z0",
                "ein Aufrufpunkt; Z: Werkstückoberfläche (ohne Z: 0)",
                "one call point; Z: the surface (without Z: 0)",
            ),
            "G81": (
                "N50 G81 ZI-12 V2",
                "Bohren: Vorschub bis zum Grund, Eilgang zurück",
                "drilling: feed to the bottom, rapid out",
            ),
            "G82": (
                "N50 G82 ZI-30 D8 V2 DA10 DR1 DM4",
                "Tiefbohren mit Spanbruch: nach jedem Schritt VB zurück",
                "deep drilling with chip breaking: back VB after each step",
            ),
            "G83": (
                "N50 G83 ZI-30 D8 V2",
                "Tiefbohren mit Entspänen: nach jedem Schritt heraus auf V",
                "deep drilling with swarf removal: out to V after each step",
            ),
            "G84": (
                "N50 G84 ZI-15 F1.5 M3 V3",
                "Gewindebohren: F Steigung in mm, M3 Rechts-, M4 Linksgewinde",
                "tapping: F pitch in mm, M3 right-hand, M4 left-hand",
            ),
            "G85": (
                "N50 G85 ZI-15 V2 E50",
                "Reiben: hinein mit F, heraus mit E",
                "reaming: in at F, out at E",
            ),
            "G86": (
                "N50 G86 ZI-20 V2 DR0.2",
                "Ausdrehen: Spindel steht beim Herausfahren",
                "boring: the spindle stands on the way out",
            ),
            "G87": (
                "N50 G87 ZI-10 R12 D2 V2",
                "Bohrfräsen auf einer Schraubenlinie der Steigung D",
                "bore milling on a helix of pitch D",
            ),
        }.items()
    },
}
_MM = (
    "X",
    "Y",
    "Z",
    "XI",
    "YI",
    "ZI",
    "XA",
    "YA",
    "ZA",
    "I",
    "J",
    "K",
    "IA",
    "JA",
    "KA",
    "R",
    "D",
    "RN",
    "TR",
    "TL",
    "RP",
    "W",
    "V",
    "LP",
    "BP",
    "AK",
    "AL",
    "DA",
    "DR",
    "DM",
    "VB",
    "RZ",
)
_UNITS = {
    **dict.fromkeys(_MM, "mm"),
    **dict.fromkeys(("AO", "AS", "AP", "AI", "AR", "AN"), "°"),
    "F": "mm/min",
    "E": "mm/min",
    "S": "1/min",
    "U": "s",
    "DB": "%",
}
_CERTAINTY = {"H": ("sicher", "certain"), "M": ("wahrscheinlich", "likely"), "L": ("unsicher", "uncertain")}
_RULES = {
    "RN": ("+ Rundung, − Fase", "+ rounding, − chamfer"),
    "R": ("+ kürzerer Bogen (bis 180°), − längerer Bogen", "+ shorter arc (up to 180°), − longer arc"),
    "F": ("mm/min unter G94, mm pro Umdrehung unter G95", "mm/min under G94, mm per revolution under G95"),
    # the words only the cycles take: reconstructed, their defaults in core.interpreter.pal_cycles.RECONSTRUCTED,
    # with the certainty of their meaning (../shared/spec/pal-cycles.md: H high, M medium, L low)
    **{
        word: (
            f"Zyklenwort, Bedeutung {_CERTAINTY[c][0]} ({c}); {RECONSTRUCTED_DE}",
            f"cycle word, meaning {_CERTAINTY[c][1]} ({c}); {RECONSTRUCTED_EN}",
        )
        for word, c in {
            "V": "H",
            "LP": "H",
            "BP": "H",
            "AK": "H",
            "AL": "H",
            "EP": "L",
            "DB": "L",
            "Q": "L",
            "DA": "M",
            "DR": "L",
            "DM": "L",
            "VB": "M",
            "AN": "L",
            "RZ": "M",
        }.items()
    },
}
_HELP["G84"]["mandatory"] = (("ZA", "ZI"), ("F",), ("V",))  # and M3 or M4 (a code, not a word)
_CODES = [replace(c, **_HELP.get(c.name, {})) for c in _CODES]  # type: ignore[arg-type]
_ADDRESSES = [
    replace(
        a,
        unit=_UNITS.get(a.name, ""),
        rule_de=_RULES.get(a.name, ("", ""))[0],
        rule_en=_RULES.get(a.name, ("", ""))[1],
        non_negative=a.name in ("F", "S", "U", "H", "E", "RP"),
    )
    for a in _ADDRESSES
]

TABLE = CodeTable(
    codes={c.name: c for c in _CODES},
    addresses={a.name: a for a in _ADDRESSES},
    groups=GROUPS,
    always_allowed=frozenset({"F", "S", "M"}),
    tool_words=TOOL_WORDS,
    max_g_words=2,
    strict_technology=True,
)
