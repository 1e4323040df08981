"""The wheel holds every package of the source tree and the built-in exercises (.ci/wheel-check installs it
into a fresh venv without node/npm and serves the editor from it)."""

from __future__ import annotations

import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def test_every_package_of_the_tree_is_in_the_wheel() -> None:
    setup = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["tool"]["setuptools"]
    tree = {
        ".".join(p.parent.relative_to(ROOT).parts)
        for top in ("core", "server")
        for p in (ROOT / top).rglob("__init__.py")
    }
    assert set(setup["packages"]) == tree | {"paltrainer_exercises"}
    assert setup["package-dir"] == {"paltrainer_exercises": "exercises"}


def test_every_file_of_the_built_in_exercises_is_package_data() -> None:
    setup = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["tool"]["setuptools"]
    patterns = setup["package-data"]["paltrainer_exercises"]
    files = [p.relative_to(ROOT / "exercises") for p in (ROOT / "exercises").rglob("*") if p.is_file()]
    assert files and all(any(f.match(pattern) for pattern in patterns) for f in files), [
        str(f) for f in files if not any(f.match(pattern) for pattern in patterns)
    ]
