"""One module per page in the web bundle (web/src): every page the server renders (server/routes/pages.py,
`_page("name", …)`) is mounted by one module page-*.js, and web/src/pages.js only routes — its table names, for each
page, the mount functions of that page's module, and it defines nothing else but `boot`. The page modules are
leaves: no module imports one, but the router, the bundle's entry (index.js, which offers some mount functions as
window.PalTrainer) and the exercise page, which hands over to the exam's page at the same address
(page-exam.js). Shared parts live in modules of their own (exam.js, layout.js, results.js …)."""

from __future__ import annotations

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SRC = ROOT / "web" / "src"
IMPORT = re.compile(r"""^import\s+(?:\{([^}]*)\}\s+from\s+)?["']\./([\w.-]+)["']""", re.MULTILINE)
# who may import a page module besides the router: the bundle's entry, and the exercise page its exam mode
IMPORTERS = {"pages.js", "index.js"}
HANDOVERS = {("page-exercise.js", "page-exam.js")}
NOT_MOUNTED = {"not_found"}  # a static page: no script mounts anything on it


def imports(text: str) -> dict[str, str]:
    """name → module of a module's named imports from ./…"""
    found: dict[str, str] = {}
    for names, module in IMPORT.findall(text):
        for name in (n.strip() for n in names.split(",")):
            if name:
                found[name.split(" as ")[-1].strip()] = module
    return found


def routes() -> dict[str, set[str]]:
    """page name → the modules whose functions its entry in pages.js calls."""
    text = (SRC / "pages.js").read_text(encoding="utf-8")
    table = text[text.index("const PAGES = {") : text.index("\n};", text.index("const PAGES = {"))]
    imported = imports(text)
    entries = re.split(r'^  "?([\w-]+)"?: ', table, flags=re.MULTILINE)[1:]
    return {
        name: {imported[f] for f in re.findall(r"\b(\w+)\(", body) if f in imported}
        for name, body in zip(entries[::2], entries[1::2], strict=True)
    }


def server_pages() -> set[str]:
    text = (ROOT / "server" / "routes" / "pages.py").read_text(encoding="utf-8")
    return set(re.findall(r'_page\(\s*"([\w-]+)"', text)) - NOT_MOUNTED


def test_every_page_has_one_module_of_its_own() -> None:
    table = routes()
    assert server_pages() <= set(table), f"pages without a route: {server_pages() - set(table)}"
    for page, modules in table.items():
        assert len(modules) == 1 and next(iter(modules)).startswith("page-"), (page, modules)
    owners = [next(iter(m)) for m in table.values()]
    assert len(owners) == len(set(owners)), f"a module mounts two pages: {owners}"
    page_modules = {p.name for p in SRC.glob("page-*.js")}
    assert page_modules - set(owners) == {b for _, b in HANDOVERS}, "a page module no route mounts"


def test_pages_js_only_routes() -> None:
    text = (SRC / "pages.js").read_text(encoding="utf-8")
    assert re.findall(r"^(?:export\s+)?(?:async\s+)?function\s+(\w+)", text, re.MULTILINE) == ["boot"]
    top = re.findall(r"^(?:export\s+)?(?:const|let|var|class)\s+(\w+)", text, re.MULTILINE)
    assert set(top) <= {"PAGES", "byId", "segment"}, top
    assert not re.search(r"\b(?:el|api|fetch|table)\(", text), "pages.js builds or asks for nothing itself"
    assert set(imports(text).values()) - {p.name for p in SRC.glob("page-*.js")} == {"header.js", "state.js"}


def test_page_modules_are_leaves() -> None:
    wrong = [
        (path.name, module)
        for path in sorted(SRC.glob("*.js"))
        for module in set(imports(path.read_text(encoding="utf-8")).values())
        | set(
            re.findall(r"""^import\s+["']\./([\w.-]+)["']""", path.read_text(encoding="utf-8"), re.MULTILINE)
        )
        if module.startswith("page-") and path.name not in IMPORTERS and (path.name, module) not in HANDOVERS
    ]
    assert wrong == [], (
        f"page modules imported by others (move the shared part into a module of its own): {wrong}"
    )


def test_the_walk_reads_the_route_table() -> None:
    table = routes()
    assert table["practice"] == {"page-practice.js"}
    assert table["exercises"] == {"page-home.js"}  # the home section and the exercise list
    assert "exercise" in server_pages() and "not_found" not in server_pages()
