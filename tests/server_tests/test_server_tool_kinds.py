"""Free practice offers every milling kind of the tool table (web/src/tool-kinds.js = core/tools.py ToolKind
without the lathe's turning tools), and the API takes each of them in a request's tools."""

from __future__ import annotations

import re
import typing
from pathlib import Path

import pytest

from core.tools import ToolKind
from tests.server_tests.server_helpers import Api

WEB_LIST = Path(__file__).parents[2] / "web" / "src" / "tool-kinds.js"


def _offered() -> list[str]:
    match = re.search(r"MILLING_TOOL_KINDS = \[([^\]]*)\]", WEB_LIST.read_text(encoding="utf-8"))
    assert match
    return re.findall(r'"([a-z_]+)"', match.group(1))


def test_the_practice_setup_offers_every_milling_kind() -> None:
    assert _offered() == [k for k in typing.get_args(ToolKind) if k != "turning"]


@pytest.mark.parametrize("kind", typing.get_args(ToolKind))
def test_the_api_takes_every_kind(api: Api, kind: str) -> None:
    program = "N10 T7 TC1 M6\nN20 S1000 F100 M3\nN30 G0 X0 Y0 Z2\nN40 G0 Z50 M30\n"
    r = api.client.post(
        "/api/v1/run", json={"program": program, "tools": [{"number": 7, "diameter": 8, "kind": kind}]}
    )
    assert r.status_code == 200, r.text
    r = api.client.post(
        "/api/v1/check", json={"program": program, "tools": [{"number": 7, "diameter": 8, "kind": "saw"}]}
    )
    assert r.status_code == 422
