"""The click group and the bare form ``irlc PROGRAM.irl`` (= ``irlc run PROGRAM.irl``)."""

from __future__ import annotations

import difflib
import os
from pathlib import Path

import click
from irlc.errors import UsageError
from irlc.lang.file_access import path_kind


class IrlcGroup(click.Group):
    """A group whose first argument may be a program file instead of a command."""

    def parse_args(self, ctx: click.Context, args: list[str]) -> list[str]:
        if args and not args[0].startswith("-") and args[0] not in self.commands:
            self._refuse_misspelt_command(args[0])
            args = ["run", *args]
        return super().parse_args(ctx, args)

    def _refuse_misspelt_command(self, word: str) -> None:
        """A :class:`UsageError` for a first word that is no file and looks like a command
        (no suffix, no folder): ``irlc chek p.irl`` ran ``chek`` as the program."""
        if "." in word or "/" in word or os.sep in word or path_kind(Path(word)) != "missing":
            return
        names = sorted(self.commands)
        close = difflib.get_close_matches(word, names, n=1, cutoff=0.6)
        hint = f"did you mean '{close[0]}'?" if close else f"commands: {', '.join(names)}"
        raise UsageError(f"no such command or program file '{word}' ({hint})")


@click.group(
    cls=IrlcGroup,
    context_settings={"help_option_names": ["-h", "--help"]},
    epilog="Bare form: `irlc PROGRAM.irl [options]` is `irlc run PROGRAM.irl [options]`.",
)
@click.version_option(package_name="irlc")
def cli() -> None:
    """irlc — compile and simulate IRL programs for redundant industrial robots.

    Environment: IRLC_ENGINE=numpy|compiled|auto chooses the engine of the IK and drive
    loops (default numpy; docs/ik.md)."""
    from irlc.runtime.accel_support import engine

    engine()  # a bad IRLC_ENGINE is an environment error (exit 3) before any work


def require_file(path: Path) -> None:
    """A :class:`UsageError` unless ``path`` names a regular file: no such file, a folder,
    or a device or pipe (read, a FIFO blocks and ``/dev/zero`` never ends)."""
    reason = {"folder": "a folder, not a file", "missing": "no such file",
              "other": "not a regular file"}.get(path_kind(path))  # fmt: skip
    if reason is not None:
        raise UsageError(f"{path}: {reason}")


def distinct_outputs(inputs: dict[str, Path], outputs: dict[str, Path | None]) -> None:
    """A :class:`UsageError` when an output (option → path) would overwrite an input (what
    → path) or another output: ``irlc compile p.irl -o p.irl`` replaced the program."""
    seen = {_same_file_key(path): what for what, path in inputs.items()}
    for option, path in outputs.items():
        if path is None:
            continue
        key = _same_file_key(path)
        if key in seen:
            raise UsageError(f"{option} {path}: that is {seen[key]}; choose another file")
        seen[key] = f"the file of {option}"


def _same_file_key(path: Path) -> str:
    """A path's identity, links and ``..`` resolved (an output need not exist yet)."""
    return str(Path(path).expanduser().resolve())
