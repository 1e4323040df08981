// The texts of the exercise page's task and Werkzeuge tabs (German, English): what a turner reads on a lathe
// tool's card (insert, nose radius and its position, V or S, F and the reduced feed E) beside the milling
// tool's diameter, S and F; and free practice's group of turning examples.

import { addTexts } from "./i18n.js";

addTexts({
  "drawing.own_pdf": ["Zeichnung (PDF)", "Drawing (PDF)"],
  "kind.turning": ["Drehmeißel", "Turning tool"],
  "tools.insert": ["Schneidplatte", "Insert"],
  "tools.insert_groove": ["Einstechplatte", "Grooving insert"],
  "tools.insert_thread": ["Gewindeplatte", "Threading insert"],
  "tools.insert_width": ["Breite", "width"],
  "tools.nose_radius": ["Schneidenradius", "Nose radius"],
  "tools.quadrant": ["Schneidenlage", "Cutting position"],
  "tools.v": ["Schnitt\u00adgeschwindigkeit", "Cutting speed"],
  "tools.s": ["Drehzahl", "Spindle speed"],
  "tools.v_value": ["V {v} m/min (G96)", "V {v} m/min (G96)"],
  "tools.s_value": ["S {s} 1/min (G97)", "S {s} rpm (G97)"],
  "tools.f": ["Vorschub", "Feed"],
  "tools.f_value": ["F {f} mm/U", "F {f} mm/rev"],
  "tools.e": ["Reduzierter Vorschub", "Reduced feed"],
  "tools.e_value": ["E {e} mm/U", "E {e} mm/rev"],
  "example.group_traub": ["TRAUB TX 8 D Drehen", "TRAUB TX 8 D turning"],
  "tools.none": ["Die Aufgabe schreibt keine Werkzeuge vor.", "The exercise prescribes no tools."],
});
