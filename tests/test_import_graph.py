"""No import cycles: core and server (every import, also those inside functions; the `if TYPE_CHECKING:` ones
are annotations only) and the web bundle's modules (web/src). A cycle is a module that cannot be read without
the one that reads it — the shape the one pipeline of pure stages rules out."""

from __future__ import annotations

import ast
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
JS_IMPORT = re.compile(
    r"""^\s*(?:import|export)\s[^;]*?from\s+["'](\.{1,2}/[^"']+)["']|^\s*import\s+["'](\.{1,2}/[^"']+)["']""",
    re.MULTILINE,
)


def python_graph() -> dict[str, set[str]]:
    modules: dict[str, Path] = {}
    for top in ("core", "server"):
        for path in (ROOT / top).rglob("*.py"):
            if "migrations" in path.parts:
                continue
            name = ".".join(path.relative_to(ROOT).with_suffix("").parts)
            modules[name.removesuffix(".__init__")] = path
    graph: dict[str, set[str]] = {}
    for name, path in modules.items():
        tree = ast.parse(path.read_text(encoding="utf-8"))
        typing_only = {
            id(n)
            for node in ast.walk(tree)
            if isinstance(node, ast.If) and "TYPE_CHECKING" in ast.unparse(node.test)
            for part in node.body
            for n in ast.walk(part)
        }
        found: set[str] = set()
        for node in ast.walk(tree):
            if id(node) in typing_only:
                continue
            if isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
                found |= {
                    m for m in [node.module, *(f"{node.module}.{a.name}" for a in node.names)] if m in modules
                }
            elif isinstance(node, ast.Import):
                found |= {a.name for a in node.names if a.name in modules}
        graph[name] = found - {name}
    return graph


def js_graph() -> dict[str, set[str]]:
    src = ROOT / "web" / "src"
    graph: dict[str, set[str]] = {}
    for path in src.glob("*.js"):
        text = path.read_text(encoding="utf-8")
        targets = {(path.parent / (a or b)).resolve() for a, b in JS_IMPORT.findall(text)}
        graph[path.name] = {t.name for t in targets if t.parent == src.resolve()}
    return graph


def cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The strongly connected components with more than one module (Tarjan)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on: set[str] = set()
    found: list[list[str]] = []

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in sorted(graph.get(v, ())):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                found.append(sorted(component))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return found


def test_no_import_cycle_in_core_and_server() -> None:
    graph = python_graph()
    assert "core.interpreter.traub_cycles" in graph and "server.lti.cli" in graph
    assert cycles(graph) == []


def test_no_import_cycle_in_the_web_modules() -> None:
    graph = js_graph()
    assert "main.js" in graph["index.js"]
    assert cycles(graph) == []


def test_the_walk_finds_a_cycle() -> None:
    assert cycles({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}) == [["a", "b", "c"]]


def test_the_traub_cycles_see_the_run_only_through_their_own_narrow_view() -> None:
    # core/interpreter/traub_cycles.py: CycleRun, Technology, BlockResult — not TurnRun, not even for annotations
    tree = ast.parse((ROOT / "core" / "interpreter" / "traub_cycles.py").read_text(encoding="utf-8"))
    imported = {
        node.module for node in ast.walk(tree) if isinstance(node, ast.ImportFrom) and node.module is not None
    }
    assert "core.interpreter.traub_turn" not in imported
    private = re.findall(r"\brun\._[a-z]\w*", ast.unparse(tree))
    assert private == []


def test_a_worker_process_imports_no_web_framework_and_no_database() -> None:
    """A worker process (forked from the fork server, which imports its modules) reads server/jobs.py and the
    core: FastAPI, SQLAlchemy and the models would double the time the fork server takes to start, with every
    server."""
    import subprocess
    import sys

    heavy = (
        "fastapi",
        "starlette",
        "sqlalchemy",
        "alembic",
        "server.models",
        "server.errors",
        "server.workers",
    )
    probe = f"import sys, server.jobs; print(' '.join(m for m in {heavy!r} if m in sys.modules))"
    out = subprocess.run([sys.executable, "-c", probe], cwd=ROOT, capture_output=True, text=True, check=True)
    assert out.stdout.split() == []
