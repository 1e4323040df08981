"""Every page runs without an uncaught error or a Content-Security-Policy violation (issue 28, point 13), in
Chromium under the site's own policy: the start page, the exercise list, an exercise page with the 3D view
switched on (viser's client in its frame, which once evaluated strings as code: server/viz.py CLIENT_PATCHES),
free practice with 3D on, the instructor page, a course page and the login page.

Collected on every page, in every frame: `pageerror` events, uncaught errors and unhandled rejections
(window listeners added before any script of the page runs), `securitypolicyviolation` events and console
messages that mention the Content Security Policy. A self-check first proves that the collector sees a string
evaluation (setTimeout with a string) in the page and in the 3D frame."""

from __future__ import annotations

import tempfile
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
from browser_helpers import CHROMIUM, PASSWORD, ROOT, log_in, running_server, steady_picture
from test_course_page import call, token
from test_viz_view import wait_until

pytestmark = [
    pytest.mark.skipif(CHROMIUM is None, reason="Chromium not installed (.ci/run installs Debian's package)")
]

SLUG = "pal-01-g1-gerade"
REFERENCE = (ROOT / "exercises" / "pal-mill" / f"{SLUG}.nc").read_text(encoding="utf-8")
STUDENT, TEACHER = "fehler-schueler", "fehler-lehrer"
# in every frame, before the page's own scripts: CSP violations, uncaught errors and rejections to the test
WATCH = """(() => {
  const report = (kind, text) => { try { window.__pageProblem(kind, String(text)); } catch (e) { /* not bound yet */ } };
  document.addEventListener("securitypolicyviolation", (e) =>
    report("csp", `${e.violatedDirective} blocked ${e.blockedURI || "inline"} (${e.sourceFile}:${e.lineNumber})`));
  window.addEventListener("error", (e) => report("error", e.message || e.error));
  window.addEventListener("unhandledrejection", (e) => report("rejection", e.reason && (e.reason.stack || e.reason)));
})();"""


@pytest.fixture(scope="module")
def server() -> Iterator[str]:
    with (
        tempfile.TemporaryDirectory() as data,
        running_server(Path(data), [(STUDENT, "student"), (TEACHER, "instructor")], workers=2) as url,
    ):
        yield url


class Problems:
    """What went wrong on the pages of one browser context, with the frame it happened in."""

    def __init__(self, context: Any) -> None:
        self.seen: list[str] = []
        context.expose_binding(
            "__pageProblem",
            lambda source, kind, text: self.seen.append(f"{kind} in {source['frame'].url}: {text}"),
        )
        context.add_init_script(WATCH)
        context.on("page", self.watch)

    def watch(self, page: Any) -> None:
        page.on("pageerror", lambda e: self.seen.append(f"pageerror in {page.url}: {e}"))
        page.on(
            "console",
            lambda m: (
                self.seen.append(f"console in {page.url}: {m.text}")
                if "Content Security Policy" in m.text or "Content-Security-Policy" in m.text
                else None
            ),
        )

    def take(self) -> list[str]:
        seen, self.seen = self.seen, []
        return seen


def context_for(browser: Any, problems: list[Problems], size: tuple[int, int] = (1366, 768)) -> Any:
    """A new browser context whose problems are collected (the last of `problems`)."""
    context = browser.new_context(viewport={"width": size[0], "height": size[1]})
    problems.append(Problems(context))
    return context


def logged_in_page(context: Any, server: str, user: str) -> Any:
    page = context.new_page()
    log_in(page, server, user)
    page.wait_for_url(lambda url: "/login" not in url, timeout=20000)
    return page


def switch_3d_on(page: Any) -> Any:
    """Click "3D-Ansicht einschalten" (off by itself: this headless browser draws without acceleration) and wait
    until viser's client has connected, drawn and run a while; the 3D frame."""
    page.wait_for_selector("#viz-on", timeout=20000)
    page.click("#viz-on")
    wait_until(page, "Number(document.getElementById('viz-frame')?.dataset.segments || 0) > 0", 30)
    page.frame_locator("#viz-frame").locator("canvas").first.wait_for(timeout=30000)
    steady_picture(page)
    page.wait_for_timeout(1000)
    frame = page.frame(url=lambda u: "/viz/" in u)
    assert frame is not None
    return frame


def reported(page: Any, problems: Problems, where: str, seconds: float = 10.0) -> list[str]:
    """What was collected, once a CSP violation in a frame whose URL contains `where` is among it."""
    seen: list[str] = []
    for _ in range(int(seconds * 10)):
        seen += problems.take()
        if any(s.startswith("csp in ") and where in s.split(": ", 1)[0] and "script-src" in s for s in seen):
            break
        page.wait_for_timeout(100)
    return seen


def test_the_collector_sees_a_string_evaluation(server: str, browser: Any) -> None:
    """The policy forbids evaluating strings: setTimeout("…") is reported, in the page and in the 3D frame."""
    problems: list[Problems] = []
    context = context_for(browser, problems)
    page = context.new_page()
    page.goto(f"{server}/practice")
    page.wait_for_selector(".cm-content")
    page.evaluate("setTimeout('window.evaluated = 1', 0)")
    seen = reported(page, problems[0], "/practice")
    assert any(s.startswith("csp in ") and "script-src" in s for s in seen), seen
    assert any(s.startswith("console in ") and "Evaluating a string" in s for s in seen), seen
    assert page.evaluate("window.evaluated") is None
    frame = switch_3d_on(page)
    problems[0].take()
    frame.evaluate("setTimeout('window.evaluated = 1', 0)")
    seen = reported(page, problems[0], "/viz/")
    assert any(s.startswith("csp in ") and "/viz/" in s.split(": ", 1)[0] for s in seen), seen
    context.close()


def test_every_page_runs_without_error_or_policy_violation(server: str, browser: Any) -> None:
    problems: list[Problems] = []
    found: dict[str, list[str]] = {}
    teacher = token(server, TEACHER, PASSWORD)
    course = call(server, "POST", "/courses", teacher, {"name": "FA 28 Fehlerfrei"})["id"]

    # nobody logged in: the start page, the login page, free practice with 3D on
    anonymous = context_for(browser, problems)
    page = anonymous.new_page()
    page.goto(f"{server}/")
    page.wait_for_load_state("networkidle")
    page.wait_for_timeout(500)
    found["start page"] = problems[-1].take()
    page.goto(f"{server}/login")
    page.wait_for_selector("input[name=username]")
    page.wait_for_timeout(500)
    found["login"] = problems[-1].take()
    page.goto(f"{server}/practice")
    page.wait_for_selector(".cm-content")
    wait_until(page, "document.getElementById('viz-picture')?.naturalWidth > 100", 30)
    switch_3d_on(page)
    found["free practice, 3D on"] = problems[-1].take()
    anonymous.close()

    # a trainee: the exercise list, an exercise page with 3D on (the reference typed, playback, views)
    student = context_for(browser, problems)
    page = logged_in_page(student, server, STUDENT)
    page.goto(f"{server}/")
    page.wait_for_selector("ul.exercises a", timeout=20000)
    page.wait_for_timeout(500)
    found["exercise list"] = problems[-1].take()
    page.goto(f"{server}/exercises/{SLUG}")
    page.wait_for_selector(".cm-content")
    page.click(".cm-content")
    page.keyboard.press("Control+a")
    page.keyboard.insert_text(REFERENCE)
    wait_until(page, "document.getElementById('viz-picture')?.dataset.text?.includes('N60 G1 X70')", 30)
    switch_3d_on(page)
    for view in ("top", "front", "iso"):
        page.click(f"#view-{view}")
        page.wait_for_timeout(800)
    page.click("#step-back")
    page.wait_for_timeout(800)
    found["exercise page, 3D on"] = problems[-1].take()
    student.close()

    # the instructor: their page and a course page
    instructor = context_for(browser, problems)
    page = logged_in_page(instructor, server, TEACHER)
    page.goto(f"{server}/instructor")
    page.wait_for_selector("#submission-list :is(table, p)", state="attached", timeout=20000)
    page.wait_for_timeout(500)
    found["instructor page"] = problems[-1].take()
    page.goto(f"{server}/courses/{course}")
    page.wait_for_selector("h1", timeout=20000)
    page.wait_for_load_state("networkidle")
    page.wait_for_timeout(800)
    found["course page"] = problems[-1].take()
    instructor.close()

    assert {name: seen for name, seen in found.items() if seen} == {}
