"""The pages' layout in Chromium at the laptop (1366×768), tablet (768×1024) and desktop (1920×1080) sizes: never
horizontal scrolling; on the laptop editor and 3D view side by side with the messages and "Abgeben" in sight;
on the tablet stacked; on the desktop the drawing, the editor and the 3D view at once; axe-core finds no
serious or critical accessibility problem; free practice loads an example with its drawing, opens, saves and
prints programs. Screenshots of every page at every size: PALTRAINER_SCREENSHOTS, else tests/browser/screenshots/."""

from __future__ import annotations

import os
from pathlib import Path

import pytest
from browser_helpers import create_users, log_in
from test_practice_page import CHROMIUM, PASSWORD, ROOT, SERVER_DATA, server  # noqa: F401 (fixtures)
from test_viz_view import WIDER, wait_until

pytestmark = [
    pytest.mark.skipif(CHROMIUM is None, reason="Chromium not installed (.ci/run installs Debian's package)")
]

SHOTS = Path(os.environ.get("PALTRAINER_SCREENSHOTS") or Path(__file__).parent / "screenshots")
SIZES = {"laptop": (1366, 768), "tablet": (768, 1024), "desktop": (1920, 1080)}
SLUG = "pal-05-g2-kreisbogen"
AXE = ROOT / "web" / "node_modules" / "axe-core" / "axe.min.js"
PAGES = {
    "practice": "/practice",
    "exercises": "/",
    "exercise": f"/exercises/{SLUG}",
    "instructor": "/instructor",
    "login": "/login",
}
READY = {
    "practice": ".cm-content",
    "exercises": "ul.exercises",
    "exercise": "figure.drawing img",
    "instructor": "#submission-list :is(table, p)",
    "login": "#login",
}


@pytest.fixture(scope="module")
def instructor(server: str) -> str:  # noqa: F811
    env = {**os.environ, "PALTRAINER_DATA_DIR": SERVER_DATA[0]}
    create_users(env, [("layout-lehrer", "instructor")])
    return "layout-lehrer"


@pytest.fixture(scope="module")
def signed_in(server: str, browser: object, instructor: str) -> dict[str, object]:  # noqa: F811
    """The browser's storage after the instructor logged in once (its session cookie): each page's context
    starts from it. Logging in is the login tests' subject; here it would only cost a login per page."""
    ctx = browser.new_context()  # type: ignore[attr-defined]
    page = ctx.new_page()
    log_in(page, server, instructor)
    page.wait_for_url(f"{server}/instructor")  # an instructor lands on their page
    state = dict(ctx.storage_state())
    ctx.close()
    return state


def open_page(
    browser: object,
    server: str,  # noqa: F811 (the fixture's value)
    state: dict[str, object],
    name: str,
    size: str,
    **context: object,
) -> object:
    width, height = SIZES[size]
    if name != "login":  # the login page is the page of someone not logged in
        context = {"storage_state": state, **context}
    ctx = browser.new_context(viewport={"width": width, "height": height}, **context)  # type: ignore[attr-defined]
    page = ctx.new_page()
    page.goto(f"{server}{PAGES[name]}")
    page.wait_for_selector(
        READY[name], state="attached", timeout=20000
    )  # the tablet folds the task (its drawing)
    if name in ("practice", "exercise"):
        page.wait_for_selector(".diag", timeout=20000)  # the first answer of the live check
        wait_until(page, "document.getElementById('viz-picture')?.naturalWidth > 100")
    if name == "exercise":
        wait_until(page, "document.querySelector('figure.drawing img')?.naturalWidth > 100")
    return page


def box(page: object, selector: str) -> dict[str, float]:
    b = page.locator(selector).first.bounding_box()  # type: ignore[attr-defined]
    assert b is not None, selector
    return dict(b)


@pytest.mark.parametrize("size", list(SIZES))
@pytest.mark.parametrize("name", list(PAGES))
def test_page_fits_the_window(
    server: str,  # noqa: F811 (the fixture)
    browser: object,
    signed_in: dict[str, object],
    name: str,
    size: str,
) -> None:
    page = open_page(browser, server, signed_in, name, size)
    width, height = SIZES[size]
    assert page.evaluate("document.documentElement.scrollWidth <= innerWidth"), page.evaluate(WIDER)
    page.screenshot(path=str(SHOTS / f"layout-{name}-{size}.png"))
    if name in ("practice", "exercise"):
        editor, viz, drawer = box(page, "#editor"), box(page, ".viz-pane"), box(page, "#drawer")
        if size == "tablet":  # stacked, each full width
            assert viz["y"] >= editor["y"] + editor["height"] - 1 and editor["width"] > width - 40
        else:  # side by side, the messages (and "Abgeben") in sight without scrolling
            assert editor["x"] + editor["width"] <= viz["x"] + 1 and editor["y"] + editor["height"] <= height
            assert drawer["y"] + drawer["height"] <= height + 1 and page.locator(".diag").first.is_visible()
            if name == "exercise":
                submit = box(page, "#submit")
                assert submit["y"] + submit["height"] <= height
        if name == "exercise" and size == "desktop":  # the drawing, the editor and the 3D view at once
            drawing = box(page, "figure.drawing img")
            assert drawing["y"] + drawing["height"] / 2 < height and drawing["width"] > 300
    page.context.close()


@pytest.mark.parametrize("name", list(PAGES))
def test_no_serious_accessibility_problems(
    server: str,  # noqa: F811 (the fixture)
    browser: object,
    signed_in: dict[str, object],
    name: str,
) -> None:
    # axe is injected as a script of its own: the pages' policy forbids inline script, so this browser ignores it
    page = open_page(browser, server, signed_in, name, "laptop", bypass_csp=True)
    page.add_script_tag(path=str(AXE))
    result = page.evaluate("axe.run(document, {resultTypes: ['violations']})")
    serious = [
        (v["id"], v["impact"], [n["target"] for n in v["nodes"]][:3])
        for v in result["violations"]
        if v["impact"] in ("serious", "critical")
    ]
    assert not serious, serious
    page.context.close()


def test_practice_loads_an_example_opens_saves_and_prints(
    server: str,  # noqa: F811 (the fixture)
    browser: object,
    signed_in: dict[str, object],
    tmp_path: Path,
) -> None:
    page = open_page(browser, server, signed_in, "practice", "laptop", accept_downloads=True)
    page.select_option(
        "#example", SLUG
    )  # a built-in example: its program and, in the Zeichnung tab, its drawing
    reference = (ROOT / "exercises" / "pal-mill" / f"{SLUG}.nc").read_text(encoding="utf-8")
    wait_until(
        page, f"document.querySelector('.cm-content').innerText.includes({reference.splitlines()[2]!r})"
    )
    page.wait_for_selector("#panel-drawing .zoom-frame img")
    wait_until(page, "document.querySelector('#panel-drawing .zoom-frame img').naturalWidth > 100")
    assert page.get_attribute("#tab-drawing", "aria-selected") == "true"
    page.screenshot(path=str(SHOTS / "layout-practice-example-laptop.png"))
    # saving: a download of the program as it stands, named after the example
    with page.expect_download() as info:
        page.click("#file-save")
    saved = tmp_path / "saved.nc"
    info.value.save_as(saved)
    assert info.value.suggested_filename == f"{SLUG}.nc" and saved.read_text(encoding="utf-8") == reference
    # opening one's own file: into the editor, and the example's drawing is gone
    own = tmp_path / "eigenes.nc"
    own.write_text("N10 T1 TC1 M6\nN20 S1000 F100 M3\nN30 G0 X0 Y0 Z2\nN40 M30\n", encoding="utf-8")
    page.set_input_files("#open-file", str(own))
    wait_until(page, "document.querySelector('.cm-content').innerText.includes('S1000 F100')")
    assert page.input_value("#example") == ""
    # printing: the program alone, with its line numbers (the print dialog itself is not opened here)
    page.evaluate("window.print = () => {}")
    page.click("#file-print")
    page.emulate_media(media="print")
    assert page.locator("#print-view li").count() == 4 and page.locator("#print-view").is_visible()
    assert not page.locator("#editor").is_visible()
    page.screenshot(path=str(SHOTS / "layout-practice-print.png"))
    page.context.close()


def test_exercise_columns_resize_collapse_and_are_remembered(
    server: str,  # noqa: F811 (the fixture)
    browser: object,
    signed_in: dict[str, object],
) -> None:
    page = open_page(browser, server, signed_in, "exercise", "laptop")
    editor = box(page, "#editor")["width"]
    page.focus(".viz-pane > .splitter")  # between editor and 3D view: the arrow keys move it
    for _ in range(5):
        page.keyboard.press("ArrowRight")
    wider = box(page, "#editor")["width"]
    assert wider > editor + 80
    side = box(page, ".side")["width"]
    page.click("#side-toggle")  # the task folds to a strip: editor and 3D view get its width
    assert box(page, ".side")["width"] < 60 and box(page, "#editor")["width"] > wider
    assert page.get_attribute("#side-toggle", "aria-expanded") == "false"
    page.reload()
    page.wait_for_selector(".cm-content")
    assert box(page, ".side")["width"] < 60
    page.click("#side-toggle")
    assert abs(box(page, ".side")["width"] - side) < 2 and abs(box(page, "#editor")["width"] - wider) < 2
    page.click("#tab-tools")  # the tabs: the tool table with its numbers
    assert page.locator("#panel-tools table").is_visible() and not page.locator("#panel-task").is_visible()
    page.keyboard.press("ArrowRight")
    assert (
        page.get_attribute("#tab-hints", "aria-selected") == "true"
        and page.locator("#panel-hints").is_visible()
    )
    page.context.close()


def test_exercise_page_in_english(server: str, browser: object, signed_in: dict[str, object]) -> None:  # noqa: F811
    page = open_page(browser, server, signed_in, "exercise", "laptop")
    page.click("#lang")
    page.wait_for_selector("#tab-task >> text=Task")
    page.wait_for_selector(".diag", timeout=20000)
    labels = [
        page.inner_text(s)
        for s in (
            "#tab-task",
            "#tab-drawing",
            "#tab-tools",
            "#tab-hints",
            "#file-open",
            "#file-save",
            "#file-print",
            "#file-reset",
            "#submit",
        )
    ]
    assert labels == ["Task", "Drawing", "Tools", "Hints", "Open", "Save", "Print", "Reset", "Submit"]
    assert page.inner_text("#drawer-toggle").startswith("Messages")
    page.screenshot(path=str(SHOTS / "layout-exercise-laptop-en.png"))
    page.context.close()


@pytest.fixture(autouse=True, scope="module")
def _shots_folder() -> None:
    SHOTS.mkdir(parents=True, exist_ok=True)
