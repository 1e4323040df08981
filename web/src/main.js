// The PAL Trainer editor: CodeMirror 6 with a PAL mode, live diagnostics from the server's
// WebSocket /api/v1/live, hover help and completion from the dialect's code table
// (GET /api/v1/dialects/{name}), German editor phrases. No geometry here: the server computes it.

import { EditorState, Compartment } from "@codemirror/state";
import {
  EditorView, keymap, lineNumbers, highlightActiveLine, highlightActiveLineGutter, hoverTooltip,
  drawSelection,
} from "@codemirror/view";
import { defaultKeymap, history, historyKeymap } from "@codemirror/commands";
import { StreamLanguage, HighlightStyle, syntaxHighlighting } from "@codemirror/language";
import { tags } from "@lezer/highlight";
import { setDiagnostics, lintGutter } from "@codemirror/lint";
import { autocompletion } from "@codemirror/autocomplete";
import { searchKeymap } from "@codemirror/search";
import { message, t } from "./i18n.js";
import { completionSource, editorHelp, emptyHelp, enterKeymap, helpDom, helpFrom } from "./help.js";
import { lockedLines } from "./locked.js";

// -- the PAL mode: block numbers, G/M codes, addresses, numbers, comments -----------------------
const palMode = StreamLanguage.define({
  name: "pal",
  token(stream) {
    if (stream.eatSpace()) return null;
    if (stream.peek() === ";") { stream.skipToEnd(); return "comment"; }
    if (stream.sol() && stream.match(/^%.*/)) return "meta";
    if (stream.match(/^\/[0-9]?/)) return "meta";
    if (stream.match(/^N[0-9]+/i)) return "labelName";
    if (stream.match(/^[GM][0-9]+/i)) return "keyword";
    if (stream.match(/^#?[A-Z]+(?==)/i)) return "propertyName";
    if (stream.match(/^[A-Z]+/i)) return "propertyName";
    if (stream.match(/^[+-]?([0-9]+(\.[0-9]*)?|\.[0-9]+)/)) return "number";
    stream.next();
    return "operator";
  },
});

// -- the TRAUB TX 8 D mode: "%", O program numbers, comments in parentheses, L parameters with brackets
// (X L2, Z-[L2/2], L1 = 11), "/" skip blocks at a block's start, decimal commas, blanks inside words (T 303)
const traubMode = StreamLanguage.define({
  name: "traub",
  startState: () => ({ fresh: true }),  // fresh: nothing yet in this block (where "%" and "/" may stand)
  token(stream, state) {
    if (stream.sol()) state.fresh = true;
    if (stream.eatSpace()) return null;
    const fresh = state.fresh;
    state.fresh = false;
    if (stream.match(/^\([^)]*\)?/)) return "comment";
    if (fresh && stream.match(/^%.*/)) return "meta";
    if (fresh && stream.match(/^\/[0-9]?/)) { state.fresh = true; return "meta"; }  // the block follows
    if (stream.match(/^[NO] *[0-9]+/i)) return "labelName";
    if (stream.match(/^[GM] *[0-9]+/i)) return "keyword";
    if (stream.match(/^L *[0-9]+/i)) return "variableName";
    if (stream.match(/^[A-Z]/i)) return "propertyName";
    if (stream.match(/^[+-]?([0-9]+([.,][0-9]*)?|[.,][0-9]+)/)) return "number";
    if (stream.match(/^[[\]]/)) return "bracket";
    stream.next();
    return "operator";
  },
});
const MODES = { "traub-tx8d": traubMode };
// where a line's comment starts (hover help is not for the words of a comment)
const COMMENTS = { "traub-tx8d": /\([^)]*\)?/g };

const palHighlight = HighlightStyle.define([
  { tag: tags.comment, color: "#6a737d", fontStyle: "italic" },
  { tag: tags.keyword, color: "#0b5cad", fontWeight: "bold" },
  { tag: tags.labelName, color: "#8250df" },
  { tag: tags.propertyName, color: "#953800" },
  { tag: tags.number, color: "#116329" },
  { tag: tags.meta, color: "#cf222e" },
  { tag: tags.variableName, color: "#0550ae", fontStyle: "italic" },
  { tag: tags.bracket, color: "#57606a" },
]);

// CodeMirror's own texts (its phrase → our key; in English the phrase itself)
const PHRASES = {
  "Find": "phrase.find", "Replace": "phrase.replace", "next": "phrase.next", "previous": "phrase.previous",
  "all": "phrase.all", "match case": "phrase.match_case", "regexp": "phrase.regexp", "by word": "phrase.by_word",
  "replace": "phrase.replace_one", "replace all": "phrase.replace_all", "close": "phrase.close",
  "Go to line": "phrase.go_to_line", "go": "phrase.go", "Diagnostics": "phrase.diagnostics",
  "No diagnostics": "phrase.no_diagnostics",
};
const phrases = EditorState.phrases.of(Object.fromEntries(Object.entries(PHRASES).map(([phrase, key]) => [phrase, t(key)])));

// -- help from the dialect's code table, kept in each editor's state (help.js: editorHelp) -------------
const helps = new Map();  // dialect → the promise of its help (asked once per page)

function loadHelp(dialect) {
  if (!helps.has(dialect)) {
    const asked = fetch(`/api/v1/dialects/${dialect}`).then(async (r) => {
      if (r.ok) return helpFrom(await r.json());
      helps.delete(dialect);  // no help this time; the next editor asks again
      return emptyHelp();
    });
    helps.set(dialect, asked);
    asked.catch(() => helps.delete(dialect));  // no answer: this editor's mount fails, as before; the next one asks again
  }
  return helps.get(dialect);
}

function wordAt(text, pos) {
  const re = /(#?[A-Z]+)([+-]?[0-9.]*)/gi;
  let m;
  while ((m = re.exec(text)) !== null) {
    if (m.index <= pos && pos <= m.index + m[0].length) return m;
  }
  return null;
}

function inComment(text, pos, comments) {
  for (const c of text.matchAll(comments)) {
    if (c.index <= pos && pos < c.index + c[0].length) return true;
  }
  return false;
}

const hoverHelp = hoverTooltip((view, pos) => {
  const { help, comments } = view.state.facet(editorHelp);
  const line = view.state.doc.lineAt(pos);
  if (inComment(line.text, pos - line.from, comments)) return null;
  const m = wordAt(line.text, pos - line.from);
  if (!m) return null;
  const address = m[1].toUpperCase();
  const code = (address === "G" || address === "M") && m[2] ? help.codes[`${address}${parseInt(m[2], 10)}`] : null;
  const entry = code || help.addresses[address];
  if (!entry) return null;
  // a cycle block: how many passes the cycle makes here (from the live toolpath of that line)
  const cycle = code ? lives.get(view)?.cycles.get(line.number) : null;
  const hovered = `${address}${parseInt(m[2], 10)}`;
  const passes = cycle && cycle.code === hovered ? cycle.of : null;
  // a PAL cycle call (G76–G79): which definition it runs, from which line, in how many steps per point
  const called = cycle && cycle.defined_in_line && cycle.code !== hovered ? cycle : null;
  return {
    pos: line.from + m.index, end: line.from + m.index + m[0].length, above: true,
    create() {
      const dom = helpDom(help, entry, Boolean(code));
      if (passes || called) {
        const note = document.createElement("p");
        note.className = "help-cycle";
        note.textContent = called
          ? t("cycle.call", { code: called.code, line: called.defined_in_line,
            points: t(`cycle.points.${called.points === 1 ? "one" : "other"}`, { n: called.points ?? 1 }),
            steps: t(`cycle.steps.${called.of === 1 ? "one" : "other"}`, { n: called.of }) })
          : t("cycle.passes", { code: cycle.code, n: passes });
        dom.append(note);
      }
      return { dom };
    },
  };
});

// -- live diagnostics over the WebSocket -------------------------------------------------------
// How long to wait before the socket connects again after it closed (ms), or null: not again. The one place
// of this rule (a replica that died: the next connect reaches another one). 4401/4403 (not logged in,
// forbidden, e.g. a running exam without live diagnostics) do not get better by trying again; 4429 (too many
// open connections) after a long wait; anything else doubling from 1 s up to 30 s.
export function reconnectDelay(code, attempt) {
  if (code === 4401 || code === 4403) return null;
  if (code === 4429) return 60000;
  return Math.min(30000, 1000 * 2 ** Math.min(attempt, 5));
}

// The German (or English) sentence for a close code: why the live check stopped or pauses.
function closeText(code, reason, delay) {
  if (code === 4403 && reason === "EXAM_RUNNING") return t("live.exam");
  if (code === 4403 && reason === "EXAM_EXERCISE_LOCKED") return t("live.locked");
  if (code === 4401) return t("live.login");
  if (code === 4403) return t("live.forbidden");
  if (code === 4429) return t("live.too_many", { s: Math.round(delay / 1000) });
  return t("live.retry", { s: Math.round(delay / 1000) });
}

class Live {
  constructor(view, dialect, exercise, tools, onUpdate, onNotice) {
    this.view = view;
    this.dialect = dialect;
    this.exercise = exercise;
    this.tools = tools;
    this.onUpdate = onUpdate;
    this.onNotice = onNotice;  // a line for the messages panel (an error of the server, a lost connection)
    this.version = 0;
    this.byLine = new Map();
    this.cycles = new Map();  // line → the cycle its moves belong to ({code, pass, of}), for the hover
    this.timer = null;
    this.attempt = 0;  // failed connects since the last open one
    this.connect();
  }

  connect() {
    const scheme = location.protocol === "https:" ? "wss" : "ws";
    this.ws = new WebSocket(`${scheme}://${location.host}/api/v1/live`);
    this.ws.onopen = () => { this.attempt = 0; this.open(); };
    this.ws.onmessage = (event) => this.receive(JSON.parse(event.data));
    this.ws.onclose = (event) => {
      const delay = reconnectDelay(event.code, this.attempt);
      this.onNotice(closeText(event.code, event.reason, delay));
      if (delay === null) return;
      this.attempt += 1;
      setTimeout(() => this.connect(), delay);
    };
  }

  open() {  // (again, when the tools change: the document is checked anew with them)
    this.version += 1;
    this.byLine.clear();
    this.cycles.clear();
    this.ws.send(JSON.stringify({
      type: "open", version: this.version, text: this.text(), dialect: this.dialect, exercise: this.exercise,
      tools: this.tools,
    }));
  }

  setTools(tools) {
    this.tools = tools;
    if (this.ws.readyState === WebSocket.OPEN) this.open();
  }

  text() { return this.view.state.doc.toString(); }

  changed() {  // the editor calls this on every change: send the text after a short pause
    clearTimeout(this.timer);
    this.timer = setTimeout(() => {
      if (this.ws.readyState !== WebSocket.OPEN) return;
      this.version += 1;
      this.ws.send(JSON.stringify({ type: "sync", version: this.version, text: this.text() }));
    }, 120);
  }

  receive(msg) {
    if (msg.type === "error") {  // a refused frame or a failed run: say so (the next update clears it)
      this.onNotice(`${msg.code}: ${message(msg)}`);
      return;
    }
    if (msg.type !== "update" || msg.version < this.version) return;  // stale: a newer one follows
    for (const entry of msg.diagnostics) this.byLine.set(entry.line, entry.items);
    for (const entry of msg.toolpath || []) {
      const move = (entry.moves || []).find((mv) => mv.cycle);
      if (move) this.cycles.set(entry.line, move.cycle); else this.cycles.delete(entry.line);
    }
    const doc = this.view.state.doc;
    const diagnostics = [];
    for (const [, items] of this.byLine) {
      for (const d of items) {
        if (d.line > doc.lines) continue;
        const line = doc.line(d.line);
        const from = Math.min(line.from + d.column - 1, line.to);
        const endLine = doc.line(Math.min(d.end_line, doc.lines));
        const to = Math.max(from, Math.min(endLine.from + d.end_column - 1, endLine.to));
        diagnostics.push({
          from, to, severity: d.severity === "info" ? "info" : d.severity,
          message: `${d.code}: ${message(d)}`, source: d.code,
        });
      }
    }
    this.view.dispatch(setDiagnostics(this.view.state, diagnostics));
    this.onUpdate(diagnostics, msg);
  }
}

// -- the page ------------------------------------------------------------------------------------
const lives = new WeakMap();  // editor view → its live connection

// Free practice: check the program with these tools ([{number, diameter}], null: the default table).
export function setTools(view, tools) { lives.get(view)?.setTools(tools); }

// The program can be read, not changed (an exam's time is over, its one submission made).
const locks = new WeakMap();  // editor view → the compartment of its read-only state
export function setReadOnly(view, on) {
  view.dispatch({ effects: locks.get(view).reconfigure(EditorState.readOnly.of(on)) });
}

export async function mountEditor(parent, {
  text = "", dialect = "pal-mill", list = null, exercise = null, tools = null, onChange = null, onPointer = null,
  locked = null,  // {lines, start}: line numbers of the start program that stay as they are (kind complete)
  live: withLive = true,  // false (an exam without live diagnostics): no socket, no hover help, no completion
  readOnly = false,
} = {}) {
  // this editor's help (an earlier editor of another dialect keeps its own)
  const help = withLive ? await loadHelp(dialect) : null;
  let live = null;
  const language = new Compartment();
  const editable = new Compartment();
  const view = new EditorView({
    parent,
    state: EditorState.create({
      doc: text,
      extensions: [
        lineNumbers(), highlightActiveLineGutter(), highlightActiveLine(), drawSelection(), history(),
        keymap.of([...defaultKeymap, ...historyKeymap, ...searchKeymap]),
        language.of(MODES[dialect] || palMode), syntaxHighlighting(palHighlight),
        // enterKeymap before the completion list's Enter
        withLive ? [editorHelp.of({ help, comments: COMMENTS[dialect] || /;.*/g }), lintGutter(), hoverHelp, enterKeymap,
          autocompletion({ override: [completionSource] })] : [],
        phrases, editable.of(EditorState.readOnly.of(readOnly)),
        EditorView.contentAttributes.of({ "aria-label": t("program.label") }), lockedLines(text, locked?.lines, locked?.start),
        EditorView.updateListener.of((u) => {
          if (u.docChanged && live) live.changed();
          if (u.docChanged && onChange) onChange(u.state.doc.toString());
          if (u.selectionSet && onPointer && u.transactions.some((t) => t.isUserEvent("select.pointer"))) {
            onPointer(u.state.doc.lineAt(u.state.selection.main.head).number);
          }
        }),
      ],
    }),
  });
  locks.set(view, editable);
  if (!withLive) return view;
  // a notice (the server's error, a lost connection) stands in the messages panel until the next update
  const notice = (text) => {
    if (!list) return;
    const li = list.querySelector(".diag-notice") || document.createElement("li");
    li.className = "diag diag-none diag-notice";
    li.textContent = text;
    list.prepend(li);
  };
  live = new Live(view, dialect, exercise, tools, (diagnostics) => {
    if (!list) return;
    list.replaceChildren(...diagnostics.map((d) => {
      const li = document.createElement("li");
      li.className = `diag diag-${d.severity}`;
      const line = view.state.doc.lineAt(d.from).number;
      li.textContent = `${t("diagnostics.line", { n: line })}: ${d.message}`;
      li.onclick = () => view.dispatch({ selection: { anchor: d.from }, scrollIntoView: true });
      return li;
    }));
    if (!diagnostics.length) {
      const li = document.createElement("li");
      li.className = "diag diag-none";
      li.textContent = t("diagnostics.none");
      list.append(li);
    }
  }, notice);
  lives.set(view, live);
  return view;
}
