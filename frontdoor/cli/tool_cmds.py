"""Tool commands: ``irlc test DIR [--update]`` (golden tests), ``irlc repl``, ``irlc lsp``
(the language server for editors) and ``irlc warmup`` (compile the optional kernels ahead of
the first run)."""

from __future__ import annotations

from pathlib import Path

import click
from irlc.cli.app import cli
from irlc.cli.lang_cmds import allow_any_path_option
from irlc.errors import EXIT_OK, UsageError
from irlc.lang.file_access import path_kind

EXIT_TEST_FAILED = 1  # some golden test failed (like pytest); 3 for usage errors


@cli.command("test")
@click.argument("directory", required=False, default=".", type=click.Path(path_type=Path))
@click.option("--update", is_flag=True, help="Rewrite NAME.expected.json / .txt from this run.")
@click.option(
    "-j", "--jobs", type=click.IntRange(min=1), default=1, show_default=True,
    help="Programs run at once on local processes (results in the same order).",
)  # fmt: skip
@allow_any_path_option
def test_cmd(directory: Path, update: bool, jobs: int, allow_any_path: bool) -> int:
    """Run every NAME.irl in DIRECTORY against NAME.expected.json (+ .expected.txt).

    Exit status: 0 all passed (or updated), 1 some failed or have no expectation,
    3 the directory does not exist or holds no programs.
    """
    from irlc.cli.console import Console
    from irlc.golden import find_programs, render_results, run_golden

    kind = path_kind(directory)
    if kind != "folder":
        raise UsageError(f"{directory}: {'no such' if kind == 'missing' else 'not a'} directory")
    if not find_programs(directory):
        raise UsageError(f"{directory}: no *.irl programs")
    results = run_golden(directory, update=update, jobs=jobs, allow_any_path=allow_any_path)
    render_results(results, Console(highlight=False))
    return EXIT_OK if all(r.ok for r in results) else EXIT_TEST_FAILED


@cli.command("repl")
@click.option(
    "--robot", "robot", multiple=True,
    help="Robot name or description file; NAME=ROBOT[@x,y,z,a,b,c] names the robot and places "
    "it (mm, deg ZYX), repeated: a cell of several robots.",
)  # fmt: skip
@click.option(
    "--datalist-path", "datalist_path", multiple=True,
    type=click.Path(path_type=Path, file_okay=False, exists=True),
    help="Folder searched for IMPORT DATALIST files (repeatable).",
)  # fmt: skip
@click.option("--plain", is_flag=True, help="Plain line input even on a terminal.")
@allow_any_path_option
def repl_cmd(
    robot: tuple[str, ...], datalist_path: tuple[Path, ...], plain: bool, allow_any_path: bool
) -> int:
    """Interactive session: declarations and statements run as they are entered."""
    from irlc.repl import main as repl_main

    return repl_main(
        robot=robot, datalist_path=datalist_path, plain=plain, allow_any_path=allow_any_path
    )


@cli.command("lsp")
@click.option(
    "--datalist-path", "datalist_path", multiple=True,
    type=click.Path(path_type=Path, file_okay=False, exists=True),
    help="Folder searched for IMPORT DATALIST files (repeatable).",
)  # fmt: skip
@allow_any_path_option
def lsp_cmd(datalist_path: tuple[Path, ...], allow_any_path: bool) -> int:
    """Language server for editors: speaks LSP on stdin/stdout (diagnostics, completion,
    hover, go to definition, document symbols). Needs the extra: pip install 'irlc[lsp]'."""
    from irlc.lsp import EXTRA_HINT, missing_dependency

    missing = missing_dependency()
    if missing is not None:
        raise UsageError(f"lsp: the language server needs the extra lsp ({missing}): {EXTRA_HINT}")
    from irlc.lsp.analysis import Settings
    from irlc.lsp.server import serve

    serve(Settings(tuple(str(d) for d in datalist_path), allow_any_path))
    return EXIT_OK


@cli.command("warmup")
def warmup_cmd() -> int:
    """Compile the optional kernels of IRLC_ENGINE=compiled|auto now (numba; once per
    installation, ≈ 35–45 s), so that no later run compiles.

    Exit status: 0 compiled or already cached, 3 numba missing or IRLC_ENGINE=numpy.
    """
    from irlc.runtime import accel_support

    if not accel_support.kernels_allowed():
        why = "numba is not installed (pip install 'irlc[fast]')"
        if accel_support.NUMBA_INSTALLED:
            why = f"{accel_support.ENV}=numpy disables the kernels"
        raise UsageError(f"warmup: {why}")
    from irlc.runtime.warmup import warm_all

    accel_support.WARMING_UP = True
    warm_all(click.echo)
    return EXIT_OK
