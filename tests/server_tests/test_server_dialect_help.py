"""The editor's help comes from the dialect's code table (GET /api/v1/dialects/{name}): names, the addresses a
code needs and takes with their units, an example block and the rule to remember; docs/codes.md is the same
table."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from core.dialects.help import codes_markdown
from tests.server_tests.server_helpers import Api


def _help(api: Api, dialect: str) -> dict[str, Any]:
    r = api.client.get(f"/api/v1/dialects/{dialect}")
    assert r.status_code == 200
    return dict(r.json())


def test_g41_carries_its_rule(api: Api) -> None:
    codes = {c["name"]: c for c in _help(api, "pal-mill")["codes"]}
    assert codes["G41"]["rule_de"] == "Werkzeug links der Kontur, in Vorschubrichtung gesehen"
    assert codes["G42"]["rule_de"].startswith("Werkzeug rechts der Kontur")
    assert codes["G41"]["example"] == "N40 G41 G0 X70 Y84"


def test_g2_mandatory_and_optional_addresses_with_units(api: Api) -> None:
    body = _help(api, "pal-mill")
    g2 = next(c for c in body["codes"] if c["name"] == "G2")
    assert ["I", "J", "IA", "JA", "R"] in g2["mandatory"]  # the centre or the radius
    assert any("X" in group and "AO" in group for group in g2["mandatory"])  # the end point or the angle
    assert {"RN", "Z", "K"} <= set(g2["optional"]) and "R" not in g2["optional"]
    assert g2["example"] == "N40 G2 X56.4 Y10 I-20 J6.4"
    units = {a["name"]: a["unit"] for a in body["addresses"]}
    assert (units["R"], units["I"], units["AO"], units["F"], units["S"], units["U"]) == (
        "mm",
        "mm",
        "°",
        "mm/min",
        "1/min",
        "s",
    )
    rn = next(a for a in body["addresses"] if a["name"] == "RN")
    assert rn["rule_de"] == "+ Rundung, − Fase"


def test_every_supported_pal_code_has_an_example(api: Api) -> None:
    codes = _help(api, "pal-mill")["codes"]
    assert [c["name"] for c in codes if c["supported"] and not c["example"]] == []


def test_codes_in_numeric_order(api: Api) -> None:
    names = [c["name"] for c in _help(api, "pal-mill")["codes"]]
    g = [int(n[1:]) for n in names if n.startswith("G")]
    assert g == sorted(g) and names.index("G3") < names.index("G10")
    assert names.index("G97") < names.index("M3")  # G before M


def test_iso_dialects_share_the_compensation_rule(api: Api) -> None:
    for dialect in ("sinumerik-iso", "beckhoff"):
        body = _help(api, dialect)
        g41 = next(c for c in body["codes"] if c["name"] == "G41")
        assert g41["rule_de"] == "Werkzeug links der Kontur, in Vorschubrichtung gesehen"
        assert next(a for a in body["addresses"] if a["name"] == "X")["unit"] == "mm"
    beckhoff = _help(api, "beckhoff")
    assert next(c for c in beckhoff["codes"] if c["name"] == "G301")["example"] == "N30 G301 I20"
    assert {a["name"]: a["unit"] for a in beckhoff["addresses"]}["#FRC"] == "mm/min"


def test_docs_are_generated_from_the_same_table() -> None:
    doc = Path(__file__).parents[2] / "docs" / "codes.md"
    assert doc.read_text(encoding="utf-8") == codes_markdown(), (
        "run: python -m core.dialects.help > docs/codes.md"
    )
    assert "Werkzeug links der Kontur, in Vorschubrichtung gesehen" in codes_markdown()
