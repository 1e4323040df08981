// The instructor page's own parts: the results table (GET /results: trainees × exercises, the best score
// linking to that submission, "*" where the teacher set it, the CSV for Excel), one submission opened read-only
// (GET /submissions/{id}: the program with line numbers, its diagnostics and criteria with line links, and the
// teacher's last word on its score: PUT / DELETE /submissions/{id}/override), and the class-list import
// (POST /users/import, the generated passwords shown this once).

import { Text } from "@codemirror/state";
import { api, el } from "./dom.js";
import { criteriaList, formatMinute, overriddenMark } from "./grades.js";
import { lang, message, t } from "./i18n.js";
import { formatTime, scoreText } from "./history.js";
import { decimalInput, parseDecimal } from "./numbers.js";
import { mountViz } from "./viz.js";

// A submission graded against an earlier version of its exercise (edited since): which one.
export function versionNote(version) { return t("results.version", { v: version }); }

const title = (e) => (lang === "en" && e.title_en ? e.title_en : e.title_de);

// Where a submission opens: this page with ?submission=ID (a real link: new tab, bookmark, back button).
export const submissionHref = (id) => `/instructor?submission=${id}`;

export async function resultsSection() {
  const section = el("section", { id: "results", className: "results" }, el("h3", {}, t("results.title")));
  const r = await api("/results");
  if (!r.ok) {
    section.append(el("p", { className: "error" }, (r.body?.error && message(r.body.error)) || t("results.failed")));
    return section;
  }
  const { exercises, trainees } = r.body;
  section.append(el("p", {}, el("a", { id: "results-csv", href: "/api/v1/results.csv", download: "ergebnisse.csv" },
    t("results.csv")), " ", el("span", { className: "meta" }, t("results.csv_note"))));
  if (!trainees.length) {
    section.append(el("p", { className: "meta" }, t("results.none")));
    return section;
  }
  const head = el("tr", {}, el("th", { scope: "col" }, t("col.learner")),
    ...exercises.map((e) => el("th", { scope: "col" }, el("a", { href: `/exercises/${e.slug}` }, title(e)))));
  const rows = trainees.map((row) => el("tr", {}, el("th", { scope: "row" }, row.username),
    ...exercises.map((e) => {
      const cell = row.results[e.slug];
      if (!cell) return el("td", { className: "num meta" }, "–");
      const label = cell.best_score === null ? t("history.ungraded") : `${cell.best_score}/${cell.max_score}`;
      return el("td", { className: "num" },
        el("a", { href: submissionHref(cell.best_submission), title: t("results.cell_title", { n: cell.submissions.length,
          time: formatTime(cell.created_at) }) }, label),
        cell.overridden ? overriddenMark() : null,
        cell.submissions.length > 1 ? el("span", { className: "meta" }, ` (${cell.submissions.length})`) : null,
        // graded against an earlier version of the exercise (it was edited since)
        cell.version_note ? el("span", { className: "meta version-note" }, ` · ${versionNote(cell.exercise_version)}`) : null);
    })));
  section.append(el("div", { className: "results-wrap" },
    el("table", { className: "results-table", id: "results-table" }, el("thead", {}, head), el("tbody", {}, ...rows))));
  if (trainees.some((row) => Object.values(row.results).some((cell) => cell.overridden))) {
    section.append(el("p", { className: "meta" }, t("override.note")));
  }
  return section;
}

// One submission, read-only: everything the trainee saw, and the form that changes its score. The 3D view
// (viz.js) is mounted once the section is in the page: call section.mountViz(). `onOverride(submission)`: the
// score was changed or restored (the page's results table follows).
export async function submissionSection(id, { onOverride = null } = {}) {
  const section = el("section", { id: "submission-view", className: "submission-view" });
  const r = await api(`/submissions/${encodeURIComponent(id)}`);
  if (!r.ok) {
    section.append(el("p", { className: "error" }, (r.body?.error && message(r.body.error)) || t("submission.missing")));
    return section;
  }
  const s = r.body;
  const lines = (s.program || "").replace(/\n$/, "").split("\n");
  const program = el("ol", { className: "submission-program", id: "submission-program", tabIndex: 0 },
    ...lines.map((line, i) => el("li", { id: `line-${i + 1}` }, line || " ")));
  program.setAttribute("aria-label", t("program.label"));
  const goLine = (n) => {
    for (const li of program.querySelectorAll("li.marked")) li.classList.remove("marked");
    const li = program.querySelector(`#line-${Math.min(n, lines.length)}`);
    if (!li) return;
    li.classList.add("marked");
    li.scrollIntoView({ block: "center" });
  };
  const diagnostics = s.diagnostics || [];
  const g = s.grading;
  const heading = el("p", { className: "meta", id: "submission-score" });
  const showScore = (now) => {
    heading.textContent = `${s.exercise} · ${formatTime(s.created_at)} · ${
      g ? scoreText(now.score ?? g.score, g.max_score) : t("history.ungraded")}${now.override ? ` (${t("override.changed")})` : ""}${
      s.version_note ? ` · ${versionNote(s.exercise_version)}` : ""}`;
  };
  showScore(s);
  section.append(...[
    el("h3", {}, t("submission.title", { id: s.id, user: s.user || s.external_user || "–" })),
    heading,
    program,
    el("h4", {}, t("diagnostics.title")),
    diagnostics.length
      ? el("ul", { className: "diagnostics", id: "submission-diagnostics" }, ...diagnostics.map((d) => el("li",
        { className: `diag diag-${d.severity}` },
        el("button", { type: "button", className: "line-link", onclick: () => goLine(d.line) }, t("diagnostics.line", { n: d.line })),
        ` ${d.code}: ${message(d)}`)))
      : el("p", { className: "meta" }, t("diagnostics.none")),
    g ? el("h4", {}, t("history.criteria")) : null,
    g ? criteriaList(g.criteria, goLine) : null,
    g ? overrideForm(s, (now) => { showScore(now); onOverride?.(now); }) : null].filter(Boolean));
  const viz = el("div", { id: "submission-viz", className: "viz submission-viz" });
  section.append(el("h4", {}, t("viz.title")), viz);
  // the 3D view reads the program as an editor's document and marks the line it plays
  const doc = Text.of(lines);
  const reader = { state: { doc }, dispatch: ({ selection }) => goLine(doc.lineAt(selection.anchor).number), focus() {} };
  section.mountViz = async () => {
    const scene = await mountViz(viz, reader, { dialect: s.dialect, exercise: s.exercise });
    if (g) await scene?.graded(s.program || "");  // the deviation colours, as the trainee saw them
  };
  return section;
}

// "Punktzahl ändern": the teacher's score (a whole number 0 … max) and a comment the trainee reads; "Automatische
// Bewertung wiederherstellen" while one is set. Shows the grader's score and who changed it when. The server
// decides who may (403/404 otherwise: its message is shown). `changed(submission)` after each change.
function overrideForm(s, changed) {
  const max = s.grading.max_score;
  const automatic = s.grading.score;
  const form = el("form", { className: "override-form", id: "override-form", noValidate: true });
  const render = (sub, status = null) => {
    const o = sub.override;
    const score = decimalInput(o ? o.score : automatic, t("override.score", { max }), { integer: true, size: 5 });
    score.id = "override-score";
    const comment = el("textarea", { id: "override-comment", rows: 2, maxLength: 2000, value: o?.comment || "" });
    const note = el("span", { id: "override-status", role: "status" });
    if (status) { note.className = status.ok ? "ok" : "error"; note.textContent = status.text; }
    const restore = o ? el("button", { type: "button", id: "override-restore" }, t("override.restore")) : null;
    const send = async (options, okText) => {
      for (const b of form.querySelectorAll("button")) b.disabled = true;
      note.className = "";
      note.textContent = "";
      const r = await api(`/submissions/${s.id}/override`, options);
      if (!r.ok) {
        for (const b of form.querySelectorAll("button")) b.disabled = false;
        note.className = "error";
        note.textContent = (r.body?.error && message(r.body.error)) || t("override.failed");
        return;
      }
      render(r.body, { ok: true, text: okText(r.body) });
      changed(r.body);
    };
    if (restore) restore.onclick = () => send({ method: "DELETE" }, () => t("override.restored"));
    score.oninput = () => { if (note.className === "error") note.textContent = ""; };  // a complaint goes as it is fixed
    form.onsubmit = (event) => {
      event.preventDefault();
      const value = parseDecimal(score.value);
      if (!Number.isInteger(value) || value < 0 || value > max) {
        note.className = "error";
        note.textContent = t("override.invalid", { max });
        score.focus();
        return;
      }
      send({ method: "PUT", headers: { "Content-Type": "application/json" },
        body: JSON.stringify({ score: value, comment: comment.value.trim() }) },
      (now) => t("override.saved", { score: now.score, max }));
    };
    form.replaceChildren(...[
      el("h4", {}, t("override.title")),
      el("p", { className: "meta" }, t("override.automatic", { score: automatic, max }),
        o ? el("span", { className: "override-set" }, ` · ${t(o.by ? "override.by" : "override.by_nobody",
          { by: o.by, time: formatMinute(o.at) })}`) : null),
      el("div", { className: "override-fields" },
        el("label", { className: "field" }, t("override.score", { max }), score),
        el("label", { className: "field" }, t("override.comment"), comment)),
      el("div", { className: "override-actions" },
        el("button", { type: "submit", className: "primary", id: "override-save" }, t("override.save")), restore, note),
      el("p", { className: "meta" }, t("override.help"))].filter(Boolean));
  };
  render(s);
  return form;
}

// The class list: a CSV file → students managed by the caller; the passwords are shown once.
export function classImportSection() {
  const file = el("input", { type: "file", id: "class-file", accept: ".csv,.txt,text/csv" });
  file.setAttribute("aria-label", t("classlist.file"));
  const out = el("div", { id: "class-result", role: "status" });
  file.onchange = async () => {
    const chosen = file.files[0];
    if (!chosen) return;
    out.replaceChildren(el("p", {}, t("classlist.busy")));
    const r = await api("/users/import", { method: "POST", headers: { "Content-Type": "text/csv" }, body: await chosen.text() });
    file.value = "";
    if (!r.ok) {
      const errors = r.body?.error?.details?.errors || [];
      out.replaceChildren(...[el("p", { className: "error" }, (r.body?.error && message(r.body.error)) || t("classlist.failed")),
        errors.length ? el("ul", { className: "error" }, ...errors.map((e) => el("li", {},
          `${e.row ? `${t("classlist.row", { n: e.row })}: ` : ""}${message(e)}`))) : null].filter(Boolean));
      return;
    }
    const users = r.body.users;
    out.replaceChildren(el("p", { className: "ok" }, t("classlist.done", { n: users.length })),
      el("p", { className: "meta" }, t("classlist.once")),
      el("table", { className: "passwords", id: "class-passwords" },
        el("thead", {}, el("tr", {}, el("th", {}, t("login.user")), el("th", {}, t("login.password")))),
        el("tbody", {}, ...users.map((u) => el("tr", {}, el("td", {}, u.username),
          el("td", {}, u.password ?? t("classlist.given")))))));
  };
  return el("section", { id: "class-import" }, el("h3", {}, t("classlist.title")),
    el("p", { className: "meta" }, t("classlist.help")), el("p", {}, file), out);
}
