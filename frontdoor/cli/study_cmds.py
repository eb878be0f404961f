"""``irlc study STUDY.toml``: one program over many variants (docs/studies.md)."""

from __future__ import annotations

from pathlib import Path

import click
from irlc.cli.app import cli, require_file
from irlc.cli.lang_cmds import allow_any_path_option
from irlc.errors import EXIT_COMPILE, EXIT_INTERRUPTED, EXIT_OK, UsageError
from irlc.study.summary import DEFAULT_SORT


@cli.command("study")
@click.argument("study_file", type=click.Path(path_type=Path))
@click.option("--workers", "-j", type=click.IntRange(min=1), default=None,
              help="Local worker processes (default: all cores).")  # fmt: skip
@click.option("--cluster", default=None, metavar="ADDRESS",
              help="A Dask scheduler, e.g. tcp://HOST:8786 (extra irlc[cluster]).")  # fmt: skip
@click.option("--out", type=click.Path(path_type=Path), default=None,
              help="Results folder (default: STUDY.results next to the study file).")  # fmt: skip
@click.option("--resume", is_flag=True, help="Run only the variants not yet in DIR/results.csv.")
@click.option("--sort", "sort", default=DEFAULT_SORT, show_default=True,
              help="Best/worst by this metric (smallest first; -METRIC: largest).")  # fmt: skip
@click.option("--plot", "plot", type=click.Path(dir_okay=False, path_type=Path), default=None,
              help="Draw the --sort metric against the varied keys into FILE.png.")  # fmt: skip
@click.option("-q", "--quiet", is_flag=True, help="No progress bar, no summary.")
@allow_any_path_option
def study_cmd(study_file, workers, cluster, out, resume, sort, plot, quiet, allow_any_path) -> int:
    """Run STUDY_FILE's program once per variant; results in DIR/results.csv.

    Exit status: 0 the study ran (a failing variant is a row with its error), 1 the
    program does not compile, 3 a bad study file, value, robot or option, 130 interrupted
    (rows written so far are kept: complete them with --resume).
    """
    from irlc.cli.console import Console
    from irlc.lang.diagnostics import CompileError
    from irlc.robots import RobotFileError
    from irlc.runtime.run import RunSetupError
    from irlc.study import run_study
    from irlc.study.figure import plot as draw
    from irlc.study.runner import ClusterError
    from irlc.study.summary import check_metric, split_sort, summary_table

    require_file(study_file)
    from irlc.summary import MAX_WIDTH

    console = Console(highlight=False)
    if not console.is_terminal:  # a file or pipe: the width irlc run's summary uses there
        console = Console(highlight=False, width=MAX_WIDTH)
    err = Console(stderr=True, highlight=False, soft_wrap=True)
    bar = _Bar(err, quiet)
    try:
        outcome = run_study(
            study_file, out=out, workers=workers, cluster=cluster, resume=resume,
            progress=bar.advance, started=bar.start,
            check=lambda columns, keys: check_metric(sort, columns, keys),
            allow_any_path=allow_any_path,
        )  # fmt: skip
    except CompileError as exc:
        from irlc.lang.diagnostics import render

        for d in exc.diagnostics:
            err.print(render(d), markup=False)
        return EXIT_COMPILE
    except (RunSetupError, RobotFileError, ClusterError) as exc:
        raise UsageError(str(exc)) from None
    except KeyboardInterrupt:
        bar.stop()
        err.print(
            "interrupted: the variants that finished are in results.csv; "
            "run again with --resume to complete the study",
            markup=False,
        )
        return EXIT_INTERRUPTED
    finally:
        bar.stop()
    keys = outcome.study.keys
    if not quiet:
        console.print(summary_table(outcome.rows, keys, sort, name=outcome.study.name))
        console.print(
            f"{outcome.ran} variant(s) run, {outcome.total} in {outcome.folder / 'results.csv'}"
        )
    if plot is not None:
        grid = {axis.key for axis in outcome.study.grid}
        try:
            path = draw(outcome.rows, keys, split_sort(sort)[0], plot, grid)
        except OSError as exc:  # the rows are in results.csv: only the figure is missing
            where = exc.filename or plot
            raise UsageError(f"--plot: cannot write {where}: {exc.strerror or exc}") from None
        if not quiet:
            console.print(f"plot: {path}")
    return EXIT_OK


class _Bar:
    """A rich progress bar with ETA on stderr (none with --quiet or when not a terminal)."""

    def __init__(self, console, quiet: bool):
        self.console, self.quiet = console, quiet
        self.progress = self.task = None

    def start(self, todo: int, total: int) -> None:
        if self.quiet or todo == 0:
            return
        from rich.progress import (
            BarColumn,
            MofNCompleteColumn,
            Progress,
            TextColumn,
            TimeElapsedColumn,
            TimeRemainingColumn,
        )

        self.progress = Progress(
            TextColumn("variants"), BarColumn(), MofNCompleteColumn(),
            TimeElapsedColumn(), TextColumn("ETA"), TimeRemainingColumn(),
            console=self.console, transient=True,
        )  # fmt: skip
        self.progress.start()
        self.task = self.progress.add_task("study", total=todo)
        if todo < total:
            self.console.print(f"resuming: {total - todo} of {total} variants already done")

    def advance(self, done: int, todo: int) -> None:
        if self.progress is not None:
            self.progress.update(self.task, completed=done)

    def stop(self) -> None:
        if self.progress is not None:
            self.progress.stop()
            self.progress = None
