"""The language front end stands alone: lang/ imports only itself, lark and the standard
library (issue 10: the runtime reads the language's tables, never the other way round)."""

from __future__ import annotations

import ast
from pathlib import Path

LANG = Path(__file__).resolve().parents[2] / "lang"


def _imported_modules(path: Path) -> list[tuple[int, str]]:
    tree = ast.parse(path.read_text(encoding="utf-8"))
    out = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            out += [(node.lineno, alias.name) for alias in node.names]
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            out.append((node.lineno, node.module))
    return out


def test_lang_imports_nothing_of_irlc_outside_lang() -> None:
    files = sorted(LANG.rglob("*.py"))
    assert len(files) > 10
    outside = [
        f"{path.relative_to(LANG.parent)}:{line}: {module}"
        for path in files
        for line, module in _imported_modules(path)
        if module.split(".")[0] == "irlc" and not module.startswith("irlc.lang")
    ]
    assert outside == []


def test_the_runtime_reads_the_motion_kind_words_from_lang() -> None:
    from irlc.lang.settings import ALL_KINDS, KIND_WORDS
    from irlc.runtime.outputs import cycle_time

    assert cycle_time.KIND_WORDS is KIND_WORDS
    assert tuple(KIND_WORDS) == ALL_KINDS
