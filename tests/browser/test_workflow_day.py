"""A working day in Chromium: a trainee (managed by an instructor) types on an exercise, reloads (the text is
back), submits twice, sees both under "Meine Abgaben" and loads the first one into the editor again; the exercise
list shows the PAL milling set in its order under the dialect's name, with the best score. The instructor sees
both submissions in the results table, opens one read-only with its criteria, and downloads the CSV, which
parses with `;` and a BOM."""

from __future__ import annotations

import csv
import io
import os
import subprocess
import sys
import time
from pathlib import Path

import pytest
from browser_helpers import log_in
from test_practice_page import CHROMIUM, PASSWORD, ROOT, SERVER_DATA, server  # noqa: F401 (fixtures)
from test_viz_view import wait_until

pytestmark = [
    pytest.mark.skipif(CHROMIUM is None, reason="Chromium not installed (.ci/run installs Debian's package)")
]

SLUG = "pal-01-g1-gerade"
REFERENCE = (ROOT / "exercises" / "pal-mill" / f"{SLUG}.nc").read_text(encoding="utf-8")
TEACHER, TRAINEE = "tag-lehrer", "tag-azubi"
SHOTS = Path(os.environ.get("PALTRAINER_SCREENSHOTS") or Path(__file__).parent / "screenshots")


def shot(page: object, name: str, full_page: bool = False) -> None:
    SHOTS.mkdir(parents=True, exist_ok=True)
    page.screenshot(path=str(SHOTS / f"day-{name}.png"), full_page=full_page)  # type: ignore[attr-defined]


def admin(*args: str) -> None:
    env = {**os.environ, "PALTRAINER_DATA_DIR": SERVER_DATA[0]}
    subprocess.run(
        [sys.executable, "-m", "core.cli", "admin", *args], cwd=ROOT, env=env, check=True, capture_output=True
    )


@pytest.fixture(scope="module")
def people(server: str) -> tuple[str, str]:  # noqa: F811
    admin("create-user", TEACHER, "--role", "instructor", "--password", PASSWORD)
    admin("create-user", TRAINEE, "--role", "student", "--password", PASSWORD, "--instructor", TEACHER)
    return TEACHER, TRAINEE


def login(browser: object, server: str, user: str, password: str = PASSWORD) -> tuple[object, object]:  # noqa: F811
    ctx = browser.new_context(viewport={"width": 1366, "height": 768}, accept_downloads=True)  # type: ignore[attr-defined]
    page = ctx.new_page()
    log_in(page, server, user, password)
    page.wait_for_url(
        lambda url: url in (f"{server}/", f"{server}/instructor")
    )  # instructors land on their page
    return ctx, page


def editor_text(page: object) -> str:
    return str(
        page.evaluate(  # type: ignore[attr-defined]
            "[...document.querySelectorAll('.cm-content .cm-line')].map((l) => l.textContent).join('\\n')"
        )
    )


def show_tab(page: object, tab: str) -> None:
    page.click(f"#{tab}")  # type: ignore[attr-defined]


def submit(page: object) -> str:
    page.click("#submit")  # type: ignore[attr-defined]
    page.wait_for_selector("#result .score", timeout=30000)  # type: ignore[attr-defined]
    score = str(page.inner_text("#result .score"))  # type: ignore[attr-defined]
    page.evaluate("document.querySelector('#result').replaceChildren()")  # type: ignore[attr-defined]
    return score


def test_a_day(server: str, browser: object, people: tuple[str, str], tmp_path: Path) -> None:  # noqa: F811
    ctx, page = login(browser, server, TRAINEE)
    # the list: PAL Fräsen first, its set in order (G1 … G66, then Ergänzen, then Fehlersuche), nothing started
    page.wait_for_selector("ul.exercises a", timeout=20000)
    assert page.inner_text("h3.dialect-title >> nth=0") == "PAL Fräsen"
    first_list = page.locator("ul.exercises").first.inner_text()
    titles = [line for line in first_list.splitlines() if line.strip()]
    assert titles[0].startswith("G1 – Kontur aus zwei Geraden"), titles
    g66 = next(i for i, line in enumerate(titles) if "G66" in line)
    fix = next(i for i, line in enumerate(titles) if "Fehler finden" in line)
    complete = next(i for i, line in enumerate(titles) if "Programm ergänzen" in line)
    assert g66 < complete < fix
    assert "nicht begonnen" in titles[0]

    # types, reloads: the text is back
    page.goto(f"{server}/exercises/{SLUG}")
    page.wait_for_selector(".cm-content", timeout=20000)
    page.click(".cm-content")
    page.keyboard.type("; erster Versuch")
    page.keyboard.press("Escape")
    page.keyboard.press("Enter")
    page.keyboard.type("N10 T1 TC1 M6")
    page.keyboard.press("Escape")
    time.sleep(2.5)
    page.reload()
    page.wait_for_selector(".cm-content", timeout=20000)
    wait_until(page, "document.querySelector('.cm-content').textContent.includes('erster Versuch')")
    first_program = editor_text(page)

    # submits twice: the typed start, then the whole program (opened from a file)
    first_score = submit(page)
    assert "von 100 Punkten" in first_score and not first_score.startswith("100 ")
    page.set_input_files(
        "#open-file", files=[{"name": "loesung.nc", "mimeType": "text/plain", "buffer": REFERENCE.encode()}]
    )
    wait_until(page, "document.querySelector('.cm-content').textContent.includes('N90 G0 X250')")
    assert submit(page) == "100 von 100 Punkten"

    # "Meine Abgaben": both, newest first; the first one back into the editor
    show_tab(page, "tab-hints")
    page.wait_for_selector(".history-item >> nth=1", timeout=10000)
    items = page.locator(".history-item")
    assert items.count() == 2
    panel = page.inner_text("#panel-hints")
    assert "Zu dieser Aufgabe gibt es keine Tipps." in panel and "null" not in panel
    assert "100 von 100 Punkten" in items.nth(0).inner_text()
    assert first_score in items.nth(1).inner_text()
    shot(page, "history")
    items.nth(1).locator(".history-load").click()
    wait_until(page, "!document.querySelector('.cm-content').textContent.includes('N90 G0 X250')")
    assert editor_text(page) == first_program

    # the list now shows the best score
    page.goto(f"{server}/")
    page.wait_for_selector("ul.exercises a", timeout=20000)
    assert "beste Abgabe 100/100" in page.locator("ul.exercises li").first.inner_text()
    shot(page, "list")
    # in English: the dialect's name and the titles follow the switch
    page.click("#lang")
    page.wait_for_selector("h3.dialect-title >> text=PAL milling", timeout=20000)
    assert page.locator("ul.exercises a").first.inner_text() == "G1 – contour of two straight lines"
    assert "best 100/100" in page.locator("ul.exercises li").first.inner_text()
    ctx.close()  # type: ignore[attr-defined]

    # the instructor: both submissions in the results table (the best one linked), the CSV for Excel
    ctx, page = login(browser, server, TEACHER)
    page.goto(f"{server}/instructor")
    page.wait_for_selector("#results-table", timeout=20000)
    row = page.locator("#results-table tbody tr", has_text=TRAINEE)
    assert row.count() == 1
    assert "100/100 (2)" in row.inner_text()
    with page.expect_download() as info:
        page.click("#results-csv")
    data = Path(info.value.path()).read_bytes()
    assert data.startswith(b"\xef\xbb\xbf")
    rows = list(csv.reader(io.StringIO(data.decode("utf-8-sig")), delimiter=";"))
    assert rows[0][:3] == ["Benutzer", "Lehrkraft", "Aufgabe"]
    mine = next(r for r in rows if r[0] == TRAINEE and r[2] == SLUG)
    assert mine[1] == TEACHER and mine[4] == "100" and mine[7] == "2"

    # the first submission opened read-only: the typed program, its messages and criteria with line links
    ids = sorted(
        int(a.inner_text())
        for a in page.locator("#submission-list tbody tr", has_text=TRAINEE).locator("td:first-child a").all()
    )
    assert len(ids) == 2
    page.click(f"#submission-list a[href='/instructor?submission={ids[0]}']")
    page.wait_for_selector("#submission-view #submission-program", timeout=20000)
    view = page.inner_text("#submission-view")
    assert f"Abgabe Nr. {ids[0]} von {TRAINEE}" in view and "erster Versuch" in page.inner_text(
        "#submission-program"
    )
    assert first_score in view and "null" not in view
    links = page.locator("#submission-view .criteria .line-link, #submission-diagnostics .line-link")
    assert links.count() >= 1
    links.first.click()
    assert page.locator("#submission-program li.marked").count() == 1
    # the part after the program (3D view, or its picture where the browser draws 3D without acceleration)
    wait_until(
        page,
        "document.querySelector('#submission-viz #viz-picture')?.naturalWidth > 100"
        " || document.querySelector('#submission-viz #viz-frame')?.src",
        timeout=30,
    )
    shot(page, "submission", full_page=True)
    # the best one from the results table: full marks
    page.locator("#results-table tbody tr", has_text=TRAINEE).locator("a").first.click()
    page.wait_for_selector("#submission-view #submission-program", timeout=20000)
    assert f"Abgabe Nr. {ids[1]}" in page.inner_text("#submission-view")
    assert "100 von 100 Punkten" in page.inner_text("#submission-view")

    # a class list: the generated password shown once, and it works
    page.set_input_files(
        "#class-file",
        files=[
            {
                "name": "klasse.csv",
                "mimeType": "text/csv",
                "buffer": "Name;Passwort\nklasse-anna\nklasse-ben;ein Passwort mit Länge\n".encode(
                    "utf-8-sig"
                ),
            }
        ],
    )
    page.wait_for_selector("#class-passwords", timeout=20000)
    cells = [c.inner_text() for c in page.locator("#class-passwords tbody td").all()]
    shot(page, "instructor")
    assert (
        cells[0] == "klasse-anna" and len(cells[1]) == 12 and cells[2:] == ["klasse-ben", "(aus der Liste)"]
    )
    page.reload()
    page.wait_for_selector("#results-table", timeout=20000)
    assert page.locator("#results-table tbody tr", has_text="klasse-anna").count() == 1
    ctx.close()  # type: ignore[attr-defined]
    ctx, page = login(browser, server, "klasse-anna", cells[1])  # logs in: back on the exercise list
    ctx.close()  # type: ignore[attr-defined]


def test_hints_one_at_a_time_and_the_solution_after_a_submission(server: str, browser: object) -> None:  # noqa: F811
    slug = "fehler-01-kreisendpunkt"
    reference = (ROOT / "exercises" / "pal-mill-fehler" / f"{slug}.nc").read_text(encoding="utf-8")
    ctx, page = login(browser, server, "schueler")
    page.goto(f"{server}/exercises/{slug}")
    page.wait_for_selector(".cm-content", timeout=20000)
    show_tab(page, "tab-hints")
    page.wait_for_selector("#hint-next")
    assert page.locator("#hint-list li").count() == 0
    assert page.inner_text("#hint-next") == "Tipp anzeigen (1 von 1)"
    page.click("#hint-next")
    page.wait_for_selector("#hint-list li")
    assert "Mittelpunkt des Kreisbogens" in page.inner_text("#hint-list")
    assert not page.locator("#hint-next").is_visible()  # that was the only one
    page.reload()
    page.wait_for_selector(".cm-content", timeout=20000)  # (the page's script is running: its tabs answer)
    show_tab(page, "tab-hints")
    page.wait_for_selector("#hint-list li")  # still shown after a reload
    # the solution: after the first submission (the server's reason in German until then)
    page.click("#solution-show")
    wait_until(
        page, "document.getElementById('solution-message').textContent.includes('nach der ersten Abgabe')"
    )
    assert not page.locator("#solution-dialog").count()
    submit(page)
    page.click("#solution-show")
    page.wait_for_selector("#solution-dialog", timeout=10000)
    shown = page.inner_text("#solution-program")
    # both parts side by side, as the server renders them
    for part in ("#solution-part-mine", "#solution-part-reference"):
        wait_until(page, f"document.querySelector('{part}').naturalWidth > 0")
    shot(page, "solution")
    assert all(line in shown for line in reference.splitlines() if line.strip())
    page.click("#solution-close")
    page.wait_for_selector("#solution-dialog", state="detached", timeout=5000)
    ctx.close()  # type: ignore[attr-defined]
