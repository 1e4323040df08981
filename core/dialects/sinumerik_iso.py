"""SINUMERIK 808D in ISO mode (milling): the code table.

Sources: ../shared/spec/iso-808d-arcs.md and DECISIONS.md §13 for the arcs; for the rest of an ordinary ISO
milling program the manufacturer's public programming manual of the ISO dialect (SINUMERIK 808D "Programming
and Operating Manual, Part 3: Programming (ISO dialects)", 6FC5398-4DP10-0BA0, and the SINUMERIK ISO Milling
programming manual 6FC5398-7BP10-1BA0 it follows): program numbers O and %, G20/G21, G54–G59, G53, G43/G44/G49
with H, G28, G04, G94/G95, G97, M98/M99, the fixed drilling cycles G73–G89 with G98/G99. docs/dialects.md names
what is modelled, what is "not supported yet" and the rulings where the manual leaves a value to the machine.

Planes G17 (X-Y, centre I J), G18 (Z-X, centre K I), G19 (Y-Z, centre J K); G02/G03 with the end point and R
(R+ at most 180°, R- the longer arc) or the centre offsets, always incremental from the start point. An omitted
end-point axis is the current position, an omitted centre offset 0. The arc leaves the selected plane only when
its centre words (or R) cannot belong to it. The optional fifth linear axes U, V, W are not part of the trainer's
3-axis machine.
"""

from __future__ import annotations

from dataclasses import replace

from core.dialects import din
from core.dialects.codes import Address, Code, CodeTable, Group

# the words of a drilling cycle block: hole position X Y, bottom Z, R plane, Q peck depth or shift, P dwell (ms),
# K (or L) number of repetitions
CYCLE_WORDS = frozenset({"X", "Y", "Z", "R", "Q", "P", "K", "L"})
CYCLES: dict[str, tuple[str, str, str, str]] = {  # code: German, English, example, rule
    "G73": (
        "Tiefbohrzyklus mit Spanbruch (Rückzug um d nach jeder Zustellung Q)",
        "high-speed peck drilling (back-off d after each infeed Q)",
        "N50 G73 X20 Y20 Z-30 R2 Q5 F120",
        "Q: Zustellung je Schritt",
    ),
    "G74": (
        "Linksgewindebohren (Spindel links hinein, rechts heraus)",
        "left-hand tapping (spindle counter-clockwise in, clockwise out)",
        "N50 G74 X20 Y20 Z-15 R5 F150",
        "F = Drehzahl × Steigung",
    ),
    "G76": (
        "Feinbohrzyklus (Spindelhalt orientiert, Freifahren um Q)",
        "fine boring (oriented spindle stop, shift by Q)",
        "N50 G76 X20 Y20 Z-20 R2 Q0.2 P500 F60",
        "Q: Freifahrweg in +X",
    ),
    "G81": (
        "Bohrzyklus (Bohren, Zentrieren)",
        "drilling cycle (drilling, spot drilling)",
        "N50 G81 X20 Y20 Z-15 R2 F120",
        "Z Bohrungsgrund, R Rückzugsebene",
    ),
    "G82": (
        "Bohrzyklus mit Verweilzeit am Bohrungsgrund",
        "drilling cycle with dwell at the bottom",
        "N50 G82 X20 Y20 Z-5 R2 P500 F100",
        "P: Verweilzeit in ms",
    ),
    "G83": (
        "Tiefbohrzyklus mit Entspänen (Rückzug zur R-Ebene nach jeder Zustellung Q)",
        "peck drilling (back to the R plane after each infeed Q)",
        "N50 G83 X20 Y20 Z-40 R2 Q8 F100",
        "Q: Zustellung je Schritt",
    ),
    "G84": (
        "Gewindebohren (Spindel rechts hinein, links heraus)",
        "tapping (spindle clockwise in, counter-clockwise out)",
        "N50 G84 X20 Y20 Z-15 R5 F150",
        "F = Drehzahl × Steigung",
    ),
    "G85": (
        "Reibzyklus (Vorschub hinein und heraus)",
        "boring cycle (feed in and out)",
        "N50 G85 X20 Y20 Z-20 R2 F80",
        "",
    ),
    "G86": (
        "Ausdrehzyklus (Spindelhalt am Grund, Eilgang heraus)",
        "boring cycle (spindle stop at the bottom, rapid out)",
        "N50 G86 X20 Y20 Z-20 R2 F80",
        "",
    ),
    "G87": (
        "Rückwärts-Ausdrehzyklus (R-Ebene unter dem Werkstück)",
        "back boring cycle (R plane below the part)",
        "N50 G98 G87 X20 Y20 Z-10 R-25 Q2 F60",
        "Rückzug immer zur Ausgangsebene",
    ),
    "G88": (
        "Ausdrehzyklus mit Verweilzeit und Handrückzug",
        "boring cycle with dwell and manual retraction",
        "N50 G88 X20 Y20 Z-20 R2 P500 F80",
        "",
    ),
    "G89": (
        "Ausdrehzyklus mit Verweilzeit (Vorschub hinein und heraus)",
        "boring cycle with dwell (feed in and out)",
        "N50 G89 X20 Y20 Z-20 R2 P500 F80",
        "P: Verweilzeit in ms",
    ),
}

GROUPS = (
    *din.GROUPS[:5],
    Group("coolant", "Kühlmittel", "coolant", ("M7", "M8", "M9"), "M9"),
    Group("program_end", "Programmende", "end of program", ("M2", "M30", "M99"), None),
    Group("feed_mode", "Vorschubart", "feed mode", ("G94", "G95"), "G94"),
    Group("units", "Maßeinheit", "units", ("G20", "G21"), "G21"),
    Group(
        "zero_offset",
        "Nullpunktverschiebung",
        "work offset",
        ("G54", "G55", "G56", "G57", "G58", "G59"),
        "G54",
    ),
    Group("length_offset", "Werkzeuglängenkorrektur", "tool length offset", ("G43", "G44", "G49"), "G49"),
    Group("cycle", "Bohrzyklus", "drilling cycle", ("G80", *CYCLES), "G80"),
    Group(
        "cycle_return",
        "Rückzugsebene der Bohrzyklen",
        "return level of the drilling cycles",
        ("G98", "G99"),
        "G98",
    ),
    Group("spindle_mode", "Drehzahlart", "spindle mode", ("G96", "G97"), "G97"),
    Group("path_mode", "Bahnsteuerbetrieb", "path mode", ("G61", "G62", "G63", "G64"), "G64"),
)

_PLANNED = [
    din.planned(
        "G5.1", "Vorausschau für Hochgeschwindigkeitsbearbeitung", "look-ahead for high-speed machining"
    ),
    din.planned("G7.1", "Zylinderinterpolation", "cylindrical interpolation"),
    din.planned("G10", "Daten einstellen per Programm", "programmable data input"),
    din.planned("G11", "Daten einstellen aus", "programmable data input off", owns=False),
    din.planned("G15", "Polarkoordinaten aus", "polar coordinates off", owns=False),
    din.planned("G16", "Polarkoordinaten", "polar coordinates"),
    din.planned("G22", "Arbeitsfeldbegrenzung ein", "stored stroke check on"),
    din.planned("G23", "Arbeitsfeldbegrenzung aus", "stored stroke check off", owns=False),
    din.planned("G27", "Referenzpunktprüfung", "reference point check"),
    din.planned("G29", "Rückkehr vom Referenzpunkt", "return from the reference point"),
    din.planned("G30", "Anfahren des 2./3./4. Referenzpunkts", "return to the 2nd/3rd/4th reference point"),
    din.planned("G31", "Messen mit Restweglöschen", "skip function"),
    din.planned("G33", "Gewindeschneiden", "thread cutting"),
    din.planned("G50", "Skalieren aus", "scaling off", owns=False),
    din.planned("G51", "Skalieren", "scaling"),
    din.planned("G50.1", "Programmierbares Spiegeln aus", "programmable mirror image off"),
    din.planned("G51.1", "Programmierbares Spiegeln", "programmable mirror image"),
    din.planned("G52", "Lokales Koordinatensystem", "local coordinate system"),
    din.planned("G54.1", "Zusätzliche Nullpunktverschiebung", "additional work offset"),
    din.planned("G60", "Einrichtungspositionierung", "single-direction positioning", owns=False),
    din.planned(
        "G62", "Automatische Eckenoverride", "automatic corner override", group="path_mode", owns=False
    ),
    din.planned("G63", "Gewindebohrbetrieb", "tapping mode", group="path_mode", owns=False),
    din.planned("G65", "Makroaufruf", "macro call"),
    din.planned("G66", "Modaler Makroaufruf", "modal macro call"),
    din.planned("G67", "Modaler Makroaufruf aus", "modal macro call off", owns=False),
    din.planned("G68", "Drehen des Koordinatensystems", "coordinate system rotation"),
    din.planned("G69", "Drehen des Koordinatensystems aus", "coordinate system rotation off", owns=False),
    din.planned("G92", "Werkstückkoordinatensystem setzen", "setting the workpiece coordinate system"),
    din.planned(
        "G96", "Konstante Schnittgeschwindigkeit", "constant surface speed", group="spindle_mode", owns=False
    ),
]

_CODES = [
    *din.motion_codes(),
    *din.CODES,
    Code(
        "G4",
        None,
        "Verweilzeit",
        "dwell",
        words=frozenset({"X", "P"}),
        required=(("X", "P"),),
        owns_block=True,
        example="N70 G04 X1.5",
        rule_de="X in Sekunden, P in Millisekunden",
        rule_en="X in seconds, P in milliseconds",
    ),
    Code("G9", None, "Genauhalt für diesen Satz", "exact stop for this block", example="N80 G09 G01 X50"),
    Code(
        "G20",
        "units",
        "Eingaben in Zoll (in mm umgerechnet)",
        "input in inches (converted to mm)",
        example="N10 G20",
        rule_de="am Programmanfang, vor allen Koordinaten",
        rule_en="at the start of the program",
    ),
    Code("G21", "units", "Eingaben in Millimetern", "input in millimetres", example="N10 G21"),
    Code(
        "G28",
        None,
        "Referenzpunkt anfahren über den Zwischenpunkt",
        "return to the reference point via the intermediate point",
        words=din.AXES,
        required=(din.TARGET,),
        example="N900 G91 G28 Z0",
        rule_de="Eilgang zum Zwischenpunkt, dann zum Referenzpunkt; nur die programmierten Achsen",
        rule_en="rapid to the intermediate point, then to the reference point; only the programmed axes",
    ),
    Code(
        "G43",
        "length_offset",
        "Werkzeuglängenkorrektur plus (H)",
        "tool length offset plus (H)",
        example="N40 G43 Z15 H1",
        rule_de="die Bahn bleibt die der Werkzeugspitze",
        rule_en="the path stays that of the tool tip",
    ),
    Code(
        "G44",
        "length_offset",
        "Werkzeuglängenkorrektur minus (H)",
        "tool length offset minus (H)",
        example="N40 G44 Z15 H1",
    ),
    Code("G49", "length_offset", "Werkzeuglängenkorrektur aus", "tool length offset off", example="N10 G49"),
    Code(
        "G53",
        None,
        "Verfahren in Maschinenkoordinaten (nur dieser Satz, Eilgang)",
        "move in machine coordinates (this block only, rapid)",
        words=din.AXES,
        required=(din.TARGET,),
        example="N900 G53 Z0",
        rule_de="Maschinennullpunkt = Referenzpunkt",
        rule_en="machine zero = reference point",
    ),
    *(
        Code(
            f"G{n}",
            "zero_offset",
            f"Einstellbare Nullpunktverschiebung {n - 53}",
            f"work offset {n - 53}",
            example=f"N10 G{n}",
        )
        for n in range(54, 60)
    ),
    Code("G61", "path_mode", "Genauhalt wirkt modal", "exact stop mode", example="N10 G61"),
    Code("G64", "path_mode", "Bahnsteuerbetrieb", "continuous path mode", example="N10 G64"),
    Code(
        "G80",
        "cycle",
        "Bohrzyklus aus",
        "cancel the drilling cycle",
        example="N90 G80",
        rule_de="auch G00–G03 beenden den Zyklus",
        rule_en="G00–G03 end the cycle as well",
    ),
    *(
        Code(name, "cycle", de, en, words=CYCLE_WORDS, owns_block=True, example=example, rule_de=rule)
        for name, (de, en, example, rule) in CYCLES.items()
    ),
    Code("G94", "feed_mode", "Vorschub in mm/min", "feed in mm/min", example="N10 G94 F200"),
    Code("G95", "feed_mode", "Vorschub in mm/Umdrehung", "feed in mm per revolution", example="N10 G95 F0.1"),
    Code("G97", "spindle_mode", "Drehzahl in 1/min", "spindle speed in 1/min", example="N10 G97 S1200"),
    Code(
        "G98",
        "cycle_return",
        "Bohrzyklen: Rückzug zur Ausgangsebene",
        "drilling cycles: return to the initial level",
        example="N50 G98 G81 X20 Y20 Z-15 R2 F120",
    ),
    Code(
        "G99",
        "cycle_return",
        "Bohrzyklen: Rückzug zur R-Ebene",
        "drilling cycles: return to the R plane",
        example="N50 G99 G81 X20 Y20 Z-15 R2 F120",
    ),
    Code("M7", "coolant", "Kühlmittel (Nebel) ein", "coolant (mist) on", example="N20 M07"),
    Code(
        "M19",
        None,
        "Spindel orientieren (ohne Wirkung auf die Bahn)",
        "spindle orientation (no effect on the path)",
        example="N20 M19",
    ),
    Code(
        "M29",
        None,
        "Starres Gewindebohren (ohne Wirkung auf die Bahn)",
        "rigid tapping (no effect on the path)",
        example="N40 M29 S500",
    ),
    Code(
        "M98",
        None,
        "Unterprogrammaufruf",
        "subprogram call",
        words=frozenset({"P", "L"}),
        required=(("P",),),
        example="N60 M98 P1000",
        rule_de="P: Programmnummer (letzte 4 Stellen), davor die Anzahl der Durchläufe; oder L",
        rule_en="P: program number (last 4 digits), the digits before it the number of runs; or L",
    ),
    Code(
        "M99", "program_end", "Unterprogrammende, Rücksprung", "end of subprogram, return", example="N120 M99"
    ),
    *_PLANNED,
]

_CYCLE_MEANING = {
    "K": ("; in Bohrzyklen: Anzahl der Wiederholungen", "; in drilling cycles: number of repetitions"),
    "R": (
        "; in Bohrzyklen: R-Ebene (G91: Abstand von der Ausgangsebene)",
        "; in drilling cycles: the R plane (G91: distance from the initial level)",
    ),
    "Z": (
        "; in Bohrzyklen: Bohrungsgrund (G91: Abstand von der R-Ebene)",
        "; in drilling cycles: the bottom of the hole (G91: distance from the R plane)",
    ),
}
_ADDRESSES = [
    *(
        replace(
            a, help_de=a.help_de + _CYCLE_MEANING[a.name][0], help_en=a.help_en + _CYCLE_MEANING[a.name][1]
        )
        if a.name in _CYCLE_MEANING
        else a
        for a in din.ADDRESSES
    ),
    Address(
        "H",
        "Werkzeuglängenkorrektur (Nummer) für G43/G44",
        "tool length offset (number) for G43/G44",
        integer=True,
    ),
    Address(
        "P",
        "Verweilzeit in ms (G04, Bohrzyklen); Programmnummer bei M98",
        "dwell in ms (G04, drilling cycles); program number with M98",
        unit="ms",
    ),
    Address(
        "Q",
        "Bohrzyklen: Zustellung je Schritt (G73, G83) bzw. Freifahrweg (G76, G87)",
        "drilling cycles: infeed per step (G73, G83) or shift (G76, G87)",
        unit="mm",
    ),
    Address(
        "L", "Anzahl der Durchläufe (M98, Bohrzyklen)", "number of runs (M98, drilling cycles)", integer=True
    ),
    Address(
        "O",
        "Programmnummer (allein im Satz am Programmanfang)",
        "program number (alone at the program start)",
        integer=True,
    ),
]
_ADDRESSES = [
    replace(a, non_negative=True) if a.name in ("H", "P", "L") else a for a in _ADDRESSES
]  # (PAL-E109)

TABLE = CodeTable(
    codes={c.name: c for c in _CODES},
    addresses={a.name: a for a in _ADDRESSES},
    groups=GROUPS,
    always_allowed=frozenset({"F", "S", "M", "D", "H"}),
    din=True,
    arc_tolerance_factor=0.001,
    program_prefix="O",
)
