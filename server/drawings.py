"""An instructor's own drawing of an exercise (PDF, PNG or SVG): recognised by its bytes, never by its name or
the type the browser claims; size-limited; an SVG only without scripts, event handlers, external references or
a document type. What trainees see of it is always an SVG (a PNG is wrapped in one) or the PDF itself."""

from __future__ import annotations

import base64
import re
import struct
import xml.etree.ElementTree as ET
from dataclasses import dataclass

from server.errors import ApiError

MAX_DRAWING_BYTES = 2_000_000
PNG_MAGIC = b"\x89PNG\r\n\x1a\n"
PDF_MAGIC = b"%PDF-"
SVG = "image/svg+xml"
PNG = "image/png"
PDF = "application/pdf"
_FORBIDDEN_ELEMENTS = {
    "script",
    "foreignobject",
    "iframe",
    "embed",
    "object",
    "audio",
    "video",
    "handler",
    "listener",
    "set",
    "animate",
}
_URL = re.compile(r"url\(\s*['\"]?\s*([^)'\"\s]*)", re.IGNORECASE)


@dataclass(frozen=True)
class Drawing:
    media_type: str
    filename: str
    data: bytes


def _refuse(de: str, en: str) -> ApiError:
    return ApiError("DRAWING_INVALID", detail=de, detail_en=en)


def _local(name: str) -> str:
    return name.rsplit("}", 1)[-1].lower()


def _check_svg(data: bytes) -> None:
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError:
        raise _refuse("das SVG ist kein UTF-8-Text", "the SVG is not UTF-8 text") from None
    if re.search(r"<!DOCTYPE|<!ENTITY", text, re.IGNORECASE):
        raise _refuse("SVG mit Dokumenttyp oder Entitäten", "SVG with a document type or entities")
    try:
        root = ET.fromstring(text)
    except ET.ParseError:
        raise _refuse("das SVG ist kein gültiges XML", "the SVG is not valid XML") from None
    if _local(root.tag) != "svg":
        raise _refuse("die Datei ist kein SVG", "the file is not an SVG")
    for element in root.iter():
        tag = _local(str(element.tag))
        if tag in _FORBIDDEN_ELEMENTS:
            raise _refuse(
                f"SVG mit dem Element <{tag}> (Skripte und eingebettete Inhalte sind nicht erlaubt)",
                f"SVG with the element <{tag}> (scripts and embedded content are not allowed)",
            )
        for name, value in element.attrib.items():
            attr = _local(name)
            if attr.startswith("on"):
                raise _refuse(
                    f"SVG mit dem Ereignis-Attribut »{attr}«", f"SVG with the event attribute '{attr}'"
                )
            if attr == "href" and not value.strip().startswith("#"):
                raise _refuse(
                    "SVG mit einem Verweis nach außen (href)", "SVG with an external reference (href)"
                )
            if any(not u.startswith("#") for u in _URL.findall(value)):
                raise _refuse(
                    "SVG mit einem Verweis nach außen (url)", "SVG with an external reference (url)"
                )
        if (
            tag == "style"
            and (element.text or "")
            and (
                "@import" in (element.text or "").lower()
                or any(not u.startswith("#") for u in _URL.findall(element.text or ""))
            )
        ):
            raise _refuse(
                "SVG mit einem Verweis nach außen (style)", "SVG with an external reference (style)"
            )


def png_size(data: bytes) -> tuple[int, int]:
    width, height = struct.unpack(">II", data[16:24])
    return int(width), int(height)


def checked(data: bytes, filename: str) -> Drawing:
    """The upload as a drawing, or DRAWING_TOO_LARGE / DRAWING_INVALID with the reason."""
    if len(data) > MAX_DRAWING_BYTES:
        raise ApiError("DRAWING_TOO_LARGE", size=len(data), limit=MAX_DRAWING_BYTES)
    if not data:
        raise _refuse("die Datei ist leer", "the file is empty")
    name = re.sub(r"[^A-Za-z0-9._ -]", "_", filename)[:120] or "zeichnung"
    if data.startswith(PNG_MAGIC) and len(data) > 24 and data[12:16] == b"IHDR":
        width, height = png_size(data)
        if not (0 < width <= 20_000 and 0 < height <= 20_000):
            raise _refuse("PNG mit unmöglicher Größe", "PNG with an impossible size")
        return Drawing(PNG, name, data)
    if data.startswith(PDF_MAGIC):
        return Drawing(PDF, name, data)
    head = data[:512].lstrip(b"\xef\xbb\xbf \t\r\n").lower()
    if head.startswith((b"<?xml", b"<svg")):
        _check_svg(data)
        return Drawing(SVG, name, data)
    raise _refuse(
        "nur PDF, PNG oder SVG (nach dem Inhalt der Datei, nicht ihrem Namen)",
        "only PDF, PNG or SVG (by the file's content, not its name)",
    )


def data_uri(media_type: str, data: bytes) -> str:
    return f"data:{media_type};base64," + base64.b64encode(data).decode("ascii")


def as_svg(media_type: str, data: bytes, lang: str) -> str:
    """What the drawing view shows: the SVG itself, a PNG inside an SVG; for a PDF a note to open it."""
    if media_type == SVG:
        return data.decode("utf-8")
    if media_type == PNG:
        width, height = png_size(data)
        return (
            f'<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 {width} {height}" width="{width}" '
            f'height="{height}"><image href="{data_uri(PNG, data)}" width="{width}" height="{height}"/></svg>'
        )
    text = (
        "Die Zeichnung dieser Aufgabe ist ein PDF: »Zeichnung (PDF)« öffnet sie."
        if lang == "de"
        else "This exercise's drawing is a PDF: 'Drawing (PDF)' opens it."
    )
    return (
        '<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 400 60" width="400" height="60">'
        f'<text x="10" y="35" font-family="sans-serif" font-size="14">{text}</text></svg>'
    )
