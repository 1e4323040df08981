"""A 2-minute mock exam in Chromium (issue 19 and the exam-integrity issue). The instructor (REST) makes a course and
an exam of 2 minutes; so that the run stays short the exam started 2 minutes minus LEFT seconds ago — the server's
real clock ends it, no test-only setting. Trainee 1 practised the exercise the day before (a practice draft with
the reference on the server, and a copy never sent from the browser, typed offline); joins with the code on the
home page, sees the exam there and no "Freies Üben" link, opens it: task, drawing, editor starting from the start
program (not the practice draft) and countdown, no messages panel, no 3D view, no hints, no free-practice link;
types, the draft is saved, the page is closed. Trainee 3 finds other exercises closed, submits by hand (asked
twice: one submission) and sees no score. Trainee 5 retakes: an earlier exam on the exercise ended and is held
(not released) with a draft of its own; the retake (the same exercise and another one) runs in the same window:
its page starts from the start program, saves without refusal into the retake (checked over REST with
?assignment=), and the retake's automatic submission is the retake's draft. An instructor's account that is a
student of the course sits the exam like a trainee (banner, no free practice, no hints). Trainee 2 keeps the page
open and sees, when the countdown ends, a read-only editor without "Abgeben", "wird abgegeben" and then that the
last draft was submitted. The server submits the drafts; the results stay hidden until the instructor releases
them, then trainee 1 sees score, criteria and the 3D view of the program, and after the instructor changed the
score the new one with the instructor's note (exam page and start page); the practice draft is still there. The
live socket is not opened during the exam, free practice is closed; with free practice allowed but no live
messages, its socket is refused (4403) and not tried again. Screenshots of home and exam page at 1366×768 and
768×1024 (PALTRAINER_SCREENSHOTS, else tests/browser/screenshots/), axe-core on both."""

from __future__ import annotations

import json
import os
import re
import time
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
SLUG = "pal-01-g1-gerade"
OTHER = "pal-05-g2-kreisbogen"  # the retake's second exercise
REFERENCE = (ROOT / "exercises" / "pal-mill" / f"{SLUG}.nc").read_text(encoding="utf-8")
TEACHER, FIRST, SECOND, THIRD, FOURTH = (
    "pruef-lehrer",
    "pruef-azubi",
    "pruef-azubi2",
    "pruef-azubi3",
    "pruef-azubi4",
)
RETAKER, COLLEAGUE = "pruef-azubi5", "pruef-meisterin"  # a retake; an instructor's account that sits the exam
# seconds of the 2-minute exam still to go when it is made: enough for the trainees to open and type on a loaded
# machine; when they are done the instructor moves the end near (an open page follows a changed end)
LEFT = 90
EARLIER_DRAFT = "N10 T1 TC1 M6 ; erste Pruefung\nN20 M30\n"  # the retaker's draft in the earlier, held exam
RETAKE_DRAFT = "N10 T1 TC1 M6 ; Wiederholung\nN20 G0 X0 Y0 Z2\nN30 M30\n"
EDITOR_TEXT = "[...document.querySelectorAll('.cm-content .cm-line')].map((l) => l.textContent).join('\\n')"
SAVED = "document.getElementById('save-state')?.textContent.includes('Entwurf gespeichert')"


def client(server: str, user: str) -> httpx.Client:  # noqa: F811
    c = httpx.Client(base_url=f"{server}/api/v1", timeout=60)
    r = c.post("/auth/token", data={"username": user, "password": PASSWORD})
    c.headers["Authorization"] = f"Bearer {r.json()['access_token']}"
    return c


@pytest.fixture(scope="module")
def teacher(server: str) -> httpx.Client:  # noqa: F811
    create_users(
        {**os.environ, "PALTRAINER_DATA_DIR": SERVER_DATA[0]},
        [(TEACHER, "instructor"), (COLLEAGUE, "instructor")],
    )
    c = client(server, TEACHER)
    for name in (
        FIRST,
        SECOND,
        THIRD,
        FOURTH,
        RETAKER,
    ):  # the instructor makes the trainees (quicker than the CLI)
        r = c.post("/users", json={"username": name, "password": PASSWORD, "role": "student"})
        assert r.status_code == 201, r.text
    return c


def enrol_as_platform_would(course_id: int, username: str) -> None:
    """A course membership as a student, written into the server's database as an LTI launch would make it."""
    from server import repository as repo
    from server.config import Settings
    from server.db import Database

    database = Database(Settings(data_dir=Path(SERVER_DATA[0])))
    try:
        with database.session() as db:
            user = repo.user_by_name(db, username)
            assert user is not None
            repo.add_member(db, course_id, user.id, "student")
    finally:
        database.engine.dispose()


def login(browser: Any, server: str, user: str, size: tuple[int, int] = (1366, 768)) -> Any:  # noqa: F811
    ctx = browser.new_context(
        viewport={"width": size[0], "height": size[1]}, bypass_csp=True
    )  # axe as a script
    page = ctx.new_page()
    log_in(page, server, user)
    page.wait_for_url(
        lambda url: url in (f"{server}/", f"{server}/instructor")
    )  # instructors land on their page
    return page


def shot(page: Any, name: str) -> None:
    SHOTS.mkdir(parents=True, exist_ok=True)
    assert page.evaluate("document.documentElement.scrollWidth <= innerWidth"), page.evaluate(WIDER)
    page.screenshot(path=str(SHOTS / f"exam-{name}.png"))


def accessible(page: Any) -> None:
    page.add_script_tag(path=str(AXE))
    result = page.evaluate("axe.run(document, {resultTypes: ['violations']})")
    serious = [
        (v["id"], v["impact"], [n["target"] for n in v["nodes"]][:3])
        for v in result["violations"]
        if v["impact"] in ("serious", "critical")
    ]
    assert not serious, serious


def type_program(page: Any, text: str) -> None:
    page.click(".cm-content")
    page.keyboard.press("Control+a")
    page.keyboard.insert_text(text)


def open_exam(page: Any, server: str, assignment: int | None = None) -> None:  # noqa: F811
    page.goto(f"{server}/")
    page.wait_for_selector(".assignment a", timeout=20000)
    page.click(f".assignment a[href^='/exercises/{SLUG}{f'?assignment={assignment}' if assignment else ''}']")
    page.wait_for_selector("#countdown", timeout=20000)
    page.wait_for_selector(".cm-content")


def practice_link_hidden(page: Any) -> None:
    """The header's "Freies Üben" is gone (the list of assignments is asked after the page has loaded)."""
    wait_until(page, "document.getElementById('nav-practice')?.hidden === true")
    assert not page.is_visible("#nav-practice") and not page.is_visible("a[href='/practice']")


def new_exam(
    teacher: httpx.Client, course: int, title: str, exercises: list[str], opens: datetime, minutes: int
) -> dict[str, Any]:
    r = teacher.post(
        f"/courses/{course}/assignments",
        json={
            "title": title,
            "exercises": exercises,
            "mode": "exam",
            "opens_at": opens.isoformat(),
            "duration_minutes": minutes,
        },
    )
    assert r.status_code == 201, r.text
    return dict(r.json())


def exam_status(trainee: httpx.Client, exam: int) -> str:
    return str(next(a["status"] for a in trainee.get("/me/assignments").json() if a["id"] == exam))


def test_two_minute_exam(server: str, browser: Any, teacher: httpx.Client) -> None:  # noqa: F811
    course = teacher.post("/courses", json={"name": "Prüfungsklasse"}).json()
    # the retaker's earlier exam on the exercise: it runs for a few seconds, gets a draft of its own, ends and
    # stays held (not released); the retake comes with the main exam below
    earlier_course = teacher.post("/courses", json={"name": "Prüfung Januar"}).json()
    retake_course = teacher.post("/courses", json={"name": "Wiederholer"}).json()
    for c in (earlier_course, retake_course):
        assert teacher.post(f"/courses/{c['id']}/members", json={"username": RETAKER}).status_code == 201
    earlier = new_exam(
        teacher, earlier_course["id"], "Prüfung Januar", [SLUG], datetime.now(UTC) - timedelta(seconds=52), 1
    )
    retaker = client(server, RETAKER)
    r = retaker.put(
        f"/exercises/{SLUG}/draft", params={"assignment": earlier["id"]}, json={"program": EARLIER_DRAFT}
    )
    assert r.status_code == 200 and r.json()["assignment"] == earlier["id"], r.text

    # trainee 1 joins with the code on the home page; trainee 2 by the same code over the API's form too
    first = login(browser, server, FIRST)
    first.wait_for_selector("form#join")
    assert "Prüfungsklasse" not in first.inner_text("#home")  # (the instructor's "Meine Klasse" only)
    first.fill("#join-code", "FALSCH")
    first.click("form#join button[type=submit]")
    first.wait_for_selector("#join-message.error")
    first.fill("#join-code", course["join_code"])
    first.click("form#join button[type=submit]")
    first.wait_for_selector("#join-message.ok")
    assert "Prüfungsklasse" in first.inner_text("#join-message") and "Prüfungsklasse" in first.inner_text(
        ".my-courses"
    )
    # the day before, trainee 1 practised the exercise: the reference as the practice draft on the server, and a
    # line typed offline that only this browser keeps (never sent)
    trainee1 = client(server, FIRST)
    r = trainee1.put(f"/exercises/{SLUG}/draft", json={"program": REFERENCE})
    assert r.status_code == 200 and r.json()["assignment"] is None, r.text
    practice = first.context.new_page()
    practice.goto(f"{server}/exercises/{SLUG}")
    practice.wait_for_selector(".cm-content", timeout=20000)
    wait_until(practice, f"{EDITOR_TEXT}.startsWith({json.dumps(REFERENCE.splitlines()[0])})")
    first.context.set_offline(True)
    practice.click(".cm-content")
    practice.keyboard.press("Control+End")
    practice.keyboard.type("; geuebt")
    local_key = f"paltrainer-draft:{FIRST}:{SLUG}"
    wait_until(practice, f"JSON.parse(localStorage.getItem('{local_key}') || 'null')?.synced === false")
    practice.close()
    first.context.set_offline(False)

    second = login(browser, server, SECOND, (768, 1024))
    second.fill("#join-code", course["join_code"])
    second.click("form#join button[type=submit]")
    second.wait_for_selector("#join-message.ok")
    third = login(browser, server, THIRD)
    third.fill("#join-code", course["join_code"])
    third.click("form#join button[type=submit]")
    third.wait_for_selector("#join-message.ok")
    fifth = login(browser, server, RETAKER)
    # an instructor's account that is a student of the class sits its exam (its role in the course decides); a
    # learning platform's launch as a Learner makes such a membership (nobody may enrol an instructor by hand)
    enrol_as_platform_would(course["id"], COLLEAGUE)
    colleague = login(browser, server, COLLEAGUE)
    start = teacher.get(f"/exercises/{SLUG}").json().get("start_program") or ""
    deadline = time.monotonic() + 90
    while exam_status(retaker, earlier["id"]) in ("upcoming", "running"):  # the earlier exam is over
        assert time.monotonic() < deadline, "the earlier exam did not end"
        time.sleep(0.5)

    opens = datetime.now(UTC) - timedelta(seconds=120 - LEFT)
    exam = new_exam(teacher, course["id"], "Probeprüfung G1", [SLUG], opens, 2)
    retake = new_exam(teacher, retake_course["id"], "Wiederholungsprüfung", [SLUG, OTHER], opens, 2)
    end = time.monotonic() + LEFT

    # free practice is closed during the exam: a notice with the way to the exam, no editor, no live socket
    sockets: list[Any] = []
    first.on("websocket", lambda ws: sockets.append(ws))
    first.goto(f"{server}/practice")
    first.wait_for_selector(".exam-notice")
    assert (
        "freies Üben gesperrt" in first.inner_text(".exam-notice")
        and first.locator(".cm-content").count() == 0
    )

    # the home page: the running exam, its times, mode and status, a link into its exercise; no free practice
    first.goto(f"{server}/")
    first.wait_for_selector(".assignment a")
    home = first.inner_text("#home")
    assert "Prüfung läuft" in home and "Probeprüfung G1" in home and "Prüfung · 2 min" in home
    assert "Läuft" in home and "noch nicht abgegeben" in home and "Ende" in home
    practice_link_hidden(first)
    shot(first, "home-laptop")
    accessible(first)

    open_exam(first, server)
    assert re.search(r"Restzeit 0[01]:[0-5]\d", first.inner_text("#countdown")), first.inner_text(
        "#countdown"
    )
    assert "Probeprüfung G1" in first.inner_text("#exam-bar")
    assert first.is_visible("figure.drawing img")  # the task with its drawing
    # the exam starts from the start program: neither the server's practice draft nor the browser's copy
    assert first.evaluate(EDITOR_TEXT) == start.rstrip("\n"), first.evaluate(EDITOR_TEXT)
    # exam conditions: no messages panel, no 3D view, no hints, no free practice, no live socket, no code help
    assert not first.is_visible("#diagnostics") and not first.is_visible(".viz-pane")
    assert (
        first.locator("#tab-hints").count() == 0
        and first.locator("[role=tab]", has_text="Tipps").count() == 0
    )
    practice_link_hidden(first)
    assert first.locator(".cm-lint-marker, .cm-gutter-lint").count() == 0
    assert first.locator("#file-open").count() == 0
    type_program(first, REFERENCE)
    wait_until(first, SAVED)
    first.wait_for_timeout(500)
    assert not [s for s in sockets if s.url.endswith("/api/v1/live")]
    wait_until(first, "document.querySelector('figure.drawing img')?.naturalWidth > 100")
    shot(first, "page-laptop")
    accessible(first)
    # in the browser the exam's draft has a key of its own; the practice copy is untouched
    stored = first.evaluate(f"""[localStorage.getItem('{local_key}'),
      localStorage.getItem('{local_key}:a{exam["id"]}')]""")
    assert "; geuebt" in json.loads(stored[0])["program"] and json.loads(stored[1])["program"] == REFERENCE
    first.context.close()  # trainee 1 closes the browser; the draft is on the server (the exam's)
    assert (
        trainee1.get(f"/exercises/{SLUG}/draft", params={"assignment": exam["id"]}).json()["program"]
        == REFERENCE
    )

    open_exam(second, server)
    type_program(second, "N10 T1 TC1 M6\nN20 G0 X0 Y0 Z2\nN30 M30\n")
    wait_until(second, SAVED)
    shot(second, "page-tablet")
    accessible(second)
    # trainee 3: another exercise is closed while the exam runs; in the exam one submission, asked twice
    third.goto(f"{server}/exercises/{OTHER}")
    third.wait_for_selector(".exam-notice")
    assert "können Sie nur deren Aufgaben bearbeiten" in third.inner_text(".exam-notice")
    assert third.locator(".cm-content").count() == 0
    third.click(".exam-notice a")
    third.wait_for_selector("#countdown")
    third.wait_for_selector(".cm-content")
    type_program(third, REFERENCE)
    third.click("#submit")
    assert third.inner_text("#submit") == "Endgültig abgeben?"
    third.click("#submit")
    third.wait_for_selector("#result p:has-text('Abgegeben')", timeout=20000)
    assert "sobald es freigegeben ist" in third.inner_text("#result") and third.is_disabled("#submit")
    assert third.locator("#result .score").count() == 0  # no score during the exam
    third.context.close()

    # trainee 5 retakes: the held earlier exam on the home page, the retake running; its page starts from the
    # start program (not the earlier exam's draft) and saves into the retake without a refusal
    open_exam(fifth, server, retake["id"])
    assert "Wiederholungsprüfung" in fifth.inner_text("#exam-bar")
    assert fifth.evaluate(EDITOR_TEXT) == start.rstrip("\n"), fifth.evaluate(EDITOR_TEXT)
    type_program(fifth, RETAKE_DRAFT)
    wait_until(fifth, SAVED)
    assert "Nicht gespeichert" not in fifth.inner_text("#exam-bar")
    mine = retaker.get(f"/exercises/{SLUG}/draft", params={"assignment": retake["id"]}).json()
    assert mine["assignment"] == retake["id"] and mine["program"] == RETAKE_DRAFT, mine
    r = retaker.get(f"/exercises/{SLUG}/draft", params={"assignment": earlier["id"]})
    assert r.status_code == 403 and r.json()["error"]["code"] == "EXAM_ELSEWHERE", r.text  # the retake's time
    shot(fifth, "retake-laptop")
    fifth.context.close()

    # the instructor's account that is a student of the class: the exam as for any trainee
    colleague.goto(f"{server}/")
    colleague.wait_for_selector(".exam-banner")
    assert "Probeprüfung G1" in colleague.inner_text(".exam-banner")
    practice_link_hidden(colleague)
    open_exam(colleague, server)
    assert colleague.locator("#tab-hints").count() == 0 and not colleague.is_visible(".viz-pane")
    practice_link_hidden(colleague)
    colleague.context.close()

    # the instructor lets both exams end in a few seconds (as one extends an exam after a disruption): the open
    # page follows the new end (it looks every 15 s)
    soon = datetime.now(UTC) - timedelta(seconds=120 - 6)
    for a in (exam, retake):
        r = teacher.patch(f"/assignments/{a['id']}", json={"opens_at": soon.isoformat()})
        assert r.status_code == 200, r.text
    end = time.monotonic() + 6
    wait_until(
        second, "/Restzeit 00:0\\d/.test(document.getElementById('countdown').textContent)", timeout=40
    )

    # trainee 2 keeps the page open: when the countdown ends the editor is read only, "Abgeben" is gone, the
    # page says the exam is being submitted, then what the server submitted
    wait_until(
        second,
        "document.getElementById('exam-message')?.textContent.includes('Ihre Prüfung wird abgegeben')",
        timeout=max(5.0, end - time.monotonic() + 15),
    )
    assert not second.is_visible("#submit")
    wait_until(second, "document.getElementById('exam-message').dataset.confirmed === 'true'", timeout=120)
    message = second.inner_text("#exam-message")
    assert "Entwurf wurde abgegeben" in message and "sobald es freigegeben ist" in message, message
    assert not second.is_visible("#submit") and second.locator("#file-reset").count() == 0
    second.click(".cm-content")
    second.keyboard.type("XYZ")
    assert "XYZ" not in second.inner_text(".cm-content")
    shot(second, "over-tablet")
    # the server refuses work for the exam after its end, with its message; the draft can still be read
    r = second.evaluate(f"""fetch('/api/v1/exercises/{SLUG}/draft?assignment={exam["id"]}', {{method: 'PUT',
      credentials: 'same-origin', headers: {{'Content-Type': 'application/json'}},
      body: JSON.stringify({{program: 'N10 M30'}})}}).then(async (r) => [r.status, (await r.json()).error.message])""")
    assert r[0] == 403 and "Prüfungszeit ist abgelaufen" in r[1]
    second.goto(f"{server}/")
    second.wait_for_selector("details.assignments-done")  # the exam is done: under "Abgeschlossene Aufträge"
    second.click("details.assignments-done summary")
    assert "automatisch abgegeben – Ergebnis noch nicht freigegeben" in second.inner_text("#home")
    shot(second, "home-tablet")
    accessible(second)

    # the server submitted both drafts; scores stay with the instructor
    results = teacher.get(f"/assignments/{exam['id']}/results").json()
    rows = {row["username"]: row["results"][SLUG] for row in results["trainees"] if SLUG in row["results"]}
    assert rows[FIRST]["auto"] is True and rows[SECOND]["auto"] is True
    assert rows[FIRST]["score"] == rows[FIRST]["max_score"] and rows[FIRST]["score"] > (
        rows[SECOND]["score"] or 0
    )
    assert rows[THIRD]["auto"] is False and rows[THIRD]["score"] == rows[THIRD]["max_score"]
    # the retake's automatic submission is the retake's draft, not the earlier exam's
    deadline = time.monotonic() + 120
    while exam_status(retaker, retake["id"]) == "submitting":
        assert time.monotonic() < deadline, "the retake was not submitted"
        time.sleep(1)
    results = teacher.get(f"/assignments/{retake['id']}/results").json()
    cell = {row["username"]: row["results"] for row in results["trainees"]}[RETAKER][SLUG]
    assert cell["auto"] is True
    assert teacher.get(f"/submissions/{cell['submission']}").json()["program"] == RETAKE_DRAFT
    held = retaker.get(f"/exercises/{SLUG}/draft", params={"assignment": earlier["id"]}).json()
    assert held["program"] == EARLIER_DRAFT, held  # the earlier exam's draft stays as it was
    results = teacher.get(f"/assignments/{earlier['id']}/results").json()
    cell = {row["username"]: row["results"] for row in results["trainees"]}[RETAKER][SLUG]
    assert teacher.get(f"/submissions/{cell['submission']}").json()["program"] == EARLIER_DRAFT

    # trainee 1 comes back before the release: time over, submitted, no score
    first = login(browser, server, FIRST)
    first.goto(f"{server}/exercises/{SLUG}?assignment={exam['id']}")
    first.wait_for_selector("#exam-message:not(:empty)")
    wait_until(first, "document.getElementById('exam-message').dataset.confirmed === 'true'")
    message = first.inner_text("#exam-message")
    assert "Prüfungszeit ist abgelaufen" in message and "Entwurf wurde abgegeben" in message
    assert "sobald es freigegeben ist" in message and first.locator("#result .score").count() == 0
    assert not first.is_visible("#submit")
    # the practice draft outlived the exam (with or without the offline line: the browser may have sent it as
    # the practice page closed)
    assert trainee1.get(f"/exercises/{SLUG}/draft").json()["program"].startswith(REFERENCE)

    assert teacher.post(f"/assignments/{exam['id']}/release").status_code == 200
    first.goto(f"{server}/exercises/{SLUG}?assignment={exam['id']}")
    first.wait_for_selector("#result .score", timeout=20000)
    max_score = rows[FIRST]["max_score"]
    assert first.inner_text("#result .score") == f"{max_score} von {max_score} Punkten"
    assert first.locator("#result .criteria li.passed").count() >= 1
    assert "Ergebnis der Prüfung" in first.inner_text("#exam-message")
    assert first.inner_text(".cm-content").startswith(REFERENCE.splitlines()[0])
    assert first.is_visible(".viz-pane")  # the simulator's view of what was written
    wait_until(
        first,
        "document.getElementById('viz-picture')?.naturalWidth > 100 "
        "|| document.getElementById('viz-frame')?.src.length > 0",
        timeout=30,
    )
    shot(first, "result-laptop")
    first.goto(f"{server}/")
    first.wait_for_selector("details.assignments-done")
    first.click("details.assignments-done summary")
    assert f"Ergebnis: {max_score} von {max_score} Punkten" in first.inner_text("#home")
    # the teacher's last word on the released result: the score and the note on the exam page and the start page
    lower, comment = max_score - 10, "Der Programmkopf fehlt."
    r = teacher.put(
        f"/submissions/{rows[FIRST]['submission']}/override", json={"score": lower, "comment": comment}
    )
    assert r.status_code == 200, r.text
    note = f"Punktzahl von der Lehrkraft geändert: {lower} statt {max_score} – {comment}"
    first.goto(f"{server}/exercises/{SLUG}?assignment={exam['id']}")
    first.wait_for_selector("#result .override-note", timeout=20000)
    assert first.inner_text("#result .score") == f"{lower} von {max_score} Punkten"
    assert first.inner_text("#result .override-note") == note
    first.goto(f"{server}/")
    first.wait_for_selector("details.assignments-done")
    first.click("details.assignments-done summary")
    assert f"Ergebnis: {lower} von {max_score} Punkten" in first.inner_text(
        "#home"
    ) and note in first.inner_text("#home")
    first.context.close()
    second.context.close()


def test_refused_live_socket_is_not_tried_again(server: str, browser: Any, teacher: httpx.Client) -> None:  # noqa: F811
    """An exam that allows free practice but no live messages: the practice page's socket is refused with 4403
    EXAM_RUNNING once; the page says so in German and does not connect again (it used to, every second). Another
    exercise's page keeps "Freies Üben" but follows the exam's settings: no Tipps tab, no 3D view."""
    course = teacher.post("/courses", json={"name": "Übungsklasse"}).json()
    r = teacher.post(f"/courses/{course['id']}/members", json={"username": FOURTH})
    assert r.status_code == 201, r.text
    r = teacher.post(
        f"/courses/{course['id']}/assignments",
        json={
            "title": "Prüfung mit freiem Üben",
            "exercises": [SLUG],
            "mode": "exam",
            "duration_minutes": 90,
            "opens_at": (datetime.now(UTC) - timedelta(minutes=1)).isoformat(),
            "settings": {"free_practice": True},
        },
    )
    assert r.status_code == 201, r.text
    page = login(browser, server, FOURTH)
    sockets: list[Any] = []
    page.on("websocket", lambda ws: sockets.append(ws))
    page.goto(f"{server}/practice")
    wait_until(page, "document.getElementById('status-line')?.textContent.includes('Während der Prüfung')")
    assert "keine Live-Prüfung" in page.inner_text("#diagnostics .diag-notice")
    time.sleep(3)  # the old client connected again every second
    assert len([s for s in sockets if s.url.endswith("/api/v1/live")]) == 1
    # another exercise in free practice: the exam's settings still hold there (no Tipps tab, no 3D view)
    page.goto(f"{server}/exercises/{OTHER}")
    page.wait_for_selector(".cm-content", timeout=20000)
    page.wait_for_selector("#tab-tools")
    assert page.locator("#tab-hints").count() == 0 and not page.is_visible(".viz-pane")
    assert page.is_visible("#nav-practice") and page.locator("#countdown").count() == 0
    assert teacher.delete(f"/courses/{course['id']}").status_code == 204
    page.context.close()


def test_live_check_error_is_shown_in_german(server: str, browser: Any) -> None:  # noqa: F811
    """The live socket's error messages reach the messages panel and the status line (not dropped)."""
    page = browser.new_page()
    page.goto(f"{server}/practice")
    page.wait_for_selector(".diag-none", timeout=20000)
    type_program(page, f"N10 M30 ; {'x' * 200_000}\n")  # over 200 000 characters
    wait_until(
        page, "document.getElementById('status-line')?.textContent.includes('PROGRAM_TOO_LARGE')", timeout=30
    )
    assert "Das Programm ist zu lang" in page.inner_text("#status-line")
    assert "error" in (page.get_attribute("#status-line", "class") or "")
    assert "Das Programm ist zu lang" in page.inner_text("#diagnostics .diag-notice")
    page.close()
