// The Tipps tab: the exercise's hints one at a time ("Tipp anzeigen", GET /exercises/{slug}/hints/{n}; how many
// were shown is kept in the browser) and "Musterlösung anzeigen" (GET /exercises/{slug}/solution): the
// reference program side by side with the trainee's, read-only, in a dialog; when the exercise does not allow
// it yet the server's reason is shown; above each program the part it makes.

import { api, el } from "./dom.js";
import { lang, message, t } from "./i18n.js";

const shownKey = (slug) => `paltrainer-hints:${slug}`;

function numbered(text) {
  return el("ol", { className: "submission-program" },
    ...text.replace(/\n$/, "").split("\n").map((line) => el("li", {}, line || " ")));
}

// The part a program makes, rendered by the server (the same view as the 3D area's picture), so the trainee sees
// the model solution's part beside their own without a second live 3D scene.
function partPicture(ex, text, id) {
  const img = el("img", { className: "solution-part", id, alt: t("solution.part") });
  fetch("/api/v1/viz/picture.png", {
    method: "POST", credentials: "same-origin", headers: { "Content-Type": "application/json" },
    body: JSON.stringify({ program: text, dialect: ex.dialect, exercise: ex.slug }),
  }).then(async (r) => { if (r.ok) img.src = URL.createObjectURL(await r.blob()); });
  return el("figure", {}, img, el("figcaption", { className: "meta" }, t("solution.part")));
}

export function mountHints(container, ex, { program }) {
  const count = ex.hint_count || 0;
  const list = el("ol", { className: "hint-list", id: "hint-list" });
  const more = el("button", { type: "button", id: "hint-next" });
  const note = el("p", { className: "meta", role: "status" });
  let shown = 0;
  const showNext = async () => {
    const n = shown + 1;
    if (n > count) return;
    const r = await api(`/exercises/${ex.slug}/hints/${n}`);
    if (!r.ok) { note.textContent = (r.body?.error && message(r.body.error)) || t("hints.failed"); return; }
    list.append(el("li", {}, lang === "en" && r.body.text_en ? r.body.text_en : r.body.text));
    shown = n;
    localStorage.setItem(shownKey(ex.slug), String(shown));
    update();
  };
  const update = () => {
    more.textContent = t("hints.next", { n: shown + 1, count });
    more.hidden = shown >= count;
  };
  more.onclick = showNext;

  const solutionMessage = el("p", { className: "meta", id: "solution-message", role: "status" });
  const solutionButton = el("button", { type: "button", id: "solution-show" }, t("solution.show"));
  solutionButton.onclick = async () => {
    const r = await api(`/exercises/${ex.slug}/solution`);
    if (!r.ok) {
      solutionMessage.textContent = (r.body?.error && message(r.body.error)) || t("solution.failed");
      return;
    }
    solutionMessage.textContent = "";
    const dialog = el("dialog", { className: "solution-dialog", id: "solution-dialog" },
      el("h2", {}, t("solution.title")),
      el("div", { className: "solution-compare" },
        el("section", {}, el("h3", {}, t("solution.mine")), partPicture(ex, program(), "solution-part-mine"),
          numbered(program())),
        el("section", { id: "solution-program" }, el("h3", {}, t("solution.reference")),
          partPicture(ex, r.body.program, "solution-part-reference"), numbered(r.body.program))),
      el("p", {}, el("button", { type: "button", id: "solution-close", onclick: () => dialog.close() }, t("solution.close"))));
    dialog.addEventListener("close", () => dialog.remove());
    document.body.append(dialog);
    dialog.showModal();
  };

  container.replaceChildren(...[el("h2", {}, t("tab.hints")),
    count ? list : el("p", { className: "meta" }, t("hints.empty")), count ? el("p", {}, more) : null, note,
    ex.solution === "never" ? null : el("p", {}, solutionButton), solutionMessage].filter(Boolean));
  update();
  // the hints shown before (this browser) again
  const before = Math.min(count, Number(localStorage.getItem(shownKey(ex.slug))) || 0);
  (async () => { for (let i = 0; i < before && shown === i; i += 1) await showNext(); })();
}
