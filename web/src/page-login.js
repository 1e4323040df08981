// The login page, which is also the start page of a visitor without an account ("/" sends them there): what PAL
// Trainer is, free practice without an account, the login form; and where the login leads.

import { api, el } from "./dom.js";
import { message as message_, t } from "./i18n.js";
import { safeNext } from "./redirect.js";

// Where the login leads: to `next` if it is a path on this site, else to the user's own start: instructors and
// admins their page (courses first), trainees the exercise list with their assignments.
export function landing(role, next) {
  if (typeof next === "string" && next && safeNext(next) === next) return next;
  return role === "instructor" || role === "admin" ? "/instructor" : "/";
}

// The login page is the start page of a visitor without an account (page-home.js: what PAL Trainer is, free practice).
export async function mountLogin(form, message) {
  mountStart(form);
  form.onsubmit = async (event) => {
    event.preventDefault();
    const data = Object.fromEntries(new FormData(form));
    const r = await api("/auth/login", {
      method: "POST", headers: { "Content-Type": "application/json" }, body: JSON.stringify(data),
    });
    if (r.ok && r.body?.must_change_password) {  // a one-time password: the user chooses their own first
      location.href = safeNext("/password");
    } else if (r.ok) {
      location.href = safeNext(landing(r.body?.role, new URLSearchParams(location.search).get("next")));
    } else {
      message.textContent = (r.body?.error && message_(r.body.error)) || t("login.failed");
    }
  };
}

// The start page for a visitor without an account (the login page: "/" sends them there): what PAL Trainer is in
// two sentences, free practice without an account, and beside it the login form (moved into a box of its own).
export function mountStart(form) {
  const main = form.closest("main");
  if (!main || main.querySelector(".start")) return;
  const heading = main.querySelector("h2");
  heading.id = "login-title";
  const intro = el("section", { className: "start-intro" },
    el("h2", { id: "start-title" }, t("start.title")),
    el("p", { className: "start-what" }, t("start.what")),
    el("p", {}, el("a", { className: "start-practice", id: "start-practice", href: "/practice" }, t("start.practice"))));
  intro.setAttribute("aria-labelledby", "start-title");
  const login = el("section", { className: "start-login" }, heading,
    el("p", { className: "meta" }, t("start.login_note")), form);
  login.setAttribute("aria-labelledby", "login-title");
  main.replaceChildren(el("div", { className: "start" }, intro, login));
}
