"""Tiny programs cannot make unbounded work: blocks, evaluation steps, moves and drawn segments each have a
budget in core/limits.py, hit as a diagnostic; answers are summarised below 5 MB.

The programs are the audit's reproducers (issue 13): a loop of full circles of radius 50 m, a 7-line loop
whose /run answer was 21 MB, and fuzzed programs under 300 characters that ran 10–12 s.
The tests bound the work by counters (blocks executed, evaluation steps, moves, segments, commands in an answer),
never by seconds: bench/limits.py measures the times of the same programs.
"""

from __future__ import annotations

import json
import tracemalloc
from typing import Any

import pytest

from core.interpreter.state import RunSetup
from core.limits import DEFAULT_LIMITS, DIAGNOSTIC_STEPS, Limits, work_ceiling
from core.pipeline import drawing, run, summarised, toolpath_json
from core.toolpath import Toolpath
from tests.conftest import codes

MB = 5_000_000

CIRCLES = "N10 T1 M6\nN20 S1000 F100 M3\nN30 G0 X0 Y0 Z2\nN40 G2 X0 Y0 I50000 J0\nN50 G29 N40\nN60 M30\n"
SEVEN_LINES = "N10 T1 M6\nN20 S1000 F100 M3\nN30 G0 X0 Y0 Z2\nN40 G1 X10\nN50 G1 X0\nN60 G29 N40\nN70 M30\n"
# compensated contour with roundings in an endless loop: each pass costs the contour stage ~0.5 ms
CONTOUR_LOOP = (
    "N10 T1 TC1 M6\nN20 F250 S2000 M3\nN30 G0 X-10 Y-50 Z2\nN40 G41 G1 X15 Y-15\n"
    "N60 G1 X15 Y75 RN5\nN70 G1 X55 Y75 RN-2\nN80 G1 X55 Y-15 RN3\nN85 G1 X15 Y-15\n"
    "N90 G29 N60\nN100 M30\n"
)
# one long block of parameter arithmetic in an endless loop
ARITHMETIC_LOOP = "N10 P1=" + "+".join(["P1*2"] * 40) + "\nN20 G29 N10\nN30 M30\n"
# every pass reports a warning for each unassigned parameter it reads
WARNING_LOOP = "N10 P1=" + "+".join(f"P{900 + i}" for i in range(40)) + "\nN20 G29 N10\nN30 M30\n"


def within_budget(tp: Toolpath) -> bool:
    return all(w <= c for w, c in zip(tp.work, work_ceiling(DEFAULT_LIMITS), strict=True))


def json_size(data: Any) -> int:
    return len(json.dumps(data, ensure_ascii=False).encode())


@pytest.mark.parametrize(
    "program",
    [CIRCLES, SEVEN_LINES, CONTOUR_LOOP, ARITHMETIC_LOOP, WARNING_LOOP],
    ids=["circles", "seven-lines", "contour-loop", "arithmetic-loop", "warning-loop"],
)
def test_audit_programs_end_at_a_budget_with_answers_under_5_mb(program: str) -> None:
    assert len(program) < 300
    tp = run(program)
    assert within_budget(tp) and len(tp.moves) <= 4 * DEFAULT_LIMITS.max_moves  # see tests/test_fuzz.py
    assert any(d.code in ("PAL-E013", "PAL-E016", "PAL-E017") for d in tp.diagnostics)
    answer = toolpath_json(tp)
    assert (
        len(answer["moves"]) + len(answer["dwells"]) + len(answer["tool_changes"])
        <= DEFAULT_LIMITS.max_answer_commands
    )
    assert json_size(answer) < MB


SERVER_CHARS = 200_000  # the server's largest program (PALTRAINER_MAX_PROGRAM_CHARS)


@pytest.mark.parametrize(
    "line",
    ["#", "X1,5", "Q1", "G1 X1\nX2"],
    ids=["bad-character", "decimal-comma", "unknown-address", "short-moves"],
)
def test_the_largest_program_the_server_takes_reads_only_max_blocks_lines(line: str) -> None:
    # the lines beyond max_blocks are not read (PAL-E006): a syntax error costs ~10 µs a line
    text = "T1 M6\nS100 F100 M3\n" + (line + "\n") * (SERVER_CHARS // (len(line) + 1) - 10)
    tp = run(text)
    assert ("PAL-E006", DEFAULT_LIMITS.max_blocks + 1) in codes(tp) and within_budget(tp)
    assert tp.work[0] <= DEFAULT_LIMITS.max_blocks
    assert json_size(toolpath_json(tp)) < MB


def test_moves_budget_stops_the_program_at_the_block_that_exceeds_it() -> None:
    tp = run(SEVEN_LINES, setup=RunSetup(limits=Limits(max_moves=100)))
    assert ("PAL-E017", 5) in codes(tp) or ("PAL-E017", 4) in codes(tp)
    assert len([m for m in tp.moves if m.kind == "feed"]) == 99  # the G0 is the first of the 100
    assert "PAL-W102" not in dict(codes(tp))  # stopped: a missing M30 is no news


def test_evaluation_budget_counts_words_and_expression_terms() -> None:
    long = "+".join(["P1*0+1"] * 40)  # 40 × (P1 0 * 1 +) and 39 more + = 239 terms
    text = f"N5 P1=0 P2=0\nN10 P2=P2+1 P1={long}\nN20 G29 N10\nN30 M30\n"
    tp = run(text, setup=RunSetup(limits=Limits(max_evaluation_steps=10_000)))
    assert ("PAL-E016", 2) in codes(tp)
    # N5: 2 × (1 + 1); a pass: N10 (1 + 3) + (1 + 239), N20 two words; the pass that would exceed is not run
    first, per_pass = 4, 4 + 240 + 2
    passes = (10_000 - first - (4 + 240)) // per_pass + 1
    assert tp.params[2] == passes and tp.params[1] == 40


def test_warnings_count_against_the_evaluation_budget() -> None:
    reads = "+".join(f"P{900 + i}" for i in range(40))  # 40 unassigned parameters: 40 warnings a pass
    tp = run(f"N5 P2=0\nN10 P2=P2+1 P1={reads}\nN20 G29 N10\nN30 M30\n")
    assert "PAL-E016" in dict(codes(tp)) and ("PAL-W106", 2) in codes(tp)
    steps = 4 + 80 + 2  # a pass without its warnings
    assert tp.params[2] < DEFAULT_LIMITS.max_evaluation_steps / (steps + 40 * DIAGNOSTIC_STEPS) + 1


def test_a_program_within_the_budgets_is_unchanged() -> None:
    tp = run(
        "N10 T1 M6\nN20 S1000 F100 M3\nN30 G0 X0 Y0 Z2\nN40 G1 X10\nN50 G1 X0\nN60 G23 N40 N50 H200\n"
        "N70 M30\n"
    )
    assert codes(tp) == [] and len(tp.moves) == 1 + 2 + 400


# -- answers: the first commands and a diagnostic that the rest is cut -------------------------------------


def test_long_toolpath_answer_is_summarised_with_a_diagnostic_at_the_first_left_out_command() -> None:
    tp = run(SEVEN_LINES, setup=RunSetup(limits=Limits(max_answer_commands=50)))
    answer = toolpath_json(tp)
    assert len(answer["moves"]) + len(answer["tool_changes"]) == 50
    cut = [d for d in answer["diagnostics"] if d["code"] == "PAL-I018"]
    assert len(cut) == 1 and cut[0]["severity"] == "info" and cut[0]["line"] in (4, 5)
    assert "50" in cut[0]["message"] and "50" in cut[0]["message_en"]
    assert answer["final"]["position"] == [round(v, 6) for v in tp.final_position]


def test_summary_keeps_the_toolpath_for_simulation_and_grading() -> None:
    tp = run(SEVEN_LINES, setup=RunSetup(limits=Limits(max_answer_commands=50)))
    short = summarised(tp)
    assert len(short.commands) == 50 and len(tp.commands) > 50
    assert summarised(run("N10 G0 X1\nN20 M30\n")).diagnostics == []


def test_deeply_called_moves_still_give_an_answer_under_5_mb() -> None:
    # every move carries the call stack of 8 nested subprograms: the largest a move's JSON gets
    subs = "".join(f"%L{n}\nN10 G22 L{n + 1}\nN20 M17\n" for n in range(1, 8))
    text = (
        "N10 T1 M6\nN20 S1000 F100 M3\nN30 G22 L1\nN40 M30\n"
        + subs
        + "%L8\nN10 G1 X10\nN20 G1 X0\nN30 G29 N10\nN40 M17\n"
    )
    answer = toolpath_json(run(text))
    assert len(answer["moves"]) + len(answer["tool_changes"]) == DEFAULT_LIMITS.max_answer_commands
    assert len(answer["moves"][-1]["call_stack"]) == 8
    assert json_size(answer) < MB


# -- the 3D view's segments: counted before they are made ---------------------------------------------------


def test_drawing_a_loop_of_huge_circles_is_bounded_before_it_is_built() -> None:
    tp = run(CIRCLES)
    tracemalloc.start()
    try:
        lines, notice = drawing(tp, 0.05)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < 50_000_000
    assert sum(len(points) - 1 for points in lines) <= DEFAULT_LIMITS.max_drawn_segments
    assert 0 < len(lines) < len(tp.moves)
    assert notice is not None and notice.code == "PAL-I019" and notice.span.line == 4


def test_drawing_keeps_the_chords_of_an_ordinary_program() -> None:
    tp = run("N10 T1 M6\nN20 S1000 F100 M3\nN30 G0 X0 Y0 Z2\nN40 G2 X0 Y0 I20 J0\nN50 M30\n")
    lines, notice = drawing(tp, 0.05)
    assert notice is None and len(lines) == len(tp.moves) == 2
    assert lines[1] == tp.moves[1].points(0.05)


def test_arc_points_can_be_bounded() -> None:
    arc = run(CIRCLES, setup=RunSetup(limits=Limits(max_executed_blocks=4))).moves[1]
    assert arc.kind == "arc" and arc.chords(0.05) > 1000
    assert len(arc.points(0.05)) == arc.chords(0.05) + 1
    points = arc.points(0.05, max_chords=16)
    assert len(points) == 17 and points[-1] == arc.end


# -- the server's jobs answer with the same bounds ---------------------------------------------------------


@pytest.mark.parametrize("program", [CIRCLES, SEVEN_LINES], ids=["circles", "seven-lines"])
def test_run_live_and_scene_jobs_stay_small(program: str) -> None:
    from server.jobs import job_live, job_run, job_scene

    answer = job_run(program, "pal-mill", {})
    assert len(answer["moves"]) <= DEFAULT_LIMITS.max_answer_commands and json_size(answer) < MB
    live = job_live("budget", 0, 1, program, "pal-mill", {})
    assert json_size(live) < MB
    assert any(d["code"] == "PAL-I018" for ds in live["diagnostics"].values() for d in json.loads(ds or "[]"))
    scene = job_scene(program, "pal-mill", {})
    assert len(scene.playback.segments) <= DEFAULT_LIMITS.max_drawn_segments


def test_grading_looks_at_a_bounded_number_of_chords_per_arc() -> None:
    from core.exercises import builtin_exercises
    from core.grading import grade

    exercise = builtin_exercises()["pal-01-g1-gerade"]
    result = grade(
        exercise, CIRCLES
    )  # 5,000 circles of 2,000 chords each above the part (bench/limits.py: time)
    assert result.score < result.max_score


def test_a_compensated_loop_of_chamfered_corners_makes_at_most_four_moves_per_budgeted_move() -> None:
    # each programmed side: the line, its chamfer, and an arc at both outside corners (G41 around the square)
    text = (
        "N10 T1 TC1 M6\nN20 F250 S2000 M3\nN30 G0 X-20 Y-20 Z2\nN40 G41 G1 X0 Y0\nN60 G1 X0 Y50 RN-3\n"
        "N70 G1 X50 Y50 RN-3\nN80 G1 X50 Y0 RN-3\nN85 G1 X0 Y0 RN-3\nN90 G29 N60\nN100 M30\n"
    )
    tp = run(text)
    assert tp.work[2] == DEFAULT_LIMITS.max_moves and "PAL-E017" in dict(codes(tp))
    assert 3 * DEFAULT_LIMITS.max_moves < len(tp.moves) <= 4 * DEFAULT_LIMITS.max_moves
