// Locked lines of "complete the program" exercises (the exercise's `locked_lines`, numbers of lines of its start
// program): greyed, a lock in the gutter, and read-only. A change that would alter a locked line is dropped and
// a short message under the editor says why. New lines may be added before and after a locked line (Enter at
// its end or at its start); the lines move with the text around them.

import { EditorState, Facet, RangeSet, StateEffect, StateField, Text } from "@codemirror/state";
import { Decoration, EditorView, GutterMarker, gutter, showPanel } from "@codemirror/view";
import { t } from "./i18n.js";

const blocked = /** @type {import("@codemirror/state").StateEffectType<number>} */ (StateEffect.define());  // the number of the locked line a dropped change would have altered

// the texts of the locked lines, in order (to find them again when a whole program is loaded)
const lockedTexts = Facet.define({ combine: (values) => values[0] || [] });

// Where the locked lines are in `doc`: each text searched after the one before; missing ones are not locked.
function locate(doc, texts) {
  const found = [];
  let n = 1;
  for (const text of texts) {
    let k = n;
    while (k <= doc.lines && doc.line(k).text !== text) k += 1;
    if (k > doc.lines) continue;
    found.push(doc.line(k).from);
    n = k + 1;
  }
  return found;
}

function wholeReplace(tr) {
  let whole = false;
  tr.changes.iterChangedRanges((fromA, toA) => { whole = fromA === 0 && toA === tr.startState.doc.length; });
  return whole && tr.startState.doc.length > 0;
}

// the start positions of the locked lines, moved along with every change (assoc 1: a line inserted at a locked
// line's start goes before it); a whole program loaded (reset, a file, an earlier submission): found anew
const starts = StateField.define({
  create: () => [],
  update(value, tr) {
    if (!tr.docChanged) return value;
    if (wholeReplace(tr)) return locate(tr.state.doc, tr.state.facet(lockedTexts));
    return value.map((pos) => tr.changes.mapPos(pos, 1));
  },
});

const notice = StateField.define({
  create: () => /** @type {string | null} */ (null),
  update(value, tr) {
    for (const e of tr.effects) if (e.is(blocked)) return t("locked.blocked", { n: e.value });
    return tr.docChanged ? null : value;
  },
  provide: (field) => showPanel.from(field, (text) => (text ? () => {
    const dom = document.createElement("div");
    dom.className = "cm-locked-notice";
    dom.setAttribute("role", "status");
    dom.textContent = text;
    return { dom, top: false };
  } : null)),
});

// Which locked line (its number) a change of from..to into `text` would alter or join with another, or 0. The
// line stays itself when the change ends before it at a line start, or begins after it at a line end.
function hits(state, from, to, text) {
  const doc = state.doc;
  const atLineStart = (pos) => pos === 0 || doc.sliceString(pos - 1, pos) === "\n";
  const atLineEnd = (pos) => pos === doc.length || doc.sliceString(pos, pos + 1) === "\n";
  for (const start of state.field(starts)) {
    const line = doc.lineAt(start);
    if (to < line.from || from > line.to) continue;
    if (to === line.from && (text.endsWith("\n") || (text === "" && atLineStart(from)))) continue;
    if (from === line.to && (text.startsWith("\n") || (text === "" && atLineEnd(to)))) continue;
    return line.number;
  }
  return 0;
}

// Typing, pasting, deleting, dropping that would alter a locked line does nothing but say why; programs loaded by
// the page (no user event: reset, a file, an earlier submission) go through.
const USER_EVENTS = ["input", "delete", "move", "undo", "redo"];
const guard = EditorState.transactionFilter.of((tr) => {
  if (!tr.docChanged || !USER_EVENTS.some((e) => tr.isUserEvent(e))) return tr;
  let line = 0;
  tr.changes.iterChanges((from, to, _fromB, _toB, inserted) => {
    if (!line) line = hits(tr.startState, from, to, inserted.toString());
  });
  return line ? { effects: blocked.of(line) } : tr;
});
class Lock extends GutterMarker {
  toDOM() {
    const span = document.createElement("span");
    span.textContent = "🔒";
    span.title = t("locked.lock");
    span.setAttribute("aria-label", t("locked.lock"));
    return span;
  }
}
const lock = new Lock();
const greyed = Decoration.line({ class: "cm-locked-line" });

const decorations = EditorView.decorations.compute([starts], (state) =>
  RangeSet.of([...new Set(state.field(starts))].sort((a, b) => a - b).map((pos) => greyed.range(pos))));
const lockGutter = gutter({
  class: "cm-lock-gutter",
  markers: (view) => RangeSet.of([...new Set(view.state.field(starts))].sort((a, b) => a - b).map((pos) => lock.range(pos))),
  initialSpacer: () => lock,
});

const theme = EditorView.baseTheme({
  ".cm-locked-line": { backgroundColor: "rgba(127, 127, 127, 0.14)", color: "#6a6f75" },
  ".cm-lock-gutter .cm-gutterElement": { fontSize: "0.75em", padding: "0 2px" },
  ".cm-locked-notice": { padding: "4px 8px", background: "#fff4ce", color: "#4d3800", borderTop: "1px solid #e0c36a" },
});

// The extension for an editor showing `text`, where `numbers` (1-based) are the locked lines of the exercise's
// `start` program (a draft may have lines added around them: they are found by their text); [] when none.
export function lockedLines(text, numbers, start = text) {
  if (!numbers?.length) return [];
  const texts = start.split("\n").filter((_, i) => numbers.includes(i + 1));
  const positions = locate(Text.of(text.split("\n")), texts);
  return [starts.init(() => positions), lockedTexts.of(texts), notice, guard, decorations, lockGutter, theme];
}
