// Self-registration with a course's join code (/signup, only when the server allows it).

import { api, errorText, post, say } from "./dom.js";
import { t } from "./i18n.js";
import { safeNext } from "./redirect.js";

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
