"""The jobs of the worker processes (check, run, simulate, the live re-runs, the 3D view's scenes, pictures and
sheets): plain top-level functions of plain data, so that they cross the process boundary by pickle. The pool
that runs them is server/workers.py; a worker process imports this module and the core only, not the web
framework or the database (a worker starts in a third of the time)."""

from __future__ import annotations

import dataclasses
import gc
import importlib.util
import json
import logging
import operator
import time
from collections import Counter, OrderedDict, defaultdict
from collections.abc import Callable
from typing import Any, Literal

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

log = logging.getLogger("paltrainer.server")

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
