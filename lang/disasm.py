"""Pretty-print IRDATA code with the program's source lines interleaved.

The listing is the code's own text (``write_code``: record numbers, operands, comments)
with each run of instructions from one source line preceded by that line, so jump targets
``@n`` can be followed in the same numbering as the ``.ird`` file.
"""

from __future__ import annotations

from pathlib import Path

from irlc.lang.file_access import program_source_lines
from irlc.lang.irdata import Code, write_code


def find_source(code: Code, ird_path: str | Path | None = None) -> list[str] | None:
    """The source lines (:func:`~irlc.lang.file_access.program_source_lines`): the ``.irl``
    file the SOURCE record names, next to the ``.ird`` first."""
    base = None if ird_path is None else Path(ird_path).parent
    return program_source_lines(code.source, base)


def disassemble(code: Code, source_lines: list[str] | None = None) -> str:
    text = write_code(code).splitlines()
    header_len = len(text) - len(code.code)
    out = text[:header_len]
    if source_lines is None:
        out.append("; (source file not found: no source lines interleaved)")
    routine_at = {r.entry: r for r in code.routines}
    last_line = None
    for i, ins in enumerate(code.code):
        if i in routine_at:
            r = routine_at[i]
            out.append(f"; ---- routine {r.index} {r.name} ({r.kind})")
            last_line = None
        if (
            ins.line != last_line
            and source_lines is not None
            and 1 <= ins.line <= len(source_lines)
        ):
            out.append(f";{ins.line:5d} | {source_lines[ins.line - 1].rstrip()}")
        last_line = ins.line
        out.append("    " + text[header_len + i])
    return "\n".join(out) + "\n"
