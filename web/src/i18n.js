// Every text the pages show, in German (the default: the trainees' language) and English.
// The language is chosen with the switch in the page header and kept in the browser (localStorage).

const TEXTS = {
  "title.practice": ["PAL Trainer – Freies Üben", "PAL Trainer – Free practice"],
  "title.exercise": ["PAL Trainer – Aufgabe", "PAL Trainer – Exercise"],
  "title.exercises": ["PAL Trainer – Aufgaben", "PAL Trainer – Exercises"],
  "title.login": ["PAL Trainer – Anmelden", "PAL Trainer – Log in"],
  "title.instructor": ["PAL Trainer – Abgaben", "PAL Trainer – Submissions"],
  "title.not_found": ["PAL Trainer – Seite nicht gefunden", "PAL Trainer – Page not found"],
  "notfound.title": ["Seite nicht gefunden", "Page not found"],
  "notfound.text": ["Diese Seite gibt es nicht. Vielleicht ist der Link veraltet oder falsch geschrieben.",
    "This page does not exist. The link may be out of date or mistyped."],
  "notfound.home": ["Zur Aufgabenliste", "To the exercise list"],
  "loading": ["Wird geladen …", "Loading …"],
  "nav.exercises": ["Aufgaben", "Exercises"],
  "nav.practice": ["Freies Üben", "Free practice"],
  "nav.submissions": ["Abgaben", "Submissions"],
  "nav.login": ["Anmelden", "Log in"],
  "nav.language": ["English", "Deutsch"],
  "diagnostics.title": ["Meldungen", "Messages"],
  "diagnostics.none": ["Keine Meldungen.", "No messages."],
  "diagnostics.line": ["Zeile {n}", "Line {n}"],
  "dialect.label": ["Dialekt", "Dialect"],
  "login.title": ["Anmelden", "Log in"],
  "login.user": ["Benutzername", "User name"],
  "login.password": ["Passwort", "Password"],
  "login.submit": ["Anmelden", "Log in"],
  "login.failed": ["Anmeldung fehlgeschlagen.", "Login failed."],
  "kind.write": ["Programm schreiben", "Write the program"],
  "kind.complete": ["Programm ergänzen", "Complete the program"],
  "kind.fix": ["Fehler finden", "Find the mistake"],
  "exercise.missing": ["Aufgabe nicht gefunden.", "Exercise not found."],
  "exercise.stock": ["Rohteil {x} × {y} × {z} mm", "Blank {x} × {y} × {z} mm"],
  "tools.tool": ["Werkzeug", "Tool"],
  "tools.kind": ["Art", "Kind"],
  "tools.diameter": ["Durchmesser", "Diameter"],
  "tools.speed": ["S (1/min)", "S (rpm)"],
  "tools.feed": ["F (mm/min)", "F (mm/min)"],
  "kind.end_mill": ["Schaftfräser", "End mill"],
  "kind.slot_drill": ["Langlochfräser", "Slot drill"],
  "kind.ball_nose": ["Radiusfräser", "Ball-nose mill"],
  "kind.torus": ["Eckradiusfräser", "Torus mill"],
  "kind.twist_drill": ["Spiralbohrer", "Twist drill"],
  "kind.spot_drill": ["NC-Anbohrer", "Spot drill"],
  "picture.alt": ["Fertigteil von oben", "Finished part from above"],
  "drawing.alt": ["Bemaßte Zeichnung des Fertigteils", "Dimensioned drawing of the finished part"],
  "drawing.open": ["Zeichnung groß öffnen / drucken", "Open the drawing full size / print"],
  "drawing.download": ["Zeichnung herunterladen (SVG)", "Download the drawing (SVG)"],
  "drawing.sheet": ["Aufgabenblatt (PDF)", "Task sheet (PDF)"],
  "drawing.sheet_title": ["Aufgabe, Zeichnung, Schnittdaten und leeres Programmierblatt zum Ausdrucken",
    "Task, drawing, cutting data and an empty programming form to print"],
  "picture.caption": ["Fertigteil von oben: {x} mm × {y} mm (dunkler = tiefer)",
    "Finished part from above: {x} mm × {y} mm (darker = deeper)"],
  "submit": ["Abgeben", "Submit"],
  "submit.busy": ["Wird bewertet …", "Grading …"],
  "submit.failed": ["Abgabe fehlgeschlagen.", "Submission failed."],
  "submit.ungraded": ["Abgegeben. Diese Aufgabe wird nicht automatisch bewertet.",
    "Submitted. This exercise is not graded automatically."],
  "score": ["{score} von {max} Punkten", "{score} of {max} points"],
  "instructor.title": ["Lehrer-Bereich", "Instructor"],
  "instructor.submissions": ["Abgaben", "Submissions"],
  "instructor.all": ["alle Aufgaben", "all exercises"],
  "instructor.exercise": ["Aufgabe", "Exercise"],
  "instructor.csv": ["als CSV herunterladen", "download as CSV"],
  "instructor.upload": ["Neue Aufgabe hochladen", "Upload a new exercise"],
  "instructor.paste": ["oder den Inhalt der Datei hier einfügen", "or paste the file's content here"],
  "instructor.create": ["Aufgabe anlegen", "Create exercise"],
  "instructor.created": ["Aufgabe »{title}« angelegt.", "Exercise '{title}' created."],
  "instructor.error": ["Fehler.", "Error."],
  "col.number": ["Nr.", "No."],
  "col.learner": ["Teilnehmer", "Learner"],
  "col.time": ["Zeit", "Time"],
  "col.errors": ["Fehler", "Errors"],
  "col.points": ["Punkte", "Points"],
  "viz.title": ["3D-Ansicht", "3D view"],
  "viz.none": ["Keine 3D-Ansicht.", "No 3D view."],
  "viz.on": ["3D-Ansicht einschalten", "Switch the 3D view on"],
  "viz.off": ["3D-Ansicht ausschalten", "Switch the 3D view off"],
  "viz.is_off": ["3D-Ansicht ist ausgeschaltet.", "The 3D view is off."],
  "viz.software": ["Dieser Browser zeichnet 3D ohne Grafikbeschleunigung; die 3D-Ansicht ist darum zunächst aus.",
    "This browser draws 3D without graphics acceleration, so the 3D view starts switched off."],
  "viz.views": ["Ansicht", "View"],
  "viz.view.top": ["Oben", "Top"],
  "viz.view.top_title": ["Draufsicht: von oben auf die XY-Ebene", "Top view: onto the XY plane"],
  "viz.view.front": ["Vorne", "Front"],
  "viz.view.front_title": ["Vorderansicht: auf die XZ-Ebene", "Front view: onto the XZ plane"],
  "viz.view.iso": ["Iso", "Iso"],
  "viz.view.iso_title": ["Schrägansicht von vorne rechts oben", "Isometric view from the front right above"],
  "viz.view.reset": ["Zurücksetzen", "Reset"],
  "viz.view.reset_title": ["Ansicht zurücksetzen: das ganze Werkstück, mittig", "Reset the view: the whole part, centred"],
  "viz.layers": ["Ebenen", "Layers"],
  "viz.layer.rapid": ["Eilgang", "Rapid"],
  "viz.layer.feed": ["Vorschub", "Feed"],
  "viz.layer.contour": ["Kontur", "Contour"],
  "viz.layer.stock": ["Rohteil", "Stock"],
  "viz.legend": ["Legende", "Legend"],
  "viz.legend.too_much": ["zu viel abgetragen", "too much removed"],
  "viz.legend.too_little": ["zu viel stehen gelassen", "too much left"],
  "viz.picture_alt": ["Werkstück nach dem Programm, von oben", "The part after the program, from above"],
  "viz.picture_note": ["Werkstück nach dem Programm, von oben (dunkler = tiefer).",
    "The part after the program, from above (darker = deeper)."],
  "play.back": ["« zurück", "« back"],
  "play.back_title": ["Schritt zurück (Alt+←)", "Step back (Alt+←)"],
  "play.play": ["Abspielen", "Play"],
  "play.play_title": ["Abspielen / anhalten (Alt+Leertaste)", "Play / pause (Alt+Space)"],
  "play.step": ["vor »", "forward »"],
  "play.step_title": ["Schritt vor (Alt+→)", "Step forward (Alt+→)"],
  "play.position": ["Abspielposition", "Playback position"],
  "play.at": ["Schritt {i} von {n} · Zeile {line}", "Step {i} of {n} · line {line}"],
  "play.segments": ["{n} Wegstücke", "{n} path pieces"],
  "play.cut": [" (gekürzt)", " (cut short)"],
  "deviation.shown": ["Abweichung vom Fertigteil: rot zu viel abgetragen {much} mm³, blau zu viel stehen gelassen {little} mm³; größte Abweichung {largest} mm.",
    "Deviation from the finished part: red too much removed {much} mm³, blue too much left {little} mm³; largest deviation {largest} mm."],
  "deviation.none": ["Das Werkstück liegt überall im Toleranzband.", "The part lies within the tolerance band everywhere."],
  "setup.title": ["Rohteil und Werkzeuge", "Stock and tools"],
  "setup.stock": ["Rohteil (Nullpunkt vorne links oben)", "Stock (zero at the front left top corner)"],
  "setup.size.0": ["Länge X in mm", "Length X in mm"],
  "setup.size.1": ["Breite Y in mm", "Width Y in mm"],
  "setup.size.2": ["Höhe Z in mm", "Height Z in mm"],
  "setup.tools": ["Eigene Werkzeuge", "Own tools"],
  "setup.default_tools": ["Alle anderen Nummern: die Standard-Werkzeugtabelle (T1 Schaftfräser Ø25, T2 Langlochfräser Ø6, T3 Radiusfräser Ø10, T4 Schaftfräser Ø20 …).",
    "Every other number: the default tool table (T1 end mill Ø25, T2 slot drill Ø6, T3 ball-nose mill Ø10, T4 end mill Ø20 …)."],
  "setup.add": ["Werkzeug hinzufügen", "Add a tool"],
  "setup.remove": ["entfernen", "remove"],
  "setup.invalid": ["Bitte gültige Maße eingeben (Rohteil 1–2000 mm, T1–T99, Ø bis 1000 mm).",
    "Please enter valid sizes (stock 1–2000 mm, T1–T99, Ø up to 1000 mm)."],
  "program.label": ["NC-Programm", "NC program"],
};

export const lang = localStorage.getItem("paltrainer-lang") === "en" ? "en" : "de";

export function t(key, params = {}) {
  const entry = TEXTS[key];
  let text = entry ? entry[lang === "en" ? 1 : 0] : key;
  for (const [name, value] of Object.entries(params)) text = text.replaceAll(`{${name}}`, String(value));
  return text;
}

// The message of a diagnostic, criterion or help entry in the chosen language.
export function message(item, de = "message", en = "message_en") {
  return lang === "en" && item[en] ? item[en] : item[de];
}

// Static page texts: elements with data-i18n="key"; the language switch in the header.
export function translatePage() {
  document.documentElement.lang = lang;
  for (const node of document.querySelectorAll("[data-i18n]")) node.textContent = t(node.dataset.i18n);
  for (const node of document.querySelectorAll("[data-i18n-label]")) {
    node.setAttribute("aria-label", t(node.dataset.i18nLabel));
  }
  const toggle = document.getElementById("lang");
  if (toggle) {
    toggle.textContent = t("nav.language");
    toggle.onclick = () => {
      localStorage.setItem("paltrainer-lang", lang === "en" ? "de" : "en");
      location.reload();
    };
  }
}
