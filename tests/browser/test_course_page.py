"""The instructor's course page in Chromium (issue 19): an instructor creates a course on the instructor page,
imports two students from a class list, creates a practice assignment with the form; the students submit (one in
time, one after the deadline); the results matrix shows both scores and the late mark, a cell opens the submission
(whose deviation colours appear when the 3D view is switched on later), the insights name the class's most
frequent diagnostic and lost criterion. The heading's number of members follows adding by name, removing and the
class list; the mode reads "Übung" / "Prüfung" in the form and "Prüfung · 45 min" in the list and headings (no
placeholder, "null", "undefined" or "NaN" anywhere on the page), and choosing an exam shows what it means for the
class's practice. No horizontal overflow at 1366×768 and 768×1024, no serious axe-core finding. Screenshots:
PALTRAINER_SCREENSHOTS, else tests/browser/screenshots/."""

from __future__ import annotations

import os
from datetime import UTC, datetime, timedelta
from pathlib import Path
from typing import Any

import pytest
from browser_helpers import call, create_users, log_in
from test_practice_page import CHROMIUM, PASSWORD, ROOT, SERVER_DATA, server  # noqa: F401 (fixtures)
from test_viz_view import WIDER

pytestmark = [
    pytest.mark.skipif(CHROMIUM is None, reason="Chromium not installed (.ci/run installs Debian's package)")
]

SHOTS = Path(os.environ.get("PALTRAINER_SCREENSHOTS") or Path(__file__).parent / "screenshots")
AXE = ROOT / "web" / "node_modules" / "axe-core" / "axe.min.js"
SIZES = {"laptop": (1366, 768), "tablet": (768, 1024)}
SLUG = "pal-01-g1-gerade"
REFERENCE = (ROOT / "exercises" / "pal-mill" / f"{SLUG}.nc").read_text(encoding="utf-8")
TEACHER = "kurs-lehrer"
STUDENTS = {"kurs-anna": "Annas langes Passwort", "kurs-ben": "Bens langes Passwort"}
# both write a decimal comma in a G1 block (PAL-E010): what the class discusses the next morning
PROGRAMS = {
    "kurs-anna": REFERENCE.replace("N70 G1 Y84", "N70 G1 Y84,5"),
    "kurs-ben": REFERENCE.replace("N60 G1 X70", "N60 G1 X70,0"),
}


def token(server: str, user: str, password: str) -> str:  # noqa: F811
    return str(
        call(server, "POST", "/auth/token", form={"username": user, "password": password})["access_token"]
    )


@pytest.fixture(scope="module")
def teacher(server: str) -> str:  # noqa: F811
    env = {**os.environ, "PALTRAINER_DATA_DIR": SERVER_DATA[0]}
    create_users(env, [(TEACHER, "instructor")])
    return TEACHER


def login(browser: Any, server: str, size: str = "laptop", **context: Any) -> Any:  # noqa: F811
    width, height = SIZES[size]
    page = browser.new_context(viewport={"width": width, "height": height}, **context).new_page()
    log_in(page, server, TEACHER)
    page.wait_for_url(f"{server}/instructor")  # an instructor lands on their page
    return page


def fits(page: Any) -> None:
    assert page.evaluate("document.documentElement.scrollWidth <= innerWidth"), page.evaluate(WIDER)


def no_placeholders(page: Any) -> None:
    """No text of the page (the select's options too) shows an unfilled {placeholder}, null, undefined or NaN."""
    text = page.evaluate(
        "document.body.innerText + ' ' + [...document.querySelectorAll('option')]"
        ".map((o) => o.textContent).join(' ')"
    )
    found = [w for w in ("{", "}", "null", "undefined", "NaN") if w in text]
    assert not found, (found, [line for line in text.splitlines() if any(w in line for w in found)])


def members_heading(page: Any) -> str:
    return str(page.inner_text("#members h3"))


def test_a_course_from_class_list_to_insights(server: str, browser: Any, teacher: str) -> None:  # noqa: F811
    SHOTS.mkdir(parents=True, exist_ok=True)
    page = login(browser, server)
    # the instructor page: no course yet; "Neue Klasse" leads to the new course's page
    page.goto(f"{server}/instructor")
    page.wait_for_selector("#courses")
    assert page.is_visible("#course-name")  # without a course the form is open
    page.fill("#course-name", "FA 24b")
    page.click("#course-new button[type=submit]")
    page.wait_for_url("**/courses/*")
    course = int(page.url.rsplit("/", 1)[1])
    page.wait_for_selector("#join-code")
    assert page.inner_text("#course-title") == "Klasse FA 24b"
    assert len(page.inner_text("#join-code")) == 8
    assert members_heading(page) == "Teilnehmer (0)"

    # the class list: two students, in this course
    csv = "Name;Passwort\n" + "".join(f"{n};{p}\n" for n, p in STUDENTS.items())
    page.set_input_files(
        "#course-class-file",
        files=[{"name": "klasse.csv", "mimeType": "text/csv", "buffer": csv.encode("utf-8-sig")}],
    )
    page.wait_for_selector("#course-passwords")
    assert "2 Schüler angelegt." in page.inner_text("#course-class-result")
    members = page.inner_text("#member-table")
    assert all(name in members for name in STUDENTS)
    page.wait_for_selector("#members h3:has-text('Teilnehmer (2)')")  # the heading counts the imported too

    # a practice assignment: exercise picked from the list, opening now, deadline in a week, late accepted
    page.fill("#a-title", "Geraden üben")
    page.check(f"#a-exercises input[value='{SLUG}']")
    assert page.is_checked("#a-hints") and not page.is_visible("#a-duration")
    page.select_option("#a-mode", "exam")  # an exam's defaults: exam conditions, a duration, no deadline
    assert (
        not page.is_checked("#a-hints")
        and not page.is_checked("#a-viz")
        and page.input_value("#a-max") == "1"
    )
    assert page.is_visible("#a-duration") and not page.is_visible("#a-deadline")
    page.select_option("#a-mode", "practice")
    assert page.is_checked("#a-hints") and page.input_value("#a-max") == "0"
    page.click("#assignment-form button[type=submit]")
    page.wait_for_url("**/courses/*?assignment=*")
    assignment = int(page.url.rsplit("=", 1)[1])
    page.wait_for_selector("#matrix")
    assert "Geraden üben" in page.inner_text("#assignment-table")

    # the students submit: Anna in time; then the deadline is moved into the past and Ben is late
    anna, ben = (token(server, n, p) for n, p in STUDENTS.items())
    call(
        server,
        "POST",
        "/submissions",
        anna,
        {"exercise": SLUG, "program": PROGRAMS["kurs-anna"], "assignment": assignment},
    )
    boss = token(server, TEACHER, PASSWORD)
    now = datetime.now(UTC)
    call(
        server,
        "PATCH",
        f"/assignments/{assignment}",
        boss,
        {
            "opens_at": (now - timedelta(hours=2)).isoformat(),
            "deadline": (now - timedelta(hours=1)).isoformat(),
        },
    )
    late = call(
        server,
        "POST",
        "/submissions",
        ben,
        {"exercise": SLUG, "program": PROGRAMS["kurs-ben"], "assignment": assignment},
    )
    page.reload()
    page.wait_for_selector("#matrix")
    rows = {r.locator("th").inner_text(): r for r in page.locator("#matrix tbody tr").all()}
    assert set(rows) == set(STUDENTS)
    results = call(server, "GET", f"/assignments/{assignment}/results", boss)["trainees"]
    scores = {r["username"]: r["results"][SLUG] for r in results}
    for name, row in rows.items():
        cell = row.locator("td").first
        assert f"{scores[name]['score']}/{scores[name]['max_score']}" in cell.inner_text()
        assert ("verspätet" in cell.inner_text()) is (name == "kurs-ben")
    assert page.get_attribute("#matrix-csv", "href") == f"/api/v1/assignments/{assignment}/results.csv"
    assert page.get_attribute("#matrix-sheets", "href") == f"/api/v1/assignments/{assignment}/sheets.pdf"

    # the insights: the decimal comma, both students, both in a G1 block; the lost geometry criterion
    insight = page.inner_text(f"#insight-{SLUG}")
    first = page.locator(f"#insight-{SLUG} .insight-diagnostics li").first.inner_text()
    assert first.startswith("2 von 2 · PAL-E010: Dezimalkomma") and "2 davon bei G1" in first, first
    assert "verloren das Kriterium »Geometrie«" in insight, insight
    for size, (width, height) in SIZES.items():
        page.set_viewport_size({"width": width, "height": height})
        fits(page)
        page.screenshot(path=str(SHOTS / f"course-{size}.png"), full_page=True)

    # a cell opens the submission above the matrix; its deviation colours once the 3D view is switched on
    page.set_viewport_size({"width": 1366, "height": 768})
    rows["kurs-ben"].locator("td a").first.click()
    page.wait_for_selector("#submission-view #submission-program", timeout=20000)
    assert f"Abgabe Nr. {late['id']} von kurs-ben" in page.inner_text("#submission-view")
    assert "X70,0" in page.inner_text("#submission-program")
    page.wait_for_selector("#submission-viz #viz-on", timeout=20000)  # off here: no graphics acceleration
    page.click("#submission-viz #viz-on")
    legend = page.wait_for_selector("#submission-viz #deviation", timeout=30000)
    assert "mm³" in legend.inner_text() or "Toleranzband" in legend.inner_text()
    fits(page)
    page.screenshot(path=str(SHOTS / "course-submission-laptop.png"))
    page.click("#submission-close")
    page.wait_for_selector("#matrix")
    assert not page.locator("#submission-view").count()

    # back on the instructor page: the course in the list
    page.goto(f"{server}/instructor")
    page.wait_for_selector("#course-list")
    assert page.get_attribute("#course-list a", "href") == f"/courses/{course}"
    assert "2 Schüler" in page.inner_text("#course-list")
    page.context.close()


def test_course_page_accessibility_and_strangers(server: str, browser: Any, teacher: str) -> None:  # noqa: F811
    boss = token(server, TEACHER, PASSWORD)
    course = call(server, "POST", "/courses", boss, {"name": "Zugänglich"})
    page = login(browser, server, bypass_csp=True)
    page.goto(f"{server}/courses/{course['id']}")
    page.wait_for_selector("#assignment-form")
    page.screenshot(
        path=str(SHOTS / "course-new-laptop.png"), full_page=True
    )  # no assignment yet: the form open
    fits(page)
    # axe is injected as a script of its own: the pages' policy forbids inline script
    page.add_script_tag(path=str(AXE))
    result = page.evaluate("axe.run(document, {resultTypes: ['violations']})")
    serious = [
        (v["id"], v["impact"], [n["target"] for n in v["nodes"]][:3])
        for v in result["violations"]
        if v["impact"] in ("serious", "critical")
    ]
    assert not serious, serious
    # in English: the page's own texts follow the switch
    page.click("#lang")
    page.wait_for_selector("#course-title >> text=Course Zugänglich")
    page.wait_for_selector("#assignment-form")
    assert "New assignment" in page.inner_text("#assignments") and "Join code" in page.inner_text("#members")
    fits(page)
    page.screenshot(path=str(SHOTS / "course-new-laptop-en.png"), full_page=True)
    page.context.close()
    # a student of no course sees no course page; nobody logged in is sent to the login
    stranger = browser.new_page()
    stranger.goto(f"{server}/courses/{course['id']}")
    assert "/login?next=/courses/" in stranger.url
    stranger.fill("input[name=username]", "schueler")
    stranger.fill("input[name=password]", PASSWORD)
    stranger.click("button[type=submit]")
    stranger.wait_for_url(f"**/courses/{course['id']}")
    stranger.wait_for_selector("#course p.error")
    assert "gibt es nicht" in stranger.inner_text("#course")
    stranger.close()


def test_member_count_and_exam_texts(server: str, browser: Any, teacher: str) -> None:  # noqa: F811
    """The heading's number of members follows adding by name and removing; the mode select reads "Übung" and
    "Prüfung", the exam's list row and heading "Prüfung · 45 min"; mode exam shows the note on what the exam means
    for the class's practice; nothing unfilled on the page, in German and English."""
    boss = token(server, TEACHER, PASSWORD)
    course = call(server, "POST", "/courses", boss, {"name": "FA 24c"})
    for name in ("kurs-clara", "kurs-dora"):
        call(server, "POST", "/users", boss, {"username": name, "password": PASSWORD, "role": "student"})
    page = login(browser, server, bypass_csp=True)
    page.on("dialog", lambda dialog: dialog.accept())  # "… aus der Klasse entfernen?"
    page.goto(f"{server}/courses/{course['id']}")
    page.wait_for_selector("#assignment-form")
    assert members_heading(page) == "Teilnehmer (0)" and page.is_visible(
        "text=Noch keine Schüler in dieser Klasse."
    )
    # adding by name: the heading counts them, the "no students" line goes
    for n, name in enumerate(("kurs-clara", "kurs-dora"), start=1):
        page.fill("#member-name", name)
        page.click("#member-add button[type=submit]")
        page.wait_for_selector(f"#members h3:has-text('Teilnehmer ({n})')")
        assert f"{name} ist jetzt in der Klasse." in page.inner_text("#member-note")
        assert name in page.inner_text("#member-table")
    assert not page.is_visible("text=Noch keine Schüler in dieser Klasse.")
    # removing (after the confirmation): one fewer, the row gone, no reload needed
    page.click("#member-table button[aria-label='kurs-clara aus der Klasse entfernen']")
    page.wait_for_selector("#members h3:has-text('Teilnehmer (1)')")
    assert "kurs-clara" not in page.inner_text("#member-table") and "kurs-dora" in page.inner_text(
        "#member-table"
    )

    # the form: the mode without a duration; an exam explains what it withholds until its release
    assert page.locator("#a-mode option").all_text_contents() == ["Übung", "Prüfung"]
    assert not page.is_visible("#a-exam-note")
    page.select_option("#a-mode", "exam")
    note = page.inner_text("#a-exam-note")
    assert "Solange die Ergebnisse dieser Prüfung nicht freigegeben sind" in note
    assert "weder Musterlösung noch Tipps" in note and "nicht bewertet" in note
    no_placeholders(page)
    fits(page)
    page.locator("#assignment-form").screenshot(path=str(SHOTS / "course-exam-form-laptop.png"))
    page.select_option("#a-mode", "practice")
    assert not page.is_visible("#a-exam-note")

    # an exam of 45 minutes from the form: its row and its heading say so
    page.select_option("#a-mode", "exam")
    page.fill("#a-title", "Klassenarbeit Geraden")
    page.check(f"#a-exercises input[value='{SLUG}']")
    page.fill("#a-duration", "45")
    page.click("#assignment-form button[type=submit]")
    page.wait_for_url("**/courses/*?assignment=*")
    page.wait_for_selector("#assignment-results")
    page.wait_for_selector("#members h3")
    assert page.inner_text("#assignment-times").startswith("Prüfung · 45 min · ")
    assert "Prüfung · 45 min · Ergebnisse noch verborgen" in page.inner_text("#assignment-table")
    assert members_heading(page) == "Teilnehmer (1)"
    no_placeholders(page)
    page.add_script_tag(path=str(AXE))
    result = page.evaluate("axe.run(document, {resultTypes: ['violations']})")
    serious = [
        (v["id"], v["impact"], [n["target"] for n in v["nodes"]][:3])
        for v in result["violations"]
        if v["impact"] in ("serious", "critical")
    ]
    assert not serious, serious
    for size, (width, height) in SIZES.items():
        page.set_viewport_size({"width": width, "height": height})
        fits(page)
        page.screenshot(path=str(SHOTS / f"course-exam-{size}.png"), full_page=True)

    # in English
    page.set_viewport_size({"width": 1366, "height": 768})
    page.click("#lang")
    page.wait_for_selector("#course-title >> text=Course FA 24c")
    page.wait_for_selector("#assignment-results")
    page.wait_for_selector("#members h3")
    assert page.inner_text("#assignment-times").startswith("Exam · 45 min · ")
    assert page.locator("#a-mode option").all_text_contents() == ["Practice", "Exam"]
    assert members_heading(page) == "Members (1)"
    page.click("#assignment-new summary")
    page.select_option("#a-mode", "exam")
    assert "neither the model solution nor hints" in page.inner_text("#a-exam-note")
    no_placeholders(page)
    page.click("#lang")  # back to German for the other tests of this browser (the choice is kept per context)
    page.context.close()
