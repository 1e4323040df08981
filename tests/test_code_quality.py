"""The house rules that tools can check: ruff-clean and mypy-clean (strict) core."""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).parents[1]


@pytest.mark.parametrize("tool,args", [("ruff", ["check", "core", "server", "tests", "bench"]), ("mypy", [])])
def test_clean(tool: str, args: list[str]) -> None:
    if shutil.which(tool) is None and not (Path(sys.executable).parent / tool).exists():
        pytest.skip(f"{tool} not installed")
    exe = shutil.which(tool, path=str(Path(sys.executable).parent)) or tool
    proc = subprocess.run([exe, *args], cwd=ROOT, capture_output=True, text=True, check=False)
    assert proc.returncode == 0, proc.stdout + proc.stderr
