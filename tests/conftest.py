"""Shared helpers: run a program text through the pipeline."""

from __future__ import annotations

from pathlib import Path

import pytest

from core.pipeline import run
from core.toolpath import Toolpath

SEEDS = Path(__file__).with_name("seeds")


def codes(toolpath: Toolpath) -> list[tuple[str, int]]:
    """(code, line) of every diagnostic, in order."""
    return [(d.code, d.span.line) for d in toolpath.diagnostics]


def errors(toolpath: Toolpath) -> list[tuple[str, int]]:
    return [(d.code, d.span.line) for d in toolpath.diagnostics if d.severity.value == "error"]


@pytest.fixture
def seed() -> type[SeedReader]:
    return SeedReader


class SeedReader:
    @staticmethod
    def text(name: str) -> str:
        return (SEEDS / name).read_text(encoding="utf-8")

    @staticmethod
    def run(name: str, replace: dict[str, str] | None = None) -> Toolpath:
        """Run seed program `name`, with whole lines replaced by block number: {"N70": "N70 G2 …"}."""
        lines = SeedReader.text(name).splitlines()
        for key, new in (replace or {}).items():
            lines = [new if ln.split(" ", 1)[0] == key else ln for ln in lines]
        return run("\n".join(lines) + "\n")
