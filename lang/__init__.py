"""The IRL front end: parse, check and compile IRL programs to IRDATA code.

``compile_file(path, resolve_robot=...)`` returns a :class:`CompileResult` with ``code``
(``None`` on errors) and ``diagnostics``; ``write_code(result.code)`` gives the text.
"""

from irlc.lang.compiler import CompileResult, compile_file, compile_source
from irlc.lang.diagnostics import CompileError, Diagnostic, Span, render
from irlc.lang.irdata import Code, read_code, write_code
from irlc.lang.signature import RobotSignature, SimpleRobot

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
