"""TRAUB TX 8 D turning (Programmieranleitung TRAUB-TX 8 D): the code table.

Source: ../shared/spec/traub-tx8d-turning.md (line references L… into the manual) and the rulings
12 and 15–22 of ../shared/spec/DECISIONS.md. X is a diameter, U (and I of G2/G3) a radius value.
Codes marked PLANNED (G73, G34, milling functions) parse and are checked for their words;
executing them yields a "not supported yet" diagnostic. The other cycles run in core.interpreter.traub_cycles.
"""

from __future__ import annotations

import dataclasses

from core.dialects.codes import Address, Code, CodeTable, Group, Support

P = Support.PLANNED

AXES = frozenset({"X", "U", "Z", "W"})
TECHNOLOGY = frozenset({"F", "E", "S", "B", "M", "T", "V"})
LINE_WORDS = AXES | {"A", "D", "R"}
ARC_WORDS = AXES | {"R", "P", "Q", "I", "K", "D", "C", "H"}
SETUP_WORDS = frozenset({"S", "B", "M"})  # what the manual allows beside G24–G28, G40, G46, G54 …

GROUPS = (
    Group("motion", "Wegbedingung", "motion", ("G0", "G1", "G2", "G3", "G9", "G33"), "G1"),
    Group(
        "compensation",
        "Schneidenradiuskorrektur (SRK)",
        "nose-radius compensation",
        ("G40", "G41", "G42", "G46"),
        "G40",
    ),
    Group("zero_offset", "Nullpunkt", "zero offset", ("G54", "G55", "G56", "G57"), "G54"),
    Group("feed_mode", "Vorschubart", "feed mode", ("G94", "G95"), "G95"),
    Group("spindle_mode", "Drehzahlart", "spindle mode", ("G96", "G97"), "G97"),
    Group("units", "Maßeinheit", "units", ("G20", "G21"), "G21"),
    Group("barriers", "Barrieren", "barriers", ("G65", "G66"), "G66"),
    Group("falling", "Fallende Kontur", "falling contour", ("G88", "G89"), "G89"),
    Group("spindle", "Spindel", "spindle", ("M3", "M4", "M5", "M19"), "M5"),
    Group("coolant", "Kühlmittel", "coolant", ("M7", "M8", "M9"), "M9"),
    Group("runout", "Gewindeauslauf", "thread run-out", ("M35", "M36"), "M36"),
    Group("program_end", "Programmende", "end of program", ("M30", "M99"), None),
)


def _motion(name: str, de: str, en: str, words: frozenset[str], **kw: object) -> Code:
    return Code(name, "motion", de, en, words=words | TECHNOLOGY, owns_block=True, **kw)  # type: ignore[arg-type]


def _setup(name: str, group: str | None, de: str, en: str, **kw: object) -> Code:
    """A code that takes only S, B and M besides itself (G24–G27, G40, G46, G54 …)."""
    return Code(name, group, de, en, words=SETUP_WORDS, **kw)  # type: ignore[arg-type]


def _planned(
    name: str,
    de: str,
    en: str,
    words: frozenset[str] = frozenset(),
    group: str | None = None,
    owns: bool = True,
) -> Code:
    return Code(
        name,
        group,
        de,
        en,
        words=words | TECHNOLOGY,
        owns_block=owns,
        support=P,
        feature_de=f"{name} ({de})",
        feature_en=f"{name} ({en})",
    )


CYCLE_WORDS = AXES | {"I", "K", "D", "H", "P", "Q", "A", "J", "L", "R"}

_CODES = [
    _motion(
        "G0",
        "Gerade im Eilgang (X Durchmesser, U Radius-Inkrement)",
        "straight line at rapid traverse (X diameter, U radius increment)",
        AXES | {"A", "I", "K"},
    ),
    _motion(
        "G1",
        "Gerade mit Vorschub; A Winkel, D Fase, R Verrundung am Ende",
        "straight line at feed; A angle, D chamfer, R rounding at the end",
        LINE_WORDS,
    ),
    _motion(
        "G2",
        "Kreisbogen im Uhrzeigersinn (Zeichnung: Z nach rechts, X nach oben); R, P/Q oder I/K",
        "arc clockwise (drawing: Z right, X up); R, P/Q or I/K",
        ARC_WORDS,
    ),
    _motion(
        "G3",
        "Kreisbogen gegen den Uhrzeigersinn; R, P/Q oder I/K",
        "arc counter-clockwise; R, P/Q or I/K",
        ARC_WORDS,
    ),
    Code(
        "G4",
        None,
        "Verweilzeit in Sekunden unter X oder U (0,001–999,99 s)",
        "dwell in seconds given as X or U (0.001–999.99 s)",
        words=frozenset({"X", "U"}) | SETUP_WORDS,
        required=(("X", "U"),),
        owns_block=True,
    ),
    _motion(
        "G9", "Gerade mit Vorschub und Genauhalt am Ende", "straight line at feed with exact stop", LINE_WORDS
    ),
    _planned("G10", "Fräsfunktion aus", "milling function off", owns=False),
    _planned("G11", "Fräsfunktion ein", "milling function on", owns=False),
    _planned("G14", "Synchronschnitt aus", "synchronised cut off", owns=False),
    _planned("G15", "Synchronschnitt ein", "synchronised cut on", owns=False),
    _planned("G16", "Fräsebene Mantelfläche (POLYFORM)", "milling plane cylinder surface"),
    _planned("G17", "Fräsebene Stirnfläche", "milling plane face"),
    _planned("G19", "Fräsebene Längsschnitt", "milling plane longitudinal section"),
    Code(
        "G20",
        "units",
        "Maßangaben in Zoll",
        "dimensions in inches",
        support=P,
        feature_de="Zollprogrammierung G20",
        feature_en="inch programming G20",
    ),
    Code(
        "G21",
        "units",
        "Maßangaben in Millimetern (Einschaltzustand)",
        "dimensions in millimetres (switch-on)",
    ),
    Code(
        "G22",
        None,
        "Unterprogrammaufruf: A Programmnummer, P/Q Satznummern des Abschnitts, H Anzahl",
        "subprogram call: A program number, P/Q block numbers of the section, H number of runs",
        words=frozenset({"A", "P", "Q", "H"}),
        required=(("A", "P", "Q"),),
        owns_block=True,
    ),
    _setup(
        "G24",
        None,
        "Eilgang zum Werkzeugwechselpunkt, nur X",
        "rapid to the tool-change point, X only",
        owns_block=True,
    ),
    _setup(
        "G25",
        None,
        "Eilgang zum Werkzeugwechselpunkt, nur Z",
        "rapid to the tool-change point, Z only",
        owns_block=True,
    ),
    _setup(
        "G26",
        None,
        "Eilgang zum Werkzeugwechselpunkt, erst X dann Z",
        "rapid to the tool-change point, X first, then Z",
        owns_block=True,
    ),
    _setup(
        "G27",
        None,
        "Eilgang zum Werkzeugwechselpunkt, erst Z dann X",
        "rapid to the tool-change point, Z first, then X",
        owns_block=True,
    ),
    Code(
        "G28",
        None,
        "Eilgang zum Referenzpunkt (X/Z: Hilfspunkt vorher)",
        "rapid to the reference point (X/Z: an intermediate point first)",
        words=AXES | SETUP_WORDS,
        owns_block=True,
    ),
    Code(
        "G33",
        "motion",
        "Gewindeschneiden, Einzelsatz: X/Z Endpunkt, F (3) oder E (5 Nachkommastellen) "
        "Steigung, selbsthaltend",
        "thread cutting, single block: X/Z end, pitch F (3) or E (5 decimals), modal",
        words=AXES | TECHNOLOGY,
        owns_block=True,
    ),
    _planned(
        "G34",
        "Gewindeschneiden mit veränderlicher Steigung",
        "thread cutting with variable pitch",
        AXES | {"K"},
    ),
    _planned("G36", "Programmspeicher öffnen", "open program memory"),
    _planned("G37", "Werkzeugspeicher öffnen", "open tool memory"),
    _planned("G38", "Parameterspeicher öffnen", "open parameter memory"),
    _setup("G40", "compensation", "Schneidenradiuskorrektur (SRK) aus", "nose-radius compensation off"),
    _setup(
        "G41",
        "compensation",
        "SRK ein, Werkzeug links der Bahn, ohne Schnittbereichsüberwachung",
        "nose-radius compensation on, tool left of the path, no cutting-range monitoring",
    ),
    _setup(
        "G42",
        "compensation",
        "SRK ein, Werkzeug rechts der Bahn, ohne Schnittbereichsüberwachung",
        "nose-radius compensation on, tool right of the path, no cutting-range monitoring",
    ),
    _setup(
        "G46",
        "compensation",
        "Schneidenradiuskorrektur (SRK) ein; Seite aus Quadrant und Fahrtrichtung",
        "nose-radius compensation on; side from the quadrant and the travel direction",
    ),
    Code(
        "G53",
        None,
        "Eilgang in Maschinenkoordinaten (X/Z bezogen auf den Maschinennullpunkt)",
        "rapid in machine coordinates (X/Z from the machine zero)",
        words=frozenset({"X", "Z"}) | SETUP_WORDS,
        required=(("X", "Z"),),
        owns_block=True,
    ),
    _setup(
        "G54",
        "zero_offset",
        "Werkstücknullpunkt 1 (SET UP-Bild 4 #2, Einschaltzustand)",
        "workpiece zero 1 (set-up screen 4 #2, switch-on)",
    ),
    *(
        _setup(
            f"G{n}",
            "zero_offset",
            f"Werkstücknullpunkt {n - 53} (SET UP-Bild 4 #{n - 52})",
            f"workpiece zero {n - 53} (set-up screen 4 #{n - 52})",
        )
        for n in (55, 56, 57)
    ),
    Code(
        "G59",
        None,
        "Nullpunktverschiebung, additiv zu G54–G57 (X als Durchmesser); ersetzt die vorige",
        "zero shift, added to G54–G57 (X as a diameter); replaces the previous one",
        words=frozenset({"X", "Z"}) | SETUP_WORDS,
        owns_block=True,
    ),
    _setup("G65", "barriers", "Barrieren aus", "barriers off"),
    _setup("G66", "barriers", "Barrieren ein (Einschaltzustand)", "barriers on (switch-on)"),
    _planned("G73", "Schruppzyklus konturparallel", "contour-parallel roughing cycle", CYCLE_WORDS),
    # the cycles of core.interpreter.traub_cycles (spec §11–§12, DECISIONS 20)
    *(
        Code(f"G{n}", None, de, en, words=CYCLE_WORDS | TECHNOLOGY, owns_block=True)
        for n, de, en in (
            (
                70,
                (
                    "Schruppzyklus längs für Anstellwinkel J < 90°: wie G71, jeder Schnitt mit voller Tiefe D (Radius); "
                    "die Wirkung von J wird nicht unterstützt"
                ),
                (
                    "longitudinal roughing for setting angles J < 90°: as G71, every cut at the full depth D (radius); the "
                    "effect of J is not supported"
                ),
            ),
            (
                71,
                (
                    "Schruppzyklus längs gegen Kontur: P/Q erster/letzter Konturs. oder A Unterprogramm, I/K Aufmaß "
                    "(I als Radius), D Schnitttiefe (Radius), E Vorschub fallender Kontur"
                ),
                (
                    "longitudinal roughing against contour: P/Q first/last contour block or A subprogram, I/K allowance "
                    "(I radius), D depth of cut (radius), E feed on falling sections"
                ),
            ),
            (
                72,
                (
                    "Schruppzyklus plan gegen Kontur: P/Q oder A, I/K Aufmaß, D Schnitttiefe in Z, E Vorschub fallender "
                    "Kontur"
                ),
                (
                    "facing roughing against contour: P/Q or A, I/K allowance, D depth of cut in Z, E feed on falling "
                    "sections"
                ),
            ),
            (
                74,
                (
                    "Schruppzyklus längs mit Spanunterbrechung: X/Z Endpunkt, I Schnitttiefe (Radius), K Schnittlänge "
                    "bis zur Unterbrechung, D Abheben (negativ: ab 2. Schnitt); ohne X/U: Bohren"
                ),
                (
                    "longitudinal roughing with chip breaking: X/Z end, I depth (radius), K cut length between "
                    "interruptions, D lift (negative: from the 2nd cut); without X/U: drilling"
                ),
            ),
            (
                75,
                (
                    "Schruppzyklus plan mit Spanunterbrechung: X/Z Endpunkt, K Schnitttiefe, I Schnittlänge bis zur "
                    "Unterbrechung (Radius), D Abheben; ohne Z/W: Querbohren"
                ),
                (
                    "facing roughing with chip breaking: X/Z end, K depth, I cut length between interruptions (radius), "
                    "D lift; without Z/W: cross drilling"
                ),
            ),
            (
                86,
                "Gewindeschneidzyklus plan (Stirngewinde): wie G76, Zustellung in Z, Gewinde entlang X",
                "face thread cutting cycle: as G76, infeed in Z, the thread along X",
            ),
            (
                76,
                (
                    "Gewindeschneidzyklus längs: X/Z Endpunkt im Gewindegrund, K Gewindetiefe, H Schnittzahl, D letzte "
                    "Zustellung, A Zustellwinkel, J Kegelwinkel, F/E Steigung"
                ),
                (
                    "thread cutting cycle, longitudinal: X/Z end at the root, K thread depth, H passes, D last infeed, "
                    "A infeed angle, J taper angle, F/E pitch"
                ),
            ),
            (
                77,
                "Fasenzyklus längs: X/Z Ziel, I Fasenweg in X, K Weg bis Fasenanfang in Z",
                "chamfer cycle, longitudinal: X/Z target, I chamfer in X, K distance to the chamfer start in Z",
            ),
            (
                78,
                (
                    "Gewindeschneidzyklus für Sondergewinde (ein Schnitt, weitere mit G81): X/Z Ziel, I/K Auslauffase, "
                    "F/E Steigung"
                ),
                (
                    "thread cutting cycle for special threads (one pass, more with G81): X/Z target, I/K run-out chamfer, "
                    "F/E pitch"
                ),
            ),
            (
                79,
                "Fasenzyklus plan: X/Z Ziel, I Weg bis Fasenanfang in X, K Fasenweg in Z",
                "chamfer cycle, facing: X/Z target, I distance to the chamfer start in X, K chamfer in Z",
            ),
            (
                81,
                "Wiederholzyklus für G77, G78, G79: U/W Versatz je Schnitt (U Radius), H Anzahl",
                "repeat cycle for G77, G78, G79: U/W shift per pass (U radius), H number",
            ),
            (
                82,
                (
                    "Gewindebohrzyklus: Z/W Tiefe, F Vorschub bis 20 % unter der Steigung; zurück mit umgekehrter "
                    "Drehrichtung"
                ),
                "tapping cycle: Z/W depth, F feed up to 20 % below the pitch; back with the spindle reversed",
            ),
            (
                83,
                "Tieflochbohrzyklus 1: Z/W Endtiefe, D erste Bohrtiefe, H gleiche Abschnitte der Resttiefe",
                "deep-hole drilling cycle 1: Z/W final depth, D first depth, H equal sections of the rest",
            ),
            (
                84,
                (
                    "Tieflochbohrzyklus 2: Z/W Endtiefe, D Eilgangweg, I erste, K weitere Bohrtiefen, A Sicherheitsabstand, "
                    "Q/R Verweilzeiten"
                ),
                (
                    "deep-hole drilling cycle 2: Z/W final depth, D rapid distance, I first, K further depths, A safety "
                    "distance, Q/R dwells"
                ),
            ),
        )
    ),
    Code(
        "G88",
        "falling",
        "Fallende Kontur ein: G71/G72 schruppen fallende Abschnitte (Vorschub E)",
        "falling contour on: G71/G72 rough falling sections (feed E)",
        words=SETUP_WORDS,
    ),
    _setup("G89", "falling", "Fallende Kontur aus", "falling contour off"),
    _setup(
        "G90",
        None,
        "Absolutmaß für C- und R-Achse (X/Z bleiben absolut, U/W inkremental)",
        "absolute dimensions for the C and R axes (X/Z stay absolute, U/W incremental)",
    ),
    _setup("G91", None, "Kettenmaß für C- und R-Achse", "incremental dimensions for the C and R axes"),
    Code(
        "G92",
        None,
        "Drehzahlbegrenzung: S höchste Drehzahl (1/min) bei G96",
        "speed limit: S highest spindle speed (1/min) under G96",
        words=frozenset({"X", "Z", "Q"}) | SETUP_WORDS,
        required=(("S",),),
    ),
    _setup("G94", "feed_mode", "Vorschub in mm/min", "feed in mm/min"),
    _setup(
        "G95",
        "feed_mode",
        "Vorschub in mm pro Umdrehung (Einschaltzustand)",
        "feed in mm per revolution (switch-on)",
    ),
    Code(
        "G96",
        "spindle_mode",
        "Konstante Schnittgeschwindigkeit V in m/min (Grenze: G92 S)",
        "constant cutting speed V in m/min (limit: G92 S)",
        words=frozenset({"V", "T"}) | SETUP_WORDS,
        required=(("V",),),
    ),
    Code(
        "G97",
        "spindle_mode",
        "Feste Drehzahl S, oder aus V und Durchmesser X berechnet",
        "fixed spindle speed S, or computed from V and diameter X",
        words=frozenset({"V", "X", "T"}) | SETUP_WORDS,
        required=(("S", "V"),),
    ),
    _planned("G98", "Vorschubkorrektur ein", "feed correction on", owns=False),
    _planned("G99", "Vorschubkorrektur aus", "feed correction off", owns=False),
]

# Macro calls G201–G299 → program O9801–O9899 (L979–1055)
_CODES += [
    Code(
        f"G{n}",
        None,
        f"Makroaufruf: Programm O98{n - 200:02d}",
        f"macro call: program O98{n - 200:02d}",
        words=SETUP_WORDS,
        owns_block=True,
    )
    for n in range(201, 300)
]

# The M functions of the manual's table (L1058–1222)
_M_TABLE: list[tuple[int, str, str]] = [
    (0, "Programmierter Halt", "programmed stop"),
    (1, "Wahlweiser Halt (wenn Taste M01 gedrückt)", "optional stop (if key M01 is pressed)"),
    (6, "Ersatzwerkzeug folgt (nur mit T)", "replacement tool follows (with T only)"),
    (10, "Werkstück spannen", "clamp workpiece"),
    (11, "Werkstück lösen", "release workpiece"),
    (13, "Letztes Ersatzwerkzeug (nur mit T)", "last replacement tool (with T only)"),
    (14, "Drehzahl-Soll-Ist-Überwachung unterdrücken", "suppress speed set/actual monitoring"),
    (15, "Werkzeugwechselsignal unterdrücken", "suppress tool-change signal"),
    (16, "M15 zurücksetzen", "reset M15"),
    (17, "C-Achsen-Kopplung ein", "C-axis coupling on"),
    (18, "C-Achsen-Kopplung aus", "C-axis coupling off"),
    (21, "Servomotor angetriebene Werkzeuge S3 ein", "servo motor driven tools S3 on"),
    (22, "Servomotor angetriebene Werkzeuge S1/S2 ein", "servo motor driven tools S1/S2 on"),
    (23, "Angetriebenes Werkzeug im Uhrzeigersinn", "driven tool clockwise"),
    (24, "Angetriebenes Werkzeug gegen den Uhrzeigersinn", "driven tool counter-clockwise"),
    (25, "Servomotor S1/S2/S3 aus", "servo motor S1/S2/S3 off"),
    (26, "Reitstock zur Spindelmitte", "tailstock to spindle centre"),
    (27, "Reitstock zurück", "tailstock back"),
    (28, "Pinole vor", "quill forward"),
    (29, "Pinole zurück", "quill back"),
    (31, "Ausblendsätze aus", "skip blocks off"),
    (32, "Spiegelfunktion ein (Nachbearbeitungsstation)", "mirror function on (post-machining station)"),
    (33, "M32 aus", "M32 off"),
    (37, "Angetriebenes Werkzeug Übersetzung 1:1", "driven tool ratio 1:1"),
    (38, "Angetriebenes Werkzeug Übersetzung 2:1", "driven tool ratio 2:1"),
    (39, "Angetriebenes Werkzeug Übersetzung aus", "driven tool ratio off"),
    (40, "Getriebestufe 1", "gear stage 1"),
    (41, "Getriebestufe 2", "gear stage 2"),
    (42, "Getriebestufe 3", "gear stage 3"),
    (43, "Getriebestufe 4", "gear stage 4"),
    (46, "System-Reset (Werkzeugüberwachung)", "system reset (tool monitoring)"),
    (48, "Overrides für Vorschub und Drehzahl wirksam", "feed and speed overrides effective"),
    (49, "Overrides für Vorschub und Drehzahl unwirksam", "feed and speed overrides ineffective"),
    (50, "Spülvorrichtung ein", "flushing device on"),
    (54, "Kühlmittel Nachbearbeitungsstation ein", "coolant post-machining station on"),
    (55, "Kühlmittel Nachbearbeitungsstation aus", "coolant post-machining station off"),
    (56, "Verschleißüberwachung ein", "wear monitoring on"),
    (57, "Standzeit löschen", "clear tool-life time"),
    (58, "Werkzeugüberwachung aus", "tool monitoring off"),
    (59, "Werkzeugüberwachung ein", "tool monitoring on"),
    (60, "Stangenwechsel", "bar change"),
    (61, "Stangenwechsel Profilmaterial", "bar change, profile material"),
    (
        62,
        "Sollwert von Hauptspindel; Gegenspindelbremse ein; Greifer schließen",
        "set value from main spindle; counter-spindle brake on; close gripper",
    ),
    (
        63,
        "Sollwert zurücksetzen; Gegenspindelbremse lösen; Greifer öffnen",
        "reset set value; release counter-spindle brake; open gripper",
    ),
    (64, "Rollkopf rechts", "rolling head right"),
    (65, "Rollkopf links", "rolling head left"),
    (66, "Greifer schließen (Zwischenstellung)", "close gripper (intermediate position)"),
    (67, "Greifer öffnen (Zwischenstellung)", "open gripper (intermediate position)"),
    (68, "Abstechschlitten Programm 1", "cut-off slide program 1"),
    (69, "Abstechschlitten Programm 2", "cut-off slide program 2"),
    (70, "Haltebremse aus", "holding brake off"),
    (71, "Reitstock lösen (R-Achse)", "release tailstock (R axis)"),
    (72, "Reitstock klemmen (R-Achse)", "clamp tailstock (R axis)"),
    (73, "Dämpfungsbremse ein", "damping brake on"),
    (74, "Dämpfungsbremse aus", "damping brake off"),
    (77, "Futter öffnen bei drehender Hauptspindel", "chuck opening with rotating main spindle"),
    (78, "M77 aus", "M77 off"),
    (80, "Lünette 1 spannen", "steady rest 1 clamp"),
    (81, "Lünette 1 lösen", "steady rest 1 release"),
    (82, "Lünette 2 spannen", "steady rest 2 clamp"),
    (83, "Lünette 2 lösen", "steady rest 2 release"),
    (84, "Lünettenschlitten vor", "steady-rest slide forward"),
    (85, "Lünettenschlitten zurück", "steady-rest slide back"),
    (90, "NC-Programm läuft nach Zyklusende weiter (mit M68/M69)", "program continues after cycle end"),
    (
        91,
        "NC-Programm läuft nach Erreichen der vorderen Endlage weiter",
        "program continues after the front end position",
    ),
    (92, "Späneförderer ein", "chip conveyor on"),
    (93, "Späneförderer aus", "chip conveyor off"),
    (94, "Teileabnahme vor", "part removal device forward"),
    (95, "Teileabnahme zurück", "part removal device back"),
    (96, "Teileabnahme zurück Zwischenstellung", "part removal device back, intermediate position"),
    (97, "Schwenkfutter schwenken", "swivel chuck swivel"),
]

_CODES += [
    Code(
        "M3",
        "spindle",
        "Hauptspindel im Uhrzeigersinn (von der Antriebsseite gesehen)",
        "main spindle clockwise (seen from the drive)",
    ),
    Code(
        "M4",
        "spindle",
        "Hauptspindel gegen den Uhrzeigersinn (von der Antriebsseite gesehen)",
        "main spindle counter-clockwise (seen from the drive)",
    ),
    Code("M5", "spindle", "Hauptspindel halt", "main spindle stop"),
    Code(
        "M19", "spindle", "Haltebremse ein / Hauptspindel verriegeln", "holding brake on / lock main spindle"
    ),
    Code("M7", "coolant", "Kühlmittel ein, Hochdruck", "coolant on, high pressure"),
    Code("M8", "coolant", "Kühlmittel ein", "coolant on"),
    Code("M9", "coolant", "Kühlmittel aus", "coolant off"),
    Code(
        "M35",
        "runout",
        "Kegeliger Gewindeauslauf ein (G76, G78, G86; Länge und Winkel: Einrichtedaten)",
        "tapered thread run-out on (G76, G78, G86; length and angle: set-up data)",
    ),
    Code("M36", "runout", "Kegeliger Gewindeauslauf aus", "tapered thread run-out off"),
    Code(
        "M30",
        "program_end",
        "Programmende mit Rücksprung zum Programmanfang",
        "end of program, back to its start",
    ),
    Code(
        "M99",
        "program_end",
        "Unterprogrammende, Rücksprung ins rufende Programm",
        "end of subprogram, back to the caller",
    ),
    *(Code(f"M{n}", None, de, en) for n, de, en in _M_TABLE),
]

_ADDRESSES = [
    Address(
        "N",
        "Satznummer (höchstens 4 Stellen); ändert die Reihenfolge nicht",
        "block number (at most 4 digits); does not change the order",
        integer=True,
    ),
    Address(
        "O",
        "Programmnummer (erster Satz eines Programms)",
        "program number (first block of a program)",
        integer=True,
    ),
    Address("G", "Wegbedingung (G-Befehl)", "preparatory function (G code)", integer=True),
    Address(
        "M",
        "Zusatzfunktion (höchstens 3 M-Wörter je Satz)",
        "miscellaneous function (at most 3 per block)",
        integer=True,
    ),
    Address(
        "X",
        "X-Zielpunkt als DURCHMESSER, absolut; bei G4 Verweilzeit in s",
        "X target as a DIAMETER, absolute; with G4 dwell in s",
    ),
    Address("Z", "Z-Zielpunkt, absolut", "Z target, absolute"),
    Address(
        "U",
        "X-Weg inkremental als RADIUSWERT (nicht Durchmesser!): U1 = 2 mm im Durchmesser; "
        "bei G4 Verweilzeit in s",
        "X distance, incremental, as a RADIUS value (not a diameter!): U1 = 2 mm on the diameter; "
        "with G4 dwell in s",
    ),
    Address("W", "Z-Weg inkremental", "Z distance, incremental"),
    Address(
        "A",
        "Winkel der Geraden (0° = +Z, gegen den Uhrzeigersinn positiv); bei G22 Programmnummer",
        "angle of the line (0° = +Z, counter-clockwise positive); with G22 program number",
    ),
    Address(
        "D",
        "Fase am Satzende: D+ Breite in Z, D- Fasenlänge",
        "chamfer at the block end: D+ width in Z, D- chamfer length",
    ),
    Address(
        "R",
        "Kreisradius (G2/G3, unter 180°) bzw. Verrundung am Satzende (G1)",
        "arc radius (G2/G3, under 180°) or rounding at the block end (G1)",
    ),
    Address("C", "Verrundung am Ende eines Kreisbogens", "rounding at the end of an arc"),
    Address(
        "P",
        "Kreismittelpunkt X absolut (Durchmesser); bei G22 erster Satz",
        "arc centre X absolute (diameter); with G22 first block",
    ),
    Address(
        "Q", "Kreismittelpunkt Z absolut; bei G22 letzter Satz", "arc centre Z absolute; with G22 last block"
    ),
    Address(
        "I",
        "Kreismittelpunkt X vom Startpunkt aus, als RADIUSWERT",
        "arc centre X from the start point, as a RADIUS value",
    ),
    Address("K", "Kreismittelpunkt Z vom Startpunkt aus", "arc centre Z from the start point"),
    Address(
        "H",
        "Schnittpunktauswahl H0/H1 bzw. Anzahl der Durchläufe (G22)",
        "intersection choice H0/H1 or number of runs (G22)",
        integer=True,
    ),
    Address("F", "Vorschub (G95 mm/U, G94 mm/min), selbsthaltend", "feed (G95 mm/rev, G94 mm/min), modal"),
    Address(
        "E", "Vorschub auf Fasen und Verrundungen, selbsthaltend", "feed on chamfers and roundings, modal"
    ),
    Address("S", "Spindeldrehzahl 1/min (bei G92: Höchstdrehzahl)", "spindle speed 1/min (with G92: limit)"),
    Address("V", "Schnittgeschwindigkeit m/min (G96, G97)", "cutting speed m/min (G96, G97)"),
    Address(
        "T",
        "Werkzeug: Revolverplatz (2 Stellen) und Korrekturnummer (2 Stellen), z. B. T0303",
        "tool: turret station (2 digits) and offset number (2 digits), e.g. T0303",
        integer=True,
    ),
    Address(
        "B",
        "B-Funktion: 2 Stellen Funktion, 4 Stellen Wert (B060800 = angetriebenes Werkzeug 800 1/min)",
        "B function: 2 digits function, 4 digits value (B060800 = driven tool 800 1/min)",
        integer=True,
    ),
    Address(
        "L",
        "Parameter L1…L48, L101…L148 (L1 = 20; X L2; Z-[L2/2])",
        "parameter L1…L48, L101…L148 (L1 = 20; X L2; Z-[L2/2])",
    ),
    Address("J", "Kegelwinkel (Gewindezyklen)", "taper angle (thread cycles)"),
]

# the manual's lists of codes with rules of their own, as columns of the table (codes.Code)
_COLUMNS: dict[str, dict[str, object]] = {
    **{m: {"alone": True} for m in ("M0", "M1", "M30", "M99", "M10", "M11", "M17", "M18")},  # L1170
    **{m: {"needs_tool": True} for m in ("M6", "M13")},  # L1160–1190
    **{g: {"change_point": True} for g in ("G24", "G25", "G26", "G27", "G28", "G53")},
    **{g: {"speed": True} for g in ("G92", "G96", "G97")},
    # the cycles of core/interpreter/traub_cycles.py by family (G33 is the modal thread motion)
    "G33": {"cycle": "thread_motion"},
    **{g: {"cycle": "contour_roughing"} for g in ("G70", "G71", "G72")},
    **{g: {"cycle": "rectangle_roughing"} for g in ("G74", "G75")},
    **{g: {"cycle": "drilling"} for g in ("G83", "G84")},
    **{g: {"cycle": "thread"} for g in ("G76", "G82", "G86")},
    **{g: {"cycle": "single_cut"} for g in ("G77", "G78", "G79", "G81")},
}
# G codes allowed while SRK is on (L2544–2566), besides the SRK codes themselves
for _g in (
    "G0",
    "G1",
    "G2",
    "G3",
    "G4",
    "G9",
    "G22",
    "G40",
    "G41",
    "G42",
    "G46",
    "G77",
    "G79",
    "G94",
    "G95",
    "G96",
    "G97",
):
    _COLUMNS.setdefault(_g, {})["with_srk"] = True
_CODES = [dataclasses.replace(c, **_COLUMNS[c.name]) if c.name in _COLUMNS else c for c in _CODES]  # type: ignore[arg-type]
_ADDRESSES = [
    dataclasses.replace(a, non_negative=True) if a.name in ("F", "E", "S", "V", "H") else a
    for a in _ADDRESSES
]  # (PAL-E109)

TABLE = CodeTable(
    codes={c.name: c for c in _CODES},
    addresses={a.name: a for a in _ADDRESSES},
    groups=GROUPS,
    always_allowed=frozenset({"F", "E", "S", "B", "M", "T", "V"}),
    tool_words=frozenset({"T"}),
)
