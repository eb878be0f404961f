"""The IRL front end: parse, check and compile IRL programs to IRDATA code.

``compile_file(path, resolve_robot=...)`` returns a :class:`CompileResult` with ``code``
(``None`` on errors) and ``diagnostics``; ``write_code(result.code)`` gives the text.

The names below are loaded on first use (PEP 562), so importing a small module of this
package (``irlc.lang.joint_kinds``, ``irlc.lang.value_ranges``) does not load the parser.
"""

from __future__ import annotations

if __name__ != "irlc.lang":  # this folder imported by its own name (from the repository root)
    raise ImportError(f"import irlc.lang, not {__name__}: this folder is irlc.lang")

from typing import TYPE_CHECKING

from irlc.lang.lazy import lazy_names

if TYPE_CHECKING:
    from irlc.lang.compiler import CompileResult, compile_file, compile_source
    from irlc.lang.diagnostics import CompileError, Diagnostic, Span, render
    from irlc.lang.irdata import Code, read_code, write_code
    from irlc.lang.signature import RobotSignature, SimpleRobot

_HOMES = {
    "irlc.lang.compiler": ("CompileResult", "compile_file", "compile_source"),
    "irlc.lang.diagnostics": ("CompileError", "Diagnostic", "Span", "render"),
    "irlc.lang.irdata": ("Code", "read_code", "write_code"),
    "irlc.lang.signature": ("RobotSignature", "SimpleRobot"),
}
_HOME_OF = {name: module for module, names in _HOMES.items() for name in names}

__all__ = [
    "Code",
    "CompileError",
    "CompileResult",
    "Diagnostic",
    "RobotSignature",
    "SimpleRobot",
    "Span",
    "compile_file",
    "compile_source",
    "read_code",
    "render",
    "write_code",
]


__getattr__, __dir__ = lazy_names("irlc.lang", _HOME_OF, globals())
