"""What every page shares, in a real browser (Debian's Chromium driven by Playwright) against a server on
127.0.0.1: the header names who is logged in with "Abmelden" and shows instructor links only to instructors; a
logged-out visitor to / lands on /login without a console error; "Über / Lizenzen" lists the bundled packages
with their licences and the licence texts are served; number fields take a decimal comma (12,5 is 12.5); the
practice set-up offers every milling tool kind; switching the language keeps the program and the 3D view on."""

from __future__ import annotations

import json
from collections.abc import Iterator
from typing import Any

import pytest
from browser_helpers import NEEDS_CHROMIUM, log_in, running_server

pytestmark = [NEEDS_CHROMIUM]


@pytest.fixture(scope="module")
def server(tmp_path_factory: pytest.TempPathFactory) -> Iterator[str]:
    with running_server(
        tmp_path_factory.mktemp("data"), [("azubi", "student"), ("meister", "instructor")]
    ) as url:
        yield url


@pytest.fixture
def page(browser: Any) -> Iterator[Any]:
    context = browser.new_context()
    yield context.new_page()
    context.close()


def _errors(page: Any) -> list[str]:
    errors: list[str] = []
    page.on("console", lambda m: errors.append(m.text) if m.type == "error" else None)
    page.on("pageerror", lambda e: errors.append(str(e)))
    return errors


def _login(page: Any, server: str, user: str) -> None:
    log_in(page, server, user)
    page.wait_for_url(
        lambda url: url in (f"{server}/", f"{server}/instructor")
    )  # instructors land on their page


def test_logged_out_visitor_goes_to_login_without_console_errors(server: str, page: Any) -> None:
    errors = _errors(page)
    page.goto(f"{server}/")
    page.wait_for_selector("input[name=username]")
    page.wait_for_timeout(500)
    assert page.url.startswith(f"{server}/login")
    assert errors == []
    assert page.is_visible("#nav-login") and not page.is_visible("#nav-user")
    assert not page.is_visible("a[href='/instructor']")  # no instructor links for visitors


def test_student_sees_name_and_logout_but_no_instructor_links(server: str, page: Any) -> None:
    errors = _errors(page)
    _login(page, server, "azubi")
    page.wait_for_selector("#nav-user")
    assert page.inner_text("#nav-username") == "azubi"
    assert page.inner_text("#logout") == "Abmelden"
    assert not page.is_visible("#nav-login")
    assert not page.is_visible("a[href='/instructor']")
    page.click("#logout")
    page.wait_for_url(f"{server}/login")
    assert page.is_visible("#nav-login") and not page.is_visible("#nav-user")
    page.goto(f"{server}/")  # the session is gone
    page.wait_for_url(f"{server}/login")
    assert [e for e in errors if "401" not in e] == []


def test_instructor_sees_the_instructor_link(server: str, page: Any) -> None:
    _login(page, server, "meister")
    page.wait_for_selector("a[href='/instructor']", state="visible")
    assert page.inner_text("#nav-username") == "meister"


def test_about_lists_codemirror_and_the_licences_are_served(server: str, page: Any) -> None:
    page.goto(f"{server}/practice")
    page.click("#nav-about")
    page.wait_for_url(f"{server}/about")
    page.wait_for_selector("#licences tbody tr")
    rows = {
        r[0]: r
        for r in page.eval_on_selector_all(
            "#licences tbody tr", "rows => rows.map(r => [...r.cells].map(c => c.textContent))"
        )
    }
    assert rows["@codemirror/view"][2] == "MIT" and rows["@codemirror/state"][2] == "MIT"
    assert rows["swagger-ui-dist"][2] == "Apache-2.0"
    assert "Apache License 2.0" in page.inner_text("#about")
    r = page.request.get(f"{server}/static/licenses.txt")
    assert r.status == 200 and r.headers["content-type"].startswith("text/plain")
    text = r.text()
    assert "@codemirror/view" in text and "Marijn Haverbeke" in text and "Apache License" in text


def test_decimal_comma_and_every_milling_tool_kind(server: str, page: Any) -> None:
    page.goto(f"{server}/practice")
    page.wait_for_selector(".cm-content")
    page.click("#setup-box summary")  # "Rohteil und Werkzeuge"
    stock_x = page.locator("form.setup input[aria-label]").first
    stock_x.fill("12,5")
    stock_x.dispatch_event("change")
    page.click("#add-tool")
    row = page.locator("form.setup tbody tr").last
    row.locator("input").nth(1).fill("6,5")
    row.locator("input").nth(1).dispatch_event("change")
    saved = json.loads(page.evaluate("localStorage.getItem('paltrainer-practice-setup')"))
    assert saved["size"][0] == 12.5
    assert saved["tools"][-1]["diameter"] == 6.5
    kinds = row.locator("select option").evaluate_all("os => os.map(o => o.value)")
    assert kinds == ["end_mill", "slot_drill", "ball_nose", "torus", "twist_drill", "spot_drill"]
    stock_x.fill("12,5,1")  # not a number: the set-up says so and keeps the last good one
    stock_x.dispatch_event("change")
    assert json.loads(page.evaluate("localStorage.getItem('paltrainer-practice-setup')"))["size"][0] == 12.5


def test_language_switch_keeps_program_and_3d(server: str, page: Any) -> None:
    page.goto(f"{server}/practice")
    page.wait_for_selector(".cm-content")
    page.click("#viz-on")
    page.wait_for_selector("#viz-off", timeout=30000)
    page.click(".cm-content")
    page.keyboard.press("Control+End")
    page.keyboard.type("; mein Kommentar")
    page.click("#lang")
    page.wait_for_function("document.documentElement.lang === 'en'")
    page.wait_for_selector(".cm-content")
    page.wait_for_selector("#viz-off", timeout=30000)  # 3D still on (it starts off with software WebGL)
    assert "; mein Kommentar" in page.inner_text(".cm-content")
