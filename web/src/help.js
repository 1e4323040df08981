// Editor help from the dialect's code table (GET /api/v1/dialects/{name}, filled from core/dialects/): the hover
// text of a G/M code or an address, and the completion list. Codes come in numeric order (G1, G2 … G10), and
// typing narrows by prefix (G4 → G4, G40 … G48), not by fuzzy matching. Enter at the end of a line starts a new
// line while the list only popped up by itself; after Ctrl+Space it takes the chosen entry.

import { closeCompletion, completionStatus } from "@codemirror/autocomplete";
import { insertNewlineAndIndent } from "@codemirror/commands";
import { Prec } from "@codemirror/state";
import { EditorView, keymap } from "@codemirror/view";
import { lang, message } from "./i18n.js";

const TEXTS = {
  de: { mandatory: "Pflicht", optional: "Optional", example: "Beispiel", rule: "Regel", unit: "Einheit",
    one_of: "eins von", planned: "noch nicht unterstützt" },
  en: { mandatory: "Required", optional: "Optional", example: "Example", rule: "Remember", unit: "Unit",
    one_of: "one of", planned: "not supported yet" },
};
const tx = TEXTS[lang === "en" ? "en" : "de"];

export function emptyHelp() { return { codes: {}, order: [], addresses: {} }; }

export function helpFrom(data) {
  const help = emptyHelp();
  for (const c of data.codes) { help.codes[c.name] = c; help.order.push(c.name); }
  for (const a of data.addresses) help.addresses[a.name] = a;
  return help;
}

function withUnit(help, name) {
  const unit = help.addresses[name]?.unit;
  return unit ? `${name} (${unit})` : name;
}

// The lines of a hover: name and meaning, then what the block needs and takes, an example, the rule.
export function helpLines(help, entry, isCode) {
  const lines = [`${entry.name}: ${message(entry, "help_de", "help_en")}${entry.supported === false ? ` (${tx.planned})` : ""}`];
  if (isCode) {
    const groups = (entry.mandatory || []).map((g) => (g.length > 1 ? `${tx.one_of} ${g.map((a) => withUnit(help, a)).join(" / ")}`
      : withUnit(help, g[0])));
    if (groups.length) lines.push(`${tx.mandatory}: ${groups.join("; ")}`);
    if (entry.optional?.length) lines.push(`${tx.optional}: ${entry.optional.map((a) => withUnit(help, a)).join(", ")}`);
    if (entry.example) lines.push(`${tx.example}: ${entry.example}`);
  } else if (entry.unit) {
    lines.push(`${tx.unit}: ${entry.unit}`);
  }
  const rule = message(entry, "rule_de", "rule_en");
  if (rule) lines.push(`${tx.rule}: ${rule}`);
  return lines;
}

export function helpDom(help, entry, isCode) {
  const dom = document.createElement("div");
  dom.className = "pal-help";
  helpLines(help, entry, isCode).forEach((text, i) => {
    const line = document.createElement(i === 0 ? "strong" : "div");
    line.textContent = text;
    if (i === 0) line.style.display = "block";
    dom.append(line);
  });
  return dom;
}

// -- completion --------------------------------------------------------------------------------------------
let explicit = false;  // the list now open was opened with Ctrl+Space (reset when it closes)

export function completionSource(getHelp) {
  return (context) => {
    const word = context.matchBefore(/#?[A-Z]*[0-9]*/i);
    if (!word || (word.from === word.to && !context.explicit)) return null;
    const help = getHelp();
    const prefix = word.text.toUpperCase();
    const options = [];
    for (const name of help.order) {
      if (!name.startsWith(prefix)) continue;
      const c = help.codes[name];
      options.push({ label: name, detail: message(c, "help_de", "help_en"), type: "keyword",
        info: () => helpDom(help, c, true) });
    }
    if (!/[0-9]/.test(prefix)) {
      for (const a of Object.values(help.addresses)) {
        if (!a.name.startsWith(prefix)) continue;
        options.push({ label: a.name, detail: message(a, "help_de", "help_en"), type: "property" });
      }
    }
    if (!options.length) return null;
    return { from: word.from, options, filter: false };
  };
}

// Enter at the end of a line with a list that opened by itself: a new line, not the first entry.
export const enterKeymap = [
  Prec.highest(keymap.of([
    { key: "Ctrl-Space", run() { explicit = true; return false; } },  // then the list's own Ctrl-Space opens it
    {
      key: "Enter",
      run(view) {
        if (completionStatus(view.state) !== "active" || explicit) return false;
        const { head, empty } = view.state.selection.main;
        if (!empty || head !== view.state.doc.lineAt(head).to) return false;
        closeCompletion(view);
        return insertNewlineAndIndent(view);
      },
    },
  ])),
  EditorView.updateListener.of((u) => { if (completionStatus(u.state) === null) explicit = false; }),
];
