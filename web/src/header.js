// The page header: who is logged in (the server puts the session's user into <body data-user data-role>) with
// "Abmelden", instructor links only for instructors and admins, "Verwaltung" (/admin) only for admins, "Freies
// Üben" not while an exam without it runs for the user (on every page, exam.js), the "Über / Lizenzen" link,
// and the language switch keeping the page's state across its reload (state.js).

import { api, el } from "./dom.js";
import { t } from "./i18n.js";
import { watchPracticeLink } from "./exam.js";
import { safeNext } from "./redirect.js";
import { keepState } from "./state.js";

const ROLES = new Set(["student", "instructor", "admin"]);  // the roles with a name of their own

export function mountHeader() {
  const { user, role } = document.body.dataset;
  const about = document.getElementById("nav-about");
  if (about) about.textContent = t("header.about");
  for (const node of /** @type {NodeListOf<HTMLElement>} */ (document.querySelectorAll("[data-role=instructor]"))) {
    node.hidden = !(role === "instructor" || role === "admin");
  }
  const adminOnly = /** @type {NodeListOf<HTMLElement>} */ (document.querySelectorAll("header [data-role=admin]"));
  for (const node of adminOnly) node.hidden = role !== "admin";
  watchPracticeLink();
  const login = document.getElementById("nav-login");
  const box = document.getElementById("nav-user");
  if (user && login && box) {
    login.hidden = true;
    box.hidden = false;
    const name = document.getElementById("nav-username");
    name.textContent = user;
    name.title = `${t("header.user", { name: user })} (${ROLES.has(role) ? t(`header.role.${role}`) : role})`;
    const logout = document.getElementById("logout");
    logout.textContent = t("header.logout");
    if (!document.getElementById("nav-password")) {  // the user menu: name, "Passwort ändern", "Abmelden"
      logout.before("· ", el("a", { href: "/password", id: "nav-password" }, t("header.password")), " · ");
    }
    logout.onclick = async () => {
      await api("/auth/logout", { method: "POST" });
      location.href = safeNext("/login");
    };
  }
  const toggle = document.getElementById("lang");
  if (toggle) {
    const reload = toggle.onclick;  // i18n.js: keep the choice and reload
    toggle.onclick = (event) => { keepState(); reload?.call(toggle, event); };
  }
}
