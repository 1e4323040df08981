// The admin page (/admin): users (role, instructor, one-time password, deactivate / activate, a new user, a class
// list), API keys (all of them; a new one with its scopes, shown once; revoke) and learning platforms (LTI 1.3: the
// registered platforms, one registered by hand, a dynamic registration URL, our signing keys: rotate, retire).
// It asks /api/v1/users, /api/v1/api-keys and /api/v1/admin/lti/…, which refuse anyone but admins anyway; anyone
// else reads "Nur für Administratoren".

import { api, el } from "./dom.js";
import { lang, message, t } from "./i18n.js";

export const SCOPES = ["practice", "exercises:read", "exercises:write", "submissions:read", "submissions:write"];
const ROLES = ["student", "instructor", "admin"];

const json = (method, body) => ({ method, headers: { "Content-Type": "application/json" },
  body: body === undefined ? undefined : JSON.stringify(body) });
const errorText = (r) => (r.body?.error && message(r.body.error)) || t("admin.failed");
const when = (iso) => (iso ? new Date(iso).toLocaleString(lang === "en" ? "en-GB" : "de-DE",
  { dateStyle: "medium", timeStyle: "short" }) : t("keys.never"));
const day = (iso) => new Date(iso).toLocaleDateString(lang === "en" ? "en-GB" : "de-DE",
  { day: "2-digit", month: "2-digit", year: "numeric" });
const path = (name) => encodeURIComponent(name);

// A status line under a section: what the last action did (green) or why it failed (red).
function status(id) {
  const node = el("p", { id, className: "admin-status", role: "status" });
  node.say = (text, ok = true) => { node.className = `admin-status ${ok ? "ok" : "error"}`; node.textContent = text; };
  return node;
}

function labelled(text, control) {
  return el("label", { className: "field" }, text, control);
}

function head(...names) {
  return el("thead", {}, el("tr", {}, ...names.map((n) => el("th", {}, n))));
}

// A secret shown this once (one-time password, API key): selectable text and a note.
function secretBox(id, title, secret, note) {
  const field = el("input", { type: "text", id: `${id}-value`, value: secret, readOnly: true, className: "secret" });
  field.setAttribute("aria-label", title);
  field.onfocus = () => field.select();
  return el("div", { id, className: "admin-secret", role: "status" }, el("p", {}, title), field,
    el("p", { className: "meta" }, note));
}

// -- users -------------------------------------------------------------------------------------------------
async function usersSection(me) {
  const section = el("section", { id: "admin-users" });
  const said = status("users-status");
  const secret = el("div", { id: "users-secret" });
  let users = [];

  const instructorOptions = (current) => [el("option", { value: "" }, t("users.nobody")),
    ...users.filter((u) => u.role !== "student").map((u) => el("option", { value: u.username,
      selected: u.username === current }, u.username))];

  const replace = (updated) => { users = users.map((u) => (u.username === updated.username ? updated : u)); draw(); };

  const row = (u) => {
    const self = u.username === me;
    const role = el("select", { className: "user-role", disabled: self },
      ...ROLES.map((r) => el("option", { value: r, selected: r === u.role }, t(`role.${r}`))));
    role.setAttribute("aria-label", t("users.role_label", { name: u.username }));
    role.onchange = async () => {
      const r = await api(`/users/${path(u.username)}`, json("PATCH", { role: role.value }));
      if (!r.ok) { role.value = u.role; said.say(errorText(r), false); return; }
      replace(r.body);
      said.say(t("users.role_saved", { name: u.username, role: t(`role.${r.body.role}`) }));
    };
    const teacher = el("select", { className: "user-instructor" }, ...instructorOptions(u.instructor));
    teacher.setAttribute("aria-label", t("users.instructor_label", { name: u.username }));
    teacher.onchange = async () => {
      const r = await api(`/users/${path(u.username)}`, json("PATCH", { instructor: teacher.value || null }));
      if (!r.ok) { teacher.value = u.instructor || ""; said.say(errorText(r), false); return; }
      replace(r.body);
      said.say(t("users.instructor_saved", { name: u.username, instructor: r.body.instructor || t("users.nobody") }));
    };
    const reset = el("button", { type: "button", className: "user-reset", title: t("users.reset_label", { name: u.username }) },
      t("users.reset"));
    reset.setAttribute("aria-label", t("users.reset_label", { name: u.username }));
    reset.onclick = async () => {
      if (!confirm(t("users.reset_confirm", { name: u.username }))) return;
      const r = await api(`/users/${path(u.username)}/password-reset`, json("POST"));
      if (!r.ok) { said.say(errorText(r), false); return; }
      said.say("");
      secret.replaceChildren(secretBox("users-password", t("users.reset_done", { name: r.body.username }),
        r.body.password, t("users.reset_once", { name: r.body.username })));
      replace({ ...u, must_change_password: true });
    };
    const active = u.active !== false;
    const toggle = el("button", { type: "button", className: "user-active", disabled: self },
      active ? t("users.deactivate") : t("users.activate"));
    toggle.onclick = async () => {
      if (active && !confirm(t("users.deactivate_confirm", { name: u.username }))) return;
      const r = await api(`/users/${path(u.username)}/${active ? "deactivate" : "activate"}`, json("POST"));
      if (!r.ok) { said.say(errorText(r), false); return; }
      replace(r.body);
      said.say(t(active ? "users.deactivated" : "users.activated", { name: u.username }));
    };
    const state = [active ? t("users.active") : t("users.inactive")];
    if (u.must_change_password) state.push(t("users.must_change"));
    return el("tr", { className: active ? "" : "inactive" },
      el("td", {}, u.username, self ? ` ${t("users.you")}` : "", el("br"),
        el("span", { className: "meta" }, t("users.created", { day: day(u.created_at) }))),
      el("td", {}, role), el("td", {}, teacher), el("td", {}, state.join(", ")),
      el("td", {}, el("div", { className: "actions" }, reset, toggle)));
  };

  const heading = el("h3", {}, t("admin.users"));
  const body = el("tbody", {});
  const newInstructor = el("select", { id: "new-user-instructor" });
  const importInstructor = el("select", { id: "import-instructor" });
  const draw = () => {
    heading.textContent = t("users.count", { n: users.length });
    body.replaceChildren(...users.map((u) => {
      const tr = row(u);
      tr.dataset.user = u.username;
      return tr;
    }));
    newInstructor.replaceChildren(...instructorOptions(newInstructor.value));
    importInstructor.replaceChildren(...instructorOptions(importInstructor.value));
  };
  const load = async () => {
    const r = await api("/users");
    if (!r.ok) { said.say(errorText(r), false); return; }
    users = r.body;
    draw();
  };

  // a new user
  const name = el("input", { type: "text", id: "new-user-name", autocomplete: "off" });
  const password = el("input", { type: "password", id: "new-user-password", autocomplete: "new-password" });
  const newRole = el("select", { id: "new-user-role" },
    ...ROLES.map((r) => el("option", { value: r }, t(`role.${r}`))));
  const created = status("new-user-status");
  const create = el("form", { id: "new-user", className: "inline-form" },
    labelled(t("users.name"), name), labelled(t("users.password"), password), labelled(t("users.role"), newRole),
    labelled(t("users.instructor"), newInstructor), el("button", { type: "submit" }, t("users.create")));
  create.onsubmit = async (event) => {
    event.preventDefault();
    const r = await api("/users", json("POST", { username: name.value.trim(), password: password.value,
      role: newRole.value, instructor: newInstructor.value || null }));
    if (!r.ok) { created.say(errorText(r), false); return; }
    name.value = ""; password.value = "";
    await load();
    created.say(t("users.created_one", { name: r.body.username }));
  };

  // a class list
  const file = el("input", { type: "file", id: "import-file", accept: ".csv,.txt,text/csv" });
  file.setAttribute("aria-label", t("users.import_file"));
  const imported = el("div", { id: "import-result", role: "status" });
  file.onchange = async () => {
    const chosen = file.files[0];
    if (!chosen) return;
    const query = importInstructor.value ? `?instructor=${path(importInstructor.value)}` : "";
    const r = await api(`/users/import${query}`, { method: "POST", headers: { "Content-Type": "text/csv" },
      body: await chosen.text() });
    file.value = "";
    if (!r.ok) {
      const errors = r.body?.error?.details?.errors || [];
      imported.replaceChildren(el("p", { className: "error" }, errorText(r)), el("ul", { className: "error" },
        ...errors.map((e) => el("li", {}, `${e.row ? `${t("users.row", { n: e.row })}: ` : ""}${message(e)}`))));
      return;
    }
    await load();
    imported.replaceChildren(el("p", { className: "ok" }, t("users.imported", { n: r.body.users.length })),
      el("table", { className: "passwords" }, head(t("users.name"), t("login.password")),
        el("tbody", {}, ...r.body.users.map((u) => el("tr", {}, el("td", {}, u.username),
          el("td", {}, u.password ?? t("users.given")))))));
  };

  await load();
  section.append(heading, said, secret,
    el("div", { className: "scroll" }, el("table", { id: "users-table", className: "admin-table" },
      head(t("users.name"), t("users.role"), t("users.instructor"), t("users.state"), t("users.actions")), body)),
    el("h4", {}, t("users.new")), create, created,
    el("h4", {}, t("users.import")), el("p", { className: "meta" }, t("users.import_help")),
    el("div", { className: "inline-form" }, labelled(t("users.instructor"), importInstructor),
      labelled(t("users.import_file"), file)), imported);
  return section;
}

// -- API keys ----------------------------------------------------------------------------------------------
async function keysSection() {
  const section = el("section", { id: "admin-keys" });
  const said = status("keys-status");
  const made = status("new-key-status");
  const shown = el("div", { id: "keys-secret" });
  const list = el("div", { className: "scroll" });

  const load = async () => {
    const r = await api("/api-keys");
    if (!r.ok) { said.say(errorText(r), false); return; }
    if (!r.body.length) { list.replaceChildren(el("p", { className: "meta" }, t("keys.none"))); return; }
    list.replaceChildren(el("table", { id: "keys-table", className: "admin-table" },
      head(t("keys.name"), t("keys.scopes"), t("keys.owner"), t("keys.created"), t("keys.used"), t("keys.state"), ""),
      el("tbody", {}, ...r.body.map((k) => {
        const revoke = el("button", { type: "button", className: "key-revoke" }, t("keys.revoke"));
        revoke.setAttribute("aria-label", t("keys.revoke_label", { name: k.name }));
        revoke.onclick = async () => {
          if (!confirm(t("keys.revoke_confirm", { name: k.name }))) return;
          const answer = await api(`/api-keys/${k.id}`, { method: "DELETE" });
          if (!answer.ok) { said.say(errorText(answer), false); return; }
          await load();
          said.say(t("keys.revoked_one", { name: k.name }));
        };
        const tr = el("tr", { className: k.revoked_at ? "inactive" : "" },
          el("td", {}, k.name, el("br"), el("code", { className: "meta", title: t("keys.prefix") }, k.prefix)),
          el("td", {}, k.scopes.map((s) => t(`scope.${s}`)).join(", ")), el("td", {}, k.owner || t("admin.none")),
          el("td", {}, day(k.created_at)), el("td", {}, when(k.last_used_at)),
          el("td", {}, k.revoked_at ? t("keys.revoked", { time: when(k.revoked_at) }) : t("keys.valid")),
          el("td", {}, k.revoked_at ? "" : revoke));
        tr.dataset.key = k.name;
        return tr;
      }))));
  };

  const name = el("input", { type: "text", id: "new-key-name", autocomplete: "off", maxLength: 80 });
  const boxes = SCOPES.map((s) => el("input", { type: "checkbox", value: s, name: "scope" }));
  const form = el("form", { id: "new-key" },
    labelled(t("keys.name"), name),
    el("fieldset", { className: "scopes" }, el("legend", {}, t("keys.scopes")),
      ...boxes.map((box) => el("label", { className: "check" }, box, ` ${t(`scope.${box.value}`)}`))),
    el("button", { type: "submit" }, t("keys.create")));
  form.onsubmit = async (event) => {
    event.preventDefault();
    const scopes = boxes.filter((b) => b.checked).map((b) => b.value);
    if (!scopes.length) { made.say(t("keys.pick_scope"), false); return; }
    const r = await api("/api-keys", json("POST", { name: name.value.trim(), scopes }));
    if (!r.ok) { made.say(errorText(r), false); return; }
    made.say("");
    name.value = "";
    for (const b of boxes) b.checked = false;
    shown.replaceChildren(secretBox("key-secret", t("keys.shown_once", { name: r.body.name }), r.body.key,
      t("keys.new_help")));
    await load();
  };

  await load();
  section.append(el("h3", {}, t("admin.keys")), said, list, el("h4", {}, t("keys.new")),
    el("p", { className: "meta" }, t("keys.new_help")), form, made, shown);
  return section;
}

// -- learning platforms ------------------------------------------------------------------------------------
const PLATFORM_FIELDS = [["issuer", "lti.issuer", "https://moodle.schule.de"], ["client_id", "lti.client_id", ""],
  ["auth_login_url", "lti.auth_url", "https://moodle.schule.de/mod/lti/auth.php"],
  ["token_url", "lti.token_url", "https://moodle.schule.de/mod/lti/token.php"],
  ["jwks_url", "lti.jwks_url", "https://moodle.schule.de/mod/lti/certs.php"],
  ["deployment_ids", "lti.deployment_ids", ""], ["name", "lti.display_name", ""]];

async function ltiSection() {
  const section = el("section", { id: "admin-lti" });
  const said = status("lti-status");
  const registered = status("platform-status");
  const keysSaid = status("lti-keys-status");
  const platforms = el("div", { className: "scroll" });
  const keyList = el("div", { className: "scroll" });

  const loadPlatforms = async () => {
    const r = await api("/admin/lti/platforms");
    if (!r.ok) { said.say(errorText(r), false); return; }
    platforms.replaceChildren(r.body.length ? el("table", { id: "platforms-table", className: "admin-table" },
      head(t("lti.name"), t("lti.issuer"), t("lti.client_id"), t("lti.deployments"), t("lti.created")),
      el("tbody", {}, ...r.body.map((p) => el("tr", {}, el("td", {}, p.name), el("td", { className: "url" }, p.issuer),
        el("td", {}, p.client_id), el("td", {}, p.deployment_ids.join(", ") || t("admin.none")),
        el("td", {}, day(p.created_at))))))
      : el("p", { className: "meta" }, t("lti.none")));
  };

  // by hand: every field with its own message
  const inputs = {};
  const notes = {};
  const form = el("form", { id: "new-platform", className: "form-grid platform-form" },
    ...PLATFORM_FIELDS.map(([field, label, example]) => {
      inputs[field] = el("input", { type: "text", id: `platform-${field}`, name: field, placeholder: example,
        autocomplete: "off", spellcheck: false });
      notes[field] = el("span", { className: "error field-error", id: `platform-${field}-error` });
      inputs[field].setAttribute("aria-describedby", notes[field].id);
      return el("label", { className: "field" }, t(label), inputs[field], notes[field]);
    }),
    el("p", {}, el("button", { type: "submit" }, t("lti.save"))));
  form.onsubmit = async (event) => {
    event.preventDefault();
    for (const note of Object.values(notes)) note.textContent = "";
    const body = Object.fromEntries(PLATFORM_FIELDS.map(([field]) => [field, inputs[field].value.trim()]));
    body.deployment_ids = body.deployment_ids.split(",").map((d) => d.trim()).filter(Boolean);
    const r = await api("/admin/lti/platforms", json("POST", body));
    if (!r.ok) {
      for (const e of r.body?.error?.details?.errors || []) {
        const field = e.field?.split(".")[0];
        if (notes[field]) notes[field].textContent = lang === "en" && e.message_en ? e.message_en : e.message;
      }
      registered.say(errorText(r), false);
      return;
    }
    for (const input of Object.values(inputs)) input.value = "";
    await loadPlatforms();
    registered.say(t("lti.registered", { name: r.body.name }));
  };

  // dynamic registration
  const made = el("div", { id: "registration-url" });
  const makeUrl = el("button", { type: "button", id: "make-registration-url" }, t("lti.dynamic_make"));
  makeUrl.onclick = async () => {
    const r = await api("/admin/lti/registration-url", json("POST"));
    if (!r.ok) { said.say(errorText(r), false); return; }
    const field = el("input", { type: "text", id: "registration-url-value", value: r.body.url, readOnly: true,
      className: "secret" });
    field.setAttribute("aria-label", t("lti.url_label"));
    field.onfocus = () => field.select();
    made.replaceChildren(field, el("p", { className: "meta" }, t("lti.dynamic_valid", { days: r.body.valid_days })));
  };

  // our keys
  const loadKeys = async () => {
    const r = await api("/admin/lti/keys");
    if (!r.ok) { keysSaid.say(errorText(r), false); return; }
    keyList.replaceChildren(el("table", { id: "lti-keys-table", className: "admin-table" },
      head(t("lti.kid"), t("lti.key_created"), t("lti.key_state"), ""),
      el("tbody", {}, ...r.body.map((k) => {
        /** @type {HTMLElement | string} */
        let retire = "";
        if (k.state === "published") {
          const button = el("button", { type: "button", className: "key-retire" }, t("lti.retire"));
          retire = button;
          button.setAttribute("aria-label", t("lti.retire_label", { kid: k.kid }));
          button.onclick = async () => {
            if (!confirm(t("lti.retire_confirm", { kid: k.kid }))) return;
            const answer = await api(`/admin/lti/keys/${path(k.kid)}/retire`, json("POST"));
            if (!answer.ok) { keysSaid.say(errorText(answer), false); return; }
            await loadKeys();
            keysSaid.say(t("lti.retired", { kid: k.kid }));
          };
        }
        return el("tr", { className: k.state === "retired" ? "inactive" : "" }, el("td", {}, el("code", {}, k.kid)),
          el("td", {}, when(k.created_at)), el("td", {}, t(`lti.state.${k.state}`)), el("td", {}, retire));
      }))));
  };
  const rotate = el("button", { type: "button", id: "rotate-key" }, t("lti.rotate"));
  rotate.onclick = async () => {
    const r = await api("/admin/lti/keys/rotate", json("POST"));
    if (!r.ok) { keysSaid.say(errorText(r), false); return; }
    await loadKeys();
    keysSaid.say(t("lti.rotated", { kid: r.body.kid }));
  };

  await Promise.all([loadPlatforms(), loadKeys()]);
  section.append(el("h3", {}, t("admin.lti")), said,
    el("h4", {}, t("lti.platforms")), platforms,
    el("h4", {}, t("lti.dynamic")), el("p", { className: "meta" }, t("lti.dynamic_help")), makeUrl, made,
    el("h4", {}, t("lti.register")), el("p", { className: "meta" }, t("lti.register_help")), form, registered,
    el("h4", {}, t("lti.keys")), el("p", { className: "meta" }, t("lti.keys_help")), keyList, rotate, keysSaid);
  return section;
}

export async function mountAdmin(root) {
  const { user, role } = document.body.dataset;
  const body = document.getElementById("admin-body");
  if (role !== "admin") {
    body.replaceChildren(el("p", { id: "admin-denied", className: "error" }, t("admin.denied")));
    return;
  }
  const nav = el("nav", { className: "admin-nav" }, el("a", { href: "#admin-users" }, t("admin.users")), " · ",
    el("a", { href: "#admin-keys" }, t("admin.keys")), " · ", el("a", { href: "#admin-lti" }, t("admin.lti")));
  const sections = await Promise.all([usersSection(user), keysSection(), ltiSection()]);
  body.replaceChildren(nav, ...sections);
  root.dataset.ready = "1";
}
