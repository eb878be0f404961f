"""Structure rules of the source tree (docs/architecture.md): no import cycle between
modules, no private (underscore) name imported from another module, no class — with the
project's own base classes it is built from — over MAX_CLASS_LINES lines.

The ``KNOWN_…`` sets list what is left of each rule's offenders; they only shrink (a new
offender fails, a fixed one must be removed from its set)."""

from __future__ import annotations

import ast
from collections import defaultdict
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = {
    "frontdoor": "irlc",
    "lang": "irlc.lang",
    "runtime": "irlc.runtime",
    "robots": "irlc.robots",
}
MAX_CLASS_LINES = 600

KNOWN_CYCLES: set[frozenset[str]] = set()
KNOWN_PRIVATE_IMPORTS: set[str] = set()
KNOWN_LARGE_CLASSES: set[str] = set()


def _modules() -> dict[str, Path]:
    """Every module of the package: dotted name → file (the folders, not the links)."""
    out = {}
    for folder, package in PACKAGES.items():
        base = ROOT / folder
        for path in sorted(base.rglob("*.py")):
            parts = list(path.relative_to(base).with_suffix("").parts)
            if parts[-1] == "__init__":
                parts.pop()
            out[".".join([package, *parts])] = path
    return out


MODULES = _modules()
TREES = {name: ast.parse(path.read_text(encoding="utf-8")) for name, path in MODULES.items()}


def _imported(module: str, tree: ast.Module) -> set[str]:
    """The project's modules ``module`` imports anywhere (also inside functions)."""
    out = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            if node.module in MODULES:
                out.add(node.module)
            out |= {f"{node.module}.{a.name}" for a in node.names} & MODULES.keys()
        elif isinstance(node, ast.Import):
            out |= {a.name for a in node.names} & MODULES.keys()
    # a package's own children and a child's own package are not cycles of note
    return {m for m in out if not (m.startswith(module + ".") or module.startswith(m + "."))}


def _strongly_connected(graph: dict[str, set[str]]) -> list[set[str]]:
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    found: list[set[str]] = []

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in graph[v]:
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = set()
            while True:
                w = stack.pop()
                on_stack.discard(w)
                component.add(w)
                if w == v:
                    break
            found.append(component)

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return found


def test_strongly_connected_components_find_a_cycle():
    graph = {"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}
    assert sorted(map(sorted, _strongly_connected(graph))) == [["a", "b", "c"], ["d"]]


def test_no_import_cycles():
    graph = defaultdict(set, {m: _imported(m, t) for m, t in TREES.items()})
    cycles = {frozenset(c) for c in _strongly_connected(graph) if len(c) > 1}
    assert cycles - KNOWN_CYCLES == set(), "new import cycles"
    assert KNOWN_CYCLES - cycles == set(), "fixed: remove them from KNOWN_CYCLES"


def _private_imports(path: Path) -> list[str]:
    out = []
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.ImportFrom) and (
            node.level > 0 or (node.module or "").split(".")[0] == "irlc"
        ):
            out += [
                a.name for a in node.names if a.name.startswith("_") and not a.name.startswith("__")
            ]
    return out


def test_no_private_name_is_imported_from_another_module():
    files = [p for m, p in MODULES.items()]
    files += sorted((ROOT / "tests").rglob("*.py")) + sorted((ROOT / "bench").rglob("*.py"))
    offenders = {str(p.relative_to(ROOT)) for p in files if _private_imports(p)}
    assert offenders - KNOWN_PRIVATE_IMPORTS == set(), "new imports of private names"
    assert KNOWN_PRIVATE_IMPORTS - offenders == set(), "fixed: remove from KNOWN_PRIVATE_IMPORTS"


def _class_lines() -> dict[str, int]:
    """Lines of each class with the project's own base classes it is built from (a mixin's
    methods are the class's)."""
    classes: dict[str, tuple[int, list[str], str]] = {}
    for module, tree in TREES.items():
        imported = {}
        for node in ast.walk(tree):
            if isinstance(node, ast.ImportFrom) and node.module in MODULES:
                imported |= {a.asname or a.name: f"{node.module}.{a.name}" for a in node.names}
        for node in tree.body:
            if isinstance(node, ast.ClassDef):
                bases = [ast.unparse(b) for b in node.bases]
                name = f"{module}.{node.name}"
                own = [imported.get(b, f"{module}.{b}") for b in bases]
                classes[name] = (node.end_lineno - node.lineno + 1, own, module)

    def total(name: str, seen: frozenset = frozenset()) -> int:
        lines, bases, _ = classes[name]
        return lines + sum(total(b, seen | {name}) for b in bases if b in classes and b not in seen)

    return {name: total(name) for name in classes}


def test_no_class_is_over_the_size_limit():
    sizes = _class_lines()
    large = {name for name, lines in sizes.items() if lines > MAX_CLASS_LINES}
    assert large - KNOWN_LARGE_CLASSES == set(), {n: sizes[n] for n in large - KNOWN_LARGE_CLASSES}
    assert KNOWN_LARGE_CLASSES - large == set(), "fixed: remove from KNOWN_LARGE_CLASSES"
