"""Run-time failures: the program compiled but could not be executed (exit code 2).

A motion failure names its **cause** (``RunFailure.cause``, the report's ``error.cause``),
decided from the solver's state, not from the last bound the relaxed step touched:

=================  ===========================================================
``unreachable``    the target (or a point of the path) is outside the workspace
                   under the active position limits and tool
``singular``       the Jacobian lost rank on the path (σ_min, the joints involved);
                   no speed resolves it
``position_limit`` the path needs a joint beyond its (active) position limit
``speed_limit``    a joint speed bound: a lower path speed resolves it (suggested)
``accel_limit``    a joint acceleration bound: a lower speed / acceleration resolves it
``freeze``         the frozen joints leave too few free joints for the task or target
``freeze_jointlimit`` FREEZE and the active JOINTLIMIT together: each alone leaves the
                   target or path reachable
``obstacle``       the arm collides with an obstacle of the cell (avoided or not)
``clearance``      two links (of two robots, or of one) collide, or come closer than
                   ``R_CLEARANCE``
``limits``         the active limits exclude the current state
``platform``       the platform task (WITH PLATFORM: the platform on its line) cannot
                   be met together with the TCP's path, which alone could be
``platform_limit`` a platform target outside the platform's (active) limits
=================  ===========================================================
"""

from __future__ import annotations

from irlc.lang.errors import IrlcError

CAUSES = (
    "unreachable",
    "singular",
    "position_limit",
    "speed_limit",
    "accel_limit",
    "freeze",
    "freeze_jointlimit",
    "obstacle",
    "clearance",
    "limits",
    "platform",
    "platform_limit",
)


class RunFailure(IrlcError):
    """A failure of the simulated run, pointing at the program line and simulated time.

    ``constraint`` names what bound the solution when the failure is an infeasible
    motion (e.g. ``"joint a11 position max 60 deg"``); ``cause`` is one of
    :data:`CAUSES` for motion failures (``None`` for others, e.g. a division by zero);
    ``details`` are extra JSON-ready facts of the cause, with units in their keys
    (``sigma_min``, ``joints``, ``distance_mm``, ``suggested_speed_mm_s`` …).
    """

    def __init__(
        self,
        message: str,
        line: int | None = None,
        time_s: float | None = None,
        constraint: str | None = None,
        cause: str | None = None,
        details: dict | None = None,
    ):
        super().__init__(message)
        self.message = message
        self.line = line
        self.time_s = time_s
        self.constraint = constraint
        self.cause = cause
        self.details = dict(details or {})

    def of_robot(self, who: str) -> RunFailure:
        """This failure as one robot's of a cell (``who``: ``robot welder``, or a
        cooperation ``welder in holder``): its message begins with ``who`` unless it names
        it already or speaks of two robots' links (a clearance). Returns ``self``."""
        if self.cause == "clearance" or self.message.startswith(who) or f"{who} " in self.message:
            return self
        self.message = f"{who}: {self.message}"
        self.args = (self.message,)
        return self

    def as_dict(self) -> dict:
        out = {"message": self.message, "line": self.line, "time_s": self.time_s}
        if self.constraint:
            out["constraint"] = self.constraint
        if self.cause:
            out["cause"] = self.cause
        out.update(self.details)
        return out


class DriveSetupError(IrlcError):
    """Drives requested but not available (module missing, robot without drive data):
    a usage error (exit code 3), raised before the drive simulation runs."""
