"""The package layout: one tree (src/irlc → frontdoor/, with lang/, runtime/, robots/
linked into it) that pip, editors and type checkers follow; the layering rules."""

from __future__ import annotations

import ast
import importlib
import os
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
MAPPING = {
    "irlc": "frontdoor",
    "irlc.lang": "lang",
    "irlc.runtime": "runtime",
    "irlc.robots": "robots",
}
LINKS = {
    "src/irlc": "../frontdoor",
    "frontdoor/lang": "../lang",
    "frontdoor/runtime": "../runtime",
    "frontdoor/robots": "../robots",
}


def test_the_package_tree_is_linked_into_src():
    """src/irlc is the package pip and the editable install see; its subpackages are the
    top-level folders, through links (not copies)."""
    for link, target in LINKS.items():
        path = ROOT / link
        assert path.is_symlink(), f"{link} should be a link to {target}"
        assert os.readlink(path) == target
        assert path.resolve() == (ROOT / link).parent.joinpath(target).resolve()


def test_every_package_folder_is_found_under_src():
    """setuptools finds packages under src/ (following the links): every folder with an
    __init__.py is a package of the wheel, with no list to keep by hand."""
    from setuptools import find_packages

    config = tomllib.loads((ROOT / "pyproject.toml").read_text())
    assert config["tool"]["setuptools"]["packages"]["find"]["where"] == ["src"]
    found = set(find_packages(str(ROOT / "src")))
    expected = set()
    for pkg, folder in MAPPING.items():
        for init in (ROOT / folder).rglob("__init__.py"):
            rel = init.parent.relative_to(ROOT / folder)
            expected.add(".".join([pkg, *rel.parts]) if rel.parts else pkg)
    assert found == expected


def test_the_installed_package_is_this_tree():
    """In the contributor install (``pip install -e``) ``irlc.runtime`` is this checkout's
    runtime/ folder (seen through src/irlc); ``import runtime`` from the root is refused
    instead of loading a second copy."""
    import irlc.runtime

    installed = Path(irlc.runtime.__file__).resolve()
    if installed.parent != (ROOT / "runtime").resolve():
        pytest.skip("irlc is installed from elsewhere (not an editable install of this tree)")
    for folder, name in (
        ("runtime", "irlc.runtime"),
        ("lang", "irlc.lang"),
        ("robots", "irlc.robots"),
        ("frontdoor", "irlc"),
    ):
        probe = subprocess.run(
            [sys.executable, "-c", f"import {folder}"],
            cwd=ROOT,
            capture_output=True,
            text=True,
        )
        assert probe.returncode != 0
        assert f"import {name}" in probe.stderr
    assert importlib.import_module("irlc.runtime") is irlc.runtime


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
    shadowing = [pkg for pkg in MAPPING if "." not in pkg and (ROOT / pkg).exists()]
    assert shadowing == []
