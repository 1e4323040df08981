"""The login page in a real browser (Debian's Chromium driven by Playwright) against a server on 127.0.0.1:
`next=javascript:…` never runs and creates no API key, `next=https://…` never leaves the site — both when
the server drops the bad `next` and when only the page's own check stands (the page served for such a URL
anyway) — and every page, /docs and the 3D view run under the Content-Security-Policy without a violation."""

from __future__ import annotations

import json
from collections.abc import Iterator
from typing import Any
from urllib.parse import quote

import pytest
from browser_helpers import NEEDS_CHROMIUM, PASSWORD, running_server

from server.security import safe_redirect

pytestmark = [NEEDS_CHROMIUM]
# what the payload does if it ever runs: an API key with every scope in the victim's name
PAYLOAD = (
    "javascript:fetch('/api/v1/api-keys',{method:'POST',headers:{'Content-Type':'application/json'},"
    "body:JSON.stringify({name:'pwned',scopes:['practice','exercises:read','exercises:write',"
    "'submissions:read','submissions:write']})}).then(()=>{window.pwned=true})"
)


@pytest.fixture(scope="module")
def server(tmp_path_factory: pytest.TempPathFactory) -> Iterator[str]:
    teachers = [(f"lehrer{k}", "instructor") for k in (1, 2, 3, 4)]
    with running_server(tmp_path_factory.mktemp("data"), teachers) as url:
        yield url


def _watch(page: Any) -> dict[str, list[str]]:
    """Records dialogs, CSP violations (console) and every request that leaves the server."""
    seen: dict[str, list[str]] = {"dialogs": [], "csp": [], "offsite": []}
    page.on("dialog", lambda d: (seen["dialogs"].append(d.message), d.dismiss()))
    page.on("console", lambda m: seen["csp"].append(m.text) if "Content Security Policy" in m.text else None)
    return seen


def _block_offsite(page: Any, server: str, seen: dict[str, list[str]]) -> None:
    def handle(route: Any) -> None:
        if route.request.url.startswith(server):
            route.continue_()
        else:
            seen["offsite"].append(route.request.url)
            route.abort()

    page.route("**/*", handle)


def _login(page: Any, user: str) -> None:
    page.fill("input[name=username]", user)
    page.fill("input[name=password]", PASSWORD)
    page.click("button[type=submit]")


def _api_keys(page: Any, server: str) -> list[dict[str, Any]]:
    r = page.request.get(f"{server}/api/v1/api-keys")
    assert r.status == 200, r.text()
    return list(r.json())


@pytest.mark.parametrize("page_check_only", [False, True], ids=["server-and-page", "page-only"])
def test_javascript_next_does_not_run(server: str, browser: Any, page_check_only: bool) -> None:
    context = browser.new_context()
    page = context.new_page()
    seen = _watch(page)
    _block_offsite(page, server, seen)
    bad = f"{server}/login?next={quote(PAYLOAD, safe='')}"
    if page_check_only:  # the login page as it would be served if the server let the URL through
        html = page.request.get(f"{server}/login").text()
        page.route(
            lambda u: u.startswith(f"{server}/login?next="),
            lambda route: route.fulfill(status=200, content_type="text/html", body=html),
        )
    page.goto(bad)
    assert ("/login?next=" in page.url) == page_check_only
    _login(page, "lehrer1" if page_check_only else "lehrer2")
    page.wait_for_url(f"{server}/instructor")  # the bad `next` dropped: the instructor's own page
    page.wait_for_timeout(500)
    assert page.evaluate("window.pwned === undefined")
    assert _api_keys(page, server) == []
    assert not seen["dialogs"] and not seen["offsite"]
    context.close()


@pytest.mark.parametrize("page_check_only", [False, True], ids=["server-and-page", "page-only"])
@pytest.mark.parametrize(
    "target", ["https://evil.example/login", "//evil.example/", "/\\evil.example/", "/\t/evil.example/"]
)
def test_offsite_next_stays_on_the_site(
    server: str, browser: Any, page_check_only: bool, target: str
) -> None:
    context = browser.new_context()
    page = context.new_page()
    seen = _watch(page)
    _block_offsite(page, server, seen)
    url = f"{server}/login?next={quote(target, safe='')}"
    if page_check_only:
        html = page.request.get(f"{server}/login").text()
        page.route(
            lambda u: u.startswith(f"{server}/login?next="),
            lambda route: route.fulfill(status=200, content_type="text/html", body=html),
        )
    page.goto(url)
    _login(page, "lehrer3")
    page.wait_for_url(f"{server}/instructor")  # the bad `next` dropped: the instructor's own page
    assert not seen["offsite"]
    context.close()


def test_site_next_is_followed(server: str, browser: Any) -> None:
    context = browser.new_context()
    page = context.new_page()
    page.goto(f"{server}/login?next={quote('/practice?dialect=beckhoff', safe='')}")
    _login(page, "lehrer4")
    page.wait_for_url(f"{server}/practice?dialect=beckhoff")
    context.close()


CASES = [
    "/",
    "/exercises/nuten",
    "/practice?dialect=beckhoff#x",
    "",
    "javascript:alert(1)",
    "JavaScript:alert(1)",
    "https://evil.example",
    "//evil.example",
    "/\\evil.example",
    "\\\\evil.example",
    "/\t/evil.example",
    "/\n/evil.example",
    " /x",
    "data:text/html,x",
    "exercises",
    "/x\x00",
    "/x\x7f",
    "/" + "a" * 3000,
    "/ü/ß",
    "/a b",
    "/%2F%2Fevil.example",
]


def test_page_rule_is_the_server_rule(server: str, browser: Any) -> None:
    page = browser.new_page()
    page.goto(f"{server}/login")
    page.wait_for_function("() => window.PalTrainer !== undefined")
    got = page.evaluate(f"{json.dumps(CASES)}.map((c) => window.PalTrainer.safeNext(c))")
    assert got == [safe_redirect(c) for c in CASES]
    assert page.evaluate("window.PalTrainer.safeNext(null)") == "/"
    page.close()


@pytest.mark.parametrize(
    "path", ["/", "/practice", "/login", "/instructor", "/exercises/pal-01-g1-gerade", "/no/such/page"]
)
def test_pages_run_under_the_policy(server: str, browser: Any, path: str) -> None:
    context = browser.new_context()
    page = context.new_page()
    seen = _watch(page)
    page.goto(f"{server}{path}")
    page.wait_for_function("() => window.PalTrainer !== undefined")
    if path == "/practice":
        page.wait_for_selector(".cm-content")
        page.wait_for_selector(".diag-none", timeout=15000)  # the live socket works under connect-src 'self'
    page.wait_for_timeout(300)
    assert not seen["csp"], seen["csp"]
    context.close()


def test_not_found_page_is_german_and_switches_to_english(server: str, browser: Any) -> None:
    context = browser.new_context()
    page = context.new_page()
    r = page.goto(f"{server}/gibt-es-nicht")
    assert r is not None and r.status == 404
    assert "Seite nicht gefunden" in page.inner_text("main")
    page.click("#lang")
    page.wait_for_selector("text=Page not found")
    context.close()


def test_docs_work_offline_under_the_policy(server: str, browser: Any) -> None:
    context = browser.new_context()
    page = context.new_page()
    seen = _watch(page)
    _block_offsite(page, server, seen)
    page.goto(f"{server}/docs")
    page.wait_for_selector("text=PAL Trainer API", timeout=15000)
    page.wait_for_selector("[data-path='/api/v1/auth/token']", timeout=15000)
    assert not seen["csp"], seen["csp"]
    assert not seen["offsite"], seen["offsite"]
    context.close()


def test_viser_page_runs_under_its_policy(server: str, browser: Any) -> None:
    context = browser.new_context()
    page = context.new_page()
    seen = _watch(page)
    _block_offsite(page, server, seen)
    r = page.request.post(f"{server}/api/v1/viz")
    assert r.status == 201, r.text()
    url = f"{server}{r.json()['url']}"
    page.goto(url)
    # the viser application (the unpacked inline module script) rendered and connected through the bridge
    page.wait_for_selector("text=Connected", state="attached", timeout=20000)
    assert not seen["csp"], seen["csp"]
    csp = page.request.get(url).headers["content-security-policy"]
    assert "'unsafe-inline'" not in csp.split("script-src", 1)[1].split(";", 1)[0]
    context.close()
