"""Drafts on the exercise page in Chromium: what the trainee types is back after a reload and on another computer
(a fresh browser profile: the server's draft), typed while offline it is kept in the browser and reaches the
server when the page is online again; "Zurücksetzen" after the confirmation restores the start program and the
draft is gone on the server too."""

from __future__ import annotations

import json
import time

import pytest
from browser_helpers import log_in
from test_practice_page import CHROMIUM, PASSWORD, server  # noqa: F401 (fixtures)
from test_viz_view import wait_until

pytestmark = [
    pytest.mark.skipif(CHROMIUM is None, reason="Chromium not installed (.ci/run installs Debian's package)")
]

SLUG = "ergaenzen-01-kreisbogen"


def login(browser: object, server: str) -> tuple[object, object]:  # noqa: F811
    ctx = browser.new_context(viewport={"width": 1366, "height": 768})  # type: ignore[attr-defined]
    page = ctx.new_page()
    log_in(page, server, "schueler")
    page.wait_for_url(f"{server}/")
    return ctx, page


def open_exercise(page: object, server: str) -> None:  # noqa: F811
    page.goto(f"{server}/exercises/{SLUG}")  # type: ignore[attr-defined]
    page.wait_for_selector(".cm-content", timeout=20000)  # type: ignore[attr-defined]


def editor_text(page: object) -> str:
    return str(
        page.evaluate(  # type: ignore[attr-defined]
            "[...document.querySelectorAll('.cm-content .cm-line')].map((l) => l.textContent).join('\\n')"
        )
    )


def server_draft(page: object) -> dict[str, object]:
    return json.loads(
        page.evaluate(  # type: ignore[attr-defined]
            f"fetch('/api/v1/exercises/{SLUG}/draft').then((r) => r.text())"
        )
    )


def type_at_end(page: object, text: str) -> None:
    page.click(".cm-content")  # type: ignore[attr-defined]
    page.keyboard.press("Control+End")  # type: ignore[attr-defined]
    page.keyboard.press("Enter")  # type: ignore[attr-defined]
    page.keyboard.type(text)  # type: ignore[attr-defined]


def test_draft_survives_reload_and_another_computer_and_reset(server: str, browser: object) -> None:  # noqa: F811
    ctx, page = login(browser, server)
    open_exercise(page, server)
    start = editor_text(page)
    assert "mein Entwurf" not in start
    type_at_end(page, "; mein Entwurf")
    # saved on the server within the 2 s of the debounce (and a little)
    deadline = time.monotonic() + 8
    while "mein Entwurf" not in str(server_draft(page).get("program")):
        assert time.monotonic() < deadline, "the draft did not reach the server"
        time.sleep(0.2)
    page.reload()  # type: ignore[attr-defined]
    page.wait_for_selector(".cm-content", timeout=20000)  # type: ignore[attr-defined]
    wait_until(page, "document.querySelector('.cm-content').textContent.includes('mein Entwurf')")

    # another computer: a fresh browser profile, nothing in its localStorage
    other_ctx, other = login(browser, server)
    open_exercise(other, server)
    wait_until(other, "document.querySelector('.cm-content').textContent.includes('mein Entwurf')")
    other_ctx.close()  # type: ignore[attr-defined]

    # offline: kept in the browser, sent when online again; a reload brings it back either way
    ctx.set_offline(True)  # type: ignore[attr-defined]
    type_at_end(page, "; offline getippt")
    time.sleep(2.5)
    stored = page.evaluate(
        "Object.keys(localStorage).filter((k) => k.startsWith('paltrainer-draft:'))"  # type: ignore[attr-defined]
        ".map((k) => localStorage.getItem(k)).join('')"
    )
    assert "offline getippt" in stored
    ctx.set_offline(False)  # type: ignore[attr-defined]
    deadline = time.monotonic() + 8
    while "offline getippt" not in str(server_draft(page).get("program")):
        assert time.monotonic() < deadline, "the offline draft did not reach the server once online"
        time.sleep(0.2)

    # "Zurücksetzen": a confirmation, then the start program, and the server forgets the draft
    messages: list[str] = []

    def accept(dialog: object) -> None:
        messages.append(dialog.message)  # type: ignore[attr-defined]
        dialog.accept()  # type: ignore[attr-defined]

    page.on("dialog", accept)  # type: ignore[attr-defined]
    page.click("#file-reset")  # type: ignore[attr-defined]
    assert messages and "Startprogramm" in messages[0]
    wait_until(page, "!document.querySelector('.cm-content').textContent.includes('Entwurf')")
    assert editor_text(page) == start
    deadline = time.monotonic() + 5
    while server_draft(page).get("program") is not None:
        assert time.monotonic() < deadline, "the draft was not deleted"
        time.sleep(0.2)
    page.reload()  # type: ignore[attr-defined]
    page.wait_for_selector(".cm-content", timeout=20000)  # type: ignore[attr-defined]
    time.sleep(0.5)
    assert editor_text(page) == start
    ctx.close()  # type: ignore[attr-defined]


def test_leaving_the_page_saves_at_once(server: str, browser: object) -> None:  # noqa: F811
    """Typed and gone within the 2 s: the keepalive save on leaving keeps it."""
    ctx, page = login(browser, server)
    open_exercise(page, server)
    type_at_end(page, "; schnell weg")
    page.goto(f"{server}/")  # type: ignore[attr-defined]
    deadline = time.monotonic() + 5
    while "schnell weg" not in str(server_draft(page).get("program")):
        assert time.monotonic() < deadline, "leaving the page did not save the draft"
        time.sleep(0.2)
    ctx.close()  # type: ignore[attr-defined]
