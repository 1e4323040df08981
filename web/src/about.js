// "Über / Lizenzen": PAL Trainer's own licence and every browser package shipped with it (the list the web
// build writes to /static/licenses.json from esbuild's metafile; the texts are /static/licenses.txt).

import { el } from "./dom.js";
import { lang } from "./i18n.js";

const TEXTS = {
  de: { title: "Über PAL Trainer", own: "PAL Trainer ist freie Software unter der Apache License 2.0.",
    packages: "Mitgelieferte Browser-Bibliotheken", name: "Paket", version: "Version", licence: "Lizenz",
    use: "Verwendung", bundled: "im Editor (app.js)", copied: "API-Dokumentation (/docs)",
    texts: "Alle Lizenztexte (licenses.txt)", missing: "Die Liste der Lizenzen fehlt (npm run build im Ordner web)." },
  en: { title: "About PAL Trainer", own: "PAL Trainer is free software under the Apache License 2.0.",
    packages: "Browser libraries shipped with it", name: "Package", version: "Version", licence: "Licence",
    use: "Used in", bundled: "the editor (app.js)", copied: "API documentation (/docs)",
    texts: "All licence texts (licenses.txt)", missing: "The list of licences is missing (npm run build in web)." },
};
const tx = TEXTS[lang === "en" ? "en" : "de"];

export async function mountAbout(root) {
  document.title = `PAL Trainer – ${tx.title}`;
  const r = await fetch("/static/licenses.json");
  const packages = r.ok ? await r.json() : null;
  const rows = (packages || []).map((p) => el("tr", {}, el("td", {}, p.name), el("td", {}, p.version),
    el("td", {}, p.license), el("td", {}, p.bundled ? tx.bundled : tx.copied)));
  root.replaceChildren(
    el("h2", {}, tx.title), el("p", {}, tx.own),
    el("h3", {}, tx.packages),
    packages ? el("table", { id: "licences" },
      el("thead", {}, el("tr", {}, ...[tx.name, tx.version, tx.licence, tx.use].map((h) => el("th", {}, h)))),
      el("tbody", {}, ...rows)) : el("p", { className: "error" }, tx.missing),
    el("p", {}, el("a", { href: "/static/licenses.txt" }, tx.texts)));
}
