// The pages around the editor: login, exercise list, exercise page with submission, instructor view.
// Every text the user reads is German; the API gives German and English messages.

import { mountEditor } from "./main.js";

const KIND_DE = {
  end_mill: "Schaftfräser", slot_drill: "Langlochfräser", ball_nose: "Radiusfräser", torus: "Eckradiusfräser",
  twist_drill: "Spiralbohrer", spot_drill: "NC-Anbohrer",
};

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
      location.href = new URLSearchParams(location.search).get("next") || "/";
    } else {
      message.textContent = r.body?.error?.message || "Anmeldung fehlgeschlagen.";
    }
  };
}

export async function mountExerciseList(parent) {
  const r = await api("/exercises");
  if (r.status === 401) {
    location.href = `/login?next=${encodeURIComponent(location.pathname)}`;
    return;
  }
  const kinds = { write: "Programm schreiben", complete: "Programm ergänzen", fix: "Fehler finden" };
  parent.replaceChildren(el("ul", { className: "exercises" }, ...r.body.map((e) => el("li", {},
    el("a", { href: `/exercises/${e.slug}` }, e.title_de),
    el("span", { className: "meta" }, ` ${kinds[e.kind] || ""} · ${e.dialect}`)))));
}

export async function mountExercise(root, slug) {
  const r = await api(`/exercises/${slug}`);
  if (r.status === 401) {
    location.href = `/login?next=${encodeURIComponent(location.pathname)}`;
    return;
  }
  if (!r.ok) {
    root.replaceChildren(el("p", { className: "error" }, r.body?.error?.message || "Aufgabe nicht gefunden."));
    return;
  }
  const ex = r.body;
  document.title = `PAL Trainer – ${ex.title_de}`;
  const s = ex.stock;
  const size = s ? s.max.map((v, i) => Math.round((v - s.min[i]) * 1000) / 1000) : null;
  const tools = (ex.tools || []).map((t) => {
    const cut = (ex.cutting_data || []).find((c) => c.tool === t.number);
    return [`T${t.number}`, t.name || KIND_DE[t.kind] || t.kind, `Ø${t.diameter}`, cut ? cut.speed : "–",
      cut ? cut.feed : "–"];
  });
  root.querySelector("#title").textContent = ex.title_de;
  // markdown paragraphs: blank lines separate them, single line breaks are spaces
  root.querySelector("#task").replaceChildren(
    ...ex.task_de.split(/\n\s*\n/).filter((p) => p.trim()).map((p) => el("p", {}, p.replace(/\s*\n\s*/g, " "))));
  root.querySelector("#data").replaceChildren(
    size ? el("p", {}, `Rohteil ${size[0]} × ${size[1]} × ${size[2]} mm`) : null,
    table(["Werkzeug", "Art", "Durchmesser", "S (1/min)", "F (mm/min)"], tools));
  if (ex.gradable && size) {
    root.querySelector("#picture").replaceChildren(
      el("figure", {},
        el("img", { src: `/api/v1/exercises/${slug}/picture.png`, alt: "Fertigteil von oben", width: 320 }),
        el("figcaption", {}, `Fertigteil von oben: ${size[0]} mm × ${size[1]} mm (dunkler = tiefer)`)));
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
    result.replaceChildren(el("p", {}, "Wird bewertet …"));
    const sub = await api("/submissions", {
      method: "POST", headers: { "Content-Type": "application/json" },
      body: JSON.stringify({ exercise: slug, program: view.state.doc.toString() }),
    });
    if (!sub.ok) {
      result.replaceChildren(el("p", { className: "error" }, sub.body?.error?.message || "Abgabe fehlgeschlagen."));
      return;
    }
    const g = sub.body.grading;
    if (!g) {
      result.replaceChildren(el("p", {}, "Abgegeben. Diese Aufgabe wird nicht automatisch bewertet."));
      return;
    }
    result.replaceChildren(
      el("p", { className: "score" }, `${g.score} von ${g.max_score} Punkten`),
      el("ul", { className: "criteria" }, ...g.criteria.map((c) => el("li", { className: c.status },
        `${c.status === "passed" ? "✓" : "✗"} ${c.points}/${c.max_points} – ${c.message}`,
        ...c.lines.map((n) => el("button", {
          className: "line-link", type: "button", textContent: `Zeile ${n}`,
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
    location.href = `/login?next=${encodeURIComponent(location.pathname)}`;
    return;
  }
  // filter by exercise, list, export
  const filter = el("select", { id: "filter" }, el("option", { value: "" }, "alle Aufgaben"),
    ...exercises.body.map((e) => el("option", { value: e.slug }, e.title_de)));
  const csv = el("a", { id: "csv", href: "/api/v1/submissions/export.csv" }, "als CSV herunterladen");
  const list = el("div", { id: "submission-list" });
  async function show() {
    const query = filter.value ? `?exercise=${encodeURIComponent(filter.value)}` : "";
    csv.href = `/api/v1/submissions/export.csv${query}`;
    const r = await api(`/submissions${query}`);
    list.replaceChildren(table(["Nr.", "Aufgabe", "Teilnehmer", "Zeit", "Fehler", "Punkte"], (r.body || []).map((s) => [
      s.id, s.exercise, s.user || s.external_user || "–", new Date(s.created_at).toLocaleString("de-DE"),
      s.error_count, s.score ?? "–"])));
  }
  filter.onchange = show;
  // authoring: an exercise file (docs/exercises.md), checked by the server
  const file = el("input", { type: "file", id: "exercise-file", accept: ".yaml,.yml,.json" });
  const text = el("textarea", { id: "exercise-text", rows: 8, cols: 80, placeholder: "oder den Inhalt der Datei hier einfügen" });
  const message = el("p", { id: "upload-message", role: "alert" });
  const upload = el("button", { type: "button", id: "upload" }, "Aufgabe anlegen");
  file.onchange = async () => { text.value = await file.files[0].text(); };
  upload.onclick = async () => {
    const r = await api("/exercises/import", {
      method: "POST", headers: { "Content-Type": "application/yaml" }, body: text.value,
    });
    message.className = r.ok ? "ok" : "error";
    message.textContent = r.ok ? `Aufgabe »${r.body.title_de}« angelegt.` : r.body?.error?.message || "Fehler.";
    if (r.ok) filter.append(el("option", { value: r.body.slug }, r.body.title_de));
  };
  parent.replaceChildren(
    el("h3", {}, "Abgaben"), el("p", {}, el("label", {}, "Aufgabe ", filter), " ", csv), list,
    el("h3", {}, "Neue Aufgabe hochladen"), el("p", {}, file), text, el("p", {}, upload), message);
  await show();
}

// -- the 3D view and playback --------------------------------------------------------------------
function softwareWebGL() {
  const gl = document.createElement("canvas").getContext("webgl");
  if (!gl) return true;
  const info = gl.getExtension("WEBGL_debug_renderer_info");
  const renderer = info ? String(gl.getParameter(info.UNMASKED_RENDERER_WEBGL)) : "";
  return /swiftshader|llvmpipe|software/i.test(renderer);
}

export async function mountViz(container, view, { dialect = "pal-mill", exercise = null } = {}) {
  let token = null;
  let lines = [];
  let states = {};
  const modal = el("p", { id: "modal-state", className: "meta" }, "");
  let playing = null;
  let timer = null;
  const frame = el("iframe", { id: "viz-frame", title: "3D-Ansicht" });
  const slider = el("input", { type: "range", id: "playhead", min: 0, max: 0, value: 0 });
  slider.setAttribute("aria-label", "Abspielposition");
  const info = el("span", { id: "playhead-info" }, "");
  const button = (id, text, title, fn) => el("button", { id, type: "button", title, onclick: fn }, text);
  const stop = () => { clearInterval(playing); playing = null; };

  async function moveTo(index, fromEditor = false) {
    if (!lines.length || !token) return;
    index = Math.max(0, Math.min(index, lines.length - 1));
    slider.value = index;
    const r = await api(`/viz/${token}/playhead`, {
      method: "POST", headers: { "Content-Type": "application/json" }, body: JSON.stringify({ index }),
    });
    const line = r.body?.line;
    info.textContent = `Schritt ${index + 1} von ${lines.length} · Zeile ${line ?? "–"}`;
    const st = states[line];
    modal.textContent = st ? [st.plane, st.dimensions, st.compensation, st.zero_offset, `T${st.tool ?? 0}`,
      `F${st.feed}`, `S${st.speed}`, `X${st.position[0]} Y${st.position[1]} Z${st.position[2]}`].join("  ") : "";
    if (line && !fromEditor) {
      const l = view.state.doc.line(Math.min(line, view.state.doc.lines));
      view.dispatch({ selection: { anchor: l.from, head: l.to }, scrollIntoView: true });
    }
  }

  async function refresh(text) {
    if (!token) return;
    const r = await api(`/viz/${token}/scene`, {
      method: "POST", headers: { "Content-Type": "application/json" },
      body: JSON.stringify({ program: text, dialect, exercise }),
    });
    if (!r.ok) return;
    lines = r.body.lines;
    states = r.body.states;
    slider.max = Math.max(0, lines.length - 1);
    slider.value = slider.max;
    frame.dataset.segments = String(lines.length);
    info.textContent = `${lines.length} Wegstücke${r.body.cut ? " (gekürzt)" : ""}`;
  }

  const controls = el("div", { className: "playback" },
    button("step-back", "« zurück", "Schritt zurück", () => { stop(); moveTo(Number(slider.value) - 1); }),
    button("play", "Abspielen", "Abspielen / anhalten", () => {
      if (playing) { stop(); return; }
      playing = setInterval(() => {
        if (Number(slider.value) >= lines.length - 1) stop(); else moveTo(Number(slider.value) + 1);
      }, 200);
    }),
    button("step", "vor »", "Schritt vor", () => { stop(); moveTo(Number(slider.value) + 1); }),
    slider, info);
  slider.oninput = () => { stop(); moveTo(Number(slider.value)); };

  async function enable() {
    const session = await api("/viz", { method: "POST" });
    if (!session.ok) {
      container.replaceChildren(el("p", { className: "error" }, session.body?.error?.message || "Keine 3D-Ansicht."));
      return;
    }
    token = session.body.token;
    frame.src = session.body.url;
    container.replaceChildren(frame, controls, modal,
      el("p", {}, button("viz-off", "3D-Ansicht ausschalten", "", disable)));
    await refresh(view.state.doc.toString());
  }

  function disable() {
    stop();
    token = null;
    frame.removeAttribute("src");
    offer("3D-Ansicht ist ausgeschaltet.");
  }

  function offer(reason) {
    container.replaceChildren(el("p", { className: "viz-off" }, reason, " ",
      button("viz-on", "3D-Ansicht einschalten", "", enable)));
  }

  // Without graphics acceleration the 3D view would slow the whole page down: then it waits to be asked for.
  if (softwareWebGL()) {
    offer("Dieser Browser zeichnet 3D ohne Grafikbeschleunigung; die 3D-Ansicht ist darum zunächst aus.");
  } else {
    await enable();
  }
  return {
    changed(text) { clearTimeout(timer); timer = setTimeout(() => refresh(text), 500); },
    pointer(line) {  // clicking a line in the editor moves playback to its first step
      const index = lines.indexOf(line);
      if (index >= 0) { stop(); moveTo(index, true); }
    },
  };
}
