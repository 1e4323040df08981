// Inside a learning platform's iframe (an LTI launch) the browser sends no cookie to this site and may refuse
// storage too: /lti/open hands the page its API token in the URL fragment (#token=…, never sent to a server),
// and every request of the page to /api/ carries it as a bearer token (the live socket: as ?token=).

// Such a frame may also refuse localStorage/sessionStorage (reading them throws): the pages keep their settings
// (language, layout, unsent programs) in memory there instead of failing to start. This module is the bundle's
// first import, so this runs before any page module reads storage.
function memoryStorage() {
  const items = new Map();
  return {
    getItem: (key) => (items.has(key) ? items.get(key) : null),
    setItem: (key, value) => { items.set(key, String(value)); },
    removeItem: (key) => { items.delete(key); },
    clear: () => { items.clear(); },
    key: (index) => [...items.keys()][index] ?? null,
    get length() { return items.size; },
  };
}

for (const name of ["localStorage", "sessionStorage"]) {
  try {
    void window[name];
  } catch {
    Object.defineProperty(window, name, { value: memoryStorage(), configurable: true });
  }
}

export function installBearer() {
  // kept in the fragment (not moved to storage): a reload of the frame keeps working
  const token = new URLSearchParams(location.hash.slice(1)).get("token");
  if (!token) return;
  // in the platform's frame the page is the exercise alone: the site's navigation (pages that need a login
  // of their own) gives way to the language switch
  const nav = document.querySelector("header nav");
  const lang = document.getElementById("lang");
  if (nav && lang) nav.replaceChildren(lang);
  const original = window.fetch.bind(window);
  window.fetch = (input, init = {}) => {
    const url = new URL(input instanceof Request ? input.url : String(input), location.href);
    if (url.origin !== location.origin || !url.pathname.startsWith("/api/")) return original(input, init);
    const headers = new Headers(init.headers || (input instanceof Request ? input.headers : undefined));
    if (!headers.has("Authorization")) headers.set("Authorization", `Bearer ${token}`);
    return original(input, { ...init, headers });
  };
  // the live socket cannot carry a header: it takes the token as a query parameter (server/live.py)
  const NativeWebSocket = window.WebSocket;
  window.WebSocket = class extends NativeWebSocket {
    constructor(address, protocols) {
      const url = new URL(address, location.href);
      if (url.host === location.host && url.pathname.startsWith("/api/") && !url.searchParams.has("token")) {
        url.searchParams.set("token", token);
      }
      super(url.toString(), protocols);
    }
  };
  // pictures and downloads of the API (the drawing, the task sheet) are loaded with the token, shown as blob: URLs
  const ours = (value) => {
    const url = new URL(value, location.href);
    return url.origin === location.origin && url.pathname.startsWith("/api/") ? url : null;
  };
  const blob = (url) => window.fetch(url.href).then((r) => (r.ok ? r.blob() : null)).catch(() => null);
  const src = Object.getOwnPropertyDescriptor(HTMLImageElement.prototype, "src");
  Object.defineProperty(HTMLImageElement.prototype, "src", {
    ...src,
    set(value) {
      const url = ours(String(value));
      if (!url) { src.set.call(this, value); return; }
      blob(url).then((b) => { if (b) src.set.call(this, URL.createObjectURL(b)); });
    },
  });
  document.addEventListener("click", async (event) => {
    const link = event.target instanceof Element ? event.target.closest("a[href]") : null;
    const url = link && ours(link.getAttribute("href"));
    if (!url) return;
    event.preventDefault();
    const b = await blob(url);
    if (!b) return;
    const href = URL.createObjectURL(b);
    if (link.hasAttribute("download")) {
      const save = Object.assign(document.createElement("a"), { href, download: link.getAttribute("download") });
      save.click();
    } else {
      // a blob of ours in a new tab, through a link rather than window.open (the one redirect rule)
      Object.assign(document.createElement("a"), { href, target: "_blank", rel: "noopener" }).click();
    }
  });
}
