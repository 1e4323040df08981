"""The 3D view as a trainee sees it, in Chromium at the laptop (1366×768) and tablet (768×1024) sizes: no viser
developer panel, connection status, WebSocket address or English notice; our own views, layers and legend;
the part framed; after "Abgeben" the deviation in colour and in mm³ and mm; while the view is off (no graphics
acceleration, as in this headless browser) the server's picture of the current state instead of an empty box.
Screenshots: PALTRAINER_SCREENSHOTS, else tests/browser/screenshots/."""

from __future__ import annotations

import os
import time
from pathlib import Path

import pytest
from test_practice_page import CHROMIUM, PASSWORD, ROOT, server  # noqa: F401 (fixtures)

pytestmark = [pytest.mark.skipif(CHROMIUM is None, reason="Chromium not installed (.ci/run installs Debian's package)")]

SHOTS = Path(os.environ.get("PALTRAINER_SCREENSHOTS") or Path(__file__).parent / "screenshots")
SIZES = {"laptop": (1366, 768), "tablet": (768, 1024)}
SLUG = "pal-01-g1-gerade"
# text a trainee must never see in the view: viser's panel, its status, its address, its notices
DEVELOPER_TEXT = ("Connected", "Dev Settings", "Scene tree", "Software WebGL", "ws://", "Save Canvas", "Reset View")


# the elements that reach beyond the window's right edge (to say what overflows)
WIDER = """[...document.querySelectorAll('body *')].filter((e) => e.getBoundingClientRect().right > innerWidth + 1)
  .slice(0, 8).map((e) => `${e.tagName}#${e.id}.${e.className} ${Math.round(e.getBoundingClientRect().right)}`)"""


def log_in(page: object, url: str) -> None:
    page.goto(f"{url}/login?next=/exercises/{SLUG}")  # type: ignore[attr-defined]
    page.fill("input[name=username]", "schueler")  # type: ignore[attr-defined]
    page.fill("input[name=password]", PASSWORD)  # type: ignore[attr-defined]
    page.click("button[type=submit]")  # type: ignore[attr-defined]
    page.wait_for_url(f"**/exercises/{SLUG}")  # type: ignore[attr-defined]
    page.wait_for_selector(".cm-content")  # type: ignore[attr-defined]


def wait_until(page: object, expression: str, timeout: float = 15.0) -> None:
    """Poll a JavaScript expression from here (the pages' Content-Security-Policy forbids the eval that
    Playwright's wait_for_function uses)."""
    deadline = time.monotonic() + timeout
    while not page.evaluate(expression):  # type: ignore[attr-defined]
        assert time.monotonic() < deadline, f"not within {timeout} s: {expression}"
        time.sleep(0.1)


def visible_frame_text(page: object) -> str:
    """All text in the 3D frame that a trainee could see (rendered, not display:none)."""
    frame = page.frame(name=None, url=lambda u: "/viz/" in u)  # type: ignore[attr-defined]
    assert frame is not None
    return str(frame.evaluate("document.body.innerText"))


@pytest.mark.parametrize("size", list(SIZES))
def test_the_3d_view_without_developer_clutter(server: str, browser: object, size: str) -> None:  # noqa: F811
    width, height = SIZES[size]
    page = browser.new_page(viewport={"width": width, "height": height})  # type: ignore[attr-defined]
    log_in(page, server)
    reference = (ROOT / "exercises" / "pal-mill" / f"{SLUG}.nc").read_text(encoding="utf-8")
    page.wait_for_selector("#viz-on")
    page.click(".cm-content")
    page.keyboard.press("Control+a")
    page.keyboard.insert_text(reference)
    # off by itself here (software WebGL): the same place shows the part after the program, from the server
    page.wait_for_selector("#viz-on")
    wait_until(page, "document.getElementById('viz-picture')?.dataset.text?.includes('N60 G1 X70')")
    wait_until(page, "document.getElementById('viz-picture')?.naturalWidth > 100")
    picture = page.locator("#viz-picture").bounding_box()
    assert picture and picture["width"] > 150 and picture["height"] > 100
    page.locator("#viz").scroll_into_view_if_needed()
    page.screenshot(path=str(SHOTS / f"viz-off-picture-{size}.png"))

    page.click("#viz-on")
    wait_until(page, "Number(document.getElementById('viz-frame')?.dataset.segments || 0) > 5")
    frame = page.frame_locator("#viz-frame")
    frame.locator("canvas").first.wait_for(timeout=30000)
    page.wait_for_timeout(6000)  # viser's client has connected and drawn (software rendering is slow)
    text = visible_frame_text(page)
    for clutter in DEVELOPER_TEXT:
        assert clutter not in text, clutter
    token = page.get_attribute("#viz-frame", "src").split("/")[2]
    assert token not in text
    # our own controls: views, layers with their colours, the deviation legend (German)
    toolbar = page.inner_text(".viz-toolbar")
    for label in ("Oben", "Vorne", "Iso", "Zurücksetzen", "Eilgang", "Vorschub", "Kontur", "Rohteil",
                  "zu viel abgetragen", "zu viel stehen gelassen"):
        assert label in toolbar, label
    # nothing in the 3D panel sticks out of it (the page's own layout is tested with the pages)
    assert page.evaluate("(v => v.scrollWidth <= v.clientWidth)(document.getElementById('viz'))"), page.evaluate(WIDER)
    page.locator("#viz").scroll_into_view_if_needed()
    page.screenshot(path=str(SHOTS / f"viz-iso-{size}.png"))

    page.click("#view-top")
    page.uncheck("#layer-rapid")
    page.wait_for_timeout(2500)
    page.screenshot(path=str(SHOTS / f"viz-top-no-rapid-{size}.png"))
    page.check("#layer-rapid")
    page.click("#view-reset")

    # a program that cuts 1 mm too deep: after "Abgeben" the colours are in sight and the numbers in mm³ and mm
    page.click(".cm-content")
    page.keyboard.press("Control+a")
    page.keyboard.insert_text(reference.replace("Z-2", "Z-3", 1))
    page.wait_for_timeout(800)
    page.click("#submit")
    page.wait_for_selector(".score", timeout=20000)
    legend = page.wait_for_selector("#deviation", timeout=20000)
    message = legend.inner_text()
    assert "mm³" in message and "größte Abweichung" in message and "Felder" not in message, message
    page.wait_for_timeout(3000)
    page.locator("#viz").scroll_into_view_if_needed()
    page.screenshot(path=str(SHOTS / f"viz-graded-{size}.png"))
    page.close()


@pytest.fixture(autouse=True, scope="module")
def _shots_folder() -> None:
    SHOTS.mkdir(parents=True, exist_ok=True)


def test_free_practice_3d_view_for_an_anonymous_browser(server: str, browser: object) -> None:  # noqa: F811
    """Without an account the browser's 3D cookie binds the scene to it: the view connects and shows the
    sample program; another browser cannot open the same scene."""
    context = browser.new_context(viewport={"width": 1366, "height": 768})  # type: ignore[attr-defined]
    page = context.new_page()
    page.goto(f"{server}/practice")
    page.wait_for_selector("#viz-on")
    wait_until(page, "document.getElementById('viz-picture')?.naturalWidth > 100")
    page.click("#viz-on")
    wait_until(page, "Number(document.getElementById('viz-frame')?.dataset.segments || 0) > 3")
    page.frame_locator("#viz-frame").locator("canvas").first.wait_for(timeout=30000)
    page.wait_for_timeout(5000)
    text = visible_frame_text(page)
    assert not [c for c in DEVELOPER_TEXT if c in text]
    page.locator("#viz").scroll_into_view_if_needed()
    page.screenshot(path=str(SHOTS / "viz-practice-laptop.png"))
    url = page.get_attribute("#viz-frame", "src")
    other = browser.new_context()  # type: ignore[attr-defined]
    response = other.new_page().goto(f"{server}{url}")
    assert response is not None and response.status == 403
    other.close()
    context.close()
