"""Numbers in the grader's texts: one format per language for every quantity (volumes, distances, diameters).

German: thousands with a point, decimals with a comma ("2.803,5 mm³", "1,95 mm"); English: thousands with a
comma, decimals with a point ("2,803.5 mm³"). Addresses of a program keep the form a program writes them in
(`F0.15`, `X56.4`, `Z-2`): they are words the trainee types, not quantities.
"""

from __future__ import annotations

import math


def number(value: float, lang: str = "de", decimals: int = 2, trim: bool = True) -> str:
    """`value` rounded to `decimals`; `trim`: without trailing zeros (1,5 rather than 1,50; 2 rather than 2,00)."""
    if not math.isfinite(value):
        return "–"
    text = f"{value:,.{decimals}f}"
    if trim and "." in text:
        text = text.rstrip("0").rstrip(".")
    if text in ("-0", "-0.0", ""):
        text = "0"
    if lang == "de":
        text = text.replace(",", "\x00").replace(".", ",").replace("\x00", ".")
    return text


def de(value: float, decimals: int = 2, trim: bool = True) -> str:
    return number(value, "de", decimals, trim)


def en(value: float, decimals: int = 2, trim: bool = True) -> str:
    return number(value, "en", decimals, trim)


def volume(value: float, lang: str = "de") -> str:
    """A volume in mm³ with one decimal: "2.803,5 mm³"."""
    return f"{number(value, lang, 1, trim=False)} mm³"


def mm(value: float, lang: str = "de") -> str:
    """A length in mm to a hundredth, without trailing zeros: "1,95 mm", "12,5 mm"."""
    return f"{number(value, lang, 2)} mm"


def word(value: float, decimals: int = 3) -> str:
    """A value as an address of a program writes it: point decimals, no trailing zeros (X56.4, Z-2, F0.15)."""
    text = f"{value:.{decimals}f}".rstrip("0").rstrip(".")
    return "0" if text in ("-0", "") else text
