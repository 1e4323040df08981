// Inside a learning platform's iframe (an LTI launch) the browser sends no cookie to this site: /lti/open keeps
// the page's API token in sessionStorage, and every request of the page to /api/ carries it as a bearer token.

export function installBearer() {
  let token = null;
  try {
    token = sessionStorage.getItem("paltrainer-token");
  } catch {
    return;  // storage blocked: the page works as without a launch
  }
  if (!token) return;
  const original = window.fetch.bind(window);
  window.fetch = (input, init = {}) => {
    const url = new URL(typeof input === "string" ? input : input.url, location.href);
    if (url.origin !== location.origin || !url.pathname.startsWith("/api/")) return original(input, init);
    const headers = new Headers(init.headers || (typeof input === "string" ? undefined : input.headers));
    if (!headers.has("Authorization")) headers.set("Authorization", `Bearer ${token}`);
    return original(input, { ...init, headers });
  };
}
