"""What an exercise's page and its printed sheet say in words: the task as HTML, the blank and the workpiece zero.

One place for both, so that the page (server/tasktext.py hands these to it) and the PDF show the same: the task's
Markdown as a safe subset of HTML (paragraphs, bold and italic, lists, inline code, links with https only) made by
markdown-it-py with raw HTML switched off, so that whatever an author types is shown as text; the blank as the
workshop names it — "Stange Ø100 × 160 mm", "Rohr Ø140 × Ø30 × 100 mm", "80 × 70 × 30 mm" — and whether the task
text already states it (then it is not printed a second time).
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping
from functools import lru_cache
from typing import Any

from markdown_it import MarkdownIt

from core.drawing.frame import value

# block and inline rules on top of markdown-it's "zero" preset (which has paragraphs and text only)
RULES = ["list", "emphasis", "backticks", "link", "escape", "entity", "newline"]
SAFE_LINK = re.compile(r"^https://[^\s<>\"']+$", re.IGNORECASE)

LABELS = {
    "de": {
        "blank": "Rohteil",
        "bar": "Stange",
        "tube": "Rohr",
        "chuck": "{c} mm im Futter",
        "zero": "Werkstücknullpunkt",
    },
    "en": {
        "blank": "Blank",
        "bar": "bar",
        "tube": "tube",
        "chuck": "{c} mm in the chuck",
        "zero": "Workpiece zero",
    },
}
ZERO = {
    "mill": {"de": "linke untere Ecke der Oberseite", "en": "lower left corner of the top face"},
    "lathe": {"de": "Drehmitte auf der Stirnfläche (Z0)", "en": "centre of the front face (Z0)"},
}


def _markdown() -> MarkdownIt:
    md = MarkdownIt("zero", {"html": False, "linkify": False, "typographer": False}).enable(RULES)
    md.validateLink = lambda url: bool(SAFE_LINK.match(url.strip()))  # type: ignore[method-assign]

    def link_open(renderer: Any, tokens: Any, idx: int, options: Any, env: Any) -> str:
        tokens[idx].attrSet("rel", "noopener noreferrer")
        tokens[idx].attrSet("target", "_blank")
        return str(renderer.renderToken(tokens, idx, options, env))

    md.add_render_rule("link_open", link_open)
    return md


_MD = _markdown()


@lru_cache(maxsize=512)
def task_html(markdown: str) -> str:
    """The task's Markdown as HTML: paragraphs, **bold**, *italic*, bullet and numbered lists, `code`, and links
    whose address is https. Raw HTML, images and other link schemes stay text, escaped."""
    return str(_MD.render(markdown or ""))


# ---- the blank --------------------------------------------------------------------------------------------


def _number(v: Any) -> float | None:
    try:
        f = float(v)
    except (TypeError, ValueError):
        return None
    return f if math.isfinite(f) else None


def _sizes(
    stock: Mapping[str, Any] | None, blank: Mapping[str, Any] | None
) -> tuple[str, list[float]] | None:
    """("bar" | "tube" | "box", the blank's sizes: Ø and length; Ø, bore Ø and length; X, Y and Z)."""
    if blank:
        d, i, length = (
            _number(blank.get("diameter")),
            _number(blank.get("inner_diameter")) or 0.0,
            _number(blank.get("length")),
        )
        if d and length:
            return ("tube", [d, i, length]) if i > 0 else ("bar", [d, length])
    if stock:
        lo, hi = stock.get("min"), stock.get("max")
        if isinstance(lo, list | tuple) and isinstance(hi, list | tuple) and len(lo) == len(hi) == 3:
            ends = [_number(b) for b in hi]
            starts = [_number(a) for a in lo]
            if all(v is not None for v in ends + starts):
                return "box", [
                    round(b - a, 6)  # type: ignore[operator]
                    for a, b in zip(starts, ends, strict=True)
                ]
    return None


def blank_size(stock: Mapping[str, Any] | None, blank: Mapping[str, Any] | None, lang: str) -> str:
    """The blank's size as a drawing's title block writes it: "Ø100 × 160", "Ø140 × Ø30 × 100", "80 × 70 × 30";
    "" where there is none."""
    found = _sizes(stock, blank)
    if found is None:
        return ""
    kind, sizes = found
    if kind == "box":
        return " × ".join(value(v, lang) for v in sizes)
    return " × ".join(("Ø" if k < len(sizes) - 1 else "") + value(v, lang) for k, v in enumerate(sizes))


def blank_text(stock: Mapping[str, Any] | None, blank: Mapping[str, Any] | None, lang: str) -> str:
    """ "Rohteil: Stange Ø100 × 160 mm, 30 mm im Futter" / "Blank: 80 × 70 × 30 mm": the page's and the sheet's
    line for the blank; "" where the exercise has none."""
    lang = "en" if lang == "en" else "de"
    labels = LABELS[lang]
    found = _sizes(stock, blank)
    if found is None:
        return ""
    kind = found[0]
    text = (
        f"{labels['blank']}: "
        + (f"{labels[kind]} " if kind != "box" else "")
        + f"{blank_size(stock, blank, lang)} mm"
    )
    chuck = _number((blank or {}).get("chuck_length"))
    if kind != "box" and chuck:
        text += ", " + labels["chuck"].format(c=value(chuck, lang))
    return text


def zero_text(stock: Mapping[str, Any] | None, blank: Mapping[str, Any] | None, lang: str) -> str:
    """ "Werkstücknullpunkt: Drehmitte auf der Stirnfläche (Z0)": where the exercise puts the workpiece zero."""
    lang = "en" if lang == "en" else "de"
    source = blank if blank else stock
    zero = (source or {}).get("zero")
    where = ""
    if isinstance(zero, Mapping):
        where = str(zero.get(lang) or zero.get("de") or "")
    where = where or ZERO["lathe" if blank else "mill"][lang]
    return f"{LABELS[lang]['zero']}: {where}"


def states_blank(text: str, stock: Mapping[str, Any] | None, blank: Mapping[str, Any] | None) -> bool:
    """Whether a task text states the blank's size itself (as the built-in tasks do: "Rohteil 80 × 70 × 30 mm",
    "Stange **Ø100 × 160 mm**"): then the page and the sheet do not print it a second time."""
    found = _sizes(stock, blank)
    if found is None or not text:
        return False
    kind, sizes = found
    plain = re.sub(r"[*_`]", "", text).replace("\u00a0", " ").replace("\u202f", " ")

    def number(v: float) -> str:
        return value(v, "de").replace(",", "[.,]")

    times = r"\s*[×xX]\s*"
    chains = [sizes] if kind != "tube" else [sizes, [sizes[0], sizes[2]]]
    for chain in chains:
        pattern = times.join(("Ø?\\s*" if kind != "box" else "") + number(v) for v in chain)
        if re.search(rf"(?<![\d.,]){pattern}(?![\d])", plain):
            return True
    return False
