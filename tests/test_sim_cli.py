"""`paltrainer simulate`: the JSON contract, exit codes, files written."""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest

from core.cli import main
from tests.conftest import SEEDS

HAND = "N10 T1 TC1 M6\nN20 S1200 F150 M3\nN30 G0 X-14 Y-2.5 Z2\nN40 G0 Z-2\nN50 G1 X82.5\nN60 G1 Y84\nN70 G0 Z50 M30\n"


@pytest.fixture
def program(tmp_path: Path) -> Path:
    path = tmp_path / "p.nc"
    path.write_text(HAND, encoding="utf-8")
    return path


def _json(capsys: pytest.CaptureFixture[str]) -> dict[str, object]:
    return json.loads(capsys.readouterr().out)  # type: ignore[no-any-return]


def test_simulate_json(program: Path, capsys: pytest.CaptureFixture[str]) -> None:
    code = main(["simulate", str(program), "--stock", "0,0,-30:80,70,0", "--json"])
    data = _json(capsys)
    assert code == 0
    assert data["removed_volume_mm3"] == pytest.approx(2800, rel=0.01)
    assert data["remaining_volume_mm3"] == pytest.approx(168000 - 2800, rel=0.001)
    assert data["resolution_mm"] == 0.1 and data["events"] == [] and data["cycle_time_s"] > 0


def test_simulate_reports_a_rapid_collision_with_exit_code_1(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    path = tmp_path / "crash.nc"
    path.write_text("T1 TC1 M6\nS1200 F150 M3\nG0 X40 Y35 Z2\nG0 Z-5\nG0 Z50\nM30\n", encoding="utf-8")
    code = main(["simulate", str(path), "--json", "--resolution", "0.5"])
    data = _json(capsys)
    assert code == 1
    assert [(e["code"], e["line"], e["severity"]) for e in data["events"]] == [("SIM-E001", 4, "error")]  # type: ignore[attr-defined]
    assert data["resolution_mm"] == 0.5


def test_simulate_tool_option_and_tool_table(
    program: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main(["simulate", str(program), "--tool", "1=10", "--json"]) == 0
    smaller = _json(capsys)["removed_volume_mm3"]
    assert smaller < 2800  # a Ø10 tool on the same centre line leaves most of the steps
    tools = tmp_path / "tools.yaml"
    tools.write_text(
        "tools:\n  - {number: 1, kind: end_mill, diameter: 25, cutting_length: 1}\n", encoding="utf-8"
    )
    assert main(["simulate", str(program), "--tools", str(tools), "--json"]) == 1
    assert "SIM-E003" in [e["code"] for e in _json(capsys)["events"]]  # type: ignore[attr-defined]


def test_simulate_writes_stl_and_png(
    program: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    stl, png = tmp_path / "out.stl", tmp_path / "out.png"
    assert (
        main(
            [
                "simulate",
                str(program),
                "--resolution",
                "1",
                "--stl",
                str(stl),
                "--png",
                str(png),
                "--max-triangles",
                "5000",
            ]
        )
        == 0
    )
    assert "2800" in capsys.readouterr().out.replace(",", "")
    data = stl.read_bytes()
    assert 0 < int.from_bytes(data[80:84], "little") <= 5000
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


@pytest.mark.parametrize(
    "args",
    [
        ["--stock", "0,0,-30:80,70"],
        ["--stock", "0,0,0:80,70,0"],
        ["--resolution", "0"],
        ["--tools", "/nonexistent/tools.yaml"],
        ["--expect-tool", "1"],
    ],
)
def test_simulate_usage_errors_exit_2(
    program: Path, args: list[str], capsys: pytest.CaptureFixture[str]
) -> None:
    assert main(["simulate", str(program), *args]) == 2


def test_simulate_bad_tool_table_exit_2(
    program: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    tools = tmp_path / "tools.yaml"
    tools.write_text("tools:\n  - {number: 1, kind: hammer, diameter: 25}\n", encoding="utf-8")
    assert main(["simulate", str(program), "--tools", str(tools)]) == 2
    assert "kind" in capsys.readouterr().err


def test_simulate_expected_diameter_warning(program: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["simulate", str(program), "--expect-tool", "1=20", "--json"]) == 0
    assert [(e["code"], e["line"]) for e in _json(capsys)["events"]] == [("SIM-W001", 1)]  # type: ignore[attr-defined]


def test_simulate_seed_pal15_on_its_own_stock(capsys: pytest.CaptureFixture[str]) -> None:
    main(["simulate", str(SEEDS / "pal-15-g45-g46.nc"), "--stock", "0,0,-20:60,50,0", "--json"])
    data = _json(capsys)
    assert data["events"] == []
    assert math.isfinite(data["cycle_time_s"])  # type: ignore[arg-type]
