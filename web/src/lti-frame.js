// Inside a learning platform's frame (an LTI launch, token in the URL fragment: lti.js) the page is the exercise
// alone. An instructor reaches the courses they teach from there: a link in the header to the course page as the
// frame shows it (/courses/{id}/lti?p=…, framable by that platform only). Links between our pages inside the
// frame keep the platform (?p=, for the frame-ancestors) and the token (the fragment).

import { api, el } from "./dom.js";
import { t } from "./i18n.js";
import { safeNext } from "./redirect.js";

const framed = () => {
  const token = new URLSearchParams(location.hash.slice(1)).get("token");
  const platform = new URLSearchParams(location.search).get("p");
  return token && platform ? { token, platform } : null;
};

// `href` as it must be inside the platform's frame (the framed course page, ?p=, the token); else `href` itself
export function framedHref(href) {
  const frame = framed();
  const url = new URL(href, location.href);
  if (!frame || url.origin !== location.origin || url.pathname.startsWith("/api/")) return href;
  // a course page link (/courses/{id}…) stays the framed course page
  const course = url.pathname.match(/^\/courses\/(\d+)$/);
  if (course) url.pathname = `/courses/${course[1]}/lti`;
  if (!url.searchParams.has("p")) url.searchParams.set("p", frame.platform);
  url.hash = `token=${encodeURIComponent(frame.token)}`;
  return url.pathname + url.search + url.hash;  // a path on this site: the one redirect rule (safeNext) takes it
}

export function keepFrameOnLinks() {
  if (!framed()) return;
  document.addEventListener("click", (event) => {
    const link = event.target instanceof Element
      ? /** @type {HTMLAnchorElement | null} */ (event.target.closest("a[href]")) : null;
    if (!link || link.target || link.hasAttribute("download") || event.defaultPrevented) return;
    const href = framedHref(link.getAttribute("href"));
    if (href === link.getAttribute("href")) return;
    event.preventDefault();
    location.assign(safeNext(href));
  });
}

export async function instructorCourseLinks() {
  const frame = framed();
  const nav = document.querySelector("header nav");
  if (!frame || !nav || !location.pathname.startsWith("/lti/")) return;
  const me = await api("/me");
  if (!me.ok || !["instructor", "admin"].includes(me.body.role)) return;
  const courses = await api("/courses");
  if (!courses.ok) return;
  const mine = courses.body.filter((c) => c.instructors.includes(me.body.username));
  nav.prepend(...mine.map((c) => {
    const link = el("a", { href: `/courses/${c.id}/lti?p=${encodeURIComponent(frame.platform)}#token=${
      encodeURIComponent(frame.token)}`, className: "lti-course-link" }, t("ltiframe.course", { name: c.name }));
    link.title = t("ltiframe.course_title", { name: c.name });
    return link;
  }));
}
