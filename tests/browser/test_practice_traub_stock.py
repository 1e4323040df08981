"""The turned part in the 3D view of the practice page (TRAUB TX 8 D), in Chromium: a tube entered as the blank
(with a decimal comma), the 3D view switched on, playback, the half section that cuts the part open.
Screenshots at 1366×768 and 768×1024: PALTRAINER_SCREENSHOTS, else tests/browser/screenshots/."""

from __future__ import annotations

import os
from pathlib import Path

import pytest
from browser_helpers import steady_picture
from test_practice_page import CHROMIUM, server  # noqa: F401 (fixtures)
from test_viz_view import wait_until

pytestmark = [
    pytest.mark.skipif(CHROMIUM is None, reason="Chromium not installed (.ci/run installs Debian's package)")
]

SHOTS = Path(os.environ.get("PALTRAINER_SCREENSHOTS") or Path(__file__).parent / "screenshots")
# a shoulder Ø36 with a rounding, a groove Ø30 and Ø44 behind it, in a tube with a bore of Ø20
PROGRAM = (
    "%\nO1 (ABSATZ UND EINSTICH)\nN10 G59 Z200\nN20 G96 V200 T0101 M4\nN30 G92 S3000\n"
    "N40 G0 X44 Z2 M8\nN50 G1 Z0 F0.2\nN60 X18\nN70 G0 X36 Z2\nN80 G1 Z-20 R2\nN90 X44\nN100 Z-26\n"
    "N110 X30 Z-30\nN120 Z-34\nN130 X44 Z-38\nN140 Z-45\nN150 G0 X100 Z100 M9\nN160 M30\n"
)


def _practice(server: str, browser: object, width: int, height: int) -> object:  # noqa: F811
    context = browser.new_context(viewport={"width": width, "height": height})  # type: ignore[attr-defined]
    page = context.new_page()
    page.goto(f"{server}/practice?dialect=traub-tx8d")
    page.wait_for_selector(".cm-content")
    page.click(".cm-content")
    page.keyboard.press("Control+a")
    page.keyboard.insert_text(PROGRAM)
    wait_until(page, "window.editor.state.doc.toString().includes('N130 X44')")
    return page


def _blank(page: object, diameter: str, bore: str, length: str) -> None:
    page.click("#setup-box summary")  # type: ignore[attr-defined]
    for name, value in (("diameter", diameter), ("bore", bore), ("length", length)):
        page.fill(f"#blank-{name}", value)  # type: ignore[attr-defined]
        page.press(f"#blank-{name}", "Tab")  # type: ignore[attr-defined]


def _turn_on(page: object) -> None:
    page.click("#viz-on")  # type: ignore[attr-defined]
    wait_until(page, "Number(document.getElementById('viz-frame')?.dataset.segments || 0) > 10", timeout=30)
    page.frame_locator("#viz-frame").locator("canvas").first.wait_for(timeout=30000)  # type: ignore[attr-defined]


def test_turned_part_blank_playback_and_half_section(server: str, browser: object) -> None:  # noqa: F811
    page = _practice(server, browser, 1366, 768)
    # the blank: a tube Ø50 with a bore Ø20, 70,5 mm long (a decimal comma)
    _blank(page, "50", "20", "70,5")
    assert page.inner_text("#blank-form .error") == ""  # type: ignore[attr-defined]
    # an impossible bore is refused with a German message, the valid blank stays
    page.fill("#blank-bore", "60")  # type: ignore[attr-defined]
    page.press("#blank-bore", "Tab")  # type: ignore[attr-defined]
    assert "kleiner als D" in page.inner_text("#blank-form .error")  # type: ignore[attr-defined]
    page.fill("#blank-bore", "20")  # type: ignore[attr-defined]
    page.press("#blank-bore", "Tab")  # type: ignore[attr-defined]
    page.click("#setup-box summary")  # type: ignore[attr-defined]

    _turn_on(page)
    wait_until(page, "document.getElementById('viz-blank').textContent.includes('70,5')")
    assert page.inner_text("#viz-blank") == "Rohteil: Ø50 × 70,5 mm, Bohrung Ø20"  # type: ignore[attr-defined]
    assert page.is_visible("#viz-half") and page.get_attribute("#viz-half", "aria-pressed") == "false"  # type: ignore[attr-defined]
    steady_picture(page)
    SHOTS.mkdir(parents=True, exist_ok=True)
    page.screenshot(path=str(SHOTS / "traub-stock-laptop.png"))  # type: ignore[attr-defined]

    # playback: a click on a block in the editor shows the part after it (the groove's first flank, N110)
    page.click(".cm-line:has-text('N110')")  # type: ignore[attr-defined]
    wait_until(page, "document.getElementById('modal-state').textContent.includes('X30 Z-30')", timeout=20)
    steady_picture(page)
    page.screenshot(path=str(SHOTS / "traub-stock-playback-laptop.png"))  # type: ignore[attr-defined]
    page.click("#play")  # type: ignore[attr-defined]
    wait_until(
        page,
        "document.getElementById('playhead').value === document.getElementById('playhead').max",
        timeout=30,
    )

    # the half section: the part cut open along the drawing plane, the bore in sight
    page.click("#viz-half")  # type: ignore[attr-defined]
    wait_until(page, "document.getElementById('viz-half').getAttribute('aria-pressed') === 'true'")
    steady_picture(page)
    page.screenshot(path=str(SHOTS / "traub-stock-half-laptop.png"))  # type: ignore[attr-defined]
    page.click("#viz-half")  # type: ignore[attr-defined]
    wait_until(page, "document.getElementById('viz-half').getAttribute('aria-pressed') === 'false'")
    page.context.close()  # type: ignore[attr-defined]

    # the tablet (768×1024): the same tube, cut open
    page = _practice(server, browser, 768, 1024)
    _blank(page, "50", "20", "70,5")
    page.click("#setup-box summary")  # type: ignore[attr-defined]
    _turn_on(page)
    wait_until(page, "document.getElementById('viz-blank').textContent.includes('70,5')")
    page.click("#viz-half")  # type: ignore[attr-defined]
    wait_until(page, "document.getElementById('viz-half').getAttribute('aria-pressed') === 'true'")
    page.locator("#viz").scroll_into_view_if_needed()  # type: ignore[attr-defined]
    steady_picture(page)
    page.screenshot(path=str(SHOTS / "traub-stock-half-tablet.png"))  # type: ignore[attr-defined]
    page.context.close()  # type: ignore[attr-defined]
