"""The inverse transformation's failure and the two tests both engines make before they
raise it: the numpy reference (:mod:`newton`) and the compiled cycle
(:mod:`irlc.runtime.ik.compiled.driver`) share them, so a failure reads the same on
either."""

from __future__ import annotations

import numpy as np
from irlc.runtime.errors import RunFailure


class IKFailure(RunFailure):
    """The inverse transformation cannot produce a valid configuration."""


def require_finite(what: str, x: np.ndarray) -> None:
    """:class:`IKFailure` unless every entry of ``x`` (``what``: the start configuration,
    the target pose) is finite."""
    if not np.all(np.isfinite(x)):
        raise IKFailure(f"inverse transformation: non-finite {what}")


def full_rank(J: np.ndarray, m: int) -> bool:
    """``J`` has rank ``m``: ``m`` singular values, the ``m``-th above 1e-10 of the largest
    (FREEZE: a singular free problem while the whole ``J`` has full rank means the frozen
    joints made the task impossible)."""
    s = np.linalg.svd(J, compute_uv=False)
    return s.size >= m and s[m - 1] > 1e-10 * s[0]
