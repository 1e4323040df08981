// Editor help from the dialect's code table (GET /api/v1/dialects/{name}, filled from core/dialects/): the hover
// text of a G/M code or an address, and the completion list. Codes come in numeric order (G1, G2 … G10), and
// typing narrows by prefix (G4 → G4, G40 … G48), not by fuzzy matching. Enter at the end of a line starts a new
// line while the list only popped up by itself; after Ctrl+Space it takes the chosen entry.
// Each editor keeps its dialect's help in its own state (the facet `editorHelp`), so that two editors of two
// dialects on one page each show their own.

import { closeCompletion, completionStatus } from "@codemirror/autocomplete";
import { insertNewlineAndIndent } from "@codemirror/commands";
import { Facet, Prec } from "@codemirror/state";
import { ViewPlugin, keymap } from "@codemirror/view";
import { message, t } from "./i18n.js";

export function emptyHelp() { return { codes: {}, order: [], addresses: {} }; }

// An editor's help: its dialect's code table (helpFrom) and where the dialect's comments stand in a line (hover
// help is not for the words of a comment; PAL: from ";" to the end of the line).
export const editorHelp = Facet.define({
  combine: (values) => values[0] ?? { help: emptyHelp(), comments: /;.*/g },
});

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
  const lines = [`${entry.name}: ${message(entry, "help_de", "help_en")}${entry.supported === false ? ` (${t("help.planned")})` : ""}`];
  if (isCode) {
    const groups = (entry.mandatory || []).map((g) => (g.length > 1 ? `${t("help.one_of")} ${g.map((a) => withUnit(help, a)).join(" / ")}`
      : withUnit(help, g[0])));
    if (groups.length) lines.push(`${t("help.mandatory")}: ${groups.join("; ")}`);
    if (entry.optional?.length) lines.push(`${t("help.optional")}: ${entry.optional.map((a) => withUnit(help, a)).join(", ")}`);
    if (entry.example) lines.push(`${t("help.example")}: ${entry.example}`);
  } else if (entry.unit) {
    lines.push(`${t("help.unit")}: ${entry.unit}`);
  }
  const rule = message(entry, "rule_de", "rule_en");
  if (rule) lines.push(`${t("help.rule")}: ${rule}`);
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
// The codes and addresses of the editor's own dialect (its state's editorHelp) that start with the typed prefix.
export function completionSource(context) {
  const word = context.matchBefore(/#?[A-Z]*[0-9]*/i);
  if (!word || (word.from === word.to && !context.explicit)) return null;
  const { help } = context.state.facet(editorHelp);
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
}

// Whether the list now open in this editor was opened with Ctrl+Space (reset when it closes).
const explicitList = ViewPlugin.fromClass(class {
  explicit = false;
  update(/** @type {import("@codemirror/view").ViewUpdate} */ u) { if (completionStatus(u.state) === null) this.explicit = false; }
});

// Enter at the end of a line with a list that opened by itself: a new line, not the first entry.
export const enterKeymap = [
  explicitList,
  Prec.highest(keymap.of([
    {  // then the list's own Ctrl-Space opens it
      key: "Ctrl-Space",
      run(view) { view.plugin(explicitList).explicit = true; return false; },
    },
    {
      key: "Enter",
      run(view) {
        if (completionStatus(view.state) !== "active" || view.plugin(explicitList).explicit) return false;
        const { head, empty } = view.state.selection.main;
        if (!empty || head !== view.state.doc.lineAt(head).to) return false;
        closeCompletion(view);
        return insertNewlineAndIndent(view);
      },
    },
  ])),
];
