"""Fails when an ``irlc…`` import does not resolve for pyright (VS Code's engine).

Runs ``pyright --outputjson`` over the source folders with the project's pyright
settings (pyproject.toml, ``[tool.pyright]``) and reports every unresolved ``irlc``
module (``reportMissingImports``) and every name imported from an ``irlc`` module that
pyright cannot find there (``… is unknown import symbol``). Other unresolved imports —
optional peers such as pinocchio or pyarrow — are not this check's business.

Usage (in the contributor install, ``pip install -e '.[test]'``): ``python .ci/check_imports.py``
"""

from __future__ import annotations

import json
import re
import shutil
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
CONFIG = ROOT / ".ci" / "pyright-imports.json"


def _import_statement(path: Path, line: int) -> str:
    """The import statement that holds ``line`` (1-based): from its ``from``/``import``
    line down to ``line``."""
    lines = path.read_text(encoding="utf-8").splitlines()
    start = line - 1
    while start > 0 and not re.match(r"\s*(from|import)\s", lines[start]):
        start -= 1
    return " ".join(lines[start:line])


def unresolved(diagnostics: list[dict]) -> list[str]:
    out = []
    for d in diagnostics:
        path, line = Path(d["file"]), d["range"]["start"]["line"] + 1
        message = d["message"].splitlines()[0]
        rule = d.get("rule")
        if rule == "reportMissingImports" and re.search(r'Import "irlc(\.|")', message):
            out.append(f"{path.relative_to(ROOT)}:{line}: {message}")
        elif rule == "reportAttributeAccessIssue" and "unknown import symbol" in message:
            statement = _import_statement(path, line)
            if re.match(r"\s*from\s+irlc(\.|\s)", statement):
                out.append(f"{path.relative_to(ROOT)}:{line}: {message}")
    return out


def main() -> int:
    pyright = shutil.which("pyright")
    if pyright is None:
        print("check_imports: pyright is not installed (pip install pyright)", file=sys.stderr)
        return 2
    proc = subprocess.run(
        [pyright, "--outputjson", "--project", str(CONFIG)],
        cwd=ROOT,
        capture_output=True,
        text=True,
    )
    try:
        report = json.loads(proc.stdout)
    except json.JSONDecodeError:
        print(proc.stdout[-2000:], proc.stderr[-2000:], sep="\n", file=sys.stderr)
        return 2
    problems = unresolved(report["generalDiagnostics"])
    files = report["summary"]["filesAnalyzed"]
    for p in problems:
        print(p)
    print(f"check_imports: {files} files, {len(problems)} unresolved irlc imports")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
