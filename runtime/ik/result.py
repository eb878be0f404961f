"""The outcome of one IPO cycle of the inverse transformation (:class:`CycleResult`)."""

from __future__ import annotations

from functools import cached_property

import numpy as np
from irlc.runtime.ik.limits import active_label, describe_box_bound


class CycleResult:
    """Outcome of one IPO cycle (SI).

    Fields: ``q`` (configuration at the end of the cycle), ``iterations`` (Newton steps
    taken), ``position_error`` (m) / ``orientation_error`` (rad) left on the controlled
    task components, ``converged``, ``relaxed`` (the hard QP had no solution: the task
    was moved into the cost), ``singular`` (no well-conditioned m×m block of J was found
    in some step), ``clearances`` (obstacle name → (distance m, link) at the end of the
    cycle, for every obstacle in ``CycleOptions.obstacles``), ``tcp`` (4×4 world TCP pose
    at ``q``, from the last forward kinematics of the cycle — callers need no second FK;
    the chain's task pose, in its base frame), ``task_errors`` (the norm of each extra
    task's rows at ``q``, in the order of ``chain.tasks``: m or rad by its kind),
    ``active_codes`` (per joint the box bound the cycle displacement touches, coded by
    :func:`~irlc.runtime.ik.limits.active_codes`; ``None`` when none: the recorder keeps
    the codes and labels them only for the report).

    Computed on first access: ``active`` (joint → ``"position max"``, ``"speed min"``, …
    decoded from ``active_codes``), ``binding`` (the active bound with the largest QP
    multiplier, in program units, e.g. ``"J11 position max 60 deg"`` or ``"coupled limit
    theta2+theta3 max 25 deg"``; ``""`` if none; joints named by
    the solver's ``naming``), ``manipulability`` (``Π σ_i`` of the
    task Jacobian over the free joints at the last Newton iterate; NaN when the cycle was
    run with ``CycleOptions.jacobian = False`` and converged) and ``sigma_min`` (its
    smallest singular value).
    """

    def __init__(
        self,
        q,
        iterations,
        position_error,
        orientation_error,
        converged,
        relaxed,
        singular,
        clearances,
        *,
        active_codes=None,
        box=None,
        model=None,
        free=None,
        qp_active=None,
        qp_multipliers=None,
        jacobian=None,
        coupled=None,
        tcp=None,
        naming=None,
        task_errors=(),
    ):
        self.q = q
        self.iterations = iterations
        self.position_error = position_error
        self.orientation_error = orientation_error
        self.converged = converged
        self.relaxed = relaxed
        self.singular = singular
        self.clearances: dict[str, tuple[float, int]] = clearances
        self.active_codes: np.ndarray | None = active_codes
        self._box, self._model, self._free = box, model, free
        self._qp_active, self._qp_mult, self._jac = qp_active, qp_multipliers, jacobian
        self._coupled = coupled
        self._naming = naming  # JointNaming of the messages (None: a1 … aN)
        self.tcp = tcp  # 4×4 world TCP pose at ``q`` (SI)
        self.task_errors: tuple[float, ...] = task_errors  # ‖F_k‖ per extra task (chain.tasks)

    def __repr__(self) -> str:
        return (
            f"CycleResult(iterations={self.iterations}, position_error="
            f"{self.position_error:.3g}, orientation_error={self.orientation_error:.3g}, "
            f"converged={self.converged}, relaxed={self.relaxed}, binding={self.binding!r})"
        )

    @cached_property
    def active(self) -> dict[int, str]:
        codes = self.active_codes
        if codes is None:
            return {}
        # min bounds first, then max (the order ``binding`` falls back on)
        order = sorted(np.flatnonzero(codes).tolist(), key=lambda j: (codes[j] % 2 == 0, j))
        return {j: active_label(codes[j]) for j in order}

    @cached_property
    def binding(self) -> str:
        if self._box is None:
            return ""
        if self._qp_active is not None and self._qp_active.size:
            nf = self._free.size
            r = int(self._qp_active[int(np.argmax(self._qp_mult))])
            if r >= 2 * nf and self._coupled is not None:  # a coupled-limit row
                return self._coupled.describe_row(r - 2 * nf)
            j = int(self._free[r % nf])
            return describe_box_bound(self._model, self._box, j, r >= nf, self._naming)
        if self.active:
            j, what = next(iter(self.active.items()))
            return describe_box_bound(self._model, self._box, j, what.endswith("max"), self._naming)
        return ""

    @cached_property
    def _singular_values(self) -> np.ndarray:
        if self._jac is None:
            return np.full(1, np.nan)
        return np.linalg.svd(self._jac, compute_uv=False)

    @property
    def manipulability(self) -> float:
        return float(np.prod(self._singular_values))

    @property
    def sigma_min(self) -> float:
        s = self._singular_values
        return float(s[-1]) if s.size else 0.0
