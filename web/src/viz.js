// The 3D view beside the editor: viser's scene in an iframe (/viz/{token}/, its own panel hidden by
// /static/viz-frame.css), with our own toolbar — views (oben, vorne, iso, zurücksetzen), layers with their
// colours as the legend, the deviation colours — and playback. Without graphics acceleration the view starts
// switched off and the same place shows the server's 2D view of the current state (core/picture2d.py: the plan
// view of a milling program, the drawing view of a turning program).

import { lang, message as message_, t } from "./i18n.js";
import { stockOf } from "./setup.js";

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

const post = (body) => ({ method: "POST", headers: { "Content-Type": "application/json" }, body: JSON.stringify(body) });
const number = (value, digits) => value.toLocaleString(lang === "en" ? "en-GB" : "de-DE",
  { minimumFractionDigits: digits, maximumFractionDigits: digits });

export function softwareWebGL() {
  const gl = document.createElement("canvas").getContext("webgl");
  if (!gl) return true;
  const info = gl.getExtension("WEBGL_debug_renderer_info");
  const renderer = info ? String(gl.getParameter(info.UNMASKED_RENDERER_WEBGL)) : "";
  return /swiftshader|llvmpipe|software/i.test(renderer);
}

// layer → its legend entry (the same colours as the scene: server/viz.py)
const LAYERS = [
  { id: "rapid", swatch: "swatch-rapid" }, { id: "feed", swatch: "swatch-feed" },
  { id: "contour", swatch: "swatch-contour" }, { id: "stock", swatch: "swatch-stock" },
];

export async function mountViz(container, view, { dialect = "pal-mill", exercise = null, setup = null } = {}) {
  let token = null;
  let lines = [];
  let states = {};
  let lathe = false;  // a turning program: the drawing view, X shown as a diameter
  let playing = null;
  let timer = null;
  let pictureTimer = null;
  let pictureUrl = null;
  let renewing = false;
  let watch = null;  // the socket that stays open while the scene's server lives (/viz/{token}/alive)
  let gradedText = null;  // the graded program whose deviation colours the view shows (again after switching on)
  const modal = el("p", { id: "modal-state", className: "meta" }, "");
  const frame = el("iframe", { id: "viz-frame", title: t("viz.title") });
  const picture = el("img", { id: "viz-picture", alt: t("viz.picture_alt") });
  picture.style.background = "#fff";  // the 2D view is drawn on white paper: no grey bands beside it
  picture.style.imageRendering = "auto";
  const pictureNote = el("p", { className: "meta viz-picture-note" }, t("viz.picture_note"));
  const stage = el("div", { className: "viz-stage" });
  const slider = el("input", { type: "range", id: "playhead", min: 0, max: 0, value: 0 });
  slider.setAttribute("aria-label", t("play.position"));
  const info = el("span", { id: "playhead-info" }, "");
  const deviation = el("p", { id: "deviation", className: "meta", role: "status" }, "");
  const button = (id, text, title, fn) => el("button", { id, type: "button", title, onclick: fn }, text);
  const stop = () => { clearInterval(playing); playing = null; };
  // free practice: the milling set-up (stock and tools), or for a lathe program the blank (none: the server
  // takes a bar around the program)
  const body = (text) => ({
    program: text, dialect, exercise,
    ...(setup?.size ? { stock: setup.stock || stockOf(setup), tools: setup.tools.length ? setup.tools : null } : {}),
    ...(setup?.blank ? { blank: setup.blank } : {}),
  });

  // -- our toolbar: views, layers (the legend of the path colours), the deviation colours ---------------
  const views = el("div", { className: "viz-views", role: "group" },
    ...["top", "front", "iso", "reset"].map((name) => button(`view-${name}`, t(`viz.view.${name}`),
      t(`viz.view.${name}_title`), () => look(name))));
  views.setAttribute("aria-label", t("viz.views"));
  const layers = el("div", { className: "viz-layers", role: "group" }, ...LAYERS.map(({ id, swatch }) => {
    const box = el("input", { type: "checkbox", id: `layer-${id}`, checked: true,
      onchange: () => token && api(`/viz/${token}/layers`, post({ [id]: box.checked })) });
    return el("label", { className: "viz-layer" }, box, el("span", { className: `swatch ${swatch}` }), t(`viz.layer.${id}`));
  }));
  layers.setAttribute("aria-label", t("viz.layers"));
  const legend = el("div", { className: "viz-legend", role: "group" },
    el("span", { className: "viz-legend-item" }, el("span", { className: "swatch swatch-too-much" }), t("viz.legend.too_much")),
    el("span", { className: "viz-legend-item" }, el("span", { className: "swatch swatch-too-little" }), t("viz.legend.too_little")));
  legend.setAttribute("aria-label", t("viz.legend"));
  const latheNote = el("p", { className: "meta viz-lathe-note", hidden: true }, t("viz.lathe_note"));
  // turning: cut the part open (the back half with the cut face) to show bores and grooves
  const half = button("viz-half", t("viz.half"), t("viz.half_title"), async () => {
    if (!token) return;
    const on = half.getAttribute("aria-pressed") !== "true";
    const r = await api(`/viz/${token}/section`, post({ half: on }));
    if (r.ok) half.setAttribute("aria-pressed", String(Boolean(r.body.half)));
  });
  half.setAttribute("aria-pressed", "false");
  half.hidden = true;
  const blankInfo = el("span", { id: "viz-blank", className: "meta" }, "");
  const toolbar = el("div", { className: "viz-toolbar" }, views, layers, legend, half, latheNote);

  async function look(name) {
    if (!token) return;
    const aspect = frame.clientHeight ? frame.clientWidth / frame.clientHeight : null;
    await api(`/viz/${token}/view`, post({ view: name, ...(aspect ? { aspect } : {}) }));
  }

  // -- playback ------------------------------------------------------------------------------------
  async function moveTo(index, fromEditor = false) {
    if (!lines.length || !token) return;
    index = Math.max(0, Math.min(index, lines.length - 1));
    slider.value = index;
    const r = await api(`/viz/${token}/playhead`, post({ index }));
    const line = r.body?.line;
    const cycle = r.body?.cycle;  // a move a cycle made: its step ("Zyklus G72, Schritt 2 von 3")
    info.textContent = t("play.at", { i: index + 1, n: lines.length, line: line ?? "–" })
      + (cycle ? t("play.cycle", { code: cycle.code, pass: cycle.pass, of: cycle.of }) : "");
    const st = states[line];
    // on a lathe the position's x is the radius (DECISIONS §15): the line shows X as the program writes it,
    // as a diameter
    const where = st && (lathe ? `X${Math.round(st.position[0] * 2000) / 1000} Z${st.position[2]}`
      : `X${st.position[0]} Y${st.position[1]} Z${st.position[2]}`);
    const speed = typeof st?.speed === "number" ? Math.round(st.speed) : st?.speed;  // G96: 1446.86… 1/min
    modal.textContent = st ? [st.plane, st.dimensions, st.compensation, st.zero_offset, `T${st.tool ?? 0}`,
      `F${st.feed}`, `S${speed}`, where].filter((word) => word !== null && word !== undefined).join("  ") : "";
    modal.title = st && lathe ? t("viz.lathe_diameter") : "";
    if (line && !fromEditor) {
      const l = view.state.doc.line(Math.min(line, view.state.doc.lines));
      view.dispatch({ selection: { anchor: l.from, head: l.to }, scrollIntoView: true });
    }
  }

  async function refresh(text) {
    if (!token) return;
    const r = await api(`/viz/${token}/scene`, post(body(text)));
    if ((r.status === 401 || r.status === 403 || r.status === 410) && !renewing) {  // the token expired, belongs
      renewing = true;  // to another session (after logging in, say) or its server stopped: a fresh one, once
      try { await enable(); } finally { renewing = false; }
      return;
    }
    if (!r.ok) return;
    lines = r.body.lines;
    states = r.body.states;
    const b = r.body.blank;
    blankInfo.textContent = b ? t("viz.blank", { d: number(b.diameter, 1).replace(/[,.]0$/, ""),
      l: number(b.length, 1).replace(/[,.]0$/, ""),
      bore: b.inner_diameter ? t("viz.blank_bore", { d: number(b.inner_diameter, 1).replace(/[,.]0$/, "") }) : "" })
      : "";
    if (Boolean(r.body.lathe) !== lathe) {  // the lathe's views and what its view leaves out
      lathe = Boolean(r.body.lathe);
      latheNote.hidden = !lathe;
      half.hidden = !lathe;
      for (const name of ["top", "front"]) {
        views.querySelector(`#view-${name}`).title = t(`viz.view.${name}${lathe ? "_lathe" : ""}_title`);
      }
    }
    slider.max = Math.max(0, lines.length - 1);
    slider.value = slider.max;
    frame.dataset.segments = String(lines.length);
    info.textContent = t("play.segments", { n: lines.length }) + (r.body.cut ? t("play.cut") : "");
  }

  const controls = el("div", { className: "playback" },
    button("step-back", t("play.back"), t("play.back_title"), () => { stop(); moveTo(Number(slider.value) - 1); }),
    button("play", t("play.play"), t("play.play_title"), () => {
      if (playing) { stop(); return; }
      playing = setInterval(() => {
        if (Number(slider.value) >= lines.length - 1) stop(); else moveTo(Number(slider.value) + 1);
      }, 200);
    }),
    button("step", t("play.step"), t("play.step_title"), () => { stop(); moveTo(Number(slider.value) + 1); }),
    slider, info, blankInfo);
  slider.oninput = () => { stop(); moveTo(Number(slider.value)); };
  // Alt with the arrow keys steps, Alt+Space plays and pauses: the same in the editor as anywhere on the page.
  document.addEventListener("keydown", (event) => {
    if (!token || !event.altKey) return;
    const id = { ArrowLeft: "step-back", ArrowRight: "step", " ": "play" }[event.key];
    if (!id) return;
    event.preventDefault();
    controls.querySelector(`#${id}`).click();
  });

  // -- on and off ----------------------------------------------------------------------------------
  async function enable(attempts = 1) {
    let session = await api("/viz", { method: "POST" });
    for (let i = 1; i < attempts && !session.ok && session.status !== 429; i++) {  // a server is restarting
      await new Promise((resolve) => setTimeout(resolve, 300 * i));
      session = await api("/viz", { method: "POST" });
    }
    if (!session.ok) {
      offer((session.body?.error && message_(session.body.error)) || t("viz.none"));
      return;
    }
    token = session.body.token;
    delete frame.dataset.segments;  // until the new scene has answered
    watchScene(token);
    stage.replaceChildren(frame);
    container.replaceChildren(toolbar, stage, controls, modal, el("p", { className: "viz-switch" },
      button("viz-off", t("viz.off"), "", disable)));
    for (const box of layers.querySelectorAll("input")) box.checked = true;
    half.setAttribute("aria-pressed", "false");  // a new scene shows the part whole
    frame.src = session.body.url;
    await look("iso");  // the frame's shape first: the first picture fills it
    await refresh(view.state.doc.toString());
    if (gradedText !== null) await showDeviation(gradedText);  // graded while the view was off
  }

  // after grading: where the part leaves the tolerance band, in colour (the camera shows it)
  async function showDeviation(text) {
    if (!token || !exercise) return;
    const r = await api(`/viz/${token}/deviation`, post({ program: text, dialect, exercise }));
    if (!r.ok) return;
    const d = r.body;
    deviation.textContent = d.too_much || d.too_little
      ? t("deviation.shown", { much: number(d.too_much_mm3, 1), little: number(d.too_little_mm3, 1),
        largest: number(d.largest_mm, 2) })
      : t("deviation.none");
    modal.after(deviation);
  }

  // With several servers each scene lives on one of them (the token names it; the load balancer routes by
  // it). When that server stops, this socket closes at once and a new scene opens on another one.
  function watchScene(current) {
    watch?.close();
    const scheme = location.protocol === "https:" ? "wss" : "ws";
    const ws = new WebSocket(`${scheme}://${location.host}/viz/${current}/alive`);
    let opened = false;  // a socket that never opened (a proxy without WebSockets) is no reason for a new scene
    watch = ws;
    ws.onopen = () => { opened = true; };
    ws.onclose = async () => {
      if (watch !== ws || token !== current || !opened || renewing) return;
      watch = null;
      renewing = true;
      try { await enable(5); } finally { renewing = false; }
    };
  }

  function disable() {
    stop();
    token = null;
    watch?.close();
    watch = null;
    frame.removeAttribute("src");
    offer(t("viz.is_off"));
  }

  // While the view is off, the same place shows the stock after the program, rendered by the server.
  function offer(reason) {
    stage.replaceChildren(picture, pictureNote);
    container.replaceChildren(stage, el("p", { className: "viz-off" }, reason, " ",
      button("viz-on", t("viz.on"), "", enable)));
    updatePicture(view.state.doc.toString());
  }

  // The 2D view (an SVG the server draws: depths with their legend, the path, the contour, axes, the zero, the
  // blocks an error skipped), asked for again whenever the program changes; the newest request wins.
  let pictureAsked = 0;
  async function updatePicture(text) {
    const asked = ++pictureAsked;
    const r = await fetch(`/api/v1/viz/picture.svg?lang=${lang === "en" ? "en" : "de"}`,
      { credentials: "same-origin", ...post(body(text)) });
    if (!r.ok || token || asked !== pictureAsked) return;
    const blob = await r.blob();
    if (asked !== pictureAsked) return;
    if (pictureUrl) URL.revokeObjectURL(pictureUrl);
    const turning = r.headers.get("X-Picture-View") === "lathe";  // the drawing view of a lathe
    pictureNote.textContent = t(turning ? "viz.picture_lathe_note" : "viz.picture_note");
    picture.alt = t(turning ? "viz.picture_lathe_alt" : "viz.picture_alt");
    pictureUrl = URL.createObjectURL(blob);
    picture.src = pictureUrl;
    picture.dataset.view = turning ? "lathe" : "mill";
    picture.dataset.text = text;  // which program it shows (the browser test waits for it)
  }

  // Without graphics acceleration the 3D view would slow the whole page down: then it waits to be asked for.
  if (softwareWebGL()) {
    offer(t("viz.software"));
  } else {
    await enable();
  }
  return {
    changed(text) {
      deviation.remove();
      gradedText = null;
      clearTimeout(timer);
      timer = setTimeout(() => refresh(text), 500);
      if (!token) { clearTimeout(pictureTimer); pictureTimer = setTimeout(() => updatePicture(text), 1000); }
    },
    setup(next) {  // free practice: other stock or tools, or another blank
      setup = next;
      if (token) refresh(view.state.doc.toString()); else updatePicture(view.state.doc.toString());
    },
    async graded(text) {  // the deviation colours now, or as soon as the view is switched on
      gradedText = text;
      await showDeviation(text);
    },
    pointer(line) {  // clicking a line in the editor moves playback to its first step
      const index = lines.indexOf(line);
      if (index >= 0) { stop(); moveTo(index, true); }
    },
  };
}
