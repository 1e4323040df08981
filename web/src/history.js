// "Meine Abgaben": the trainee's earlier submissions to one exercise (GET /me/submissions?exercise=slug), each
// with score (the teacher's, with their note, where one is set), time and criteria, and "in den Editor laden".
// The criteria list with line links (grades.js) is shared with the drawer, the exam page and the instructor's view.

import { api, el } from "./dom.js";
import { criteriaList, overrideNote } from "./grades.js";
import { lang, t } from "./i18n.js";

export function formatTime(iso) {
  return new Date(iso).toLocaleString(lang === "en" ? "en-GB" : "de-DE");
}

export function scoreText(score, max) {
  return score === null || score === undefined ? t("history.ungraded") : t("score", { score, max });
}

// The caller's submissions to `slug`, newest first (the answer of api()).
export const mySubmissions = (slug) => api(`/me/submissions?exercise=${encodeURIComponent(slug)}`);

// Mounts the list in `container`; load(program) puts a program into the editor. `first`: the list already asked
// for (a promise of api()'s answer), so that the page asks once. Returns refresh().
export function mountHistory(container, slug, { load, onLine, first = null }) {
  const refresh = async (pending = null) => {
    const r = await (pending || mySubmissions(slug));
    const items = r.ok ? r.body : [];
    container.replaceChildren(el("h2", {}, t("history.title")), items.length
      ? el("ol", { className: "history", reversed: true, start: items.length }, ...items.map((s, i) => el("li", { className: "history-item" },
        el("div", { className: "history-head" },
          el("strong", {}, scoreText(s.score, s.max_score)), " · ", el("time", { dateTime: s.created_at }, formatTime(s.created_at)),
          " · ", t("history.counts", { errors: s.error_count, warnings: s.warning_count })),
        overrideNote(s.override),
        s.criteria.length ? el("details", {}, el("summary", {}, t("history.criteria")), criteriaList(s.criteria, onLine)) : null,
        el("button", {
          type: "button", className: "history-load", textContent: t("history.load"),
          title: t("history.load_title", { n: items.length - i }),
          onclick: () => load(s.program),
        }))))
      : el("p", { className: "meta" }, t("history.none")));
  };
  refresh(first);
  return { refresh };
}
