// The framed page after an LTI launch: exchange the one-time ticket (URL fragment) for the page's API token and
// go on to the exercise. The token travels in the next page's URL fragment (never sent to a server, no Referer):
// browsers that block storage in a cross-site frame (no third-party cookies, no sessionStorage) still work.
(async () => {
  const status = document.getElementById("status");
  const ticket = new URLSearchParams(location.hash.slice(1)).get("ticket");
  history.replaceState(null, "", location.pathname + location.search);
  if (!ticket) { status.textContent = status.dataset.missing; return; }
  const r = await fetch("/lti/session", {
    method: "POST", headers: { "Content-Type": "application/json" }, body: JSON.stringify({ ticket }),
  }).catch(() => null);
  const body = r && r.ok ? await r.json() : null;
  if (!body) { status.textContent = status.dataset.failed; return; }
  location.replace(`${body.next}#token=${encodeURIComponent(body.token)}`);
})();
