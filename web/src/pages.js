// The pages around the editor: login, exercise list, exercise page with submission, instructor view.
// Every text the user reads is German; the API gives German and English messages.

import { lang, message as message_, t } from "./i18n.js";
import { mountEditor } from "./main.js";
import { mountViz } from "./viz.js";
import { loginUrl, safeNext } from "./redirect.js";

async function api(path, options = {}) {
  const r = await fetch(`/api/v1${path}`, { credentials: "same-origin", ...options });
  const body = r.headers.get("content-type")?.includes("json") ? await r.json() : null;
  return { ok: r.ok, status: r.status, body };
}

function el(tag, props = {}, ...children) {
  const node = document.createElement(tag);
  Object.assign(node, props);
  node.append(...children.filter((c) => c !== null && c !== undefined));
  return node;
}

function table(head, rows) {
  return el("table", {},
    el("thead", {}, el("tr", {}, ...head.map((h) => el("th", {}, h)))),
    el("tbody", {}, ...rows.map((r) => el("tr", {}, ...r.map((c) => el("td", {}, String(c)))))));
}

export async function mountLogin(form, message) {
  form.onsubmit = async (event) => {
    event.preventDefault();
    const data = Object.fromEntries(new FormData(form));
    const r = await api("/auth/login", {
      method: "POST", headers: { "Content-Type": "application/json" }, body: JSON.stringify(data),
    });
    if (r.ok) {
      location.href = safeNext(new URLSearchParams(location.search).get("next"));
    } else {
      message.textContent = (r.body?.error && message_(r.body.error)) || t("login.failed");
    }
  };
}

export async function mountExerciseList(parent) {
  const r = await api("/exercises");
  if (r.status === 401) {
    location.href = loginUrl();
    return;
  }
  const kinds = { write: t("kind.write"), complete: t("kind.complete"), fix: t("kind.fix") };
  parent.replaceChildren(el("ul", { className: "exercises" }, ...r.body.map((e) => el("li", {},
    el("a", { href: `/exercises/${e.slug}` }, lang === "en" && e.title_en ? e.title_en : e.title_de),
    el("span", { className: "meta" }, ` ${kinds[e.kind] || ""} · ${e.dialect}`)))));
}

export async function mountExercise(root, slug) {
  const r = await api(`/exercises/${slug}`);
  if (r.status === 401) {
    location.href = loginUrl();
    return;
  }
  if (!r.ok) {
    root.replaceChildren(el("p", { className: "error" }, (r.body?.error && message_(r.body.error)) || t("exercise.missing")));
    return;
  }
  const ex = r.body;
  const title = lang === "en" && ex.title_en ? ex.title_en : ex.title_de;
  const task = lang === "en" && ex.task_en ? ex.task_en : ex.task_de;
  document.title = `PAL Trainer – ${title}`;
  const s = ex.stock;
  const size = s ? s.max.map((v, i) => Math.round((v - s.min[i]) * 1000) / 1000) : null;
  const tools = (ex.tools || []).map((tool) => {
    const cut = (ex.cutting_data || []).find((c) => c.tool === tool.number);
    return [`T${tool.number}`, tool.name || t(`kind.${tool.kind}`), `Ø${tool.diameter}`, cut ? cut.speed : "–",
      cut ? cut.feed : "–"];
  });
  root.querySelector("#title").textContent = title;
  // markdown paragraphs: blank lines separate them, single line breaks are spaces
  root.querySelector("#task").replaceChildren(
    ...task.split(/\n\s*\n/).filter((p) => p.trim()).map((p) => el("p", {}, p.replace(/\s*\n\s*/g, " "))));
  root.querySelector("#data").replaceChildren(
    size ? el("p", {}, t("exercise.stock", { x: size[0], y: size[1], z: size[2] })) : null,
    table([t("tools.tool"), t("tools.kind"), t("tools.diameter"), t("tools.speed"), t("tools.feed")], tools));
  if (ex.gradable && size) {
    // the dimensioned drawing (server-side SVG from the reference); opens full size in a tab, for printing
    const drawing = `/api/v1/exercises/${slug}/drawing.svg?lang=${lang}`;
    root.querySelector("#picture").replaceChildren(
      el("figure", { class: "drawing" },
        el("a", { href: drawing, target: "_blank", rel: "noopener" },
          el("img", { src: drawing, alt: t("drawing.alt"), class: "drawing-sheet" })),
        el("figcaption", {},
          el("a", { href: drawing, target: "_blank", rel: "noopener" }, t("drawing.open")), " · ",
          el("a", { href: `${drawing}&download=true`, download: `${slug}.svg` }, t("drawing.download")), " · ",
          el("a", { href: `/api/v1/exercises/${slug}/sheet.pdf?lang=${lang}`, target: "_blank", rel: "noopener",
            title: t("drawing.sheet_title") }, t("drawing.sheet")))));
  }
  const list = root.querySelector("#diagnostics");
  let scene = null;
  const view = await mountEditor(root.querySelector("#editor"), {
    text: ex.start_program || "", dialect: ex.dialect, list, exercise: slug,
    onChange: (text) => scene?.changed(text), onPointer: (line) => scene?.pointer(line),
  });
  scene = await mountViz(root.querySelector("#viz"), view, { dialect: ex.dialect, exercise: slug });
  const result = root.querySelector("#result");
  root.querySelector("#submit").onclick = async () => {
    result.replaceChildren(el("p", {}, t("submit.busy")));
    const sub = await api("/submissions", {
      method: "POST", headers: { "Content-Type": "application/json" },
      body: JSON.stringify({ exercise: slug, program: view.state.doc.toString() }),
    });
    if (!sub.ok) {
      result.replaceChildren(el("p", { className: "error" }, (sub.body?.error && message_(sub.body.error)) || t("submit.failed")));
      return;
    }
    const g = sub.body.grading;
    if (!g) {
      result.replaceChildren(el("p", {}, t("submit.ungraded")));
      return;
    }
    scene?.graded(view.state.doc.toString());
    result.replaceChildren(
      el("p", { className: "score" }, t("score", { score: g.score, max: g.max_score })),
      el("ul", { className: "criteria" }, ...g.criteria.map((c) => el("li", { className: c.status },
        `${c.status === "passed" ? "✓" : "✗"} ${c.points}/${c.max_points} – ${message_(c)}`,
        ...c.lines.map((n) => el("button", {
          className: "line-link", type: "button", textContent: t("diagnostics.line", { n }),
          onclick: () => {
            const line = view.state.doc.line(Math.min(n, view.state.doc.lines));
            view.dispatch({ selection: { anchor: line.from }, scrollIntoView: true });
            view.focus();
          },
        }))))));
  };
}

export async function mountInstructor(parent) {
  const exercises = await api("/exercises");
  if (exercises.status === 401) {
    location.href = loginUrl();
    return;
  }
  // filter by exercise, list, export
  const filter = el("select", { id: "filter" }, el("option", { value: "" }, t("instructor.all")),
    ...exercises.body.map((e) => el("option", { value: e.slug }, e.title_de)));
  const csv = el("a", { id: "csv", href: "/api/v1/submissions/export.csv" }, t("instructor.csv"));
  const list = el("div", { id: "submission-list" });
  async function show() {
    const query = filter.value ? `?exercise=${encodeURIComponent(filter.value)}` : "";
    csv.href = `/api/v1/submissions/export.csv${query}`;
    const r = await api(`/submissions${query}`);
    list.replaceChildren(table([t("col.number"), t("instructor.exercise"), t("col.learner"), t("col.time"),
      t("col.errors"), t("col.points")], (r.body || []).map((s) => [
      s.id, s.exercise, s.external_user || s.user || "–", new Date(s.created_at).toLocaleString(lang === "en" ? "en-GB" : "de-DE"),
      s.error_count, s.score ?? "–"])));
  }
  filter.onchange = show;
  // authoring: an exercise file (docs/exercises.md), checked by the server
  const file = el("input", { type: "file", id: "exercise-file", accept: ".yaml,.yml,.json" });
  const text = el("textarea", { id: "exercise-text", rows: 8, cols: 80, placeholder: t("instructor.paste") });
  const message = el("p", { id: "upload-message", role: "alert" });
  const upload = el("button", { type: "button", id: "upload" }, t("instructor.create"));
  file.onchange = async () => { text.value = await file.files[0].text(); };
  upload.onclick = async () => {
    const r = await api("/exercises/import", {
      method: "POST", headers: { "Content-Type": "application/yaml" }, body: text.value,
    });
    message.className = r.ok ? "ok" : "error";
    message.textContent = r.ok ? t("instructor.created", { title: r.body.title_de })
      : (r.body?.error && message_(r.body.error)) || t("instructor.error");
    if (r.ok) filter.append(el("option", { value: r.body.slug }, r.body.title_de));
  };
  parent.replaceChildren(
    el("h3", {}, t("instructor.submissions")), el("p", {}, el("label", {}, `${t("instructor.exercise")} `, filter), " ", csv),
    list, el("h3", {}, t("instructor.upload")), el("p", {}, file), text, el("p", {}, upload), message);
  await show();
}

// -- free practice: the stock and the tools, kept in the browser ----------------------------------
const SETUP_KEY = "paltrainer-practice-setup";
const DEFAULT_SETUP = { size: [80, 70, 30], tools: [] };  // the PAL examples' block; tools: the default table

export function practiceSetup() {
  try {
    const saved = JSON.parse(localStorage.getItem(SETUP_KEY));
    if (saved && saved.size?.length === 3 && Array.isArray(saved.tools)) return saved;
  } catch { /* a damaged entry: start afresh */ }
  return structuredClone(DEFAULT_SETUP);
}

// The stock as the API wants it: zero at the front left corner of the top face.
export function stockOf(setup) {
  const [x, y, z] = setup.size;
  return { min: [0, 0, -z], max: [x, y, 0] };
}

export function mountPracticeSetup(parent, onChange) {
  const setup = practiceSetup();
  const number = (value, min, max, step, label) => {
    const input = el("input", { type: "number", value, min, max, step, required: true });
    input.setAttribute("aria-label", label);
    return input;
  };
  const size = setup.size.map((v, i) => number(v, 1, 2000, 1, t(`setup.size.${i}`)));
  const rows = el("tbody");
  const changed = () => {
    const next = {
      size: size.map((input) => Number(input.value)),
      tools: [...rows.children].map((tr) => {
        const [num, kind, dia] = tr.querySelectorAll("input, select");
        return { number: Number(num.value), kind: kind.value, diameter: Number(dia.value) };
      }),
    };
    const valid = next.size.every((v) => v > 0 && v <= 2000)
      && next.tools.every((tool) => tool.number >= 1 && tool.number <= 99 && tool.diameter > 0 && tool.diameter <= 1000);
    message.textContent = valid ? "" : t("setup.invalid");
    if (!valid) return;
    localStorage.setItem(SETUP_KEY, JSON.stringify(next));
    onChange(next);
  };
  const message = el("p", { className: "error", role: "status" }, "");
  const row = (tool) => {
    const kind = el("select", {}, ...["end_mill", "slot_drill"].map((k) =>
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
    const used = [...rows.querySelectorAll("tr td:first-child input")].map((i) => Number(i.value));
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

export { mountViz };  // the 3D view lives in viz.js
