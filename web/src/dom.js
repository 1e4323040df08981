// Small DOM and API helpers shared by the page modules.

import { message, t } from "./i18n.js";

export async function api(path, options = {}) {
  const r = await fetch(`/api/v1${path}`, { credentials: "same-origin", ...options });
  const body = r.headers.get("content-type")?.includes("json") ? await r.json() : null;
  return { ok: r.ok, status: r.status, body };
}

// The options of api() for a POST of `body` as JSON.
export const post = (body) => ({ method: "POST", headers: { "Content-Type": "application/json" }, body: JSON.stringify(body) });

// The message of an API answer's error, or the text of `fallback` (a key of the text tables).
export const errorText = (r, fallback) => (r.body?.error && message(r.body.error)) || t(fallback);

// A status line: its class ("ok", "error") and text.
export function say(node, kind, text) {
  node.className = kind;
  node.textContent = text;
}

// An element with properties (className, onclick …) and children (null and undefined are left out).
export function el(tag, props = {}, ...children) {
  const node = document.createElement(tag);
  Object.assign(node, props);
  node.append(...children.filter((c) => c !== null && c !== undefined));
  return node;
}

// A table; `numeric` names the columns whose numbers are right-aligned.
export function table(head, rows, numeric = []) {
  const cls = (i) => (numeric.includes(i) ? "num" : "");
  return el("table", {},
    el("thead", {}, el("tr", {}, ...head.map((h, i) => el("th", { className: cls(i) }, h)))),
    el("tbody", {}, ...rows.map((r) => el("tr", {}, ...r.map((c, i) => el("td", { className: cls(i) }, String(c)))))));
}
