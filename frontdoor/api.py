"""The public Python API; the command line is a thin layer over the same functions.

from irlc import compile_program, run_program, load_robot

robot = load_robot("koch11")                    # RobotModel (SI)
code = compile_program("programs/square.irl")   # IRDATA Code; CompileError on errors
run = run_program("programs/square.irl")        # RunResult: status, report, trace, q
run.robots["r"].q                               # each robot's samples (a cell: several)
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from irlc.lang.diagnostics import CompileError
from irlc.lang.irdata import Code
from irlc.robots import RobotModel, resolve_robot, resolver


def load_robot(name_or_path: str | Path) -> RobotModel:
    """A robot of the library by name (``"koch11"``) or a ``.toml`` / ``.urdf`` file."""
    return resolve_robot(name_or_path)


def compile_program(
    path: str | Path,
    *,
    robot: str | None = None,
    datalist_path: Sequence[str | Path] = (),
    source: str | None = None,
    allow_any_path: bool = False,
) -> Code:
    """Compile an IRL program to IRDATA code.

    ``robot`` overrides the program's ``ROBOT`` clause (like ``--robot``); ``source``
    compiles that text under the name ``path`` instead of reading the file;
    ``allow_any_path`` lets the program's robot file and data lists lie outside its folder,
    the ``datalist_path`` folders and the robot library (like ``--allow-any-path``). Raises
    :class:`~irlc.lang.diagnostics.CompileError` carrying the diagnostics on errors.
    """
    from irlc.lang.compiler import compile_file, compile_source

    path = Path(path)
    options = {
        "resolve_robot": resolver(path.parent, allow_any_path=allow_any_path, user_robot=robot),
        "datalist_path": tuple(str(d) for d in datalist_path),
        "robot_override": robot,
        "allow_any_path": allow_any_path,
    }
    if source is None:
        result = compile_file(path, **options)
    else:
        result = compile_source(source, str(path), **options)
    if result.code is None:
        raise CompileError(result.diagnostics)
    return result.code


def run_program(program: str | Path | Code, **options):
    """Compile (``.irl``) or read (``.ird``) and simulate a program; or run given ``Code``.

    Options are those of :func:`irlc.runtime.run.run_code` / ``run_file`` (``robot``,
    ``ipo``, ``drives``, ``path_tolerance`` (mm), ``orientation_tolerance`` (deg),
    ``seed_config``, ``datalist_path``, ``instruction_budget`` — the endless-loop guard…,
    ``max_time`` (s) and ``max_cycles`` — the run's budgets, ``override`` (%, the start
    value of ``R_OVERRIDE``), ``allow_any_path`` (like ``--allow-any-path``)).
    Returns a ``RunResult``
    whose ``status`` is ``"ok"`` or ``"failed"`` (with ``error``); raises
    :class:`~irlc.lang.diagnostics.CompileError` if the program does not compile.
    """
    from irlc.runtime.run import run_code, run_file

    if isinstance(program, Code):
        return run_code(program, **options)
    return run_file(program, **options)
