// The workplace around the editor (exercise page and free practice): the side panel's tabs and its
// collapse button, the drawer with the messages and the score, the editor toolbar (open, save, print,
// reset) and the drawing with its zoom. The page modules (page-exercise.js, page-practice.js) call these.

import { el } from "./dom.js";
import { drawingPageUrl, drawingViewer } from "./drawing-viewer.js";
import { t } from "./i18n.js";

const SIDE_KEY = "paltrainer-side-collapsed";
const DRAWER_KEY = "paltrainer-drawer-closed";

// Tabs (WAI-ARIA tabs pattern): click or the arrow keys choose; the panel of the chosen tab is shown.
export function mountTabs(root, onSelect = null) {
  const tabs = [...root.querySelectorAll("[role=tab]")];
  const select = (tab, focus = false) => {
    for (const other of tabs) {
      const chosen = other === tab;
      other.setAttribute("aria-selected", String(chosen));
      other.tabIndex = chosen ? 0 : -1;
      document.getElementById(other.getAttribute("aria-controls")).hidden = !chosen;
    }
    if (focus) tab.focus();
    onSelect?.(tab.id);
  };
  for (const tab of tabs) {
    tab.addEventListener("click", () => select(tab));
    tab.addEventListener("keydown", (event) => {
      const i = tabs.indexOf(tab);
      const next = { ArrowRight: i + 1, ArrowLeft: i - 1, Home: 0, End: tabs.length - 1 }[event.key];
      if (next === undefined) return;
      event.preventDefault();
      select(tabs[(next + tabs.length) % tabs.length], true);
    });
  }
  return (id) => select(document.getElementById(id));
}

// The side panel folds to a strip (remembered in the browser), so that editor and 3D view get the width. On a
// narrow screen (tablet, phone: the panes stacked) the exercise's task starts folded, so that the editor gets the
// height: the strip keeps the tabs and the exercise's title, and choosing a tab unfolds it. Each width remembers
// its own choice. Free practice keeps its set-up open (the dialect and the example are chosen there first).
const NARROW = "(max-width: 1023.98px)";

export function mountSideToggle(root) {
  const side = root.querySelector(".side");
  const button = root.querySelector("#side-toggle");
  const narrow = window.matchMedia(NARROW);
  const folds = root.querySelector("#panel-task") !== null;  // the exercise page (free practice: the set-up)
  const key = () => (narrow.matches ? `${SIDE_KEY}-narrow` : SIDE_KEY);
  const chosen = () => ({ 1: true, 0: false }[localStorage.getItem(key())] ?? (narrow.matches && folds));
  // the task's heading (the exercise's title, an exam's) into the strip, shown by the stylesheet (::before), so
  // that the page's text holds the title once
  const task = root.querySelector("#panel-task");
  if (task) {
    const caption = el("span", { className: "side-title", id: "side-title" });
    caption.setAttribute("aria-hidden", "true");
    button.before(caption);
    new MutationObserver(() => { caption.dataset.title = task.querySelector("h2")?.textContent || ""; })
      .observe(task, { childList: true, characterData: true, subtree: true });
  }
  const set = (collapsed, remember = true) => {
    side.classList.toggle("collapsed", collapsed);
    root.classList.toggle("side-collapsed", collapsed);
    button.setAttribute("aria-expanded", String(!collapsed));
    button.textContent = collapsed ? "›" : "‹";
    button.setAttribute("aria-label", t(collapsed ? "side.expand" : "side.collapse"));
    button.title = t(collapsed ? "side.expand" : "side.collapse");
    if (remember) localStorage.setItem(key(), collapsed ? "1" : "0");
  };
  button.addEventListener("click", () => set(!side.classList.contains("collapsed")));
  // a tab of the folded strip unfolds the panel (with the pointer or the keys of the tab list)
  const unfold = () => { if (side.classList.contains("collapsed")) set(false); };
  for (const tab of root.querySelectorAll(".side [role=tab]")) {
    tab.addEventListener("click", unfold);
    tab.addEventListener("keydown", (event) => { if (["ArrowLeft", "ArrowRight", "Home", "End"].includes(event.key)) unfold(); });
  }
  narrow.addEventListener("change", () => set(chosen(), false));  // turned or resized across the border
  set(chosen(), false);
}

// The drawer: its bar always shows the number of messages (and the score after "Abgeben"); open it shows
// the messages and the criteria. Open or closed is remembered in the browser. `open()` (after "Abgeben", an
// exam's result) opens it tall, at least half the window, so that the criteria read without scrolling a slit;
// "Verkleinern" gives the editor its room back, "Vergrößern" the result.
export function mountDrawer(root) {
  const drawer = root.querySelector("#drawer");
  const toggle = root.querySelector("#drawer-toggle");
  const body = root.querySelector("#drawer-body");
  const list = root.querySelector("#diagnostics");
  const count = root.querySelector("#diag-count");
  const status = root.querySelector("#status-line");
  const size = el("button", { type: "button", id: "drawer-size", className: "drawer-size" });
  size.setAttribute("aria-controls", "drawer-body");
  toggle.after(size);
  const tall = (on) => {
    drawer.classList.toggle("tall", on);
    size.textContent = t(on ? "drawer.smaller" : "drawer.taller");
    size.title = t(on ? "drawer.smaller_title" : "drawer.taller_title");
  };
  size.addEventListener("click", () => tall(!drawer.classList.contains("tall")));
  const set = (open) => {
    body.hidden = !open;
    size.hidden = !open;
    if (!open) tall(false);
    toggle.setAttribute("aria-expanded", String(open));
    localStorage.setItem(DRAWER_KEY, open ? "" : "1");
  };
  toggle.addEventListener("click", () => set(body.hidden));
  tall(false);
  set(localStorage.getItem(DRAWER_KEY) !== "1");
  // the editor fills the list (main.js); the bar counts what is in it
  new MutationObserver(() => {
    const errors = list.querySelectorAll(".diag-error").length;
    const warnings = list.querySelectorAll(".diag-warning").length;
    const all = list.querySelectorAll(".diag:not(.diag-none)").length;
    count.textContent = `(${all})`;
    const notice = list.querySelector(".diag-notice");  // the live check's own trouble (main.js) comes first
    status.textContent = notice ? notice.textContent : all ? t("drawer.summary", { errors, warnings, e: t(errors === 1 ? "drawer.error" : "drawer.errors"),
      w: t(warnings === 1 ? "drawer.warning" : "drawer.warnings") }) : t("diagnostics.none");
    status.className = `status-line${errors || notice ? " error" : ""}`;
  }).observe(list, { childList: true });
  return {
    open: () => { set(true); tall(true); },
    score(text) { const s = root.querySelector("#score-summary"); if (s) s.textContent = text; },
  };
}

// Printing: the program alone, with line numbers, under a heading (the print stylesheet in app.css). The
// editor shows only the lines in sight, so the program is printed from its text, not from the editor.
function printView(text, heading) {
  document.getElementById("print-view")?.remove();
  const view = el("div", { id: "print-view", className: "print-only" },
    el("h1", {}, heading),
    el("p", { className: "meta" }, new Date().toLocaleString(document.documentElement.lang === "en" ? "en-GB" : "de-DE")),
    el("ol", {}, ...text.replace(/\n$/, "").split("\n").map((line) => el("li", {}, line || " "))));
  document.body.append(view);
  document.body.classList.add("printing");
  window.addEventListener("afterprint", () => { document.body.classList.remove("printing"); view.remove(); }, { once: true });
}

export function printProgram(text, heading) {
  printView(text, heading);
  window.print();
}

// Save as a file on the trainee's computer (a download), open one from there (a file picker).
export function download(text, filename) {
  const url = URL.createObjectURL(new Blob([text], { type: "text/plain;charset=utf-8" }));
  const a = el("a", { href: url, download: filename });
  document.body.append(a);
  a.click();
  a.remove();
  setTimeout(() => URL.revokeObjectURL(url), 1000);
}

const MAX_FILE = 2_000_000;  // bytes: an NC program of 20,000 lines is far smaller

// The editor's toolbar: [leading …] Öffnen · Speichern · Drucken [· Zurücksetzen]
export function editorToolbar(bar, view, { filename, heading, reset = null, onOpen = null, leading = [] }) {
  const replace = (text) => view.dispatch({ changes: { from: 0, to: view.state.doc.length, insert: text } });
  const picker = el("input", { type: "file", id: "open-file", accept: ".nc,.txt,.mpf,.spf,.cnc,.h,.tap", className: "visually-hidden" });
  picker.tabIndex = -1;
  picker.setAttribute("aria-hidden", "true");
  const message = el("span", { className: "error", role: "status" });
  picker.addEventListener("change", async () => {
    const file = picker.files[0];
    picker.value = "";
    if (!file) return;
    if (file.size > MAX_FILE) { message.textContent = t("file.too_large"); return; }
    message.textContent = "";
    replace(await file.text());
    onOpen?.(file.name);
  });
  const button = (id, key, fn) => el("button", { type: "button", id, title: t(`${key}_title`), onclick: fn }, t(key));
  // the browser's own print (Ctrl+P) prints the program as the button does
  window.addEventListener("beforeprint", () => {
    if (!document.body.classList.contains("printing")) printView(view.state.doc.toString(), heading());
  });
  bar.replaceChildren(...[...leading,
    button("file-open", "file.open", () => picker.click()),
    button("file-save", "file.save", () => download(view.state.doc.toString(), filename())),
    button("file-print", "file.print", () => printProgram(view.state.doc.toString(), heading())),
    reset ? button("file-reset", "file.reset", () => {
      if (window.confirm(t("file.reset_confirm"))) replace(reset());
    }) : null,
    picker, message].filter(Boolean));
  return { replace };
}

// The dimensioned drawing: a sheet that fits the column (click: the Zeichnung tab), links to open and save it,
// and with `sheet` one to the printed task sheet (PDF).
export function drawingFigure(url, slug, onEnlarge = null, sheet = null) {
  const img = el("img", { src: url, alt: t("drawing.alt"), className: "drawing-sheet" });
  return el("figure", { className: "drawing" },
    onEnlarge ? el("button", { type: "button", className: "drawing-button", onclick: onEnlarge, title: t("drawing.enlarge") }, img) : img,
    el("figcaption", {},
      el("a", { href: drawingPageUrl(url), target: "_blank", rel: "noopener" }, t("drawing.open")),
      el("a", { href: `${url}&download=true`, download: `${slug}.svg` }, t("drawing.download")),
      sheetLink(sheet)));
}

function sheetLink(sheet) {
  return sheet ? el("a", { href: sheet, target: "_blank", rel: "noopener", title: t("drawing.sheet_title") }, t("drawing.sheet"))
    : null;
}

// The same drawing larger: fitted to the Zeichnung tab, zoom and move (drawing-viewer.js).
export function drawingZoom(url, slug, sheet = null) {
  return drawingViewer(url, { slug, sheet });
}

// The column splitters (from 1024 px, three columns): drag with the pointer or move with the arrow keys; the
// widths are remembered in the browser. Each column keeps at least 15 % of the width.
const SPLIT_KEY = "paltrainer-columns";
const DEFAULT_COLUMNS = [25, 35, 40];

export function mountSplitters(root) {
  let columns = DEFAULT_COLUMNS;
  try {
    const saved = JSON.parse(localStorage.getItem(SPLIT_KEY));
    if (Array.isArray(saved) && saved.length === 3 && saved.every((v) => v >= 15)) columns = saved;
  } catch { /* a damaged entry: the default */ }
  const apply = () => {
    columns.forEach((v, i) => root.style.setProperty(`--col-${i + 1}`, `${v}fr`));
    for (const handle of handles) handle.setAttribute("aria-valuenow", String(Math.round(handle.value())));
  };
  // handle 0 sits between task and editor, handle 1 between editor and 3D view
  const move = (index, percent) => {
    const [a, b] = [index, index + 1];
    const pair = columns[a] + columns[b];
    const start = columns.slice(0, a).reduce((s, v) => s + v, 0);
    const left = Math.max(15, Math.min(pair - 15, percent - start));
    columns = columns.map((v, i) => (i === a ? left : i === b ? pair - left : v));
    apply();
    localStorage.setItem(SPLIT_KEY, JSON.stringify(columns.map((v) => Math.round(v * 10) / 10)));
  };
  const handles = [root.querySelector(".editor-pane"), root.querySelector(".viz-pane")].map((pane, index) => {
    const handle = el("div", { className: "splitter", tabIndex: 0, title: t("split.title") });
    handle.setAttribute("role", "separator");
    handle.setAttribute("aria-orientation", "vertical");
    handle.setAttribute("aria-label", t(index ? "split.editor_viz" : "split.side_editor"));
    handle.setAttribute("aria-valuemin", "0");
    handle.setAttribute("aria-valuemax", "100");
    handle.value = () => columns.slice(0, index + 1).reduce((s, v) => s + v, 0);
    handle.addEventListener("pointerdown", (event) => {
      if (root.classList.contains("side-collapsed") && index === 0) return;
      event.preventDefault();
      handle.setPointerCapture(event.pointerId);
      root.classList.add("resizing");
      const box = root.getBoundingClientRect();
      const onMove = (e) => move(index, ((e.clientX - box.left) / box.width) * 100);
      handle.addEventListener("pointermove", onMove);
      handle.addEventListener("pointerup", () => {
        handle.removeEventListener("pointermove", onMove);
        root.classList.remove("resizing");
      }, { once: true });
    });
    handle.addEventListener("keydown", (event) => {
      const step = { ArrowLeft: -2, ArrowRight: 2 }[event.key];
      if (!step) return;
      event.preventDefault();
      move(index, handle.value() + step);
    });
    handle.addEventListener("dblclick", () => { columns = DEFAULT_COLUMNS; apply(); localStorage.removeItem(SPLIT_KEY); });
    pane.prepend(handle);
    return handle;
  });
  apply();
}
