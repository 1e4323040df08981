"""Diagnostics: the one catalogue of every message the pipeline can produce, and the type that carries one.

A code is stable and never reused (tests assert codes, not wording). Each entry has a default
severity and a German and an English text with `{named}` parameters. The letter after the
dialect prefix tells the default severity: E error, W warning, I info.

The PAL- checks are shared: ISO, Beckhoff and TRAUB programs run through the same syntax, block and limit
checks (and ISO and Beckhoff through the whole PAL milling interpreter). A program of another dialect reports
a shared check with its own dialect's prefix and the number + 1000 (`in_dialect`): PAL-E301 is TX-E1301,
ISO-E1301 and BK-E1301 — the dialects' own codes (TX-E301, ISO-E301) keep their meaning.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field
from enum import Enum
from typing import Any

from core.syntax.blocks import Span


class Severity(str, Enum):
    ERROR = "error"
    WARNING = "warning"
    INFO = "info"


@dataclass(frozen=True, slots=True)
class Entry:
    severity: Severity
    de: str
    en: str


E, W, I = Severity.ERROR, Severity.WARNING, Severity.INFO  # noqa: E741 - the letters of the codes

CATALOGUE: dict[str, Entry] = {
    # --- input and limits -------------------------------------------------------------
    "PAL-E001": Entry(E, "Unerwartetes Zeichen »{char}«.", "Unexpected character '{char}'."),
    "PAL-E002": Entry(
        E,
        "Ungültige Zahl »{text}« bei Adresse {address}.",
        "Malformed number '{text}' for address {address}.",
    ),
    "PAL-E003": Entry(E, "Unbekannte Adresse »{address}«.", "Unknown address '{address}'."),
    "PAL-E004": Entry(
        E,
        "Satz ist zu lang ({length} Zeichen, höchstens {limit}); er wird nicht ausgeführt.",
        "Block is too long ({length} characters, at most {limit}); it is not executed.",
    ),
    "PAL-E005": Entry(
        E,
        "Programm ist zu groß ({size} Zeichen, höchstens {limit}); es wird nicht ausgeführt.",
        "Program is too large ({size} characters, at most {limit}); it is not executed.",
    ),
    "PAL-E006": Entry(
        E,
        "Programm hat zu viele Sätze ({count}, höchstens {limit}); "
        "die Sätze ab Zeile {line} werden nicht ausgeführt.",
        "Program has too many blocks ({count}, at most {limit}); "
        "blocks from line {line} on are not executed.",
    ),
    "PAL-E007": Entry(
        E, "Unerwartetes »{token}«: {expected} erwartet.", "Unexpected '{token}': expected {expected}."
    ),
    "PAL-E008": Entry(
        E,
        "Steuerzeichen oder Binärdaten im Programmtext (Zeichencode {char_code}).",
        "Control character or binary data in the program text (character code {char_code}).",
    ),
    "PAL-E009": Entry(
        E,
        "Zuweisung an »{address}« ist nicht möglich; nur Parameter P1…P999 können einen Wert erhalten.",
        "Cannot assign to '{address}'; only parameters P1…P999 can be assigned.",
    ),
    "PAL-E010": Entry(
        E,
        "Dezimalkomma in »{text}«: Dezimalzahlen werden mit Punkt geschrieben ({fixed}).",
        "Decimal comma in '{text}': decimals are written with a point ({fixed}).",
    ),
    "PAL-E011": Entry(
        E,
        "Die Satznummer muss eine ganze Zahl sein (»N{raw}«).",
        "The block number must be a whole number ('N{raw}').",
    ),
    "PAL-E012": Entry(
        E,
        "Zu viele Meldungen; weitere werden nicht angezeigt (höchstens {limit}).",
        "Too many diagnostics; further ones are not shown (at most {limit}).",
    ),
    "PAL-E013": Entry(
        E,
        "Ausgeführte Sätze überschreiten die Grenze von {limit}; das Programm wird "
        "hier abgebrochen (Endlosschleife?).",
        "Executed blocks exceed the limit of {limit}; the program is stopped here (endless loop?).",
    ),
    "PAL-E014": Entry(
        E,
        "Ausdruck ist zu tief geschachtelt (höchstens {limit} Ebenen).",
        "Expression is nested too deeply (at most {limit} levels).",
    ),
    "PAL-E015": Entry(
        E,
        "Wert {value} bei {address} liegt außerhalb des zulässigen Bereichs ±{limit}.",
        "Value {value} of {address} is outside the allowed range ±{limit}.",
    ),
    "PAL-E016": Entry(
        E,
        "Das Programm rechnet zu viel: mehr als {limit} Rechenschritte (Wörter, Rechenterme und "
        "Meldungen der ausgeführten Sätze); es wird hier abgebrochen (Endlosschleife?).",
        "The program computes too much: more than {limit} evaluation steps (words, terms and "
        "diagnostics of the executed blocks); it is stopped here (endless loop?).",
    ),
    "PAL-E017": Entry(
        E,
        "Das Programm erzeugt mehr als {limit} Verfahrbewegungen; es wird hier abgebrochen "
        "(Endlosschleife?).",
        "The program makes more than {limit} moves; it is stopped here (endless loop?).",
    ),
    "PAL-I018": Entry(
        I,
        "Werkzeugweg gekürzt: gezeigt werden die ersten {shown} von {total} Befehlen "
        "(Bewegungen, Verweilzeiten, Werkzeugwechsel), ab hier nicht mehr.",
        "Toolpath shortened: the first {shown} of {total} commands (moves, dwells, tool changes) "
        "are shown, none from here on.",
    ),
    "PAL-I019": Entry(
        I,
        "Darstellung gekürzt: der Werkzeugweg wird mit höchstens {limit} Strecken gezeichnet "
        "(Kreisbögen als Sehnen); ab hier wird er nicht mehr gezeichnet.",
        "Drawing shortened: the toolpath is drawn with at most {limit} segments (arcs as chords); "
        "from here on it is not drawn.",
    ),
    # --- block structure ------------------------------------------------------------------
    "PAL-E101": Entry(
        E,
        "Adresse {address} ist mit {command} nicht erlaubt.",
        "Address {address} is not allowed with {command}.",
    ),
    "PAL-E102": Entry(
        E,
        "Pflichtadresse {address} fehlt bei {command}.",
        "Mandatory address {address} is missing for {command}.",
    ),
    "PAL-E103": Entry(
        E,
        "{first} und {second} gehören zur selben Gruppe ({group}) und dürfen nicht im selben Satz stehen.",
        "{first} and {second} belong to the same group ({group_en}) and cannot be in one block.",
    ),
    "PAL-E104": Entry(
        E,
        "Mehr als zwei G-Befehle in einem Satz ({count}).",
        "More than two G commands in one block ({count}).",
    ),
    "PAL-E105": Entry(E, "Unbekannter G-Befehl {code}.", "Unknown G command {code}."),
    "PAL-E106": Entry(
        E,
        "Adresse {address} steht mehrfach im Satz.",
        "Address {address} appears more than once in the block.",
    ),
    "PAL-E107": Entry(
        E,
        "{first} und {second} geben dieselbe Achse zweimal an.",
        "{first} and {second} give the same axis twice.",
    ),
    "PAL-E108": Entry(
        E, "{address} braucht eine ganze Zahl, nicht »{raw}«.", "{address} needs a whole number, not '{raw}'."
    ),
    "PAL-E109": Entry(
        E, "{address} darf nicht negativ sein ({raw}).", "{address} must not be negative ({raw})."
    ),
    "PAL-E110": Entry(
        E,
        "{command} gibt es in der PAL-Fräsen-Syntax nicht (nur Ebene G17).",
        "{command} does not exist in PAL milling (plane G17 only).",
    ),
    "PAL-E111": Entry(E, "{address} braucht einen Wert.", "{address} needs a value."),
    "PAL-E112": Entry(
        E,
        "Korrekturschalter TC{value} gibt es nicht (TC1 bis TC9).",
        "Offset memory TC{value} does not exist (TC1 to TC9).",
    ),
    "PAL-E113": Entry(
        E,
        "Parameter P{number} gibt es nicht (P1 bis P999).",
        "Parameter P{number} does not exist (P1 to P999).",
    ),
    "PAL-E114": Entry(E, "Division durch null im Ausdruck.", "Division by zero in the expression."),
    "PAL-E115": Entry(
        E,
        "{address} ist hier nur mit einer Zahl erlaubt, nicht mit einem Ausdruck.",
        "{address} takes a number here, not an expression.",
    ),
    "PAL-W101": Entry(
        W,
        "Sätze nach M30 (Programmende) werden nicht ausgeführt.",
        "Blocks after M30 (end of program) are not executed.",
    ),
    "PAL-W102": Entry(W, "Programmende M30 fehlt.", "End of program M30 is missing."),
    "PAL-W103": Entry(
        W,
        "Unbekannte M-Funktion M{code}; sie hat keine Wirkung.",
        "Unknown M function M{code}; it has no effect.",
    ),
    "PAL-I101": Entry(
        I,
        "{address} ist unter {mode} nicht üblich; es wird als {meaning} ausgeführt.",
        "{address} is unusual under {mode}; it is executed as {meaning}.",
    ),
    "PAL-W105": Entry(
        W, "{address} hat bei {command} keine Wirkung.", "{address} has no effect with {command}."
    ),
    "PAL-W106": Entry(
        W,
        "Parameter P{number} wird gelesen, bevor ihm ein Wert zugewiesen wurde (gilt als 0).",
        "Parameter P{number} is read before it was assigned (taken as 0).",
    ),
    # --- geometry -------------------------------------------------------------------------
    "PAL-E201": Entry(E, "Kreisbogen ohne Lösung: {reason}.", "Arc has no solution: {reason_en}."),
    "PAL-E202": Entry(
        E,
        "Kreisendpunktfehler: Start- und Endpunkt haben vom Mittelpunkt verschiedene "
        "Abstände ({r_start} mm und {r_end} mm, erlaubt sind {tolerance} mm Unterschied).",
        "Circle end point error: start and end point lie at different distances from the "
        "centre ({r_start} mm and {r_end} mm, tolerance {tolerance} mm).",
    ),
    "PAL-E203": Entry(
        E,
        "Kreisbogen ist unterbestimmt: {command} braucht Endpunkt und Mittelpunkt "
        "(I/J oder IA/JA) oder Radius R.",
        "Arc is underdetermined: {command} needs an end point and a centre (I/J or IA/JA) or a radius R.",
    ),
    "PAL-E204": Entry(
        E,
        "{address} ist in der Ebene {plane} nicht erlaubt; der Mittelpunkt wird mit {centre} angegeben.",
        "{address} is not allowed in plane {plane}; give the centre with {centre}.",
    ),
    "PAL-E205": Entry(
        E,
        "Ein Vollkreis lässt sich nicht mit R programmieren; Mittelpunkt mit I/J angeben.",
        "A full circle cannot be programmed with R; give the centre with I/J.",
    ),
    "PAL-E206": Entry(
        E,
        "Kreisbogen mit Radius 0: der Mittelpunkt liegt auf dem Startpunkt.",
        "Arc of radius 0: the centre lies on the start point.",
    ),
    "PAL-E207": Entry(
        E,
        "{command} mit {address}{raw} braucht eine Zielkoordinate X, Y oder Z.",
        "{command} with {address}{raw} needs a target coordinate X, Y or Z.",
    ),
    "PAL-E208": Entry(
        E,
        "Übergangselement {element} passt nicht zwischen Zeile {first} und Zeile {second}: {reason}.",
        "Transition element {element} does not fit between line {first} and line {second}: {reason_en}.",
    ),
    "PAL-E209": Entry(
        E,
        "Nach dem Übergangselement RN in Zeile {line} folgt kein Konturelement (G1, G2, G3, "
        "G11, G12, G13 in der Ebene).",
        "The transition element RN in line {line} is not followed by a contour element (G1, G2, "
        "G3, G11, G12, G13 in the plane).",
    ),
    "PAL-E210": Entry(E, "Gerade ohne Lösung: {reason}.", "Line has no solution: {reason_en}."),
    "PAL-E211": Entry(
        E,
        "Gerade ist überbestimmt: höchstens zwei von X, Y, D, AS (außer Z) angeben.",
        "Line is overdetermined: give at most two of X, Y, D, AS (besides Z).",
    ),
    "PAL-E212": Entry(
        E,
        "Gerade ist unterbestimmt: {address} allein legt keinen Endpunkt fest.",
        "Line is underdetermined: {address} alone does not fix an end point.",
    ),
    "PAL-E213": Entry(
        E, "{address} muss größer als 0 sein ({raw}).", "{address} must be greater than 0 ({raw})."
    ),
    "PAL-E214": Entry(
        E,
        "Innenbogen mit Radius {radius} mm ist {relation} der Fräserradius {tool_radius} mm.",
        "Inside arc of radius {radius} mm is {relation_en} the cutter radius {tool_radius} mm.",
    ),
    "PAL-E215": Entry(
        E,
        "Konturelement verschwindet oder kehrt sich um, wenn der Fräserradius {tool_radius} mm "
        "berücksichtigt wird.",
        "Contour element vanishes or reverses when the cutter radius {tool_radius} mm is applied.",
    ),
    "PAL-E216": Entry(
        E,
        "{address} darf bei aktiver Fräserradiuskorrektur (G41/G42) nicht geändert werden.",
        "{address} must not be changed while cutter radius compensation (G41/G42) is active.",
    ),
    "PAL-E217": Entry(
        E,
        "Die Kontur lässt sich an dieser Ecke nicht um den Fräserradius {tool_radius} mm "
        "versetzen (Zeile {first} und Zeile {second}).",
        "The contour cannot be offset by the cutter radius {tool_radius} mm at this corner "
        "(line {first} and line {second}).",
    ),
    "PAL-E218": Entry(
        E,
        "Nach {command} folgt kein Konturelement in der Ebene; die Korrektur kann nicht angefahren werden.",
        "No contour element in the plane follows {command}; compensation cannot be started.",
    ),
    "PAL-E219": Entry(
        E,
        "{command} muss zusammen mit {needed} im selben Satz stehen.",
        "{command} must be in the same block as {needed}.",
    ),
    "PAL-E220": Entry(
        E,
        "Fräserradiuskorrektur ohne Werkzeug: zuerst ein Werkzeug einwechseln (T).",
        "Cutter radius compensation without a tool: load a tool first (T).",
    ),
    "PAL-E221": Entry(
        E,
        "Der Startpunkt liegt im Pol; {command} braucht einen Radius größer 0.",
        "The start point lies on the pole; {command} needs a radius greater than 0.",
    ),
    "PAL-W222": Entry(
        W,
        "Die Fräserradiuskorrektur wird ohne Anfahrbewegung angewählt: mit {command} fährt das "
        "Werkzeug hier schon auf der Kontur, und der Fräser schneidet in die Kontur, während sich die "
        "Korrektur aufbaut. Fahren Sie zuerst einen Punkt vor der Kontur an (mindestens den "
        "Fräserradius {tool_radius_de} mm entfernt) und wählen Sie {command} mit der Bewegung dorthin "
        "an, oder fahren Sie mit G45/G47 an.",
        "Cutter radius compensation is selected without an approach move: with {command} the tool "
        "already travels on the contour here, and the cutter cuts into the contour while the "
        "compensation builds up. First move to a point in front of the contour (at least the cutter "
        "radius {tool_radius} mm away) and select {command} with the move there, or approach with "
        "G45/G47.",
    ),
    # --- technology -----------------------------------------------------------------------
    "PAL-E301": Entry(
        E,
        "Vorschubbewegung mit Vorschub F0: es ist kein Vorschub programmiert.",
        "Feed move with feed F0: no feed has been programmed.",
    ),
    "PAL-E302": Entry(
        E,
        "Vorschubbewegung bei stehender Spindel (M3 oder M4 fehlt).",
        "Feed move with the spindle stopped (M3 or M4 missing).",
    ),
    "PAL-E303": Entry(
        E, "Vorschubbewegung ohne Werkzeug in der Spindel.", "Feed move with no tool in the spindle."
    ),
    "PAL-E304": Entry(
        E, "Werkzeug T{tool} steht nicht in der Werkzeugtabelle.", "Tool T{tool} is not in the tool table."
    ),
    "PAL-E305": Entry(
        E,
        "Verweilzeit in Umdrehungen (O2) bei Drehzahl S0.",
        "Dwell in revolutions (O2) with spindle speed S0.",
    ),
    "PAL-E306": Entry(E, "Spindel M3/M4 mit Drehzahl S0.", "Spindle M3/M4 with speed S0."),
    "PAL-E307": Entry(
        E,
        "{address} ist nur im Satz mit M6 erlaubt (Maschine mit Werkzeugmagazin).",
        "{address} is only allowed in the block with M6 (machine with tool magazine).",
    ),
    "PAL-E308": Entry(E, "M6 ohne vorgewähltes Werkzeug T.", "M6 without a preselected tool T."),
    "PAL-E309": Entry(
        E,
        "Zoll-Maßangabe G70 wird nicht unterstützt; PAL arbeitet in Millimetern (G71).",
        "Inch dimensions G70 are not supported; PAL works in millimetres (G71).",
    ),
    "PAL-I301": Entry(
        I,
        "{what} auch in {count} weiteren Sätzen: Zeile {lines}.",
        "{what_en} also in {count} more blocks: line {lines}.",
    ),
    # --- simulation ------------------------------------------------------------------------
    "SIM-E001": Entry(
        E,
        "Eilgang ins Material: {volume} mm³ werden im Eilgang abgetragen (Kollision).",
        "Rapid move into the material: {volume} mm³ removed at rapid traverse (collision).",
    ),
    "SIM-E002": Entry(
        E,
        "T{tool} schneidet nicht über Mitte und taucht hier ins Material ein; zum Eintauchen "
        "einen über Mitte schneidenden Fräser (z. B. Langlochfräser) verwenden oder außerhalb "
        "des Werkstücks zustellen.",
        "T{tool} is not centre-cutting and plunges into the material here; use a centre-cutting "
        "tool (e.g. a slot drill) or feed in outside the workpiece.",
    ),
    "SIM-E003": Entry(
        E,
        "Schnitttiefe {depth} mm ist größer als die Schneidenlänge {length} mm von T{tool}: "
        "der Schaft berührt das Werkstück.",
        "Depth of cut {depth} mm exceeds the cutting length {length} mm of T{tool}: "
        "the shank touches the workpiece.",
    ),
    "SIM-E004": Entry(
        E,
        "Der Werkzeughalter berührt das Werkstück: T{tool} ragt {length} mm aus dem Halter, "
        "die Schnitttiefe ist {depth} mm.",
        "The tool holder touches the workpiece: T{tool} sticks out {length} mm, "
        "the depth of cut is {depth} mm.",
    ),
    "SIM-E005": Entry(
        E,
        "Das Werkzeug fährt bis Z{z} unter die Unterseite des Rohteils (Z{base}) in den Maschinentisch.",
        "The tool goes down to Z{z}, below the bottom of the stock (Z{base}), into the machine table.",
    ),
    "SIM-E006": Entry(
        E,
        "Zerspanung bei stehender Spindel: {volume} mm³ werden ohne Drehzahl abgetragen.",
        "Cutting with the spindle stopped: {volume} mm³ removed without spindle speed.",
    ),
    "SIM-E007": Entry(
        E,
        "Bewegung ohne Werkzeug ins Werkstück: die Spindel stößt an.",
        "Move into the workpiece with no tool: the spindle collides.",
    ),
    "SIM-E008": Entry(
        E,
        "Zerspanung mit Vorschub F0: {volume} mm³ werden ohne Vorschub abgetragen.",
        "Cutting with feed F0: {volume} mm³ removed without a feed.",
    ),
    "SIM-E009": Entry(
        E,
        "Werkzeug T{tool} steht nicht in der Werkzeugtabelle der Simulation; seine Bewegungen "
        "tragen nichts ab.",
        "Tool T{tool} is not in the simulation's tool table; its moves remove nothing.",
    ),
    "SIM-E010": Entry(
        E,
        "Simulation abgebrochen: mehr als {limit} Zellen-Aktualisierungen (Grenze); das Ergebnis "
        "ist ab hier unvollständig.",
        "Simulation stopped: more than {limit} cell updates (limit); the result is incomplete from here on.",
    ),
    # turning (core/sim/turning.py); SIM-E001, E006, E008 and E010 apply to turning as well
    "SIM-E011": Entry(
        E,
        "Der Halter von T{tool} berührt das Werkstück bei Z{z} (Ø{d} mm).",
        "The holder of T{tool} touches the workpiece at Z{z} (Ø{d} mm).",
    ),
    "SIM-E012": Entry(
        E,
        "T{tool} fährt bei Z{z} in die Spannbacken des Futters (gespannt bis Z{jaw}).",
        "T{tool} runs into the chuck jaws at Z{z} (clamped up to Z{jaw}).",
    ),
    "SIM-E013": Entry(
        E,
        "Schnitttiefe {depth} mm ist größer als die nutzbare Schneidenlänge {length} mm "
        "der Wendeschneidplatte von T{tool}.",
        "Depth of cut {depth} mm exceeds the usable cutting length {length} mm of the insert of T{tool}.",
    ),
    "SIM-E014": Entry(
        E,
        "T{tool} ({what}) zerspant gegen seine Schneidrichtung: ein Stechdrehmeißel schneidet "
        "nur radial, ein Gewindedrehmeißel nur längs in seiner Richtung.",
        "T{tool} ({what_en}) cuts against its direction: a grooving tool cuts only radially, a "
        "threading tool only along Z in its own direction.",
    ),
    "SIM-W001": Entry(
        W,
        "T{tool} hat in der Werkzeugtabelle Ø{actual} mm, die Aufgabe sieht Ø{expected} mm vor.",
        "T{tool} has Ø{actual} mm in the tool table, the exercise expects Ø{expected} mm.",
    ),
    "SIM-W002": Entry(
        W,
        "Rasterweite von {requested} mm auf {used} mm vergröbert: das Rohteil hätte sonst mehr "
        "als {limit} Zellen.",
        "Cell size coarsened from {requested} mm to {used} mm: the stock would otherwise have more "
        "than {limit} cells.",
    ),
    "SIM-W003": Entry(
        W,
        "Zu viele Simulationsmeldungen; weitere werden nicht angezeigt (höchstens {limit}).",
        "Too many simulation events; further ones are not shown (at most {limit}).",
    ),
    # --- program flow and transforms ------------------------------------------------------
    "PAL-E401": Entry(
        E, "Unterprogramm L{number} ist nicht vorhanden.", "Subprogram L{number} does not exist."
    ),
    "PAL-E402": Entry(
        E,
        "M17 (Unterprogrammende) steht nicht in einem Unterprogramm.",
        "M17 (end of subprogram) is not inside a subprogram.",
    ),
    "PAL-E403": Entry(
        E,
        "M30 (Programmende) in Unterprogramm L{number}; ein Unterprogramm endet mit M17.",
        "M30 (end of program) in subprogram L{number}; a subprogram ends with M17.",
    ),
    "PAL-E404": Entry(
        E,
        "Unterprogramm L{number} ruft sich selbst auf (Rekursion).",
        "Subprogram L{number} calls itself (recursion).",
    ),
    "PAL-E405": Entry(
        E,
        "Unterprogramme sind zu tief verschachtelt (höchstens {limit} Ebenen).",
        "Subprograms are nested too deeply (at most {limit} levels).",
    ),
    "PAL-E406": Entry(
        E,
        "Satznummer N{number} ist im Programm nicht vorhanden.",
        "Block number N{number} does not exist in the program.",
    ),
    "PAL-E407": Entry(
        E,
        "Der Endsatz N{end} steht vor dem Anfangssatz N{start}.",
        "The end block N{end} comes before the start block N{start}.",
    ),
    "PAL-E408": Entry(
        E,
        "{command} ist bei aktivem Spiegeln (G66) nicht erlaubt.",
        "{command} is not allowed while mirroring (G66) is active.",
    ),
    "PAL-E409": Entry(E, "Unterprogramm L{number} endet ohne M17.", "Subprogram L{number} ends without M17."),
    "PAL-E410": Entry(
        E,
        "Vergleich O{value} gibt es nicht (O1 =, O2 ≠, O3 >, O4 <).",
        "Comparison O{value} does not exist (O1 =, O2 ≠, O3 >, O4 <).",
    ),
    "PAL-E411": Entry(
        E,
        "G23 steht im eigenen Abschnitt N{start} bis N{end}: die Wiederholung würde sich ohne Ende selbst "
        "wiederholen; der Satz wird übersprungen.",
        "G23 lies inside its own section N{start} to N{end}: the repeat would repeat itself without end; the "
        "block is skipped.",
    ),
    # --- Beckhoff --------------------------------------------------------------------------
    "PAL-E501": Entry(
        E,
        "Das erste {command} braucht ein I-Wort ungleich 0 (Fasenbreite bzw. Radius); die "
        "Decodierung wird abgebrochen.",
        "The first {command} needs an I word other than 0 (chamfer width or radius); decoding stops.",
    ),
    # --- TRAUB TX 8 D turning: blocks, technology, tools (TX-x1xx) ---------------------------
    "TX-E101": Entry(
        E,
        "Die erste Bewegung nach dem Werkzeugaufruf muss absolut (X, Z) programmiert sein; "
        "{address} ist ein Kettenmaß.",
        "The first motion after a tool call must be absolute (X, Z); {address} is incremental.",
    ),
    "TX-E102": Entry(
        E,
        "Bewegung ohne Werkzeugaufruf: {command} hat die Werkzeugdaten abgewählt, vor der "
        "nächsten Bewegung muss ein T-Wort stehen.",
        "Motion without a tool call: {command} deselected the tool data, a T word must come "
        "before the next motion.",
    ),
    "TX-E103": Entry(
        E,
        "{command} ist bei eingeschalteter Schneidenradiuskorrektur ({srk}) nicht erlaubt; "
        "vorher G40 programmieren.",
        "{command} is not allowed while nose-radius compensation ({srk}) is on; program G40 first.",
    ),
    "TX-E104": Entry(
        E,
        "Höchstens 3 M-Wörter je Satz ({count} programmiert).",
        "At most 3 M words per block ({count} programmed).",
    ),
    "TX-E105": Entry(
        E, "{code} muss allein in einem eigenen Satz stehen.", "{code} must stand alone in its block."
    ),
    "TX-E106": Entry(
        E,
        "{code} ist nur zusammen mit einem Werkzeugaufruf T im selben Satz erlaubt.",
        "{code} is only allowed together with a tool call T in the same block.",
    ),
    "TX-E107": Entry(
        E,
        "B06 (Drehzahl des angetriebenen Werkzeugs) erst nach M21/M22 und M23/M24 "
        "(vorher oder im selben Satz).",
        "B06 (driven-tool speed) needs M21/M22 and M23/M24 before it or in the same block.",
    ),
    "TX-E108": Entry(
        E,
        "Verweilzeit {value} s liegt außerhalb von 0,001 bis 999,99 s.",
        "Dwell time {value} s is outside 0.001 to 999.99 s.",
    ),
    "TX-E109": Entry(
        E,
        "M17 (C-Achsen-Kopplung) erst nach M05: die Hauptspindel dreht noch.",
        "M17 (C-axis coupling) needs M05 first: the main spindle is still turning.",
    ),
    "TX-E110": Entry(
        E,
        "Parameter L{number} gibt es nicht (L1…L48, L101…L148).",
        "There is no parameter L{number} (L1…L48, L101…L148).",
    ),
    "TX-E111": Entry(
        E,
        "Werkzeugplatz {station} gibt es nicht (T0101…T1616 erste Schneide, T2121…T3636 zweite Schneide).",
        "There is no turret station {station} (T0101…T1616 first edge, T2121…T3636 second edge).",
    ),
    "TX-E112": Entry(
        E,
        "G97 V… braucht den Durchmesser X (größer als 0), für den die Drehzahl berechnet wird.",
        "G97 V… needs the diameter X (greater than 0) to compute the speed for.",
    ),
    "TX-E113": Entry(
        E,
        "Bei eingeschalteter Schneidenradiuskorrektur müssen von 5 aufeinanderfolgenden Sätzen "
        "mindestens 3 Verfahrsätze sein; hier sind es {count}.",
        "With nose-radius compensation on, at least 3 of every 5 consecutive blocks must be motion "
        "blocks; here there are {count}.",
    ),
    "TX-W101": Entry(
        W,
        "Parameter L{number} wird gelesen, bevor ihm ein Wert zugewiesen wurde (gilt als 0).",
        "Parameter L{number} is read before it was assigned a value (taken as 0).",
    ),
    "TX-W102": Entry(
        W,
        "{address} hat bei G92 keine festgelegte Bedeutung und wird nicht beachtet.",
        "{address} has no defined meaning with G92 and is ignored.",
    ),
    "TX-W103": Entry(
        W,
        "Programmnummer O{number}: Unterprogramme haben üblicherweise Nummern ab 8000 (Makros O9801…O9899).",
        "Program number O{number}: subprograms usually have numbers from 8000 (macros O9801…O9899).",
    ),
    "TX-W104": Entry(
        W,
        "G09 (Genauhalt) mit Übergangselement {address}: das Übergangselement hebt den Genauhalt auf.",
        "G09 (exact stop) with the transition element {address}: the transition cancels the exact stop.",
    ),
    "TX-W105": Entry(
        W,
        "Durchmesser 0 bei G96: die Drehzahl ist nur durch {limit} begrenzt (G92 S… programmieren).",
        "Diameter 0 under G96: the speed is limited only by {limit} (program G92 S…).",
    ),
    # --- TRAUB TX 8 D turning: contour trains and nose-radius compensation (TX-x2xx) ------------
    "TX-E201": Entry(E, "Geometriezug ohne Lösung: {reason}.", "Contour train has no solution: {reason_en}."),
    "TX-E202": Entry(
        E,
        "Kreisbogen-Radius R{radius} ist zu klein: der halbe Abstand von Start- und Endpunkt "
        "beträgt {chord} mm.",
        "Arc radius R{radius} is too small: half the distance from start to end point is {chord} mm.",
    ),
    "TX-E203": Entry(
        E,
        "Kreisbogen mit R überstreicht 180° oder mehr; dafür den Mittelpunkt mit P, Q oder I, K angeben.",
        "Arc with R sweeps 180° or more; give the centre with P, Q or I, K instead.",
    ),
    "TX-E204": Entry(
        E,
        "Kreisbogen ohne Radius R und ohne Mittelpunkt (P, Q oder I, K).",
        "Arc without radius R and without a centre (P, Q or I, K).",
    ),
    "TX-E205": Entry(
        E,
        "Kreisendpunktfehler: Start- und Endpunkt sind {start_radius} mm und {end_radius} mm vom "
        "Mittelpunkt entfernt (Differenz {difference} mm).",
        "Arc end point error: start and end point are {start_radius} mm and {end_radius} mm from the "
        "centre (difference {difference} mm).",
    ),
    "TX-E206": Entry(
        E,
        "Auf einen unbekannten Punkt muss im nächsten Satz ein bekannter Punkt X, Z (bei einer "
        "Geraden mit Winkel A) folgen.",
        "An unknown point must be followed in the next block by a known point X, Z (with angle A for "
        "a line).",
    ),
    "TX-E207": Entry(
        E,
        "Gerade und Kreisbogen schneiden sich zweimal: H0 (näherer Schnittpunkt) oder H1 angeben.",
        "Line and arc intersect twice: give H0 (the nearer intersection) or H1.",
    ),
    "TX-E208": Entry(
        E,
        "Kreisbogen im Geometriezug braucht den Radius R (tangentialer Übergang) oder den "
        "Mittelpunkt P, Q; I, K bezieht sich auf einen unbekannten Startpunkt.",
        "An arc in a contour train needs radius R (tangential transition) or centre P, Q; I, K refer "
        "to an unknown start point.",
    ),
    "TX-E209": Entry(
        E,
        "Kreisbogen – Kreisbogen: die Bögen müssen gegenläufig sein (G2/G3) und einer braucht den "
        "Mittelpunkt P, Q.",
        "Arc – arc: the arcs must turn in opposite senses (G2/G3) and one needs its centre P, Q.",
    ),
    "TX-E210": Entry(
        E,
        "Nach dem Übergangselement {element} muss ein G1-, G2- oder G3-Satz folgen (Richtungserkennung).",
        "The transition element {element} must be followed by a G1, G2 or G3 block (direction).",
    ),
    "TX-E211": Entry(
        E,
        "Übergangselement {element} passt nicht zwischen diesen Satz und Zeile {second}: {reason}.",
        "Transition element {element} does not fit between this block and line {second}: {reason_en}.",
    ),
    "TX-E212": Entry(
        E,
        "G46 braucht die Schneidenlage (Quadrant P1 bis P4) des Werkzeugs aus den Einrichtedaten "
        "(P{quadrant}).",
        "G46 needs the tool's cutting-edge position (quadrant P1 to P4) from the set-up data (P{quadrant}).",
    ),
    "TX-E213": Entry(
        E,
        "Der erste Verfahrsatz nach {command} muss eine Gerade (G0/G1) sein, kein Kreisbogen.",
        "The first motion after {command} must be a line (G0/G1), not an arc.",
    ),
    "TX-E214": Entry(
        E,
        "Innenbogen mit Radius {radius} mm ist kleiner als der Schneidenradius {nose} mm.",
        "Inside arc of radius {radius} mm is smaller than the nose radius {nose} mm.",
    ),
    "TX-E215": Entry(
        E,
        "Die Kontur lässt sich an dieser Ecke (bis Zeile {second}) nicht um den Schneidenradius "
        "{nose} mm versetzen.",
        "The contour cannot be offset by the nose radius {nose} mm at this corner (to line {second}).",
    ),
    "TX-W216": Entry(
        W,
        "A{angle} im Eilgangsatz vor G40 weicht von der Richtung {direction}° des letzten Konturelements ab.",
        "A{angle} in the rapid block before G40 differs from the direction {direction}° of the last "
        "contour element.",
    ),
    "TX-W217": Entry(
        W,
        "Der letzte Vorschubsatz vor dem Eilgang endet {length} mm zu früh (Vektor zur "
        "Eilgangrichtung, Zeile {second}); im G0 die Richtung A des letzten Elements angeben.",
        "The last feed block before the rapid ends {length} mm short (vector towards the rapid, "
        "line {second}); give the direction A of the last element in the G0.",
    ),
    "TX-W218": Entry(
        W,
        "G40 direkt nach einem Vorschubsatz: dieser Satz zeigt Abwahlverhalten, die Kontur wird "
        "verfälscht; vor G40 einen G0 mit A programmieren.",
        "G40 straight after a feed block: that block deselects, the contour is falsified; program a "
        "G0 with A before G40.",
    ),
    "TX-E219": Entry(
        E,
        "Konturschutz: die erste Vorschubbewegung nach der Anwahl ist {length} mm lang, kürzer als "
        "der Schneidenradius {nose} mm.",
        "Contour protection: the first feed move after selection is {length} mm long, shorter than "
        "the nose radius {nose} mm.",
    ),
    "TX-W220": Entry(
        W,
        "Satzausblendung: dieser Satz lässt sich mit dem Schneidenradius {nose} mm nicht ausführen.",
        "Block suppression: this block cannot be machined with the nose radius {nose} mm.",
    ),
    "TX-E221": Entry(
        E,
        "Unmittelbar vor der Abwahl der Schneidenradiuskorrektur darf keine Satzausblendung anstehen.",
        "No block suppression may be pending immediately before nose-radius compensation is deselected.",
    ),
    "TX-E222": Entry(
        E,
        "Vor der Abwahl muss der Satz nach dem Übergangselement {element} mindestens {need} mm "
        "verfahren (Übergangselement + Schneidenradius + 0,01 mm), er verfährt {length} mm.",
        "Before deselection the block after the transition element {element} must travel at least "
        "{need} mm (element + nose radius + 0.01 mm); it travels {length} mm.",
    ),
    "TX-E223": Entry(
        E,
        "Der Verfahrweg nach dem Übergangselement {element} ist {length} mm, mindestens {need} mm "
        "nötig (W min = D/R + 0,1 + Schneidenradius).",
        "The travel after the transition element {element} is {length} mm, at least {need} mm is "
        "needed (W min = D/R + 0.1 + nose radius).",
    ),
    "TX-W106": Entry(W, "Vorschubbewegung ohne Werkzeugaufruf T.", "Feed motion without a tool call T."),
    "TX-W107": Entry(
        W,
        "L{number} erhält erst nach dem Aufruf von {program} einen neuen Wert: das "
        "Unterprogramm hat mit dem alten gerechnet (Werte vor dem Aufruf zuweisen).",
        "L{number} gets its new value only after the call of {program}: the subprogram used the "
        "old one (assign values before the call).",
    ),
    "TX-E224": Entry(
        E,
        "Abwahl in X-Richtung: der letzte Verfahrweg ({length} mm) muss mindestens 2 × "
        "Schneidenradius ({need} mm) betragen.",
        "Deselection in X: the last travel ({length} mm) must be at least 2 × the nose radius ({need} mm).",
    ),
    "TX-W225": Entry(
        W,
        "Falscher Schneidbereich: diese Bewegungsrichtung passt nicht zur Schneidenlage P{quadrant} "
        "bei G46; die Bearbeitungsrichtung lässt sich nur nach G40 ändern (oder G41/G42 ohne "
        "Überwachung).",
        "Wrong cutting range: this direction of travel does not suit the cutting-edge position "
        "P{quadrant} under G46; the machining direction can only change after G40 (or G41/G42 "
        "without monitoring).",
    ),
    "TX-W108": Entry(
        W,
        "{tool} im G00-Satz: während G00 soll T nicht auf einen anderen Revolverplatz schalten "
        "(nur auf die zweite Schneide, {current} ± 20); den Werkzeugaufruf in einen eigenen Satz.",
        "{tool} in a G00 block: during G00, T should not index to another turret station (only to "
        "the second edge, {current} ± 20); put the tool call in a block of its own.",
    ),
    "TX-E226": Entry(
        E,
        "{code} darf nicht {where} stehen: die Schneidenradiuskompensation wird am Anfang oder "
        "Ende einer Kontur an- und abgewählt.",
        "{code} must not stand {where_en}: nose-radius compensation is switched on and off at the "
        "start or end of a contour.",
    ),
    "TX-W227": Entry(
        W,
        "A{angle} passt nicht zur Geraden vom Startpunkt zum Zielpunkt X, Z (Richtung "
        "{direction}°); es gilt der Zielpunkt.",
        "A{angle} does not match the line from the start point to the end point X, Z (direction "
        "{direction}°); the end point is used.",
    ),
    # --- TRAUB TX 8 D turning: programs and subprograms (TX-x3xx) ------------------------------
    "TX-E301": Entry(
        E,
        "Programm O{number} gibt es weder in dieser Datei noch in der Bibliothek.",
        "Program O{number} is neither in this file nor in the library.",
    ),
    "TX-E302": Entry(
        E,
        "Unterprogramme sind höchstens {limit} Ebenen tief schachtelbar.",
        "Subprograms can be nested at most {limit} levels deep.",
    ),
    "TX-E303": Entry(
        E,
        "Programm O{number} ruft sich selbst auf (Rekursion).",
        "Program O{number} calls itself (recursion).",
    ),
    "TX-E304": Entry(
        E,
        "Satznummer N{number} gibt es in {program} nicht.",
        "Block number N{number} does not exist in {program}.",
    ),
    "TX-E305": Entry(
        E,
        "Abschnitt P{start} bis Q{end}: N{end} steht vor N{start}.",
        "Section P{start} to Q{end}: N{end} comes before N{start}.",
    ),
    "TX-E306": Entry(
        E,
        "M30 in einem Unterprogramm (O{number}); Unterprogramme enden mit M99.",
        "M30 in a subprogram (O{number}); subprograms end with M99.",
    ),
    "TX-W301": Entry(
        W,
        "M99 ohne Unterprogrammaufruf: das Programm endet hier (Hauptprogramme enden mit M30).",
        "M99 without a subprogram call: the program ends here (main programs end with M30).",
    ),
    "TX-W302": Entry(W, "Unterprogramm O{number} endet ohne M99.", "Subprogram O{number} ends without M99."),
    # --- TRAUB TX 8 D turning: cycles (TX-x4xx) ------------------------------------------------
    "TX-E401": Entry(
        E,
        "{code}: der Startpunkt ist nicht bekannt; vor dem Zyklus einen Punkt mit X und Z anfahren.",
        "{code}: the start point is not known; approach a point with X and Z before the cycle.",
    ),
    "TX-E402": Entry(
        E,
        "{code}: {address}{value} muss größer als 0 sein.",
        "{code}: {address}{value} must be greater than 0.",
    ),
    "TX-W403": Entry(
        W,
        "{code}: Schnitttiefe D{depth} ist größer als das ganze Aufmaß ({stock} mm); es wird in einem "
        "Schnitt geschruppt.",
        "{code}: depth of cut D{depth} is larger than the whole stock ({stock} mm); one cut roughs it.",
    ),
    "TX-E404": Entry(
        E,
        "{code}: die Kontur läuft in Zeile {second} gegen die Schnittrichtung zurück (nicht "
        "monoton); so lässt sie sich nicht schruppen.",
        "{code}: the contour runs back against the cutting direction in line {second} (not "
        "monotone); it cannot be roughed this way.",
    ),
    "TX-W405": Entry(
        W,
        "{code}: die Kontur endet in Zeile {second} außerhalb des Rohteils, das der Startpunkt begrenzt.",
        "{code}: the contour ends in line {second} outside the blank bounded by the start point.",
    ),
    "TX-E406": Entry(
        E,
        "{code} ergäbe {count} Schnitte, mehr als die erlaubten {limit}; der Zyklus wird nicht ausgeführt.",
        "{code} would make {count} cuts, more than the allowed {limit}; the cycle is not executed.",
    ),
    "TX-E407": Entry(
        E,
        "{code}: die Gewindesteigung fehlt (F mit 3 oder E mit 5 Nachkommastellen).",
        "{code}: the thread pitch is missing (F with 3 or E with 5 decimals).",
    ),
    "TX-E408": Entry(
        E,
        "{code}: die Gewindetiefe K{depth} passt nicht zum Startdurchmesser X{diameter}: der "
        "Startpunkt liegt im Gewindeprofil.",
        "{code}: the thread depth K{depth} does not suit the start diameter X{diameter}: the start "
        "point lies inside the thread profile.",
    ),
    "TX-E409": Entry(
        E,
        "{code}: keine Fertigkontur – P und Q (erster und letzter Satz) oder A (Unterprogramm) mit "
        "Verfahrsätzen angeben.",
        "{code}: no finished contour – give P and Q (first and last block) or A (subprogram) with "
        "motion blocks.",
    ),
    "TX-E410": Entry(
        E,
        "{code}: die Fertigkontur enthält einen Fehler (Zeile {second}).",
        "{code}: the finished contour contains an error (line {second}).",
    ),
    "TX-E411": Entry(
        E,
        "{code} als Bohrzyklus: {address} ist hier nicht erlaubt.",
        "{code} as a drilling cycle: {address} is not allowed here.",
    ),
    "TX-E412": Entry(
        E,
        "{code}: die Wirkung von {address} ist in der Anleitung nicht festgelegt und wird noch "
        "nicht unterstützt; der Zyklus wird nicht ausgeführt.",
        "{code}: the effect of {address} is not fixed by the manual and is not supported yet; the "
        "cycle is not executed.",
    ),
    "TX-W413": Entry(
        W,
        "{code}: nichts zu zerspanen – der Startpunkt liegt schon auf der Kontur.",
        "{code}: nothing to cut – the start point already lies on the contour.",
    ),
    "TX-E414": Entry(
        E,
        "G81 wiederholt nur einen unmittelbar vorangehenden G77-, G78- oder G79-Schnitt.",
        "G81 repeats only a G77, G78 or G79 pass right before it.",
    ),
    "TX-E416": Entry(E, "Kegelwinkel J{value} außerhalb von ±45°.", "Taper angle J{value} outside ±45°."),
    "TX-W418": Entry(
        W,
        "G70: die Wirkung des Anstellwinkels J auf die Schnitte legt die Anleitung nicht fest (die "
        "Beispielseite fehlt) und wird noch nicht unterstützt; geschruppt wird wie mit G71 mit "
        "voller Schnitttiefe D.",
        "G70: the manual does not fix how the setting angle J changes the cuts (its example page is "
        "missing); it is not supported yet, the cycle roughs like G71 with the full depth D.",
    ),
    "TX-W419": Entry(
        W,
        "G70 schneidet immer mit der vollen Tiefe D{depth}: {rest} mm bleiben zusätzlich zum Aufmaß "
        "stehen (D so wählen, dass es aufgeht).",
        "G70 always cuts the full depth D{depth}: {rest} mm stay on top of the allowance (choose D so "
        "that it divides the stock).",
    ),
    "TX-E420": Entry(
        E,
        "{code}: die Schruppzyklen dieses Programms zusammen sind zu umfangreich; dieser und "
        "weitere werden nicht ausgeführt.",
        "{code}: the roughing cycles of this program together are too large; this one and further "
        "ones are not executed.",
    ),
    "TX-W421": Entry(
        W,
        "{code} mit M35: der kegelige Gewindeauslauf (Länge und Winkel aus den Einrichtedaten) wird "
        "nicht dargestellt; das Gewinde endet am programmierten Endpunkt.",
        "{code} with M35: the tapered thread run-out (length and angle from the set-up data) is not "
        "shown; the thread ends at the programmed end point.",
    ),
    "TX-E417": Entry(
        E,
        "G82 Gewindebohren braucht die drehende Hauptspindel (G97 S…, M3/M4); mit angetriebenen "
        "Werkzeugen geht es nicht.",
        "G82 tapping needs the main spindle turning (G97 S…, M3/M4); it does not work with driven tools.",
    ),
    # --- DIN/ISO dialects: SINUMERIK 808D ISO and Beckhoff TwinCAT (DIN-, ISO-, BK-) -------------------------
    "DIN-E203": Entry(
        E,
        "Kreisbogen ist unterbestimmt: {command} braucht einen Mittelpunkt ({centre}) oder einen Radius R.",
        "Arc is underdetermined: {command} needs a centre ({centre}) or a radius R.",
    ),
    "BK-W202": Entry(
        W,
        "Mittelpunktskorrektur (G165): der Kreismittelpunkt wird um {shift} mm verschoben, damit Start- "
        "und Endpunkt auf dem Kreis liegen (programmiert: Radius {r_start} mm am Start, {r_end} mm am "
        "Ende).",
        "Centre point correction (G165): the circle centre is moved by {shift} mm so that the start and "
        "end point lie on the circle (as programmed: radius {r_start} mm at the start, {r_end} mm at the "
        "end).",
    ),
    "BK-E203": Entry(
        E,
        "Kreisendpunktfehler: der Kreismittelpunkt müsste um {shift} mm verschoben werden, erlaubt sind "
        "{limit} mm (Mittelpunktskorrektur G165; programmiert: Radius {r_start} mm am Start, {r_end} mm "
        "am Ende).",
        "Circle end point error: the circle centre would have to move by {shift} mm, {limit} mm are "
        "allowed (centre point correction G165; as programmed: radius {r_start} mm at the start, {r_end} "
        "mm at the end).",
    ),
    "BK-E502": Entry(
        E,
        "{element} in Zeile {line} steht vor dem ersten Verfahrsatz: eine Fase oder Rundung wird "
        "zwischen zwei Verfahrsätzen eingefügt und braucht einen davor und einen danach.",
        "{element} in line {line} comes before the first motion block: a chamfer or rounding is inserted "
        "between two motion blocks and needs one before it and one after it.",
    ),
    "BK-E503": Entry(
        E,
        "Nach {element} in Zeile {line} folgt kein Verfahrsatz (G00, G01, G02, G03) in der Ebene mit "
        "derselben Werkzeugradiuskorrektur; die Fase bzw. Rundung kann nicht eingefügt werden.",
        "{element} in line {line} is not followed by a motion block (G00, G01, G02, G03) in the plane "
        "with the same tool radius compensation; the chamfer or rounding cannot be inserted.",
    ),
    "BK-E504": Entry(
        E,
        "Zwei Fasen oder Rundungen ohne Verfahrsatz dazwischen: {element} in Zeile {line} folgt auf "
        "{first} in Zeile {first_line}.",
        "Two chamfers or roundings without a motion block between them: {element} in line {line} follows "
        "{first} in line {first_line}.",
    ),
    "ISO-E301": Entry(
        E,
        "Programm O{number} gibt es weder in dieser Datei noch in der Bibliothek.",
        "Program O{number} is neither in this file nor in the library.",
    ),
    "ISO-E302": Entry(
        E,
        "Unterprogramme sind höchstens {limit} Ebenen tief schachtelbar.",
        "Subprograms can be nested at most {limit} levels deep.",
    ),
    "ISO-E303": Entry(
        E,
        "Programm O{number} ruft sich selbst auf (Rekursion).",
        "Program O{number} calls itself (recursion).",
    ),
    "ISO-E304": Entry(
        E,
        "M30 (Programmende) im Unterprogramm O{number}; ein Unterprogramm endet mit M99.",
        "M30 (end of program) in subprogram O{number}; a subprogram ends with M99.",
    ),
    "ISO-E305": Entry(E, "Unterprogramm O{number} endet ohne M99.", "Subprogram O{number} ends without M99."),
    "ISO-W306": Entry(
        W,
        "M99 im Hauptprogramm: die Steuerung springt an den Programmanfang zurück und wiederholt das "
        "Programm ohne Ende; die Simulation endet hier (Hauptprogramme enden mit M30).",
        "M99 in the main program: the control jumps back to the program start and repeats the program "
        "endlessly; the simulation ends here (main programs end with M30).",
    ),
    "ISO-E307": Entry(
        E,
        "Die Programmnummer O{number} steht allein in ihrem Satz; {words} wird nicht ausgeführt.",
        "The program number O{number} stands alone in its block; {words} is not executed.",
    ),
    "ISO-E401": Entry(
        E,
        "{code}: {what} {address} fehlt; sie muss im ersten Bohrsatz nach der Anwahl des Zyklus stehen.",
        "{code}: {what_en} {address} is missing; it must be in the first drilling block after the cycle "
        "is selected.",
    ),
    "ISO-E402": Entry(
        E,
        "{code}: der Bohrungsgrund Z{bottom} liegt {relation} der R-Ebene Z{r}.",
        "{code}: the bottom of the hole Z{bottom} lies {relation_en} the R plane Z{r}.",
    ),
    "ISO-E404": Entry(
        E,
        "{code} ergäbe {count} Bohrschritte, mehr als die erlaubten {limit}; der Zyklus wird nicht "
        "ausgeführt.",
        "{code} would make {count} drilling steps, more than the allowed {limit}; the cycle is not executed.",
    ),
    "ISO-W405": Entry(
        W,
        "{code} bei eingeschalteter Fräserradiuskorrektur ({compensation}): die Bohrung wird ohne "
        "Korrektur gefahren; vor Bohrzyklen G40 programmieren.",
        "{code} with cutter radius compensation on ({compensation}): the hole is drilled without "
        "compensation; program G40 before drilling cycles.",
    ),
    "ISO-I406": Entry(
        I,
        "G88: an der Steuerung fährt der Bediener das Werkzeug im Bohrungsgrund von Hand zurück; "
        "gezeigt wird ein Eilgang bei stehender Spindel zur Rückzugsebene.",
        "G88: on the control the operator retracts the tool from the bottom of the hole by hand; shown "
        "is a rapid with the spindle stopped to the return level.",
    ),
    # --- PAL milling cycles G72–G87 and their calls G76–G79 (PAL-x6xx; reconstructed, docs/pal-milling.md) ------
    "PAL-E601": Entry(
        E,
        "{command}: es ist kein Bearbeitungszyklus definiert; zuerst einen Zyklus (G72–G75, "
        "G81–G87) programmieren, dann aufrufen.",
        "{command}: no machining cycle is defined; program a cycle (G72–G75, G81–G87) before the call.",
    ),
    "PAL-E602": Entry(
        E,
        "{command}: das Werkzeug T{tool} (Ø{tool_d} mm) ist zu groß für {what}{size} mm.",
        "{command}: tool T{tool} (Ø{tool_d_en} mm) is too large for {what_en}{size_en} mm.",
    ),
    "PAL-E603": Entry(
        E,
        "{command}: der Grund (Z {bottom} mm) liegt nicht unter der Oberfläche (Z {surface} mm); "
        "ZI muss negativ sein, ZA unter der Oberfläche liegen.",
        "{command}: the bottom (Z {bottom_en} mm) is not below the surface (Z {surface_en} mm); ZI must "
        "be negative, ZA below the surface.",
    ),
    "PAL-E604": Entry(
        E,
        "Aufmaß {address} darf nicht negativ sein ({raw}).",
        "Allowance {address} must not be negative ({raw}).",
    ),
    "PAL-E605": Entry(
        E,
        "{command}: das Aufmaß {address} ({value} mm) ist zu groß für {what} ({limit} mm).",
        "{command}: the allowance {address} ({value_en} mm) is too large for {what_en} ({limit_en} mm).",
    ),
    "PAL-W606": Entry(
        W,
        "G84 ohne laufende Spindel: vor dem Gewindebohren die Spindel mit M3 oder M4 und einer "
        "Drehzahl S einschalten.",
        "G84 without a running spindle: switch the spindle on with M3 or M4 and a speed S before tapping.",
    ),
    "PAL-W607": Entry(
        W,
        "G84: die Steigung F{pitch} mm ist keine Regel- oder Feingewindesteigung eines metrischen "
        "ISO-Gewindes (z. B. M6 × 1, M8 × 1,25, M10 × 1,5).",
        "G84: the pitch F{pitch} mm is no standard coarse or fine pitch of an ISO metric thread "
        "(e.g. M6 × 1, M8 × 1.25, M10 × 1.5).",
    ),
    "PAL-E608": Entry(
        E,
        "{command} bei eingeschalteter Fräserradiuskorrektur ({compensation}): Zyklen werden mit "
        "G40 definiert und aufgerufen.",
        "{command} with cutter radius compensation on ({compensation}): cycles are defined and called "
        "under G40.",
    ),
    "PAL-W609": Entry(
        W,
        "Eckenradius RN{raw} ist kleiner als der Werkzeugradius ({radius} mm); die Tasche erhält "
        "den Werkzeugradius als Eckenradius.",
        "Corner radius RN{raw} is smaller than the tool radius ({radius_en} mm); the pocket gets the "
        "tool radius as its corner radius.",
    ),
    "PAL-E610": Entry(
        E,
        "{command} ergäbe {count} Bahnen, mehr als die erlaubten {limit}; der Zyklus wird nicht ausgeführt.",
        "{command} would make {count} passes, more than the allowed {limit}; the cycle is not executed.",
    ),
    "PAL-E611": Entry(
        E,
        "{address}{raw} ist bei {command} nicht zulässig; erlaubt: {allowed}.",
        "{address}{raw} is not allowed with {command}; allowed: {allowed_en}.",
    ),
    "PAL-E612": Entry(
        E,
        "{command} lässt sich so nicht ausführen: {reason}.",
        "{command} cannot be executed like this: {reason_en}.",
    ),
    # --- not supported yet ----------------------------------------------------------------
    "PAL-E901": Entry(
        E, "{feature} wird noch nicht unterstützt; {effect}", "{feature_en} is not supported yet; {effect_en}"
    ),
    "PAL-W901": Entry(
        W, "{feature} wird noch nicht unterstützt; {effect}", "{feature_en} is not supported yet; {effect_en}"
    ),
}


@dataclass(frozen=True, slots=True)
class Diagnostic:
    """One finding about the program: a stable code, a severity, a source span and its texts.

    `source` names the library subprogram (e.g. "L200") the span points into; None: the program file.
    """

    code: str
    severity: Severity
    span: Span
    message: str
    message_en: str
    params: dict[str, Any] = field(default_factory=dict, compare=False)
    source: str | None = None
    follows_from: int | None = None  # a follow-up error: the line of the error it follows from

    def to_json(self) -> dict[str, Any]:
        s = self.span
        data: dict[str, Any] = {
            "code": self.code,
            "severity": self.severity.value,
            "line": s.line,
            "column": s.column,
            "end_line": s.end_line,
            "end_column": s.end_column,
            "message": self.message,
            "message_en": self.message_en,
        }
        if self.source is not None:
            data["source"] = self.source
        if self.follows_from is not None:
            data["follows_from"] = self.follows_from
        shared = catalogue_code(self.code)
        if shared != self.code:
            data["same_as"] = shared  # the shared check's code in the catalogue (docs/diagnostics.md)
        return data


def diag(code: str, span: Span, severity: Severity | None = None, /, **params: Any) -> Diagnostic:
    """Build the diagnostic `code` of the catalogue with its texts filled from `params`."""
    entry = CATALOGUE[code]
    texts = {k: _fmt(v) for k, v in params.items()}
    return Diagnostic(
        code=code,
        severity=severity or entry.severity,
        span=span,
        message=entry.de.format(**texts),
        message_en=entry.en.format(**texts),
        params=params,
    )


SHARED_PREFIX = "PAL"  # the catalogue's prefix of the checks every dialect shares
SHARED_OFFSET = 1000  # another dialect reports a shared check with its number + 1000 (TX-E1301 = PAL-E301)


def in_dialect(d: Diagnostic, prefix: str) -> Diagnostic:
    """`d` as a program of the dialect with code prefix `prefix` (TX, ISO, BK) reports it: a shared PAL- check
    under the dialect's own prefix; every other code (the dialect's own, SIM-, DIN-) as it is."""
    if prefix == SHARED_PREFIX or not d.code.startswith(SHARED_PREFIX + "-"):
        return d
    letter, number = d.code[len(SHARED_PREFIX) + 1], int(d.code[len(SHARED_PREFIX) + 2 :])
    return dataclasses.replace(d, code=f"{prefix}-{letter}{number + SHARED_OFFSET}")


def catalogue_code(code: str) -> str:
    """The catalogue's code of a reported one: TX-E1301 → PAL-E301; every catalogue code stays itself."""
    prefix, _, rest = code.partition("-")
    if prefix == SHARED_PREFIX or len(rest) < 5 or not rest[1:].isdigit() or int(rest[1:]) < SHARED_OFFSET:
        return code
    return f"{SHARED_PREFIX}-{rest[0]}{int(rest[1:]) - SHARED_OFFSET:03d}"


def _fmt(value: Any) -> str:
    """Numbers as a machinist writes them: no trailing zeros, point as decimal separator."""
    if isinstance(value, float):
        text = f"{value:.4f}".rstrip("0").rstrip(".")
        return "0" if text == "-0" else text
    return str(value)


# Follow-up errors (Folgefehler): what a diagnostic depends on that an earlier error can leave wrong. A block
# dropped because of an error (a syntax error, or an error that stops its execution) leaves these unknown;
# a later diagnostic of this code that depends on them says "Folgefehler von Zeile N" and carries
# follows_from: N, until a block that runs sets them again. Codes not listed are always reported as they are.
FOLLOW_UPS: dict[str, tuple[str, str, str]] = {
    # code: (what it depends on, Deutsch, English)
    **{
        code: ("position", "der Startpunkt (X, Y, Z)", "the start point (X, Y, Z)")
        for code in (
            "PAL-E201",
            "PAL-E202",
            "PAL-E206",
            "PAL-E208",
            "PAL-E210",
            "PAL-E214",
            "PAL-E215",
            "PAL-E217",
            "PAL-E221",
        )
    },
    "PAL-E301": ("feed", "der Vorschub F", "the feed F"),
    "PAL-E302": (
        "spindle",
        "das Einschalten der Spindel (M3, M4, M13, M14)",
        "the spindle start (M3, M4, M13, M14)",
    ),
    "PAL-E305": ("speed", "die Drehzahl S", "the spindle speed S"),
    "PAL-E306": ("speed", "die Drehzahl S", "the spindle speed S"),
    "PAL-E303": ("tool", "der Werkzeugwechsel (T, M6)", "the tool change (T, M6)"),
    "PAL-E220": ("tool", "der Werkzeugwechsel (T, M6)", "the tool change (T, M6)"),
    "PAL-E308": ("tool", "der Werkzeugwechsel (T, M6)", "the tool change (T, M6)"),
    "PAL-E406": (
        "number",
        "die Satznummer N des verworfenen Satzes",
        "the block number N of the dropped block",
    ),
    "PAL-E601": (
        "cycle",
        "die Zyklusdefinition (G72–G75, G81–G87)",
        "the cycle definition (G72–G75, G81–G87)",
    ),
}
# the same finding on many feed moves (no feed, spindle stopped, no tool): the first stays, the later ones
# become one PAL-I301 note that follows from it
REPEATED = frozenset({"PAL-E301", "PAL-E302", "PAL-E303"})


def as_follow_up(d: Diagnostic, line: int) -> Diagnostic:
    """`d` named as a follow-up of the error in `line`: "… (Folgefehler von Zeile 7)." """

    def add(text: str, note: str) -> str:
        return f"{text[:-1]} ({note})." if text.endswith(".") else f"{text} ({note})"

    return dataclasses.replace(
        d,
        follows_from=line,
        message=add(d.message, f"Folgefehler von Zeile {line}"),
        message_en=add(d.message_en, f"follows from the error in line {line}"),
    )


def has_errors(diagnostics: list[Diagnostic]) -> bool:
    return any(d.severity is Severity.ERROR for d in diagnostics)


# What a code checks, where a row of the table cannot say it (docs/diagnostics.md, "Notes")
NOTES: dict[str, str] = {
    "PAL-W222": (
        "PAL selects cutter radius compensation with a move to a point in front of the contour, which the control "
        "approaches equidistantly (`N40 G42 G0 X-14 Y10` in the PAL examples; G45/G47 make the approach themselves). "
        "The warning stands on the first move after G41/G42 (without G45/G47) when that move is no such approach: "
        "(1) it is an arc (a contour element; the circular approach is G47); (2) it runs in the direction of the "
        "contour's first element (within 20°) and does not start at least a cutter radius clear of that element on "
        "the compensation side – the tool travels along the contour while the compensation builds up (`G0 X70 Y84` "
        "then `G41 G1 Y23.6`); (3) the tool centre passes within an eighth of the cutter radius of the contour that "
        "follows (its first four elements) – the cutter runs across the contour, typically because the tool stood on "
        "the contour's line when G41/G42 was selected (`G0 X-14 Y10`, `G42`, `G1 X70`). None of the built-in "
        "exercises' references, the seed programs (tests/seeds/) or the spec's worked examples warns "
        "(tests/test_grading_corpus.py). The grader names it as the cause of a deviating geometry."
    ),
}


def catalogue_markdown() -> str:
    """docs/diagnostics.md, generated from the catalogue (tests keep the two in step)."""
    rows = [
        "# Diagnostics",
        "",
        (
            "Every message PAL Trainer can give, generated from `core/diagnostics.py` "
            "(`python -m core.diagnostics > docs/diagnostics.md`). Codes are stable and never reused. The PAL- "
            "checks are shared by every dialect: a program of another dialect reports one with its own prefix and "
            "the number + 1000 — PAL-E301 is TX-E1301 (TRAUB), ISO-E1301 (SINUMERIK ISO) and BK-E1301 (Beckhoff), "
            'and its JSON says `"same_as": "PAL-E301"`. The dialects\' own codes (TX-E301, ISO-E301 …) are '
            "listed as they are."
        ),
        "",
        "| Code | Severity | Deutsch | English |",
        "|---|---|---|---|",
    ]
    for code, e in CATALOGUE.items():
        rows.append(f"| {code} | {e.severity.value} | {e.de} | {e.en} |")
    rows += [
        "",
        "## Follow-up errors (Folgefehler)",
        "",
        (
            "When a block is dropped because of an error (a syntax error such as a decimal comma, or an error "
            "that stops the block), what it would have set is unknown until a later block that runs sets it "
            "again. A diagnostic of a code below that depends on such a value is a follow-up error: its message "
            'ends in "(Folgefehler von Zeile N)." / "(follows from the error in line N)." and its JSON '
            "carries `follows_from: N`. Every other code is reported as it is. A feed move without feed, with "
            "the spindle stopped or with no tool ("
            + ", ".join(sorted(REPEATED))
            + ") is reported on the first "
            "such move; the later ones become one PAL-I301 note that follows from it."
        ),
        "",
        "| Code | Depends on | Hängt ab von |",
        "|---|---|---|",
    ]
    for code, (_, de, en) in FOLLOW_UPS.items():
        rows.append(f"| {code} | {en} | {de} |")
    rows += ["", "## Notes", ""]
    for code, note in NOTES.items():
        rows += [f"**{code}**: {note}", ""]
    return "\n".join(rows).rstrip("\n") + "\n"


if __name__ == "__main__":
    print(catalogue_markdown(), end="")
