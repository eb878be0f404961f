"""``irlc run PROGRAM.irl|PROGRAM.ird`` (and the bare form ``irlc PROGRAM.irl``).

Exit codes (``docs/interfaces.md``): 0 ok; 1 the program does not compile (diagnostics on
stderr); 2 run-time failure (report and trace up to the failure are still written, with
``status = "failed"``); 3 usage or environment error.

``--seed-config`` takes the start configuration in program units (deg | mm), either as
one string (``--seed-config "0 90 -90"``, commas allowed) or repeated once per joint
(``--seed-config 0 --seed-config 90 --seed-config -90``).
"""

from __future__ import annotations

import re
import sys
import time
from pathlib import Path

import click
from irlc.cli.app import cli, distinct_outputs, require_file
from irlc.cli.lang_cmds import allow_any_path_option
from irlc.errors import EXIT_COMPILE, EXIT_OK, EXIT_RUN, UsageError
from irlc.runtime.drives.levels import LEVELS as DRIVE_LEVELS


def parse_seed_config(values: tuple[str, ...]) -> list[float] | None:
    """``("0 90", "-90")`` → ``[0.0, 90.0, -90.0]``; raises UsageError for non-numbers."""
    if not values:
        return None
    out = []
    for text in values:
        for tok in re.split(r"[\s,;]+", text.strip()):
            if not tok:
                continue
            try:
                out.append(float(tok))
            except ValueError:
                raise UsageError(f"--seed-config: {tok!r} is not a number") from None
    return out


@cli.command("run")
@click.argument("program", type=click.Path(path_type=Path, dir_okay=False))
@click.option("--robot", default=None, help="Robot name or description file (overrides ROBOT).")
@click.option(
    "--datalist-path",
    "datalist_path",
    multiple=True,
    type=click.Path(path_type=Path, file_okay=False, exists=True),
    help="Folder searched for IMPORT DATALIST files (repeatable).",
)
@click.option("--ipo", type=float, default=None, help="IPO cycle in seconds (overrides R_IPO).")
@click.option(
    "--max-time",
    "max_time",
    type=float,
    default=None,
    help="Simulated-time budget of the run in seconds (default 86400 = 24 h).",
)
@click.option(
    "--max-cycles",
    "max_cycles",
    type=int,
    default=None,
    help="Cycle budget: IPO cycles the run may simulate (of motion, and those a WAIT "
    "records), the bound on what it computes (default 50000, about 8 min of robot time at "
    "a 10 ms IPO cycle).",
)
@click.option(
    "--instruction-budget",
    "instruction_budget",
    type=int,
    default=None,
    help="Endless-loop guard: instructions without motion or waiting before the run fails "
    "(a motion that does not move counts as 250).  "
    "[default: 500000]",
)
@click.option(
    "--drives",
    type=click.Choice(DRIVE_LEVELS),
    default="ideal",
    show_default=True,
    help="Drive simulation level after the kinematic run.",
)
@click.option(
    "--path-tolerance",
    "path_tolerance",
    type=float,
    default=None,
    help="Path tolerance in mm (start value of R_PATH_TOL; default 0.05). A larger TCP "
    "deviation fails the run; with --drives, that of the actual motion.",
)
@click.option(
    "--override",
    type=float,
    default=None,
    metavar="PERCENT",
    help="Program override in % (start value of R_OVERRIDE, 1-100; default 100): "
    "speeds ×k, accelerations ×k², k = PERCENT/100.",
)
@click.option(
    "--orientation-tolerance",
    "orientation_tolerance",
    type=float,
    default=None,
    help="Orientation tolerance in deg (default 0.01).",
)
@click.option(
    "--report",
    "report_path",
    type=click.Path(path_type=Path, dir_okay=False),
    help="Write the report as JSON.",
)
@click.option(
    "--trace",
    "trace_path",
    type=click.Path(path_type=Path, dir_okay=False),
    help="Write the trace as CSV (one row per IPO sample).",
)
@click.option(
    "--trace-every-step",
    is_flag=True,
    help="With --drives: one trace row per drive step instead of per IPO sample.",
)
@click.option(
    "--plot",
    "plot_dir",
    type=click.Path(path_type=Path, file_okay=False),
    help="Write PNG figures into this folder.",
)
@click.option(
    "--animate",
    "animate_path",
    type=click.Path(path_type=Path, dir_okay=False),
    help="Write a self-contained 3D animation (HTML).",
)
@click.option(
    "--compare",
    "compare_path",
    type=click.Path(path_type=Path, dir_okay=False),
    help="A previous report (.json) or trace (.csv) to compare with.",
)
@click.option(
    "--export-trajectory",
    "export_path",
    type=click.Path(path_type=Path, dir_okay=False),
    help="Write the joint trajectory as JSON.",
)
@click.option(
    "--mcap",
    "mcap_path",
    type=click.Path(path_type=Path, dir_okay=False),
    help="Write the run as MCAP with ROS 2 messages (Foxglove; extra irlc[mcap]).",
)
@click.option(
    "--allow-collisions",
    "allow_collisions",
    is_flag=True,
    help="A penetration of an obstacle of the cell does not fail the run (the summary and "
    "the report list them).",
)
@click.option("--json", "as_json", is_flag=True, help="Print the report as JSON on stdout.")
@click.option("--quiet", "-q", is_flag=True, help="No summary, no progress, no program output.")
@click.option(
    "--seed-config",
    "seed_config",
    multiple=True,
    help="Start configuration (deg | mm): one string of numbers, or repeated.",
)
@allow_any_path_option
def run_cmd(
    program: Path,
    robot,
    datalist_path,
    ipo,
    max_time,
    max_cycles,
    instruction_budget,
    drives,
    path_tolerance,
    override,
    orientation_tolerance,
    report_path,
    trace_path,
    trace_every_step,
    plot_dir,
    animate_path,
    compare_path,
    export_path,
    mcap_path,
    allow_collisions,
    as_json,
    quiet,
    seed_config,
    allow_any_path,
) -> int:
    """Compile (.irl) or load (.ird) PROGRAM and simulate it; print a summary."""
    from irlc.cli.console import Console, echo

    seed = parse_seed_config(seed_config)
    require_file(program)
    distinct_outputs(  # (the --compare file is read first: a report may replace it)
        {"the program": program},
        {"--report": report_path, "--trace": trace_path, "--animate": animate_path,
         "--export-trajectory": export_path, "--mcap": mcap_path},
    )  # fmt: skip
    if mcap_path is not None:
        _require_mcap_writer()
    if trace_every_step and drives == "ideal":
        raise UsageError("--trace-every-step needs --drives other than ideal")
    compare = _load_compare(compare_path) if compare_path is not None else None
    out = Console(highlight=False, soft_wrap=False)
    err = Console(stderr=True, highlight=False, soft_wrap=True)  # one line a message, as check's
    live = not (quiet or as_json)
    run = _run(
        program,
        robot,
        datalist_path,
        dict(
            ipo=ipo,
            drives=drives,
            path_tolerance=path_tolerance,
            override=override,
            orientation_tolerance=orientation_tolerance,
            instruction_budget=instruction_budget,
            max_time=max_time,
            max_cycles=max_cycles,
            allow_any_path=allow_any_path,
            allow_collisions=allow_collisions,
            stream=True,  # bounded memory: the trace is written piece by piece
        ),
        seed,
        trace_every_step,
        live and sys.stdout.isatty(),
        None if not live else echo,
        err,
    )
    if isinstance(run, int):
        return run
    for d in run.diagnostics:
        err.print(_render_diag(d), markup=False)
    written = _write_outputs(run, report_path, trace_path)
    written += _tool_outputs(run, plot_dir, animate_path, export_path, compare, err)
    written += _mcap_output(run, mcap_path)
    if as_json:
        from irlc.report import report_json

        echo(report_json(run.report), nl=False)
    elif not quiet:
        from irlc.summary import render_comparison, render_summary

        render_summary(run.report, out)
        if compare is not None:
            render_comparison(run.report, compare, out)
        if written:  # (a file name is text, never rich markup)
            out.print(f"wrote {', '.join(written)}", markup=False, soft_wrap=True)
    if run.error is not None:
        err.print(_render_failure(program, run.code, run.error), markup=False)
        return EXIT_RUN
    return EXIT_OK


def _run(program, robot, datalist_path, options, seed, every_step, show_progress, echo, err):
    """Compile and run; returns the RunResult, or an exit code after printing the error."""
    from irlc.lang.diagnostics import CompileError
    from irlc.robots import RobotFileError
    from irlc.runtime.errors import DriveSetupError
    from irlc.runtime.run import RunSetupError, run_file

    progress = Progress(echo) if show_progress else None
    try:
        return run_file(
            program,
            robot=robot,
            datalist_path=datalist_path,
            seed_config=seed,
            progress=progress.update if progress else None,
            phase=progress.phase if progress else None,
            output=progress.say if progress else echo,
            trace_every_step=every_step,
            **options,
        )
    except CompileError as exc:
        if progress:
            progress.stop()
        for d in exc.diagnostics:
            err.print(_render_diag(d), markup=False)
        return EXIT_COMPILE
    except (RunSetupError, DriveSetupError, RobotFileError) as exc:
        if progress:
            progress.stop()
        raise UsageError(str(exc)) from None
    finally:
        if progress:
            progress.stop()


def _render_diag(d) -> str:
    from irlc.lang.diagnostics import render

    return render(d)


def _render_failure(program: Path, code, error) -> str:
    """``FILE:LINE:COL: error: run-time failure at t = … s: message`` with the source line,
    its statement text underlined (:func:`~irlc.lang.diagnostics.line_span`)."""
    from irlc.lang.diagnostics import Diagnostic, line_span, program_text, render

    when = f" at t = {error.time_s:.3f} s" if error.time_s is not None else ""
    if not error.line:
        when += " (the code records no source line for it)"
    source = _source_file(program, code)
    span = line_span(program_text(str(source)), error.line) if error.line else None
    hint = f"binding constraint: {error.constraint}" if error.constraint else None
    diag = Diagnostic("error", f"run-time failure{when}: {error.message}", str(source), span, hint)
    return render(diag)


def _source_file(program: Path, code) -> Path:
    """The .irl source of a program: an .ird's SOURCE record (``code.source``, from the code
    the run already read) when that file exists next to it, else the program itself."""
    src = getattr(code, "source", "") if program.suffix.lower() == ".ird" else ""
    cand = program.parent / src if src else program
    return cand if cand.is_file() else program


def _write_outputs(run, report_path, trace_path) -> list[str]:
    """Write the report and the trace; returns what was written (``report r.json``, …)."""
    from irlc.report import write_report, write_trace

    written = []
    try:
        if report_path is not None:
            write_report(run.report, report_path)
            written.append(f"report {report_path}")
        if trace_path is not None:
            partial = run.error is not None
            write_trace(run.trace_columns, run.trace_tables(), trace_path, partial)
            written.append(f"trace {trace_path}" + (" (up to the failure)" if partial else ""))
    except OSError as exc:
        raise UsageError(f"cannot write {exc.filename}: {exc.strerror}") from None
    return written


def _tool_outputs(run, plot_dir, animate_path, export_path, compare, err) -> list[str]:
    """Figures, animation, trajectory export; returns what was written."""
    jobs = [
        (plot_dir, "irlc.plots", "write_plots", "--plot", "figures"),
        (animate_path, "irlc.animate", "write_animation", "--animate", "animation"),
        (export_path, "irlc.export", "write_trajectory", "--export-trajectory", "trajectory"),
    ]
    written = []
    for target, module, func, option, what in jobs:
        if target is None:
            continue
        try:
            mod = __import__(module, fromlist=[func])
            fn = getattr(mod, func)
        except (ImportError, AttributeError) as exc:
            raise UsageError(f"{option} is not available: {exc}") from None
        try:
            if func == "write_plots":
                overlay = compare if getattr(compare, "trace", None) is not None else None
                if compare is not None and overlay is None:
                    err.print(
                        "note: --compare with a report has no samples to overlay in the "
                        "plots; give a trace CSV (--trace) for that",
                        markup=False,
                    )
                written.append(f"{len(fn(run, target, compare=overlay))} {what} in {target}")
            else:
                fn(run, target)
                written.append(f"{what} {target}")
        except ImportError as exc:  # e.g. matplotlib not installed
            raise UsageError(f"{option} needs an optional package: {exc}") from None
        except OSError as exc:
            raise UsageError(f"{option}: cannot write {exc.filename}: {exc.strerror}") from None
    return written


def _require_mcap_writer() -> None:
    """A usage error before the run when the MCAP writer (extra ``mcap``) is missing."""
    from irlc.mcap_export import MissingWriter, require_writer

    try:
        require_writer()
    except MissingWriter as exc:
        raise UsageError(f"--mcap: {exc}") from None


def _mcap_output(run, mcap_path) -> list[str]:
    """Write the MCAP file (``--mcap``); returns what was written."""
    if mcap_path is None:
        return []
    from irlc.mcap_export import write_mcap

    try:
        write_mcap(run, mcap_path)
    except OSError as exc:
        raise UsageError(f"--mcap: cannot write {exc.filename}: {exc.strerror}") from None
    return [f"MCAP {mcap_path}"]


def _load_compare(path: Path):
    from irlc.report import RunFileError, load_run

    try:
        return load_run(path)
    except RunFileError as exc:
        raise UsageError(f"--compare: {exc}") from None


class Progress:
    """A transient progress line on a terminal — the simulated time and program line, then
    the run's later stages (the drive simulation) — for runs longer than a moment. The
    program's output (``say``) is printed above it, never onto the same line; a line
    printed before the progress line shows goes out at once (``echo``)."""

    DELAY_S = 0.5  # only runs longer than this show it

    def __init__(self, echo, console=None):
        from irlc.cli.console import Console
        from rich.progress import Progress as Bar
        from rich.progress import SpinnerColumn, TextColumn, TimeElapsedColumn

        self.echo = echo
        self.bar = Bar(
            SpinnerColumn(),
            TextColumn("{task.description}"),
            TimeElapsedColumn(),
            console=console or Console(highlight=False),  # the output's: lines go above it
            transient=True,
        )
        self.task = self.bar.add_task("simulating", total=None)
        self.started = False
        self.wall0 = time.monotonic()

    def _show(self, description: str, now: bool = False) -> None:
        if not self.started:
            if not now and time.monotonic() - self.wall0 < self.DELAY_S:
                return
            self.bar.start()
            self.started = True
        self.bar.update(self.task, description=description)

    def update(self, t: float, line: int) -> None:
        """The kinematic run's progress (the controller's callback)."""
        self._show(f"simulating: line {line}, t = {t:.2f} s")

    def phase(self, text: str) -> None:
        """A later stage of the run starts (``run_file(phase=…)``): shown at once."""
        self._show(text, now=True)

    def say(self, text: str) -> None:
        """One line of the program's output, above the progress line."""
        if self.started:
            self.bar.console.print(text, markup=False, highlight=False, soft_wrap=True)
        else:
            self.echo(text)

    def stop(self) -> None:
        if self.started:
            self.bar.stop()
            self.started = False


__all__ = ["parse_seed_config", "run_cmd"]
