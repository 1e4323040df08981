"""The CLI contract: exit codes, JSON shapes, --tool, --dialect."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from core.cli import main

SEEDS = Path(__file__).with_name("seeds")
DEMO = Path(__file__).parents[1] / "exercises" / "pal-mill" / "nuten-demo.nc"


def write(tmp_path: Path, text: str) -> str:
    path = tmp_path / "prog.nc"
    path.write_text(text, encoding="utf-8")
    return str(path)


def test_check_clean_program_exits_0(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["check", str(DEMO)]) == 0


def test_check_errors_exit_1_with_line_and_column(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = write(tmp_path, "N10 G1 X5\nN20 G1 B7\nM30\n")
    assert main(["check", path]) == 1
    out = capsys.readouterr().out
    assert f"{path}:2:8: Fehler PAL-E003: Unbekannte Adresse »B«." in out


def test_check_json_shape(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = write(tmp_path, "N10 G1 X1,5\nM30\n")
    assert main(["check", path, "--json"]) == 1
    data = json.loads(capsys.readouterr().out)
    (d,) = data["diagnostics"]
    assert set(d) == {"code", "severity", "line", "column", "end_line", "end_column", "message", "message_en"}
    assert (d["code"], d["severity"], d["line"], d["column"], d["end_line"], d["end_column"]) == (
        "PAL-E010",
        "error",
        1,
        9,
        1,
        12,
    )


def test_run_json_shape(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["run", str(SEEDS / "pal-12-g40.nc"), "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["final"] == {"position": [-10, 50, 5]}
    arc = next(m for m in data["moves"] if m["kind"] == "arc")
    for key in ("line", "kind", "start", "end", "center", "direction", "feed", "spindle", "tool"):
        assert key in arc
    assert (
        arc["line"],
        arc["center"],
        arc["direction"],
        arc["end"],
        arc["feed"],
        arc["spindle"],
        arc["tool"],
    ) == (8, [35, 75, -10], "cw", [55, 75, -10], 250, 2000, 1)
    rapid = data["moves"][0]
    assert (rapid["kind"], rapid["center"], rapid["direction"]) == ("rapid", None, None)
    assert data["diagnostics"] == []


def test_tool_option_overrides_the_table(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = write(tmp_path, "T17 M6\nM30\n")
    assert main(["check", path]) == 1
    assert main(["check", path, "--tool", "17=10"]) == 0


def test_usage_errors_exit_2(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = write(tmp_path, "M30\n")
    assert main(["check", path, "--dialect", "klingon"]) == 2
    assert main(["check", str(tmp_path / "missing.nc")]) == 2
    assert main(["check", path, "--tool", "x"]) == 2
    assert main([]) == 2


def test_console_entry_point_runs_as_a_module() -> None:
    proc = subprocess.run(
        [sys.executable, "-m", "core.cli", "run", str(DEMO)], capture_output=True, text=True, check=False
    )
    assert proc.returncode == 0
    assert "23 arc ccw X55 Y10 Z-2 -> X70 Y25 Z-2 C X55 Y25 R15 A90" in proc.stdout


def test_windows_encoded_file_is_read(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = tmp_path / "win.nc"
    path.write_bytes("; Fräsen über Kante\nM30\n".encode("cp1252"))
    assert main(["check", str(path)]) == 0
