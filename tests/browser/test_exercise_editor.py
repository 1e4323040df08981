"""The exercise editor in Chromium (issue 31, "Done when"): an instructor duplicates a built-in exercise on their
page, changes its contour (the reference in the trainees' editor) and its blank and sees the drawing follow, and
publishes it to their course; a student of that course finds it in the list and solves it (submits the reference),
a student of another course does not see it; the instructor edits it again (version 2) and the results matrix says
the old submission was graded against version 1. "Speichern" with broken fields shows every error at its field.
Screenshots at 1366×768 and 768×1024: PALTRAINER_SCREENSHOTS, else tests/browser/screenshots/."""

from __future__ import annotations

import json
import os
import tempfile
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
from browser_helpers import NEEDS_CHROMIUM, PASSWORD, ROOT, call, log_in, running_server
from test_viz_view import wait_until

pytestmark = [NEEDS_CHROMIUM]

SHOTS = Path(os.environ.get("PALTRAINER_SCREENSHOTS") or Path(__file__).parent / "screenshots")
SIZES = {"laptop": (1366, 768), "tablet": (768, 1024)}
BUILTIN = "pal-01-g1-gerade"
COPY = f"{BUILTIN}-kopie"
REFERENCE = (ROOT / "exercises" / "pal-mill" / f"{BUILTIN}.nc").read_text(encoding="utf-8")
# the changed contour: the first line is longer (X80), the second shorter (Y60)
CHANGED = REFERENCE.replace("N60 G1 X70", "N60 G1 X80").replace("N70 G1 Y84", "N70 G1 Y60")
USERS = [
    ("ed-lehrer", "instructor"),
    ("ed-kollege", "instructor"),
    ("ed-anna", "student"),
    ("ed-bert", "student"),
]


def token(server: str, user: str) -> str:
    return str(
        call(server, "POST", "/auth/token", form={"username": user, "password": PASSWORD})["access_token"]
    )


@pytest.fixture(scope="module")
def server() -> Iterator[str]:
    with tempfile.TemporaryDirectory() as data, running_server(Path(data), USERS, workers=2) as url:
        # two courses: the instructor's with Anna, a colleague's with Bert
        for teacher, student in (("ed-lehrer", "ed-anna"), ("ed-kollege", "ed-bert")):
            course = call(url, "POST", "/courses", token(url, teacher), {"name": f"Klasse von {teacher}"})
            call(url, "POST", "/courses/join", token(url, student), {"code": course["join_code"]})
        yield url


def login(browser: Any, server: str, user: str, size: str = "laptop") -> Any:
    width, height = SIZES[size]
    page = browser.new_context(viewport={"width": width, "height": height}).new_page()
    log_in(page, server, user)
    return page


def fits(page: Any) -> None:
    assert page.evaluate("document.documentElement.scrollWidth <= innerWidth + 1")


# what the preview shows, as pixels (the page's Content-Security-Policy lets no script fetch the image again)
SHOWN = """(() => { const img = document.getElementById('drawing-preview');
  const c = document.createElement('canvas'); c.width = img.naturalWidth; c.height = img.naturalHeight;
  c.getContext('2d').drawImage(img, 0, 0); return c.toDataURL(); })()"""


def drawn(page: Any, action: Any) -> str:
    """The drawing preview the page shows after `action` (asked for once the typing settled), as pixels."""
    before = page.evaluate("document.getElementById('drawing-preview').src")
    action()
    wait_until(page, f"document.getElementById('drawing-preview').src !== {json.dumps(before)}", 60)
    wait_until(page, "document.getElementById('drawing-preview').naturalWidth > 50", 30)
    return str(page.evaluate(SHOWN))


def test_instructor_writes_an_exercise_for_one_course(server: str, browser: Any) -> None:
    SHOTS.mkdir(parents=True, exist_ok=True)
    page = login(browser, server, "ed-lehrer")
    page.wait_for_url(f"{server}/instructor")
    page.wait_for_selector("#my-exercises")
    assert page.locator("#exercise-text").count() == 0  # no YAML textarea as the way to make an exercise
    page.select_option("#template", BUILTIN)
    with page.expect_navigation():
        page.click("#copy-template")
    assert page.url == f"{server}/exercises/{COPY}/edit"
    page.wait_for_selector("#reference-editor .cm-content")
    wait_until(page, "document.getElementById('drawing-preview').naturalWidth > 50", 60)
    original = page.evaluate(SHOWN)
    assert "(Kopie)" in page.input_value("[data-field='title.de'] input")
    assert page.input_value("[data-field='visibility'] select") == "draft"
    page.wait_for_selector("#reference-diagnostics li", timeout=30000)  # the live check answers in the editor
    page.screenshot(path=str(SHOTS / "exercise-editor-laptop.png"), full_page=False)

    # the contour: the reference typed anew in the trainees' editor; the drawing follows
    first = drawn(page, lambda: page.locator("#reference-editor .cm-content").fill(CHANGED))
    assert first != original
    # the 3D view of the reference, as trainees see theirs (Chromium without graphics: the server's picture)
    page.click("#viz-show")
    wait_until(
        page,
        "document.getElementById('viz-picture')?.naturalWidth > 100 "
        "|| Boolean(document.getElementById('viz-frame')?.src)",
        60,
    )
    page.locator("#viz").scroll_into_view_if_needed()
    page.screenshot(path=str(SHOTS / "exercise-editor-3d-laptop.png"))
    page.locator(".program-and-drawing").scroll_into_view_if_needed()
    page.screenshot(path=str(SHOTS / "exercise-editor-program-laptop.png"))
    # the blank: 100 × 70 instead of 80 × 70; the drawing follows again
    max_x = page.locator("[data-field='stock'] .triple").nth(1).locator("input").first
    second = drawn(page, lambda: max_x.fill("100"))
    assert second != first
    task_text = page.locator("[data-field='task.de'] textarea")
    task_text.fill(task_text.input_value().replace("80 × 70", "100 × 70"))  # the task says the new blank

    # every error at its field at once: an empty title and points that do not add up
    title = page.locator("[data-field='title.de'] input")
    title.fill("")
    geometry = page.locator(".rubric input").first
    geometry.fill("40")
    page.click("#save")
    page.wait_for_selector("[data-field='title.de'].has-error")
    assert "fehlt" in page.inner_text("[data-field='title.de'] .field-error")
    assert "100" in page.inner_text("[data-field='rubric'] .field-error")
    assert page.locator("#edit-errors li").count() >= 2
    page.screenshot(path=str(SHOTS / "exercise-editor-errors-laptop.png"))
    title.fill("Kontur FA 23 – Prüfungsvorbereitung")
    geometry.fill("50")

    # publish to the instructor's courses
    page.select_option("[data-field='visibility'] select", "courses")
    page.click("#save")
    wait_until(page, "document.getElementById('edit-status').textContent.includes('Version 1')", 60)
    assert page.locator(".has-error").count() == 0
    fits(page)

    tablet = login(browser, server, "ed-lehrer", "tablet")
    tablet.goto(f"{server}/exercises/{COPY}/edit")
    wait_until(tablet, "document.getElementById('drawing-preview')?.naturalWidth > 50", 60)
    wait_until(tablet, "document.getElementById('task-preview').textContent.length > 20", 30)
    fits(tablet)
    tablet.screenshot(path=str(SHOTS / "exercise-editor-tablet.png"))
    tablet.locator(".program-and-drawing").scroll_into_view_if_needed()
    tablet.screenshot(path=str(SHOTS / "exercise-editor-program-tablet.png"))

    # Anna (the instructor's course) sees it and solves it; Bert (another course) does not see it
    anna = login(browser, server, "ed-anna")
    anna.goto(f"{server}/")
    anna.wait_for_selector("ul.exercises", timeout=90000)  # a busy machine: the first list is slow
    assert anna.locator("ul.exercises a", has_text="Kontur FA 23").count() == 1
    anna.goto(f"{server}/exercises/{COPY}")
    anna.wait_for_selector("figure.drawing img", state="attached", timeout=30000)
    wait_until(anna, "document.querySelector('figure.drawing img')?.naturalWidth > 100", 60)
    assert "100 × 70" in anna.inner_text("#task")
    anna.screenshot(path=str(SHOTS / "exercise-editor-student-laptop.png"))
    solved = call(
        server, "POST", "/submissions", token(server, "ed-anna"), {"exercise": COPY, "program": CHANGED}
    )
    assert solved["score"] == 100 and solved["exercise_version"] == 1
    bert = login(browser, server, "ed-bert")
    bert.goto(f"{server}/")
    bert.wait_for_selector("ul.exercises", timeout=90000)
    assert bert.locator("ul.exercises a", has_text="Kontur FA 23").count() == 0
    bert.goto(f"{server}/exercises/{COPY}")
    wait_until(bert, "document.body.innerText.includes('nicht gefunden')", 30)

    # the instructor edits the published exercise: version 2; Anna's submission keeps version 1
    page.goto(f"{server}/exercises/{COPY}/edit")
    page.wait_for_selector("[data-field='task.de'] textarea")
    task = page.locator("[data-field='task.de'] textarea")
    task.fill(task.input_value() + "\n\nAchten Sie auf die **Anfahrbewegung**.")
    wait_until(
        page, "document.getElementById('task-preview').innerHTML.includes('<strong>Anfahrbewegung')", 30
    )
    page.click("#save")
    wait_until(page, "document.getElementById('edit-status').textContent.includes('Version 2')", 60)
    page.goto(f"{server}/instructor")
    page.wait_for_selector("#my-exercises td")
    row = page.locator("#my-exercises tr", has_text="Kontur FA 23")
    assert row.locator("td").nth(2).inner_text() == "2"
    page.wait_for_selector("#results .version-note")
    assert "Version 1" in page.inner_text("#results .version-note")
    fits(page)
    page.screenshot(path=str(SHOTS / "exercise-editor-instructor-laptop.png"), full_page=True)
    tablet.goto(f"{server}/instructor")
    tablet.wait_for_selector("#results .version-note")
    fits(tablet)
    tablet.screenshot(path=str(SHOTS / "exercise-editor-instructor-tablet.png"), full_page=True)


def test_editor_has_no_serious_accessibility_problems(server: str, browser: Any) -> None:
    """axe-core on the editor of a new exercise and on an existing one (its errors shown)."""
    axe = ROOT / "web" / "node_modules" / "axe-core" / "axe.min.js"
    page = browser.new_context(viewport={"width": 1366, "height": 768}, bypass_csp=True).new_page()
    log_in(page, server, "ed-kollege")
    page.goto(f"{server}/exercises/new")
    page.wait_for_selector("#reference-editor .cm-content", timeout=60000)
    for errors in (False, True):
        if errors:
            page.click("#save")  # an empty exercise: every error at its field
            page.wait_for_selector("#edit-errors li", timeout=60000)
            assert page.locator(".has-error").count() >= 2
        page.add_script_tag(path=str(axe))
        result = page.evaluate("axe.run(document, {resultTypes: ['violations']})")
        serious = [
            (v["id"], v["impact"], [n["target"] for n in v["nodes"]][:3])
            for v in result["violations"]
            if v["impact"] in ("serious", "critical")
        ]
        assert not serious, serious
    page.screenshot(path=str(SHOTS / "exercise-editor-new-errors-laptop.png"))
    page.fill("[data-field='title.de'] input", "Kontur für Übung 3")  # the slug follows the title
    assert page.input_value("[data-field='id'] input") == "kontur-fuer-uebung-3"
    page.context.close()


def test_a_turning_exercise_to_complete_round_trips_through_the_editor(server: str, browser: Any) -> None:
    """A copy of the TRAUB exercise "ergänzen": the blank as a bar, the start program with its locked lines (a click
    on a line number frees or locks it), saved and published unchanged otherwise."""
    bearer = token(server, "ed-kollege")
    copy = call(server, "POST", "/exercises/traub-02-uebersichtskontur/duplicate", bearer)
    page = login(browser, server, "ed-kollege")
    page.goto(f"{server}/exercises/{copy['slug']}/edit")
    page.wait_for_selector("#start-editor .cm-content", timeout=60000)
    assert (
        page.locator("[data-field='blank']").is_visible()
        and not page.locator("[data-field='stock']").is_visible()
    )
    diameter = f"{copy['document']['blank']['diameter']:g}".replace(".", ",")
    assert page.input_value("[data-field='blank.diameter'] input") == diameter
    locked = page.locator("[data-field='locked_lines'] input")
    before = locked.input_value()
    assert before == ", ".join(str(n) for n in copy["document"]["locked_lines"])
    page.locator("#start-editor .cm-lineNumbers .cm-gutterElement", has_text="1").first.click()
    assert locked.input_value() != before
    page.locator("#start-editor .cm-lineNumbers .cm-gutterElement", has_text="1").first.click()
    assert locked.input_value() == before
    page.select_option("[data-field='visibility'] select", "public")
    page.click("#save")
    wait_until(page, "document.getElementById('edit-status').textContent.includes('Version 1')", 90)
    assert page.locator(".has-error").count() == 0
    fits(page)
    page.locator("#start-section").scroll_into_view_if_needed()
    page.screenshot(path=str(SHOTS / "exercise-editor-turning-laptop.png"))
    saved = call(server, "GET", f"/exercises/{copy['slug']}", bearer)
    assert saved["visibility"] == "public" and saved["document"]["blank"] == copy["document"]["blank"]
    assert saved["document"]["locked_lines"] == copy["document"]["locked_lines"]
    assert saved["document"]["start_program"] == copy["document"]["start_program"]
