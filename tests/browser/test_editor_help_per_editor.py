"""Each editor keeps its own dialect's help (help.js: the facet `editorHelp` in the editor's state): on one page a PAL
milling editor (free practice) and a TRAUB turning editor mounted after it each show their own dialect's hover
text and completion list — the one mounted last does not take the other's help over, nor its comment syntax
(a word after ";" is a comment in PAL, not in TRAUB). And both languages of the pages' texts come from the one
text table per language: the practice page in German, then in English. Screenshots (laptop and tablet):
PALTRAINER_SCREENSHOTS, else tests/browser/screenshots/ (help-two-editors-*: each editor's hover open)."""

from __future__ import annotations

import os
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
from browser_helpers import NEEDS_CHROMIUM, completion_labels, running_server

pytestmark = [NEEDS_CHROMIUM]

SHOTS = Path(os.environ.get("PALTRAINER_SCREENSHOTS") or Path(__file__).parent / "screenshots")
SIZES = {"laptop": (1366, 768), "tablet": (768, 1024)}
PAL = "N10 T1 TC1 M6\nN20 S1200 F150 M3\nN30 G41 G0 X70 Y84 Z2 ; G41 X\nN40 G40\n"
TRAUB = "%\nO1 (ABSATZ)\nN10 G96 V200 T0101 M4\nN20 G92 S3000\nN30 G41 G1 X36 Z2 F0.2\nN40 G40\nN50 M30\n"
# the second editor: fixed at the bottom left of the window, over the page (the page's own layout stays as it is)
MOUNT_TRAUB = """async (text) => {
  const box = document.createElement("div");
  box.id = "second-editor";
  box.style.cssText = "position:fixed;left:8px;bottom:8px;width:520px;height:230px;z-index:50;background:#fff;"
    + "border:2px solid #0b5cad;overflow:auto";
  document.body.append(box);
  await window.PalTrainer.mountEditor(box, { text, dialect: "traub-tx8d" });
}"""
FIRST = "#editor .cm-content"
SECOND = "#second-editor .cm-content"


@pytest.fixture(scope="module")
def server(tmp_path_factory: pytest.TempPathFactory) -> Iterator[str]:
    with running_server(tmp_path_factory.mktemp("data")) as url:
        yield url


def _two_editors(browser: Any, server: str, size: tuple[int, int], lang: str = "de") -> tuple[Any, Any]:
    context = browser.new_context(viewport={"width": size[0], "height": size[1]})
    page = context.new_page()
    page.add_init_script(f"localStorage.setItem('paltrainer-lang', '{lang}')")
    page.goto(f"{server}/practice")
    page.wait_for_selector(FIRST)
    page.click(FIRST)
    page.keyboard.press("Control+a")
    page.keyboard.insert_text(PAL)
    page.evaluate(MOUNT_TRAUB, TRAUB)
    page.wait_for_selector(SECOND)
    return context, page


def _point(page: Any, editor: str, line: int, word: str, occurrence: int = 0) -> None:
    """The mouse onto the `occurrence`-th `word` in line `line` (from 0) of an editor (no hover open before)."""
    page.mouse.move(0, 0)
    page.wait_for_selector(".pal-help", state="detached")
    box = page.evaluate(
        """([selector, line, word, occurrence]) => {
      const node = document.querySelectorAll(selector + " .cm-line")[line];
      const walker = document.createTreeWalker(node, NodeFilter.SHOW_TEXT);
      let seen = 0;
      for (let text = walker.nextNode(); text; text = walker.nextNode()) {
        let at = text.textContent.indexOf(word);
        while (at >= 0) {
          if (seen === occurrence) {
            const range = document.createRange();
            range.setStart(text, at + 1);
            range.setEnd(text, at + 2);
            const r = range.getBoundingClientRect();
            return { x: r.x + r.width / 2, y: r.y + r.height / 2 };
          }
          seen += 1;
          at = text.textContent.indexOf(word, at + 1);
        }
      }
      return null;
    }""",
        [editor, line, word, occurrence],
    )
    assert box, (editor, line, word, occurrence)
    page.mouse.move(box["x"], box["y"])


def _hover(page: Any, editor: str, line: int, word: str, occurrence: int = 0) -> str:
    """The hover text over a word (see _point)."""
    _point(page, editor, line, word, occurrence)
    return str(page.wait_for_selector(".pal-help", timeout=5000).inner_text())


def _no_hover(page: Any, editor: str, line: int, word: str, occurrence: int = 0) -> bool:
    """No hover text over a word: none a while after the hover's delay (CodeMirror's is 300 ms)."""
    _point(page, editor, line, word, occurrence)
    page.wait_for_timeout(1000)
    return page.locator(".pal-help").count() == 0


def _type_at_end(page: Any, editor: str, text: str) -> list[str]:
    page.keyboard.press("Escape")
    page.click(f"{editor} .cm-line >> nth=-1")
    page.keyboard.press("Control+End")
    page.keyboard.press("Enter")
    page.keyboard.type(text)
    return completion_labels(page)


def test_each_editor_hovers_with_its_own_dialect(server: str, browser: Any) -> None:
    context, page = _two_editors(browser, server, SIZES["laptop"])
    # the PAL editor, mounted first, keeps PAL's G41 after the TRAUB editor has loaded TRAUB's table
    pal = _hover(page, FIRST, 2, "G41")
    assert pal and "G41: Fräserradiuskorrektur links der Kontur" in pal
    assert "Regel: Werkzeug links der Kontur" in pal
    traub = _hover(page, SECOND, 4, "G41")
    assert traub and "G41: SRK ein, Werkzeug links der Bahn" in traub, traub
    assert "Fräserradiuskorrektur" not in traub
    # G92 is a TRAUB code (speed limit) and no PAL code: its help only in the TRAUB editor
    g92 = _hover(page, SECOND, 3, "G92")
    assert g92 and "Drehzahlbegrenzung" in g92
    # and the PAL editor again, after hovering in the other one
    pal = _hover(page, FIRST, 2, "G41")
    assert pal and "Fräserradiuskorrektur links der Kontur" in pal
    # comments: after ";" PAL has a comment (no help there); TRAUB's comments are in parentheses
    assert _no_hover(page, FIRST, 2, "G41", occurrence=1)
    context.close()


def test_each_editor_completes_with_its_own_dialect(server: str, browser: Any) -> None:
    context, page = _two_editors(browser, server, SIZES["laptop"])
    # PAL: G45, G47, G48 are PAL's (approach and departure); TRAUB has none of them
    labels = _type_at_end(page, FIRST, "N50 G4")
    assert {"G45", "G47", "G48"} <= set(labels), labels
    # TRAUB: G92 (speed limit) is TRAUB's; PAL has no G92
    assert "G92" in _type_at_end(page, SECOND, "N60 G9")
    assert "G92" not in _type_at_end(page, FIRST, "N50 G9")
    assert not {"G45", "G47", "G48"} & set(_type_at_end(page, SECOND, "N70 G4")), (
        "PAL's codes in TRAUB's list"
    )
    # back in the PAL editor: still PAL's list
    labels = _type_at_end(page, FIRST, "N70 G4")
    assert {"G45", "G47", "G48"} <= set(labels), labels
    context.close()


@pytest.mark.parametrize("size", SIZES)
def test_two_editors_in_both_languages(server: str, browser: Any, size: str) -> None:
    """The hover's own words (Pflicht, Beispiel, Regel / Required, Example, Remember) and the page's texts come
    from the text table of the chosen language; screenshots of the two editors with a hover open."""
    for lang, words, title in (
        ("de", ("Pflicht:", "Beispiel:", "Regel:"), "Freies Üben"),
        ("en", ("Required:", "Example:", "Remember:"), "Free practice"),
    ):
        context, page = _two_editors(browser, server, SIZES[size], lang)
        assert title in page.title()
        SHOTS.mkdir(parents=True, exist_ok=True)
        text = _hover(page, SECOND, 4, "G41")
        assert text and ("SRK" in text if lang == "de" else "G41:" in text)
        page.screenshot(path=str(SHOTS / f"help-two-editors-{lang}-{size}-traub.png"))
        pal = _hover(page, FIRST, 2, "G41")
        assert pal and any(w in pal for w in words), pal
        page.screenshot(path=str(SHOTS / f"help-two-editors-{lang}-{size}-pal.png"))
        context.close()
