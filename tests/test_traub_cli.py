"""`paltrainer check|run FILE --dialect traub-tx8d`: skip-block default, --nose, --lib with O<n>.nc, the trace
with X as a diameter, JSON with x as a radius."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from core.cli import main

SEEDS = Path(__file__).with_name("seeds") / "traub"


def write(path: Path, text: str) -> str:
    path.write_text(text, encoding="utf-8")
    return str(path)


def test_run_json_gives_x_as_a_radius(capsys: pytest.CaptureFixture[str]) -> None:
    assert (
        main(["run", str(SEEDS / "tx-09-absolut-inkremental.nc"), "--dialect", "traub-tx8d", "--json"]) == 0
    )
    moves = json.loads(capsys.readouterr().out)["moves"]
    assert moves[2]["end"] == [30.0, 0.0, -55.0]  # X60 Z-55
    assert moves[2]["plane"] == "G18"


def test_run_trace_writes_x_as_a_diameter(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["run", str(SEEDS / "tx-14-g97-s.nc"), "--dialect", "traub-tx8d"]) == 0
    out = capsys.readouterr().out.splitlines()
    assert out[-1] == "7 feed X0 Z2 -> X0 Z-20 F0.1 S800"


def test_skip_blocks_default_per_dialect_and_explicit_switches(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    path = str(SEEDS / "tx-47-ausblendsatz.nc")
    counts = {}
    for flag in ([], ["--skip-blocks"], ["--no-skip-blocks"]):
        main(["run", path, "--dialect", "traub-tx8d", "--json", *flag])
        counts[tuple(flag)] = len(json.loads(capsys.readouterr().out)["moves"])
    assert counts == {(): 2, ("--skip-blocks",): 2, ("--no-skip-blocks",): 3}
    pal = write(tmp_path / "pal.nc", "T1 M6\nS1000 M3\nG0 X0 Y0 Z10\n/G0 X10\nM30\n")
    main(["run", pal, "--json"])
    assert len(json.loads(capsys.readouterr().out)["moves"]) == 2  # PAL runs "/" blocks by default


def test_help_names_each_dialects_skip_default(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["run", "--help"]) == 0
    text = " ".join(capsys.readouterr().out.split())
    assert "pal-mill: ausführen" in text and "traub-tx8d: überspringen" in text
    assert "--nose T=R:P" in text


def test_library_folder_with_o_files(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    lib = tmp_path / "lib"
    lib.mkdir()
    write(lib / "O8000.nc", "%\nO8000\nG0 X40 Z2\nG1 Z-10 F0.2\nM99\n%\n")
    write(lib / "L8000.nc", "G0 X99 Z99\nM17\n")  # a PAL file name: not a TRAUB program
    main_prog = write(tmp_path / "main.nc", "G97 S800 T0101 M3\nG22 A8000\nM30\n")
    assert main(["run", main_prog, "--dialect", "traub-tx8d", "--lib", str(lib), "--json"]) == 0
    moves = json.loads(capsys.readouterr().out)["moves"]
    assert [m["end"] for m in moves] == [[20.0, 0.0, 2.0], [20.0, 0.0, -10.0]]
    assert moves[0]["source"] == "O8000" and moves[0]["call_stack"] == [{"source": None, "line": 2}]


def test_missing_program_without_library(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    main_prog = write(tmp_path / "main.nc", "G22 A8000\nM30\n")
    assert main(["check", main_prog, "--dialect", "traub-tx8d"]) == 1
    assert "TX-E301" in capsys.readouterr().out


def test_nose_option_reaches_the_tool_table(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    from core.cli import _parser, setup_from_args

    args = _parser().parse_args(
        ["run", "x.nc", "--dialect", "traub-tx8d", "--nose", "3=0.4:2", "--nose", "5=0.8:3"]
    )
    tools = setup_from_args(args).tools
    assert (tools.get(3).nose_radius, tools.get(3).quadrant) == (0.4, 2)  # type: ignore[union-attr]
    assert (tools.get(5).nose_radius, tools.get(5).quadrant) == (0.8, 3)  # type: ignore[union-attr]


@pytest.mark.parametrize("bad", ["3=0.4", "3=x:2", "3=0.4:5", "0=0.4:2"])
def test_bad_nose_option_is_a_usage_error(bad: str, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["run", "x.nc", "--dialect", "traub-tx8d", "--nose", bad]) == 2
    assert "T=R:P" in capsys.readouterr().err
