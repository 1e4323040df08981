"""The drawing readable at laptop and tablet size (issue 28, point 10), in Chromium at 1366×768 and 768×1024:

- the Zeichnung tab fits the drawing's views to the panel's height and width (not an A4 sheet squeezed into its
  width), and zooms and moves it: the buttons − + ⤢, the mouse wheel (about the pointer), dragging, two fingers
  (pinch), the keys + − 0 and the arrows;
- "Groß öffnen" opens our own page (/exercises/{slug}/drawing) with the same viewer, the whole sheet fitted to
  the window, and "Drucken", which prints the sheet alone on one A4 landscape page; free practice's examples have
  the same page without login; neither page has an uncaught error or a Content-Security-Policy violation.

Screenshots (PALTRAINER_SCREENSHOTS, else tests/browser/screenshots/): drawing-tab-{size}.png (fitted),
drawing-tab-zoomed-{size}.png, drawing-page-{size}.png, drawing-page-print.png (the printed PDF as a picture)."""

from __future__ import annotations

import os
import re
import shutil
import subprocess
from pathlib import Path
from typing import Any

import pytest
from browser_helpers import log_in
from test_practice_page import CHROMIUM, PASSWORD, server  # noqa: F401 (fixtures)
from test_viz_view import wait_until

pytestmark = [
    pytest.mark.skipif(CHROMIUM is None, reason="Chromium not installed (.ci/run installs Debian's package)")
]

SHOTS = Path(os.environ.get("PALTRAINER_SCREENSHOTS") or Path(__file__).parent / "screenshots")
SIZES = {"laptop": (1366, 768), "tablet": (768, 1024)}
SLUG = "pal-05-g2-kreisbogen"
TAB = "#panel-drawing .drawing-stage"

# the stage, the sheet in it and the viewer's state
STATE = """(selector) => {
  const stage = document.querySelector(selector);
  const img = stage.querySelector('img');
  const s = stage.getBoundingClientRect(), i = img.getBoundingClientRect();
  return { stage: { x: s.x, y: s.y, w: s.width, h: s.height }, img: { x: i.x, y: i.y, w: i.width, h: i.height },
           zoom: Number(stage.dataset.zoom), fitted: stage.dataset.fitted === 'true', loaded: img.naturalWidth > 100 };
}"""
# two fingers on the stage, as pointer events (Playwright's touch has one finger): put down, spread, lift
PINCH = """([selector, from, to]) => {
  const stage = document.querySelector(selector);
  const b = stage.getBoundingClientRect();
  const cx = b.x + b.width / 2, cy = b.y + b.height / 2;
  const fire = (type, id, dx) => stage.dispatchEvent(new PointerEvent(type, { pointerId: id, pointerType: 'touch',
    isPrimary: id === 11, clientX: cx + dx, clientY: cy, bubbles: true, cancelable: true }));
  fire('pointerdown', 11, -from); fire('pointerdown', 12, from);
  for (let k = 1; k <= 5; k++) { const d = from + (to - from) * k / 5; fire('pointermove', 11, -d); fire('pointermove', 12, d); }
  fire('pointerup', 11, -to); fire('pointerup', 12, to);
}"""


def _watch(page: Any) -> list[str]:
    """Uncaught errors and Content-Security-Policy violations of the page."""
    seen: list[str] = []
    page.on("pageerror", lambda e: seen.append(f"pageerror: {e}"))
    page.on("console", lambda m: seen.append(m.text) if m.type == "error" else None)
    return seen


def _login(browser: Any, server: str, size: str) -> Any:  # noqa: F811
    width, height = SIZES[size]
    page = browser.new_context(viewport={"width": width, "height": height}).new_page()
    log_in(page, server, "schueler")
    page.wait_for_url(lambda url: "/login" not in url)
    return page


def _state(page: Any, selector: str = TAB) -> dict[str, Any]:
    result: dict[str, Any] = page.evaluate(STATE, selector)
    return result


def _sheet_point(state: dict[str, Any], x: float, y: float) -> tuple[float, float]:
    """Where on the sheet (shares of its width and height) the screen point (x, y) is."""
    img = state["img"]
    return ((x - img["x"]) / img["w"], (y - img["y"]) / img["h"])


@pytest.mark.parametrize("size", list(SIZES))
def test_the_zeichnung_tab_fits_zooms_and_moves_the_drawing(server: str, browser: Any, size: str) -> None:  # noqa: F811
    page = _login(browser, server, size)
    errors = _watch(page)
    page.goto(f"{server}/exercises/{SLUG}")
    page.wait_for_selector(TAB, state="attached")  # the page is set up (its tabs too)
    page.click("#tab-drawing")
    page.wait_for_selector(f"{TAB} img", state="visible")
    wait_until(
        page,
        f"document.querySelector('{TAB} img').naturalWidth > 100 && document.querySelector('{TAB}').dataset.zoom",
    )
    page.wait_for_timeout(300)
    fitted = _state(page)
    stage, img = fitted["stage"], fitted["img"]
    panel = page.locator("#side-panels").bounding_box()
    assert panel is not None
    # the stage takes the panel's height (below its toolbar) and width
    assert stage["w"] >= panel["width"] - 40 and stage["y"] + stage["h"] >= panel["y"] + panel["height"] - 30
    assert stage["h"] >= 0.6 * panel["height"], (stage, panel)
    # fitted to the views (the drawing's data-views): larger than the whole A4 sheet fitted into the stage, and
    # filling the stage in one direction
    whole = min(stage["w"] / (297 / 25.4 * 96), stage["h"] / (210 / 25.4 * 96))
    assert fitted["fitted"] and fitted["zoom"] > 1.3 * whole, (fitted["zoom"], whole)
    inside_w = min(img["x"] + img["w"], stage["x"] + stage["w"]) - max(img["x"], stage["x"])
    inside_h = min(img["y"] + img["h"], stage["y"] + stage["h"]) - max(img["y"], stage["y"])
    assert inside_w >= stage["w"] - 3 or inside_h >= stage["h"] - 3
    page.screenshot(path=str(SHOTS / f"drawing-tab-{size}.png"))

    # "+" and "−": 25 % more, then back
    page.click("#panel-drawing button[aria-label='Vergrößern']")
    assert _state(page)["zoom"] == pytest.approx(fitted["zoom"] * 1.25, rel=0.01)
    page.click("#panel-drawing button[aria-label='Verkleinern']")
    assert _state(page)["zoom"] == pytest.approx(fitted["zoom"], rel=0.01)
    # the wheel zooms about the pointer: the sheet's point under it stays there
    px, py = stage["x"] + stage["w"] * 0.3, stage["y"] + stage["h"] * 0.4
    before = _sheet_point(_state(page), px, py)
    page.mouse.move(px, py)
    page.mouse.wheel(0, -300)
    page.wait_for_timeout(200)
    zoomed = _state(page)
    assert zoomed["zoom"] > fitted["zoom"] * 1.3 and not zoomed["fitted"]
    after = _sheet_point(zoomed, px, py)
    assert after == pytest.approx(before, abs=0.01)
    # dragging moves the sheet with the pointer
    page.mouse.move(px, py)
    page.mouse.down()
    page.mouse.move(px + 60, py + 40, steps=5)
    page.mouse.up()
    dragged = _state(page)
    assert dragged["img"]["x"] - zoomed["img"]["x"] == pytest.approx(60, abs=2)
    assert dragged["img"]["y"] - zoomed["img"]["y"] == pytest.approx(40, abs=2)
    page.screenshot(path=str(SHOTS / f"drawing-tab-zoomed-{size}.png"))
    # the keyboard on the stage: the arrows move, + and − zoom, 0 fits again
    page.focus(TAB)
    page.keyboard.press("ArrowLeft")
    assert _state(page)["img"]["x"] == pytest.approx(dragged["img"]["x"] + 48, abs=2)
    page.keyboard.press("+")
    assert _state(page)["zoom"] == pytest.approx(dragged["zoom"] * 1.25, rel=0.01)
    page.keyboard.press("-")
    page.keyboard.press("-")
    assert _state(page)["zoom"] == pytest.approx(dragged["zoom"] / 1.25, rel=0.01)
    page.keyboard.press("0")
    again = _state(page)
    assert again["fitted"] and again["zoom"] == pytest.approx(fitted["zoom"], rel=0.001)
    # "Einpassen" pressed once more: the whole sheet
    page.click("#panel-drawing button[aria-label='Einpassen']")
    assert _state(page)["zoom"] == pytest.approx(whole, rel=0.02)
    page.click("#panel-drawing button[aria-label='Einpassen']")
    assert _state(page)["zoom"] == pytest.approx(fitted["zoom"], rel=0.001)
    # two fingers spread: zoom in, about their middle
    page.evaluate(PINCH, [TAB, 40, 100])
    assert _state(page)["zoom"] == pytest.approx(fitted["zoom"] * 2.5, rel=0.05)
    # the Aufgabe tab's "Zeichnung groß öffnen" is our page, not the raw SVG
    links = page.eval_on_selector_all("a", "(all) => all.map((a) => a.getAttribute('href'))")
    assert f"/exercises/{SLUG}/drawing" in links and not any(
        h and h.endswith("drawing.svg?lang=de") for h in links
    )
    assert not errors, errors


@pytest.mark.parametrize("size", list(SIZES))
def test_the_drawings_own_page_with_the_same_viewer_and_print(
    server: str,  # noqa: F811 (the fixture)
    browser: Any,
    size: str,
    tmp_path: Path,
) -> None:
    page = _login(browser, server, size)
    page.goto(f"{server}/exercises/{SLUG}")
    page.wait_for_selector(TAB, state="attached")
    page.click("#tab-drawing")
    page.wait_for_selector("#panel-drawing a.drawing-open")
    with page.context.expect_page() as opened:
        page.click("#panel-drawing a.drawing-open")
    big = opened.value
    errors = _watch(big)
    big.wait_for_load_state()
    assert big.url.endswith(f"/exercises/{SLUG}/drawing")
    stage = ".drawing-page .drawing-stage"
    wait_until(
        big,
        f"document.querySelector('{stage} img')?.naturalWidth > 100 && document.querySelector('{stage}').dataset.zoom",
    )
    big.wait_for_timeout(300)
    state = _state(big, stage)
    width, height = SIZES[size]
    # the viewer takes the window below the header and the title, the whole sheet fitted in it
    assert state["stage"]["w"] >= width - 40 and state["stage"]["y"] + state["stage"]["h"] >= height - 20
    assert state["img"]["w"] == pytest.approx(state["stage"]["w"] - 2, abs=3) or state["img"][
        "h"
    ] == pytest.approx(state["stage"]["h"] - 2, abs=3)
    assert "G2 – Konturzug mit Kreisbogen" in big.inner_text("#drawing-title")
    assert big.is_visible("button:has-text('Drucken')") and big.is_visible("a:has-text('Zurück zur Aufgabe')")
    big.screenshot(path=str(SHOTS / f"drawing-page-{size}.png"))
    # the same zoom and moves as in the tab
    big.focus(stage)
    big.keyboard.press("+")
    assert _state(big, stage)["zoom"] == pytest.approx(state["zoom"] * 1.25, rel=0.01)
    big.keyboard.press("0")
    assert _state(big, stage)["zoom"] == pytest.approx(state["zoom"], rel=0.01)
    # printed: the sheet alone, on one A4 landscape page
    big.emulate_media(media="print")
    assert not big.is_visible("header") and not big.is_visible(".drawing-toolbar")
    printed = big.locator(f"{stage} img").bounding_box()
    assert printed is not None and printed["width"] == pytest.approx(297 / 25.4 * 96, abs=3)
    pdf = tmp_path / "drawing.pdf"
    big.pdf(path=str(pdf), prefer_css_page_size=True)
    if shutil.which("pdfinfo") and shutil.which("pdftoppm"):
        info = subprocess.run(["pdfinfo", str(pdf)], capture_output=True, text=True, check=True).stdout
        assert re.search(r"Pages:\s+1\n", info) and re.search(
            r"Page size:\s+841\.\d+ x 59[45]\.\d+ pts", info
        ), info
        if size == "laptop":
            subprocess.run(
                ["pdftoppm", "-png", "-r", "60", "-singlefile", str(pdf), str(SHOTS / "drawing-page-print")],
                check=True,
                timeout=60,
            )
    assert not errors, errors


def test_an_examples_drawing_page_without_login(server: str, browser: Any) -> None:  # noqa: F811
    """Free practice's examples: the same page for the example's drawing, no account needed; a turned part."""
    page = browser.new_context(viewport={"width": 1366, "height": 768}).new_page()
    errors = _watch(page)
    page.goto(f"{server}/examples/traub-10-schruppen-g71-g88/drawing")
    stage = ".drawing-page .drawing-stage"
    wait_until(page, f"document.querySelector('{stage} img')?.naturalWidth > 100")
    assert "Längsschruppen G71" in page.inner_text("#drawing-title")
    assert page.is_visible("a:has-text('Zum freien Üben')")
    page.screenshot(path=str(SHOTS / "drawing-page-example-laptop.png"))
    # an unknown example: a message, not an empty page
    page.goto(f"{server}/examples/gibt-es-nicht/drawing")
    page.wait_for_selector(".drawing-page .error")
    assert not errors or all("404" in e for e in errors), errors
