// The exercise page: the side panel (Aufgabe with the drawing, Zeichnung large, Werkzeuge, Tipps), the editor
// with its toolbar, the 3D view, and the drawer with the messages and the result: after "Abgeben", and on load
// the newest submission's (its score in the drawer's bar).

import { api, el } from "./dom.js";
import { draftSaver, loadDraft } from "./drafts.js";
import { editorLine, resultBlock } from "./grades.js";
import { mountHints } from "./hints.js";
import { mountHistory, mySubmissions } from "./history.js";
import { lang, message as message_, t } from "./i18n.js";
import { drawingFigure, drawingZoom, editorToolbar, mountDrawer, mountSideToggle, mountSplitters, mountTabs } from "./layout.js";
import { mountEditor } from "./main.js";
import { formatDecimal } from "./numbers.js";
import { loginUrl } from "./redirect.js";
import { LATHE_DIALECTS } from "./tool-kinds.js";
import { mountViz } from "./viz.js";
import { examContext } from "./exam.js";
import { examNotice, mountExam, prepareExam } from "./page-exam.js";  // the exam's page at the exercise's address

// The Werkzeuge tab: one small table per tool, so that it fits the side panel. Milling: the diameter, S (1/min),
// F (mm/min) and the spindle's direction. Turning, what a turner reads: the insert, its nose radius and cutting
// position (quadrant), the cutting speed V (G96) or the speed S (G97), the feed F and the reduced feed E in mm/U
// (which feeds the reference writes as E: the server's tool_feeds, as on the printed sheet) and the direction.
// Every cutting-data entry of a tool is shown (several allowed values side by side); nothing empty is shown.
const INSERT_ANGLES = { C: 80, D: 55, V: 35 };  // the rhombic inserts' corner angle (docs/tools.md)
const given = (v) => v !== null && v !== undefined && v !== "" && !(typeof v === "number" && !Number.isFinite(v));
const joined = (values) => [...new Set(values.filter(given).map(String))].join(" / ");
const number = (v) => (typeof v === "number" && Number.isFinite(v) ? formatDecimal(v) : null);

function toolName(tool) {
  const text = tool.kind ? t(`kind.${tool.kind}`) : "";
  const kind = text.startsWith("kind.") ? "" : text;
  // a tool's own name is German ("Schruppmeißel D R0,8"); the English page names its kind
  return (lang === "en" ? kind || tool.name : tool.name || kind) || "";
}

function insertText(tool) {
  if (tool.insert === "groove") {
    const width = number(tool.width);
    return width ? `${t("tools.insert_groove")}, ${t("tools.insert_width")} ${width} mm` : t("tools.insert_groove");
  }
  if (tool.insert === "thread") return `${t("tools.insert_thread")} (60°)`;
  const letter = tool.insert || "C";
  const angle = number(tool.insert_angle) || number(INSERT_ANGLES[letter]);
  return angle ? `${letter} (${angle}°)` : letter;
}

function latheRows(tool, cuts, feeds) {
  const rows = [];
  if (tool.kind === "turning") {
    rows.push([t("tools.insert"), insertText(tool)]);
    if (tool.nose_radius > 0) rows.push([t("tools.nose_radius"), `R${number(tool.nose_radius)} mm`]);
    if (tool.quadrant) rows.push([t("tools.quadrant"), `P${tool.quadrant}`]);
  } else if (tool.diameter > 0) {
    rows.push([t("tools.diameter"), `Ø${number(tool.diameter)} mm`]);
  }
  const v = joined(cuts.map((c) => number(c.cutting_speed)));
  const s = joined(cuts.map((c) => number(c.speed)));
  if (v) rows.push([t("tools.v"), t("tools.v_value", { v })]);
  if (s) rows.push([t("tools.s"), t("tools.s_value", { s })]);
  // F and E as the reference writes them; without the server's word every entry's feed is an F
  const f = joined((feeds ? feeds.feed || [] : cuts.map((c) => c.feed)).map(number));
  const e = joined((feeds?.reduced || []).map(number));
  if (f) rows.push([t("tools.f"), t("tools.f_value", { f })]);
  if (e) rows.push([t("tools.e"), t("tools.e_value", { e })]);
  const spindle = joined(cuts.map((c) => c.spindle)) || feeds?.spindle;
  if (spindle) rows.push([t("tools.spindle"), spindle.split(" / ").map((m) => t(`spindle.${m}`)).join(" / ")]);
  return rows;
}

function millRows(tool, cuts) {
  const spindle = joined(cuts.map((c) => c.spindle));
  return [
    [t("tools.diameter"), tool.diameter > 0 ? `Ø${number(tool.diameter)} mm` : ""],
    [t("tools.speed"), joined(cuts.map((c) => number(c.speed)))],
    [t("tools.feed"), joined(cuts.map((c) => number(c.feed)))],
    [t("tools.spindle"), spindle ? spindle.split(" / ").map((m) => t(`spindle.${m}`)).join(" / ") : ""],
  ];
}

function toolTables(ex) {
  const lathe = LATHE_DIALECTS.has(ex.dialect);
  const data = (ex.cutting_data || []).filter((c) => c && given(c.tool));
  const tools = [...(ex.tools || [])].filter((tool) => tool && given(tool.number));
  for (const c of data) {  // cutting data of a tool from the default table
    if (!tools.some((tool) => tool.number === c.tool)) tools.push({ number: c.tool });
  }
  if (!tools.length) return el("p", { className: "meta" }, t("tools.none"));
  return el("div", { className: "tool-cards" }, ...tools.map((tool) => {
    const cuts = data.filter((c) => c.tool === tool.number);
    const feeds = ex.tool_feeds?.[String(tool.number)] || null;
    const rows = (lathe ? latheRows(tool, cuts, feeds) : millRows(tool, cuts)).filter(([, value]) => value);
    const name = toolName(tool);
    return el("table", { className: lathe ? "tool-card lathe" : "tool-card" },
      el("thead", {}, el("tr", {}, el("th", { colSpan: 2, scope: "colgroup" }, `T${tool.number}${name ? ` · ${name}` : ""}`))),
      el("tbody", {}, ...rows.map(([key, value]) => el("tr", {}, el("th", { scope: "row" }, key), el("td", {}, value)))));
  }));
}

// The task's text: the server's safe HTML of its Markdown (core/sheet/tasktext.py: raw HTML off, https links only),
// inserted as it is, as the printed sheet shows it.
function taskBody(ex) {
  const html = lang === "en" ? ex.task_html_en || ex.task_html_de : ex.task_html_de;
  const body = el("div");
  if (html) {
    body.innerHTML = html;
  } else {  // an older answer without it: the text as paragraphs
    const task = (lang === "en" && ex.task_en) || ex.task_de || "";
    body.append(...task.split(/\n\s*\n/).filter((p) => p.trim()).map((p) => el("p", {}, p.replace(/\s*\n\s*/g, " "))));
  }
  return [...body.childNodes];
}

// The blank and the workpiece zero ("Rohteil: Stange Ø100 × 160 mm, 30 mm im Futter"): above the task only where
// its text does not state the blank already; in the Werkzeuge tab always, with the tools.
function blankLines(ex, always) {
  const en = lang === "en";
  const blank = en ? ex.blank_en || ex.blank_de : ex.blank_de;
  const zero = en ? ex.zero_en || ex.zero_de : ex.zero_de;
  if (!always && (en ? ex.blank_in_task_en : ex.blank_in_task_de)) return [];
  return [blank, zero].filter((text) => typeof text === "string" && text).map((text) => el("p", {}, text));
}

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
  document.title = `PAL Trainer – ${title}`;
  const s = ex.stock;
  const size = s ? s.max.map((v, i) => Math.round((v - s.min[i]) * 1000) / 1000) : null;
  root.querySelector("#title").textContent = title;
  root.querySelector("#task").replaceChildren(...taskBody(ex));
  root.querySelector("#data").replaceChildren(...blankLines(ex, false));
  root.querySelector("#tools").replaceChildren(el("h2", {}, t("tab.tools")),
    el("div", { className: "meta" }, ...blankLines(ex, true)), toolTables(ex));
  if (ex.gradable && size) {
    // the dimensioned drawing (server-side SVG from the reference): in the task first, as on a PAL task sheet
    const drawing = `/api/v1/exercises/${slug}/drawing.svg?lang=${lang}`;
    const sheet = `/api/v1/exercises/${slug}/sheet.pdf?lang=${lang}`;  // task, drawing and programming form to print
    root.querySelector("#picture").replaceChildren(drawingFigure(drawing, slug, () => showTab("tab-drawing"), sheet));
    if (ex.own_drawing === "application/pdf") {  // the author's own drawing is a PDF: opened as it is
      root.querySelector("#picture figcaption")?.append(el("a", { href: `/api/v1/exercises/${slug}/own-drawing`,
        target: "_blank", rel: "noopener", id: "own-drawing-pdf" }, t("drawing.own_pdf")));
    }
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
  const earlier = mySubmissions(slug);  // the newest one's result goes into the drawer; "Meine Abgaben" lists them
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
  const goLine = editorLine(view);
  // "Meine Abgaben" (history.js): an earlier submission back into the editor
  // (while an exam runs elsewhere its settings may have taken away the Tipps tab and the 3D view: prepareExam)
  const history = root.querySelector("#my-submissions")
    ? mountHistory(root.querySelector("#my-submissions"), slug,
      { load: (program) => toolbar.replace(program), onLine: goLine, first: earlier })
    : null;
  if (root.querySelector("#hints")) mountHints(root.querySelector("#hints"), { ...ex, slug }, { program: () => view.state.doc.toString() });
  if (!root.querySelector(".viz-pane").hidden) scene = await mountViz(root.querySelector("#viz"), view, { dialect: ex.dialect, exercise: slug });
  const result = root.querySelector("#result");
  // the result of the newest submission, as after "Abgeben" (the drawer is not opened for it; its bar shows the
  // score); not one held by an exam, nor once the trainee has submitted again
  let submitted = false;
  earlier.then((r) => {
    const last = r.ok ? r.body[0] : null;
    if (submitted || !last || last.held || last.score === null || last.score === undefined) return;
    drawer.score(t("score.short", { score: last.score, max: last.max_score }));
    result.replaceChildren(...resultBlock(last, goLine, { when: last.created_at }));
  });
  root.querySelector("#submit").onclick = async () => {
    submitted = true;
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
    const score = sub.body.score ?? g.score;
    drawer.score(t("score.short", { score, max: g.max_score }));
    result.replaceChildren(...resultBlock({ score, max_score: g.max_score, criteria: g.criteria, override: sub.body.override },
      goLine));
  };
}
