"""Command line: a thin layer over the public API (``irlc.api``).

Each area registers its commands in its own module; ``main`` maps errors to the
exit codes of ``docs/interfaces.md`` and never lets a traceback reach the user for bad
input.
"""

from __future__ import annotations

import contextlib
import logging
import os
import sys
import warnings

import click
import numpy as np

# Command modules register themselves on `cli` when imported.
from irlc.cli import lang_cmds, robot_cmds, run_cmds, study_cmds, tool_cmds  # noqa: F401
from irlc.cli.app import cli
from irlc.errors import EXIT_INTERNAL, EXIT_INTERRUPTED, EXIT_USAGE, UsageError
from irlc.runtime.accel_support import EngineChoiceError

__all__ = ["cli", "main"]


def main(argv: list[str] | None = None) -> int:
    _usable_streams()
    try:
        with quiet_libraries():
            rv = cli.main(args=argv, prog_name="irlc", standalone_mode=False)
    except click.exceptions.Exit as e:
        return e.exit_code
    except click.Abort:
        click.echo("aborted", err=True)
        return EXIT_INTERRUPTED
    except click.ClickException as e:  # usage errors: exit 3, not click's 2; one line
        click.echo(f"irlc: error: {click_message(e)}", err=True)
        return EXIT_USAGE
    except (UsageError, EngineChoiceError) as e:
        click.echo(f"irlc: error: {e}", err=True)
        return EXIT_USAGE
    except KeyboardInterrupt:
        return EXIT_INTERRUPTED
    except OSError as e:  # the environment: a full standard output or disk, a lost device
        if e.filename is None:  # a stream: the standard output (what is left goes nowhere)
            _discard_stdout()
        where = e.filename or "the standard output"
        with contextlib.suppress(OSError):
            click.echo(f"irlc: error: cannot write {where}: {e.strerror or e}", err=True)
        return EXIT_USAGE
    except MemoryError:  # the environment: the machine's (or the limit's) memory is too small
        click.echo(
            "irlc: error: out of memory: the command needs more memory than this process may"
            " use (a shorter run: --max-time, a larger --ipo, a coarser --drives level)",
            err=True,
        )
        return EXIT_USAGE
    except Exception as e:
        import traceback

        click.echo(
            f"irlc: internal error: {type(e).__name__}: {e}\n"
            "This is a bug in irlc; please report it with the program that triggered it.",
            err=True,
        )
        if "--debug" in (argv or sys.argv):
            traceback.print_exc()
        return EXIT_INTERNAL
    return rv if isinstance(rv, int) else 0


def click_message(error: click.ClickException) -> str:
    """click's error as irlc's one line: its message (a leading capital lowered), then for a
    usage error the command's usage and where its help is — instead of click's four lines
    ``Usage: … / Try '… --help' for help. / (blank) / Error: …``."""
    text = error.format_message()
    if text[:1].isupper() and text[1:2].islower():
        text = text[0].lower() + text[1:]
    ctx = getattr(error, "ctx", None)
    if isinstance(error, click.UsageError) and ctx is not None:
        text = text.removesuffix(".")
        usage = ctx.get_usage().removeprefix("Usage: ")
        text += f" — usage: {' '.join(usage.split())} (see {ctx.command_path} --help)"
    return text


MIN_COLUMNS = 40  # a narrower COLUMNS is taken as this: at 0 the tables printed nothing


def _usable_streams() -> None:
    """Standard output and error that can take any text: a closed one (``>&-``: Python's
    ``None``) writes to the null device, and a character the stream's encoding lacks
    (``PYTHONIOENCODING=ascii``, the ``²`` of a unit) is escaped instead of failing; a
    ``COLUMNS`` below :data:`MIN_COLUMNS` is raised to it (rich's tables drew nothing at
    0 and one character a line at 5)."""
    columns = os.environ.get("COLUMNS", "").strip()
    if columns.isdigit() and int(columns) < MIN_COLUMNS:
        os.environ["COLUMNS"] = str(MIN_COLUMNS)
    for name in ("stdout", "stderr"):
        if getattr(sys, name) is None:
            setattr(sys, name, open(os.devnull, "w", encoding="utf-8"))  # noqa: SIM115
        with contextlib.suppress(AttributeError, ValueError, OSError):
            getattr(sys, name).reconfigure(errors="backslashreplace")
    if not isinstance(sys.stderr, _Unfailing):
        sys.stderr = _Unfailing(sys.stderr)


class _Unfailing:
    """The standard error, whose write errors (``2>/dev/full``, a closed pipe) are dropped:
    nobody can be told of them, and the exit status keeps saying what the command did
    (a full standard error turned exit 1 and 2 into 3, and 3 into 1)."""

    def __init__(self, stream) -> None:
        self._stream = stream

    def write(self, text: str) -> int:
        try:
            return self._stream.write(text)
        except OSError:
            return len(text)

    def flush(self) -> None:
        with contextlib.suppress(OSError):
            self._stream.flush()

    def __getattr__(self, name: str):
        return getattr(self._stream, name)


def _discard_stdout() -> None:
    """Point the standard output at the null device, so that the text still buffered for
    it is dropped at exit instead of failing again."""
    with contextlib.suppress(OSError, ValueError, AttributeError):
        null = os.open(os.devnull, os.O_WRONLY)
        os.dup2(null, sys.stdout.fileno())
        os.close(null)


@contextlib.contextmanager
def quiet_libraries():
    """No library noise on stderr: numpy's floating-point RuntimeWarnings (a non-finite
    result is caught where it matters: every output is checked finite) and the warnings
    yourdfpy and lxml log while parsing a URDF (a bad URDF is a RobotFileError)."""
    loggers = [logging.getLogger(name) for name in ("yourdfpy", "trimesh", "lxml")]
    levels = [lg.level for lg in loggers]
    for lg in loggers:
        lg.setLevel(logging.ERROR + 1)
    try:
        with warnings.catch_warnings():
            warnings.filterwarnings("ignore", category=RuntimeWarning, module=r"numpy(\.|$)")
            with np.errstate(all="ignore"):
                yield
    finally:
        for lg, level in zip(loggers, levels, strict=True):
            lg.setLevel(level)


def entry() -> None:
    sys.exit(main())
