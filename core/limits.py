"""The explicit limits of one run; hitting one is a diagnostic, never a hang or a crash.

The work of a run is bounded three ways, so that any program, however small, finishes in well under a
second (bench/limits.py, bench/fuzz.py): executed blocks (PAL-E013), evaluation steps (PAL-E016) and
programmed moves (PAL-E017). What leaves the run is bounded as well: an answer shows the first
`max_answer_commands` commands (PAL-I018) and a drawing of the toolpath at most `max_drawn_segments`
segments (PAL-I019), counted before a point is made.
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True, slots=True)
class Limits:
    max_program_chars: int = 5_000_000  # whole program text
    max_line_length: int = 1_000  # characters in one block
    max_blocks: int = 20_000  # lines in one program (as many as the live editor takes); then PAL-E006
    max_executed_blocks: int = 100_000  # blocks executed in one run (loops count every pass)
    # evaluation steps of one run: each word of an executed block, each number, parameter and operator of
    # its expressions, and DIAGNOSTIC_STEPS for each diagnostic it reports (loops count every pass)
    max_evaluation_steps: int = 600_000
    max_moves: int = 5_000  # programmed moves in one run (each motion block once per pass)
    max_cycle_passes: int = 500  # passes (levels, pecks, thread passes) of one TRAUB cycle block; then TX-E406
    max_abs_value: float = 100_000.0  # any address value or parameter, in its unit
    max_diagnostics: int = 1_000  # further diagnostics are dropped with one PAL-E012
    max_answer_commands: int = 5_000  # moves, dwells and tool changes in one answer (JSON); then PAL-I018
    max_drawn_segments: int = 20_000  # line segments of one toolpath drawing (arcs as chords); then PAL-I019


DIAGNOSTIC_STEPS = 20  # making a diagnostic costs about as much as evaluating twenty terms

DEFAULT_LIMITS = Limits()
