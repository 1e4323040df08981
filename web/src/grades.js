// The grade as every page shows it: the criteria (✓ passed, ◐ partly, ✗ failed) with their points, message and
// line links — the likely cause's line first — and under the geometry criterion its features (kept or not, each
// with its line) folded away; the teacher's score where one is set ("Punktzahl von der Lehrkraft geändert: 80
// statt 50 – …", the server's words); the result block of the drawer and the exam page; the mark of a changed
// score in the results tables. Used by the exercise and exam pages, "Meine Abgaben", the start page, the
// instructor's submission view and both results tables.

import { el } from "./dom.js";
import { lang, message, t } from "./i18n.js";
import { formatDecimal } from "./numbers.js";

const MARKS = { passed: "✓", partial: "◐", failed: "✗" };

// The grader's status; older grades without one: from the points.
export function statusOf(c) {
  if (MARKS[c.status]) return c.status;
  if (c.points >= c.max_points) return "passed";
  return c.points > 0 ? "partial" : "failed";
}

// ✓ / ◐ / ✗, read out as its word ("teilweise erfüllt")
function mark(status, key = `criterion.${status}`) {
  const span = el("span", { className: `mark mark-${status}`, title: t(key) }, MARKS[status]);
  span.setAttribute("role", "img");
  span.setAttribute("aria-label", t(key));
  return span;
}

// "Zeile 7" as a button that moves the editor there (`onLine`), else as plain text
function lineLink(n, onLine, cause = false) {
  const text = t(cause ? "criterion.cause_line" : "diagnostics.line", { n });
  if (!onLine) return el("span", { className: `line-ref meta${cause ? " cause-line" : ""}` }, text);
  return el("button", {
    type: "button", className: `line-link${cause ? " cause-line" : ""}`, textContent: text,
    title: cause ? t("criterion.cause_title") : "", onclick: () => onLine(n),
  });
}

const millimetres = (value) => formatDecimal(Math.round(value * 100) / 100);

// The geometry's features, kept or not, folded in a <details> (its summary counts the kept ones).
function featureList(features, onLine) {
  const kept = features.filter((f) => f.ok).length;
  return el("details", { className: "features" },
    el("summary", {}, t("features.summary", { kept, total: features.length })),
    el("ul", { className: "feature-list" }, ...features.map((f) => el("li", { className: f.ok ? "kept" : "lost" },
      mark(f.ok ? "passed" : "failed", f.ok ? "feature.kept" : "feature.lost"), " ",
      lang === "en" && f.name_en ? f.name_en : f.name,
      !f.ok && f.deviation > 0 ? el("span", { className: "meta" }, ` – ${t("feature.deviation", { mm: millimetres(f.deviation) })}`)
        : null,
      f.line ? lineLink(f.line, onLine) : null))));
}

// The criteria as a list; `onLine(n)` (optional) makes the lines links.
export function criteriaList(criteria, onLine = null) {
  return el("ul", { className: "criteria" }, ...criteria.map((c) => {
    const status = statusOf(c);
    const cause = status !== "passed" && c.cause?.line ? c.cause.line : null;
    const lines = [...new Set([cause, ...(c.lines || [])].filter(Boolean))];
    return el("li", { className: status },
      el("span", { className: "criterion-text" }, mark(status), ` ${c.points}/${c.max_points} – ${message(c)}`),
      lines.length ? el("span", { className: "criterion-lines" }, ...lines.map((n) => lineLink(n, onLine, n === cause)))
        : null,
      c.features?.length ? featureList(c.features, onLine) : null);
  }));
}

// The teacher's score as the trainee reads it (null: none set).
export function overrideNote(override) {
  return override ? el("p", { className: "override-note" }, message(override)) : null;
}

// times to the minute: "22.11.2026, 18:46"
export const formatMinute = (iso) => new Date(iso).toLocaleString(lang === "en" ? "en-GB" : "de-DE",
  { dateStyle: "medium", timeStyle: "short" });

// The result block of the drawer and the exam page: the score that counts, the teacher's note, the criteria.
// `r`: {score, max_score, criteria, override}; `when`: the submission's time, for a result shown again.
export function resultBlock(r, onLine, { when = null } = {}) {
  return [when ? el("p", { className: "meta result-when" }, t("result.last", { time: formatMinute(when) })) : null,
    el("p", { className: "score" }, t("score", { score: r.score, max: r.max_score })),
    overrideNote(r.override),
    criteriaList(r.criteria || [], onLine)].filter(Boolean);
}

// A results table's mark of a score the teacher set: "*" with its meaning as title and for screen readers.
export function overriddenMark() {
  const star = el("span", { className: "overridden-mark", title: t("override.changed") }, "*");
  star.setAttribute("role", "img");
  star.setAttribute("aria-label", t("override.changed"));
  return star;
}

// Moves the editor's cursor to line n (clamped to the document) and scrolls it into sight.
export function editorLine(view) {
  return (n) => {
    const line = view.state.doc.line(Math.max(1, Math.min(n, view.state.doc.lines)));
    view.dispatch({ selection: { anchor: line.from }, scrollIntoView: true });
    view.focus();
  };
}
