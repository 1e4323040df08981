"""The 3D view as a trainee sees it, in Chromium at the laptop (1366×768) and tablet (768×1024) sizes: no viser
developer panel, connection status, WebSocket address or English notice; our own views, layers and legend;
every preset view (Oben, Vorne, Iso) frames the stock with a margin; after "Abgeben" the deviation in colour
and in mm³ and mm; while the view is off (no graphics acceleration, as in this headless browser) the server's
2D view of the current state instead (core/picture2d.py: the plan view of a milling program, the drawing view
of a turning program), asked for again when the program changes.
Screenshots: PALTRAINER_SCREENSHOTS, else tests/browser/screenshots/."""

from __future__ import annotations

import os
import time
from pathlib import Path

import pytest
from browser_helpers import steady_picture
from test_practice_page import CHROMIUM, PASSWORD, ROOT, server  # noqa: F401 (fixtures)

pytestmark = [
    pytest.mark.skipif(CHROMIUM is None, reason="Chromium not installed (.ci/run installs Debian's package)")
]

SHOTS = Path(os.environ.get("PALTRAINER_SCREENSHOTS") or Path(__file__).parent / "screenshots")
SIZES = {"laptop": (1366, 768), "tablet": (768, 1024)}
SLUG = "pal-01-g1-gerade"
# counts the animation frames a page draws (viser's scene draws on request only, in requestAnimationFrame)
COUNT_FRAMES = """(() => { window.framesDrawn = 0; const request = window.requestAnimationFrame.bind(window);
  window.requestAnimationFrame = (callback) => request((t) => { window.framesDrawn++; callback(t); }); })();"""
# text a trainee must never see in the view: viser's panel, its status, its address, its notices
DEVELOPER_TEXT = (
    "Connected",
    "Dev Settings",
    "Scene tree",
    "Software WebGL",
    "ws://",
    "Save Canvas",
    "Reset View",
)


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


def frame_fit(shot: bytes) -> dict[str, float]:
    """Where the part is in a picture of the 3D frame (taken with the path layers hidden): its margins left, right,
    top and bottom and its size, as fractions of the frame's width and height (whatever differs from the
    backdrop's colour)."""
    import io

    import numpy as np
    from PIL import Image

    image = np.asarray(Image.open(io.BytesIO(shot)).convert("RGB"), dtype=np.int32)[
        3:-3, 3:-3
    ]  # inside the border
    backdrop = np.median(np.concatenate([image[0], image[-1], image[:, 0], image[:, -1]]), axis=0)
    part = np.abs(image - backdrop).sum(axis=2) > 24
    rows, cols = np.flatnonzero(part.any(axis=1)), np.flatnonzero(part.any(axis=0))
    height, width = part.shape
    assert len(rows) and len(cols), "nothing drawn in the 3D frame"
    return {
        "left": cols[0] / width,
        "right": 1 - (cols[-1] + 1) / width,
        "top": rows[0] / height,
        "bottom": 1 - (rows[-1] + 1) / height,
        "width": (cols[-1] + 1 - cols[0]) / width,
        "height": (rows[-1] + 1 - rows[0]) / height,
    }


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
    # off by itself here (software WebGL): the same place shows the 2D view of the part after the program,
    # drawn by the server (core/picture2d.py): depths with their legend, the path, the contour, axes, the zero
    page.wait_for_selector("#viz-on")
    wait_until(page, "document.getElementById('viz-picture')?.dataset.text?.includes('N60 G1 X70')")
    wait_until(page, "document.getElementById('viz-picture')?.naturalWidth > 300")
    assert page.get_attribute("#viz-picture", "data-view") == "mill"
    assert (page.get_attribute("#viz-picture", "alt") or "").startswith("2D-Ansicht")
    picture = page.locator("#viz-picture").bounding_box()
    assert picture and picture["width"] > 300 and picture["height"] > 250
    page.locator("#viz").scroll_into_view_if_needed()
    page.screenshot(path=str(SHOTS / f"viz-off-picture-{size}.png"))
    page.locator("#viz-picture").screenshot(path=str(SHOTS / f"viz-2d-{size}.png"))
    # a block with an error: the picture asks again and marks where the block was skipped
    page.click(".cm-content")
    page.keyboard.press("Control+a")
    page.keyboard.insert_text(reference.replace("N70 G1 Y84", "N70 G1 Y84 Q7"))
    wait_until(page, "document.getElementById('viz-picture')?.dataset.text?.includes('Y84 Q7')")
    page.wait_for_timeout(300)
    page.locator("#viz-picture").screenshot(path=str(SHOTS / f"viz-2d-error-{size}.png"))
    page.click(".cm-content")
    page.keyboard.press("Control+a")
    page.keyboard.insert_text(reference)
    wait_until(page, "!document.getElementById('viz-picture')?.dataset.text?.includes('Q7')")

    page.click("#viz-on")
    wait_until(page, "Number(document.getElementById('viz-frame')?.dataset.segments || 0) > 5")
    frame = page.frame_locator("#viz-frame")
    frame.locator("canvas").first.wait_for(timeout=30000)
    steady_picture(page)  # viser's client has connected and drawn (software rendering is slow)
    text = visible_frame_text(page)
    for clutter in DEVELOPER_TEXT:
        assert clutter not in text, clutter
    token = page.get_attribute("#viz-frame", "src").split("/")[2]
    assert token not in text
    # our own controls: views, layers with their colours, the deviation legend (German)
    toolbar = page.inner_text(".viz-toolbar")
    for label in (
        "Oben",
        "Vorne",
        "Iso",
        "Zurücksetzen",
        "Eilgang",
        "Vorschub",
        "Kontur",
        "Rohteil",
        "zu viel abgetragen",
        "zu viel stehen gelassen",
    ):
        assert label in toolbar, label
    # nothing in the 3D panel sticks out of it (the page's own layout is tested with the pages)
    assert page.evaluate("(v => v.scrollWidth <= v.clientWidth)(document.getElementById('viz'))"), (
        page.evaluate(WIDER)
    )
    page.locator("#viz").scroll_into_view_if_needed()
    page.screenshot(path=str(SHOTS / f"viz-iso-{size}.png"))

    # every preset view frames the stock with a margin: nothing of it cut off, and it fills the view
    # (the zero's Z axis and the tool stand above the part in the views from the side: their tops not counted).
    # The path layers are hidden for all three (each switch redraws the scene, in software here).
    for layer in ("rapid", "feed", "contour"):
        page.uncheck(f"#layer-{layer}")
    page.locator("#viz").scroll_into_view_if_needed()
    for view, sides in (
        ("top", ("left", "right", "top", "bottom")),
        ("front", ("left", "right", "bottom")),
        ("iso", ("left", "right", "bottom")),
    ):
        page.click(f"#view-{view}")
        fit = frame_fit(steady_picture(page))
        page.screenshot(path=str(SHOTS / f"viz-view-{view}-{size}.png"))
        for side in sides:
            assert fit[side] > 0.02, (view, side, fit)
        assert max(fit["width"], fit["height"]) > 0.6, (view, fit)
        assert fit["left"] < 0.3 and fit["right"] < 0.3 or fit["top"] < 0.3 and fit["bottom"] < 0.3, (
            view,
            fit,
        )
        assert abs(fit["left"] - fit["right"]) < 0.08, (view, fit)  # centred

    for layer in ("feed", "contour"):
        page.check(f"#layer-{layer}")
    page.click("#view-top")
    steady_picture(page)
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
    steady_picture(page)
    page.locator("#viz").scroll_into_view_if_needed()
    page.screenshot(path=str(SHOTS / f"viz-graded-{size}.png"))
    page.close()


@pytest.mark.parametrize("size", list(SIZES))
def test_the_2d_view_of_a_turning_program(server: str, browser: object, size: str) -> None:  # noqa: F811
    """Free practice with a TRAUB example, 3D off: the 2D drawing view of the turned part (half section, path,
    axes with diameters, zero), consistent with the milling plan view."""
    width, height = SIZES[size]
    page = browser.new_page(viewport={"width": width, "height": height})  # type: ignore[attr-defined]
    page.goto(f"{server}/practice?dialect=traub-tx8d")
    page.wait_for_selector(".cm-content")
    program = (ROOT / "exercises" / "traub-tx8d" / "traub-10-schruppen-g71-g88.nc").read_text(
        encoding="utf-8"
    )
    page.click(".cm-content")
    page.keyboard.press("Control+a")
    page.keyboard.insert_text(program)
    wait_until(page, "document.getElementById('viz-picture')?.dataset.view === 'lathe'", 30)
    wait_until(page, "document.getElementById('viz-picture')?.dataset.text?.includes('G71')", 30)
    wait_until(page, "document.getElementById('viz-picture')?.naturalWidth > 300")
    assert "Halbschnitt" in (page.get_attribute("#viz-picture", "alt") or "")
    page.locator("#viz").scroll_into_view_if_needed()
    page.screenshot(path=str(SHOTS / f"viz-2d-lathe-page-{size}.png"))
    page.locator("#viz-picture").screenshot(path=str(SHOTS / f"viz-2d-lathe-{size}.png"))
    page.close()


@pytest.fixture(autouse=True, scope="module")
def _shots_folder() -> None:
    SHOTS.mkdir(parents=True, exist_ok=True)


def test_free_practice_3d_view_for_an_anonymous_browser(server: str, browser: object) -> None:  # noqa: F811
    """Without an account the browser's 3D cookie binds the scene to it: the view connects and shows the
    sample program; another browser cannot open the same scene."""
    context = browser.new_context(viewport={"width": 1366, "height": 768})  # type: ignore[attr-defined]
    context.add_init_script(COUNT_FRAMES)
    page = context.new_page()
    page.goto(f"{server}/practice")
    page.wait_for_selector("#viz-on")
    wait_until(page, "document.getElementById('viz-picture')?.naturalWidth > 100")
    page.click("#viz-on")
    wait_until(page, "Number(document.getElementById('viz-frame')?.dataset.segments || 0) > 3")
    page.frame_locator("#viz-frame").locator("canvas").first.wait_for(timeout=30000)
    steady_picture(page)
    # an idle view draws nothing (a redraw every 10 s at most): without graphics acceleration every frame costs
    # the processor, once a second it was half a core. (Up to five windows of 3 s: the fine level of the stock
    # may still arrive and be drawn on a loaded machine; with a redraw every second no window is quiet.)
    scene = next(f for f in page.frames if "/viz/" in f.url)
    counts = []
    for _ in range(5):
        drawn = scene.evaluate("window.framesDrawn")
        page.wait_for_timeout(3000)
        counts.append(scene.evaluate("window.framesDrawn") - drawn)
        if counts[-1] <= 1:
            break
    assert counts[-1] <= 1, counts
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
