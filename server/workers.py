"""CPU-bound work (check, run, simulate, the live re-runs) in worker processes, never on the event loop.

The jobs are plain top-level functions of plain data, so they cross the process boundary by pickle.
A job that exceeds the time limit is abandoned: its pool is torn down and a fresh one started.
"""

from __future__ import annotations

import asyncio
import gc
import importlib.util
import itertools
import json
import logging
import multiprocessing
from collections import OrderedDict, defaultdict
from concurrent.futures import Future, ProcessPoolExecutor
from typing import Any, TypeVar

from core.diagnostics import Severity
from core.exercises import Exercise as ExerciseDocument
from core.exercises import ExerciseError, parse_exercise
from core.grading import grade
from core.interpreter.state import RunSetup
from core.pipeline import Memo, diagnostics_json, run, toolpath_json
from core.tools import DEFAULT_TOOLS, Tool, ToolTable
from server.errors import ApiError

log = logging.getLogger("paltrainer.server")
T = TypeVar("T")

HAS_SIM = importlib.util.find_spec("core.sim") is not None


_DOCUMENTS: OrderedDict[str, ExerciseDocument] = OrderedDict()


def exercise_document(spec: dict[str, Any]) -> ExerciseDocument | None:
    """The validated exercise of a spec (kept per worker by its key, as live edits repeat it)."""
    data = spec.get("exercise")
    if data is None:
        return None
    key = str(spec.get("exercise_key", ""))
    doc = _DOCUMENTS.get(key) if key else None
    if doc is None:
        doc = ExerciseDocument.model_validate(data)
        if key:
            _DOCUMENTS[key] = doc
            while len(_DOCUMENTS) > 200:
                _DOCUMENTS.popitem(last=False)
    return doc


def make_setup(spec: dict[str, Any], base: ToolTable = DEFAULT_TOOLS) -> RunSetup:
    """The RunSetup a request describes: an exercise's tools, zero offsets and subprograms, or the
    default table; then the request's own tools on top; and whether "/" blocks are skipped."""
    exercise = exercise_document(spec)
    extra: dict[str, Any] = {}
    if exercise is not None:
        table = exercise.tool_table()
        extra = {"zero_offsets": tuple(exercise.zero_offsets.items()),
                 "subprograms": tuple(exercise.subprograms.items())}
    else:
        table = ToolTable({}) if spec.get("replace_tools") else base
    for t in spec.get("tools") or ():
        table = table.with_tool(Tool(int(t["number"]), t.get("kind", "end_mill"), float(t["diameter"]),
                                     t.get("name", "")))
    return RunSetup(tools=table, skip_blocks=bool(spec.get("skip_blocks", False)), **extra)


# --- jobs (run inside a worker process) -----------------------------------------------------


def job_warm() -> bool:
    """Load the grammars, then freeze what is loaded: the collector no longer walks the grammar tables
    on every full collection (which doubled some runs' time), and collects the old generation seldom."""
    run("N10 G0 X0 Y0 Z2\nN20 M30\n")
    for module in ("core.sim", "core.grading"):  # so that no first simulation or grading waits for them
        importlib.import_module(module)
    gc.collect()
    gc.freeze()
    gc.set_threshold(100_000, 50, 1000)
    return True


def job_check(text: str, dialect: str, spec: dict[str, Any]) -> dict[str, Any]:
    return diagnostics_json(run(text, dialect, make_setup(spec)).diagnostics)


def job_run(text: str, dialect: str, spec: dict[str, Any]) -> dict[str, Any]:
    return toolpath_json(run(text, dialect, make_setup(spec)))


def job_simulate(text: str, dialect: str, spec: dict[str, Any]) -> dict[str, Any]:
    """`paltrainer simulate --json` for a program: spec["stock"] is {"min": [x, y, z], "max": [x, y, z]}."""
    from core.sim import DEFAULT_SIM_TOOLS, Stock, simulate, simulation_json

    setup = make_setup(spec, DEFAULT_SIM_TOOLS)
    lo, hi = spec["stock"]["min"], spec["stock"]["max"]
    stock = Stock(lo[0], lo[1], lo[2], hi[0], hi[1], hi[2])
    result = simulate(run(text, dialect, setup), stock, setup.tools, spec["resolution"])
    return simulation_json(result)


def job_submission(text: str, dialect: str, spec: dict[str, Any]) -> dict[str, Any]:
    """A submission's result: its diagnostics, a summary of its run and, for an exercise the grader
    can read, the grade (`paltrainer grade --json`, all criteria; None otherwise)."""
    toolpath = run(text, dialect, make_setup(spec))
    exercise = exercise_document(spec)
    grading = grade(exercise, text).to_json("instructor") if exercise is not None else None
    diags = [d.to_json() for d in toolpath.diagnostics]
    kinds: dict[str, int] = defaultdict(int)
    for m in toolpath.moves:
        kinds[m.kind] += 1
    return {
        "diagnostics": diags,
        "errors": sum(d.severity is Severity.ERROR for d in toolpath.diagnostics),
        "warnings": sum(d.severity is Severity.WARNING for d in toolpath.diagnostics),
        "summary": {"moves": len(toolpath.moves), "rapid": kinds["rapid"], "feed": kinds["feed"],
                    "arc": kinds["arc"], "tool_changes": len(toolpath.tool_changes),
                    "dwells": len(toolpath.dwells)},
        "grading": grading,
    }


MAX_SCENE_SEGMENTS = 20_000  # toolpath segments sent to the 3D view; beyond, the path is cut (and said so)
SCENE_RESOLUTION = 0.5  # mm: the 3D view's stock is a coarse level of detail
SCENE_TRIANGLES = 40_000  # the fine level of detail, sent right after the coarse one
PLAYBACK_TRIANGLES = 6_000  # the coarse level: first picture and playback (a step stays under 150 KB)


def job_scene(text: str, dialect: str, spec: dict[str, Any]) -> dict[str, Any]:
    """What the 3D view shows of a program: toolpath segments (arcs as chords), the stock after it, the tool."""
    import numpy as np

    from core.sim import Stock, simulate, stock_tiles

    setup = make_setup(spec)
    toolpath = run(text, dialect, setup)
    segments: list[tuple[Any, Any]] = []
    rapid: list[bool] = []
    lines: list[int] = []
    moves: list[int] = []  # the move each segment belongs to (playback shows the stock after that move)
    contour: list[tuple[Any, Any]] = []  # the programmed contour where it differs from the tool-centre path
    for k, m in enumerate(toolpath.moves):
        points = m.points(0.05)
        for a, b in itertools.pairwise(points):
            segments.append((a, b))
            rapid.append(m.kind == "rapid")
            lines.append(m.line)
            moves.append(k)
        if m.programmed_end is not None and m.programmed_end != m.end:
            contour.append((contour[-1][1] if contour else m.programmed_end, m.programmed_end))
    states = {}
    for line in sorted(set(lines)):
        state, position = toolpath.state_at(line)
        codes = state.codes
        states[line] = {"plane": codes.get("plane"), "dimensions": codes.get("dimensions"),
                        "compensation": codes.get("compensation"), "zero_offset": codes.get("zero_offset"),
                        "feed": state.feed, "speed": state.speed, "tool": state.tool,
                        "position": [round(v, 3) for v in position]}
    cut = len(segments) > MAX_SCENE_SEGMENTS
    segments, rapid = segments[:MAX_SCENE_SEGMENTS], rapid[:MAX_SCENE_SEGMENTS]
    lines, moves = lines[:MAX_SCENE_SEGMENTS], moves[:MAX_SCENE_SEGMENTS]
    seg = np.asarray(segments, dtype=np.float32).reshape(-1, 2, 3)
    is_rapid = np.asarray(rapid, dtype=bool)
    stock = None
    box = spec.get("stock")
    if box:
        result = simulate(toolpath, Stock(*box["min"], *box["max"]), setup.tools, SCENE_RESOLUTION)
        stock = {"coarse": stock_tiles(result.heightmap, PLAYBACK_TRIANGLES),
                 "fine": stock_tiles(result.heightmap, SCENE_TRIANGLES)}
    last = toolpath.moves[-1] if toolpath.moves else None
    tool = setup.tools.get(last.tool) if last is not None and last.tool is not None else None
    programmed = np.asarray(contour, dtype=np.float32).reshape(-1, 2, 3)
    return {"segments": seg, "feed": seg[~is_rapid], "rapid": seg[is_rapid], "lines": lines, "cut": cut,
            "contour": programmed, "states": states, "moves": moves,
            "stock": stock, "tool": list(toolpath.final_position), "tool_radius": tool.radius if tool else 3.0,
            "errors": sum(d.severity is Severity.ERROR for d in toolpath.diagnostics)}



def job_stock_after(text: str, dialect: str, spec: dict[str, Any], moves: int) -> Any:
    """The stock after the first `moves` moves of the program, as coarse tiles (see core.sim.stock_tiles)."""
    import copy

    from core.sim import Stock, simulate, stock_tiles
    from core.toolpath import Move

    setup = make_setup(spec)
    toolpath = run(text, dialect, setup)
    prefix: list[Any] = []
    count = 0
    for c in toolpath.commands:
        if isinstance(c, Move):
            if count >= moves:
                break
            count += 1
        prefix.append(c)
    partial = copy.copy(toolpath)
    partial.commands = prefix
    box = spec["stock"]
    result = simulate(partial, Stock(*box["min"], *box["max"]), setup.tools, SCENE_RESOLUTION)
    return stock_tiles(result.heightmap, PLAYBACK_TRIANGLES)


def job_deviation(text: str, spec: dict[str, Any]) -> dict[str, Any]:
    """Where a program's part leaves the exercise's tolerance band: the cells' surface points (mm) where too
    much material was removed and where too much is left."""
    import numpy as np

    from core.grading import deviation

    exercise = exercise_document(spec)
    if exercise is None:
        return {"too_much": np.zeros((0, 3), np.float32), "too_little": np.zeros((0, 3), np.float32), "cell": 0.0}
    d = deviation(exercise, text)
    return {"too_much": d.points("over"), "too_little": d.points("left"), "cell": d.part.grid.dx}


def job_picture(document: dict[str, Any]) -> bytes:
    """The finished part of an exercise as a top-view depth image (PNG)."""
    from core.sim import depth_png, simulate

    exercise = ExerciseDocument.model_validate(document)
    tools = exercise.tool_table()
    setup = RunSetup(tools=tools, zero_offsets=tuple(exercise.zero_offsets.items()),
                     subprograms=tuple(exercise.subprograms.items()))
    result = simulate(run(exercise.reference, exercise.dialect, setup), exercise.stock.stock(), tools, 0.2)
    return depth_png(result.heightmap, max_pixels=640)


def job_validate_exercise(text: str) -> dict[str, Any]:
    """An uploaded exercise (YAML or JSON, the format of docs/exercises.md) checked as an author's upload must be:
    valid, and its reference scoring full marks. Answers {"document"} or {"invalid"} or {"reference"}."""
    try:
        exercise = parse_exercise(text)
    except ExerciseError as err:
        return {"invalid": str(err)}
    result = grade(exercise, exercise.reference)
    if result.score < result.max_score:
        lost = [c for c in result.criteria if not c.passed]
        return {"reference": {"score": result.score, "max_score": result.max_score,
                              "detail": " ".join(c.message for c in lost),
                              "detail_en": " ".join(c.message_en for c in lost)}}
    return {"document": exercise.model_dump(mode="json")}


class _LiveCache:
    """One live document's last result in this worker: per line, its diagnostics and its commands, and
    the pipeline's memo (parsed lines, block readings) for the next run of the same dialect and set-up."""

    __slots__ = ("commands", "diagnostics", "gen", "memo", "memo_key")

    def __init__(self, gen: int, diagnostics: dict[int, tuple[Any, ...]], commands: dict[int, tuple[Any, ...]],
                 memo: Memo, memo_key: str) -> None:
        self.gen, self.diagnostics, self.commands = gen, diagnostics, commands
        self.memo, self.memo_key = memo, memo_key


_LIVE: OrderedDict[str, _LiveCache] = OrderedDict()
_LIVE_MAX = 500  # documents kept per worker process; the oldest is dropped first


def _by_line(items: Any) -> dict[int, tuple[Any, ...]]:
    out: dict[int, list[Any]] = defaultdict(list)
    for x in items:
        out[x.span.line].append(x)
    return {k: tuple(v) for k, v in out.items()}


def _path_json(commands: tuple[Any, ...]) -> dict[str, list[dict[str, Any]]]:
    entry: dict[str, list[dict[str, Any]]] = {"moves": [], "dwells": [], "tool_changes": []}
    for c in commands:
        kind = type(c).__name__
        entry["moves" if kind == "Move" else "dwells" if kind == "Dwell" else "tool_changes"].append(c.to_json())
    return entry


def job_live(doc: str, base_gen: int, gen: int, text: str, dialect: str, spec: dict[str, Any]) -> dict[str, Any]:
    """Re-run live document `doc` and answer the lines whose result differs from generation `base_gen`.

    The worker keeps each document's last result (a pool of one process per slot keeps a document
    on one process). If it does not hold generation `base_gen` (a new or restarted worker), the
    answer is complete (`full`): every line that has something.
    """
    cached = _LIVE.pop(doc, None)
    memo_key = json.dumps([dialect, spec], sort_keys=True, default=str)
    memo = cached.memo if cached is not None and cached.memo_key == memo_key else Memo()
    toolpath = run(text, dialect, make_setup(spec), memo)
    diagnostics, commands = _by_line(toolpath.diagnostics), _by_line(toolpath.commands)
    full = cached is None or cached.gen != base_gen
    old_d = {} if full or cached is None else cached.diagnostics
    old_c = {} if full or cached is None else cached.commands
    _LIVE[doc] = _LiveCache(gen, diagnostics, commands, memo, memo_key)
    while len(_LIVE) > _LIVE_MAX:
        _LIVE.popitem(last=False)
    d_out = {n: [x.to_json() for x in diagnostics.get(n, ())] for n in old_d.keys() | diagnostics.keys()
             if old_d.get(n) != diagnostics.get(n)}
    empty: tuple[Any, ...] = ()
    c_out = {n: _path_json(commands.get(n, empty)) for n in old_c.keys() | commands.keys()
             if old_c.get(n) != commands.get(n)}
    p = toolpath.final_position
    return {"full": full, "gen": gen, "diagnostics": d_out, "toolpath": c_out,
            "final": [round(p[0], 6), round(p[1], 6), round(p[2], 6)]}


def job_live_close(doc: str) -> None:
    _LIVE.pop(doc, None)


# --- the pool -------------------------------------------------------------------------------


class Workers:
    """Worker processes with a time limit per job: one single-process pool per slot, so that a live
    document can stay on one process (`affinity`) while other jobs go to the least busy slot."""

    def __init__(self, processes: int, seconds: float) -> None:
        self.processes, self.seconds = max(1, processes), seconds
        self._pools: list[ProcessPoolExecutor] = []
        self._busy: list[int] = []
        self._documents = [0] * self.processes  # live documents per slot

    @staticmethod
    def _new_pool() -> tuple[ProcessPoolExecutor, Future[bool]]:
        pool = ProcessPoolExecutor(1, mp_context=multiprocessing.get_context("spawn"))
        return pool, pool.submit(job_warm)

    def start(self) -> None:
        started = [self._new_pool() for _ in range(self.processes)]
        self._pools = [pool for pool, _ in started]
        self._busy = [0] * self.processes
        for _, warm in started:
            warm.result()

    def stop(self) -> None:
        pools, self._pools = self._pools, []
        for pool in pools:
            pool.shutdown(wait=True, cancel_futures=True)

    @property
    def alive(self) -> bool:
        return bool(self._pools)

    def _restart(self, slot: int) -> None:
        pool = self._pools[slot]
        for proc in list(getattr(pool, "_processes", {}).values()):
            proc.terminate()
        pool.shutdown(wait=False, cancel_futures=True)
        self._pools[slot] = self._new_pool()[0]

    def take_slot(self) -> int:
        """The slot for a new live document: the one holding the fewest; give it back with `release_slot`."""
        slot = min(range(self.processes), key=self._documents.__getitem__)
        self._documents[slot] += 1
        return slot

    def release_slot(self, slot: int) -> None:
        self._documents[slot] = max(0, self._documents[slot] - 1)

    async def call(self, fn: Any, *args: Any, affinity: int | None = None) -> Any:
        """Run `fn(*args)` in a worker; TIME_LIMIT (503) when it takes longer than the limit."""
        if not self._pools:
            raise ApiError("NOT_READY", detail="workers not started")
        slot = affinity % self.processes if affinity is not None else min(range(self.processes),
                                                                           key=self._busy.__getitem__)
        pool = self._pools[slot]
        future: Future[Any] = pool.submit(fn, *args)
        self._busy[slot] += 1
        try:
            return await asyncio.wait_for(asyncio.wrap_future(future), self.seconds)
        except TimeoutError:
            log.warning("job over time limit, restarting its worker", extra={"job": fn.__name__})
            if self._pools and self._pools[slot] is pool:
                self._restart(slot)
            raise ApiError("TIME_LIMIT", seconds=self.seconds) from None
        finally:
            self._busy[slot] -= 1
