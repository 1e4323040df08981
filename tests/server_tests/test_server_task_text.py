"""The task text and the blank as the exercise page gets them (GET /exercises/{slug}): Markdown rendered to a safe
subset of HTML on the server — bold, lists, inline code, https links — the same HTML the printed sheet shows; an
author's raw HTML or javascript: link stays text; the blank named as the workshop names it (a bar is no box)."""

from __future__ import annotations

import re

from server_helpers import Api, auth, builtin_as_read

from core.exercises import EXERCISES_DIR, load_exercise
from core.sheet import task_sheet_html

HOSTILE = (
    'Fräsen Sie **die Nut**.\n\n<img src=x onerror="alert(1)">\n\n'
    "[Handbuch](javascript:alert(document.cookie)) [Daten](data:text/html,<script>alert(1)</script>) "
    "[Norm](https://example.org/din-406) <script>alert(2)</script> `G1 X10`\n\n"
    "- erster Punkt\n- zweiter Punkt\n"
)


def test_a_turning_task_reads_as_formatted_text_and_names_its_bar(api: Api) -> None:
    ex = builtin_as_read(api, "traub-tx8d/traub-10-schruppen-g71-g88.yaml")
    html = ex["task_html_de"]
    assert "**" not in html and "<strong>G88</strong>" in html
    assert html.count("<li>") >= 6 and "<ul>" in html  # the list items, not one paragraph
    assert (
        "<strong>Ø100 × 160 mm</strong>" in html
        and "bar <strong>Ø100 × 160 mm</strong>" in ex["task_html_en"]
    )
    assert ex["blank_de"] == "Rohteil: Stange Ø100 × 160 mm, 30 mm im Futter"
    assert ex["blank_en"] == "Blank: bar Ø100 × 160 mm, 30 mm in the chuck"
    assert ex["zero_de"] == "Werkstücknullpunkt: Drehmitte auf der Stirnfläche (Z0)"
    assert "100 × 100" not in ex["blank_de"]
    assert ex["blank_in_task_de"] and ex["blank_in_task_en"]  # the text says it: the page prints it once


def test_a_tube_and_a_milling_blank(api: Api) -> None:
    tube = builtin_as_read(api, "traub-tx8d/traub-11-innen-g71-g89.yaml")
    assert tube["blank_de"] == "Rohteil: Rohr Ø140 × Ø30 × 100 mm, 20 mm im Futter"
    milled = builtin_as_read(api, "pal-mill/pal-13-g41-aussenkontur.yaml")
    assert (
        milled["blank_de"] == "Rohteil: 70 × 100 × 20 mm" and milled["blank_en"] == "Blank: 70 × 100 × 20 mm"
    )
    assert milled["zero_de"] == "Werkstücknullpunkt: linke untere Ecke der Oberseite"


def test_raw_html_and_foreign_links_in_a_task_stay_text(api: Api) -> None:
    owner = api.user("instructor")
    made = api.exercise(owner, task_de=HOSTILE, task_en="", stock={"min": [0, 0, -30], "max": [80, 70, 0]})
    for reader in (owner, api.user()):
        ex = api.client.get(f"/api/v1/exercises/{made['slug']}", headers=auth(reader)).json()
        html = ex["task_html_de"]
        assert "<img" not in html and "&lt;img src=x onerror=" in html
        assert "<script" not in html and "&lt;script&gt;alert(2)&lt;/script&gt;" in html
        assert "javascript:" not in re.findall(r'href="([^"]*)"', html) and "[Handbuch](javascript:" in html
        assert "data:" not in " ".join(re.findall(r'href="([^"]*)"', html))
        assert re.findall(r"<a [^>]*>", html) == [
            '<a href="https://example.org/din-406" rel="noopener noreferrer" target="_blank">'
        ]
        assert (
            "<strong>die Nut</strong>" in html and "<code>G1 X10</code>" in html and html.count("<li>") == 2
        )
        assert ex["task_html_en"] == html  # no English text: the German one
        assert ex["blank_de"] == "Rohteil: 80 × 70 × 30 mm" and not ex["blank_in_task_de"]


def test_the_page_and_the_sheet_show_the_same_task(api: Api) -> None:
    ex = builtin_as_read(api, "traub-tx8d/traub-10-schruppen-g71-g88.yaml")
    sheet = task_sheet_html(
        [load_exercise(EXERCISES_DIR / "traub-tx8d/traub-10-schruppen-g71-g88.yaml")], "de"
    )
    assert ex["task_html_de"].strip() in sheet
    assert "**" not in sheet and not re.search(r"\b(null|None|undefined|NaN)\b", sheet)
