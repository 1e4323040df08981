"""Grades a teacher can stand behind, in Chromium. An instructor makes a trainee (POST /users: the instructor manages
them), a course with them and a practice assignment of two exercises. The trainee submits the G2 exercise with G41
forgotten: the drawer shows the score, ◐ for the geometry (partial points) with its features folded away (1 of 4
kept), ✗ for the compensation criterion, and the cause's line link "Ursache: Zeile 5" puts the cursor on that
line; after a reload the drawer shows that result again (the bar with the score). The instructor opens the
submission from the course page's matrix, sees the grader's score, refuses a score above the maximum, sets 80 with
a comment; the matrix marks the cell "*" ("von der Lehrkraft geändert") and the sum (the exercise not handed in
counts 0) follows with its percentage. The trainee reads "Punktzahl von der Lehrkraft geändert: 80 statt … – …" in
the drawer after a reload (in English too), under "Meine Abgaben" and on the start page; restoring the automatic
grade takes the mark and the note away. The cutting data table names the spindle direction. Screenshots of the
drawer with the partial result and of the override form at 1366×768 and 768×1024 (PALTRAINER_SCREENSHOTS, else
tests/browser/screenshots/)."""

from __future__ import annotations

import os
import re
from datetime import UTC, datetime, timedelta
from pathlib import Path
from typing import Any

import httpx
import pytest
from browser_helpers import create_users, log_in
from test_practice_page import CHROMIUM, PASSWORD, ROOT, SERVER_DATA, server  # noqa: F401 (fixtures)
from test_viz_view import WIDER, wait_until

pytestmark = [
    pytest.mark.skipif(CHROMIUM is None, reason="Chromium not installed (.ci/run installs Debian's package)")
]

SHOTS = Path(os.environ.get("PALTRAINER_SCREENSHOTS") or Path(__file__).parent / "screenshots")
AXE = ROOT / "web" / "node_modules" / "axe-core" / "axe.min.js"
SIZES = {"laptop": (1366, 768), "tablet": (768, 1024)}
SLUG, OTHER = "pal-05-g2-kreisbogen", "pal-01-g1-gerade"
REFERENCE = (ROOT / "exercises" / "pal-mill" / f"{SLUG}.nc").read_text(encoding="utf-8")
MISTAKE = REFERENCE.replace(
    "N40 G41 G0 X70 Y84", "N40 G0 X70 Y84"
)  # the cutter radius compensation forgotten
TEACHER, TRAINEE = "noten-lehrer", "noten-azubi"
COMMENT = "Anfahrt im Unterricht besprochen, die Kontur selbst ist richtig gedacht."
ACTIVE_LINE = "document.querySelector('.cm-activeLine')?.textContent"


def percent(total: int, of: int) -> str:
    """As the page writes it: one decimal at most, a decimal comma, a no-break space before %."""
    return f"{round(100 * total / of, 1):g}".replace(".", ",") + "\u00a0%"


@pytest.fixture(scope="module")
def course(server: str) -> dict[str, Any]:  # noqa: F811
    env = {**os.environ, "PALTRAINER_DATA_DIR": SERVER_DATA[0]}
    create_users(env, [(TEACHER, "instructor")])
    with httpx.Client(base_url=f"{server}/api/v1", timeout=60) as c:
        r = c.post("/auth/token", data={"username": TEACHER, "password": PASSWORD})
        c.headers["Authorization"] = f"Bearer {r.json()['access_token']}"
        r = c.post("/users", json={"username": TRAINEE, "password": PASSWORD, "role": "student"})
        assert r.status_code == 201, r.text
        made = c.post("/courses", json={"name": "Noten 24"}).json()
        assert c.post(f"/courses/{made['id']}/members", json={"username": TRAINEE}).status_code == 201
        now = datetime.now(UTC)
        r = c.post(
            f"/courses/{made['id']}/assignments",
            json={
                "title": "Konturen",
                "exercises": [SLUG, OTHER],
                "mode": "practice",
                "opens_at": (now - timedelta(minutes=5)).isoformat(),
                "deadline": (now + timedelta(days=7)).isoformat(),
            },
        )
        assert r.status_code == 201, r.text
        return {"id": made["id"], "assignment": r.json()["id"]}


def login(browser: Any, server: str, user: str, size: str = "laptop") -> Any:  # noqa: F811
    width, height = SIZES[size]
    # axe-core is injected as a script of its own: the pages' policy forbids inline script
    page = browser.new_context(viewport={"width": width, "height": height}, bypass_csp=True).new_page()
    log_in(page, server, user)
    page.wait_for_url(
        lambda url: url in (f"{server}/", f"{server}/instructor")
    )  # instructors land on their page
    return page


def shot(page: Any, name: str, top: bool = True) -> None:
    SHOTS.mkdir(parents=True, exist_ok=True)
    if top:  # the drawer's result from its score on
        page.evaluate("document.querySelector('.drawer-body')?.scrollTo(0, 0)")
    assert page.evaluate("document.documentElement.scrollWidth <= innerWidth"), page.evaluate(WIDER)
    page.screenshot(path=str(SHOTS / f"grades-{name}.png"))


def accessible(page: Any, selector: str) -> None:
    """axe-core on the part of the page this test is about (`selector`)."""
    page.add_script_tag(path=str(AXE))
    result = page.evaluate(f"axe.run({{include: [['{selector}']]}}, {{resultTypes: ['violations']}})")
    serious = [
        (v["id"], v["impact"], [n["target"] for n in v["nodes"]][:3])
        for v in result["violations"]
        if v["impact"] in ("serious", "critical")
    ]
    assert not serious, serious


def open_exercise(page: Any, server: str) -> None:  # noqa: F811
    page.goto(f"{server}/exercises/{SLUG}")
    page.wait_for_selector(".cm-content", timeout=20000)


def matrix_cells(page: Any) -> list[str]:
    """The trainee's row of the course page's matrix: the two exercises and the sum."""
    return [
        str(c)
        for c in page.evaluate(f"""[...([...document.querySelectorAll('#matrix tbody tr')]
      .find((r) => r.querySelector('th').textContent === '{TRAINEE}')?.querySelectorAll('td') || [])]
      .map((c) => c.innerText.trim())""")
    ]


def test_a_partial_grade_the_teacher_changes(server: str, browser: Any, course: dict[str, Any]) -> None:  # noqa: F811
    page = login(browser, server, TRAINEE)
    open_exercise(page, server)
    # the cutting data: S, F and the spindle direction the task asks for
    page.click("#tab-tools")
    tools = page.inner_text("#panel-tools table")
    assert "Drehrichtung" in tools and "M3 (rechts)" in tools and "1200" in tools and "150" in tools, tools
    shot(page, "tools-laptop")
    page.click("#tab-task")

    # the program with G41 forgotten: the geometry partly kept, the cause named with its line
    page.click(".cm-content")
    page.keyboard.press("Control+a")
    page.keyboard.insert_text(MISTAKE)
    page.click("#submit")
    page.wait_for_selector("#result .score", timeout=30000)
    score = page.inner_text("#result .score")
    automatic = int(score.split()[0])
    assert score == f"{automatic} von 100 Punkten" and 0 < automatic < 100, score
    assert page.inner_text("#score-summary") == f"Ergebnis {automatic}/100"
    geometry = page.locator("#result .criteria > li").first
    assert geometry.get_attribute("class") == "partial"
    mark = geometry.locator(".mark").first
    assert mark.inner_text() == "◐" and mark.get_attribute("aria-label") == "teilweise erfüllt"
    text = geometry.inner_text()
    assert re.search(
        r"◐ \d+/50 – 1 von 4 Formelementen maßhaltig\. Ursache: Die Fräserradiuskorrektur fehlt", text
    ), text
    compensation = page.locator("#result .criteria > li.failed", has_text="G41/G42 fehlt")
    assert compensation.count() == 1 and compensation.locator(".mark").inner_text() == "✗"
    assert page.locator("#result .criteria > li.passed .mark").first.inner_text() == "✓"
    # the features are folded away, one line for them
    features = geometry.locator("details.features")
    assert features.locator("summary").inner_text() == "Formelemente: 1 von 4 maßhaltig"
    assert not page.is_visible("#result .feature-list")
    # the cause's line first, marked as such; it puts the cursor on the block where G41 belongs
    links = geometry.locator(":scope > .criterion-lines .line-link")
    assert [links.nth(i).inner_text() for i in range(links.count())] == [
        "Ursache: Zeile 5",
        "Zeile 7",
        "Zeile 8",
        "Zeile 9",
    ]
    cause = geometry.locator(".line-link.cause-line")
    cause.click()
    wait_until(page, f"{ACTIVE_LINE} === 'N40 G0 X70 Y84'")
    for size, (
        width,
        height,
    ) in SIZES.items():  # the drawer with the partial result (the features still folded)
        page.set_viewport_size({"width": width, "height": height})
        page.locator("#drawer").scroll_into_view_if_needed()
        shot(page, f"drawer-partial-{size}")
    page.set_viewport_size({"width": 1366, "height": 768})
    features.locator("summary").click()
    items = features.locator(".feature-list li")
    assert items.count() == 4 and features.locator(".feature-list li.kept").count() == 1
    assert items.nth(3).inner_text().startswith("✓ Boden Z-2")
    lost = items.nth(1).inner_text()
    assert lost.startswith("✗ Kontur Kreisbogen G2") and "mm daneben" in lost and "Zeile 8" in lost, lost
    items.nth(1).locator(".line-link").click()
    wait_until(page, f"{ACTIVE_LINE} === 'N70 G2 X56.4 Y10 I-20 J6.4'")
    features.locator("summary").scroll_into_view_if_needed()
    shot(page, "drawer-features-laptop", top=False)
    accessible(page, "#drawer")

    # a reload: the last result is in the drawer again, its links work
    page.reload()
    page.wait_for_selector("#result .score", timeout=20000)
    assert page.inner_text("#result .score") == score
    assert page.inner_text("#score-summary") == f"Ergebnis {automatic}/100"
    assert "Ihre letzte Abgabe vom" in page.inner_text("#result .result-when")
    assert page.locator("#result .criteria > li.partial").count() == 1
    page.wait_for_selector(".cm-content")
    page.click("#result .cause-line")
    wait_until(page, f"{ACTIVE_LINE} === 'N40 G0 X70 Y84'")
    page.context.close()

    # the instructor: the submission from the course page's matrix, the grader's score, the form
    teacher = login(browser, server, TEACHER)
    teacher.goto(f"{server}/courses/{course['id']}?assignment={course['assignment']}")
    teacher.wait_for_selector("#matrix")
    assert matrix_cells(teacher) == [f"{automatic}/100", "–", f"{automatic}/200 ({percent(automatic, 200)})"]
    assert "Summe: alle Aufgaben des Auftrags" in teacher.inner_text("#assignment-results")
    teacher.locator("#matrix tbody tr", has_text=TRAINEE).locator("td a").first.click()
    teacher.wait_for_selector("#override-form", timeout=20000)
    form = teacher.locator("#override-form")
    assert form.locator("h4").inner_text() == "Punktzahl ändern"
    assert f"Automatische Bewertung: {automatic} von 100 Punkten" in form.inner_text()
    assert teacher.input_value("#override-score") == str(automatic)
    assert not teacher.locator("#override-restore").count() and "Geändert von" not in form.inner_text()
    assert (
        teacher.locator("#submission-view .criteria > li.partial .cause-line").inner_text()
        == "Ursache: Zeile 5"
    )
    teacher.fill("#override-score", "101")  # more than the maximum: refused here, nothing sent
    teacher.click("#override-save")
    assert "ganze Zahl von 0 bis 100" in teacher.inner_text("#override-status.error")
    teacher.fill("#override-score", "80")
    teacher.fill("#override-comment", COMMENT)
    for size, (width, height) in SIZES.items():
        teacher.set_viewport_size({"width": width, "height": height})
        form.scroll_into_view_if_needed()
        shot(teacher, f"override-form-{size}")
    teacher.set_viewport_size({"width": 1366, "height": 768})
    teacher.click("#override-save")
    teacher.wait_for_selector("#override-status.ok")
    assert teacher.inner_text("#override-status") == "Gespeichert: 80 von 100 Punkten zählen."
    assert f"Geändert von {TEACHER} am" in form.inner_text()
    assert (
        teacher.input_value("#override-comment") == COMMENT
        and teacher.locator("#override-restore").count() == 1
    )
    assert "80 von 100 Punkten (von der Lehrkraft geändert)" in teacher.inner_text("#submission-score")
    # the matrix follows: the cell marked, the sum with it
    wait_until(teacher, "document.querySelector('#matrix tbody tr')?.innerText.includes('80/200')")
    assert matrix_cells(teacher) == ["80/100*", "–", f"80/200 ({percent(80, 200)})"]
    star = teacher.locator("#matrix .overridden-mark")
    assert star.get_attribute("title") == "von der Lehrkraft geändert"
    assert "* von der Lehrkraft geändert" in teacher.inner_text("#assignment-results")
    teacher.locator("#matrix").scroll_into_view_if_needed()
    shot(teacher, "matrix-laptop")
    form.scroll_into_view_if_needed()
    shot(teacher, "override-set-laptop")
    accessible(teacher, "#submission-view")

    # the trainee sees the teacher's word wherever the score stands
    note = f"Punktzahl von der Lehrkraft geändert: 80 statt {automatic} – {COMMENT}"
    page = login(browser, server, TRAINEE, "tablet")
    page.wait_for_selector(".assignment-items li", timeout=20000)
    item = page.locator(".assignment-items li", has_text="G2")
    assert "Ergebnis: 80 von 100 Punkten" in item.inner_text() and note in item.inner_text()
    shot(page, "home-tablet")
    open_exercise(page, server)
    page.wait_for_selector("#result .override-note", timeout=20000)
    assert page.inner_text("#result .score") == "80 von 100 Punkten"
    assert page.inner_text("#result .override-note") == note
    assert page.inner_text("#score-summary") == "Ergebnis 80/100"
    page.click("#tab-hints")
    page.wait_for_selector(".history-item .override-note")
    history = page.locator(".history-item").first
    assert "80 von 100 Punkten" in history.locator(".history-head").inner_text()
    assert history.locator(".override-note").inner_text() == note
    shot(page, "history-tablet")
    page.click("#lang")  # in English: the server's English note, the cause's line
    page.wait_for_selector("#result .override-note", timeout=20000)
    assert page.inner_text("#result .override-note").startswith(
        f"Score changed by the instructor: 80 instead of {automatic}"
    )
    assert page.inner_text("#result .cause-line") == "Cause: line 5"
    page.click("#lang")
    page.wait_for_selector("#tab-task >> text=Aufgabe")

    # back to the grader's score: mark and note are gone
    teacher.click("#override-restore")
    teacher.wait_for_selector("#override-status.ok:has-text('Die automatische Bewertung gilt wieder.')")
    assert not teacher.locator("#override-restore").count() and teacher.input_value("#override-score") == str(
        automatic
    )
    wait_until(teacher, f"document.querySelector('#matrix tbody tr')?.innerText.includes('{automatic}/200')")
    assert matrix_cells(teacher) == [f"{automatic}/100", "–", f"{automatic}/200 ({percent(automatic, 200)})"]
    assert not teacher.locator("#matrix .overridden-mark").count()
    page.reload()
    page.wait_for_selector("#result .score", timeout=20000)
    assert page.inner_text("#result .score") == score and not page.locator(".override-note").count()
    teacher.context.close()
    page.context.close()
