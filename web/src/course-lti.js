// The course page's "Lernplattform (LTI)" part, shown only when a learning-platform course is linked to the
// course (GET /courses/{id}/lti): the linked platform courses, pulling their roster (POST …/lti/roster), and the
// grade passback's status for the course or one assignment (GET /lti/scores): rows per state, and the rows that
// need the instructor (given up, or retried after an error) with the platform's error in plain words and
// "erneut senden" for a given-up one (POST /lti/scores/{id}/retry).

import { api, el } from "./dom.js";
import { lang, message, t } from "./i18n.js";

const STATES = ["sent", "pending", "failed", "superseded"];
const error = (r, fallback) => (r.body?.error && message(r.body.error)) || t(fallback);
const formatTime = (iso) => new Date(iso).toLocaleString(lang === "en" ? "en-GB" : "de-DE",
  { dateStyle: "medium", timeStyle: "short" });

// The passback's error (server/lti/ags.py: technical, English) in plain words; the original stays as a tooltip.
export function plainError(text) {
  // the server stores its own fixed text, "German / English", with at most the platform's HTTP status
  if (!text) return "";
  const [de, en] = text.split(" / ");
  return lang === "en" && en ? en : de;
}

// The section, or null when no platform course is linked (or the caller may not see it).
// `assignments`: the course's assignments (the status can be narrowed to one; by default the whole course, as
// a platform's links are mostly to single exercises); `onRoster`: called after a pull, to show the new members.
export async function ltiPart(courseId, assignments, titleOf, onRoster) {
  const linked = await api(`/courses/${courseId}/lti`);
  if (!linked.ok || !linked.body.length) return null;
  const section = el("section", { id: "lti", className: "lti" }, el("h3", {}, t("lti.title")),
    el("p", {}, t("lti.linked")),
    el("ul", { id: "lti-courses" }, ...linked.body.map((c) => el("li", {}, t("lti.course", c),
      c.roster ? null : el("span", { className: "meta" }, ` ${t("lti.no_roster")}`)))));
  if (linked.body.some((c) => c.roster)) section.append(rosterPart(courseId, onRoster));
  section.append(await gradesPart(courseId, assignments, titleOf));
  return section;
}

function rosterPart(courseId, onRoster) {
  const button = el("button", { type: "button", id: "lti-roster" }, t("lti.roster"));
  const note = el("p", { role: "status", id: "lti-roster-note" });
  button.onclick = async () => {
    button.disabled = true;
    note.className = "meta";
    note.textContent = t("lti.roster_busy");
    const r = await api(`/courses/${courseId}/lti/roster`, { method: "POST" });
    button.disabled = false;
    if (!r.ok) {
      note.className = "error";
      note.textContent = error(r, "lti.roster_failed");
      return;
    }
    const b = r.body;
    await onRoster?.();  // the member list shows the new members before the note says they are there
    note.className = "ok";
    note.textContent = `${t("lti.roster_done", { ...b, updated: b.students + b.instructors - b.created })}${
      b.skipped ? ` ${t("lti.roster_skipped", { n: b.skipped })}` : ""}`;
  };
  return el("div", { className: "lti-roster" }, el("p", {}, button), el("p", { className: "meta" }, t("lti.roster_help")), note);
}

async function gradesPart(courseId, assignments, titleOf) {
  const part = el("div", { id: "lti-grades" });
  const scope = el("select", { id: "lti-scope" }, el("option", { value: "" }, t("lti.grades_all")),
    ...assignments.map((a) => el("option", { value: String(a.id) }, a.title)));
  const refresh = el("button", { type: "button", id: "lti-refresh", className: "link-button" }, t("lti.refresh"));
  const body = el("div", { id: "lti-grades-body" });
  const load = async () => {
    const params = new URLSearchParams(scope.value ? { assignment: scope.value } : { course: courseId });
    const r = await api(`/lti/scores?${params}`);
    body.replaceChildren(...(r.ok ? statusOf(r.body, titleOf, load) : [el("p", { className: "error" }, error(r, "lti.grades_failed"))]));
  };
  scope.onchange = load;
  refresh.onclick = load;
  part.append(el("h4", {}, t("lti.grades")),
    el("p", { className: "inline-form" }, el("label", {}, `${t("lti.grades_for")} `, scope), refresh), body);
  await load();
  return part;
}

function statusOf(data, titleOf, reload) {
  const { counts, scores } = data;
  if (!scores.length) return [el("p", { className: "meta" }, t("lti.grades_none"))];
  const shown = STATES.filter((s) => counts[s] || s !== "superseded");
  const summary = el("ul", { id: "lti-counts", className: "lti-counts" }, ...shown.map((s) => {
    const item = el("li", {}, el("span", { className: `badge lti-${s}` }, `${counts[s] || 0}`), ` ${t(`lti.state.${s}`)}`);
    item.dataset.state = s;
    return item;
  }));
  // what needs the instructor: given up, or waiting after a failed attempt
  const problems = scores.filter((x) => x.state === "failed" || (x.state === "pending" && x.last_error));
  if (!problems.length) return [summary, el("p", { className: "meta" }, t("lti.problems_none"))];
  const rows = problems.map((x) => {
    const who = x.name || x.user || "–";
    const action = el("td", {});
    if (x.state === "failed") {
      const retry = el("button", { type: "button", className: "lti-retry" }, t("lti.retry"));
      retry.setAttribute("aria-label", t("lti.retry_label", { name: who }));
      retry.onclick = async () => {
        retry.disabled = true;
        const r = await api(`/lti/scores/${x.id}/retry`, { method: "POST" });
        if (r.ok) {
          action.replaceChildren(el("span", { className: "ok" }, t("lti.retried")));
          setTimeout(reload, 3000);  // the server sends it within seconds: show the new state then
        } else {
          retry.disabled = false;
          action.append(el("span", { className: "error" }, ` ${error(r, "lti.grades_failed")}`));
        }
      };
      action.append(retry);
    }
    const state = x.state === "pending" && x.next_attempt_at
      ? `${t("lti.state.pending")} · ${t("lti.next", { time: formatTime(x.next_attempt_at) })}` : t(`lti.state.${x.state}`);
    return el("tr", { id: `lti-score-${x.id}`, className: `lti-${x.state}` },
      el("td", { title: x.user || "" }, who),
      el("td", {}, titleOf(x.exercise) || x.exercise),
      el("td", { className: "num" }, x.score === null ? "–" : `${x.score}`),
      el("td", {}, state), el("td", { className: "num" }, `${x.attempts}`),
      el("td", { title: x.last_error || "" }, plainError(x.last_error)), action);
  });
  return [summary, el("h5", {}, t("lti.problems")), el("div", { className: "results-wrap" },
    el("table", { id: "lti-problems" }, el("thead", {}, el("tr", {},
      ...["student", "exercise", "score", "state", "attempts", "error"].map((k) => el("th", {}, t(`lti.col.${k}`))),
      el("th", {}, el("span", { className: "visually-hidden" }, t("lti.retry"))))), el("tbody", {}, ...rows)))];
}
