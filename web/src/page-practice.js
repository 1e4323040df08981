// Free practice: the editor with live diagnostics and the 3D view, the stock and tools kept in the browser;
// "Beispiel laden" puts a built-in example's program into the editor (GET /api/v1/examples; every dialect's,
// the TRAUB turning examples with their blank) and shows its drawing; programs open from and save to the
// trainee's computer and print with line numbers. While an exam without free practice runs, a notice instead.

import { api, el } from "./dom.js";
import { lang, t } from "./i18n.js";
import { decimalInput, formatDecimal, parseDecimal } from "./numbers.js";
import { drawingZoom, editorToolbar, mountDrawer, mountSideToggle, mountSplitters, mountTabs } from "./layout.js";
import { mountEditor, setTools } from "./main.js";
import { practiceBlocked } from "./exam.js";
import { practiceSetup, saveSetup } from "./setup.js";
import { LATHE_DIALECTS, MILLING_TOOL_KINDS } from "./tool-kinds.js";
import { mountViz } from "./viz.js";

const SAMPLE = "N10 T1 TC1 M6\nN20 S1200 F150 M3\nN30 G0 X-25 Y-15 Z2\nN40 G42 G0 X-14 Y10\nN50 G0 Z-2\n" +
  "N60 G1 X70 Y10 RN20\nN70 G1 Y84\nN80 G40\nN90 G0 X250 Y150 Z250 M30\n";
// turning: face, then a shoulder Ø36 with a rounding and a chamfer (X is a diameter)
const SAMPLES = {
  "pal-mill": SAMPLE,
  "traub-tx8d": "%\nO1 (ABSATZ DREHEN)\nN10 G59 Z200\nN20 G96 V200 T0101 M4\nN30 G92 S3000\nN40 G0 X44 Z2 M8\n" +
    "N50 G1 Z0 F0.2\nN60 X-1.6\nN70 G0 X36 Z2\nN80 G1 Z-20 R2\nN90 X44 D1\nN100 Z-35\nN110 G0 X100 Z100 M9\nN120 M30\n",
};

// Turning: the blank (a bar or tube) instead of the milling block; empty fields: a bar that fits the program
// (LATHE_DIALECTS: tool-kinds.js).
const BLANK_KEY = "paltrainer-practice-blank";
const decimal = (text) => {  // "40,5" as well as "40.5"; "" is not given
  const value = String(text).trim().replace(",", ".");
  return value === "" ? null : Number(value);
};

function mountBlank(parent, onChange) {
  let saved = {};
  try { saved = JSON.parse(localStorage.getItem(BLANK_KEY)) || {}; } catch { /* a damaged entry: empty */ }
  const field = (name) => {
    const input = el("input", { type: "text", inputMode: "decimal", id: `blank-${name}`, size: 7,
      value: saved[name] ?? "", autocomplete: "off" });
    input.setAttribute("aria-label", t(`setup.blank.${name}`));
    return el("label", { className: "field" }, el("span", {}, t(`setup.blank.${name}`)), input);
  };
  const fields = ["diameter", "bore", "length"].map(field);
  const message = el("p", { className: "error", role: "status" }, "");
  const read = () => {
    const [d, bore, l] = fields.map((f) => f.querySelector("input").value);
    const raw = { diameter: d, bore, length: l };
    const [diameter, inner, length] = [decimal(d), decimal(bore) ?? 0, decimal(l)];
    if (diameter === null && length === null) return { raw, blank: null, valid: !inner };
    const valid = [diameter, inner, length].every(Number.isFinite) && diameter > 0 && diameter <= 2000
      && length > 0 && length <= 2000 && inner >= 0 && inner < diameter;
    return { raw, valid, blank: valid ? { diameter, inner_diameter: inner, length } : null };
  };
  const setup = { blank: read().blank };
  const form = el("form", { className: "setup", id: "blank-form", onsubmit: (e) => e.preventDefault(),
    onchange: () => {
      const { raw, valid, blank } = read();
      message.textContent = valid ? "" : t("setup.blank.invalid");
      if (!valid) return;
      localStorage.setItem(BLANK_KEY, JSON.stringify(raw));
      setup.blank = blank;
      onChange({ blank });
    } },
  el("fieldset", {}, el("legend", {}, t("setup.blank")), ...fields, el("p", { className: "meta" }, t("setup.blank.auto"))),
  message);
  parent.replaceChildren(form);
  return setup;
}

// The blank of a turning example as the blank form keeps it ("100", "", "160"): its bar or tube, else the box
// around it (a bar of that diameter and length).
function blankOf(example) {
  const text = (v) => (Number.isFinite(v) && v > 0 ? formatDecimal(Math.round(v * 1000) / 1000) : "");
  const b = example.blank;
  if (b && Number.isFinite(b.diameter) && Number.isFinite(b.length)) {
    return { diameter: text(b.diameter), bore: text(b.inner_diameter), length: text(b.length) };
  }
  const s = example.stock;
  if (!s?.min || !s?.max) return null;
  return { diameter: text(s.max[0] - s.min[0]), bore: "", length: text(s.max[2] - s.min[2]) };
}

// The practice setup of an example: its stock (zero at the front left top corner) and its tools.
function setupOf(example) {
  const s = example.stock;
  const size = s.max.map((v, i) => Math.round((v - s.min[i]) * 1000) / 1000);
  const tools = (example.tools || []).filter((tool) => tool.number && tool.diameter).map((tool) => ({
    number: tool.number, kind: MILLING_TOOL_KINDS.includes(tool.kind) ? tool.kind : "end_mill", diameter: tool.diameter,
  }));
  return { size, tools };
}

export async function mountPractice(root) {
  if (await practiceBlocked(root)) return;  // an exam without free practice runs: its notice instead (exam.js)
  const showTab = mountTabs(root);
  mountSideToggle(root);
  mountSplitters(root);
  mountDrawer(root);
  const params = new URLSearchParams(location.search);
  const select = root.querySelector("#dialect");
  select.value = params.get("dialect") || "pal-mill";
  select.onchange = () => { location.search = `?dialect=${select.value}`; };
  // the program is kept in the browser per dialect: a reload loses nothing; so is the example it came from
  const saved = `paltrainer-practice-${select.value}`;
  const savedExample = `paltrainer-practice-example-${select.value}`;
  let scene = null;
  let filename = localStorage.getItem(`${saved}-file`) || t("file.default_name");
  const lathe = LATHE_DIALECTS.has(select.value);
  const setup = lathe ? mountBlank(root.querySelector("#setup"), (next) => scene?.setup(next))
    : mountPracticeSetup(root.querySelector("#setup"), (next) => {
      setTools(window.editor, next.tools.length ? next.tools : null);
      scene?.setup(next);
    });
  window.editor = await mountEditor(root.querySelector("#editor"), {
    text: localStorage.getItem(saved) ?? (SAMPLES[select.value] ?? ""), dialect: select.value,
    tools: setup.tools?.length ? setup.tools : null, list: root.querySelector("#diagnostics"),
    onChange: (text) => { localStorage.setItem(saved, text); scene?.changed(text); },
    onPointer: (line) => scene?.pointer(line),
  });

  // -- the examples --------------------------------------------------------------------------------------
  const picker = root.querySelector("#example");
  const note = root.querySelector("#example-note");
  const picture = root.querySelector("#picture");
  const noDrawing = picture.innerHTML;
  const r = await api("/examples");
  const examples = r.ok ? r.body : [];
  const title = (e) => (lang === "en" && e.title_en ? e.title_en : e.title_de);
  // every dialect's examples, the page's own first (the others open the practice page of their dialect)
  const dialects = { "pal-mill": t("dialect.pal_mill"), "sinumerik-iso": "SINUMERIK 808D ISO", beckhoff: "Beckhoff TwinCAT",
    "traub-tx8d": t("example.group_traub") };
  const order = [select.value, ...Object.keys(dialects).filter((d) => d !== select.value)];
  for (const dialect of order) {
    const name = dialects[dialect];
    if (!name) continue;
    const mine = examples.filter((e) => e.dialect === dialect);
    if (mine.length) {
      picker.append(el("optgroup", { label: name }, ...mine.map((e) => el("option", { value: e.slug },
        `${title(e)}${e.program_is === "start" ? ` (${t("example.start")})` : ""}`))));
    }
  }
  const show = (example) => {
    picker.value = example ? example.slug : "";
    note.textContent = example ? t(example.program_is === "start" ? "example.loaded_start" : "example.loaded",
      { title: title(example) }) : "";
    if (!example) { picture.innerHTML = noDrawing; return; }
    const url = `/api/v1/examples/${example.slug}/drawing.svg?lang=${lang}`;
    picture.replaceChildren(el("h2", {}, title(example)), drawingZoom(url, example.slug));
  };
  show(examples.find((e) => e.slug === localStorage.getItem(savedExample)) || null);

  const toolbar = editorToolbar(root.querySelector("#editor-toolbar"), window.editor, {
    filename: () => filename, heading: () => `${t("nav.practice")} – ${filename}`,
    onOpen: (name) => {  // a program of one's own: no example's drawing any more
      filename = name;
      localStorage.setItem(`${saved}-file`, name);
      localStorage.removeItem(savedExample);
      show(null);
    },
  });
  // an example's set-up: a turning example's blank, else a milling example's stock and tools
  const keepSetup = (example) => {
    if (!LATHE_DIALECTS.has(example.dialect)) {
      saveSetup(setupOf(example));
      return;
    }
    const blank = blankOf(example);
    if (blank) localStorage.setItem(BLANK_KEY, JSON.stringify(blank));
  };
  picker.onchange = () => {
    const example = examples.find((e) => e.slug === picker.value);
    if (!example) return;
    if (example.dialect !== select.value) {  // another dialect: that page, with the example
      localStorage.setItem(`paltrainer-practice-${example.dialect}`, example.program);
      localStorage.setItem(`paltrainer-practice-example-${example.dialect}`, example.slug);
      localStorage.setItem(`paltrainer-practice-${example.dialect}-file`, `${example.slug}.nc`);
      keepSetup(example);
      location.search = `?dialect=${example.dialect}`;
      return;
    }
    filename = `${example.slug}.nc`;
    localStorage.setItem(`${saved}-file`, filename);
    localStorage.setItem(savedExample, example.slug);
    keepSetup(example);
    if (lathe) {
      const next = mountBlank(root.querySelector("#setup"), (changed) => scene?.setup(changed));
      toolbar.replace(example.program);
      scene?.setup({ blank: next.blank });
    } else {
      const next = mountPracticeSetup(root.querySelector("#setup"), (changed) => {
        setTools(window.editor, changed.tools.length ? changed.tools : null);
        scene?.setup(changed);
      });
      setTools(window.editor, next.tools.length ? next.tools : null);
      toolbar.replace(example.program);
      scene?.setup(next);
    }
    show(example);
    showTab("tab-drawing");
  };
  scene = await mountViz(root.querySelector("#viz"), window.editor, { dialect: select.value, setup });
}

// -- milling: the stock and the tools, kept in the browser (setup.js) ----------------------------------
export function mountPracticeSetup(parent, onChange) {
  const setup = practiceSetup();
  // text fields that take "12,5" as 12.5 (numbers.js); the limits are checked in changed()
  const number = (value, min, max, step, label) => decimalInput(value, label, { integer: step === 1 });
  const size = setup.size.map((v, i) => number(v, 1, 2000, 0.1, t(`setup.size.${i}`)));
  const rows = el("tbody");
  const changed = () => {
    const next = {
      size: size.map((input) => parseDecimal(input.value)),
      tools: [...rows.children].map((tr) => {
        const [num, kind, dia] = tr.querySelectorAll("input, select");
        return { number: parseDecimal(num.value), kind: kind.value, diameter: parseDecimal(dia.value) };
      }),
    };
    const valid = next.size.every((v) => v > 0 && v <= 2000)
      && next.tools.every((tool) => Number.isInteger(tool.number) && tool.number >= 1 && tool.number <= 99
        && tool.diameter > 0 && tool.diameter <= 1000);
    message.textContent = valid ? "" : t("setup.invalid");
    if (!valid) return;
    saveSetup(next);
    onChange(next);
  };
  const message = el("p", { className: "error", role: "status" }, "");
  const row = (tool) => {
    const kind = el("select", {}, ...MILLING_TOOL_KINDS.map((k) =>
      el("option", { value: k, selected: tool.kind === k }, t(`kind.${k}`))));
    kind.setAttribute("aria-label", t("tools.kind"));
    const tr = el("tr", {},
      el("td", {}, number(tool.number, 1, 99, 1, t("tools.tool"))), el("td", {}, kind),
      el("td", {}, number(tool.diameter, 0.1, 1000, 0.1, t("tools.diameter"))),
      el("td", {}, el("button", { type: "button", className: "remove", onclick: () => { tr.remove(); changed(); } },
        t("setup.remove"))));
    return tr;
  };
  rows.append(...setup.tools.map(row));
  const add = el("button", { type: "button", id: "add-tool", onclick: () => {
    const used = [...rows.querySelectorAll("tr td:first-child input")].map((i) => parseDecimal(i.value) || 0);
    rows.append(row({ number: Math.max(0, ...used) + 1, kind: "end_mill", diameter: 10 }));
    changed();
  } }, t("setup.add"));
  const form = el("form", { className: "setup", onchange: changed, onsubmit: (e) => e.preventDefault() },
    el("fieldset", {}, el("legend", {}, t("setup.stock")),
      ...size.flatMap((input, i) => [el("label", {}, `${"XYZ"[i]} `, input), " "]), el("span", {}, " mm")),
    el("fieldset", {}, el("legend", {}, t("setup.tools")),
      el("table", {}, el("thead", {}, el("tr", {}, ...["tools.tool", "tools.kind", "tools.diameter"].map((k) =>
        el("th", {}, t(k))), el("th"))), rows),
      el("p", { className: "meta" }, t("setup.default_tools")), add),
    message);
  parent.replaceChildren(form);
  return setup;
}
