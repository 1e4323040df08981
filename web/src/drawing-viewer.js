// The dimensioned drawing (an A4 sheet, server-side SVG) readable on a laptop: fitted to the room it has (the
// Zeichnung tab's height and width, or the whole window on the drawing's own page), zoomed and moved with the
// mouse wheel, dragging, two fingers (pinch), the buttons − + ⤢ and the keys + − 0 and the arrows. The image is
// re-laid out at each zoom (not scaled as a bitmap), so its lines and numbers stay sharp. In the tab "Einpassen"
// fits the views with their dimensions (the SVG's data-views, core/drawing), not the empty paper around them;
// pressed again, the whole sheet.
//
// "Zeichnung groß öffnen" opens the drawing's own page (/exercises/{slug}/drawing, /examples/{slug}/drawing;
// page-drawing.js: the same viewer over the whole window, with "Drucken", which prints the sheet alone on A4
// landscape).

import { el } from "./dom.js";
import { t } from "./i18n.js";
import { framedHref } from "./lti-frame.js";

const SHEET_WIDTH = (297 / 25.4) * 96;  // CSS px of the A4 sheet at 100 %
const STEP = 1.25;  // one button press or key: 25 % more or less
const MOVE = 48;  // px per arrow key (four times that with Shift)

// The drawing's own page for its SVG's API address (/api/v1/exercises/{slug}/drawing.svg?lang=…), inside a
// learning platform's frame with the platform and the token (lti-frame.js).
export function drawingPageUrl(svgUrl) {
  const url = new URL(svgUrl, location.href);
  const m = url.pathname.match(/^\/api\/v1\/(exercises|examples)\/([^/]+)\/drawing\.svg$/);
  return m ? framedHref(`/${m[1]}/${m[2]}/drawing`) : svgUrl;
}

function iconButton(text, key, onclick) {
  const b = el("button", { type: "button", className: "icon", title: t(key), onclick }, text);
  b.setAttribute("aria-label", t(key));
  return b;
}

// The viewer: a toolbar (− + ⤢, the zoom level, links) over the stage with the sheet. `links`: "groß öffnen"
// (not on the drawing's own page), the SVG download and, with `sheet`, the task sheet (PDF).
export function drawingViewer(url, { slug = t("drawing.default_name"), sheet = null, page = true, extra = [], whole = false } = {}) {
  const img = el("img", { alt: t("drawing.alt"), draggable: false, className: "drawing-image" });
  const stage = el("div", { className: "drawing-stage zoom-frame", tabIndex: 0 }, img);  // zoom-frame: as before
  stage.setAttribute("role", "application");
  stage.setAttribute("aria-label", t("drawing.stage"));
  stage.title = t("drawing.hint");
  const level = el("span", { className: "meta drawing-level", title: t("drawing.level") }, "");
  let aspect = 297 / 210;
  let region = null;  // the views on the sheet, as shares of its width and height: [x0, y0, x1, y1]
  let view = null;  // { k, x, y }: the sheet's width is k × SHEET_WIDTH, its top left corner at (x, y) in the stage
  let fitted = true;  // follows the stage's size until the trainee zooms or moves
  let sheetFit = whole;  // "Einpassen" fits the whole sheet (else the views)

  const size = () => ({ w: stage.clientWidth, h: stage.clientHeight });
  const area = () => (sheetFit || !region ? [0, 0, 1, 1] : region);
  const fitScale = (part = [0, 0, 1, 1]) => {
    const { w, h } = size();
    return Math.min(w / ((part[2] - part[0]) * SHEET_WIDTH), h / ((part[3] - part[1]) * SHEET_WIDTH / aspect));
  };
  const limits = () => { const f = fitScale(); return [f * 0.5, Math.max(f * 12, 4)]; };
  // the sheet may not leave the stage: it keeps covering all of it, or at least 60 % of the way across
  const clamp = (v) => {
    const { w, h } = size();
    const sw = v.k * SHEET_WIDTH;
    const sh = sw / aspect;
    const x = Math.min(Math.max(0, w - sw) + 0.4 * w, Math.max(Math.min(0, w - sw) - 0.4 * w, v.x));
    const y = Math.min(Math.max(0, h - sh) + 0.4 * h, Math.max(Math.min(0, h - sh) - 0.4 * h, v.y));
    return { k: v.k, x, y };
  };
  const apply = () => {
    if (!view) return;
    const sw = view.k * SHEET_WIDTH;
    img.style.width = `${sw}px`;
    img.style.height = `${sw / aspect}px`;
    img.style.transform = `translate(${view.x}px, ${view.y}px)`;
    level.textContent = `${Math.round(view.k * 100)} %`;
    stage.dataset.zoom = view.k.toFixed(4);  // for the browser tests
    stage.dataset.fitted = String(fitted);
  };
  const fit = () => {
    const { w, h } = size();
    if (!w || !h) return;  // hidden (another tab): fitted when shown
    fitted = true;
    const part = area();
    const k = fitScale(part);
    const sw = k * SHEET_WIDTH;
    const sh = sw / aspect;
    view = clamp({ k, x: (w - (part[2] - part[0]) * sw) / 2 - part[0] * sw, y: (h - (part[3] - part[1]) * sh) / 2 - part[1] * sh });
    apply();
  };
  // the button and the key 0: fit the views; when they are fitted already, the whole sheet (and back)
  const refit = () => {
    if (fitted && region) sheetFit = !sheetFit;
    fit();
  };
  // zoom by `factor` keeping the sheet's point under (px, py) (stage px) where it is
  const zoom = (factor, px, py) => {
    if (!view) fit();
    if (!view) return;
    const { w, h } = size();
    const [lo, hi] = limits();
    const k = Math.min(hi, Math.max(lo, view.k * factor));
    const cx = px ?? w / 2;
    const cy = py ?? h / 2;
    const r = k / view.k;
    fitted = false;
    view = clamp({ k, x: cx - (cx - view.x) * r, y: cy - (cy - view.y) * r });
    apply();
  };
  const move = (dx, dy) => {
    if (!view) return;
    fitted = false;
    view = clamp({ ...view, x: view.x + dx, y: view.y + dy });
    apply();
  };
  img.addEventListener("load", () => {
    if (img.naturalWidth && img.naturalHeight) aspect = img.naturalWidth / img.naturalHeight;
    if (fitted) fit(); else { view = clamp(view); apply(); }
  });
  new ResizeObserver(() => { if (fitted || !view) fit(); else { view = clamp(view); apply(); } }).observe(stage);

  // the wheel (and a touchpad's pinch, which arrives as a wheel with Ctrl) zooms at the pointer
  stage.addEventListener("wheel", (event) => {
    event.preventDefault();
    const box = stage.getBoundingClientRect();
    const delta = event.deltaMode === 1 ? event.deltaY * 16 : event.deltaY;
    zoom(Math.exp(-delta * (event.ctrlKey ? 0.01 : 0.0015)), event.clientX - box.left, event.clientY - box.top);
  }, { passive: false });
  stage.addEventListener("dblclick", (event) => {
    const box = stage.getBoundingClientRect();
    zoom(2, event.clientX - box.left, event.clientY - box.top);
  });
  // one pointer drags the sheet, two pinch it (the zoom about their middle, which moves it too)
  const pointers = new Map();
  let last = null;
  const gesture = () => {
    const [a, b] = [...pointers.values()];
    return b ? { x: (a.x + b.x) / 2, y: (a.y + b.y) / 2, d: Math.hypot(a.x - b.x, a.y - b.y) } : { x: a.x, y: a.y, d: 0 };
  };
  stage.addEventListener("pointerdown", (event) => {
    if (event.button !== 0 && event.pointerType === "mouse") return;
    try { stage.setPointerCapture(event.pointerId); } catch { /* a pointer the browser no longer knows */ }
    pointers.set(event.pointerId, { x: event.clientX, y: event.clientY });
    last = gesture();
    stage.classList.add("dragging");
  });
  stage.addEventListener("pointermove", (event) => {
    if (!pointers.has(event.pointerId)) return;
    pointers.set(event.pointerId, { x: event.clientX, y: event.clientY });
    const now = gesture();
    if (last && now.d && last.d) {
      const box = stage.getBoundingClientRect();
      zoom(now.d / last.d, now.x - box.left, now.y - box.top);
    }
    if (last) move(now.x - last.x, now.y - last.y);
    last = now;
  });
  const release = (event) => {
    pointers.delete(event.pointerId);
    last = pointers.size ? gesture() : null;
    if (!pointers.size) stage.classList.remove("dragging");
  };
  stage.addEventListener("pointerup", release);
  stage.addEventListener("pointercancel", release);
  // the keyboard, while the stage has the focus
  stage.addEventListener("keydown", (event) => {
    if (event.ctrlKey || event.metaKey || event.altKey) return;
    const far = event.shiftKey ? 4 : 1;
    const action = {
      "+": () => zoom(STEP), "=": () => zoom(STEP), "-": () => zoom(1 / STEP), "_": () => zoom(1 / STEP),
      0: refit, ArrowLeft: () => move(MOVE * far, 0), ArrowRight: () => move(-MOVE * far, 0),
      ArrowUp: () => move(0, MOVE * far), ArrowDown: () => move(0, -MOVE * far),
    }[event.key];
    if (!action) return;
    event.preventDefault();
    action();
  });

  // short link texts (the tab is narrow), the whole in title and aria-label
  const link = (props, text, label) => {
    const a = el("a", { ...props, title: label }, text);
    a.setAttribute("aria-label", label);
    return a;
  };
  const links = [
    page ? link({ href: drawingPageUrl(url), target: "_blank", rel: "noopener", className: "drawing-open" },
      t("drawing.open_short"), t("drawing.open")) : null,
    link({ href: `${url}${url.includes("?") ? "&" : "?"}download=true`, download: `${slug}.svg` }, t("drawing.svg_short"),
      t("drawing.download")),
    sheet ? link({ href: sheet, target: "_blank", rel: "noopener" }, t("drawing.sheet_short"), t("drawing.sheet_title")) : null,
  ];
  const bar = el("div", { className: "drawing-toolbar zoom" },
    iconButton("−", "drawing.zoom_out", () => zoom(1 / STEP)), iconButton("+", "drawing.zoom_in", () => zoom(STEP)),
    iconButton("⤢", "drawing.zoom_fit", refit), level, ...extra, ...links);
  bar.setAttribute("role", "toolbar");
  bar.setAttribute("aria-label", t("tab.drawing"));
  const viewer = el("div", { className: "drawing-viewer" }, bar, stage);
  viewer.drawing = { fit, zoom, move, stage };
  // the SVG once: its views for "Einpassen", then the picture from it (inside a platform's frame the request
  // carries the token: lti.js)
  fetch(url, { credentials: "same-origin" }).then(async (r) => {
    if (!r.ok) throw new Error(String(r.status));
    const text = await r.text();
    const root = new DOMParser().parseFromString(text, "image/svg+xml").documentElement;
    const box = (root.getAttribute("data-views") || "").split(" ").map(Number);
    if (box.length === 4 && box.every(Number.isFinite) && box[2] > box[0] && box[3] > box[1]) {
      region = [box[0] / 297, box[1] / 210, box[2] / 297, box[3] / 210];
    }
    img.src = URL.createObjectURL(new Blob([text], { type: "image/svg+xml" }));
  }).catch(() => stage.replaceChildren(el("p", { className: "error drawing-failed" }, t("drawing.failed"))));
  return viewer;
}
