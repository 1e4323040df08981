// The exercise editor for instructors (/exercises/new, /exercises/{slug}/edit): the whole exercise in the
// exercise format (docs/exercises.md) as a form — titles, task with its preview (rendered by the server, as the
// exercise page shows it), dialect, kind, blank, tools, cutting data, the reference program in the editor the
// trainees use (live diagnostics), the start program and its locked lines, hints, the solution policy, the
// grading weights, visibility — and the drawing, generated from the reference as it is typed, or the author's own.
// "Speichern" sends the document; the server validates it and names every error at its field.

import { api, el } from "./dom.js";
import { lang, message, t } from "./i18n.js";
import { mountEditor } from "./main.js";
import { mountViz } from "./viz.js";
import { decimalInput, parseDecimal } from "./numbers.js";
import { loginUrl, safeNext } from "./redirect.js";
import { LATHE_DIALECTS, MILLING_TOOL_KINDS } from "./tool-kinds.js";

const LATHE_KINDS = ["turning"];
const NEW_DOCUMENT = {
  format: 1, id: "", title: { de: "", en: "" }, task: { de: "", en: "" }, dialect: "pal-mill", kind: "write",
  stock: { min: [0, 0, -20], max: [80, 70, 0] }, tools: [{ number: 1, kind: "end_mill", diameter: 10 }],
  cutting_data: [], reference: "", start_program: "", locked_lines: [], hints: [], solution: "after_submission",
};
const PREVIEW_DELAY = 700;  // ms after the last keystroke before the drawing or task preview is asked for

function debounce(fn, ms) {
  let timer = null;
  return (...args) => { clearTimeout(timer); timer = setTimeout(() => fn(...args), ms); };
}

const read = (input) => (input.value.trim() === "" ? null : parseDecimal(input.value));
// a number field's value for the document: a number, or the text as typed (the server names what is wrong)
const value = (input) => { const n = read(input); return n === null ? null : Number.isNaN(n) ? input.value : n; };

export async function mountExerciseEdit(root, slug) {
  const form = root.querySelector("#edit-form");
  const heading = root.querySelector("#edit-title");
  const role = document.body.dataset.role;  // set by the server for the logged-in user (server/routes/pages.py)
  if (!role) { location.href = loginUrl(); return; }
  if (!["instructor", "admin"].includes(role)) {
    form.replaceChildren(el("p", { className: "error" }, t("edit.forbidden")));
    return;
  }
  let exercise = null;
  let doc = structuredClone(NEW_DOCUMENT);
  if (slug) {
    const r = await api(`/exercises/${encodeURIComponent(slug)}`);
    if (!r.ok || !r.body.document) {
      form.replaceChildren(el("p", { className: "error" }, (r.body?.error && message(r.body.error)) || t("exercise.missing")));
      return;
    }
    exercise = r.body;
    doc = structuredClone(r.body.document);
  }
  const dialects = await api("/dialects");
  const dialectList = dialects.ok ? dialects.body : [{ name: "pal-mill", title: t("dialect.pal_mill") }];

  // -- a field: label, control, hint, and the place for its errors (data-field: the document's path) --
  const field = (name, label, control, hint = null) => el("div", { className: "field" },
    el("label", {}, label, control), hint ? el("p", { className: "meta" }, hint) : null,
    el("p", { className: "field-error", role: "alert" }));
  const withName = (node, name, label = null) => {
    node.dataset.field = name;
    if (label) node.dataset.label = label;
    return node;
  };
  const text = (v, props = {}) => el("input", { type: "text", value: v ?? "", ...props });
  const area = (v, rows) => el("textarea", { rows, value: v ?? "" });
  const select = (options, current, label = null) => {
    const node = el("select", {}, ...options.map(([v, text]) => el("option", { value: v, selected: v === current }, text)));
    if (label) node.setAttribute("aria-label", label);
    return node;
  };

  const slugInput = text(doc.id, { readOnly: Boolean(slug), pattern: "[a-z0-9][a-z0-9-]*" });
  const titleDe = text(doc.title?.de); const titleEn = text(doc.title?.en);
  // a new exercise's slug follows its title until the author types one ("Kontur FA 23" → kontur-fa-23)
  let slugTyped = Boolean(slug);
  slugInput.addEventListener("input", () => { slugTyped = true; });
  titleDe.addEventListener("input", () => {
    if (slugTyped) return;
    slugInput.value = titleDe.value.toLowerCase().replace(/ä/g, "ae").replace(/ö/g, "oe").replace(/ü/g, "ue")
      .replace(/ß/g, "ss").normalize("NFKD").replace(/[^a-z0-9]+/g, "-").replace(/^-+|-+$/g, "").slice(0, 60);
  });
  const taskDe = area(doc.task?.de, 6); const taskEn = area(doc.task?.en, 4);
  const taskPreview = el("div", { className: "task-text task-preview", id: "task-preview" });
  const dialect = select(dialectList.map((d) => [d.name, (lang === "en" && d.title_en) || d.title || d.name]), doc.dialect);
  const kind = select([["write", t("kind.write")], ["complete", t("kind.complete")], ["fix", t("kind.fix")]], doc.kind);
  const lathe = () => LATHE_DIALECTS.has(dialect.value);

  // -- blank: the box (milling) or the bar/tube (turning) --
  const stock = doc.stock || NEW_DOCUMENT.stock;
  const stockMin = [0, 1, 2].map((i) => decimalInput(stock.min?.[i] ?? 0, `min ${"XYZ"[i]}`));
  const stockMax = [0, 1, 2].map((i) => decimalInput(stock.max?.[i] ?? 0, `max ${"XYZ"[i]}`));
  const blank = doc.blank || { diameter: 60, inner_diameter: 0, length: 80 };
  const blankInputs = {
    diameter: decimalInput(blank.diameter, t("edit.blank_diameter")),
    inner_diameter: decimalInput(blank.inner_diameter ?? 0, t("edit.blank_inner")),
    length: decimalInput(blank.length, t("edit.blank_length")),
    chuck_length: decimalInput(blank.chuck_length ?? "", t("edit.blank_chuck")),
  };
  blankInputs.chuck_length.required = false;
  const zero = text((doc.blank || doc.stock)?.zero?.de ?? "");
  const millBlank = withName(el("div", {},
    field("stock", t("edit.stock_min"), el("span", { className: "triple" }, ...stockMin)),
    field("stock", t("edit.stock_max"), el("span", { className: "triple" }, ...stockMax), t("edit.stock_hint"))), "stock", t("edit.blank"));
  const latheBlank = withName(el("div", { className: "row" }, ...Object.entries(blankInputs).map(([k, input]) =>
    withName(field(`blank.${k}`, t(`edit.blank_${k === "inner_diameter" ? "inner" : k === "chuck_length" ? "chuck" : k}`), input),
      `blank.${k}`))), "blank", t("edit.blank"));

  // -- tools and cutting data: rows; fields the form does not show are kept as they were --
  const toolRows = el("tbody");
  const toolRow = (tool) => {
    const kinds = [...MILLING_TOOL_KINDS, ...LATHE_KINDS];
    const tr = el("tr", {},
      el("td", {}, decimalInput(tool.number, t("edit.tool_number"), { integer: true, size: 3 })),
      el("td", {}, select(kinds.map((k) => [k, t(`kind.${k}`)]), tool.kind || "end_mill", t("tools.kind"))),
      el("td", {}, decimalInput(tool.diameter ?? 10, t("tools.diameter"), { size: 5 })),
      el("td", {}, decimalInput(tool.kind === "turning" ? tool.nose_radius ?? 0 : tool.corner_radius ?? 0, t("edit.tool_radius"), { size: 4 })),
      el("td", {}, decimalInput(tool.quadrant ?? 0, t("edit.tool_quadrant"), { integer: true, size: 2 })),
      el("td", {}, el("button", { type: "button", className: "remove", onclick: () => { tr.remove(); changed(); } }, t("edit.remove"))));
    tr.original = tool;
    return tr;
  };
  toolRows.append(...(doc.tools || []).map(toolRow));
  const tools = () => [...toolRows.children].map((tr) => {
    const [n, k, d, r, q] = tr.querySelectorAll("input, select");
    const entry = { ...tr.original, number: value(n), kind: k.value, diameter: value(d) };
    delete entry.corner_radius; delete entry.nose_radius; delete entry.quadrant;
    const radius = value(r);
    if (k.value === "turning") {
      if (radius) entry.nose_radius = radius;
      if (value(q)) entry.quadrant = value(q);
    } else if (radius && k.value === "torus") entry.corner_radius = radius;
    return entry;
  });
  const addTool = el("button", { type: "button", id: "add-tool", onclick: () => {
    const used = tools().map((x) => Number(x.number) || 0);
    toolRows.append(toolRow({ number: Math.max(0, ...used) + 1, kind: lathe() ? "turning" : "end_mill", diameter: 10 }));
    changed();
  } }, t("edit.add_tool"));

  const cutRows = el("tbody");
  const cutRow = (c) => {
    const tr = el("tr", {},
      el("td", {}, decimalInput(c.tool, t("edit.tool_number"), { integer: true, size: 3 })),
      el("td", {}, decimalInput(c.speed ?? c.cutting_speed ?? "", c.cutting_speed != null ? t("edit.cut_vc") : t("edit.cut_speed"), { size: 6 })),
      el("td", {}, select([["speed", t("edit.cut_speed")], ["cutting_speed", t("edit.cut_vc")]],
        c.cutting_speed != null ? "cutting_speed" : "speed", t("edit.cut_which"))),
      el("td", {}, decimalInput(c.feed ?? "", t("edit.cut_feed"), { size: 6 })),
      el("td", {}, select([["", "–"], ["M3", "M3"], ["M4", "M4"]], c.spindle || "", t("edit.cut_spindle"))),
      el("td", {}, el("button", { type: "button", className: "remove", onclick: () => { tr.remove(); changed(); } }, t("edit.remove"))));
    return tr;
  };
  cutRows.append(...(doc.cutting_data || []).map(cutRow));
  const cutting = () => [...cutRows.children].map((tr) => {
    const [tool, speed, which, feed, spindle] = tr.querySelectorAll("input, select");
    const entry = { tool: value(tool), [which.value]: value(speed), feed: value(feed) };
    if (spindle.value) entry.spindle = spindle.value;
    return entry;
  });
  const addCut = el("button", { type: "button", onclick: () => { cutRows.append(cutRow({ tool: 1 })); } }, t("edit.add_cut"));

  // -- the programs: the reference in the trainees' editor (live diagnostics), the start program --
  const referenceBox = el("div", { className: "editor-box", id: "reference-editor" });
  const diagnostics = el("ul", { className: "diagnostics", id: "reference-diagnostics" });
  let reference = null;
  let scene = null;  // the 3D view, once asked for
  let referenceText = doc.reference || "";
  const liveTools = () => tools().filter((x) => Number.isInteger(x.number) && x.diameter > 0).map((x) => ({
    number: x.number, diameter: x.diameter, kind: x.kind, nose_radius: x.nose_radius || 0, quadrant: x.quadrant || 0 }));
  async function mountReference() {
    reference?.destroy();
    referenceBox.replaceChildren();
    reference = await mountEditor(referenceBox, { text: referenceText, dialect: dialect.value, list: diagnostics,
      tools: liveTools(), onChange: (v) => { referenceText = v; drawingSoon(); scene?.changed(v); } });
  }
  const startBox = el("div", { className: "editor-box", id: "start-editor" });
  let startText = doc.start_program || "";
  let start = null;
  const locked = text((doc.locked_lines || []).join(", "));
  const lockedLines = () => locked.value.split(/[\s,;]+/).filter(Boolean).map((x) => (/^[0-9]+$/.test(x) ? Number(x) : x));
  async function mountStart() {
    start?.destroy();
    startBox.replaceChildren();
    start = await mountEditor(startBox, { text: startText, dialect: dialect.value, live: false, onChange: (v) => { startText = v; } });
  }
  // a click on a line number of the start program locks or frees that line
  startBox.addEventListener("mousedown", (event) => {
    const gutter = event.target.closest?.(".cm-lineNumbers .cm-gutterElement");
    const n = Number(gutter?.textContent);
    if (!n) return;
    const lines = new Set(lockedLines());
    if (lines.has(n)) lines.delete(n); else lines.add(n);
    locked.value = [...lines].sort((a, b) => a - b).join(", ");
  });
  const startSection = el("section", { className: "edit-section", id: "start-section" },
    el("h3", {}, t("edit.start")), withName(el("div", {}, startBox, el("p", { className: "meta" }, t("edit.start_hint")),
      el("p", { className: "field-error", role: "alert" })), "start_program", t("edit.start")),
    withName(field("locked_lines", t("edit.locked"), locked), "locked_lines"));

  const hints = area((doc.hints || []).map((h) => h.de).join("\n\n"), 4);
  const solution = select(["never", "after_submission", "after_full_marks"].map((s) => [s, t(`solution.${s}`)]), doc.solution || "after_submission");
  const visibility = select(["draft", "courses", "public"].map((v) => [v, t(`visibility.${v}`)]), exercise?.visibility || "draft");

  // -- grading weights: the criteria as stored (a new exercise: the server's usual weights) --
  const rubricInputs = (doc.rubric || []).map((c) => ({ c, input: decimalInput(c.points, t(`crit.${c.id}`), { integer: true, size: 3 }) }));
  const rubricSum = el("p", { className: "meta", id: "rubric-sum" });
  const sumRubric = () => { rubricSum.textContent = t("edit.rubric_sum", { n: rubricInputs.reduce((s, r) => s + (read(r.input) || 0), 0) }); };
  sumRubric();
  const rubric = rubricInputs.length
    ? el("div", { className: "rubric", oninput: sumRubric }, ...rubricInputs.map(({ c, input }) =>
      el("label", {}, `${t(`crit.${c.id}`)} `, input)), rubricSum)
    : el("p", { className: "meta" }, t("edit.rubric_default"));

  // -- the drawing: asked for the unsaved state, a moment after the last change --
  const drawingImg = el("img", { id: "drawing-preview", alt: t("drawing.alt") });
  const drawingNote = el("p", { className: "meta", id: "drawing-note" }, t("edit.drawing_hint"));
  let drawingUrl = null;
  let drawingAsked = 0;
  async function drawing() {
    const asked = ++drawingAsked;
    drawingNote.textContent = t("edit.drawing_wait");
    const r = await fetch("/api/v1/exercises/drawing-preview", {
      method: "POST", credentials: "same-origin", headers: { "Content-Type": "application/json" },
      body: JSON.stringify({ document: drawingPart(), lang }),
    });
    if (asked !== drawingAsked) return;  // a newer state is on its way
    if (r.ok) {
      if (drawingUrl) URL.revokeObjectURL(drawingUrl);
      drawingUrl = URL.createObjectURL(await r.blob());
      drawingImg.src = drawingUrl;
      drawingNote.textContent = t("edit.drawing_hint");
    } else {
      const body = await r.json().catch(() => null);
      drawingNote.textContent = t("edit.drawing_error", { msg: (body?.error && message(body.error)) || r.status });
    }
  }
  const drawingSoon = debounce(drawing, PREVIEW_DELAY);
  const drawingPart = () => {
    const d = document_();
    return { dialect: d.dialect, stock: d.stock, blank: d.blank, tools: d.tools, reference: d.reference,
      cutting_data: d.cutting_data, zero_offsets: d.zero_offsets, subprograms: d.subprograms, title: d.title };
  };
  const ownBox = el("div", { id: "own-drawing" });
  function showOwn() {
    if (!exercise) { ownBox.replaceChildren(el("p", { className: "meta" }, t("edit.own_drawing_after_save"))); return; }
    const file = el("input", { type: "file", id: "own-drawing-file", accept: ".pdf,.png,.svg,application/pdf,image/png,image/svg+xml" });
    file.setAttribute("aria-label", t("edit.own_drawing"));
    const note = el("p", { className: "field-error", role: "alert" });
    file.onchange = async () => {
      const chosen = file.files[0];
      if (!chosen) return;
      const r = await api(`/exercises/${encodeURIComponent(exercise.slug)}/own-drawing?filename=${encodeURIComponent(chosen.name)}`,
        { method: "PUT", headers: { "Content-Type": "application/octet-stream" }, body: chosen });
      if (r.ok) { exercise = r.body; showOwn(); ownBox.querySelector(".meta")?.append(` ${t("edit.own_drawing_uploaded")}`); }
      else note.textContent = (r.body?.error && message(r.body.error)) || t("edit.error");
    };
    const parts = [el("label", {}, `${t("edit.own_drawing")} `, file), note];
    if (exercise.own_drawing) {
      const type = exercise.own_drawing.split("/")[1].replace("+xml", "").toUpperCase();
      parts.unshift(el("p", { className: "meta" }, `${t("edit.own_drawing_set", { type })} `,
        el("a", { href: `/api/v1/exercises/${encodeURIComponent(exercise.slug)}/own-drawing`, target: "_blank", rel: "noopener" }, t("edit.own_drawing_open")), " ",
        el("button", { type: "button", id: "own-drawing-remove", onclick: async () => {
          const r = await api(`/exercises/${encodeURIComponent(exercise.slug)}/own-drawing`, { method: "DELETE" });
          if (r.ok) { exercise = { ...exercise, own_drawing: null }; showOwn(); }
        } }, t("edit.own_drawing_remove"))));
    }
    ownBox.replaceChildren(...parts);
  }

  // -- the 3D view of the reference (free practice's scene with the form's blank and tools), on request --
  const vizBox = el("div", { id: "viz", className: "edit-viz" });
  const vizButton = el("button", { type: "button", id: "viz-show" }, t("edit.viz_show"));
  vizButton.onclick = async () => {
    const d = document_();
    const setup = lathe() ? { blank: d.blank, tools: liveTools() }
      : { size: [0, 1, 2].map((i) => d.stock.max[i] - d.stock.min[i]), stock: { min: d.stock.min, max: d.stock.max },
        tools: liveTools() };
    vizBox.replaceChildren();
    scene = await mountViz(vizBox, reference, { dialect: dialect.value, setup });
    vizButton.textContent = t("edit.viz_again");
  };

  // -- the document from the form, on top of the one loaded (fields the form does not show stay) --
  function document_() {
    /** @type {Record<string, any>} */
    const d = { ...doc, id: slugInput.value.trim(), title: { de: titleDe.value, en: titleEn.value },
      task: { de: taskDe.value, en: taskEn.value }, dialect: dialect.value, kind: kind.value,
      tools: tools(), cutting_data: cutting(), reference: referenceText, solution: solution.value };
    const zeroText = zero.value.trim() ? { zero: { de: zero.value.trim(), en: (doc.blank || doc.stock)?.zero?.en || "" } } : {};
    if (lathe()) {
      d.blank = { ...(doc.blank || {}), ...zeroText };
      for (const [k, input] of Object.entries(blankInputs)) {
        const v = value(input);
        if (v === null) delete d.blank[k]; else d.blank[k] = v;
      }
      delete d.stock;
    } else {
      d.stock = { ...(doc.stock || {}), min: stockMin.map(value), max: stockMax.map(value), ...zeroText };
      delete d.blank;
    }
    if (kind.value === "write") { d.start_program = ""; d.locked_lines = []; } else {
      d.start_program = startText;
      d.locked_lines = kind.value === "complete" ? lockedLines() : [];
    }
    const old = doc.hints || [];
    d.hints = hints.value.split(/\n\s*\n/).map((h) => h.trim()).filter(Boolean).map((h, i) =>
      ({ de: h, en: old[i]?.de === h ? old[i].en || "" : "" }));
    if (rubricInputs.length) d.rubric = rubricInputs.map(({ c, input }) => ({ ...c, points: value(input) }));
    return d;
  }

  // -- errors at their fields; the rest above the button --
  const summary = el("div", { id: "edit-errors", role: "alert" });
  const status = el("p", { id: "edit-status", role: "status" });
  function showErrors(errors, fallback) {
    for (const node of form.querySelectorAll(".field-error")) node.textContent = "";
    for (const node of form.querySelectorAll(".has-error")) node.classList.remove("has-error");
    const items = [];
    for (const e of errors) {
      // "tools[2].diameter" is shown at "tools", "blank.length" at "blank.length" or else "blank"
      let name = String(e.field || "");
      let target = null;
      while (name && !(target = form.querySelector(`[data-field="${CSS.escape(name)}"]`))) {
        const shorter = name.replace(/(\[[0-9]+\]|\.[^.[\]]*)$/, "");
        name = shorter === name ? "" : shorter;
      }
      // at the field its message (with the entry, e.g. "tools[2].diameter", where the field is a list); above
      // the button the field's label
      const inner = target && name !== e.field ? `${e.field.slice(name.length).replace(/^\./, "")}: ${message(e)}` : message(e);
      const label = target?.dataset.label || target?.querySelector("label, h4")?.firstChild?.textContent?.trim();
      if (target) {
        target.classList.add("has-error");
        const slot = target.querySelector(".field-error") || target.appendChild(el("p", { className: "field-error", role: "alert" }));
        slot.textContent = slot.textContent ? `${slot.textContent} · ${inner}` : inner;
      }
      items.push(el("li", {}, `${label || e.field}: ${message(e)}`));
    }
    summary.replaceChildren(...(items.length ? [el("p", { className: "error" }, t("edit.errors")), el("ul", {}, ...items)]
      : fallback ? [el("p", { className: "error" }, fallback)] : []));
    form.querySelector(".has-error")?.scrollIntoView({ block: "center" });
  }

  const save = el("button", { type: "button", id: "save", className: "primary" }, t("edit.save"));
  save.onclick = async () => {
    save.disabled = true;
    status.textContent = "";
    const body = JSON.stringify({ document: document_(), visibility: visibility.value });
    const r = exercise
      ? await api(`/exercises/${encodeURIComponent(exercise.slug)}`, { method: "PATCH", headers: { "Content-Type": "application/json" }, body })
      : await api("/exercises", { method: "POST", headers: { "Content-Type": "application/json" }, body });
    save.disabled = false;
    if (!r.ok) {
      showErrors(r.body?.error?.details?.errors || [], (r.body?.error && message(r.body.error)) || t("edit.error"));
      return;
    }
    showErrors([]);
    const created = !exercise;
    exercise = r.body;
    doc = structuredClone(r.body.document);
    status.textContent = t("edit.saved", { v: exercise.version });
    if (created) {
      history.replaceState(null, "", `/exercises/${encodeURIComponent(exercise.slug)}/edit`);
      slugInput.readOnly = true;
      showOwn();
      links();
    }
    heading.textContent = t("edit.title_edit", { title: exercise.title_de });
  };

  // -- secondary: YAML export of this exercise, a new exercise from a YAML file --
  const other = el("div", { id: "edit-other" });
  function links() {
    const importFile = el("input", { type: "file", id: "import-file", accept: ".yaml,.yml,.json" });
    importFile.setAttribute("aria-label", t("edit.import"));
    importFile.onchange = async () => {
      const r = await api("/exercises/import?visibility=draft", { method: "POST", headers: { "Content-Type": "application/yaml" },
        body: await importFile.files[0].text() });
      if (r.ok) location.href = safeNext(editPath(r.body.slug));
      else showErrors(r.body?.error?.details?.errors || [], (r.body?.error && message(r.body.error)) || t("edit.error"));
    };
    other.replaceChildren(
      exercise ? el("p", {}, el("a", { href: `/api/v1/exercises/${encodeURIComponent(exercise.slug)}/export`, id: "export" }, t("edit.export")),
        " · ", el("a", { href: `/exercises/${encodeURIComponent(exercise.slug)}` }, t("edit.view"))) : "",
      el("p", {}, el("label", {}, `${t("edit.import")} `, importFile)));
  }
  links();

  // -- the task's preview: the server renders the Markdown, as on the exercise page --
  async function taskPreviewNow() {
    const r = await api("/exercises/task-preview", { method: "POST", headers: { "Content-Type": "application/json" },
      body: JSON.stringify({ markdown: taskDe.value }) });
    if (r.ok) taskPreview.innerHTML = r.body.html;  // safe HTML from the server (core/sheet/tasktext.py)
  }
  const taskSoon = debounce(taskPreviewNow, 300);
  taskDe.addEventListener("input", taskSoon);

  const changed = () => { drawingSoon(); };
  function showKind() {
    startSection.hidden = kind.value === "write";
    locked.closest(".field").hidden = kind.value !== "complete";
  }
  function showDialect() {
    millBlank.hidden = lathe();
    latheBlank.hidden = !lathe();
  }
  kind.onchange = async () => { showKind(); if (kind.value !== "write" && !start) await mountStart(); };
  dialect.onchange = async () => {
    showDialect();
    scene = null;  // the 3D view belonged to the editor of the other dialect
    vizBox.replaceChildren();
    vizButton.textContent = t("edit.viz_show");
    await mountReference();
    if (start) await mountStart();
    changed();
  };

  const section = (title, ...children) => el("section", { className: "edit-section" }, el("h3", {}, title), ...children);
  form.replaceChildren(
    section(t("edit.general"),
      withName(field("id", t("edit.slug"), slugInput, t("edit.slug_hint")), "id"),
      el("div", { className: "row" }, withName(field("title.de", t("edit.title_de"), titleDe), "title.de"),
        withName(field("title.en", t("edit.title_en"), titleEn), "title.en")),
      el("div", { className: "row" }, withName(field("dialect", t("edit.dialect"), dialect), "dialect"),
        withName(field("kind", t("edit.kind"), kind), "kind"),
        withName(field("visibility", t("edit.visibility"), visibility), "visibility"))),
    section(t("edit.task"),
      el("div", { className: "task-edit" }, withName(field("task.de", t("edit.task_de"), taskDe, t("edit.task_hint")), "task.de"),
        el("div", {}, el("p", { className: "meta" }, t("edit.preview")), taskPreview)),
      withName(field("task.en", t("edit.task_en"), taskEn), "task.en")),
    section(t("edit.blank"), millBlank, latheBlank, withName(field("zero", t("edit.zero"), zero), "zero")),
    section(t("edit.tools"), withName(el("div", {}, el("table", { className: "edit-table", onchange: changed },
      el("thead", {}, el("tr", {}, ...["edit.tool_number", "tools.kind", "tools.diameter", "edit.tool_radius", "edit.tool_quadrant"].map((k) =>
        el("th", {}, t(k))), el("th"))), toolRows), addTool, el("p", { className: "field-error", role: "alert" })), "tools", t("edit.tools")),
    withName(el("div", {}, el("h4", {}, t("edit.cutting")), el("table", { className: "edit-table" },
      el("thead", {}, el("tr", {}, ...["edit.tool_number", "edit.cut_speed", "", "edit.cut_feed", "edit.cut_spindle"].map((k) =>
        el("th", {}, k ? t(k) : "")), el("th"))), cutRows), addCut, el("p", { className: "field-error", role: "alert" })), "cutting_data")),
    el("section", { className: "edit-section program-and-drawing" },
      el("div", {}, el("h3", {}, t("edit.reference")), withName(el("div", {}, referenceBox,
        el("p", { className: "field-error", role: "alert" })), "reference", t("edit.reference")),
      el("p", { className: "meta" }, t("edit.reference_hint")), diagnostics),
      el("div", {}, el("h3", {}, t("edit.drawing")), el("figure", { className: "drawing-preview" }, drawingImg), drawingNote, ownBox)),
    section(t("edit.viz"), el("p", {}, vizButton), vizBox),
    startSection,
    section(t("edit.hints"), withName(field("hints", t("edit.hints"), hints), "hints"),
      withName(field("solution", t("edit.solution"), solution), "solution")),
    section(t("edit.rubric"), withName(el("div", {}, rubric, el("p", { className: "field-error", role: "alert" })), "rubric", t("edit.rubric"))),
    el("div", { className: "edit-actions" }, summary, save, status),
    section(t("edit.other"), other),
    el("p", {}, el("a", { href: "/instructor" }, t("edit.back"))));
  for (const input of [...stockMin, ...stockMax, ...Object.values(blankInputs)]) input.addEventListener("input", changed);
  toolRows.addEventListener("input", changed);
  if (exercise) heading.textContent = t("edit.title_edit", { title: exercise.title_de });
  showKind();
  showDialect();
  showOwn();
  taskPreviewNow();
  drawing();
  await mountReference();
  if (kind.value !== "write") await mountStart();
}

// the editor of a saved exercise (the page goes there through the one redirect rule, safeNext)
function editPath(slug) { return `/exercises/${encodeURIComponent(slug)}/edit`; }
