// The exercise page: the side panel (Aufgabe with the drawing, Zeichnung large, Werkzeuge, Tipps), the editor
// with its toolbar, the 3D view, and the drawer with the messages and, after "Abgeben", the score.

import { api, el, table } from "./dom.js";
import { draftSaver, loadDraft } from "./drafts.js";
import { mountHints } from "./hints.js";
import { mountHistory } from "./history.js";
import { lang, message as message_, t } from "./i18n.js";
import { drawingFigure, drawingZoom, editorToolbar, mountDrawer, mountSideToggle, mountSplitters, mountTabs } from "./layout.js";
import { mountEditor } from "./main.js";
import { loginUrl } from "./redirect.js";
import { mountViz } from "./viz.js";
import { examContext, examNotice, mountExam, prepareExam } from "./page-exam.js";

export async function mountExercise(root, slug) {
  // a trainee in an exam gets the exam's page (page-exam.js): what it forbids goes before the tabs are mounted;
  // on another exercise during an exam with free practice the exam's settings still take away hints and 3D
  const [r, exam] = await Promise.all([api(`/exercises/${slug}`), examContext(slug)]);
  if (exam) prepareExam(root, exam);
  const showTab = mountTabs(root);
  mountSideToggle(root);
  mountSplitters(root);
  const drawer = mountDrawer(root);
  if (r.status === 401) {
    location.href = loginUrl();
    return;
  }
  if (!r.ok) {
    root.querySelector("#panel-task").replaceChildren(
      el("p", { className: "error" }, (r.body?.error && message_(r.body.error)) || t("exercise.missing")));
    return;
  }
  const ex = r.body;
  const title = lang === "en" && ex.title_en ? ex.title_en : ex.title_de;
  const task = lang === "en" && ex.task_en ? ex.task_en : ex.task_de;
  document.title = `PAL Trainer – ${title}`;
  const s = ex.stock;
  const size = s ? s.max.map((v, i) => Math.round((v - s.min[i]) * 1000) / 1000) : null;
  const tools = (ex.tools || []).map((tool) => {
    const cut = (ex.cutting_data || []).find((c) => c.tool === tool.number);
    return [`T${tool.number}`, tool.name || t(`kind.${tool.kind}`), `Ø${tool.diameter} mm`, cut ? cut.speed : "–",
      cut ? cut.feed : "–"];
  });
  root.querySelector("#title").textContent = title;
  // markdown paragraphs: blank lines separate them, single line breaks are spaces
  root.querySelector("#task").replaceChildren(
    ...task.split(/\n\s*\n/).filter((p) => p.trim()).map((p) => el("p", {}, p.replace(/\s*\n\s*/g, " "))));
  const toolTable = table([t("tools.tool"), t("tools.kind"), t("tools.diameter"), t("tools.speed"), t("tools.feed")],
    tools, [2, 3, 4]);
  root.querySelector("#data").replaceChildren(size ? el("p", {}, t("exercise.stock", { x: size[0], y: size[1], z: size[2] })) : null);
  root.querySelector("#tools").replaceChildren(el("h2", {}, t("tab.tools")),
    size ? el("p", {}, t("exercise.stock", { x: size[0], y: size[1], z: size[2] })) : null, toolTable);
  if (ex.gradable && size) {
    // the dimensioned drawing (server-side SVG from the reference): in the task first, as on a PAL task sheet
    const drawing = `/api/v1/exercises/${slug}/drawing.svg?lang=${lang}`;
    const sheet = `/api/v1/exercises/${slug}/sheet.pdf?lang=${lang}`;  // task, drawing and programming form to print
    root.querySelector("#picture").replaceChildren(drawingFigure(drawing, slug, () => showTab("tab-drawing"), sheet));
    root.querySelector("#drawing-large").replaceChildren(drawingZoom(drawing, slug, sheet));
  } else {
    root.querySelector("#drawing-large").replaceChildren(el("p", { className: "meta" }, t("drawing.none")));
  }
  if (exam?.blocked || exam?.phase === "upcoming") {
    examNotice(root, exam);
    return;
  }
  if (exam && !exam.during) {
    await mountExam(root, slug, ex, exam, { drawer, title });
    return;
  }
  const list = root.querySelector("#diagnostics");
  let scene = null;
  // the draft (server or browser, the newer) or the start program; every change is kept (drafts.js). The
  // practice draft; should the server answer with a running exam's draft, the saver keeps to that exam.
  const start = ex.start_program || "";
  const draft = await loadDraft(slug);
  const saver = draftSaver(slug, draft.user, start, draft.program, draft.pending, null, draft.assignment);
  const view = await mountEditor(root.querySelector("#editor"), {
    text: draft.program ?? start, dialect: ex.dialect, list, exercise: slug,
    locked: ex.kind === "complete" ? { lines: ex.locked_lines, start } : null,
    onChange: (text) => { saver.changed(text); scene?.changed(text); }, onPointer: (line) => scene?.pointer(line),
  });
  const toolbar = editorToolbar(root.querySelector("#editor-toolbar"), view, {
    filename: () => `${slug}.nc`, heading: () => title, reset: () => { saver.forget(); return start; },
  });
  const goLine = (n) => {
    const line = view.state.doc.line(Math.min(n, view.state.doc.lines));
    view.dispatch({ selection: { anchor: line.from }, scrollIntoView: true });
    view.focus();
  };
  // "Meine Abgaben" (history.js): an earlier submission back into the editor
  // (while an exam runs elsewhere its settings may have taken away the Tipps tab and the 3D view: prepareExam)
  const history = root.querySelector("#my-submissions")
    ? mountHistory(root.querySelector("#my-submissions"), slug, { load: (program) => toolbar.replace(program), onLine: goLine })
    : null;
  if (root.querySelector("#hints")) mountHints(root.querySelector("#hints"), { ...ex, slug }, { program: () => view.state.doc.toString() });
  if (!root.querySelector(".viz-pane").hidden) scene = await mountViz(root.querySelector("#viz"), view, { dialect: ex.dialect, exercise: slug });
  const result = root.querySelector("#result");
  root.querySelector("#submit").onclick = async () => {
    drawer.open();
    drawer.score("");
    result.replaceChildren(el("p", {}, t("submit.busy")));
    const sub = await api("/submissions", {
      method: "POST", headers: { "Content-Type": "application/json" },
      body: JSON.stringify({ exercise: slug, program: view.state.doc.toString() }),
    });
    if (!sub.ok) {
      result.replaceChildren(el("p", { className: "error" }, (sub.body?.error && message_(sub.body.error)) || t("submit.failed")));
      return;
    }
    history?.refresh();
    const g = sub.body.grading;
    if (!g) {
      result.replaceChildren(el("p", {}, t("submit.ungraded")));
      return;
    }
    scene?.graded(view.state.doc.toString());
    drawer.score(t("score.short", { score: g.score, max: g.max_score }));
    result.replaceChildren(
      el("p", { className: "score" }, t("score", { score: g.score, max: g.max_score })),
      el("ul", { className: "criteria" }, ...g.criteria.map((c) => el("li", { className: c.status },
        `${c.status === "passed" ? "✓" : "✗"} ${c.points}/${c.max_points} – ${message_(c)}`,
        ...c.lines.map((n) => el("button", {
          className: "line-link", type: "button", textContent: t("diagnostics.line", { n }),
          onclick: () => {
            const line = view.state.doc.line(Math.min(n, view.state.doc.lines));
            view.dispatch({ selection: { anchor: line.from }, scrollIntoView: true });
            view.focus();
          },
        }))))));
  };
}
