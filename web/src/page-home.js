// The trainee's start page above the exercise list: their courses, joining a course with its code, and the
// assignments (GET /me/assignments) with opening time, deadline, mode, status and a link into each exercise
// (an exam's from its start); below them the exercise list, one list per dialect with the trainee's progress.

import { api, el } from "./dom.js";
import { overrideNote } from "./grades.js";
import { lang, message, t } from "./i18n.js";
import { clock, formatTime, modeLabel, myAssignments, watchPracticeLink } from "./exam.js";
import { loginUrl } from "./redirect.js";

const DONE = new Set(["submitting", "submitted", "late", "closed"]);

// `fresh`: ask the list anew (after joining a course). An account whose role is not trainee sees the section
// only when it is a student in a course (an instructor who sits a course's exam): its assignments, no joining.
export async function mountHome(section, fresh = false) {
  const student = document.body.dataset.role === "student";
  if (!document.body.dataset.user) return;
  const assignments = (await myAssignments(fresh)) || [];
  if (!student && !assignments.length) return;
  const [courses, exercises, progress] = await Promise.all([
    student ? api("/courses") : null, api("/exercises"), api("/me/progress")]);
  if (student && !courses.ok) return;
  const titles = new Map((exercises.ok ? exercises.body : []).map((e) =>
    [e.slug, lang === "en" && e.title_en ? e.title_en : e.title_de]));
  const drafts = new Set((progress.ok ? progress.body : []).filter((p) => p.status === "draft").map((p) => p.exercise));
  const open = assignments.filter((a) => !DONE.has(a.status));
  const done = assignments.filter((a) => DONE.has(a.status));
  const running = assignments.find((a) => a.mode === "exam" && a.status === "running");
  section.replaceChildren(...[
    running ? el("p", { className: "exam-banner", role: "status" },
      t("home.exam_running", { title: running.title, left: clock(running.seconds_left) }), " ",
      el("a", { href: exerciseHref(running, running.exercises[0]) }, t("home.to_exam"))) : null,
    el("h2", {}, t("home.assignments")),
    open.length ? el("div", { className: "assignments" }, ...open.map((a) => card(a, titles, drafts)))
      : el("p", { className: "meta" }, t("home.no_assignments")),
    done.length ? el("details", { className: "assignments-done" }, el("summary", {}, t("home.done", { n: done.length })),
      ...done.map((a) => card(a, titles, drafts))) : null,
    ...(student ? [el("h2", {}, t("home.courses")),
      courses.body.length ? el("ul", { className: "my-courses" }, ...courses.body.map((c) => el("li", {},
        el("strong", {}, c.name), c.instructors.length
          ? el("span", { className: "meta" }, ` · ${t("home.instructors", { names: c.instructors.join(", ") })}`) : null)))
        : el("p", { className: "meta" }, t("home.no_courses")),
      joinForm(section)] : [])].filter(Boolean));
}

const exerciseHref = (a, slug) => `/exercises/${encodeURIComponent(slug)}?assignment=${a.id}`;

function card(a, titles, drafts) {
  const started = a.status !== "upcoming";
  const times = [
    t("assignment.opens", { time: formatTime(a.opens_at) }),
    t(a.mode === "exam" ? "assignment.exam_end" : "assignment.deadline", { time: formatTime(a.deadline) }),
    a.seconds_left !== null && !DONE.has(a.status) ? t("assignment.left", { left: clock(a.seconds_left) }) : null,
    a.mode === "practice" && a.late === "accept" ? t("assignment.late_ok") : null,
  ].filter(Boolean).join(" · ");
  return el("article", { className: `assignment assignment-${a.status}` },
    el("h3", {}, a.title, " ",
      el("span", { className: `badge mode-${a.mode}` }, modeLabel(a)),
      " ", el("span", { className: `badge status-${a.status}` }, t(`astatus.${a.status}`))),
    el("p", { className: "meta" }, `${t("assignment.course", { name: a.course_name })} · ${times}`),
    a.items.length ? el("ul", { className: "assignment-items" }, ...a.items.map((item) => el("li", {},
      started ? el("a", { href: exerciseHref(a, item.exercise) }, titles.get(item.exercise) || item.exercise)
        : el("span", {}, titles.get(item.exercise) || item.exercise),
      " ", el("span", { className: "meta item-status" }, `· ${itemStatus(a, item, drafts)}`),
      a.results_visible && item.submitted ? overrideNote(item.override) : null)))
      : el("p", { className: "meta" }, t("assignment.exercises_later")));  // an exam before its start
}

// not started / draft / submitted (late, automatically) / held until released / the released score (the teacher's
// where one is set: their note follows the item). An exam keeps drafts of its own: the practice drafts
// (/me/progress) say nothing about it.
function itemStatus(a, item, drafts) {
  if (!item.submitted && a.mode === "exam") {
    return t(a.status === "submitting" ? "item.submitting" : item.draft ? "item.draft" : "item.open");
  }
  if (!item.submitted) return t(drafts.has(item.exercise) ? "item.draft" : "item.not_started");
  const how = t(item.auto ? "item.auto" : item.late ? "item.late" : "item.submitted");
  if (!a.results_visible) return `${how} – ${t("item.held")}`;
  return item.score === null ? how : `${how} – ${t("item.score", { score: item.score, max: item.max_score })}`;
}

function joinForm(section) {
  const input = el("input", { id: "join-code", name: "code", required: true, maxLength: 32, autocomplete: "off" });
  const status = el("p", { id: "join-message", role: "status" });
  const form = el("form", { className: "join", id: "join" },
    el("h2", {}, t("home.join")),
    el("label", { htmlFor: "join-code" }, t("home.code")), " ", input, " ",
    el("button", { type: "submit" }, t("home.join_button")), status);
  form.onsubmit = async (event) => {
    event.preventDefault();
    const r = await api("/courses/join", {
      method: "POST", headers: { "Content-Type": "application/json" }, body: JSON.stringify({ code: input.value.trim() }),
    });
    if (!r.ok) {
      status.className = "error";
      status.textContent = (r.body?.error && message(r.body.error)) || t("home.join_failed");
      return;
    }
    await mountHome(section, true);
    watchPracticeLink();  // an exam of the new course may be running
    const again = section.querySelector("#join-message");
    again.className = "ok";
    again.textContent = t("home.joined", { name: r.body.name });
  };
  return form;
}

// The exercise list: one list per dialect, each exercise with its kind and where the trainee stands.
export async function mountExerciseList(parent) {
  const r = await api("/exercises");
  if (r.status === 401) {
    location.href = loginUrl();
    return;
  }
  if (!r.ok) {  // (a busy server: 429 or 503) said, with a way to ask again, instead of an empty page
    const again = el("button", { type: "button", className: "link-button", id: "list-again" }, t("home.list_again"));
    again.onclick = () => mountExerciseList(parent);
    parent.replaceChildren(el("p", { className: "error", role: "alert" },
      (r.body?.error && message(r.body.error)) || t("home.list_failed"), " ", again));
    return;
  }
  const kinds = { write: t("kind.write"), complete: t("kind.complete"), fix: t("kind.fix") };
  // where the trainee stands on each exercise (not started, draft, best score); the list keeps the API's order
  const progress = await api("/me/progress");
  const state = new Map((progress.ok ? progress.body : []).map((p) => [p.exercise, p]));
  const status = (slug) => {
    const p = state.get(slug);
    if (!p || p.status === "not_started") return el("span", { className: "progress not-started" }, t("progress.not_started"));
    if (p.status === "draft") return el("span", { className: "progress draft" }, t("progress.draft"));
    return el("span", { className: "progress submitted" }, p.best_score === null
      ? t("progress.submitted") : t("progress.best", { score: p.best_score, max: p.max_score }));
  };
  // one list per dialect, under its name ("PAL Fräsen")
  const groups = [];
  for (const e of r.body) {
    if (groups.at(-1)?.dialect !== e.dialect) groups.push({ dialect: e.dialect, title: (lang === "en" && e.dialect_title_en) || e.dialect_title || e.dialect, items: [] });
    groups.at(-1).items.push(e);
  }
  parent.replaceChildren(...groups.flatMap((g) => [el("h3", { className: "dialect-title" }, g.title),
    el("ul", { className: "exercises" }, ...g.items.map((e) => el("li", {},
      el("a", { href: `/exercises/${e.slug}` }, lang === "en" && e.title_en ? e.title_en : e.title_de),
      el("span", { className: "meta" }, ` ${kinds[e.kind] || ""} · `), status(e.slug))))]));
}
