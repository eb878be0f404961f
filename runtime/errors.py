"""Run-time failures: the program compiled but could not be executed (exit code 2)."""

from __future__ import annotations


class RunFailure(Exception):
    """A failure of the simulated run, pointing at the program line and simulated time.

    ``constraint`` names what bound the solution when the failure is an infeasible
    motion (e.g. ``"joint a11 position max 60 deg"``).
    """

    def __init__(
        self,
        message: str,
        line: int | None = None,
        time_s: float | None = None,
        constraint: str | None = None,
    ):
        super().__init__(message)
        self.message = message
        self.line = line
        self.time_s = time_s
        self.constraint = constraint

    def as_dict(self) -> dict:
        out = {"message": self.message, "line": self.line, "time_s": self.time_s}
        if self.constraint:
            out["constraint"] = self.constraint
        return out
