// The pages around the editor: login, exercise list, instructor view, free practice's stock and tools.
// The exercise page is page-exercise.js, free practice page-practice.js; the workplace around the editor
// (tabs, drawer, editor toolbar) is layout.js. Every text the user reads is German; the API gives German and
// English messages.

import { api, el, table } from "./dom.js";
import { lang, message as message_, t } from "./i18n.js";
import { mountViz } from "./viz.js";
import { loginUrl, safeNext } from "./redirect.js";
import { classImportSection, resultsSection, submissionHref, submissionSection } from "./results.js";
import { decimalInput, parseDecimal } from "./numbers.js";
import { MILLING_TOOL_KINDS } from "./tool-kinds.js";
import { practiceSetup, saveSetup } from "./setup.js";
import { coursesSection } from "./page-course.js";
import { mountStart } from "./page-home.js";
import { myExercisesSection } from "./page-exercise-edit.js";

export { mountExercise } from "./page-exercise.js";

// Where the login leads: to `next` if it is a path on this site, else to the user's own start: instructors and
// admins their page (courses first), trainees the exercise list with their assignments.
export function landing(role, next) {
  if (typeof next === "string" && next && safeNext(next) === next) return next;
  return role === "instructor" || role === "admin" ? "/instructor" : "/";
}

// The login page is the start page of a visitor without an account (page-home.js: what PAL Trainer is, free practice).
export async function mountLogin(form, message) {
  mountStart(form);
  form.onsubmit = async (event) => {
    event.preventDefault();
    const data = Object.fromEntries(new FormData(form));
    const r = await api("/auth/login", {
      method: "POST", headers: { "Content-Type": "application/json" }, body: JSON.stringify(data),
    });
    if (r.ok && r.body?.must_change_password) {  // a one-time password: the user chooses their own first
      location.href = safeNext("/password");
    } else if (r.ok) {
      location.href = safeNext(landing(r.body?.role, new URLSearchParams(location.search).get("next")));
    } else {
      message.textContent = (r.body?.error && message_(r.body.error)) || t("login.failed");
    }
  };
}

export async function mountExerciseList(parent) {
  const r = await api("/exercises");
  if (r.status === 401) {
    location.href = loginUrl();
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

export async function mountInstructor(parent) {
  const exercises = await api("/exercises");
  if (exercises.status === 401) {
    location.href = loginUrl();
    return;
  }
  // filter by exercise, list (the exercises by their titles), export
  const title = (e) => (lang === "en" && e.title_en ? e.title_en : e.title_de);
  const titles = new Map(exercises.body.map((e) => [e.slug, title(e)]));
  const filter = el("select", { id: "filter" }, el("option", { value: "" }, t("instructor.all")),
    ...exercises.body.map((e) => el("option", { value: e.slug }, title(e))));
  const csv = el("a", { id: "csv", href: "/api/v1/submissions/export.csv" }, t("instructor.csv"));
  const list = el("div", { id: "submission-list" });
  async function show() {
    const query = filter.value ? `?exercise=${encodeURIComponent(filter.value)}` : "";
    csv.href = `/api/v1/submissions/export.csv${query}`;
    const r = await api(`/submissions${query}`);
    const rows = r.ok ? r.body : [];
    if (!rows.length) {
      list.replaceChildren(el("p", { className: "meta" }, r.ok ? t("instructor.no_submissions") : t("instructor.error")));
      return;
    }
    list.replaceChildren(table([t("col.number"), t("instructor.exercise"), t("col.learner"), t("col.time"),
      t("col.errors"), t("col.points")], rows.map((s) => [
      s.id, (lang === "en" && s.exercise_title_en) || s.exercise_title || titles.get(s.exercise) || s.exercise,
      s.external_user || s.user || "–", new Date(s.created_at).toLocaleString(lang === "en" ? "en-GB" : "de-DE"),
      s.error_count ?? "–", s.score ?? "–"]), [0, 4, 5]));
    // the numbers open the submission (results.js)
    for (const row of list.querySelectorAll("tbody tr")) {
      const cell = row.firstElementChild;
      cell.replaceChildren(el("a", { href: submissionHref(cell.textContent) }, cell.textContent));
    }
  }
  filter.onchange = show;
  // results.js: one submission opened (?submission=ID), the results table, the class list
  const opened = new URLSearchParams(location.search).get("submission");
  // a changed score: the results table is read again (its cell marked "*")
  const onOverride = async () => document.getElementById("results")?.replaceWith(await resultsSection());
  const [view, courses, mine, results] = await Promise.all([opened ? submissionSection(opened, { onOverride }) : null,
    coursesSection(), myExercisesSection(), resultsSection()]);
  parent.replaceChildren(view ?? "", courses, mine, results,
    el("h3", {}, t("instructor.submissions")), el("p", {}, el("label", {}, `${t("instructor.exercise")} `, filter), " ", csv),
    list, classImportSection());
  view?.mountViz?.();
  await show();
}

// -- free practice: the stock and the tools, kept in the browser ----------------------------------
export function mountPracticeSetup(parent, onChange) {
  const setup = practiceSetup();
  // text fields that take "12,5" as 12.5 (numbers.js); the limits are checked in changed()
  const number = (value, min, max, step, label) => decimalInput(value, label, { integer: step === 1 });
  const size = setup.size.map((v, i) => number(v, 1, 2000, 0.1, t(`setup.size.${i}`)));
  const rows = el("tbody");
  const changed = () => {
    const next = {
      size: size.map((input) => parseDecimal(input.value)),
      tools: [...rows.children].map((tr) => {
        const [num, kind, dia] = tr.querySelectorAll("input, select");
        return { number: parseDecimal(num.value), kind: kind.value, diameter: parseDecimal(dia.value) };
      }),
    };
    const valid = next.size.every((v) => v > 0 && v <= 2000)
      && next.tools.every((tool) => Number.isInteger(tool.number) && tool.number >= 1 && tool.number <= 99
        && tool.diameter > 0 && tool.diameter <= 1000);
    message.textContent = valid ? "" : t("setup.invalid");
    if (!valid) return;
    saveSetup(next);
    onChange(next);
  };
  const message = el("p", { className: "error", role: "status" }, "");
  const row = (tool) => {
    const kind = el("select", {}, ...MILLING_TOOL_KINDS.map((k) =>
      el("option", { value: k, selected: tool.kind === k }, t(`kind.${k}`))));
    kind.setAttribute("aria-label", t("tools.kind"));
    const tr = el("tr", {},
      el("td", {}, number(tool.number, 1, 99, 1, t("tools.tool"))), el("td", {}, kind),
      el("td", {}, number(tool.diameter, 0.1, 1000, 0.1, t("tools.diameter"))),
      el("td", {}, el("button", { type: "button", className: "remove", onclick: () => { tr.remove(); changed(); } },
        t("setup.remove"))));
    return tr;
  };
  rows.append(...setup.tools.map(row));
  const add = el("button", { type: "button", id: "add-tool", onclick: () => {
    const used = [...rows.querySelectorAll("tr td:first-child input")].map((i) => parseDecimal(i.value) || 0);
    rows.append(row({ number: Math.max(0, ...used) + 1, kind: "end_mill", diameter: 10 }));
    changed();
  } }, t("setup.add"));
  const form = el("form", { className: "setup", onchange: changed, onsubmit: (e) => e.preventDefault() },
    el("fieldset", {}, el("legend", {}, t("setup.stock")),
      ...size.flatMap((input, i) => [el("label", {}, `${"XYZ"[i]} `, input), " "]), el("span", {}, " mm")),
    el("fieldset", {}, el("legend", {}, t("setup.tools")),
      el("table", {}, el("thead", {}, el("tr", {}, ...["tools.tool", "tools.kind", "tools.diameter"].map((k) =>
        el("th", {}, t(k))), el("th"))), rows),
      el("p", { className: "meta" }, t("setup.default_tools")), add),
    message);
  parent.replaceChildren(form);
  return setup;
}

export { mountViz };  // the 3D view lives in viz.js
