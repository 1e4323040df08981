// Number fields that take a decimal comma as well as a point ("12,5" is 12.5, never 125): text fields with a
// decimal keyboard on tablets, read with parseDecimal. German shows the comma, English the point.

import { lang } from "./i18n.js";

// "12,5", "12.5", " 12 " → the number; anything else (also "", "1.2.3", "12,5,0", "1e3") → NaN
export function parseDecimal(text) {
  const s = String(text ?? "").trim();
  if (!/^[+-]?([0-9]+([.,][0-9]*)?|[.,][0-9]+)$/.test(s)) return NaN;
  return Number(s.replace(",", "."));
}

export function formatDecimal(value) {
  const text = String(value);
  return lang === "en" ? text : text.replace(".", ",");
}

// A number field: `integer` ones offer the digits keyboard; min and max are checked by the caller.
export function decimalInput(value, label, { integer = false, size = 6 } = {}) {
  const input = document.createElement("input");
  input.type = "text";
  input.inputMode = integer ? "numeric" : "decimal";
  input.autocomplete = "off";
  input.size = size;
  input.required = true;
  input.value = formatDecimal(value);
  input.setAttribute("aria-label", label);
  return input;
}
