// The user's own account: "Passwort ändern" (/password, from the header's user menu; after a one-time password
// every page leads here until the user has chosen their own), self-registration with a course's join code
// (/signup, only when the server allows it), and the one-time password an instructor sets for a student on the
// course page (shown once).

import { api, el } from "./dom.js";
import { addTexts, message, t } from "./i18n.js";
import { loginUrl, safeNext } from "./redirect.js";

addTexts({
  "title.password": ["PAL Trainer – Passwort ändern", "PAL Trainer – Change password"],
  "title.signup": ["PAL Trainer – Registrieren", "PAL Trainer – Sign up"],
  "password.title": ["Passwort ändern", "Change password"],
  "password.required": ["Ihr Passwort wurde zurückgesetzt. Bitte legen Sie jetzt ein eigenes Passwort fest; vorher lässt sich nichts anderes öffnen.",
    "Your password was reset. Please choose your own password now; nothing else opens before that."],
  "password.current": ["Bisheriges Passwort", "Current password"],
  "password.current_once": ["Einmal-Passwort (von Ihrer Lehrkraft)", "One-time password (from your instructor)"],
  "password.new": ["Neues Passwort", "New password"],
  "password.repeat": ["Neues Passwort wiederholen", "Repeat the new password"],
  "password.rule": ["Mindestens 8 Zeichen.", "At least 8 characters."],
  "password.submit": ["Passwort ändern", "Change password"],
  "password.mismatch": ["Die beiden neuen Passwörter stimmen nicht überein.", "The two new passwords differ."],
  "password.done": ["Ihr Passwort ist geändert.", "Your password has been changed."],
  "password.continue": ["Weiter zu Ihren Aufgaben", "On to your exercises"],
  "password.failed": ["Das Passwort ließ sich nicht ändern.", "The password could not be changed."],
  "signup.title": ["Registrieren", "Sign up"],
  "signup.intro": ["Mit dem Beitrittscode Ihrer Klasse legen Sie hier Ihr eigenes Konto an und sind gleich in der Klasse.",
    "With your course's join code you create your own account here and are in the course at once."],
  "signup.code": ["Beitrittscode der Klasse", "The course's join code"],
  "signup.name_rule": ["Buchstaben ohne Umlaute, Ziffern und _ . @ -", "Letters without umlauts, digits and _ . @ -"],
  "signup.repeat": ["Passwort wiederholen", "Repeat the password"],
  "signup.submit": ["Konto anlegen", "Create the account"],
  "signup.mismatch": ["Die beiden Passwörter stimmen nicht überein.", "The two passwords differ."],
  "signup.failed": ["Das Konto ließ sich nicht anlegen.", "The account could not be created."],
  "signup.have_account": ["Sie haben schon ein Konto? Anmelden", "Already have an account? Log in"],
  "login.signup": ["Neu hier? Mit dem Beitrittscode Ihrer Klasse registrieren", "New here? Sign up with your course's join code"],
  "reset.button": ["Passwort zurücksetzen", "Reset password"],
  "reset.label": ["Passwort zurücksetzen für {name}", "Reset password for {name}"],  // starts with the visible text
  "reset.confirm": ["Für {name} ein neues Einmal-Passwort festlegen? Das bisherige Passwort gilt dann nicht mehr.",
    "Set a new one-time password for {name}? The old password stops working."],
  "reset.done": ["Einmal-Passwort für {name}:", "One-time password for {name}:"],
  "reset.once": ["Es wird nur jetzt angezeigt. {name} meldet sich damit an und muss dann ein eigenes Passwort festlegen.",
    "It is shown only now. {name} logs in with it and must then choose their own password."],
  "reset.failed": ["Das Passwort ließ sich nicht zurücksetzen.", "The password could not be reset."],
});

const post = (body) => ({ method: "POST", headers: { "Content-Type": "application/json" }, body: JSON.stringify(body) });
const errorText = (r, fallback) => (r.body?.error && message(r.body.error)) || t(fallback);

function say(node, kind, text) {
  node.className = kind;
  node.textContent = text;
}

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

// Self-registration: join code, name, password (twice); the new account is logged in and lands on its start page.
export function mountSignup(form) {
  const note = document.getElementById("signup-message");
  form.onsubmit = async (event) => {
    event.preventDefault();
    const data = Object.fromEntries(new FormData(form));
    if (data.password !== data.repeat) {
      say(note, "error", t("signup.mismatch"));
      return;
    }
    const r = await api("/auth/signup", post({ join_code: String(data.join_code).trim(), username: String(data.username).trim(),
      password: data.password }));
    if (r.ok) location.href = safeNext("/");
    else say(note, "error", errorText(r, "signup.failed"));
  };
}

// The course page's "Passwort zurücksetzen" for one student: a confirmation, then the one-time password shown once
// in `out`.
export function resetButton(username, out) {
  const button = el("button", { type: "button", className: "link-button reset-password" }, t("reset.button"));
  button.setAttribute("aria-label", t("reset.label", { name: username }));
  button.onclick = async () => {
    if (!confirm(t("reset.confirm", { name: username }))) return;
    const r = await api(`/users/${encodeURIComponent(username)}/password-reset`, { method: "POST" });
    if (!r.ok) {
      out.replaceChildren(el("p", { className: "error" }, errorText(r, "reset.failed")));
      return;
    }
    out.replaceChildren(el("p", { className: "ok" }, `${t("reset.done", { name: r.body.username })} `,
      el("code", { className: "one-time-password", id: "one-time-password" }, r.body.password)),
    el("p", { className: "meta" }, t("reset.once", { name: r.body.username })));
  };
  return button;
}
