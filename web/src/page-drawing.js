// The drawing's own page (/exercises/{slug}/drawing, /examples/{slug}/drawing): the viewer of drawing-viewer.js
// over the whole window, with "Drucken" (the sheet alone, A4 landscape) and the way back.

import { api, el } from "./dom.js";
import { drawingViewer } from "./drawing-viewer.js";
import { lang, t } from "./i18n.js";
import { framedHref } from "./lti-frame.js";
import { loginUrl } from "./redirect.js";

// The drawing's own page: the exercise's (or free practice's example's) drawing over the whole window, with
// "Drucken" (the sheet alone, A4 landscape) and the way back.
export async function mountDrawingPage(root) {
  const [, kind, slug] = location.pathname.split("/").map(decodeURIComponent);
  const heading = root.querySelector("#drawing-title");
  const svg = `/api/v1/${kind}/${encodeURIComponent(slug)}/drawing.svg?lang=${lang}`;
  let title = slug;
  if (kind === "exercises") {
    const r = await api(`/exercises/${encodeURIComponent(slug)}`);
    if (r.status === 401) { location.href = loginUrl(); return; }
    if (!r.ok) { root.replaceChildren(el("p", { className: "error" }, t("drawing.missing"))); return; }
    title = (lang === "en" && r.body.title_en) || r.body.title_de || slug;
  } else {
    const r = await api("/examples");
    const found = r.ok ? r.body.find((e) => e.slug === slug) : null;
    if (!found) { root.replaceChildren(el("p", { className: "error" }, t("drawing.missing"))); return; }
    title = (lang === "en" && found.title_en) || found.title_de || slug;
  }
  document.title = `PAL Trainer – ${t("drawing.page_heading", { title })}`;
  heading.textContent = t("drawing.page_heading", { title });
  // the sheet alone on the paper, A4 landscape without the browser's margins (this page only)
  document.head.append(el("style", { textContent: "@page { size: A4 landscape; margin: 0; }" }));
  const print = el("button", { type: "button", className: "primary", title: t("drawing.print_title"), onclick: () => window.print() },
    t("drawing.print"));
  const back = el("a", { href: framedHref(kind === "exercises" ? `/exercises/${encodeURIComponent(slug)}` : "/practice") },
    t(kind === "exercises" ? "drawing.back" : "drawing.back_practice"));
  const viewer = drawingViewer(svg, { slug, page: false, extra: [print, back], whole: true });
  root.querySelector("#drawing-viewer").replaceChildren(viewer);
  viewer.drawing.stage.focus();
}
