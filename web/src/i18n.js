// The one lookup of the pages' texts: t(key) in the language chosen with the switch in the page header and kept in
// the browser (localStorage); German is the default (the trainees' language). The texts are two flat tables,
// texts-de.js and texts-en.js, with the same keys and {placeholders} (scripts/check-texts.mjs); the API's own
// messages come in both languages (message()).

import { DE } from "./texts-de.js";
import { EN } from "./texts-en.js";

export const lang = localStorage.getItem("paltrainer-lang") === "en" ? "en" : "de";
const TEXTS = lang === "en" ? EN : DE;

// The text of `key` with its {placeholders} filled in (an unknown key stands for itself).
export function t(key, params = {}) {
  let text = TEXTS[key] ?? key;
  for (const [name, value] of Object.entries(params)) text = text.replaceAll(`{${name}}`, String(value));
  return text;
}

// The message of a diagnostic, criterion or help entry in the chosen language.
export function message(item, de = "message", en = "message_en") {
  return lang === "en" && item[en] ? item[en] : item[de];
}

// Static page texts: elements with data-i18n="key"; the language switch in the header.
export function translatePage() {
  document.documentElement.lang = lang;
  const all = (/** @type {string} */ selector) => /** @type {NodeListOf<HTMLElement>} */ (document.querySelectorAll(selector));
  for (const node of all("[data-i18n]")) node.textContent = t(node.dataset.i18n);
  for (const node of all("[data-i18n-label]")) {
    node.setAttribute("aria-label", t(node.dataset.i18nLabel));
  }
  const toggle = document.getElementById("lang");
  if (toggle) {
    toggle.textContent = t("nav.language");
    toggle.onclick = () => {
      localStorage.setItem("paltrainer-lang", lang === "en" ? "de" : "en");
      location.reload();
    };
  }
}
