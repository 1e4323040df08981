// The texts of the grade wherever it is shown (criteria with their features, the teacher's score), of the
// teacher's form that changes it and of the cutting data in the Werkzeuge tab (German, English).

import { addTexts } from "./i18n.js";

addTexts({
  "criterion.passed": ["erfüllt", "met"],
  "criterion.partial": ["teilweise erfüllt", "partly met"],
  "criterion.failed": ["nicht erfüllt", "not met"],
  "criterion.cause_line": ["Ursache: Zeile {n}", "Cause: line {n}"],
  "criterion.cause_title": ["Zur Zeile der wahrscheinlichen Ursache springen", "Go to the line of the likely cause"],
  "features.summary": ["Formelemente: {kept} von {total} maßhaltig", "Features: {kept} of {total} made to size"],
  "feature.kept": ["maßhaltig", "made to size"],
  "feature.lost": ["nicht maßhaltig", "not made to size"],
  "feature.deviation": ["bis {mm} mm daneben", "up to {mm} mm off"],
  "result.last": ["Ihre letzte Abgabe vom {time}", "Your last submission: {time}"],

  "override.title": ["Punktzahl ändern", "Change the score"],
  "override.automatic": ["Automatische Bewertung: {score} von {max} Punkten", "Automatic grade: {score} of {max} points"],
  "override.by": ["Geändert von {by} am {time}", "Changed by {by} on {time}"],
  "override.by_nobody": ["Geändert am {time}", "Changed on {time}"],
  "override.score": ["Punkte (0 bis {max})", "Points (0 to {max})"],
  "override.comment": ["Kommentar für den Schüler (optional)", "Comment for the trainee (optional)"],
  "override.save": ["Punktzahl speichern", "Save the score"],
  "override.restore": ["Automatische Bewertung wiederherstellen", "Restore the automatic grade"],
  "override.invalid": ["Bitte eine ganze Zahl von 0 bis {max} eingeben.", "Please enter a whole number from 0 to {max}."],
  "override.saved": ["Gespeichert: {score} von {max} Punkten zählen.", "Saved: {score} of {max} points count."],
  "override.restored": ["Die automatische Bewertung gilt wieder.", "The automatic grade counts again."],
  "override.failed": ["Die Punktzahl konnte nicht gespeichert werden.", "The score could not be saved."],
  "override.help": ["Der Schüler sieht die neue Punktzahl mit Ihrem Kommentar; die automatische Bewertung bleibt erhalten.",
    "The trainee sees the new score with your comment; the automatic grade is kept."],
  "override.changed": ["von der Lehrkraft geändert", "changed by the instructor"],
  "override.note": ["* von der Lehrkraft geändert", "* changed by the instructor"],

  "tools.spindle": ["Drehrichtung", "Spindle"],
  "spindle.M3": ["M3 (rechts)", "M3 (clockwise)"],
  "spindle.M4": ["M4 (links)", "M4 (counter-clockwise)"],
  "matrix.total_note": ["Summe: alle Aufgaben des Auftrags; was nicht abgegeben ist, zählt 0.",
    "Total: every exercise of the assignment; what is not handed in counts 0."],
});
