"""Fuzzing in CI: mutated example programs (exercises/, tests/seeds/) never raise, the work each does stays
within the default limits (blocks executed, evaluation steps, moves — deterministic counters, never seconds: a
test must pass on a loaded machine) and each answers under 5 MB. The seconds are bench/fuzz.py's.

The mutations are bench/fuzz.py's (which runs 10^6 of them); here hypothesis makes the choices, so a
failure shrinks to a small program. Most mutated programs take a millisecond; those with an added loop
often run into a budget of core/limits.py, so they get fewer cases of their own.
"""

from __future__ import annotations

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from bench.fuzz import MAX_ANSWER_BYTES, check, mutate, seeds
from core.limits import DEFAULT_LIMITS, work_ceiling

SEEDS = seeds()
LIMITS = DEFAULT_LIMITS


def _run_case(data: st.DataObject, loops: bool) -> None:
    name, dialect, text = data.draw(st.sampled_from(SEEDS), label="seed")
    others = tuple(t for _, d, t in SEEDS if d == dialect)
    program = mutate(text, lambda n: data.draw(st.integers(0, max(0, n - 1))), others, loops)
    data.draw(st.just(program), label="program")  # shown with a failing example
    out = check(program, dialect)  # an exception fails the test with the program above
    ceiling = work_ceiling(LIMITS)
    assert all(w <= c for w, c in zip(out.work, ceiling, strict=True)), (
        f"work {out.work} > {ceiling} ({name})"
    )
    # the budget counts programmed moves; a chamfer or rounding (RN, D) inserts one element after a move, and the
    # radius compensation an arc at each outside corner (two per move with chamfers): at most four for each
    assert out.moves <= 4 * LIMITS.max_moves, f"{out.moves} moves in the toolpath of a mutation of {name}"
    assert out.segments <= LIMITS.max_drawn_segments
    assert out.answer_bytes < MAX_ANSWER_BYTES


FUZZ = settings(
    deadline=None, database=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large]
)


@settings(FUZZ, max_examples=2500)
@given(st.data())
def test_mutated_programs(data: st.DataObject) -> None:
    _run_case(data, loops=False)


@settings(FUZZ, max_examples=200)
@given(st.data())
def test_mutated_programs_with_loops_and_calls(data: st.DataObject) -> None:
    _run_case(data, loops=True)
