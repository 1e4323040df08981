"""The editor in a real browser (Debian's Chromium driven by Playwright) against a server on 127.0.0.1: help from
the dialect's code table — the hover of a G/M code names it, lists the addresses it needs and takes with their
units, an example block and the rule to remember; completion narrows by prefix (G4 → G4, G40 … G48) in numeric
order; Enter at the end of a line makes a new line unless the list was opened with Ctrl+Space — and the locked
lines of "complete the program" exercises, which typing does not change and which say why."""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

import pytest
from browser_helpers import NEEDS_CHROMIUM, PASSWORD, completion_labels, running_server

pytestmark = [NEEDS_CHROMIUM]


@pytest.fixture(scope="module")
def server(tmp_path_factory: pytest.TempPathFactory) -> Iterator[str]:
    with running_server(tmp_path_factory.mktemp("data"), [("azubi", "student")]) as url:
        yield url


PROGRAM = "N10 T1 TC1 M6\nN20 S1200 F150 M3\nN30 G41 G0 X70 Y84 Z2\nN40 G2 X56.4 Y10 R21 RN5\nN50 G40\n"


@pytest.fixture
def editor(server: str, browser: Any) -> Iterator[Any]:
    context = browser.new_context()
    page = context.new_page()
    page.goto(f"{server}/practice")
    page.wait_for_selector(".cm-content")
    page.click(".cm-content")
    page.keyboard.press("Control+a")
    page.keyboard.insert_text(PROGRAM)
    # the server's first answer (a new worker may take seconds) redraws the messages: wait for it
    page.wait_for_selector(".cm-lintRange", state="attached", timeout=20000)
    yield page
    context.close()


def _hover(page: Any, line: int, word: str) -> str:
    page.mouse.move(0, 0)
    page.wait_for_selector(".pal-help", state="detached")
    page.hover(f".cm-line >> nth={line} >> text={word}")
    return str(page.wait_for_selector(".pal-help", timeout=5000).inner_text())


def test_hover_on_g41_names_the_rule_and_an_example(editor: Any) -> None:
    text = _hover(editor, 2, "G41")
    assert "G41: Fräserradiuskorrektur links der Kontur" in text
    assert "Regel: Werkzeug links der Kontur, in Vorschubrichtung gesehen" in text
    assert "Beispiel: N40 G41 G0 X70 Y84" in text


def test_hover_on_g2_lists_addresses_with_units(editor: Any) -> None:
    text = _hover(editor, 3, "G2")
    assert "Kreisinterpolation im Uhrzeigersinn" in text
    assert "Pflicht:" in text and "R (mm)" in text and "AO (°)" in text
    assert "Optional:" in text and "RN (mm)" in text
    assert "Beispiel: N40 G2 X56.4 Y10 I-20 J6.4" in text


def test_hover_on_rn_shows_its_sign_rule(editor: Any) -> None:
    text = _hover(editor, 3, "RN5")
    assert "Regel: + Rundung, − Fase" in text and "Einheit: mm" in text


def _doc(page: Any) -> list[str]:
    return [str(x) for x in page.eval_on_selector_all(".cm-line", "els => els.map(e => e.textContent)")]


def test_completion_narrows_by_prefix_in_numeric_order(editor: Any) -> None:
    editor.keyboard.press("Control+End")
    editor.keyboard.type("N60 G")
    labels = completion_labels(editor)
    assert labels[:8] == ["G0", "G1", "G2", "G3", "G4", "G9", "G10", "G11"]
    editor.keyboard.type("4")
    editor.wait_for_timeout(300)
    assert completion_labels(editor) == ["G4", "G40", "G41", "G42", "G45", "G46", "G47", "G48"]


def test_enter_at_line_end_starts_a_new_line(editor: Any) -> None:
    editor.keyboard.press("Control+End")
    editor.keyboard.type("N60 G4")
    completion_labels(editor)  # the list is open by itself
    editor.keyboard.press("Enter")
    editor.keyboard.type("N70")
    assert _doc(editor)[-2:] == ["N60 G4", "N70"]


def test_enter_takes_the_entry_after_ctrl_space(editor: Any) -> None:
    editor.keyboard.press("Control+End")
    editor.keyboard.type("N60 G1")
    completion_labels(editor)
    editor.keyboard.press("Escape")
    editor.wait_for_selector(".cm-tooltip-autocomplete", state="detached")
    editor.keyboard.press("Control+Space")
    assert completion_labels(editor)[:2] == ["G1", "G10"]
    editor.keyboard.press("ArrowDown")
    editor.keyboard.press("Enter")
    assert _doc(editor)[-2:] == ["N50 G40", "N60 G10"]


def test_locked_lines_stay_and_say_why(server: str, browser: Any) -> None:
    context = browser.new_context()
    page = context.new_page()
    page.goto(f"{server}/exercises/ergaenzen-01-kreisbogen")
    page.wait_for_url("**/login?next=*")
    page.fill("input[name=username]", "azubi")
    page.fill("input[name=password]", PASSWORD)
    page.click("button[type=submit]")
    page.wait_for_selector(".cm-content")
    start = _doc(page)
    assert start[1] == "N10 T1 TC1 M6" and start[7] == ""
    assert page.locator(".cm-locked-line").count() == 10  # lines 1–7 and 9–11; line 8 is the trainee's
    assert (
        page.eval_on_selector_all(
            ".cm-lock-gutter .cm-gutterElement",
            """els => els.filter(
        e => e.textContent === "🔒" && e.style.visibility !== "hidden").length""",
        )
        == 10
    )  # (not the spacer)
    # typing into a locked line does nothing and says why
    page.click(".cm-line >> nth=1")
    page.keyboard.press("End")
    page.keyboard.type("X")
    notice = page.wait_for_selector(".cm-locked-notice", timeout=5000)
    assert "Zeile 2 ist vorgegeben" in notice.inner_text()
    page.keyboard.press("Home")
    page.keyboard.press("Backspace")
    page.keyboard.press("Delete")
    assert _doc(page) == start
    # the free line takes the missing block, and the notice goes
    page.click(".cm-line >> nth=7")
    page.keyboard.type("N70 G2 X56.4 Y10 R21")
    page.wait_for_selector(".cm-locked-notice", state="detached")
    # (the pointer rested where the text was typed: its word's help goes when it moves away)
    page.mouse.move(5, 5)
    page.wait_for_selector(".cm-tooltip-hover", state="detached")
    # a new line after a locked one is fine; the locks move with their lines
    page.click(".cm-line >> nth=6")
    page.keyboard.press("End")
    page.keyboard.press("Enter")
    page.keyboard.type("N65 G1 X50")
    lines = _doc(page)
    assert lines[6:9] == ["N60 G1 Y23.6", "N65 G1 X50", "N70 G2 X56.4 Y10 R21"]
    locked = page.eval_on_selector_all(".cm-locked-line", "els => els.map(e => e.textContent)")
    assert locked[-4:] == ["N60 G1 Y23.6", "N80 G1 X-14", "N90 G40", "N100 G0 X250 Y150 Z250 M30"]
    context.close()
