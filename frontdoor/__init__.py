"""irlc — compiler and simulator for IRL programs of redundant industrial robots.

Public API (loaded on first use, PEP 562, so that ``import irlc.lang`` stays light)::

    from irlc import compile_program, run_program, load_robot
    from irlc import CompileError, RunFailure, RunResult, IrlcError

``compile_program`` raises :class:`CompileError` (its ``diagnostics``); ``run_program``
returns a :class:`RunResult` whose ``error`` is a :class:`RunFailure` when the run failed;
a bad robot, option or file raises :class:`RunSetupError`, :class:`RobotFileError`
(:class:`UnknownRobotError`), :class:`DriveSetupError` — every one an :class:`IrlcError`.
"""

from __future__ import annotations

if __name__ != "irlc":  # this folder imported by its own name (from the repository root)
    raise ImportError(f"import irlc, not {__name__}: this folder is irlc")

from typing import TYPE_CHECKING

from irlc.lang.lazy import lazy_names

if TYPE_CHECKING:
    from irlc.api import compile_program, load_robot, run_program
    from irlc.lang.diagnostics import CompileError, Diagnostic
    from irlc.lang.errors import IrlcError
    from irlc.lang.irdata import Code
    from irlc.robots import UnknownRobotError
    from irlc.robots.model import RobotModel
    from irlc.robots.toml_reader import RobotFileError
    from irlc.runtime.errors import DriveSetupError, RunFailure
    from irlc.runtime.outputs.run_result import RunResult
    from irlc.runtime.run import RunSetupError

__version__ = "0.1.0"

_HOMES = {
    "irlc.api": ("compile_program", "load_robot", "run_program"),
    "irlc.lang.diagnostics": ("CompileError", "Diagnostic"),
    "irlc.lang.errors": ("IrlcError",),
    "irlc.lang.irdata": ("Code",),
    "irlc.robots": ("UnknownRobotError",),
    "irlc.robots.model": ("RobotModel",),
    "irlc.robots.toml_reader": ("RobotFileError",),
    "irlc.runtime.errors": ("DriveSetupError", "RunFailure"),
    "irlc.runtime.outputs.run_result": ("RunResult",),
    "irlc.runtime.run": ("RunSetupError",),
}
_HOME_OF = {name: module for module, names in _HOMES.items() for name in names}

__all__ = [
    "Code",
    "CompileError",
    "Diagnostic",
    "DriveSetupError",
    "IrlcError",
    "RobotFileError",
    "RobotModel",
    "RunFailure",
    "RunResult",
    "RunSetupError",
    "UnknownRobotError",
    "compile_program",
    "load_robot",
    "run_program",
]


__getattr__, __dir__ = lazy_names("irlc", _HOME_OF, globals())
