"""Fuzzing in CI: mutated example programs (exercises/, tests/seeds/) never raise, each finishes in under a
second with the default limits and answers under 5 MB.

The mutations are bench/fuzz.py's (which runs 10^6 of them); here hypothesis makes the choices, so a
failure shrinks to a small program. Most mutated programs take a millisecond; those with an added loop
often run into a budget of core/limits.py (a few hundred ms), so they get fewer cases of their own: both
tests together take about 30 s of CPU.
"""

from __future__ import annotations

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from bench.fuzz import MAX_ANSWER_BYTES, MAX_SECONDS, check, mutate, seeds

SEEDS = seeds()

def _run_case(data: st.DataObject, loops: bool) -> None:
    name, dialect, text = data.draw(st.sampled_from(SEEDS), label="seed")
    others = tuple(t for _, d, t in SEEDS if d == dialect)
    program = mutate(text, lambda n: data.draw(st.integers(0, max(0, n - 1))), others, loops)
    data.draw(st.just(program), label="program")  # shown with a failing example
    out = check(program, dialect)  # an exception fails the test with the program above
    assert out.seconds < MAX_SECONDS, f"{out.seconds:.2f} s for a mutation of {name}"
    assert out.answer_bytes < MAX_ANSWER_BYTES


FUZZ = settings(deadline=None, database=None, suppress_health_check=[HealthCheck.too_slow,
                                                                      HealthCheck.data_too_large])


@settings(FUZZ, max_examples=2500)
@given(st.data())
def test_mutated_programs(data: st.DataObject) -> None:
    _run_case(data, loops=False)


@settings(FUZZ, max_examples=200)
@given(st.data())
def test_mutated_programs_with_loops_and_calls(data: st.DataObject) -> None:
    _run_case(data, loops=True)
