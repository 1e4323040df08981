// The instructor's course page (/courses/{id}): the class (join code, members, adding by name, the class list),
// its assignments (list, a new one: exercises, times, practice or exam with its conditions, late policy), and
// for the chosen assignment the results matrix (students × exercises, best score, late marks, "*" where the
// teacher changed the score, the sum with its percentage; a cell opens the submission above it, where the
// teacher may change its score), CSV and PDF task sheets, releasing an exam's results, and what the class got wrong
// (GET /assignments/{id}/insights).

import { api, el, errorText as error, post } from "./dom.js";
import { overriddenMark } from "./grades.js";
import { lang, message, t } from "./i18n.js";
import { formatDecimal } from "./numbers.js";
import { loginUrl, safeNext } from "./redirect.js";
import { submissionSection, versionNote } from "./results.js";
import { ltiPart } from "./course-lti.js";
import { framedHref } from "./lti-frame.js";
import { modeLabel } from "./exam.js";

const titleOf = (e) => (e ? (lang === "en" && e.title_en ? e.title_en : e.title_de) : "");
const query = () => new URLSearchParams(location.search);
// times to the minute: "22.11.2026, 18:46"
const formatTime = (iso) => new Date(iso).toLocaleString(lang === "en" ? "en-GB" : "de-DE",
  { dateStyle: "medium", timeStyle: "short" });
const SETTINGS = ["live_diagnostics", "viz", "hints", "solution", "free_practice"];

// -- the course page ---------------------------------------------------------------------------------
export async function mountCourse(parent, id) {
  const [course, members, exercises, assignments] = await Promise.all([api(`/courses/${id}`),
    api(`/courses/${id}/members`), api("/exercises"), api(`/courses/${id}/assignments`)]);
  if (course.status === 401) {
    location.href = loginUrl();
    return;
  }
  if (!course.ok || !members.ok) {
    parent.replaceChildren(el("p", { className: "error" }, t(course.ok ? "course.only_instructors" : "course.missing")));
    return;
  }
  const c = course.body;
  document.getElementById("course-title").textContent = `${t("course.heading")} ${c.name}`;
  document.title = `PAL Trainer – ${c.name}`;
  const byslug = new Map((exercises.body || []).map((e) => [e.slug, e]));
  const list = assignments.body || [];
  const chosen = list.find((a) => String(a.id) === query().get("assignment")) || list.at(-1);
  const opened = query().get("submission");
  // a changed score: the matrix is read again (the cell marked "*", the sum follows)
  const onOverride = async () => {
    if (chosen) document.getElementById("assignment-results")?.replaceWith(await resultsPart(chosen, byslug));
  };
  const view = opened ? await submissionSection(opened, { onOverride }) : null;
  if (view) {
    const close = new URLSearchParams(location.search);
    close.delete("submission");
    view.prepend(el("p", {}, el("a", { href: `?${close}`, id: "submission-close" }, t("matrix.close"))));
  }
  parent.replaceChildren(...[
    el("p", { className: "meta" }, el("a", { href: "/instructor" }, t("course.back")), " · ",
      t("course.instructors", { names: c.instructors.join(", ") })),
    view,
    chosen ? await resultsPart(chosen, byslug) : null,
    assignmentsPart(id, list, chosen, byslug, exercises.body || []),
    // shown only when a learning-platform course is linked; a roster pull shows the new members below
    await ltiPart(id, list, (slug) => titleOf(byslug.get(slug)), async () => {
      const now = await api(`/courses/${id}/members`);
      if (now.ok) document.getElementById("members")?.replaceWith(membersPart(c, now.body));
    }),
    membersPart(c, members.body),
  ].filter(Boolean));
  view?.mountViz?.();
}

function joinCode(c) {
  const code = el("code", { id: "join-code", className: "join-code" }, c.join_code || "–");
  const renew = el("button", { type: "button", id: "join-renew", className: "link-button" }, t("course.new_code"));
  renew.onclick = async () => {
    if (!confirm(t("course.new_code_confirm"))) return;
    const r = await api(`/courses/${c.id}`, { method: "PATCH", headers: { "Content-Type": "application/json" },
      body: JSON.stringify({ new_join_code: true }) });
    if (r.ok) code.textContent = r.body.join_code;
  };
  return el("div", { className: "join-box" }, el("p", {}, `${t("course.code")} `, code, " ", renew),
    el("p", { className: "meta" }, t("course.code_help")));
}

// The class: heading with the number of students, join code, the members table, adding by name, the class list.
// The heading and the table follow every add, removal and import (the server's list is read again).
function membersPart(c, members) {
  const heading = el("h3", {});
  const none = el("p", { className: "meta" }, t("members.none"));
  const rows = el("tbody", {});
  const row = (m) => {
    const remove = el("button", { type: "button", className: "link-button" }, t("members.remove"));
    remove.setAttribute("aria-label", t("members.remove_label", { name: m.username }));
    remove.onclick = async () => {
      if (!confirm(t("members.remove_confirm", { name: m.username }))) return;
      const r = await api(`/courses/${c.id}/members/${encodeURIComponent(m.username)}`, { method: "DELETE" });
      if (r.ok) await refresh(members.filter((x) => x.username !== m.username));
      else { note.className = "error"; note.textContent = error(r, "instructor.error"); }
    };
    const mark = m.signed_up ? el("span", { className: "badge signed-up", title: t("members.signed_up_title") },
      t("members.signed_up")) : null;
    return el("tr", {}, el("td", {}, m.username, mark ? " " : null, mark), el("td", {}, t(`members.role.${m.role}`)),
      el("td", { className: "member-actions" }, ...(m.role === "student" ? [resetButton(m.username, once), " · ", remove] : [])));
  };
  const once = el("div", { id: "reset-result", role: "status" });  // a one-time password, shown once
  const render = (list) => {
    members = list;
    const students = list.filter((m) => m.role === "student").length;
    heading.textContent = t("members.title", { n: students });
    none.hidden = students > 0;
    rows.replaceChildren(...list.map(row));
  };
  // the server's list after a change; should it not answer, `guess` (the list as the change left it)
  const refresh = async (guess) => {
    const now = await api(`/courses/${c.id}/members`);
    render(now.ok ? now.body : guess);
  };
  render(members);
  const name = el("input", { type: "text", id: "member-name", required: true, maxLength: 64, autocomplete: "off" });
  const note = el("p", { role: "status", id: "member-note" });
  const add = el("form", { className: "inline-form", id: "member-add" },
    el("label", {}, `${t("members.add_label")} `, name), " ", el("button", { type: "submit" }, t("members.add")),
    el("p", { className: "meta" }, t("members.add_help")));
  add.onsubmit = async (event) => {
    event.preventDefault();
    const r = await api(`/courses/${c.id}/members`, post({ username: name.value.trim() }));
    note.className = r.ok ? "ok" : "error";
    note.textContent = r.ok ? t("members.added", { name: r.body.username }) : error(r, "instructor.error");
    if (r.ok) {
      name.value = "";
      await refresh([...members.filter((m) => m.username !== r.body.username), r.body]);
    }
  };
  // the class list: new accounts in this course, the generated passwords shown this once
  const file = el("input", { type: "file", id: "course-class-file", accept: ".csv,.txt,text/csv" });
  file.setAttribute("aria-label", t("classlist.file"));
  const out = el("div", { id: "course-class-result", role: "status" });
  file.onchange = async () => {
    const chosen = file.files[0];
    if (!chosen) return;
    out.replaceChildren(el("p", {}, t("classlist.busy")));
    const r = await api(`/courses/${c.id}/members/import`, { method: "POST", headers: { "Content-Type": "text/csv" },
      body: await chosen.text() });
    file.value = "";
    if (!r.ok) {
      const errors = r.body?.error?.details?.errors || [];
      out.replaceChildren(el("p", { className: "error" }, error(r, "classlist.failed")),
        el("ul", { className: "error" }, ...errors.map((e) => el("li", {},
          `${e.row ? `${t("classlist.row", { n: e.row })}: ` : ""}${message(e)}`))));
      return;
    }
    const users = r.body.users;
    await refresh([...members, ...users.map((u) => ({ username: u.username, role: "student" }))]);
    out.replaceChildren(el("p", { className: "ok" }, t("classlist.done", { n: users.length })),
      el("p", { className: "meta" }, t("classlist.once")),
      el("table", { className: "passwords", id: "course-passwords" },
        el("thead", {}, el("tr", {}, el("th", {}, t("login.user")), el("th", {}, t("login.password")))),
        el("tbody", {}, ...users.map((u) => el("tr", {}, el("td", {}, u.username),
          el("td", {}, u.password ?? t("classlist.given")))))));
  };
  return el("section", { id: "members" },
    heading, joinCode(c), none,
    el("table", { id: "member-table", className: "members" }, el("thead", {}, el("tr", {},
      el("th", {}, t("login.user")), el("th", {}, t("members.role")),
      el("th", {}, el("span", { className: "visually-hidden" }, t("members.actions"))))), rows),
    once, add, note,
    el("h4", {}, t("members.import")), el("p", { className: "meta" }, t("members.import_help")), el("p", {}, file), out);
}

// -- assignments: the list and a new one --------------------------------------------------------------
const localInput = (date) => {  // a Date as <input type=datetime-local> wants it (local time, minutes)
  const d = new Date(date.getTime() - date.getTimezoneOffset() * 60000);
  return d.toISOString().slice(0, 16);
};

function assignmentsPart(courseId, list, chosen, byslug, exercises) {
  const rows = list.map((a) => el("tr", { className: a.id === chosen?.id ? "chosen" : "" },
    el("td", {}, el("a", { href: `?assignment=${a.id}`, ...(a.id === chosen?.id ? { ariaCurrent: "true" } : {}) }, a.title),
      el("span", { className: "meta" }, ` · ${a.exercises.map((s) => titleOf(byslug.get(s)) || s).join(", ")}`)),
    el("td", {}, modeLabel(a), a.mode === "exam"
      ? el("span", { className: "meta" }, ` · ${t(a.released ? "assignments.released" : "assignments.held")}`) : null,
    a.mode === "practice" && a.late === "refuse" ? el("span", { className: "meta" }, ` · ${t("form.late.refuse")}`) : null),
    el("td", {}, formatTime(a.opens_at)), el("td", {}, formatTime(a.deadline))));
  return el("section", { id: "assignments" }, el("h3", {}, t("assignments.title")),
    list.length ? el("div", { className: "results-wrap" }, el("table", { id: "assignment-table" },
      el("thead", {}, el("tr", {}, ...["title", "mode", "opens", "deadline"].map((k) => el("th", {}, t(`assignments.col.${k}`))))),
      el("tbody", {}, ...rows)))
      : el("p", { className: "meta" }, t("assignments.none")),
    el("details", { id: "assignment-new", open: !list.length }, el("summary", {}, t("assignments.new")),
      assignmentForm(courseId, exercises)));
}

function assignmentForm(courseId, exercises) {
  const field = (label, input) => el("label", { className: "field" }, label, input);
  const title = el("input", { type: "text", id: "a-title", required: true, maxLength: 200 });
  // the exercises by dialect, as on the exercise list
  const groups = [];
  for (const e of exercises) {
    if (groups.at(-1)?.dialect !== e.dialect) groups.push({ dialect: e.dialect,
      title: (lang === "en" && e.dialect_title_en) || e.dialect_title || e.dialect, items: [] });
    groups.at(-1).items.push(e);
  }
  const picker = el("div", { className: "exercise-picker", id: "a-exercises", tabIndex: 0 },
    ...groups.map((g) => el("div", {}, el("p", { className: "picker-group" }, g.title), ...g.items.map((e) =>
      el("label", { className: "check" }, el("input", { type: "checkbox", value: e.slug, name: "exercise" }), ` ${titleOf(e)}`)))));
  picker.setAttribute("role", "group");  // a scrolling box of checkboxes, reachable by keyboard
  picker.setAttribute("aria-label", t("form.exercises"));
  const now = new Date();
  const opens = el("input", { type: "datetime-local", id: "a-opens", required: true, value: localInput(now) });
  const deadline = el("input", { type: "datetime-local", id: "a-deadline",
    value: localInput(new Date(now.getTime() + 7 * 86400000)) });
  const mode = el("select", { id: "a-mode" }, ...["practice", "exam"].map((m) => el("option", { value: m }, t(`mode.${m}`))));
  const duration = el("input", { type: "number", id: "a-duration", min: 1, max: 1440, value: 90 });
  const late = el("select", { id: "a-late" }, ...["accept", "refuse"].map((v) => el("option", { value: v }, t(`form.late.${v}`))));
  const boxes = Object.fromEntries(SETTINGS.map((k) => [k, el("input", { type: "checkbox", id: `a-${k}`, checked: true })]));
  const maxSubs = el("input", { type: "number", id: "a-max", min: 0, max: 1000, value: 0 });
  const deadlineField = field(t("form.deadline"), deadline);
  const durationField = field(t("form.duration"), duration);
  const lateField = field(t("form.late"), late);
  // what an exam means for the class's practice until its results are released (server/access.py, rule 3)
  const examNote = el("p", { id: "a-exam-note", className: "exam-banner" }, t("form.exam_note"));
  examNote.style.fontWeight = "normal";
  // the mode's defaults (server/access.py): an exam under exam conditions, practice with everything
  const applyMode = () => {
    const exam = mode.value === "exam";
    for (const box of Object.values(boxes)) box.checked = !exam;
    maxSubs.value = exam ? 1 : 0;
    deadlineField.hidden = exam;
    lateField.hidden = exam;
    durationField.hidden = !exam;
    examNote.hidden = !exam;
  };
  mode.onchange = applyMode;
  const note = el("p", { role: "status", id: "a-note" });
  const form = el("form", { id: "assignment-form", className: "assignment-form" },
    el("div", { className: "form-grid" }, field(t("form.title"), title), field(t("form.mode"), mode),
      field(t("form.opens"), opens), deadlineField, durationField, lateField),
    examNote,
    el("fieldset", {}, el("legend", {}, t("form.exercises")), picker),
    el("fieldset", { id: "a-settings" }, el("legend", {}, t("form.settings")),
      el("p", { className: "meta" }, t("form.settings_help")),
      ...SETTINGS.map((k) => el("label", { className: "check" }, boxes[k], ` ${t(`setting.${k}`)}`)),
      el("label", { className: "field" }, t("setting.max_submissions"), maxSubs)),
    el("p", {}, el("button", { type: "submit", className: "primary" }, t("form.create"))), note);
  applyMode();
  form.onsubmit = async (event) => {
    event.preventDefault();
    const chosen = [...picker.querySelectorAll("input:checked")].map((b) => b.value);
    if (!chosen.length) {
      note.className = "error";
      note.textContent = t("form.no_exercise");
      return;
    }
    const exam = mode.value === "exam";
    const body = { title: title.value.trim(), exercises: chosen, mode: mode.value,
      opens_at: new Date(opens.value).toISOString(),
      ...(exam ? { duration_minutes: Number(duration.value) }
        : { deadline: deadline.value ? new Date(deadline.value).toISOString() : null, late: late.value }),
      settings: { ...Object.fromEntries(SETTINGS.map((k) => [k, boxes[k].checked])), max_submissions: Number(maxSubs.value) } };
    const r = await api(`/courses/${courseId}/assignments`, post(body));
    note.className = r.ok ? "ok" : "error";
    note.textContent = r.ok ? t("form.created", { title: r.body.title }) : error(r, "instructor.error");
    if (r.ok) location.href = safeNext(framedHref(`/courses/${courseId}?assignment=${r.body.id}`));  // in a platform's frame too
  };
  return form;
}

// -- one assignment: results matrix, downloads, release, insights ------------------------------------------
async function resultsPart(a, byslug) {
  const [results, insights] = await Promise.all([api(`/assignments/${a.id}/results`), api(`/assignments/${a.id}/insights`)]);
  const section = el("section", { id: "assignment-results" }, el("h3", {}, t("matrix.title", { title: a.title })));
  section.append(el("p", { className: "meta", id: "assignment-times" },
    `${modeLabel(a)} · ${formatTime(a.opens_at)} – ${formatTime(a.deadline)}`));
  const links = el("p", { className: "actions" },
    el("a", { id: "matrix-csv", href: `/api/v1/assignments/${a.id}/results.csv`, download: `auftrag-${a.id}.csv` }, t("matrix.csv")),
    " · ", el("a", { id: "matrix-sheets", href: `/api/v1/assignments/${a.id}/sheets.pdf${lang === "en" ? "?lang=en" : ""}`,
      target: "_blank", rel: "noopener" }, t("matrix.sheets")));
  if (a.mode === "exam" && !a.released) {
    const release = el("button", { type: "button", id: "matrix-release" }, t("matrix.release"));
    const note = el("span", { role: "status" });
    release.onclick = async () => {
      if (!confirm(t("matrix.release_confirm"))) return;
      const r = await api(`/assignments/${a.id}/release`, { method: "POST" });
      if (r.ok) { release.remove(); note.className = "ok"; note.textContent = t("assignments.released"); }
      else { note.className = "error"; note.textContent = error(r, "instructor.error"); }
    };
    links.append(" · ", release, " ", note);
  }
  section.append(links);
  if (!results.ok) {
    section.append(el("p", { className: "error" }, error(results, "results.failed")));
    return section;
  }
  const { exercises, trainees } = results.body;
  if (!trainees.length) section.append(el("p", { className: "meta" }, t("matrix.none")));
  else {
    const here = new URLSearchParams(location.search);
    here.set("assignment", a.id);
    const href = (submission) => { here.set("submission", submission); return `?${here}`; };
    const head = el("tr", {}, el("th", { scope: "col" }, t("matrix.student")),
      ...exercises.map((s) => el("th", { scope: "col" }, titleOf(byslug.get(s)) || s)),
      el("th", { scope: "col", className: "num" }, t("matrix.total")));
    const rows = trainees.map((row) => el("tr", {}, el("th", { scope: "row" }, row.username),
      ...exercises.map((s) => {
        const cell = row.results[s];
        if (!cell) return el("td", { className: "num meta" }, "–");
        const label = cell.score === null ? t("history.ungraded") : `${cell.score}/${cell.max_score}`;
        return el("td", { className: `num${cell.late ? " late" : ""}` },
          el("a", { href: href(cell.submission), title: t("matrix.cell_title", { user: row.username,
            time: formatTime(cell.created_at) }) }, label),
          cell.overridden ? overriddenMark() : null,
          cell.late ? el("span", { className: "tag tag-late" }, t("matrix.late")) : null,
          cell.auto ? el("span", { className: "tag", title: t("matrix.auto_title") }, t("matrix.auto")) : null,
          // graded against an earlier version of the exercise (edited since)
          cell.version_note ? el("span", { className: "meta version-note" }, ` · ${versionNote(cell.exercise_version)}`) : null);
      }),
      el("td", { className: "num total" }, sum(row))));
    const changed = trainees.some((row) => Object.values(row.results).some((cell) => cell.overridden));
    section.append(...[el("div", { className: "results-wrap" },
      el("table", { className: "results-table", id: "matrix" }, el("thead", {}, head), el("tbody", {}, ...rows))),
    el("p", { className: "meta" }, `${t("matrix.note")} ${t("matrix.total_note")}`),
    changed ? el("p", { className: "meta" }, t("override.note")) : null].filter(Boolean));
  }
  section.append(insightsPart(insights, byslug));
  return section;
}

// The row's sum over every gradable exercise of the assignment (one not handed in counts 0): "150/200 (75 %)"
function sum(row) {
  if (row.total === null || row.total === undefined || !row.max_total) return "–";
  const percent = row.percent ?? Math.round((1000 * row.total) / row.max_total) / 10;
  return `${row.total}/${row.max_total} (${formatDecimal(percent)}\u00a0%)`;
}

function insightsPart(r, byslug) {
  const section = el("section", { id: "insights", className: "insights" }, el("h3", {}, t("insights.title")));
  if (!r.ok) {
    section.append(el("p", { className: "error" }, error(r, "results.failed")));
    return section;
  }
  const d = r.body;
  section.append(el("p", { className: "meta" }, t("insights.basis"),
    d.capped ? ` ${t("insights.capped", { n: d.scanned })}` : ""));
  const where = (w) => (w ? el("span", { className: "meta" }, ` (${t("insights.where", { n: w.students, block: w.block })})`) : null);
  for (const ex of d.exercises) {
    const part = el("div", { className: "insight", id: `insight-${ex.exercise}` },
      el("h4", {}, titleOf(byslug.get(ex.exercise)) || ex.title_de || ex.exercise),
      el("p", { className: "meta" }, ex.students ? t("insights.submitted", { n: ex.students, of: d.students }) : t("insights.nothing")));
    if (ex.students) {
      part.append(el("div", { className: "insight-cols" },
        el("div", {}, el("h5", {}, t("insights.diagnostics")), ex.diagnostics.length
          ? el("ul", { className: "insight-diagnostics" }, ...ex.diagnostics.map((x) => el("li", {},
            el("strong", {}, t("insights.of", { n: x.students, of: ex.students })), ` · ${x.code}: ${message(x)}`, where(x.where))))
          : el("p", { className: "meta" }, t("insights.no_diagnostics"))),
        el("div", {}, el("h5", {}, t("insights.criteria")), ex.criteria.length
          ? el("ul", { className: "insight-criteria" }, ...ex.criteria.map((x) => el("li", {},
            el("strong", {}, t("insights.of", { n: x.lost, of: x.of })),
            ` ${t("insights.lost", { name: lang === "en" ? x.name_en : x.name })}`, where(x.where))))
          : el("p", { className: "meta" }, t("insights.no_criteria")))));
    }
    section.append(part);
  }
  return section;
}

// "Passwort zurücksetzen" for one student of the members table: a confirmation, then the one-time password shown
// once in `out`.
function resetButton(username, out) {
  const button = el("button", { type: "button", className: "link-button reset-password" }, t("reset.button"));
  button.setAttribute("aria-label", t("reset.label", { name: username }));
  button.onclick = async () => {
    if (!confirm(t("reset.confirm", { name: username }))) return;
    const r = await api(`/users/${encodeURIComponent(username)}/password-reset`, { method: "POST" });
    if (!r.ok) {
      out.replaceChildren(el("p", { className: "error" }, error(r, "reset.failed")));
      return;
    }
    out.replaceChildren(el("p", { className: "ok" }, `${t("reset.done", { name: r.body.username })} `,
      el("code", { className: "one-time-password", id: "one-time-password" }, r.body.password)),
    el("p", { className: "meta" }, t("reset.once", { name: r.body.username })));
  };
  return button;
}
