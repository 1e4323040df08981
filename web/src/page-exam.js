// The exercise page during an exam (an assignment in mode "exam"): the task, the drawing, the editor with
// highlighting only and a countdown to the server's end; the exam's settings decide what else is there
// (live messages, 3D view, hints; the number of submissions). The editor starts from the exam's own draft or
// the start program, never from a practice draft, and saves into the exam. After the end the editor is read
// only, "Abgeben" is gone, and the page says "wird abgegeben" until the server has submitted the last saved
// drafts (also when the browser was closed), then what it submitted; once the instructor releases the results
// it shows the score, the criteria and the 3D view of the submitted program.
// page-exercise.js asks examContext() (exam.js) first and hands over to mountExam().

import { api, el } from "./dom.js";
import { clock, formatTime, myAssignments, untilStart } from "./exam.js";
import { draftSaver, loadDraft } from "./drafts.js";
import { mountHints } from "./hints.js";
import { editorLine, resultBlock } from "./grades.js";
import { lang, message, t } from "./i18n.js";
import { editorToolbar } from "./layout.js";
import { mountEditor, setReadOnly } from "./main.js";
import { mountViz } from "./viz.js";

const dropHints = (root) => {  // the Tipps tab with its panel ("Meine Abgaben" would show scores too)
  root.querySelector("#tab-hints")?.remove();
  root.querySelector("#panel-hints")?.remove();
};

const hideViz = (root) => {
  root.classList.add("no-viz");
  root.querySelector(".viz-pane").hidden = true;
};

// Before the page's tabs and panes are mounted: take away what the exam does not allow.
export function prepareExam(root, ctx) {
  if (ctx.during) {  // another exercise during exams with free practice: their switches hold here too
    if (ctx.during.some((a) => !a.settings.hints)) dropHints(root);
    if (ctx.during.some((a) => !a.settings.viz)) hideViz(root);
    return;
  }
  document.body.classList.add("exam-page");
  if (ctx.blocked || ctx.phase === "upcoming") return;
  const s = ctx.exam.settings;
  const running = ctx.phase === "running";
  root.classList.add("exam-mode");
  if (!(running && s.hints)) dropHints(root);
  if (!(running && s.live_diagnostics)) {  // no messages panel: the drawer holds the result only
    root.classList.add("no-live");
    root.querySelector("#drawer-toggle [data-i18n]").textContent = t("result.title");
  }
  if ((running && !s.viz) || ctx.phase === "over") hideViz(root);
  if (running && !s.free_practice) document.getElementById("nav-practice")?.setAttribute("hidden", "");
}

// The page when it is not the exam's (blocked, not yet started): a message where the editor would be. Before
// its start an exam names no exercises: the page opens anew at the start.
export function examNotice(root, ctx) {
  const a = ctx.blocked || ctx.exam;
  const text = ctx.blocked ? t("exam.blocked", { title: a.title }) : t("exam.upcoming", { title: a.title, time: formatTime(a.opens_at) });
  if (!ctx.blocked) root.querySelector("#panel-task").replaceChildren(el("h2", {}, a.title));  // the task from the start
  root.querySelector(".editor-pane").replaceChildren(el("div", { className: "exam-notice" },
    el("p", { role: "status" }, text),
    ctx.blocked ? el("p", {}, el("a", { href: `/exercises/${a.exercises[0]}?assignment=${a.id}` }, t("home.to_exam")))
      : el("p", { className: "meta" }, t("exam.opens_here"))));
  root.querySelector("#submit").hidden = true;
  const wait = untilStart(a);
  if (!ctx.blocked && wait < 24 * 3600 * 1000) setTimeout(() => location.reload(), Math.max(wait, 0) + 1500);
}

// What the server reports for the trainee's exercise once the exam is over and its drafts are submitted.
function verdict(item) {
  const over = t(item?.submitted ? (item.auto ? "exam.over" : "exam.over_submitted") : "exam.over_nothing");
  return item?.submitted ? `${over} ${t("exam.held")}` : over;
}

const pause = (ms) => new Promise((done) => { setTimeout(done, ms); });
const RECHECK = 15000;  // ms between two looks at the exam's end while it runs (an instructor may change it)
const POLL = 2000;  // ms between two looks at the list while the server submits
const POLLS = 60;  // about 2 minutes, then the start page has the answer

// After the end: "wird abgegeben" while the server submits the last saved drafts (status "submitting"; it does so
// a few seconds after the end, whether anybody looks or not), then what it reports. `now`: the exam as the list
// said when the page opened (null: the countdown just ended; the list is asked in 2 s).
async function awaitVerdict(note, examId, slug, now) {
  for (let i = 0; i <= POLLS; i += 1) {
    if (now && now.seconds_left === null && now.status !== "submitting") {
      note.textContent = verdict(now.items.find((x) => x.exercise === slug));
      note.dataset.confirmed = "true";  // the server's end has come and its list says what was submitted
      return;
    }
    note.textContent = t("exam.submitting");
    if (i === POLLS) break;
    await pause(POLL);
    now = (await myAssignments(true))?.find((x) => x.id === examId) ?? null;
  }
  note.textContent = t("exam.submitting_slow");
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
      el("span", { id: "exam-ends", className: "meta" }, t("exam.ends", { time: formatTime(a.deadline) })), saved),
    phase === "running" ? el("p", { className: "meta exam-rules" }, t("exam.rules", { rules: rules(s) })) : null,
    note), root.querySelector("#editor-toolbar"));
  submit.hidden = phase !== "running";
  // the countdown once more in the drawer's bar: on a tablet that bar stays in sight while the task is read
  const barClock = el("span", { className: "countdown countdown-bar" });
  barClock.setAttribute("aria-hidden", "true");  // the timer above is the one for screen readers
  if (phase === "running") submit.before(barClock);

  if (phase !== "running") {  // over or released: the program as it was, read only
    // held: the exam's own draft as the server kept it (what it submitted), never the practice draft
    const draft = phase === "over" ? await loadDraft(slug, a.id, { local: false }) : null;
    const program = item?.program ?? draft?.program ?? "";
    const view = await mountEditor(root.querySelector("#editor"), {
      text: program, dialect: ex.dialect, exercise: slug, live: false, readOnly: true,
    });
    if (phase === "over") {
      await awaitVerdict(note, a.id, slug, a);
      return;
    }
    note.textContent = `${t("exam.released", { title: a.title })}. ${item?.submitted ? t("exam.your_program") : t("exam.none_submitted")}`;
    if (!item?.submitted) return;
    showResult(item, view, drawer, result);
    const scene = await mountViz(root.querySelector("#viz"), view, { dialect: ex.dialect, exercise: slug });
    scene?.graded(program);
    return;
  }

  // running: the exam's own draft (or the start program; never the practice draft) saves as usual, the server
  // submits the last one at the end; the countdown runs
  const draft = await loadDraft(slug, a.id);
  const saver = draftSaver(slug, draft.user, start, draft.program, draft.pending, (state, error) => {
    const time = new Date().toLocaleTimeString(lang === "en" ? "en-GB" : "de-DE", { timeStyle: "short" });
    saved.textContent = state === "refused" ? t("exam.refused", { message: message(error) || "" }) : t(`exam.${state}`, { time });
    saved.className = state === "refused" || state === "offline" ? "error" : "meta";
  }, a.id);
  const limit = s.max_submissions || 0;
  const used = () => limit && item?.submitted && limit <= 1;  // the trainee's list tells submitted or not, not how often
  let scene = null;
  const view = await mountEditor(root.querySelector("#editor"), {
    text: draft.program ?? start, dialect: ex.dialect, list, exercise: slug, live: Boolean(s.live_diagnostics),
    locked: ex.kind === "complete" ? { lines: ex.locked_lines, start } : null, readOnly: Boolean(used()),
    onChange: (text) => { saver.changed(text); scene?.changed(text); }, onPointer: (line) => scene?.pointer(line),
  });
  const toolbar = root.querySelector("#editor-toolbar");
  // "Zurücksetzen" forgets this exam's draft only
  editorToolbar(toolbar, view, { filename: () => `${slug}.nc`, heading: () => title, reset: () => { saver.forget(); return start; } });
  toolbar.querySelector("#file-open")?.remove();  // no prepared programs from the computer during an exam
  if (s.hints) mountHints(root.querySelector("#hints"), { ...ex, slug }, { program: () => view.state.doc.toString() });
  if (s.viz) scene = await mountViz(root.querySelector("#viz"), view, { dialect: ex.dialect, exercise: slug });
  const held = () => {
    submit.disabled = true;
    note.textContent = t("exam.submitted");
    toolbar.querySelector("#file-reset")?.remove();
  };
  if (used()) held();

  let armed = null;  // one submission: the first click asks, the second submits
  const disarm = () => {
    clearTimeout(armed);
    armed = null;
    submit.textContent = t("submit");
    submit.title = "";
  };
  submit.onclick = async () => {
    if (limit === 1 && !armed) {
      submit.textContent = t("exam.confirm");
      submit.title = t("exam.confirm_title");
      armed = setTimeout(disarm, 6000);
      return;
    }
    disarm();
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
  let endAt = Date.now() + a.seconds_left * 1000;
  // the end as the server has it now: an instructor may extend (or shorten) a running exam; the page follows
  // within RECHECK, and asks once more before it ends (without an answer it ends by its own count)
  const recheck = async () => {
    const now = (await myAssignments(true))?.find((x) => x.id === a.id);
    if (!now) return;
    endAt = Date.now() + (now.seconds_left ?? 0) * 1000;
    if (now.deadline) root.querySelector("#exam-ends").textContent = t("exam.ends", { time: formatTime(now.deadline) });
  };
  let asking = false;
  const tick = () => {
    const left = (endAt - Date.now()) / 1000;
    countdown.textContent = t("exam.left", { left: clock(Math.max(0, Math.ceil(left))) });
    barClock.textContent = clock(Math.max(0, Math.ceil(left)));
    for (const c of [countdown, barClock]) c.classList.toggle("soon", left < 300);
    if (left > 0 || asking) return;
    asking = true;
    recheck().then(() => {
      asking = false;
      if (endAt > Date.now()) return;  // extended
      clearInterval(timer);
      clearInterval(rechecks);
      ended();
    });
  };
  const timer = setInterval(tick, 1000);
  const rechecks = setInterval(recheck, RECHECK);
  tick();

  // the end: nothing more to type or hand in; the page waits for the server's word on what was submitted
  async function ended() {
    saver.stop();
    setReadOnly(view, true);
    disarm();
    submit.hidden = true;
    barClock.hidden = true;
    toolbar.querySelector("#file-reset")?.remove();
    root.querySelector(".exam-rules")?.remove();  // the conditions no longer matter; the message below does
    await awaitVerdict(note, a.id, slug, null);
  }
}

// The released result: the score that counts (the teacher's, with their note, where one is set) and the criteria
// with line links into the read-only program.
function showResult(item, view, drawer, result) {
  drawer.open();
  if (item.score === null) {
    result.replaceChildren(el("p", {}, t("submit.ungraded")));
    return;
  }
  drawer.score(`${item.score}/${item.max_score}`);  // the bar already says "Ergebnis"
  result.replaceChildren(...resultBlock(item, editorLine(view)));
}
