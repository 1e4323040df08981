"""Accounts in Chromium (issue 31): an instructor resets a student's password on the course page and reads the
one-time password once; the student logs in with it, is sent to "Passwort ändern" (every other page leads back
there) and chooses their own; a visitor finds "Registrieren" on the login page (the server runs with
PALTRAINER_SELF_SIGNUP=course-code), signs up with the course's join code and is in the course, marked "selbst
registriert" on the course page. The header's user menu leads to "Passwort ändern". No horizontal overflow at
1366×768 and 768×1024. Screenshots: PALTRAINER_SCREENSHOTS, else tests/browser/screenshots/."""

from __future__ import annotations

import os
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
from browser_helpers import NEEDS_CHROMIUM, PASSWORD, call, running_server
from playwright.sync_api import expect
from test_viz_view import WIDER

pytestmark = [NEEDS_CHROMIUM]

SHOTS = Path(os.environ.get("PALTRAINER_SCREENSHOTS") or Path(__file__).parent / "screenshots")
SIZES = {"laptop": (1366, 768), "tablet": (768, 1024)}
TEACHER, STUDENT = "konto-lehrer", "konto-anna"
OWN = "Annas eigenes Passwort"


@pytest.fixture(scope="module")
def server(tmp_path_factory: pytest.TempPathFactory) -> Iterator[str]:
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("PALTRAINER_SELF_SIGNUP", "course-code")
        with running_server(tmp_path_factory.mktemp("accounts"), [(TEACHER, "instructor")]) as url:
            yield url


@pytest.fixture(scope="module")
def course(server: str) -> dict[str, Any]:
    """The instructor's course "FA 24b" with their student konto-anna (made by them, password PASSWORD)."""
    token = call(server, "POST", "/auth/token", form={"username": TEACHER, "password": PASSWORD})[
        "access_token"
    ]
    made = call(server, "POST", "/courses", token, {"name": "FA 24b"})
    call(server, "POST", "/users", token, {"username": STUDENT, "password": PASSWORD})
    call(server, "POST", f"/courses/{made['id']}/members", token, {"username": STUDENT})
    return dict(made)


def page_of(browser: Any, size: str) -> Any:
    width, height = SIZES[size]
    page = browser.new_context(viewport={"width": width, "height": height}).new_page()
    page.on("dialog", lambda dialog: dialog.accept())  # "… zurücksetzen?"
    return page


def log_in(page: Any, server: str, name: str, password: str) -> None:
    page.goto(f"{server}/login")
    page.fill("input[name=username]", name)
    page.fill("input[name=password]", password)
    page.click("#login button[type=submit]")


def fits(page: Any) -> None:
    assert page.evaluate("document.documentElement.scrollWidth <= innerWidth"), page.evaluate(WIDER)


def shot(page: Any, name: str) -> None:
    SHOTS.mkdir(parents=True, exist_ok=True)
    page.screenshot(path=str(SHOTS / name), full_page=True)


def test_reset_on_the_course_page_and_the_student_must_change_it(
    browser: Any, server: str, course: dict[str, Any]
) -> None:
    teacher = page_of(browser, "laptop")
    log_in(teacher, server, TEACHER, PASSWORD)
    teacher.wait_for_url(f"{server}/instructor")
    teacher.goto(f"{server}/courses/{course['id']}")
    row = teacher.locator("#member-table tr", has_text=STUDENT)
    row.get_by_role("button", name=f"Passwort zurücksetzen für {STUDENT}").click()
    once = teacher.locator("#one-time-password")
    once.wait_for()
    one_time = once.inner_text().strip()
    assert len(one_time) >= 8 and one_time != PASSWORD
    assert "nur jetzt angezeigt" in teacher.locator("#reset-result").inner_text()
    fits(teacher)
    shot(teacher, "accounts-reset-laptop.png")

    student = page_of(browser, "tablet")
    log_in(student, server, STUDENT, PASSWORD)  # the old password no longer works
    expect(student.locator("#message")).to_contain_text("Benutzername oder Passwort ist falsch.")
    log_in(student, server, STUDENT, one_time)
    student.wait_for_url(f"{server}/password")
    assert student.locator("#password-required").is_visible()
    assert "zurückgesetzt" in student.locator("#password-required").inner_text()
    student.goto(f"{server}/")  # nothing else opens before the change
    assert student.url == f"{server}/password"
    student.fill("input[name=current_password]", one_time)
    student.fill("input[name=new_password]", OWN)
    student.fill("input[name=repeat]", OWN + "!")
    student.click("#password-form button[type=submit]")
    expect(student.locator("#password-message")).to_contain_text("stimmen nicht überein")
    student.fill("input[name=repeat]", OWN)
    fits(student)
    shot(student, "accounts-must-change-tablet.png")
    student.click("#password-form button[type=submit]")
    student.locator("#password-continue").wait_for()
    assert "Ihr Passwort ist geändert." in student.locator("#password-message").inner_text()
    student.click("#password-continue")
    student.wait_for_url(f"{server}/")
    student.locator("#list a").first.wait_for()  # the exercise list opens now
    assert student.locator("#nav-username").inner_text() == STUDENT

    # the user menu leads to the change form (no reset notice there)
    teacher.click("#nav-password")
    teacher.wait_for_url(f"{server}/password")
    assert not teacher.locator("#password-required").is_visible()
    assert teacher.locator("h2").first.inner_text() == "Passwort ändern"
    fits(teacher)
    shot(teacher, "accounts-password-laptop.png")
    tablet = page_of(browser, "tablet")
    log_in(tablet, server, TEACHER, PASSWORD)
    tablet.wait_for_url(f"{server}/instructor")
    tablet.goto(f"{server}/courses/{course['id']}")
    tablet.locator("#member-table").get_by_text(STUDENT).wait_for()
    fits(tablet)
    shot(tablet, "accounts-course-tablet.png")


def test_a_visitor_signs_up_with_the_join_code(browser: Any, server: str, course: dict[str, Any]) -> None:
    for size in ("laptop", "tablet"):
        name = f"konto-neu-{size}"
        visitor = page_of(browser, size)
        visitor.goto(f"{server}/login")
        visitor.get_by_role("link", name="Neu hier? Mit dem Beitrittscode Ihrer Klasse registrieren").click()
        visitor.wait_for_url(f"{server}/signup")
        visitor.fill("input[name=join_code]", "FALSCH99")
        visitor.fill("input[name=username]", name)
        visitor.fill("input[name=password]", OWN)
        visitor.fill("input[name=repeat]", OWN)
        visitor.click("#signup-form button[type=submit]")
        message = visitor.locator("#signup-message")
        message.get_by_text("Zu diesem Beitrittscode gibt es keine Klasse.").wait_for()
        visitor.fill("input[name=join_code]", f" {course['join_code'].lower()} ")
        fits(visitor)
        shot(visitor, f"accounts-signup-{size}.png")
        visitor.click("#signup-form button[type=submit]")
        visitor.wait_for_url(f"{server}/")
        assert visitor.locator("#nav-username").inner_text() == name
        visitor.get_by_text("FA 24b").first.wait_for()  # "Meine Kurse" on the start page

    teacher = page_of(browser, "laptop")
    log_in(teacher, server, TEACHER, PASSWORD)
    teacher.wait_for_url(f"{server}/instructor")
    teacher.goto(f"{server}/courses/{course['id']}")
    row = teacher.locator("#member-table tr", has_text="konto-neu-laptop")
    expect(row).to_contain_text("selbst registriert")
    assert "selbst registriert" not in teacher.locator("#member-table tr", has_text=STUDENT).inner_text()
    fits(teacher)
    shot(teacher, "accounts-signed-up-laptop.png")
    row.get_by_role(
        "button", name="konto-neu-laptop aus der Klasse entfernen"
    ).click()  # the instructor removes them
    teacher.locator("#member-table tr", has_text="konto-neu-laptop").wait_for(state="detached")
