"""One form of address, as the PAL exam papers use it: "Fräsen Sie …", "Ihre Abgabe", never "Du bist …" or
"Dein Entwurf". Every string of the page sources (web/src/*.js), of the server (server/**/*.py: error, access,
exam and course messages), of the core's messages (core/**/*.py: diagnostics, grading, sheet), of the page
templates (server/pages/*.html) and every German text of the built-in exercises (title, task, hints) is scanned
for the du form's words (whole words, "du" and "Du" alike; an all-capitals word such as a CLI's "DIR" is not
German prose) and its imperatives where a sentence starts ("Wähle …", "Merke: …"). The English texts may say
"you": they use none of these words.
"""

from __future__ import annotations

import io
import re
import tokenize
from collections.abc import Iterator
from html.parser import HTMLParser
from pathlib import Path

import pytest
import yaml

ROOT = Path(__file__).parents[1]
DU_WORDS = (
    "du",
    "dich",
    "dir",
    "dein",
    "deine",
    "deinen",
    "deinem",
    "deiner",
    "deines",
    "bist",
    "hast",
    "kannst",
    "musst",
    "wirst",
    "willst",
    "sollst",
    "darfst",
    "möchtest",
    "weißt",
    "siehst",
    "gibst",
    "hättest",
    "wärst",
    "euch",
    "euer",
    "eure",
    "euren",
    "eurem",
    "eurer",
)
_WORD = "|".join(DU_WORDS)
DU_FORM = re.compile(rf"(?<![\w-])(?:{_WORD}|{'|'.join(w.capitalize() for w in DU_WORDS)})(?![\w-])")
# the du form's imperative where a text or a sentence starts ("Wähle …", "Merke: …"; the Sie form: "Wählen Sie …")
DU_IMPERATIVES = (
    "Wähle",
    "Gib",
    "Klicke",
    "Öffne",
    "Schreibe",
    "Prüfe",
    "Melde",
    "Speichere",
    "Sieh",
    "Lies",
    "Nimm",
    "Trage",
    "Ändere",
    "Starte",
    "Beachte",
    "Füge",
    "Drücke",
    "Wechsle",
    "Gehe",
    "Nutze",
    "Benutze",
    "Setze",
    "Achte",
    "Denke",
    "Vergiss",
    "Schaue",
    "Warte",
    "Programmiere",
    "Ergänze",
    "Korrigiere",
    "Verwende",
    "Fahre",
    "Rechne",
    "Merke",
    "Lösche",
    "Entferne",
    "Wiederhole",
    "Kontrolliere",
    "Überprüfe",
    "Suche",
    "Finde",
)
DU_IMPERATIVE = re.compile(rf"(?:^|[.:;!?]\s+|[(»„]\s*)(?:{'|'.join(DU_IMPERATIVES)})(?![\w-])")


def python_strings(text: str) -> Iterator[tuple[int, str]]:
    """(line, text) of every string literal of a Python source (f-strings as a whole)."""
    for token in tokenize.generate_tokens(io.StringIO(text).readline):
        if token.type == tokenize.STRING or token.type == getattr(tokenize, "FSTRING_MIDDLE", -1):
            yield token.start[0], token.string


def js_strings(text: str) -> Iterator[tuple[int, str]]:
    """(line, text) of every string and template literal of a JavaScript source: comments and regular expression
    literals are skipped (a regex starts where an operand may: after an operator, a bracket or `return`)."""
    i, n, line, prev = 0, len(text), 1, ""
    while i < n:
        c = text[i]
        if text.startswith("//", i):
            i = n if (j := text.find("\n", i)) < 0 else j
            continue
        if text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j
            line += text.count("\n", i, j)
            i = j + 2
            continue
        if c in "\"'`":
            j, chars = i + 1, []
            while j < n and text[j] != c:
                chars.append(text[j : j + 2] if text[j] == "\\" else text[j])
                j += 2 if text[j] == "\\" else 1
            literal = "".join(chars)
            yield line, literal
            line += literal.count("\n")
            i, prev = j + 1, c
            continue
        if c == "/" and (
            prev == ""
            or prev in "(,=:[!&|?{};+-*%<>~^"
            or re.search(r"\breturn\s*$", text[max(0, i - 10) : i])
        ):
            j, in_class = i + 1, False
            while j < n and text[j] != "\n" and (text[j] != "/" or in_class):
                if text[j] == "\\":
                    j += 1
                elif text[j] in "[]":
                    in_class = text[j] == "["
                j += 1
            i, prev = j + 1, "/"
            continue
        if c == "\n":
            line += 1
        elif not c.isspace():
            prev = c
        i += 1


class _Text(HTMLParser):
    def __init__(self) -> None:
        super().__init__()
        self.parts: list[tuple[int, str]] = []

    def handle_data(self, data: str) -> None:
        self.parts.append((self.getpos()[0], data))

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        for name, value in attrs:
            if name in ("aria-label", "title", "placeholder", "alt") and value:
                self.parts.append((self.getpos()[0], value))


def _german(value: object) -> Iterator[str]:
    """The German texts of an exercise's field: {de: …, en: …} → its de; a list of them → each de."""
    if isinstance(value, dict) and isinstance(value.get("de"), str):
        yield value["de"]
    elif isinstance(value, list):
        for item in value:
            yield from _german(item)


def texts() -> Iterator[tuple[str, int, str]]:
    """(file, line, text) of every user-facing string the scan covers."""
    for path in sorted((ROOT / "web" / "src").glob("*.js")):
        for line, text in js_strings(path.read_text(encoding="utf-8")):
            yield str(path.relative_to(ROOT)), line, text
    for folder in ("server", "core"):
        for path in sorted((ROOT / folder).rglob("*.py")):
            for line, text in python_strings(path.read_text(encoding="utf-8")):
                yield str(path.relative_to(ROOT)), line, text
    for path in sorted((ROOT / "server" / "pages").glob("*.html")):
        parser = _Text()
        parser.feed(path.read_text(encoding="utf-8"))
        for line, text in parser.parts:
            yield str(path.relative_to(ROOT)), line, text
    for path in sorted((ROOT / "exercises").rglob("*.yaml")):
        document = yaml.safe_load(path.read_text(encoding="utf-8")) or {}
        for field in ("title", "task", "hints"):
            for text in _german(document.get(field)):
                yield str(path.relative_to(ROOT)), 0, text


def du_form(text: str) -> str | None:
    """The first du-form word of a text, or None."""
    match = DU_FORM.search(text) or DU_IMPERATIVE.search(text.strip())
    return match.group(0).strip(" (»„.:;!?") if match else None


def test_every_text_addresses_the_reader_with_sie() -> None:
    found = [(file, line, du_form(text), text[:120]) for file, line, text in texts() if du_form(text)]
    assert not found, "du form (use the Sie form): " + "; ".join(
        f"{f}:{n} »{w}« in {t!r}" for f, n, w, t in found
    )


def test_the_scan_sees_the_strings() -> None:
    """The scanners find what they must: a text table's German entries, strings after a regular expression and
    a comment, f-strings; and the words as whole words only."""
    js = (
        "// Du bist hier nicht gemeint (a comment)\nconst r = /[\"']/g;\naddTexts({\n"
        '  "a": ["Dein Entwurf ist gespeichert.", "Your draft is saved."],\n  "b": [`Du bist ${n}.`, "x"],\n});\n'
    )
    found = [(line, text) for line, text in js_strings(js) if DU_FORM.search(text)]
    assert found == [(4, "Dein Entwurf ist gespeichert."), (5, "Du bist ${n}.")]
    py = 'X = ("Sie sind angemeldet.", f"Das kannst du {n} Mal.")\n# du: a comment\n'
    assert [text for _, text in python_strings(py) if DU_FORM.search(text)] in (
        ['f"Das kannst du {n} Mal."'],
        ["Das kannst du "],
    )
    for clean in (
        "Sie haben {n} Abgaben.",
        "Duplikat",
        "dual",
        "Bestand",
        "Fräsen Sie die Kontur.",
        "--dir DIR",
        "Ihr Entwurf",
        "Durchmesser",
        "Wählen Sie ein Beispiel.",
        "Zu Zeile springen",
        "Regel: G41 links",
        "Versuche",
        "Gehäuse",
    ):
        assert du_form(clean) is None, clean
    for du in (
        "Du bist im Kurs.",
        "Was hast du abgegeben?",
        "dein Programm",
        "Gib dir Zeit.",
        "(du)",
        "Wähle ein Beispiel.",
        "Merke: + Rundung",
        "Gespeichert. Prüfe die Meldungen.",
    ):
        assert du_form(du), du


@pytest.mark.parametrize("folder", ["web/src", "server", "exercises"])
def test_the_scan_covers_the_folder(folder: str) -> None:
    assert any(file.startswith(folder) for file, _, _ in texts())
