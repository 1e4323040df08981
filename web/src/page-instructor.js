// The instructor's page (/instructor): a submission opened from a list (results.js), their courses with "Neue
// Klasse", their own exercises (edit, duplicate, archive, a new one, a copy of a built-in one, a YAML import), the
// results table, all submissions by exercise with the CSV export, and the class list import.

import { api, el, errorText as error, post, table } from "./dom.js";
import { lang, message, t } from "./i18n.js";
import { loginUrl, safeNext } from "./redirect.js";
import { classImportSection, resultsSection, submissionHref, submissionSection } from "./results.js";

// the editor of a saved exercise (the page goes there through the one redirect rule, safeNext)
const editPath = (slug) => `/exercises/${encodeURIComponent(slug)}/edit`;

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

// -- the instructor page's list of courses and "Neue Klasse" ---------------------------------------------
export async function coursesSection() {
  const section = el("section", { id: "courses" });
  const r = await api("/courses");
  const admin = document.body.dataset.role === "admin";
  const list = r.ok && r.body.length
    ? el("ul", { className: "courses", id: "course-list" }, ...r.body.map((c) => el("li", {},
      el("a", { href: `/courses/${c.id}` }, c.name), el("span", { className: "meta" },
        ` · ${t("courses.students", { n: c.students })} · ${c.instructors.join(", ")}`))))
    : el("p", { className: "meta" }, r.ok ? t("courses.none") : error(r, "instructor.error"));
  const name = el("input", { type: "text", id: "course-name", required: true, maxLength: 200 });
  const note = el("p", { role: "status" });
  const form = el("form", { className: "inline-form", id: "course-new" },
    el("label", {}, `${t("courses.name")} `, name), " ", el("button", { type: "submit" }, t("courses.create")), note);
  form.onsubmit = async (event) => {
    event.preventDefault();
    const made = await api("/courses", post({ name: name.value.trim() }));
    if (made.ok) location.href = safeNext(`/courses/${made.body.id}`);
    else { note.className = "error"; note.textContent = error(made, "instructor.error"); }
  };
  section.append(el("h3", {}, t(admin ? "courses.all" : "courses.title")), list,
    el("details", { open: r.ok && !r.body.length }, el("summary", {}, t("courses.new")), form));
  return section;
}

// The instructor's page: their exercises with edit, duplicate and archive; a new one, a copy of a built-in one,
// and (secondary) a YAML file as a new draft.
export async function myExercisesSection() {
  const section = el("section", { id: "my-exercises" });
  const status = el("div", { id: "my-exercises-message", role: "alert" });
  const fail = (r) => { status.replaceChildren(el("p", { className: "error" }, (r.body?.error && message(r.body.error)) || t("edit.error"))); };
  const title = (e) => (lang === "en" && e.title_en ? e.title_en : e.title_de);
  const duplicate = async (slug) => {
    const r = await api(`/exercises/${encodeURIComponent(slug)}/duplicate`, { method: "POST" });
    if (r.ok) location.href = safeNext(editPath(r.body.slug)); else fail(r);
  };
  async function show() {
    const [mine, all] = await Promise.all([api("/exercises?mine=true&archived=true"), api("/exercises")]);
    const rows = mine.ok ? mine.body : [];
    const builtins = all.ok ? all.body.filter((e) => e.builtin) : [];
    const template = el("select", { id: "template" }, ...builtins.map((e) => el("option", { value: e.slug },
      `${title(e)} (${(lang === "en" && e.dialect_title_en) || e.dialect_title})`)));
    template.setAttribute("aria-label", t("mine.template"));
    const importFile = el("input", { type: "file", id: "import-exercise", accept: ".yaml,.yml,.json" });
    importFile.setAttribute("aria-label", t("mine.import"));
    importFile.onchange = async () => {
      const r = await api("/exercises/import?visibility=draft", { method: "POST", headers: { "Content-Type": "application/yaml" },
        body: await importFile.files[0].text() });
      if (r.ok) location.href = safeNext(editPath(r.body.slug));
      else {
        fail(r);
        const errors = r.body?.error?.details?.errors || [];
        if (errors.length) status.append(el("ul", {}, ...errors.map((e) => el("li", {}, `${e.field}: ${message(e)}`))));
      }
    };
    const list = rows.length ? el("table", { className: "my-exercises" },
      el("thead", {}, el("tr", {}, el("th", {}, t("mine.col_title")), el("th", {}, t("mine.col_visibility")),
        el("th", { className: "num" }, t("mine.col_version")), el("th"))),
      el("tbody", {}, ...rows.map((e) => el("tr", { className: e.archived ? "archived" : "" },
        el("td", {}, el("a", { href: `/exercises/${encodeURIComponent(e.slug)}` }, title(e))),
        el("td", {}, e.archived ? t("mine.archived") : t(`visibility.${e.visibility}`)),
        el("td", { className: "num" }, String(e.version)),
        el("td", { className: "actions" },
          el("a", { href: `/exercises/${encodeURIComponent(e.slug)}/edit`, className: "edit" }, t("mine.edit")), " ",
          el("button", { type: "button", className: "copy", onclick: () => duplicate(e.slug) }, t("mine.copy")), " ",
          e.archived
            ? el("button", { type: "button", className: "restore", onclick: async () => {
              const r = await api(`/exercises/${encodeURIComponent(e.slug)}`, { method: "PATCH",
                headers: { "Content-Type": "application/json" }, body: JSON.stringify({ archived: false }) });
              if (r.ok) show(); else fail(r);
            } }, t("mine.restore"))
            : el("button", { type: "button", className: "archive", onclick: async () => {
              if (!confirm(t("mine.archive_confirm", { title: title(e) }))) return;
              const r = await api(`/exercises/${encodeURIComponent(e.slug)}`, { method: "DELETE" });
              if (r.ok) show(); else fail(r);
            } }, t("mine.archive"))))))) : el("p", { className: "meta" }, t("mine.none"));
    section.replaceChildren(el("h3", {}, t("mine.title")),
      el("p", { className: "my-actions" }, el("a", { href: "/exercises/new", id: "new-exercise", className: "button" }, t("mine.new")),
        " ", el("label", {}, `${t("mine.template")} `, template), " ",
        el("button", { type: "button", id: "copy-template", onclick: () => template.value && duplicate(template.value) }, t("mine.copy"))),
      status, list,
      el("details", { className: "yaml-import" }, el("summary", {}, t("edit.other")),
        el("p", {}, el("label", {}, `${t("mine.import")} `, importFile))));
  }
  await show();
  return section;
}
