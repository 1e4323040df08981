"""CPU-bound work (check, run, simulate, the live re-runs, the 3D view's scenes, pictures and sheets) in worker
processes, never on the event loop: every job is here, and the pool that runs them.

The jobs are plain top-level functions of plain data, so they cross the process boundary by pickle.
Every job is submitted through `Workers.call`, which handles for all callers what can happen to a worker
process: a job over the time limit (counted from its start) ends its process, a process that dies is
replaced and its job retried once; see the class. Heavy jobs (everything but check, run and the live
re-runs) never take the last free process, and one user has only so many heavy requests at a time
(`Workers.admit`); results of pure jobs on content (pictures, drawings, task sheets) are kept by that content
(`Workers.cached`).
"""

from __future__ import annotations

import asyncio
import contextlib
import dataclasses
import gc
import hashlib
import importlib.util
import json
import logging
import multiprocessing
import operator
import threading
import time
from collections import Counter, OrderedDict, defaultdict, deque
from collections.abc import Callable, Iterator
from concurrent.futures import Future, ProcessPoolExecutor
from concurrent.futures.process import BrokenProcessPool
from multiprocessing.connection import wait as mp_wait
from typing import Any, Literal, TypeVar

from core.diagnostics import Severity
from core.exercises import Exercise as ExerciseDocument
from core.exercises import ExerciseError, parse_exercise
from core.grading import grade
from core.interpreter.state import RunSetup
from core.pipeline import DIALECTS, Memo, diagnostics_json, run, summarised, toolpath_json
from core.scene.meshes import Tiles
from core.scene.payload import (
    NO_DEVIATION,
    SceneDeviation,
    ScenePayload,
    StockLevels,
    TurnedPart,
    lathe_scene,
    mill_scene,
    milled_deviation,
    turned_deviation,
)
from core.scene.turned import TURNED_RESOLUTION, TurnedProfile, ViewBlank, turned_chunks, view_blank
from core.sequences import common_ends
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
        extra = {
            "zero_offsets": tuple(exercise.zero_offsets.items()),
            "subprograms": tuple(exercise.subprograms.items()),
        }
    else:
        table = ToolTable({}) if spec.get("replace_tools") else base
    for t in spec.get("tools") or ():
        table = table.with_tool(
            Tool(
                int(t["number"]),
                t.get("kind", "end_mill"),
                float(t["diameter"]),
                t.get("name", ""),
                nose_radius=float(t.get("nose_radius", 0.0)),
                quadrant=int(t.get("quadrant", 0)),
            )
        )
    skip = spec.get("skip_blocks")  # None: the dialect's default
    return RunSetup(tools=table, skip_blocks=None if skip is None else bool(skip), **extra)


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


STORED_DIAGNOSTICS = 200  # diagnostics a submission keeps (the first ones); its summary counts all of them


def job_submission(text: str, dialect: str, spec: dict[str, Any]) -> dict[str, Any]:
    """A submission's result: its first STORED_DIAGNOSTICS diagnostics, a summary of its run (with the number
    of all its diagnostics, `diagnostics`) and, for an exercise the grader can read, the grade (`paltrainer
    grade --json`, all criteria; None otherwise). The error and warning counts are of all diagnostics."""
    toolpath = run(text, dialect, make_setup(spec))
    exercise = exercise_document(spec)
    grading = grade(exercise, text).to_json("instructor") if exercise is not None else None
    diags = [d.to_json() for d in toolpath.diagnostics[:STORED_DIAGNOSTICS]]
    kinds: dict[str, int] = defaultdict(int)
    for m in toolpath.moves:
        kinds[m.kind] += 1
    return {
        "diagnostics": diags,
        "errors": sum(d.severity is Severity.ERROR for d in toolpath.diagnostics),
        "warnings": sum(d.severity is Severity.WARNING for d in toolpath.diagnostics),
        "summary": {
            "moves": len(toolpath.moves),
            "rapid": kinds["rapid"],
            "feed": kinds["feed"],
            "arc": kinds["arc"],
            "tool_changes": len(toolpath.tool_changes),
            "dwells": len(toolpath.dwells),
            "diagnostics": len(toolpath.diagnostics),
        },
        "grading": grading,
    }


# --- the 3D view and its 2D stand-in (server/viz.py shows what these make: core/scene/payload.py) ---------
SCENE_RESOLUTION = 0.5  # mm: the 3D view's stock is a coarse level of detail
SCENE_TRIANGLES = 40_000  # the fine level of detail, sent right after the coarse one
PLAYBACK_TRIANGLES = 6_000  # the coarse level: first picture and playback (a step stays under 150 KB)


def is_lathe(dialect: str) -> bool:
    """A turning dialect: its scene is the lathe's drawing view, its pictures the turned part."""
    found = DIALECTS.get(dialect)
    return found is not None and found.lathe


def _given_blank(spec: dict[str, Any]) -> dict[str, Any] | None:
    """The blank a request names, else its exercise's (None: a bar around the program)."""
    found: dict[str, Any] | None = spec.get("blank") or (spec.get("exercise") or {}).get("blank")
    return found


def job_scene(text: str, dialect: str, spec: dict[str, Any]) -> ScenePayload:
    """What the 3D view shows of a program: its toolpath, the tools that cut it, the stock after it (the
    request's box; none without one) or, for a turning program, the part turned from the blank
    (`job_turned_after`) in the lathe's drawing view."""
    from core.sim import DEFAULT_LATHE_TOOLS, Stock, simulate, stock_tiles

    setup = make_setup(spec)
    toolpath = run(text, dialect, setup)
    if is_lathe(dialect):
        inserts = make_setup(spec, DEFAULT_LATHE_TOOLS).tools
        return lathe_scene(toolpath, setup.tools, inserts, job_turned_after(text, dialect, spec, None))
    stock = None
    box = spec.get("stock")
    if box:
        result = simulate(toolpath, Stock(*box["min"], *box["max"]), setup.tools, SCENE_RESOLUTION)
        stock = StockLevels(
            stock_tiles(result.heightmap, PLAYBACK_TRIANGLES), stock_tiles(result.heightmap, SCENE_TRIANGLES)
        )
    return mill_scene(toolpath, setup.tools, stock)


def job_stock_after(text: str, dialect: str, spec: dict[str, Any], moves: int) -> Tiles:
    """The stock after the first `moves` moves of the program, as coarse tiles (see core.sim.stock_tiles)."""
    from core.sim import Stock, simulate, stock_tiles

    setup = make_setup(spec)
    partial = run(text, dialect, setup).until_move(moves)
    box = spec["stock"]
    result = simulate(partial, Stock(*box["min"], *box["max"]), setup.tools, SCENE_RESOLUTION)
    return stock_tiles(result.heightmap, PLAYBACK_TRIANGLES)


def job_turned_after(text: str, dialect: str, spec: dict[str, Any], moves: int | None) -> TurnedPart:
    """The turned part after the first `moves` moves (None: all; playback: the move shown), turned from the
    blank the view shows (view_blank) with the lathe's tools, its chunks cut open when spec["half"] says so."""
    from core.sim import DEFAULT_LATHE_TOOLS, simulate_turning

    setup = make_setup(spec, DEFAULT_LATHE_TOOLS)
    toolpath = run(text, dialect, setup)
    blank = view_blank(_given_blank(spec), toolpath)
    if moves is not None:
        toolpath = toolpath.until_move(moves)
    result = simulate_turning(toolpath, blank, setup.tools, TURNED_RESOLUTION)
    profile = TurnedProfile.of(result.profile)
    return TurnedPart(profile, ViewBlank.of(blank), turned_chunks(profile, bool(spec.get("half"))))


def job_turned_chunks(profile: TurnedProfile, half: bool) -> Tiles:
    """The chunks of a profile shown already, whole or cut open (the half-section toggle)."""
    return turned_chunks(profile, half)


def job_view_deviation(text: str, spec: dict[str, Any]) -> SceneDeviation:
    """Where a program's part leaves the exercise's tolerance band (the geometry criterion's tolerance), as
    the view colours it: milling the cells, turning bands around the part (cut open when spec["half"] says
    so); nothing for a request without an exercise document."""
    from core.grading import deviation
    from core.grading.turning import compare_profiles, execute_turning

    exercise = exercise_document(spec)
    if exercise is None:
        return NO_DEVIATION
    if not exercise.lathe:
        return milled_deviation(deviation(exercise, text))
    tol = next(
        (c.tolerance if c.tolerance is not None else 0.05 for c in exercise.rubric if c.id == "geometry"),
        0.05,
    )
    reference, submission = execute_turning(exercise, exercise.reference), execute_turning(exercise, text)
    dev = compare_profiles(reference.sim.profile, submission.sim.profile, tol)
    return turned_deviation(dev, bool(spec.get("half")))


def job_picture_now(text: str, dialect: str, spec: dict[str, Any]) -> bytes:
    """The stock after a program, seen from above (PNG, darker = deeper): what the page shows while the 3D
    view is off. Runs in a worker process."""
    from core.sim import DEFAULT_SIM_TOOLS, Stock, depth_png, simulate

    if is_lathe(dialect):
        return turned_picture(text, dialect, spec)
    setup = make_setup(spec, DEFAULT_SIM_TOOLS)
    lo, hi = spec["stock"]["min"], spec["stock"]["max"]
    result = simulate(run(text, dialect, setup), Stock(*lo, *hi), setup.tools, spec["resolution"])
    return depth_png(result.heightmap, max_pixels=480)


# cells along the stock's longer side at most: the 2D picture's height map (core/picture2d.py)
PICTURE_RASTER = 400
PICTURE_CELL = 0.25  # mm: no finer cells for it


def picture_resolution(spec: dict[str, Any]) -> float:
    """The cell of the 2D picture's height map: the request's, at least PICTURE_CELL and coarse enough that the
    stock's longer side has at most PICTURE_RASTER cells (the simulation's cost is bounded with it)."""
    lo, hi = spec["stock"]["min"], spec["stock"]["max"]
    side = max(float(hi[0]) - float(lo[0]), float(hi[1]) - float(lo[1]))
    return max(float(spec.get("resolution") or 0.0), PICTURE_CELL, side / PICTURE_RASTER)


def job_picture_svg(text: str, dialect: str, spec: dict[str, Any], lang: str = "de") -> dict[str, Any]:
    """The 2D picture of a program's result (core/picture2d.py), what the page shows while the 3D view is off:
    milling the plan view with the depths, the path, the contour, the zero and the blocks an error skipped;
    turning the drawing view with the part in half section (the blank the 3D view turns). {"svg", "info"}.
    Runs in a worker process."""
    from core.picture2d import lathe_picture, mill_picture
    from core.sim import DEFAULT_LATHE_TOOLS, DEFAULT_SIM_TOOLS, Stock, simulate, simulate_turning

    language: Literal["de", "en"] = "en" if lang == "en" else "de"
    if is_lathe(dialect):
        setup = make_setup(spec, DEFAULT_LATHE_TOOLS)
        toolpath = run(text, dialect, setup)
        blank = view_blank(_given_blank(spec), toolpath)
        resolution = max(TURNED_RESOLUTION, blank.length / 4000)
        profile = simulate_turning(toolpath, blank, setup.tools, resolution).profile
        picture = lathe_picture(toolpath, profile, blank, language)
    else:
        setup = make_setup(spec, DEFAULT_SIM_TOOLS)
        toolpath = run(text, dialect, setup)
        stock = Stock(*spec["stock"]["min"], *spec["stock"]["max"])
        result = simulate(toolpath, stock, setup.tools, picture_resolution(spec))
        picture = mill_picture(toolpath, result.heightmap, stock, language)
    return {"svg": picture.svg, "info": picture.info}


PICTURE_SIZE = (480, 320)  # pixels: the lathe's picture while the 3D view is off


def turned_picture(text: str, dialect: str, spec: dict[str, Any]) -> bytes:
    """A turning program's part after it, turned from the blank the 3D view turns (view_blank), as a half
    section in the drawing view (core/drawing/turned_picture.py): the PNG the page shows while the 3D view is
    off."""
    from core.drawing.turned_picture import half_section_image
    from core.picture2d import png_rgb
    from core.sim import DEFAULT_LATHE_TOOLS, simulate_turning

    setup = make_setup(spec, DEFAULT_LATHE_TOOLS)
    toolpath = run(text, dialect, setup)
    blank = view_blank(_given_blank(spec), toolpath)
    profile = simulate_turning(toolpath, blank, setup.tools, TURNED_RESOLUTION).profile
    return png_rgb(
        half_section_image(profile.outer, profile.inner, profile.z0, profile.dz, blank, PICTURE_SIZE)
    )


# --- exercises: pictures, drawings, task sheets -------------------------------------------------


def job_picture(document: dict[str, Any]) -> bytes:
    """The finished part of an exercise as a top-view depth image (PNG)."""
    from core.sim import depth_png, simulate

    exercise = ExerciseDocument.model_validate(document)
    tools = exercise.tool_table()
    setup = RunSetup(
        tools=tools,
        zero_offsets=tuple(exercise.zero_offsets.items()),
        subprograms=tuple(exercise.subprograms.items()),
    )
    result = simulate(run(exercise.reference, exercise.dialect, setup), exercise.stock.stock(), tools, 0.2)
    return depth_png(result.heightmap, max_pixels=640)


def job_drawing(document: dict[str, Any], lang: str) -> str:
    """The dimensioned drawing of an exercise's part (SVG)."""
    from core.drawing import part_drawing

    return part_drawing(ExerciseDocument.model_validate(document), lang)


def job_sheet(document: dict[str, Any], lang: str, drawing: tuple[str, bytes] | None = None) -> bytes:
    """The printed task sheet of one exercise (PDF, core/sheet): its task page and its programming-form pages;
    SheetUnavailable without WeasyPrint. One exercise per job: an assignment's sheets are these, put together
    (job_merge_pdfs), so that no job grows with the number of exercises. `drawing`: the author's own drawing
    (media type, bytes), printed instead of the generated one — an image on the task page, a PDF after the form."""
    import base64

    from core.sheet import merge_pdfs, task_sheet_pdf

    exercise = ExerciseDocument.model_validate(document)
    if drawing is not None and drawing[0] != "application/pdf":
        uri = f"data:{drawing[0]};base64," + base64.b64encode(drawing[1]).decode("ascii")
        return task_sheet_pdf([exercise], lang, {exercise.id: uri})
    sheet = task_sheet_pdf([exercise], lang)
    return merge_pdfs([sheet, drawing[1]]) if drawing is not None else sheet


def job_merge_pdfs(parts: list[bytes]) -> bytes:
    """PDFs one after the other as one (core.sheet.merge_pdfs)."""
    from core.sheet import merge_pdfs

    return merge_pdfs(parts)


def job_validate_exercise(text: str, graded: bool = True) -> dict[str, Any]:
    """An uploaded exercise (YAML or JSON, the format of docs/exercises.md) checked as an author's upload must be:
    valid (every error at once), and (`graded`: published) its reference scoring full marks. Answers {"document"}
    or {"invalid"} or {"reference"}."""
    try:
        exercise = parse_exercise(text)
    except ExerciseError as err:
        return {"invalid": err.message, "invalid_en": err.message_en, "problems": err.problems}
    if not graded:
        return {"document": exercise.model_dump(mode="json")}
    result = grade(exercise, exercise.reference)
    if result.score < result.max_score:
        lost = [c for c in result.criteria if not c.passed]
        return {
            "reference": {
                "score": result.score,
                "max_score": result.max_score,
                "detail": " ".join(c.message for c in lost),
                "detail_en": " ".join(c.message_en for c in lost),
            }
        }
    return {"document": exercise.model_dump(mode="json")}


class _LiveCache:
    """One live document's last result in this worker: per line, its diagnostics and its commands (and the
    list of commands they group), and the pipeline's memo (parsed lines, block readings) for the next run of
    the same dialect and set-up."""

    __slots__ = ("command_list", "commands", "diagnostics", "gen", "json", "memo", "memo_key")

    def __init__(
        self,
        gen: int,
        diagnostics: dict[int, tuple[Any, ...]],
        commands: dict[int, tuple[Any, ...]],
        command_list: list[Any],
        memo: Memo,
        memo_key: str,
        json: dict[int, tuple[Any, dict[str, Any]]] | None = None,
    ) -> None:
        self.gen, self.diagnostics = gen, diagnostics
        self.commands, self.command_list = commands, command_list
        self.memo, self.memo_key, self.json = memo, memo_key, json or {}


_LIVE: OrderedDict[str, _LiveCache] = OrderedDict()
_LIVE_MAX = 500  # documents kept per worker process; the oldest is dropped first


def _by_line(items: Any) -> dict[int, tuple[Any, ...]]:
    out: dict[int, list[Any]] = defaultdict(list)
    for x in items:
        out[x.span.line].append(x)
    return {k: tuple(v) for k, v in out.items()}


def _regroup(
    old: list[Any], new: list[Any], by_line: dict[int, tuple[Any, ...]]
) -> dict[int, tuple[Any, ...]] | None:
    """Make `by_line` (the items of `old` by their line) group `new`, looking only at the items between the two
    lists' common prefix and suffix of the same objects (a live run takes the previous run's commands over
    where the edit changed nothing); answer the lines it changed with their items before. None, with
    `by_line` untouched, where that middle is most of the lists or a line has items outside it: the caller
    groups `new` whole."""
    n_old, n_new = len(old), len(new)
    a, b = common_ends(old, new, operator.is_)
    was, now = old[a : n_old - b], new[a : n_new - b]
    if len(was) + len(now) > min(n_old, n_new) // 2 + 16:
        return None
    gone = Counter(x.span.line for x in was)
    fresh: dict[int, list[Any]] = defaultdict(list)
    for x in now:
        fresh[x.span.line].append(x)
    changed: dict[int, tuple[Any, ...]] = {}
    for n in gone.keys() | fresh.keys():
        before = by_line.get(n, ())
        if len(before) != gone[n]:
            return None  # the line has items before or after the middle too (a subprogram's line)
        changed[n] = before
    for n in changed:
        if n in fresh:
            by_line[n] = tuple(fresh[n])
        else:
            del by_line[n]
    return changed


def _text(items: list[dict[str, Any]]) -> str:
    """A line's diagnostics as JSON text; "" for none. A live answer carries each line's part as text: the
    server's main process keeps one string per line and session instead of its objects (with 500 sessions
    their millions of objects made each of its full collections take most of a second)."""
    return json.dumps(items, separators=(",", ":")) if items else ""


def _members(entry: dict[str, list[dict[str, Any]]]) -> str:
    """A line's toolpath as the members of a JSON object ("moves":[…],"dwells":[…],"tool_changes":[…]), to
    be set into the update's line object; "" for nothing."""
    return json.dumps(entry, separators=(",", ":"))[1:-1] if any(entry.values()) else ""


def _path_json(
    commands: tuple[Any, ...],
    to_json: Callable[[Any], dict[str, Any]] | None = None,
) -> dict[str, list[dict[str, Any]]]:
    entry: dict[str, list[dict[str, Any]]] = {"moves": [], "dwells": [], "tool_changes": []}
    for c in commands:
        kind = type(c).__name__
        entry["moves" if kind == "Move" else "dwells" if kind == "Dwell" else "tool_changes"].append(
            c.to_json() if to_json is None else to_json(c)
        )
    return entry


class _Json:
    """The JSON of the moves of a live document's last answer, kept with the moves (so no other object can
    have their ids): a move taken over from the previous run with its line shifted (Keep.shifted) gets the
    JSON of the move it was made from, with the new lines, instead of being converted again."""

    def __init__(self, known: dict[int, tuple[Any, dict[str, Any]]], shifted: dict[int, Any]) -> None:
        self.known, self.shifted = known, shifted

    def __call__(self, c: Any) -> dict[str, Any]:
        hit = self.known.get(id(c))
        if hit is not None and hit[0] is c:
            return hit[1]
        data: dict[str, Any] | None = None
        was = self.shifted.get(id(c))
        if was is not None:
            hit = self.known.get(id(was))
            if hit is not None and hit[0] is was:  # only the span and the calling lines differ
                data = {
                    **hit[1],
                    "line": c.span.line,
                    "call_stack": [{"source": src, "line": line} for src, line in c.call_stack],
                }
        if data is None:
            data = c.to_json()
        self.known[id(c)] = (c, data)
        return data

    def kept(self, commands: dict[int, tuple[Any, ...]], count: int) -> dict[int, tuple[Any, dict[str, Any]]]:
        """The JSON known for the next answer: all of it while it is not much more than the `count` commands
        of this answer (a keystroke replaces a few), else that of these commands."""
        known = self.known
        if len(known) <= 2 * count + 256:
            return known
        out = {}
        for line in commands.values():
            for c in line:
                hit = known.get(id(c))
                if hit is not None and hit[0] is c:
                    out[id(c)] = hit
        return out


def job_live(
    doc: str, base_gen: int, gen: int, text: str, dialect: str, spec: dict[str, Any]
) -> dict[str, Any]:
    """Re-run live document `doc` and answer the lines whose result differs from generation `base_gen`, each
    line's diagnostics and toolpath as JSON text ("" where the line has none: `_text`, `_members`).

    The worker keeps each document's last result (a pool of one process per slot keeps a document
    on one process). If it does not hold generation `base_gen` (a new or restarted worker), the
    answer is complete (`full`): every line that has something.
    """
    cached = _LIVE.pop(doc, None)
    memo_key = json.dumps([dialect, spec], sort_keys=True, default=str)
    memo = cached.memo if cached is not None and cached.memo_key == memo_key else Memo()
    # the answer has no state per line: the run makes none
    setup = dataclasses.replace(make_setup(spec), answer_only=True)
    toolpath = summarised(run(text, dialect, setup, memo))  # at most max_answer_commands (PAL-I018)
    diagnostics, command_list = _by_line(toolpath.diagnostics), toolpath.commands
    full = cached is None or cached.gen != base_gen
    old_d = {} if full or cached is None else cached.diagnostics
    to_json = _Json(cached.json if cached is not None and cached.memo is memo else {}, memo.runs.shifted)
    d_out = {
        n: _text([x.to_json() for x in diagnostics.get(n, ())])
        for n in old_d.keys() | diagnostics.keys()
        if old_d.get(n) != diagnostics.get(n)
    }
    # the commands by line: regrouped where the run changed a few of them, else grouped anew
    changed = _regroup(cached.command_list, command_list, cached.commands) if cached is not None else None
    if changed is not None and cached is not None:
        commands = cached.commands
        if full:
            changed = dict.fromkeys(commands, ())
    else:
        commands = _by_line(command_list)
        old_c = {} if full or cached is None else cached.commands
        changed = {n: old_c.get(n, ()) for n in old_c.keys() | commands.keys()}
    empty: tuple[Any, ...] = ()
    c_out = {
        n: _members(_path_json(commands.get(n, empty), to_json))
        for n, before in changed.items()
        if before != commands.get(n, empty)
    }
    _LIVE[doc] = _LiveCache(
        gen,
        diagnostics,
        commands,
        command_list,
        memo,
        memo_key,
        to_json.kept(commands, len(command_list)),
    )
    while len(_LIVE) > _LIVE_MAX:
        _LIVE.popitem(last=False)
    p = toolpath.final_position
    return {
        "full": full,
        "gen": gen,
        "diagnostics": d_out,
        "toolpath": c_out,
        "final": [round(p[0], 6), round(p[1], 6), round(p[2], 6)],
        "run": memo.runs.kind,
    }


def job_live_close(doc: str) -> None:
    _LIVE.pop(doc, None)


def job_live_batch(
    fn: Callable[..., dict[str, Any]],
    requests: list[tuple[Any, ...]],
    seconds: float,
) -> list[dict[str, Any] | None]:
    """Several live documents of one worker process in one job, so that the documents waiting for it cost one
    round trip, not one each: the answer of `fn(*request)` (job_live) for each, {"failed": True} where it
    raised, and None for those it left for the next job because `seconds` had passed (well within the job's
    time limit)."""
    start = time.monotonic()
    out: list[dict[str, Any] | None] = []
    gc.disable()  # (live runs make no cycles: collected once at the end instead of on the way)
    for i, request in enumerate(requests):
        if i and time.monotonic() - start > seconds:
            out.extend([None] * (len(requests) - i))
            break
        try:
            out.append(fn(*request))
        except Exception:  # a defect in one document's run: that document's session says so, the others go on
            log.exception("live run failed")
            out.append({"failed": True})
    _keep_out_of_the_collector()
    return out


def _keep_out_of_the_collector() -> None:
    """The live documents' memos (~17,000 objects each for 500 blocks) live long and make no reference cycles:
    moved out of the collector's generations after each batch, so that a collection never walks them. With
    250 documents in a process, one collection of them took 2 s, and each keystroke waited behind it
    (bench/live_latency.py). What the batch and jobs before it left in cycles is collected first (young
    generations only: about 0,2 ms); frozen objects are still freed when nothing refers to them."""
    gc.collect(1)
    gc.freeze()
    gc.enable()


# the jobs every page waits for while a trainee types: they may take any process; every other job is heavy and
# leaves one process free for them (Workers.call)
LIGHT_JOBS: frozenset[Callable[..., Any]] = frozenset(
    {job_warm, job_check, job_run, job_live, job_live_batch, job_live_close}
)


def content_key(*parts: Any) -> str:
    """A key for job results that depend on nothing but `parts` (an exercise's document, the language …)."""
    text = json.dumps(parts, sort_keys=True, separators=(",", ":"), default=str)
    return hashlib.sha256(text.encode("utf-8", errors="surrogatepass")).hexdigest()


class _Results:
    """Results of pure jobs by their content key, the least recently used dropped first beyond `budget` bytes."""

    def __init__(self, budget: int) -> None:
        self.budget, self.size = budget, 0
        self.items: OrderedDict[str, bytes | str] = OrderedDict()
        self.lock = threading.Lock()

    def get(self, key: str) -> bytes | str | None:
        with self.lock:
            value = self.items.get(key)
            if value is not None:
                self.items.move_to_end(key)
            return value

    def put(self, key: str, value: Any) -> None:
        if not isinstance(value, bytes | str) or len(value) > self.budget // 8:
            return
        with self.lock:
            old = self.items.pop(key, None)
            self.size += len(value) - (len(old) if old is not None else 0)
            self.items[key] = value
            while self.size > self.budget and self.items:
                _, dropped = self.items.popitem(last=False)
                self.size -= len(dropped)


# --- the pool -------------------------------------------------------------------------------


class _Job:
    """One job handed to a worker: its future, the worker generation it runs in, and whether it ran out of time."""

    __slots__ = ("future", "generation", "name", "timed_out")

    def __init__(self, future: Future[Any], generation: int, name: str) -> None:
        self.future, self.generation, self.name, self.timed_out = future, generation, name, False


_RESERVED = object()  # a slot handed to a caller that has not submitted its job yet


class _Requeue(Exception):
    """The job never started (its process went away first): it waits for a process again, not counted as a failure."""


class _Slot:
    """One worker process (a ProcessPoolExecutor of one) that runs one job at a time. Each replacement of
    the process is a new generation; callbacks of an older generation find nothing left to do."""

    def __init__(self, index: int) -> None:
        self.index = index
        self.pool: ProcessPoolExecutor | None = None
        self.process: Any = None  # multiprocessing.Process
        self.generation = 0
        self.ready = False  # warmed up and not known dead
        self.job: Any = None  # _Job, _RESERVED or None (free)
        self.heavy = False  # the job it holds is heavy
        self.watched: int | None = None  # the sentinel file descriptor the event loop watches

    def dead(self) -> bool:
        """Whether the process has ended (its sentinel is readable), without reaping it."""
        return self.process is None or bool(mp_wait([self.process.sentinel], 0))


class Workers:
    """Worker processes with a time limit per job: one single-process pool per slot, so that a live
    document can stay on one process (`affinity`) while other jobs go to a free slot.

    Every job goes through `call`, which owns the failure handling for all callers: a job is handed to
    a process only when that process is free, so its time limit counts from its start and a process
    killed for running over time takes no other job with it; a process that dies (kill -9, the
    out-of-memory killer) is replaced at once, and the job that was in it runs once more (jobs are
    pure); a job that kills its process twice is answered 503 WORKER_FAILED.

    Heavy jobs (all but LIGHT_JOBS: pictures, drawings, task sheets, grading, simulations, 3D scenes and
    deviations) run in at most `heavy_processes` processes at once, one fewer than there are: however many
    of them wait, a check, a run or a live update finds a process within one light job's time. `admit`
    counts each user's heavy requests, `cached` keeps the results of jobs on content.
    """

    queue_seconds = 60.0  # longest wait for a free process before 503 BUSY
    respawn_delay = 1.0  # pause before starting again a process that failed to start
    cache_bytes = 64 * 1024 * 1024  # results kept by `cached` (pictures, drawings, task sheets)

    def __init__(self, processes: int, seconds: float) -> None:
        self.processes, self.seconds = max(1, processes), seconds
        self.heavy_processes = self.processes - 1 if self.processes > 1 else 1
        self._slots: list[_Slot] = []
        self._documents = [0] * self.processes  # live documents per slot
        self._waiting: deque[tuple[int | None, bool, asyncio.Future[_Slot]]] = deque()
        self._loop: asyncio.AbstractEventLoop | None = None
        self._owners: Counter[str] = Counter()  # heavy requests under way, per user, key or address
        self._owners_lock = threading.Lock()
        self._results = _Results(self.cache_bytes)
        self._flights: dict[str, asyncio.Future[Any]] = {}  # `cached` jobs under way, by key

    # -- life cycle

    def start(self) -> None:
        """Start the processes and wait until each is warm (called in the app's start-up)."""
        with contextlib.suppress(RuntimeError):
            self._loop = asyncio.get_running_loop()
        self._slots = [_Slot(k) for k in range(self.processes)]
        warms = [self._spawn(slot) for slot in self._slots]
        for slot, warm in zip(self._slots, warms, strict=True):
            warm.result()
            slot.ready = True

    def stop(self) -> None:
        slots, self._slots = self._slots, []
        for slot in slots:
            slot.generation += 1  # callbacks still under way find nothing to do
            self._unwatch(slot)
            if slot.process is not None and slot.job is not None:
                slot.process.kill()  # jobs are pure: nothing is lost
            if slot.pool is not None:
                slot.pool.shutdown(wait=True, cancel_futures=True)
        for _, _, waiter in self._waiting:
            if not waiter.done():
                waiter.set_exception(ApiError("NOT_READY", detail="workers stopped"))
        self._waiting.clear()

    @property
    def alive(self) -> bool:
        """Started and not stopped."""
        return bool(self._slots)

    @property
    def ready(self) -> bool:
        """Whether some process can take a job now or after the one it runs (GET /readyz)."""
        return any(slot.ready and not slot.dead() for slot in self._slots)

    def pids(self) -> list[int]:
        """The worker processes' ids, one per slot."""
        return [slot.process.pid for slot in self._slots if slot.process is not None]

    @property
    def waiting(self) -> int:
        """Callers waiting for a process."""
        return sum(1 for _, _, waiter in self._waiting if not waiter.done())

    @property
    def busy(self) -> int:
        """Processes running a job (or handed one)."""
        return sum(1 for slot in self._slots if slot.job is not None)

    @staticmethod
    def is_heavy(fn: Callable[..., Any]) -> bool:
        """Whether a job leaves the last free process to the light ones (all but LIGHT_JOBS)."""
        return fn not in LIGHT_JOBS

    # -- heavy requests per user, and results by content

    @contextlib.contextmanager
    def admit(self, owner: str, limit: int) -> Iterator[None]:
        """One heavy request of `owner` (a user, key or address) while the block runs; 429 TOO_MANY_JOBS when
        `owner` has `limit` of them under way already. Counted in this process (each replica on its own)."""
        with self._owners_lock:
            if self._owners[owner] >= limit:
                raise ApiError("TOO_MANY_JOBS", headers={"Retry-After": "2"}, limit=limit)
            self._owners[owner] += 1
        try:
            yield
        finally:
            with self._owners_lock:
                self._owners[owner] -= 1
                if self._owners[owner] <= 0:
                    del self._owners[owner]

    async def cached(self, key: str, fn: Any, *args: Any) -> Any:
        """`call(fn, *args)` for a pure job whose result depends on nothing but `key` (content_key of its
        input): a result made before is answered from memory (cache_bytes, least recently used dropped first),
        and callers asking for the same key at once share one job."""
        hit = self._results.get(key)
        if hit is not None:
            return hit
        loop = asyncio.get_running_loop()
        flight = self._flights.get(key)
        if flight is None or flight.get_loop() is not loop:
            flight = asyncio.ensure_future(self.call(fn, *args))
            self._flights[key] = flight
            flight.add_done_callback(lambda done: self._landed(key, done))
        return await asyncio.shield(flight)  # a caller that goes away leaves the job to the others

    def _landed(self, key: str, flight: asyncio.Future[Any]) -> None:
        if self._flights.get(key) is flight:
            del self._flights[key]
        if not flight.cancelled() and flight.exception() is None:
            self._results.put(key, flight.result())

    def _attach(self) -> asyncio.AbstractEventLoop:
        """The event loop the pool reports to: the one start() ran in, else the first caller's."""
        if self._loop is None:
            self._loop = asyncio.get_running_loop()
            for slot in self._slots:
                self._watch(slot)
        return self._loop

    def _rehome(self) -> None:
        for slot in self._slots:
            slot.watched = None  # registered with the old loop, which is gone
        self._waiting.clear()
        self._loop = None
        self._attach()

    def _spawn(self, slot: _Slot) -> Future[bool]:
        """A new process for `slot`, warming up; the slot takes jobs once it is warm."""
        pool = ProcessPoolExecutor(1, mp_context=multiprocessing.get_context("spawn"))
        warm = pool.submit(job_warm)  # starts the process
        slot.generation += 1
        slot.pool, slot.ready, slot.job = pool, False, None
        slot.process = next(iter(getattr(pool, "_processes", {}).values()), None)
        if self._loop is not None:
            self._watch(slot)
            generation = slot.generation
            warm.add_done_callback(lambda f: self._soon(self._warmed, slot, generation, f))
        return warm

    def _replace(self, slot: _Slot, reason: str) -> None:
        """End `slot`'s process (if it still runs) and start a new one."""
        log.warning(
            "worker process replaced (slot %d, pid %s): %s",
            slot.index,
            getattr(slot.process, "pid", None),
            reason,
        )
        self._unwatch(slot)
        if slot.process is not None:
            slot.process.kill()
        if slot.pool is not None:
            # not cancel_futures: a job still queued in it fails as BrokenProcessPool, and its caller retries
            slot.pool.shutdown(wait=False)
        slot.ready, slot.job = False, None
        try:
            self._spawn(slot)
        except OSError:  # no process to be had now (memory, descriptors): try again shortly
            log.exception("worker process could not be started (slot %d)", slot.index)
            if self._loop is not None:
                self._loop.call_later(self.respawn_delay, self._respawn_if, slot, slot.generation)

    def _soon(self, fn: Any, *args: Any) -> None:
        """Run `fn(*args)` on the event loop (from a pool's thread); nothing when the loop has ended."""
        if self._loop is not None:
            with contextlib.suppress(RuntimeError):
                self._loop.call_soon_threadsafe(fn, *args)

    def _watch(self, slot: _Slot) -> None:
        # the sentinel becomes readable when the process ends: a dead idle worker is replaced at once
        if self._loop is not None and slot.process is not None and slot.watched is None:
            slot.watched = slot.process.sentinel
            self._loop.add_reader(slot.watched, self._died, slot, slot.generation)

    def _unwatch(self, slot: _Slot) -> None:
        if slot.watched is not None and self._loop is not None:
            with contextlib.suppress(RuntimeError):  # the loop may be closed already
                self._loop.remove_reader(slot.watched)
        slot.watched = None

    def _died(self, slot: _Slot, generation: int) -> None:
        self._unwatch(slot)
        if generation == slot.generation and slot in self._slots:
            self._replace(slot, f"process ended (exit code {slot.process.exitcode})")
            self._dispatch()

    def _warmed(self, slot: _Slot, generation: int, warm: Future[bool]) -> None:
        if generation != slot.generation or slot not in self._slots:
            return
        if warm.cancelled() or warm.exception() is not None:
            log.error("worker process failed to start (slot %d)", slot.index)
            self._unwatch(slot)
            assert self._loop is not None
            self._loop.call_later(self.respawn_delay, self._respawn_if, slot, generation)
            return
        slot.ready = True
        self._dispatch()

    def _respawn_if(self, slot: _Slot, generation: int) -> None:
        if generation == slot.generation and slot in self._slots:
            self._replace(slot, "failed to start")

    # -- handing out slots

    def take_slot(self) -> int:
        """The slot for a new live document: the one holding the fewest; give it back with `release_slot`."""
        slot = min(range(self.processes), key=self._documents.__getitem__)
        self._documents[slot] += 1
        return slot

    def release_slot(self, slot: int) -> None:
        self._documents[slot] = max(0, self._documents[slot] - 1)

    def _free(self, affinity: int | None, heavy: bool = False) -> _Slot | None:
        """A slot that can start a job now: the document's own, or any (those with fewer live documents first);
        for a heavy job none while `heavy_processes` run heavy jobs."""
        if not self._slots:
            return None
        if heavy and sum(1 for s in self._slots if s.job is not None and s.heavy) >= self.heavy_processes:
            return None
        if affinity is not None:
            candidates = [self._slots[affinity % len(self._slots)]]
        else:
            candidates = sorted(self._slots, key=lambda s: self._documents[s.index % self.processes])
        for slot in candidates:
            if slot.ready and slot.job is None:
                if slot.dead():  # died since; its watcher has not run yet
                    self._replace(slot, "process ended")
                    continue
                return slot
        return None

    def _dispatch(self) -> None:
        """Hand free slots to the waiting callers, oldest first (a heavy one that must wait lets the light ones
        behind it go first)."""
        for item in list(self._waiting):
            affinity, heavy, waiter = item
            if waiter.done():
                self._waiting.remove(item)
                continue
            slot = self._free(affinity, heavy)
            if slot is not None:
                slot.job, slot.heavy = _RESERVED, heavy
                waiter.set_result(slot)
                self._waiting.remove(item)

    def _release(self, slot: _Slot, job: Any) -> None:
        if slot.job is job:
            slot.job, slot.heavy = None, False
            self._dispatch()

    async def _acquire(self, affinity: int | None, heavy: bool = False) -> _Slot:
        loop = self._attach()
        waiter: asyncio.Future[_Slot] = loop.create_future()
        item = (affinity, heavy, waiter)
        self._waiting.append(item)
        self._dispatch()
        try:
            async with asyncio.timeout(self.queue_seconds):
                return await waiter
        except BaseException as err:
            if item in self._waiting:
                self._waiting.remove(item)
            if waiter.done() and not waiter.cancelled() and waiter.exception() is None:
                slot = waiter.result()
                self._release(slot, _RESERVED)  # handed over just as the caller gave up
            if isinstance(err, TimeoutError):
                raise ApiError("BUSY", seconds=self.queue_seconds) from None
            raise

    # -- running jobs

    def _finished(self, slot: _Slot, job: _Job, timer: asyncio.TimerHandle) -> None:
        timer.cancel()
        if job.generation == slot.generation:
            error = None if job.future.cancelled() else job.future.exception()
            if isinstance(error, BrokenProcessPool):
                self._replace(slot, "process ended during a job")
                self._dispatch()
                return
        self._release(slot, job)

    def _overtime(self, slot: _Slot, job: _Job) -> None:
        """The time limit, counted from the job's start: end its process (it runs nothing else)."""
        if not job.future.done() and job.generation == slot.generation:
            job.timed_out = True
            log.warning("job over time limit, restarting its worker", extra={"job": job.name})
            self._replace(slot, "time limit")
            self._dispatch()

    async def _run_once(self, slot: _Slot, fn: Any, args: tuple[Any, ...]) -> Any:
        loop = self._attach()
        name = getattr(fn, "__name__", "job")
        if slot.job is not _RESERVED or not slot.ready or slot.pool is None:
            self._release(slot, _RESERVED)
            raise _Requeue  # the process was replaced between the hand-over and now
        try:
            future: Future[Any] = slot.pool.submit(fn, *args)
        except (BrokenProcessPool, RuntimeError):  # it died before its watcher noticed, or the pool stopped
            if slot not in self._slots:
                raise ApiError("NOT_READY", detail="workers stopped") from None
            self._replace(slot, "broken pool")
            self._dispatch()
            raise _Requeue from None
        job = _Job(future, slot.generation, name)
        slot.job = job
        timer = loop.call_later(self.seconds, self._overtime, slot, job)
        future.add_done_callback(lambda _: self._soon(self._finished, slot, job, timer))
        try:
            return await asyncio.wrap_future(future)
        except BrokenProcessPool:
            if job.timed_out:
                raise ApiError("TIME_LIMIT", seconds=self.seconds) from None
            raise

    async def call(self, fn: Any, *args: Any, affinity: int | None = None, heavy: bool | None = None) -> Any:
        """Run `fn(*args)` in a worker: TIME_LIMIT (503) when it runs longer than the limit, WORKER_FAILED (503)
        when its process dies twice, BUSY (503) when no process is free for `queue_seconds`. `heavy` (by default
        `is_heavy(fn)`): the job waits while `heavy_processes` run heavy jobs."""
        if not self._slots:
            raise ApiError("NOT_READY", detail="workers not started")
        heavy = self.is_heavy(fn) if heavy is None else heavy
        home, loop = self._loop, asyncio.get_running_loop()
        if home is not None and home is not loop:
            if home.is_running():  # the pool's state belongs to its loop: the call runs there
                return await asyncio.wrap_future(
                    asyncio.run_coroutine_threadsafe(
                        self.call(fn, *args, affinity=affinity, heavy=heavy), home
                    )
                )
            self._rehome()  # the loop start() ran in has ended: this one takes the pool over
        failures = 0
        while True:
            if not self._slots:
                raise ApiError("NOT_READY", detail="workers stopped")
            slot = await self._acquire(affinity, heavy)
            try:
                return await self._run_once(slot, fn, args)
            except _Requeue:
                continue
            except BrokenProcessPool:
                failures += 1
                log.warning(
                    "worker process lost during a job (%d of 2)",
                    failures,
                    extra={"job": getattr(fn, "__name__", "job")},
                )
                if failures >= 2:
                    raise ApiError("WORKER_FAILED") from None
