"""The package-dir mapping lists packages explicitly; every package folder must be listed."""

from __future__ import annotations

import ast
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
MAPPING = {
    "irlc": "frontdoor",
    "irlc.lang": "lang",
    "irlc.runtime": "runtime",
    "irlc.robots": "robots",
}


def _package_folders() -> set[str]:
    found = set()
    for pkg, folder in MAPPING.items():
        base = ROOT / folder
        for init in base.rglob("__init__.py"):
            rel = init.parent.relative_to(base)
            found.add(".".join([pkg, *rel.parts]) if rel.parts else pkg)
    return found


def test_every_package_folder_is_listed_in_pyproject():
    config = tomllib.loads((ROOT / "pyproject.toml").read_text())
    listed = set(config["tool"]["setuptools"]["packages"])
    assert _package_folders() == listed


def test_package_dir_mapping_matches_layout():
    config = tomllib.loads((ROOT / "pyproject.toml").read_text())
    assert config["tool"]["setuptools"]["package-dir"] == MAPPING


def test_lang_never_imports_runtime():
    offenders = [
        p.name
        for p in (ROOT / "lang").rglob("*.py")
        if "irlc.runtime" in p.read_text(encoding="utf-8")
    ]
    assert offenders == []


LOWER_LAYERS = ("lang", "runtime", "robots")


def _front_door_imports(path: Path) -> list[str]:
    """The ``irlc.…`` modules ``path`` imports that are not in a lower layer (every
    import, also those inside functions)."""
    out = []
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            names = (
                [node.module] if node.module != "irlc" else [f"irlc.{a.name}" for a in node.names]
            )
        elif isinstance(node, ast.Import):
            names = [a.name for a in node.names]
        else:
            continue
        for name in names:
            parts = name.split(".")
            if parts[0] == "irlc" and (len(parts) < 2 or parts[1] not in LOWER_LAYERS):
                out.append(name)
    return out


def test_lower_layers_never_import_the_front_door():
    """lang/, runtime/ and robots/ sit below the front door (frontdoor/, ``irlc.*``): the
    robot loader and the runtime read user files through :mod:`irlc.lang.textfile`, not
    the front door's ``irlc.files``."""
    offenders = {
        f"{p.relative_to(ROOT)}: {name}"
        for layer in LOWER_LAYERS
        for p in (ROOT / layer).rglob("*.py")
        for name in _front_door_imports(p)
    }
    assert sorted(offenders) == []


def test_no_root_folder_shadows_the_installed_package():
    """Python puts the current folder first on ``sys.path``: a folder named like an
    installed package at the repository root would shadow it (``from irlc import …`` in
    the root after ``pip install .`` found the front door alone: no ``irlc.lang``)."""
    shadowing = [pkg for pkg in MAPPING if "." not in pkg and (ROOT / pkg).is_dir()]
    assert shadowing == []
