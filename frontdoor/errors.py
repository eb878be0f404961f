"""Exit codes of the command line (``docs/interfaces.md``) and the errors that map onto them."""

from __future__ import annotations

from irlc.lang.errors import IrlcError

EXIT_OK = 0
EXIT_COMPILE = 1  # the program does not compile
EXIT_RUN = 2  # compiled, but failed at run time
EXIT_USAGE = 3  # usage or environment error (missing file, unknown robot, bad option)
EXIT_INTERNAL = 4  # a bug in irlc
EXIT_INTERRUPTED = 130  # Ctrl-C (128 + SIGINT, as shells report it)


class UsageError(IrlcError):
    """Bad command-line usage or environment (exit code 3)."""
