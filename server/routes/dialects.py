"""The dialects and their code tables: what the editor's hover help and completion show."""

from __future__ import annotations

from typing import Any

from fastapi import APIRouter

from core.dialects.help import code_order
from core.pipeline import DIALECTS
from server.errors import ApiError, responses

router = APIRouter(prefix="/dialects", tags=["dialects"])


@router.get("")
def list_dialects() -> list[dict[str, str]]:
    return [{"name": d.name, "title": d.title_de, "title_en": d.title_en} for d in DIALECTS.values()]


@router.get("/{name}", responses=responses(404))
def dialect_help(name: str) -> dict[str, Any]:
    """Every G/M code (G before M, by number) and address of the dialect with its German and English help text;
    a code with its example block, its rule, the groups of addresses of which it needs one each (`mandatory`)
    and the others it takes (`optional`); an address with its unit."""
    d = DIALECTS.get(name)
    if d is None:
        raise ApiError("NOT_FOUND")
    return {
        "name": d.name,
        "title": d.title_de,
        "title_en": d.title_en,
        "codes": [
            {
                "name": c.name,
                "group": c.group,
                "help_de": c.help_de,
                "help_en": c.help_en,
                "supported": c.support.value == "yes",
                "example": c.example,
                "rule_de": c.rule_de,
                "rule_en": c.rule_en,
                "mandatory": [list(g) for g in c.help_mandatory()],
                "optional": list(c.help_optional()),
            }
            for c in sorted(d.table.codes.values(), key=code_order)
        ],
        "addresses": [
            {
                "name": a.name,
                "help_de": a.help_de,
                "help_en": a.help_en,
                "unit": a.unit,
                "rule_de": a.rule_de,
                "rule_en": a.rule_en,
            }
            for a in d.table.addresses.values()
        ],
    }
