"""The admin page (/admin) in Chromium (issue 31): an admin finds it in the header, makes a trainee an instructor
(kept after a reload), sets a one-time password (shown once; it logs in) and deactivates an account (it no longer
logs in), creates an API key (shown once, it works, gone after a reload), registers a learning platform by hand (a
wrong address is named at its field, in German) and makes a dynamic registration URL; a trainee opening /admin reads
"Nur für Administratoren" and sees no link to it. No horizontal overflow at 1366×768 and 768×1024, no serious
axe-core finding. Screenshots: PALTRAINER_SCREENSHOTS, else tests/browser/screenshots/."""

from __future__ import annotations

import json
import os
import urllib.error
import urllib.parse
import urllib.request
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
from browser_helpers import NEEDS_CHROMIUM, PASSWORD, ROOT, log_in, running_server
from test_viz_view import wait_until

pytestmark = [NEEDS_CHROMIUM]

SHOTS = Path(os.environ.get("PALTRAINER_SCREENSHOTS") or Path(__file__).parent / "screenshots")
AXE = ROOT / "web" / "node_modules" / "axe-core" / "axe.min.js"
SIZES = {"laptop": (1366, 768), "tablet": (768, 1024)}
ADMIN, TRAINEE, TEACHER, LEAVER, FORGETFUL, VISITOR = (
    "verwalter",
    "azubi-anna",
    "lehrer-lutz",
    "azubi-ben",
    "azubi-carla",
    "azubi-dora",
)
WIDER = (
    "[...document.querySelectorAll('body *')].filter((e) => e.getBoundingClientRect().right > innerWidth + 1)"
    ".slice(0, 5).map((e) => e.tagName + '#' + e.id + '.' + e.className)"
)


@pytest.fixture(scope="module")
def server(tmp_path_factory: pytest.TempPathFactory) -> Iterator[str]:
    users = [
        (ADMIN, "admin"),
        (TRAINEE, "student"),
        (TEACHER, "instructor"),
        (LEAVER, "student"),
        (FORGETFUL, "student"),
        (VISITOR, "student"),
    ]
    with running_server(tmp_path_factory.mktemp("data"), users) as url:
        yield url


def login_status(server: str, user: str, password: str) -> int:
    data = urllib.parse.urlencode({"username": user, "password": password}).encode()
    request = urllib.request.Request(f"{server}/api/v1/auth/token", data=data, method="POST")
    try:
        with urllib.request.urlopen(request, timeout=30) as r:
            return int(r.status)
    except urllib.error.HTTPError as err:
        return int(err.code)


def key_status(server: str, key: str) -> int:
    request = urllib.request.Request(f"{server}/api/v1/exercises", headers={"X-API-Key": key})
    try:
        with urllib.request.urlopen(request, timeout=30) as r:
            return int(r.status)
    except urllib.error.HTTPError as err:
        return int(err.code)


def logged_in(browser: Any, server: str, user: str, size: str = "laptop") -> Any:
    width, height = SIZES[size]
    # axe-core comes in as a script (the pages' Content-Security-Policy allows only our own)
    page = browser.new_context(viewport={"width": width, "height": height}, bypass_csp=True).new_page()
    page.on("dialog", lambda dialog: dialog.accept())  # the confirmations of reset, deactivate, revoke
    log_in(page, server, user)
    page.wait_for_url(lambda url: not url.endswith("/login"))
    return page


def open_admin(page: Any, server: str) -> None:
    page.goto(f"{server}/admin")
    page.wait_for_selector("#admin[data-ready]", timeout=20000)


def checked(page: Any, size: str, name: str) -> None:
    """No horizontal overflow, no serious axe-core finding, no placeholder; the screenshot."""
    assert page.evaluate("document.documentElement.scrollWidth <= innerWidth"), page.evaluate(WIDER)
    text = page.inner_text("main")
    assert not [w for w in ("{", "}", "null", "undefined", "NaN") if w in text], text
    if AXE.exists():
        page.add_script_tag(path=str(AXE))
        found = page.evaluate(
            "async () => (await axe.run(document)).violations"
            ".filter((v) => ['serious', 'critical'].includes(v.impact)).map((v) => v.id)"
        )
        assert not found, found
    SHOTS.mkdir(parents=True, exist_ok=True)
    page.screenshot(path=str(SHOTS / f"admin-{name}-{size}.png"), full_page=True)


def row(page: Any, table: str, name: str) -> Any:
    if table == "users-table":  # by the row's user (every row's instructor choice names the instructors too)
        return page.locator(f"#users-table tbody tr[data-user='{name}']")
    return page.locator(f"#{table} tbody tr", has_text=name).first


def test_admin_manages_users_keys_and_platforms(browser: Any, server: str) -> None:
    page = logged_in(browser, server, ADMIN)
    link = page.locator("header a[href='/admin']")
    assert link.is_visible() and link.inner_text() == "Verwaltung"
    link.click()
    page.wait_for_selector("#admin[data-ready]", timeout=20000)
    assert page.title() == "PAL Trainer – Verwaltung"

    # a trainee becomes an instructor; the page says so, and it holds after a reload
    role = row(page, "users-table", TRAINEE).locator("select.user-role")
    assert role.input_value() == "student"
    role.select_option("instructor")
    wait_until(page, "document.getElementById('users-status').textContent.includes('ist jetzt')")
    assert page.inner_text("#users-status") == f"{TRAINEE} ist jetzt Ausbilder/in."
    open_admin(page, server)
    assert row(page, "users-table", TRAINEE).locator("select.user-role").input_value() == "instructor"
    # the own role cannot be changed here (the API refuses it too)
    assert row(page, "users-table", ADMIN).locator("select.user-role").is_disabled()

    # an API key: shown once, it works; after a reload only its prefix is left
    page.fill("#new-key-name", "Schulsystem")
    page.check("#new-key input[value='exercises:read']")
    page.click("#new-key button[type=submit]")
    page.wait_for_selector("#key-secret-value")
    key = page.input_value("#key-secret-value")
    assert "nur jetzt angezeigt" in page.inner_text("#key-secret")
    assert key_status(server, key) == 200
    assert "Aufgaben lesen" in row(page, "keys-table", "Schulsystem").inner_text()
    checked(page, "laptop", "key")
    open_admin(page, server)
    assert not page.locator("#key-secret-value").count() and key not in page.content()
    assert row(page, "keys-table", "Schulsystem").inner_text().count("gültig") == 1
    # every scope of the server can be chosen
    from server.models import SCOPES

    assert page.eval_on_selector_all(
        "#new-key input[name=scope]", "(boxes) => boxes.map((b) => b.value)"
    ) == list(SCOPES)

    # a platform by hand: a wrong address is named at its field, then the right one registers it
    fields = {
        "issuer": "moodle.bs-ost.example",
        "client_id": "pal-42",
        "auth_login_url": "https://moodle.bs-ost.example/mod/lti/auth.php",
        "token_url": "https://moodle.bs-ost.example/mod/lti/token.php",
        "jwks_url": "https://moodle.bs-ost.example/mod/lti/certs.php",
        "deployment_ids": "3, 4",
        "name": "Moodle BS Ost",
    }
    for field, value in fields.items():
        page.fill(f"#platform-{field}", value)
    page.click("#new-platform button[type=submit]")
    wait_until(page, "document.getElementById('platform-issuer-error').textContent !== ''")
    assert page.inner_text("#platform-issuer-error").startswith("keine gültige https-Adresse")
    assert page.inner_text("#platform-client_id-error") == ""
    assert "Die Anfrage ist ungültig" in page.inner_text("#platform-status")
    page.fill("#platform-issuer", "https://moodle.bs-ost.example")
    page.click("#new-platform button[type=submit]")
    page.wait_for_selector("#platforms-table")
    listed = row(page, "platforms-table", "Moodle BS Ost").inner_text()
    assert "https://moodle.bs-ost.example" in listed and "pal-42" in listed and "3, 4" in listed
    assert page.inner_text("#platform-status") == "Plattform »Moodle BS Ost« registriert."
    assert page.inner_text("#platform-issuer-error") == "" and page.input_value("#platform-issuer") == ""

    # a dynamic registration URL on this server
    page.click("#make-registration-url")
    page.wait_for_selector("#registration-url-value")
    assert page.input_value("#registration-url-value").startswith(f"{server}/lti/register?code=")
    assert "Gilt 7 Tage für genau eine Registrierung." in page.inner_text("#registration-url")

    # our keys: a new one signs, the old one can then be retired
    page.click("#rotate-key")
    wait_until(page, "document.getElementById('lti-keys-status').textContent.includes('signiert ab jetzt')")
    states = page.eval_on_selector_all(
        "#lti-keys-table tbody tr td:nth-child(3)", "(cells) => cells.map((c) => c.textContent)"
    )
    assert states.count("signiert") == 1 and "veröffentlicht" in states
    checked(page, "laptop", "page")
    page.context.close()


def test_admin_resets_and_deactivates(browser: Any, server: str) -> None:
    page = logged_in(browser, server, ADMIN)
    open_admin(page, server)
    # a one-time password, shown once: it logs in (and must be changed then); the old one no longer does
    row(page, "users-table", FORGETFUL).locator("button.user-reset").click()
    page.wait_for_selector("#users-password-value")
    once = page.input_value("#users-password-value")
    assert f"Einmalpasswort für {FORGETFUL}:" in page.inner_text("#users-secret")
    assert "nur jetzt angezeigt" in page.inner_text("#users-secret")
    assert "muss Passwort ändern" in row(page, "users-table", FORGETFUL).inner_text()
    assert login_status(server, FORGETFUL, once) == 200 and login_status(server, FORGETFUL, PASSWORD) == 401
    # deactivated: the row says so, the account no longer logs in; activated again, it does
    leaver = row(page, "users-table", LEAVER)
    leaver.locator("button.user-active").click()
    wait_until(page, "document.getElementById('users-status').textContent.includes('deaktiviert')")
    assert "deaktiviert" in row(page, "users-table", LEAVER).inner_text()
    assert row(page, "users-table", LEAVER).locator("button.user-active").inner_text() == "Aktivieren"
    assert login_status(server, LEAVER, PASSWORD) != 200
    checked(page, "laptop", "users")
    row(page, "users-table", LEAVER).locator("button.user-active").click()
    wait_until(page, "document.getElementById('users-status').textContent.includes('wieder aktiv')")
    assert login_status(server, LEAVER, PASSWORD) == 200
    # the admin's own account cannot be deactivated here
    assert row(page, "users-table", ADMIN).locator("button.user-active").is_disabled()
    page.context.close()


def test_admin_creates_users_and_imports_a_class_list(browser: Any, server: str) -> None:
    page = logged_in(browser, server, ADMIN)
    open_admin(page, server)
    page.fill("#new-user-name", "azubi-emil")
    page.fill("#new-user-password", "kurz")
    page.select_option("#new-user-instructor", TEACHER)
    page.click("#new-user button[type=submit]")
    wait_until(page, "document.getElementById('new-user-status').textContent !== ''")
    assert "Die Anfrage ist ungültig" in page.inner_text("#new-user-status")  # the password rule, in German
    assert not page.locator("#users-table tbody tr[data-user='azubi-emil']").count()
    page.fill("#new-user-password", "Emils langes Passwort")
    page.click("#new-user button[type=submit]")
    wait_until(page, "document.getElementById('new-user-status').textContent.includes('angelegt')")
    emil = row(page, "users-table", "azubi-emil")
    assert emil.locator("select.user-instructor").input_value() == TEACHER
    assert login_status(server, "azubi-emil", "Emils langes Passwort") == 200
    # a class list for the instructor: the generated passwords shown this once
    page.select_option("#import-instructor", TEACHER)
    csv = b"Name;Passwort\nazubi-fritz\nazubi-greta;Gretas Passwort\n"
    page.set_input_files(
        "#import-file", files=[{"name": "klasse.csv", "mimeType": "text/csv", "buffer": csv}]
    )
    wait_until(page, "document.querySelector('#import-result table') !== null")
    assert page.inner_text("#import-result p") == "2 Konten angelegt."
    passwords = dict(
        page.eval_on_selector_all(
            "#import-result tbody tr", "(rows) => rows.map((r) => [...r.cells].map((c) => c.textContent))"
        )
    )
    assert passwords["azubi-greta"] == "(aus der Liste)" and len(passwords["azubi-fritz"]) >= 8
    assert login_status(server, "azubi-fritz", passwords["azubi-fritz"]) == 200
    assert row(page, "users-table", "azubi-greta").locator("select.user-instructor").input_value() == TEACHER
    page.context.close()


def test_admin_page_on_a_tablet(browser: Any, server: str) -> None:
    page = logged_in(browser, server, ADMIN, "tablet")
    open_admin(page, server)
    checked(page, "tablet", "page")
    page.context.close()


def test_trainee_reads_only_for_admins(browser: Any, server: str) -> None:
    for size in SIZES:
        page = logged_in(browser, server, VISITOR, size)
        assert not page.locator("header a[href='/admin']").is_visible()
        response = page.goto(f"{server}/admin")
        assert response is not None and response.status == 403
        page.wait_for_selector("#admin-denied")
        assert page.inner_text("#admin-denied").startswith("Nur für Administratoren.")
        assert not page.locator("#users-table, #keys-table, #platforms-table").count()
        checked(page, size, "denied")
        page.context.close()


def test_english_admin_page(browser: Any, server: str) -> None:
    page = logged_in(browser, server, ADMIN)
    page.evaluate("localStorage.setItem('paltrainer-lang', 'en')")
    open_admin(page, server)
    assert page.inner_text("main h2") == "Administration"
    assert "Registered platforms" in page.inner_text("#admin-lti")
    assert json.dumps(
        page.eval_on_selector_all("#users-table th", "(ths) => ths.map((t) => t.textContent)")
    ) == json.dumps(["Name", "Role", "Instructor", "Status", "Actions"])
    page.context.close()
