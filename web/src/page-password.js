// "Passwort ändern" (/password, from the header's user menu; after a one-time password every page leads here until
// the user has chosen their own).

import { api, el, errorText, post, say } from "./dom.js";
import { t } from "./i18n.js";
import { loginUrl, safeNext } from "./redirect.js";

// "Passwort ändern": current, new, new again. After a one-time password the page says why it is shown and, once
// changed, leads on (to `next` if given).
export async function mountPassword(form) {
  const note = document.getElementById("password-message");
  const me = await api("/me");
  if (me.status === 401) {
    location.href = loginUrl();
    return;
  }
  // shown by the server when the password is a one-time one (server/routes/pages.py)
  if (!document.getElementById("password-required").hidden) {
    form.querySelector("[data-i18n='password.current']").textContent = t("password.current_once");
  }
  form.onsubmit = async (event) => {
    event.preventDefault();
    const data = Object.fromEntries(new FormData(form));
    if (data.new_password !== data.repeat) {
      say(note, "error", t("password.mismatch"));
      return;
    }
    const r = await api("/me/password", post({ current_password: data.current_password, new_password: data.new_password }));
    if (!r.ok) {
      say(note, "error", errorText(r, "password.failed"));
      return;
    }
    document.getElementById("password-required").hidden = true;
    form.reset();
    say(note, "ok", t("password.done"));
    const next = new URLSearchParams(location.search).get("next");
    note.append(" ", el("a", { href: safeNext(next || "/"), id: "password-continue" }, t("password.continue")));
  };
}
