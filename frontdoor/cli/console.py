"""The command line's rich console: output to a reader that may stop reading.

``irlc run prog.irl | head -3`` closes the pipe while the run still writes; rich's default
then exits with status 1 — which irlc's exit codes reserve for a program that does not
compile. Here the rest of the standard output goes to the null device instead and the
command carries on, so its exit status is still the run's own (docs/interfaces.md).
"""

from __future__ import annotations

import os
import sys

import click
from rich import console as rich_console


def _drop_stdout() -> None:
    """Point the standard output at the null device: every later write is dropped."""
    devnull = os.open(os.devnull, os.O_WRONLY)
    try:
        os.dup2(devnull, sys.stdout.fileno())
    finally:
        os.close(devnull)


class Console(rich_console.Console):
    """:class:`rich.console.Console` that goes quiet, not away, when its pipe closes."""

    def on_broken_pipe(self) -> None:
        self.quiet = True
        _drop_stdout()


def echo(text: str, nl: bool = True) -> None:
    """``click.echo`` to the standard output (a program's WRITELN lines, ``--json``) that
    drops the rest of the output when the reader has closed the pipe (click would exit 1)."""
    try:
        click.echo(text, nl=nl)
    except BrokenPipeError:
        _drop_stdout()
