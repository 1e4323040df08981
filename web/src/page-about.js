// "Über / Lizenzen": PAL Trainer's own licence and every browser package shipped with it (the list the web
// build writes to /static/licenses.json from esbuild's metafile; the texts are /static/licenses.txt).

import { el } from "./dom.js";
import { t } from "./i18n.js";

export async function mountAbout(root) {
  document.title = t("title.about");
  const r = await fetch("/static/licenses.json");
  const packages = r.ok ? await r.json() : null;
  const rows = (packages || []).map((p) => el("tr", {}, el("td", {}, p.name), el("td", {}, p.version),
    el("td", {}, p.license), el("td", {}, p.bundled ? t("about.bundled") : t("about.copied"))));
  root.replaceChildren(
    el("h2", {}, t("about.title")), el("p", {}, t("about.own")),
    el("h3", {}, t("about.packages")),
    packages ? el("table", { id: "licences" },
      el("thead", {}, el("tr", {}, ...[t("about.name"), t("about.version"), t("about.licence"), t("about.use")].map((h) => el("th", {}, h)))),
      el("tbody", {}, ...rows)) : el("p", { className: "error" }, t("about.missing")),
    el("p", {}, el("a", { href: "/static/licenses.txt" }, t("about.texts"))));
}
