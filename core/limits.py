"""The explicit limits of one run; hitting one is a diagnostic, never a hang or a crash."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True, slots=True)
class Limits:
    max_program_chars: int = 5_000_000  # whole program text
    max_line_length: int = 1_000  # characters in one block
    max_blocks: int = 200_000  # lines in one program
    max_executed_blocks: int = 100_000  # blocks executed in one run (loops count every pass)
    max_abs_value: float = 100_000.0  # any address value or parameter, in its unit
    max_diagnostics: int = 1_000  # further diagnostics are dropped with one PAL-E012


DEFAULT_LIMITS = Limits()
