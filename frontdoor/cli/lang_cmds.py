"""``irlc check``, ``irlc compile`` and ``irlc disasm`` (the language front end's commands).

Diagnostics go to stderr as ``FILE:LINE:COL: severity: message`` + source line + caret +
hint. Exit codes: 0 ok, 1 compile errors, 3 usage errors (missing file, unknown --robot).
"""

from __future__ import annotations

from pathlib import Path

import click
from irlc.cli.app import cli, distinct_outputs, require_file
from irlc.errors import EXIT_COMPILE, EXIT_OK, UsageError


def library_resolver(name_or_path: str):
    """Resolve a robot by :func:`irlc.robots.resolve_robot` (its errors are LookupErrors)."""
    from irlc.robots import resolve_robot

    return resolve_robot(name_or_path)


def _compile(
    program: Path, robot: str | None, datalist_path: tuple[Path, ...], allow_any_path: bool
):
    from irlc.lang import compile_file
    from irlc.robots import RobotFileError, resolve_robot, resolver

    require_file(program)
    for d in datalist_path:
        if not d.is_dir():
            raise UsageError(f"--datalist-path {d}: no such folder")
    resolve = resolver(program.parent, allow_any_path=allow_any_path)
    if robot is not None:
        try:
            model = resolve_robot(robot, program.parent)
        except RobotFileError as e:
            raise UsageError(str(e)) from None
        resolve = lambda name: model  # noqa: E731 - the --robot model for any name

    return compile_file(
        str(program),
        resolve_robot=resolve,
        datalist_path=tuple(str(d) for d in datalist_path),
        robot_override=robot,
        allow_any_path=allow_any_path,
    )


def print_diagnostics(result) -> None:
    from irlc.lang import render

    for d in result.diagnostics:
        src = result.source if d.file == result.filename else None
        click.echo(render(d, src), err=True)


def _reported(program: Path, result) -> bool:
    """Print ``result``'s diagnostics; on failure also the count line on stderr. Whether
    the program compiled."""
    print_diagnostics(result)
    if not result.ok:
        click.echo(f"{program}: {_summary(result)}", err=True)
    return result.ok


def _summary(result) -> str:
    n_err, n_warn = len(result.errors), len(result.warnings)
    return f"{n_err} error{'s' if n_err != 1 else ''}, {n_warn} warning{'s' if n_warn != 1 else ''}"


_robot_option = click.option("--robot", default=None, help="Robot name or file (overrides ROBOT).")
_datalist_option = click.option(
    "--datalist-path",
    "datalist_path",
    multiple=True,
    type=click.Path(path_type=Path),
    help="Folder searched for IMPORT DATALIST files (repeatable).",
)
allow_any_path_option = click.option(
    "--allow-any-path",
    "allow_any_path",
    is_flag=True,
    help="Let the program's ROBOT file and data lists lie anywhere (default: only in its "
    "folder, the --datalist-path folders and the robot library).",
)


@cli.command("check")
@click.argument("program", type=click.Path(path_type=Path))
@_robot_option
@_datalist_option
@allow_any_path_option
def check_cmd(
    program: Path, robot: str | None, datalist_path: tuple[Path, ...], allow_any_path: bool
) -> int:
    """Compile PROGRAM.irl without writing code; print diagnostics."""
    result = _compile(program, robot, datalist_path, allow_any_path)
    if not _reported(program, result):
        return EXIT_COMPILE
    click.echo(f"{program}: ok ({_summary(result)})")
    return EXIT_OK


@cli.command("compile")
@click.argument("program", type=click.Path(path_type=Path))
@click.option(
    "-o",
    "--output",
    type=click.Path(path_type=Path, dir_okay=False),
    default=None,
    help="Output file (default: PROGRAM.ird next to the source).",
)
@_robot_option
@_datalist_option
@allow_any_path_option
def compile_cmd(
    program: Path,
    output: Path | None,
    robot: str | None,
    datalist_path: tuple[Path, ...],
    allow_any_path: bool,
) -> int:
    """Compile PROGRAM.irl to IRDATA code (PROGRAM.ird)."""
    from irlc.files import atomic_write_text
    from irlc.lang import write_code

    out = output if output is not None else program.with_suffix(".ird")
    distinct_outputs({"the program": program}, {"-o": out})
    result = _compile(program, robot, datalist_path, allow_any_path)
    if not _reported(program, result):
        return EXIT_COMPILE
    try:
        atomic_write_text(out, write_code(result.code))
    except OSError as e:
        raise UsageError(f"cannot write {out}: {e.strerror or e}") from None
    click.echo(f"wrote {out}")
    return EXIT_OK


@cli.command("disasm")
@click.argument("code_file", metavar="PROGRAM.ird", type=click.Path(path_type=Path))
def disasm_cmd(code_file: Path) -> int:
    """Pretty-print IRDATA code with the source lines interleaved."""
    from irlc.lang import CompileError, read_code, render
    from irlc.lang.disasm import disassemble, find_source
    from irlc.lang.textfile import read_user_text

    require_file(code_file)
    text = read_user_text(code_file, lambda file, reason: UsageError(f"{file}: {reason}"))
    try:
        code = read_code(text, str(code_file))
    except CompileError as e:
        for d in e.diagnostics:  # positioned, without the code's line (as `irlc run` does)
            click.echo(render(d), err=True)
        return EXIT_COMPILE
    click.echo(disassemble(code, find_source(code, code_file)), nl=False)
    return EXIT_OK
