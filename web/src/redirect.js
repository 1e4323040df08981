// Where the browser may go after logging in: a path on this site, nothing else. The same rule as
// safe_redirect in server/security.py (the tests run one table of cases against both): no scheme
// (javascript:, https:), no second slash or backslash at the start (//host and /\host name another host),
// no control characters (browsers drop tab and newline inside a URL: "/\t/host" becomes "//host").
// eslint-disable-next-line no-control-regex -- the control characters are what it refuses
const SAFE_PATH = /^\/(?![/\\])[^\\\x00-\x1f\x7f]{0,2047}$/u;

export function safeNext(target) {
  if (typeof target !== "string" || !SAFE_PATH.test(target)) return "/";
  try {
    return new URL(target, location.origin).origin === location.origin ? target : "/";
  } catch {
    return "/";
  }
}

// The login page, coming back here afterwards.
export function loginUrl() {
  return `/login?next=${encodeURIComponent(safeNext(location.pathname + location.search))}`;
}
