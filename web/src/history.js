// "Meine Abgaben": the trainee's earlier submissions to one exercise (GET /me/submissions?exercise=slug), each
// with score, time and criteria, and "in den Editor laden". The criteria list with line links is shared with
// the instructor's view of a submission.

import { api, el } from "./dom.js";
import { lang, message, t } from "./i18n.js";

export function formatTime(iso) {
  return new Date(iso).toLocaleString(lang === "en" ? "en-GB" : "de-DE");
}

export function scoreText(score, max) {
  return score === null || score === undefined ? t("history.ungraded") : t("score", { score, max });
}

// The criteria as a list; `onLine(n)` (optional) makes the lines links.
export function criteriaList(criteria, onLine = null) {
  return el("ul", { className: "criteria" }, ...criteria.map((c) => el("li", { className: c.status },
    `${c.status === "passed" ? "✓" : "✗"} ${c.points}/${c.max_points} – ${message(c)}`,
    ...(c.lines || []).map((n) => (onLine
      ? el("button", { className: "line-link", type: "button", textContent: t("diagnostics.line", { n }), onclick: () => onLine(n) })
      : el("span", { className: "meta" }, ` ${t("diagnostics.line", { n })}`))))));
}

// Mounts the list in `container`; load(program) puts a program into the editor. Returns refresh().
export function mountHistory(container, slug, { load, onLine }) {
  const refresh = async () => {
    const r = await api(`/me/submissions?exercise=${encodeURIComponent(slug)}`);
    const items = r.ok ? r.body : [];
    container.replaceChildren(el("h2", {}, t("history.title")), items.length
      ? el("ol", { className: "history", reversed: true, start: items.length }, ...items.map((s, i) => el("li", { className: "history-item" },
        el("div", { className: "history-head" },
          el("strong", {}, scoreText(s.score, s.max_score)), " · ", el("time", { dateTime: s.created_at }, formatTime(s.created_at)),
          " · ", t("history.counts", { errors: s.error_count, warnings: s.warning_count })),
        s.criteria.length ? el("details", {}, el("summary", {}, t("history.criteria")), criteriaList(s.criteria, onLine)) : null,
        el("button", {
          type: "button", className: "history-load", textContent: t("history.load"),
          title: t("history.load_title", { n: items.length - i }),
          onclick: () => load(s.program),
        }))))
      : el("p", { className: "meta" }, t("history.none")));
  };
  refresh();
  return { refresh };
}
