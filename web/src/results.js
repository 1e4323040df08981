// The instructor page's own parts: the results table (GET /results: trainees × exercises, the best score
// linking to that submission, the CSV for Excel), one submission opened read-only (GET /submissions/{id}:
// the program with line numbers, its diagnostics and criteria with line links), and the class-list import
// (POST /users/import, the generated passwords shown this once).

import { Text } from "@codemirror/state";
import { api, el } from "./dom.js";
import { lang, message, t } from "./i18n.js";
import { criteriaList, formatTime, scoreText } from "./history.js";
import { mountViz } from "./viz.js";

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
        cell.submissions.length > 1 ? el("span", { className: "meta" }, ` (${cell.submissions.length})`) : null);
    })));
  section.append(el("div", { className: "results-wrap" },
    el("table", { className: "results-table", id: "results-table" }, el("thead", {}, head), el("tbody", {}, ...rows))));
  return section;
}

// One submission, read-only: everything the trainee saw. The 3D view (viz.js) is mounted once the section is in
// the page: call section.mountViz().
export async function submissionSection(id) {
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
  section.append(...[
    el("h3", {}, t("submission.title", { id: s.id, user: s.user || s.external_user || "–" })),
    el("p", { className: "meta" }, `${s.exercise} · ${formatTime(s.created_at)} · ${
      g ? scoreText(g.score, g.max_score) : t("history.ungraded")}`),
    program,
    el("h4", {}, t("diagnostics.title")),
    diagnostics.length
      ? el("ul", { className: "diagnostics", id: "submission-diagnostics" }, ...diagnostics.map((d) => el("li",
        { className: `diag diag-${d.severity}` },
        el("button", { type: "button", className: "line-link", onclick: () => goLine(d.line) }, t("diagnostics.line", { n: d.line })),
        ` ${d.code}: ${message(d)}`)))
      : el("p", { className: "meta" }, t("diagnostics.none")),
    g ? el("h4", {}, t("history.criteria")) : null,
    g ? criteriaList(g.criteria, goLine) : null].filter(Boolean));
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
