"""Turning on the practice page, in Chromium at the laptop size (1366×768): the TRAUB TX 8 D dialect from the
menu, its words highlighted (comments in parentheses, L parameters, brackets), German hover help that calls
U a radius value, no error for a clean turning program, and the 3D view's modal-state line with X as a
diameter. Screenshot: PALTRAINER_SCREENSHOTS, else tests/browser/screenshots/traub-practice-laptop.png."""

from __future__ import annotations

import os
from pathlib import Path

import pytest
from browser_helpers import steady_picture
from playwright.sync_api import TimeoutError as PlaywrightTimeout
from test_practice_page import CHROMIUM, server  # noqa: F401 (fixtures)
from test_viz_view import wait_until

pytestmark = [
    pytest.mark.skipif(CHROMIUM is None, reason="Chromium not installed (.ci/run installs Debian's package)")
]

SHOTS = Path(os.environ.get("PALTRAINER_SCREENSHOTS") or Path(__file__).parent / "screenshots")
PROGRAM = (
    "%\nO1 (ABSATZ DREHEN)\nN10 G59 Z200\nN20 G96 V200 T0101 M4\nN30 G92 S3000\nL1 = 36\n"
    "N40 G0 X44 Z2 M8\nN50 G1 Z0 F0.2\nN60 X-1.6\nN70 G0 X L1 Z2\nN80 G1 Z-[L1/2+2]\nN90 U4\n"
    "N100 Z-35\nN110 G0 X100 Z100 M9\nN120 M30\n"
)

# the colour of the first span in the editor whose text starts with `text` (the highlighting of that word)
COLOUR = """(text) => {
  const span = [...document.querySelectorAll('.cm-line span')].find((s) => s.textContent.startsWith(text));
  return span ? getComputedStyle(span).color : null;
}"""
# where a character of the document is on the screen (the editor is window.editor)
COORDS = """(needle) => {
  const view = window.editor;
  const pos = view.state.doc.toString().indexOf(needle);
  const c = view.coordsAtPos(pos);
  return { x: (c.left + c.right) / 2 + 2, y: (c.top + c.bottom) / 2 };
}"""


def test_turning_on_the_practice_page(server: str, browser: object) -> None:  # noqa: F811
    context = browser.new_context(viewport={"width": 1366, "height": 768})  # type: ignore[attr-defined]
    page = context.new_page()
    page.goto(f"{server}/practice")
    page.wait_for_selector(".cm-content")
    page.select_option("#dialect", "traub-tx8d")
    page.wait_for_url("**/practice?dialect=traub-tx8d")
    page.wait_for_selector(".cm-content")
    assert page.input_value("#dialect") == "traub-tx8d"
    # the dialect's sample: a turning program, clean
    page.wait_for_selector(".diag-none", timeout=20000)
    assert "T0101" in page.inner_text(".cm-content")

    page.click(".cm-content")
    page.keyboard.press("Control+a")
    page.keyboard.insert_text(PROGRAM)
    wait_until(page, "window.editor.state.doc.toString().includes('N90 U4')")
    page.wait_for_timeout(500)
    page.wait_for_selector(".diag-none", timeout=10000)
    assert not page.query_selector(".diag-error") and not page.query_selector(".cm-lintRange-error")

    # highlighting: a comment in parentheses is grey, G words keywords, L parameters their own colour
    comment, keyword = page.evaluate(COLOUR, "(ABSATZ"), page.evaluate(COLOUR, "G96")
    parameter, address = page.evaluate(COLOUR, "L1"), page.evaluate(COLOUR, "X")
    assert comment == "rgb(106, 115, 125)" and keyword == "rgb(11, 92, 173)"
    assert parameter == "rgb(5, 80, 174)" and address == "rgb(149, 56, 0)"

    # hover help in German from the dialect's table: U is a radius value
    at = page.evaluate(COORDS, "U4")
    page.mouse.move(at["x"], at["y"])
    tip = page.wait_for_selector(".pal-help", timeout=5000)
    assert tip.inner_text().startswith("U:") and "RADIUSWERT" in tip.inner_text(), tip.inner_text()
    page.mouse.move(5, 5)
    # no help for the words of a comment
    at = page.evaluate(COORDS, "DREHEN")
    page.mouse.move(at["x"], at["y"])
    page.wait_for_timeout(800)
    assert not page.query_selector(".pal-help")

    # off by itself here (software WebGL): the server's picture is the turned part in half section
    page.wait_for_selector("#viz-on")
    wait_until(page, "document.getElementById('viz-picture')?.dataset.text?.includes('N90 U4')")
    wait_until(page, "document.getElementById('viz-picture')?.naturalWidth > 100")
    assert "Halbschnitt" in page.inner_text(".viz-picture-note")
    SHOTS.mkdir(parents=True, exist_ok=True)
    page.screenshot(path=str(SHOTS / "traub-practice-picture-laptop.png"))

    # the 3D view: the lathe's drawing view, the modal state with X as a diameter
    page.click("#viz-on")
    wait_until(page, "Number(document.getElementById('viz-frame')?.dataset.segments || 0) > 5", timeout=30)
    page.frame_locator("#viz-frame").locator("canvas").first.wait_for(timeout=30000)
    assert page.is_visible(".viz-lathe-note") and page.is_visible(
        ".viz-legend"
    )  # deviation colours after grading
    page.click("#step-back")  # from the last piece (N110) to the one before: N100 Z-35 at Ø44, radius 22
    wait_until(page, "document.getElementById('modal-state').textContent.includes('Z-35')")
    state = page.inner_text("#modal-state")
    assert "X44 Z-35" in state and "X22" not in state and "G18" in state and " Y" not in state, state
    assert "S1447" in state  # G96 V200 at Ø44: 1446.86 1/min, shown whole
    assert "Durchmesser" in (page.get_attribute("#modal-state", "title") or "")
    steady_picture(page)  # viser's client has drawn (software rendering is slow)
    page.screenshot(path=str(SHOTS / "traub-practice-laptop.png"))
    context.close()


CYCLE = (
    "%\nO2 (SCHRUPPEN)\nN10 G59 Z200\nN20 G96 V200 T0101 M4\nN30 G92 S3000\nN40 G0 X60 Z2 M8\n"
    "N50 G71 P60 Q80 I0.5 K0.1 D2.5 F0.25\nN60 G0 X30 Z2\nN70 G1 Z-20 F0.2\nN80 X60\n"
    "N90 G0 X100 Z100 M9\nN100 M30\n"
)


def hover_note(browser: object, url: str, dialect: str, program: str, needle: str) -> str:
    """The cycle note of the hover help over `needle` once `program` is checked without a message."""
    context = browser.new_context(viewport={"width": 1366, "height": 768})  # type: ignore[attr-defined]
    page = context.new_page()
    page.goto(f"{url}/practice?dialect={dialect}")
    page.wait_for_selector(".cm-content")
    page.click(".cm-content")
    page.keyboard.press("Control+a")
    page.keyboard.insert_text(program)
    last = program.rstrip().splitlines()[-1]
    wait_until(page, f"window.editor.state.doc.toString().includes('{last}')")
    page.wait_for_selector(".diag-none", timeout=20000)
    # a loaded machine may miss a hover while it draws the 3D view (a 5 s wait failed once in CI): the pointer
    # leaves and comes again
    for _ in range(4):
        at = page.evaluate(COORDS, needle)
        page.mouse.move(0, 0)
        page.mouse.move(at["x"], at["y"])
        try:
            note = page.wait_for_selector(".help-cycle", timeout=5000)
        except PlaywrightTimeout:
            continue
        text = str(note.inner_text()) if note is not None else ""
        context.close()
        return text
    raise AssertionError(f"no hover help over {needle!r} after four tries")


def test_hover_over_a_cycle_block_tells_its_passes(server: str, browser: object) -> None:  # noqa: F811
    # Ø60 to Ø30 is 15 mm of stock less the 0.5 mm allowance, in passes of at most 2.5 mm: 6 passes
    note = hover_note(browser, server, "traub-tx8d", CYCLE, "G71 P60")
    assert note == "Zyklus G71: 6 Schnitte in diesem Programm", note


POCKET = (
    "N10 T2 M6\nN20 S2000 F300 M3\nN30 G0 X0 Y0 Z10\nN40 G72 ZI-5 LP40 BP30 D2 V2 RN8\n"
    "N50 G79 X50 Y40 Z0\nN60 G0 Z50\nN70 M30\n"
)


HOLES = (
    "N10 T3 M6\nN20 S1800 F180 M3\nN30 G0 X0 Y0 Z10\nN40 G81 ZI-10 V2\n"
    "N50 G77 IA50 JA50 R20 AN0 AI90 O4 Z0\nN60 G0 Z50\nN70 M30\n"
)


def test_hover_over_a_pal_cycle_call_names_its_definition(server: str, browser: object) -> None:  # noqa: F811
    # ZI-5 in levels of at most D2: 3 levels at the one point of G79
    note = hover_note(browser, server, "pal-mill", POCKET, "G79 X50")
    assert note == "Ruft den Zyklus G72 aus Zeile 4 auf: 1 Punkt, je 3 Schritte", note
    # G81 on a pitch circle of four holes, one step each
    note = hover_note(browser, server, "pal-mill", HOLES, "G77 IA50")
    assert note == "Ruft den Zyklus G81 aus Zeile 4 auf: 4 Punkte, je 1 Schritt", note
