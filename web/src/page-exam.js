// The exercise page during an exam (an assignment in mode "exam"): the task, the drawing, the editor with
// highlighting only and a countdown to the server's end; the exam's settings decide what else is there
// (live messages, 3D view, hints; the number of submissions). After the end the page says that the last saved
// draft was submitted (the server does it, also when the browser was closed); once the instructor releases
// the results it shows the score, the criteria and the 3D view of the submitted program.
// page-exercise.js asks examContext() first and hands over to mountExam().

import { api, el } from "./dom.js";
import { draftSaver, loadDraft } from "./drafts.js";
import { mountHints } from "./hints.js";
import { criteriaList } from "./history.js";
import { lang, message, t } from "./i18n.js";
import { editorToolbar } from "./layout.js";
import { mountEditor, setReadOnly } from "./main.js";
import { mountViz } from "./viz.js";
import "./texts-exam.js";

// 5400 → "1:30:00", 59 → "00:59"
export function clock(seconds) {
  const s = Math.max(0, Math.round(seconds));
  const two = (n) => String(n).padStart(2, "0");
  const [h, m] = [Math.floor(s / 3600), Math.floor((s % 3600) / 60)];
  return h ? `${h}:${two(m)}:${two(s % 60)}` : `${two(m)}:${two(s % 60)}`;
}

export function formatTime(iso) {
  return new Date(iso).toLocaleString(lang === "en" ? "en-GB" : "de-DE", { dateStyle: "medium", timeStyle: "short" });
}

// What this exercise page is for a trainee: null (an ordinary exercise), {blocked: exam} (an exam without
// free practice runs and this exercise is not in it), or {exam, item, phase} with phase "upcoming",
// "running", "over" (results held) or "released". ?assignment=ID (the home page's links) names the exam.
export async function examContext(slug) {
  if (document.body.dataset.role !== "student") return null;
  const r = await api("/me/assignments");
  if (!r.ok) return null;
  const wanted = Number(new URLSearchParams(location.search).get("assignment")) || null;
  const exams = r.body.filter((a) => a.mode === "exam");
  const running = exams.find((a) => a.seconds_left !== null);
  if (running && !running.exercises.includes(slug) && !running.settings.free_practice) return { blocked: running };
  const has = (a) => a.exercises.includes(slug);
  const exam = (running && has(running) ? running : null) || exams.find((a) => a.id === wanted && has(a))
    || exams.find((a) => has(a) && !a.released && a.status !== "upcoming");
  if (!exam) return null;
  const phase = exam.status === "upcoming" ? "upcoming" : exam.seconds_left !== null ? "running"
    : exam.results_visible ? "released" : "over";
  return { exam, phase, item: exam.items.find((i) => i.exercise === slug) };
}

// Before the page's tabs and panes are mounted: take away what the exam does not allow.
export function prepareExam(root, ctx) {
  document.body.classList.add("exam-page");
  if (ctx.blocked || ctx.phase === "upcoming") return;
  const s = ctx.exam.settings;
  const running = ctx.phase === "running";
  root.classList.add("exam-mode");
  if (!(running && s.hints)) {  // hints and "Meine Abgaben" (its earlier submissions would show scores)
    root.querySelector("#tab-hints")?.remove();
    root.querySelector("#panel-hints")?.remove();
  }
  if (!(running && s.live_diagnostics)) {  // no messages panel: the drawer holds the result only
    root.classList.add("no-live");
    root.querySelector("#drawer-toggle [data-i18n]").textContent = t("result.title");
  }
  if ((running && !s.viz) || ctx.phase === "over") {
    root.classList.add("no-viz");
    root.querySelector(".viz-pane").hidden = true;
  }
  if (running && !s.free_practice) document.getElementById("nav-practice")?.setAttribute("hidden", "");
}

// The page when it is not the exam's (blocked, not yet started): a message where the editor would be.
export function examNotice(root, ctx) {
  const a = ctx.blocked || ctx.exam;
  const text = ctx.blocked ? t("exam.blocked", { title: a.title }) : t("exam.upcoming", { title: a.title, time: formatTime(a.opens_at) });
  if (!ctx.blocked) root.querySelector("#panel-task").replaceChildren(el("h2", {}, a.title));  // the task from the start
  root.querySelector(".editor-pane").replaceChildren(el("div", { className: "exam-notice" },
    el("p", { role: "status" }, text), el("p", {}, el("a", { href: `/exercises/${a.exercises[0]}?assignment=${a.id}` }, t("home.to_exam")))));
  root.querySelector("#submit").hidden = true;
}

// Free practice while an exam without it runs for the trainee: a notice with the way to the exam instead of the
// editor (true), else nothing happens (false).
export async function practiceBlocked(root) {
  if (document.body.dataset.role !== "student") return false;
  const r = await api("/me/assignments");
  const exam = r.ok ? r.body.find((a) => a.mode === "exam" && a.seconds_left !== null && !a.settings.free_practice) : null;
  if (!exam) return false;
  document.getElementById("nav-practice")?.setAttribute("hidden", "");
  root.className = "narrow";
  root.replaceChildren(el("div", { className: "exam-notice" },
    el("h2", {}, t("nav.practice")),
    el("p", { role: "status" }, t("exam.no_practice", { title: exam.title })),
    el("p", {}, el("a", { href: `/exercises/${exam.exercises[0]}?assignment=${exam.id}` }, t("home.to_exam")))));
  return true;
}

function rules(s) {
  return [!s.live_diagnostics && t("exam.rule.live"), !s.viz && t("exam.rule.viz"), !s.hints && t("exam.rule.hints"),
    s.max_submissions === 1 ? t("exam.rule.one") : s.max_submissions ? t("exam.rule.n", { n: s.max_submissions }) : null]
    .filter(Boolean).join(" · ");
}

export async function mountExam(root, slug, ex, ctx, { drawer, title }) {
  const { exam: a, phase } = ctx;
  let item = ctx.item;
  const s = a.settings;
  const start = ex.start_program || "";
  const list = root.querySelector("#diagnostics");
  const result = root.querySelector("#result");
  const submit = root.querySelector("#submit");
  const countdown = el("span", { id: "countdown", className: "countdown", role: "timer" });
  const saved = el("span", { id: "save-state", className: "meta", role: "status" });
  const note = el("p", { id: "exam-message", className: "exam-message", role: "status" });
  root.querySelector(".editor-pane").insertBefore(el("div", { className: "exam-bar", id: "exam-bar" },
    el("div", { className: "exam-head" }, el("strong", {}, t("exam.title", { title: a.title })),
      phase === "running" ? countdown : null,
      el("span", { className: "meta" }, t("exam.ends", { time: formatTime(a.deadline) })), saved),
    phase === "running" ? el("p", { className: "meta exam-rules" }, t("exam.rules", { rules: rules(s) })) : null,
    note), root.querySelector("#editor-toolbar"));
  submit.hidden = phase !== "running";
  // the countdown once more in the drawer's bar: on a tablet that bar stays in sight while the task is read
  const barClock = el("span", { className: "countdown countdown-bar" });
  barClock.setAttribute("aria-hidden", "true");  // the timer above is the one for screen readers
  if (phase === "running") submit.before(barClock);

  if (phase !== "running") {  // over or released: the program as it was, read only
    const draft = phase === "over" ? await loadDraft(slug) : null;
    const program = item?.program ?? draft?.program ?? "";
    const view = await mountEditor(root.querySelector("#editor"), {
      text: program, dialect: ex.dialect, exercise: slug, live: false, readOnly: true,
    });
    if (phase === "over") {
      note.textContent = `${t(item?.submitted ? (item.auto ? "exam.over" : "exam.over_submitted") : "exam.over_nothing")} `
        + (item?.submitted ? t("exam.held") : "");
      return;
    }
    note.textContent = `${t("exam.released", { title: a.title })}. ${item?.submitted ? t("exam.your_program") : t("exam.none_submitted")}`;
    if (!item?.submitted) return;
    showResult(item, view, drawer, result);
    const scene = await mountViz(root.querySelector("#viz"), view, { dialect: ex.dialect, exercise: slug });
    scene?.graded(program);
    return;
  }

  // running: drafts save as usual (the server submits the last one at the end), the countdown runs
  const draft = await loadDraft(slug);
  const saver = draftSaver(slug, draft.user, start, draft.program, draft.pending, (state, error) => {
    const time = new Date().toLocaleTimeString(lang === "en" ? "en-GB" : "de-DE", { timeStyle: "short" });
    saved.textContent = state === "refused" ? t("exam.refused", { message: message(error) || "" }) : t(`exam.${state}`, { time });
    saved.className = state === "refused" || state === "offline" ? "error" : "meta";
  });
  const limit = s.max_submissions || 0;
  const used = () => limit && item?.submitted && limit <= 1;  // the trainee's list tells submitted or not, not how often
  let scene = null;
  const view = await mountEditor(root.querySelector("#editor"), {
    text: draft.program ?? start, dialect: ex.dialect, list, exercise: slug, live: Boolean(s.live_diagnostics),
    locked: ex.kind === "complete" ? { lines: ex.locked_lines, start } : null, readOnly: Boolean(used()),
    onChange: (text) => { saver.changed(text); scene?.changed(text); }, onPointer: (line) => scene?.pointer(line),
  });
  const toolbar = root.querySelector("#editor-toolbar");
  editorToolbar(toolbar, view, { filename: () => `${slug}.nc`, heading: () => title, reset: () => { saver.forget(); return start; } });
  toolbar.querySelector("#file-open")?.remove();  // no prepared programs from the computer during an exam
  if (s.hints) mountHints(root.querySelector("#hints"), { ...ex, slug }, { program: () => view.state.doc.toString() });
  if (s.viz) scene = await mountViz(root.querySelector("#viz"), view, { dialect: ex.dialect, exercise: slug });
  const held = () => { submit.disabled = true; note.textContent = t("exam.submitted"); };
  if (used()) held();

  let armed = null;  // one submission: the first click asks, the second submits
  submit.onclick = async () => {
    if (limit === 1 && !armed) {
      submit.textContent = t("exam.confirm");
      submit.title = t("exam.confirm_title");
      armed = setTimeout(() => { armed = null; submit.textContent = t("submit"); submit.title = ""; }, 6000);
      return;
    }
    clearTimeout(armed);
    armed = null;
    submit.textContent = t("submit");
    submit.disabled = true;
    const r = await api("/submissions", {
      method: "POST", headers: { "Content-Type": "application/json" },
      body: JSON.stringify({ exercise: slug, program: view.state.doc.toString(), assignment: a.id }),
    });
    drawer.open();
    if (!r.ok) {
      submit.disabled = false;
      result.replaceChildren(el("p", { className: "error" }, (r.body?.error && message(r.body.error)) || t("submit.failed")));
      return;
    }
    item = { ...item, submitted: true };
    result.replaceChildren(el("p", {}, t("exam.submitted")));
    if (used()) { held(); setReadOnly(view, true); }
    else submit.disabled = false;
  };

  // the countdown to the server's end (its seconds_left, so the computer's clock does not matter)
  const endAt = Date.now() + a.seconds_left * 1000;
  const tick = () => {
    const left = (endAt - Date.now()) / 1000;
    countdown.textContent = t("exam.left", { left: clock(Math.ceil(left)) });
    barClock.textContent = clock(Math.ceil(left));
    for (const c of [countdown, barClock]) c.classList.toggle("soon", left < 300);
    if (left > 0) return;
    clearInterval(timer);
    ended();
  };
  const timer = setInterval(tick, 1000);
  tick();

  async function ended() {
    saver.stop();
    setReadOnly(view, true);
    submit.disabled = true;
    note.textContent = t("exam.over");
    // the server's word on it: reading the list finalises the exam (retry while the server's end is not there)
    for (let i = 0; i < 10; i += 1) {
      await new Promise((done) => { setTimeout(done, 2000); });
      const r = await api("/me/assignments");
      const now = r.ok ? r.body.find((x) => x.id === a.id) : null;
      if (!now || now.seconds_left !== null) continue;
      const mine = now.items.find((x) => x.exercise === slug);
      note.textContent = `${t(mine?.submitted ? (mine.auto ? "exam.over" : "exam.over_submitted") : "exam.over_nothing")} `
        + (mine?.submitted ? t("exam.held") : "");
      note.dataset.confirmed = "true";  // the server's end has come and its list says what was submitted
      return;
    }
  }
}

function showResult(item, view, drawer, result) {
  const goLine = (n) => {
    const line = view.state.doc.line(Math.min(n, view.state.doc.lines));
    view.dispatch({ selection: { anchor: line.from }, scrollIntoView: true });
    view.focus();
  };
  drawer.open();
  if (item.score === null) {
    result.replaceChildren(el("p", {}, t("submit.ungraded")));
    return;
  }
  drawer.score(`${item.score}/${item.max_score}`);  // the bar already says "Ergebnis"
  result.replaceChildren(el("p", { className: "score" }, t("score", { score: item.score, max: item.max_score })),
    criteriaList(item.criteria || [], goLine));
}
