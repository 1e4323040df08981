// The page's state across the reload that switches the language: the program in the editor and whether the 3D
// view is on, kept for this tab (sessionStorage) just before the reload and put back once the page is mounted.

import { EditorView } from "@codemirror/view";

const KEY = "paltrainer-page-state";
const here = () => location.pathname + location.search;

function editorView() {
  const dom = /** @type {HTMLElement | null} */ (document.querySelector(".cm-editor"));
  return dom ? EditorView.findFromDOM(dom) : null;
}

function vizOn() {  // the 3D view offers "off" while it is on and "on" while it is off
  if (document.getElementById("viz-off")) return true;
  if (document.getElementById("viz-on")) return false;
  return null;
}

export function keepState() {
  const view = editorView();
  sessionStorage.setItem(KEY, JSON.stringify({ path: here(), program: view ? view.state.doc.toString() : null, viz: vizOn() }));
}

export function restoreState() {
  let saved = null;
  try { saved = JSON.parse(sessionStorage.getItem(KEY)); } catch { /* a damaged entry: nothing to restore */ }
  sessionStorage.removeItem(KEY);
  if (!saved || saved.path !== here()) return;
  const view = editorView();
  if (view && typeof saved.program === "string" && saved.program !== view.state.doc.toString()) {
    view.dispatch({ changes: { from: 0, to: view.state.doc.length, insert: saved.program } });
  }
  const now = vizOn();
  if (saved.viz === true && now === false) document.getElementById("viz-on").click();
  if (saved.viz === false && now === true) document.getElementById("viz-off").click();
}
