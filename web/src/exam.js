// The caller's assignments and the exams among them, shared by the pages: the list (GET /me/assignments, asked
// once per page), the running exam that closes free practice (the header's link, the practice page's notice),
// what an exercise page is during exams (examContext; page-exam.js mounts the exam's page), an exam's mode as a
// label, and the clock and times the exam texts show.

import { api, el } from "./dom.js";
import { lang, t } from "./i18n.js";

// 5400 → "1:30:00", 59 → "00:59"
export function clock(seconds) {
  const s = Math.max(0, Math.round(seconds));
  const two = (n) => String(n).padStart(2, "0");
  const [h, m] = [Math.floor(s / 3600), Math.floor((s % 3600) / 60)];
  return h ? `${h}:${two(m)}:${two(s % 60)}` : `${two(m)}:${two(s % 60)}`;
}

export function formatTime(iso) {
  return new Date(iso).toLocaleString(lang === "en" ? "en-GB" : "de-DE", { dateStyle: "medium", timeStyle: "short" });
}

// Who may have assignments: a logged-in user (the server names them in <body data-user>) or a learning platform's
// frame with its token. The list holds the courses where the account is a student, whatever its role: an
// instructor's account that is a student in a course sits that course's exams.
function loggedIn() {
  return Boolean(document.body.dataset.user) || new URLSearchParams(location.hash.slice(1)).has("token");
}

let mine = null;
// The caller's assignments (GET /me/assignments), asked once per page (`fresh`: again); null when nobody is
// logged in or there is no answer.
export function myAssignments(fresh = false) {
  if (!loggedIn()) return Promise.resolve(null);
  if (!mine || fresh) {
    // (null also when the server cannot be reached, as when it refuses)
    mine = api("/me/assignments").then((r) => (r.ok ? r.body.map((a) => ({ ...a, received: Date.now() })) : null),
      () => null);
  }
  return mine;
}

const isRunning = (a) => a.mode === "exam" && a.seconds_left !== null;
// the running exam that closes free practice (and every exercise outside it), if any
const closing = (list, slug = null) => (list || []).find((a) => isRunning(a) && !a.settings.free_practice
  && !(slug && a.exercises.includes(slug))) || null;

// ms until an upcoming assignment opens, by the server's clock (its seconds_to_start when the list was read)
export const untilStart = (a) => (a.seconds_to_start != null && a.received
  ? a.seconds_to_start * 1000 - (Date.now() - a.received) : Date.parse(a.opens_at) - Date.now());

// The header's "Freies Üben": hidden on every page while an exam without free practice runs for the user, and
// from the start of such an exam that is still to come (the list is asked again then).
export async function watchPracticeLink(fresh = false) {
  const list = await myAssignments(fresh);
  if (!list) return;
  const link = document.getElementById("nav-practice");
  if (closing(list)) {
    link?.setAttribute("hidden", "");
    return;
  }
  const next = Math.min(...list.filter((a) => a.mode === "exam" && a.status === "upcoming" && !a.settings.free_practice)
    .map(untilStart));
  if (next < 6 * 3600 * 1000) setTimeout(() => watchPracticeLink(true), Math.max(next, 0) + 1000);
}

// What this exercise page is: null (an ordinary exercise), {blocked: exam} (an exam without free practice runs
// and this exercise is not in it), {during: [exams]} (free practice on another exercise while exams run: their
// settings still switch features off), or {exam, item, phase} with phase "upcoming", "running", "over" (results
// held) or "released". ?assignment=ID (the home page's links) names the exam.
export async function examContext(slug) {
  const list = await myAssignments();
  if (!list) return null;
  const wanted = Number(new URLSearchParams(location.search).get("assignment")) || null;
  const exams = list.filter((a) => a.mode === "exam");
  const has = (a) => a.exercises.includes(slug);
  const blocked = closing(exams, slug);
  if (blocked) return { blocked };
  const running = exams.filter(isRunning);
  // an exam's exercises are named only from its start: an upcoming one is the page's when the link names it
  const exam = running.find((a) => a.id === wanted && has(a)) || running.find(has)
    || exams.find((a) => a.id === wanted && (has(a) || a.status === "upcoming"))
    || exams.find((a) => has(a) && !a.released && a.status !== "upcoming");
  if (!exam) return running.length ? { during: running } : null;
  const phase = exam.status === "upcoming" ? "upcoming" : isRunning(exam) ? "running"
    : exam.results_visible ? "released" : "over";
  return { exam, phase, item: exam.items.find((i) => i.exercise === slug) };
}

// Free practice while an exam without it runs for the user: a notice with the way to the exam instead of the
// editor (true), else nothing happens (false).
export async function practiceBlocked(root) {
  const exam = closing(await myAssignments());
  if (!exam) return false;
  document.getElementById("nav-practice")?.setAttribute("hidden", "");
  root.className = "narrow";
  root.replaceChildren(el("div", { className: "exam-notice" },
    el("h2", {}, t("nav.practice")),
    el("p", { role: "status" }, t("exam.no_practice", { title: exam.title })),
    el("p", {}, el("a", { href: `/exercises/${exam.exercises[0]}?assignment=${exam.id}` }, t("home.to_exam")))));
  return true;
}

// The exam's mode with its duration where it is known: "Prüfung · 90 min"
export function modeLabel(a) {
  if (a.mode !== "exam") return t("mode.practice");
  return a.duration_minutes ? t("mode.exam_minutes", { min: a.duration_minutes }) : t("mode.exam");
}
