// Starts the page: every page names itself in <body data-page="…"> and this mounts it. The pages carry no
// inline script, so that the Content-Security-Policy can forbid inline script (script-src 'self').

import { mountEditor, setTools } from "./main.js";
import {
  mountExercise, mountExerciseList, mountInstructor, mountLogin, mountPracticeSetup, mountViz,
} from "./pages.js";

const SAMPLE = "N10 T1 TC1 M6\nN20 S1200 F150 M3\nN30 G0 X-25 Y-15 Z2\nN40 G42 G0 X-14 Y10\nN50 G0 Z-2\n" +
  "N60 G1 X70 Y10 RN20\nN70 G1 Y84\nN80 G40\nN90 G0 X250 Y150 Z250 M30\n";

async function mountPractice() {
  const params = new URLSearchParams(location.search);
  const select = document.getElementById("dialect");
  select.value = params.get("dialect") || "pal-mill";
  select.onchange = () => { location.search = `?dialect=${select.value}`; };
  // the program is kept in the browser per dialect: a reload loses nothing
  const saved = `paltrainer-practice-${select.value}`;
  let scene = null;
  const setup = mountPracticeSetup(document.getElementById("setup"), (next) => {
    setTools(window.editor, next.tools.length ? next.tools : null);
    scene?.setup(next);
  });
  window.editor = await mountEditor(document.getElementById("editor"), {
    text: localStorage.getItem(saved) ?? (select.value === "pal-mill" ? SAMPLE : ""), dialect: select.value,
    tools: setup.tools.length ? setup.tools : null, list: document.getElementById("diagnostics"),
    onChange: (text) => { localStorage.setItem(saved, text); scene?.changed(text); },
    onPointer: (line) => scene?.pointer(line),
  });
  scene = await mountViz(document.getElementById("viz"), window.editor, { dialect: select.value, setup });
}

const PAGES = {
  practice: mountPractice,
  exercise: () => mountExercise(document.getElementById("exercise"),
    decodeURIComponent(location.pathname.split("/").pop())),
  exercises: () => mountExerciseList(document.getElementById("list")),
  instructor: () => mountInstructor(document.getElementById("submissions")),
  login: () => mountLogin(document.getElementById("login"), document.getElementById("message")),
};

export function boot() {
  return PAGES[document.body.dataset.page]?.();
}
