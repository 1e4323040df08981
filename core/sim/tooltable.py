"""The tool table for the simulation: the YAML format (docs/tools.md) and the default table for free practice.

`parse_tool_table` turns YAML text into a `ToolTable`; it reads no file (the CLI does). Every
mistake is a `ToolTableError` naming the entry and the field, in German and English.
"""

from __future__ import annotations

import math
from typing import Any, cast, get_args

import yaml  # type: ignore[import-untyped, unused-ignore]

from core.tools import (
    DEFAULT_TOOLS,
    INSERTS,
    KIND_NAMES_DE,
    LATHE_KIND_NAMES_DE,
    Tool,
    ToolKind,
    ToolOffset,
    ToolTable,
)

KINDS: tuple[str, ...] = get_args(ToolKind)
_FIELDS = {
    "number",
    "kind",
    "diameter",
    "name",
    "cutting_length",
    "overall_length",
    "shank_diameter",
    "centre_cutting",
    "corner_radius",
    "point_angle",
    "tc",
    "nose_radius",
    "quadrant",
    "insert",
    "insert_angle",
    "width",
    "holder",
}
MAX_TOOLS = 999


class ToolTableError(ValueError):
    """A tool table that cannot be used; `str()` is German / English."""


DEFAULT_SIM_TOOLS = DEFAULT_TOOLS  # the one free-practice table, defined with the tools


def _err(where: str, de: str, en: str) -> ToolTableError:
    return ToolTableError(f"Werkzeugtabelle, {where}: {de} / tool table, {where}: {en}")


def _number(
    entry: dict[str, Any], key: str, where: str, low: float, high: float, default: float | None = None
) -> float:
    value = entry.get(key, default)
    if value is None:
        raise _err(where, f"»{key}« fehlt", f"'{key}' is missing")
    if isinstance(value, bool) or not isinstance(value, int | float) or not math.isfinite(value):
        raise _err(where, f"»{key}« muss eine Zahl sein", f"'{key}' must be a number")
    if not low < value <= high:
        raise _err(
            where,
            f"»{key}« = {value} liegt nicht in ({low}, {high}]",
            f"'{key}' = {value} is not in ({low}, {high}]",
        )
    return float(value)


def _entry(raw: object, index: int) -> Tool:
    where = f"Eintrag {index + 1}"
    if not isinstance(raw, dict):
        raise _err(
            where,
            "erwartet ein Objekt mit number, kind, diameter …",
            "expected a mapping with number, kind, diameter …",
        )
    entry = cast(dict[str, Any], raw)
    unknown = sorted(str(k) for k in entry if k not in _FIELDS)
    if unknown:
        raise _err(where, f"unbekannte Felder {', '.join(unknown)}", f"unknown fields {', '.join(unknown)}")
    t = entry.get("number")
    if isinstance(t, bool) or not isinstance(t, int) or not 1 <= t <= MAX_TOOLS:
        raise _err(
            where,
            f"»number« (Platz T) muss eine ganze Zahl 1…{MAX_TOOLS} sein",
            f"'number' (place T) must be a whole number 1…{MAX_TOOLS}",
        )
    where = f"T{t}"
    kind = entry.get("kind")
    if kind not in KINDS:
        raise _err(
            where,
            f"»kind« muss eines von {', '.join(KINDS)} sein",
            f"'kind' must be one of {', '.join(KINDS)}",
        )
    diameter = _number(entry, "diameter", where, 0, 1000)
    cutting = _number(entry, "cutting_length", where, 0, 1000, 2 * diameter)
    overall = _number(entry, "overall_length", where, 0, 2000, cutting + 40)
    if overall < cutting:
        raise _err(
            where,
            "»overall_length« ist kleiner als »cutting_length«",
            "'overall_length' is less than 'cutting_length'",
        )
    shank = _number(entry, "shank_diameter", where, 0, 1000, diameter)
    corner = _number(entry, "corner_radius", where, -1e-9, diameter / 2, 0.0)
    if kind == "torus" and corner <= 0:
        raise _err(
            where, "ein Eckradiusfräser braucht »corner_radius« > 0", "a torus mill needs 'corner_radius' > 0"
        )
    angle = _number(entry, "point_angle", where, -1e-9, 179.999, 0.0)
    centre = entry.get("centre_cutting", True)
    if not isinstance(centre, bool):
        raise _err(
            where, "»centre_cutting« muss true oder false sein", "'centre_cutting' must be true or false"
        )
    nose = _number(entry, "nose_radius", where, -1e-9, 50, 0.0)  # turning (TRAUB SET UP-Bild 2)
    quadrant = entry.get("quadrant", 0)
    if not isinstance(quadrant, int) or isinstance(quadrant, bool) or not 0 <= quadrant <= 4:
        raise _err(where, "»quadrant« muss 1, 2, 3 oder 4 sein", "'quadrant' must be 1, 2, 3 or 4")
    insert = entry.get("insert", "")  # turning inserts (core/sim/insert.py)
    if insert not in ("", *INSERTS):
        raise _err(
            where,
            f"»insert« muss eines von {', '.join(INSERTS)} sein",
            f"'insert' must be one of {', '.join(INSERTS)}",
        )
    insert_angle = _number(entry, "insert_angle", where, -1e-9, 179.999, 0.0)
    width = _number(entry, "width", where, -1e-9, 100, 0.0)
    if insert == "groove" and width <= 2 * nose:
        raise _err(
            where,
            "ein Stechdrehmeißel braucht »width« (Breite B) > 2 × »nose_radius«",
            "a grooving tool needs 'width' (B) > 2 × 'nose_radius'",
        )
    holder = _number(entry, "holder", where, -1e-9, 500, 0.0)
    if kind == "turning" and "cutting_length" not in entry:
        cutting_length: float | None = None  # the insert's own default (core/sim/insert.py)
    else:
        cutting_length = cutting
    name = entry.get("name", f"{(KIND_NAMES_DE | LATHE_KIND_NAMES_DE)[str(kind)]} Ø{diameter:g}")
    offsets = _offsets(entry.get("tc", {}), where)
    return Tool(
        t,
        cast(ToolKind, kind),
        diameter,
        str(name),
        cutting_length=cutting_length,
        overall_length=overall,
        shank_diameter=shank,
        centre_cutting=centre,
        corner_radius=max(corner, 0.0),
        point_angle=max(angle, 0.0),
        offsets=offsets,
        nose_radius=nose,
        quadrant=quadrant,
        insert=str(insert),
        insert_angle=max(insert_angle, 0.0),
        width=max(width, 0.0),
        holder=max(holder, 0.0),
    )


def _offsets(raw: object, where: str) -> tuple[ToolOffset, ...]:
    if not isinstance(raw, dict):
        raise _err(
            where,
            "»tc« muss TC-Nummern 1…9 auf {radius, length} abbilden",
            "'tc' must map TC numbers 1…9 to {radius, length}",
        )
    out = []
    for key, value in sorted(raw.items(), key=lambda kv: str(kv[0])):
        if isinstance(key, bool) or not isinstance(key, int) or not 1 <= key <= 9:
            raise _err(
                where,
                f"Korrekturschalter TC{key} gibt es nicht (TC1…TC9)",
                f"offset memory TC{key} does not exist",
            )
        if (
            not isinstance(value, dict)
            or set(value) - {"radius", "length"}
            or set(value) != {"radius", "length"}
        ):
            raise _err(
                where, f"TC{key} braucht genau radius und length", f"TC{key} needs exactly radius and length"
            )
        out.append(
            ToolOffset(
                key,
                _number(value, "radius", f"{where} TC{key}", 0, 1000),
                _number(value, "length", f"{where} TC{key}", 0, 2000),
            )
        )
    return tuple(out)


def parse_tool_table(text: str) -> ToolTable:
    """The tools of a YAML tool table (`tools:` list, see docs/tools.md). Raises ToolTableError."""
    try:
        data = yaml.safe_load(text)
    except yaml.YAMLError as exc:
        raise ToolTableError(
            f"Werkzeugtabelle: kein gültiges YAML ({exc}) / tool table: not valid YAML"
        ) from None
    if not isinstance(data, dict) or not isinstance(data.get("tools"), list):
        raise ToolTableError(
            "Werkzeugtabelle: erwartet »tools:« mit einer Liste / tool table: expected 'tools:' with a list"
        )
    return tools_from_entries(cast(list[object], data["tools"]))


def tools_from_entries(entries: list[object]) -> ToolTable:
    """The tools of an already-read `tools:` list (as in tool tables and exercise files)."""
    if len(entries) > MAX_TOOLS:
        raise ToolTableError(
            f"Werkzeugtabelle: mehr als {MAX_TOOLS} Werkzeuge / tool table: more than {MAX_TOOLS} tools"
        )
    tools: dict[int, Tool] = {}
    for i, raw in enumerate(entries):
        tool = _entry(raw, i)
        if tool.number in tools:
            raise _err(f"T{tool.number}", "steht zweimal in der Tabelle", "appears twice")
        tools[tool.number] = tool
    return ToolTable(tools)


def tool_table_yaml(table: ToolTable) -> str:
    """`table` in the YAML format `parse_tool_table` reads."""
    items = []
    for t in sorted(table.tools.values(), key=lambda x: x.number):
        item: dict[str, Any] = {
            "number": t.number,
            "kind": t.kind,
            "diameter": t.diameter,
            "name": t.name,
            "cutting_length": t.flute_length,
            "overall_length": t.length,
            "shank_diameter": t.shank,
            "centre_cutting": t.centre_cutting,
        }
        if t.kind == "turning" and t.cutting_length is None:
            del item["cutting_length"]  # the insert's own default
        if t.corner_radius:
            item["corner_radius"] = t.corner_radius
        if t.point_angle:
            item["point_angle"] = t.point_angle
        if t.nose_radius or t.quadrant:
            item["nose_radius"], item["quadrant"] = t.nose_radius, t.quadrant
        for key, value in (
            ("insert", t.insert),
            ("insert_angle", t.insert_angle),
            ("width", t.width),
            ("holder", t.holder),
        ):
            if value:
                item[key] = value
        if t.offsets:
            item["tc"] = {o.tc: {"radius": o.radius, "length": o.length} for o in t.offsets}
        items.append(item)
    return str(yaml.safe_dump({"tools": items}, allow_unicode=True, sort_keys=False))
