"""CSV we write: one writer for every export, safe to open in a spreadsheet and made for German Excel."""

from __future__ import annotations

import csv
import datetime as dt
import io
from collections.abc import Iterable, Sequence
from zoneinfo import ZoneInfo

# A cell starting with one of these is read as a formula by Excel, LibreOffice and Google Sheets (OWASP: CSV
# injection); a tab or line break before one hides it. The full-width forms are read as formulas too.
FORMULA_START = ("=", "+", "-", "@", "\t", "\r", "\n", "\uff1d", "\uff0b", "\uff0d", "\uff20")
BERLIN = ZoneInfo("Europe/Berlin")
BOM = "\ufeff"  # German Excel reads UTF-8 only with it (else the umlauts break)


def spreadsheet_safe(value: object) -> object:
    """A text cell a spreadsheet would read as a formula, with a leading ' that makes it text; numbers stay."""
    if isinstance(value, str) and value.startswith(FORMULA_START):
        return "'" + value
    return value


def csv_text(header: Sequence[str], rows: Iterable[Sequence[object]], delimiter: str = ",") -> str:
    """The CSV of a header and rows, every text cell made spreadsheet-safe (`delimiter` ";": German Excel)."""
    out = io.StringIO()
    writer = csv.writer(out, delimiter=delimiter)
    writer.writerow([spreadsheet_safe(cell) for cell in header])
    writer.writerows([spreadsheet_safe(cell) for cell in row] for row in rows)
    return out.getvalue()


def excel_cell(value: object) -> object:
    """A cell as German Excel reads it: a decimal comma in numbers with a fraction, a time as local time in
    Germany to the second (a stored time without a zone is UTC); None empty; everything else as it is."""
    if value is None:
        return ""
    if isinstance(value, float):
        text = f"{value:.6f}".rstrip("0").rstrip(".")
        return (text if text not in ("-0", "") else "0").replace(".", ",")
    if isinstance(value, dt.datetime):
        moment = value if value.tzinfo is not None else value.replace(tzinfo=dt.UTC)
        return moment.astimezone(BERLIN).strftime("%d.%m.%Y %H:%M:%S")
    return value


def excel_csv(header: Sequence[str], rows: Iterable[Sequence[object]]) -> str:
    """Every CSV the server offers: `;` between cells, UTF-8 with a byte-order mark, decimal commas and German
    local time (excel_cell), every text cell spreadsheet-safe."""
    return BOM + csv_text(header, ([excel_cell(cell) for cell in row] for row in rows), delimiter=";")
