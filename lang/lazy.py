"""Public names of a package loaded on first use (PEP 562): ``irlc`` and ``irlc.lang``.

``__getattr__, __dir__ = lazy_names("irlc.lang", HOME_OF, globals())`` makes ``name`` of
``HOME_OF`` (name → home module) resolve by importing its home on first access (then it is
an ordinary global), an unknown name an ``AttributeError``, and ``dir()`` list the public
names (and the module's dunders), not the package's helpers — so importing the package
stays light and a small module of it does not load the parser.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable
from typing import Any


def lazy_names(
    package: str, home_of: dict[str, str], namespace: dict[str, Any]
) -> tuple[Callable[[str], Any], Callable[[], list[str]]]:
    """``(__getattr__, __dir__)`` for ``package`` (module doc)."""

    def getattr_(name: str) -> Any:
        if name not in home_of:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        value = getattr(importlib.import_module(home_of[name]), name)
        namespace[name] = value
        return value

    def dir_() -> list[str]:
        return sorted({*home_of, *(name for name in namespace if name.startswith("__"))})

    return getattr_, dir_
