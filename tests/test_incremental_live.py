"""Incremental live checking: a run that restarts from the previous run's checkpoints and takes over the rest
of it gives exactly a full run's answer, for any sequence of edits (core/interpreter/checkpoints.py).

The comparison is of the JSON the live socket is built from: every move, dwell, tool change and diagnostic
(with its line), the final position, and the state after each line.
"""

from __future__ import annotations

import gc
import json
from typing import Any

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from core.interpreter.checkpoints import STATS
from core.interpreter.state import RunSetup
from core.limits import Limits
from core.pipeline import Memo, run, toolpath_json
from server import live
from server.jobs import job_live

# small budgets: endless loops end quickly, and the budgets' diagnostics are part of what is compared
SMALL = RunSetup(
    limits=Limits(
        max_executed_blocks=400,
        max_moves=150,
        max_evaluation_steps=4_000,
        max_diagnostics=60,
        max_answer_commands=120,
    )
)

PAL_LINES = [
    "N10 T1 TC1 M6",
    "N20 S1200 F150 M3",
    "G0 X10 Y10 Z2",
    "G1 Z-2",
    "G1 X20 Y15",
    "G1 X35 Y40",
    "G2 X30 Y15 R10",
    "G3 X20 Y15 R10",
    "G2 X40 Y20 I10 J0",
    "P1=5",
    "P2=P1*2+1",
    "G1 X=P1 Y=P2",
    "P3=P3+1",
    "G91",
    "G90",
    "G1 X5",
    "G91 G1 X5",
    "G41 G1 X10 Y10",
    "G40 G1 X0",
    "G1 X30 RN3",
    "G1 Y30 RN-2",
    "N100 G1 X40",
    "N110 G0 Z5",
    "G23 N100 N110 H2",
    "G29 N110",
    "G29 N100",
    "G22 L10",
    "G22 L10 H2",
    "G22 L20",
    "G22 L30",
    "M17",
    "M30",
    "G4 F1",
    "T2 M6",
    "G54",
    "G59 X10",
    "G17",
    "F0",
    "M5",
    "/G1 X7",
    "/N115 G0 Z9",
    # broken, half-typed, empty and comment lines
    "",
    "; Kommentar",
    "G1 X",
    "G1 X1 X2",
    "N",
    "P4=",
    "G7",
    "G2 X10 R",
    "N12 G1 X5 Y(",
    "(offen",
]
PAL_HEADERS = ["%L10", "%L20"]

# a subprogram of the program library (an exercise's subprograms): its lines are its own, never shifted
LIBRARY = RunSetup(limits=SMALL.limits, subprograms=((30, "G91 G1 X2\nG90\nM17\n"),))
SKIPPING = RunSetup(limits=SMALL.limits, skip_blocks=True)

BECKHOFF_LINES = [
    "N05 G17 G00 G90 X0 Y0",
    "G01 F2000 X100 G301=20 #FRC=500",
    "Y100 G302=20 #FRC=1000",
    "X0 G301=20",
    "N120 G301 I20",
    "X-60",
    "G00 G90 X0 Y0",
    "G01 F2000 X200 #CHR=20 #FRC=500",
    "Y100 #RND=20",
    "X0 #CHF=35",
    "G00 G91 X100 Y0",
    "G01 Y100 F200",
    "M30",
    "",
    "G01 X",
    "T1 M6",
    "S1000 M3",
]

ISO_LINES = [
    "N10 T1 M6",
    "N20 S1200 M3",
    "N30 G17 G90 G00 X-20 Y10 Z2",
    "N40 G01 Z-2 F150",
    "G01 X40",
    "G03 X60 Y30 R20",
    "G01 Y50",
    "G02 X80 Y70 I20 J0",
    "G91 G01 X5",
    "G90",
    "G00 Z50",
    "M30",
    "G04 X1",
    "",
    "G01 X",
    "G99",
    "; Satz",
]

TRAUB_LINES = [
    "G59 X0 Z210",
    "G95",
    "G96 V180 T0101 M4",
    "G92 S3000",
    "G0 X54 Z2 M8",
    "G0 X100 Z50",
    "G1 X20 Z0 F0.15",
    "G1 A180",
    "G2 X40 Z-20 R10",
    "G1 Z-30",
    "G1 X50 A135",
    "G1 Z-60",
    "G1 X54 Z-62",
    "N10 G46",
    "N20 G40",
    "G71 P10 Q20 I0.5 K0.1 D3 F0.3",
    "G22 A8001",
    "M9",
    "M30",
    "G97 S1000 M3",
    "G1 X30 F0,2",
    "G1 U-2",
    "",
    "G1 X",
    "G7",
    "(Kommentar)",
    "L1=10",
    "G1 X=L1 Z-5",
]
TRAUB_SUB = ["%", "O 8001", "G00 X40 Z2", "G01 X20 F0,2", "M99", "%"]


def live_json(text: str, dialect: str, setup: RunSetup, memo: Memo | None) -> str:
    """What the live answer is made of, as JSON (plus the state after each line)."""
    tp = run(text, dialect, setup, memo)
    data: dict[str, Any] = toolpath_json(tp)
    data["states"] = [[s.to_json(), list(p)] for s, p in zip(tp.line_states, tp.line_positions, strict=True)]
    return json.dumps(data, sort_keys=True)


def edits(pool: list[str]) -> st.SearchStrategy[tuple[str, int, int, list[str]]]:
    """(kind, at, count, lines): replace, insert or delete lines at a relative position (0..1000)."""
    line = st.one_of(st.sampled_from(pool), st.sampled_from(pool).map(lambda s: s[: len(s) // 2]))
    return st.tuples(
        st.sampled_from(["replace", "insert", "delete", "type"]),
        st.integers(0, 1000),
        st.integers(1, 3),
        st.lists(line, min_size=1, max_size=3),
    )


def apply(lines: list[str], edit: tuple[str, int, int, list[str]]) -> list[str]:
    kind, at, count, new = edit
    i = at * len(lines) // 1001 if lines else 0
    if kind == "insert":
        return lines[:i] + new + lines[i:]
    if kind == "delete":
        return lines[:i] + lines[i + count :]
    if kind == "type" and lines:  # one more character of a line from the pool, as a typist does
        target = new[0] or "X1"
        current = lines[i]
        return (
            lines[:i]
            + [target[: len(current) + 1] if target.startswith(current) else target[:1]]
            + lines[i + 1 :]
        )
    return lines[:i] + new + lines[i + 1 :]


def check_sequence(
    start: list[str], steps: list[tuple[str, int, int, list[str]]], dialect: str, setup: RunSetup
) -> None:
    memo = Memo()
    lines = start
    for k in range(len(steps) + 1):
        text = "\n".join(lines) + "\n"
        assert live_json(text, dialect, setup, memo) == live_json(text, dialect, setup, None), (
            f"after {k} edits of {start!r} by {steps!r}"
        )
        if k < len(steps):
            lines = apply(lines, steps[k])


PAL_PROGRAM = st.tuples(
    st.lists(st.sampled_from(PAL_LINES), min_size=3, max_size=30),
    st.lists(
        st.tuples(st.sampled_from(PAL_HEADERS), st.lists(st.sampled_from(PAL_LINES), max_size=6)), max_size=2
    ),
).map(
    lambda p: (
        ["N10 T1 TC1 M6", "N20 S1200 F150 M3", *p[0], "M30"]
        + [x for header, body in p[1] for x in (header, *body, "M17")]
    )
)


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(PAL_PROGRAM, st.lists(edits(PAL_LINES + PAL_HEADERS), min_size=1, max_size=8))
def test_pal_milling_incremental_equals_full_run(program: list[str], steps: list[Any]) -> None:
    check_sequence(program, steps, "pal-mill", SMALL)


@settings(max_examples=100, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(PAL_PROGRAM, st.lists(edits(PAL_LINES + PAL_HEADERS), min_size=1, max_size=6), st.booleans())
def test_pal_milling_with_a_library_subprogram_or_skipped_blocks(
    program: list[str], steps: list[Any], skipping: bool
) -> None:
    check_sequence(program, steps, "pal-mill", SKIPPING if skipping else LIBRARY)


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    st.lists(st.sampled_from(BECKHOFF_LINES), min_size=2, max_size=20),
    st.lists(edits(BECKHOFF_LINES), min_size=1, max_size=6),
)
def test_beckhoff_incremental_equals_full_run(program: list[str], steps: list[Any]) -> None:
    check_sequence(program, steps, "beckhoff", SMALL)


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(PAL_PROGRAM, st.lists(edits(PAL_LINES), min_size=1, max_size=6))
def test_pal_milling_incremental_equals_full_run_default_limits(program: list[str], steps: list[Any]) -> None:
    setup = RunSetup(limits=Limits(max_executed_blocks=3_000))  # endless loops stay affordable
    check_sequence(program, steps, "pal-mill", setup)


@settings(max_examples=100, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    st.lists(st.sampled_from(ISO_LINES), min_size=2, max_size=25),
    st.lists(edits(ISO_LINES), min_size=1, max_size=6),
)
def test_iso_incremental_equals_full_run(program: list[str], steps: list[Any]) -> None:
    check_sequence(program, steps, "sinumerik-iso", SMALL)


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    st.lists(st.sampled_from(TRAUB_LINES), min_size=2, max_size=20),
    st.booleans(),
    st.lists(edits(TRAUB_LINES), min_size=1, max_size=5),
)
def test_traub_incremental_equals_full_run(program: list[str], sub: bool, steps: list[Any]) -> None:
    check_sequence(
        ["%", "O 4711", *program, "M30", "%", *(TRAUB_SUB if sub else [])], steps, "traub-tx8d", RunSetup()
    )


def fold(answers: list[dict[str, Any]]) -> dict[str, Any]:
    """The document a client holds after these live answers (folded as server/live.py folds them)."""
    doc: dict[str, dict[int, str]] = {"diagnostics": {}, "toolpath": {}}
    final: Any = None
    for a in answers:
        live.fold(doc, a)
        final = a["final"]
    return {"diagnostics": doc["diagnostics"], "toolpath": doc["toolpath"], "final": final}


def typing(lines: list[str], line: int, target: str) -> list[list[str]]:
    """The documents while `target` is typed into line `line` character by character."""
    return [lines[: line - 1] + [target[:i]] + lines[line:] for i in range(1, len(target) + 1)]


def bench_program(blocks: int = 500) -> list[str]:
    lines = ["N10 T1 TC1 M6", "N20 S1200 F150 M3", "N30 G0 X10 Y10 Z2", "N40 G1 Z-2"]
    while len(lines) < blocks - 1:
        n = (len(lines) + 1) * 10
        lines.append(
            f"N{n} G1 X{len(lines) % 70 + 5} Y{len(lines) * 7 % 60 + 5}"
            if n % 30
            else f"N{n} G2 X{len(lines) % 70 + 5} Y{len(lines) * 7 % 60 + 5} R40"
        )
    return [*lines, f"N{blocks * 10} G0 Z50 M30"]


@pytest.mark.parametrize("dialect", ["pal-mill", "traub-tx8d"])
def test_live_answers_fold_to_a_full_answer_while_typing_and_breaking_lines(dialect: str) -> None:
    """The worker's live job, keystroke by keystroke (in-line typing, a new line, a deleted line): the
    client's folded document equals the answer of a fresh document after every keystroke."""
    lines = bench_program(120) if dialect == "pal-mill" else ["%", "O 4711", *TRAUB_LINES[:13], "M30", "%"]
    docs = [lines, *typing(lines, 40 if dialect == "pal-mill" else 8, "N395 G91 G1 X5 Y-3 F200")]
    docs.append(docs[-1][:20] + ["G1 X50 Y20"] + docs[-1][20:])  # a new line (Enter)
    docs.append(docs[-1][:10] + docs[-1][11:])  # a deleted line
    docs.append(docs[-1][:-1])  # M30 gone
    spec = {"skip_blocks": None}
    answers = []
    for gen, doc in enumerate(docs):
        text = "\n".join(doc) + "\n"
        answers.append(job_live("inc", gen, gen + 1, text, dialect, spec))
        fresh = fold([job_live(f"fresh-{gen}", 0, 1, text, dialect, spec)])
        assert json.dumps(fold(answers), sort_keys=True) == json.dumps(fresh, sort_keys=True), gen


def test_typing_in_a_long_program_takes_over_the_previous_run() -> None:
    """Typing a line in the middle of a 500-block program re-runs a few blocks, not the program: the runs
    meet the previous run again (STATS counts them), and a new line or a deleted one shifts the rest."""
    lines = bench_program(500)
    memo = Memo()
    run("\n".join(lines) + "\n", "pal-mill", RunSetup(), memo)
    before = STATS.copy()
    docs = typing(lines, 250, "N2495 G1 X33 Y44")
    docs.append(docs[-1][:100] + ["N995 G1 X20 Y20"] + docs[-1][100:])
    docs.append(docs[-1][:300] + docs[-1][301:])
    for doc in docs:
        text = "\n".join(doc) + "\n"
        assert live_json(text, "pal-mill", RunSetup(), memo) == live_json(text, "pal-mill", RunSetup(), None)
    assert STATS["incremental"] - before["incremental"] == len(docs)
    assert memo.runs.trace is not None and len(memo.runs.trace.points) > 490


def test_a_loop_across_the_edit_runs_to_the_end_and_stays_correct() -> None:
    """A G23 section around the edited line: the previous run meets it in every pass, so the new run can only
    take over after the last pass; a G29 jump back over it the same."""
    text = (
        "N10 T1 TC1 M6\nN20 S1000 F200 M3\nN30 G0 X0 Y0 Z2\nN40 G91 G1 X5\nN50 G1 Y{y}\nN60 G90\n"
        "N70 G23 N40 N60 H3\nN80 G1 X0 Y0\nN90 M30\n"
    )
    memo = Memo()
    for y in (1, 2, 3, 13):
        t = text.format(y=y)
        assert live_json(t, "pal-mill", RunSetup(), memo) == live_json(t, "pal-mill", RunSetup(), None)
    tp = run(text.format(y=13), "pal-mill", RunSetup(), memo)
    assert [round(m.end[1], 3) for m in tp.moves if m.line == 5] == [13, 26, 39, 52]


def test_a_batch_of_live_documents_answers_each_and_a_failing_one_fails_alone() -> None:
    """The documents waiting for one worker go in one job (server/live.py LiveBatch): each gets its own
    answer, a run that raises fails only its own document, and once the job's time is up the rest waits
    for the next job (None) instead of running over the job's time limit."""
    from server.jobs import job_live_batch

    good = ("batch-a", 0, 1, "N10 G0 X5 Y0 Z2\nN20 M30\n", "pal-mill", {"skip_blocks": None})
    bad = ("batch-b", 0, 1, None, "pal-mill", {"skip_blocks": None})  # no text: the run raises
    again = ("batch-a", 1, 2, *good[3:])
    answers = job_live_batch(job_live, [good, bad, again], 10.0)
    assert answers[0] is not None and answers[0]["final"] == [5.0, 0.0, 2.0]
    assert answers[1] == {"failed": True}
    assert answers[2] is not None and answers[2]["toolpath"] == {}  # the same text again: nothing changed
    assert job_live_batch(job_live, [good, good], 0.0)[1:] == [None]  # the first always runs


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(PAL_PROGRAM, st.lists(edits(PAL_LINES), min_size=1, max_size=6))
def test_live_answers_fold_to_a_full_answer_for_any_edits(program: list[str], steps: list[Any]) -> None:
    """The worker's answers (only what changed; moves taken over with shifted lines reuse their JSON), folded
    as the client does, equal a fresh document's answer after every edit, byte for byte."""
    spec: dict[str, Any] = {"skip_blocks": None}
    lines, answers = program, []
    for gen in range(len(steps) + 1):
        text = "\n".join(lines) + "\n"
        answers.append(job_live("fold", gen, gen + 1, text, "pal-mill", spec))
        fresh = fold([job_live(f"fold-fresh-{gen}", 0, 1, text, "pal-mill", spec)])
        assert json.dumps(fold(answers), sort_keys=True) == json.dumps(fresh, sort_keys=True), (
            program,
            steps,
        )
        if gen < len(steps):
            lines = apply(lines, steps[gen])


# a TRAUB program with a roughing cycle over a P/Q contour, a subprogram called by G22 and L parameters
TRAUB_BODY = [
    "G59 X0 Z210",
    "G95",
    "G96 V180 T0101 M4",
    "G92 S3000",
    "L1=10",
    "L2=L1*2",
    "G0 X54 Z2 M8",
    "N10 G46",
    "G1 X20 Z0 F0.15",
    "G1 X=L1 Z-5",
    "G1 Z-30",
    "G2 X40 Z-40 R10",
    "G1 X50 A135",
    "N20 G40",
    "G71 P10 Q20 I0.5 K0.1 D3 F0.3",
    "G0 X100 Z50",
    "G22 A8001",
    "L1=L1+1",
    "G22 A8001 H2",
    "G22 P10 Q20",
]
TRAUB_EDITS = [
    "G0 X100 Z50",
    "G1 X30 F0,2",
    "G1 U-2",
    "L1=12",
    "L3=L1+L2",
    "G1 X=L2 Z-8",
    "G22 A8001",
    "M9",
    "G97 S1000 M3",
    "G1 Z-20",
    "G2 X40 Z-20 R10",
    "G71 P10 Q20 I0.5 K0.1 D3 F0.3",
    "",
    "G1 X",
    "G7",
    "(Kommentar)",
    "G1 A180",
    "N10 G46",
    "N20 G40",
    "N10 G1 X30",
]


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    st.lists(st.sampled_from(TRAUB_EDITS), max_size=8),
    st.integers(1, 3),
    st.lists(edits(TRAUB_EDITS), min_size=1, max_size=6),
)
def test_traub_cycles_subprograms_and_l_parameters_incremental_equal_full_runs(
    extra: list[str], copies: int, steps: list[Any]
) -> None:
    body = [x for _ in range(copies) for x in TRAUB_BODY] + extra
    check_sequence(["%", "O 4711", *body, "M30", "%", *TRAUB_SUB], steps, "traub-tx8d", SMALL)
    check_sequence(["%", "O 4711", *body, "M30", "%", *TRAUB_SUB], steps, "traub-tx8d", RunSetup())


def test_typing_in_a_long_traub_program_takes_over_the_previous_run() -> None:
    """Typing, a new line and a deleted line in a 500-block TRAUB program with cycles, subprogram calls and L
    parameters: each run meets the previous one again (STATS) and answers what a full run answers."""
    body = [x for _ in range(27) for x in TRAUB_BODY][:495]
    lines = ["%", "O 4711", *body, "M30", "%", *TRAUB_SUB]
    memo = Memo()
    run("\n".join(lines) + "\n", "traub-tx8d", RunSetup(), memo)
    before = STATS.copy()
    docs = typing(lines, 253, "G1 X44 Z-12")  # (line 253 is "G1 Z-30")
    docs.append(docs[-1][:100] + ["G1 X20 Z-3"] + docs[-1][100:])
    docs.append(docs[-1][:300] + docs[-1][301:])
    for doc in docs:
        text = "\n".join(doc) + "\n"
        assert live_json(text, "traub-tx8d", RunSetup(), memo) == live_json(
            text, "traub-tx8d", RunSetup(), None
        )
    assert STATS["full"] == before["full"]
    assert STATS["incremental"] - before["incremental"] >= len(docs) - 2


def test_a_dwell_in_a_library_subprogram_keeps_its_line_when_lines_before_the_call_move() -> None:
    """A dwell of a library subprogram taken over from the previous run names a line of the library's file:
    a line inserted into the program before the call moves the program's lines, not the library's."""
    setup = RunSetup(subprograms=((30, "G1 X1\nG1 X2\nG1 X3\nG1 X4\nG4 U2\nM17\n"),))
    lines = ["N10 T1 TC1 M6", "N20 S1200 F150 M3", "G0 X0 Y0 Z2", "G1 Z-1", "G1 X5", "G22 L30", "M30"]
    memo = Memo()
    run("\n".join(lines) + "\n", "pal-mill", setup, memo)
    text = "\n".join([*lines[:2], "(Kommentar)", *lines[2:]]) + "\n"
    before = STATS.copy()
    assert live_json(text, "pal-mill", setup, memo) == live_json(text, "pal-mill", setup, None)
    assert STATS["incremental"] - before["incremental"] == 1  # it met the previous run before the call
    assert run(text, "pal-mill", setup).dwells[0].span.line == 5  # the G4 U2 of L30


def test_live_runs_leave_no_reference_cycles() -> None:
    """The live worker moves its documents' memos out of the garbage collector's way after each batch
    (server/jobs.py: gc.freeze), which is only safe while live runs make no reference cycles: none of
    the objects of core or server that keystrokes in a long program leave behind is cyclic garbage."""
    lines = bench_program(300)
    gc.collect()
    gc.set_debug(gc.DEBUG_SAVEALL)  # unreachable objects go to gc.garbage instead of being freed
    try:
        for gen, doc in enumerate(typing(lines, 150, "N1495 G1 X33 Y44 F200")):
            job_live("cycles", gen, gen + 1, "\n".join(doc) + "\n", "pal-mill", {"skip_blocks": None})
        job_live("cycles", 99, 100, "\n".join(lines[:100] + ["G1 X5"] + lines[100:]) + "\n", "pal-mill", {})
        gc.collect()
        ours = [x for x in gc.garbage if type(x).__module__.startswith(("core.", "server."))]
    finally:
        gc.set_debug(0)
        gc.garbage.clear()
    assert ours == []


def test_an_answer_only_run_makes_the_same_answer_and_no_line_states() -> None:
    """The live worker's runs make only what an answer shows (RunSetup.answer_only): the same commands,
    diagnostics and final position as a whole run, incremental runs included, and no state per line."""
    lines = bench_program(120)
    answer = RunSetup(answer_only=True)
    memo, kinds = Memo(), []
    for doc in [lines, *typing(lines, 60, "N595 G1 X33 Y44 F200"), lines[:30] + ["G1 X5"] + lines[30:]]:
        text = "\n".join(doc) + "\n"
        whole, quick = run(text, "pal-mill"), run(text, "pal-mill", answer, memo)
        kinds.append(memo.runs.kind)
        assert quick.commands == whole.commands
        assert quick.diagnostics == whole.diagnostics
        assert quick.final_position == whole.final_position
        assert quick.line_states == [] and quick.moves == []
        assert len(whole.line_states) == len(doc) and len(whole.moves) > 100
    assert kinds.count("incremental") >= 15  # (most keystrokes' runs met the previous ones)


class _Item:
    def __init__(self, line: int) -> None:
        self.span = type("S", (), {"line": line})()


@settings(max_examples=200, deadline=None)
@given(
    st.lists(st.integers(1, 30), max_size=60),
    st.integers(0, 60),
    st.integers(0, 8),
    st.lists(st.integers(1, 30), max_size=8),
)
def test_a_live_answer_regroups_only_the_commands_a_run_changed(
    lines: list[int], at: int, removed: int, added: list[int]
) -> None:
    """The worker groups a run's commands by line from the previous grouping where the run took most of them
    over (the same objects): the grouping equals one made anew, and the lines it names as changed are every
    line whose commands differ, each with its commands before. Where it cannot tell (a line with commands
    outside the changed ones, as a subprogram's line called twice), it says so and changes nothing."""
    from server.jobs import _by_line, _regroup

    old = [_Item(n) for n in lines]
    at = min(at, len(old))
    new = old[:at] + [_Item(n) for n in added] + old[at + removed :]
    grouped = _by_line(old)
    before = dict(grouped)
    changed = _regroup(old, new, grouped)
    if changed is None:
        assert grouped == before
        return
    assert grouped == _by_line(new)
    differ = {n for n in before.keys() | grouped.keys() if before.get(n) != grouped.get(n)}
    assert differ <= changed.keys()
    assert all(before.get(n, ()) == was for n, was in changed.items())
