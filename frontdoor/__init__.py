"""irlc — compiler and simulator for IRL programs of redundant industrial robots.

Public API (imported lazily so that ``import irlc.lang`` stays light)::

    from irlc import compile_program, run_program, load_robot
"""

from __future__ import annotations

if __name__ != "irlc":  # this folder imported by its own name (from the repository root)
    raise ImportError(f"import irlc, not {__name__}: this folder is irlc")

__version__ = "0.1.0"

__all__ = ["compile_program", "load_robot", "run_program"]


def __getattr__(name: str):
    if name in __all__:
        from irlc import api

        return getattr(api, name)
    raise AttributeError(f"module 'irlc' has no attribute {name!r}")
