// Drafts: what the trainee types on an exercise page is kept, on the server (PUT /exercises/{slug}/draft, at
// most every 2 s while typing and once more when the page is left) and in the browser (localStorage), so
// that a reload, another tab or another computer brings it back and nothing is lost while offline. The
// newer of the two wins; a draft equal to the start program is no draft.
// An exam keeps drafts of its own (?assignment=ID, in the browser under a key with the exam's number): an exam
// starts from the start program, never from the practice draft, and its drafts never turn up in practice.

import { api } from "./dom.js";

const EVERY = 2000;  // ms between two saves on the server (the server allows 120 a minute)

// the practice draft's key as it always was (drafts kept in browsers stay found); an exam's with its number
const key = (user, slug, assignment = null) => `paltrainer-draft:${user || "-"}:${slug}${assignment ? `:a${assignment}` : ""}`;
const draftUrl = (slug, assignment) => `/exercises/${encodeURIComponent(slug)}/draft${assignment ? `?assignment=${assignment}` : ""}`;

function readLocal(name) {
  try {
    const saved = JSON.parse(localStorage.getItem(name));
    if (saved && typeof saved.program === "string") return saved;
  } catch { /* a damaged entry: as if there were none */ }
  return null;
}

// The program to start the editor with: the server's draft or the browser's, whichever is newer; else null.
// `assignment`: the exam whose draft it is (null: the practice draft — unless the server answers with a running
// exam's draft, whose number then comes back as `assignment` for the saver).
// `local: false`: the server's draft only (an ended exam shows what the server kept).
export async function loadDraft(slug, assignment = null, { local: useLocal = true } = {}) {
  const [me, r] = await Promise.all([api("/me"), api(draftUrl(slug, assignment))]);
  const user = me.ok ? me.body?.username : null;
  const scope = (r.ok && r.body?.assignment) || assignment || null;
  const local = useLocal ? readLocal(key(user, slug, scope)) : null;
  const server = r.ok && r.body?.program != null ? r.body : null;
  const serverTime = server ? Date.parse(server.updated_at) : 0;
  // the browser's copy counts only when it was never saved on the server and is newer than the server's draft
  if (local && !local.synced && Date.parse(local.saved_at) > serverTime) {
    return { user, program: local.program, pending: true, assignment: scope };
  }
  if (server) return { user, program: server.program, pending: false, assignment: scope };
  return { user, program: null, pending: false, assignment: scope };
}

// Keeps the editor's text: call changed(text) on every change; forget() for "Zurücksetzen" (the draft of this
// scope only: an exam's reset leaves the practice draft alone).
// onState(state, error) (optional) hears "saving", "saved", "offline" and "refused" (the server said no, e.g. after
// an exam's end: its error, no further tries). `assignment`: the exam the draft belongs to (null: practice).
export function draftSaver(slug, user, start, initial = null, pending = false, onState = null, assignment = null) {
  const name = key(user, slug, assignment);
  const url = `/api/v1${draftUrl(slug, assignment)}`;
  let text = initial ?? start;
  let dirty = false;  // not yet on the server
  let timer = null;
  let last = 0;  // when the last save left
  const status = { state: "idle" };
  let stopped = false;
  const set = (state, error = null) => { status.state = state; onState?.(state, error); };

  const keepLocal = (synced) => {
    try {
      if (text === start) localStorage.removeItem(name);
      else localStorage.setItem(name, JSON.stringify({ program: text, saved_at: new Date().toISOString(), synced }));
    } catch { /* storage full or off: the server keeps it */ }
  };

  const send = async (keepalive = false) => {
    clearTimeout(timer);
    timer = null;
    if (!dirty || stopped) return;
    const sent = text;
    last = Date.now();
    set("saving");
    let refused = null;
    try {
      const r = await fetch(url, sent === start
        ? { method: "DELETE", credentials: "same-origin", keepalive }
        : { method: "PUT", credentials: "same-origin", keepalive, headers: { "Content-Type": "application/json" },
          body: JSON.stringify({ program: sent }) });
      if (r.status === 403 || r.status === 409) {  // refused (an exam's rules): trying again changes nothing
        refused = (await r.json().catch(() => null))?.error || {};
      } else if (!r.ok) {
        throw new Error(String(r.status));
      }
      if (refused) {
        set("refused", refused);
        return;
      }
      if (sent === text) {
        dirty = false;
        keepLocal(true);
      }
      set("saved");
    } catch {
      set("offline");  // kept in the browser; the next change or going online sends it again
      schedule();
    }
  };

  function schedule() {
    if (timer) return;
    timer = setTimeout(send, Math.max(200, last + EVERY - Date.now()));
  }

  const flush = () => { if (dirty) send(true); };
  window.addEventListener("pagehide", flush);
  document.addEventListener("visibilitychange", () => { if (document.visibilityState === "hidden") flush(); });
  window.addEventListener("online", () => { if (dirty) send(); });
  // a draft found only in this browser goes to the server now
  if (pending) { dirty = true; schedule(); }

  return {
    status,
    stop() { stopped = true; clearTimeout(timer); timer = null; },  // no more saves (an exam ended)
    changed(next) {
      if (next === text) return;
      text = next;
      dirty = true;
      keepLocal(false);
      schedule();
    },
    async forget() {
      clearTimeout(timer);
      timer = null;
      text = start;
      dirty = false;
      keepLocal(true);
      await fetch(url, { method: "DELETE", credentials: "same-origin" }).catch(() => null);
    },
  };
}
