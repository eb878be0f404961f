"""Parameters of the inverse transformation and the per-cycle options.

Defaults (SI) and where they come from:

* ``tol_position = 1e-9`` m, ``tol_orientation = 1e-9`` rad: Newton stops when both
  parts of ``F`` are below them (1–3 iterations per IPO cycle).
* ``max_iter = 10`` Newton iterations per cycle.
* ``relax_weight = 1e6``: ``ρ = relax_weight·max(diag H)`` in the relaxed step.
* ``cond_max = 1e4`` (re-choose the compact basis), ``singular_cond = 1e10``.
* obstacle criterion (seed 4.2.4, chapter 6.6): ``a_obst = 0.7``, ``a_conf = 0.3``,
  ``α = c/R``. The seed writes ``α = 1000/R`` in its program units (mm): ``α·v`` is the
  desired escape displacement of the critical point *per IPO cycle*, 1000/R mm with R in
  mm, i.e. ``c = 1e-3 m²`` in SI (R = 1 m → 1 mm per cycle). Beyond ``activation``
  (0.5 m) an obstacle contributes nothing; between ``activation·(1 − ramp)`` and
  ``activation`` its weight fades smoothly to zero, so switching on is continuous.
* ``task``: which components of the 6-vector pose error are controlled — all six by
  default; a robot file may restrict it (``[ik] task = ["x", "y"]`` for a planar arm).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
from irlc.robots.model import RobotModel
from irlc.runtime.ik.clearance import ClearanceSpec
from irlc.runtime.model.chain import task_rows_for


@dataclass
class ObstacleParams:
    a_obst: float = 0.7
    a_conf: float = 0.3
    c: float = 1e-3  # m²: α = c/R metres per cycle
    activation: float = 0.5  # m: farther obstacles contribute nothing
    ramp: float = 0.5  # fraction of ``activation`` over which the weight fades in
    min_distance: float = 1e-3  # m: R is floored here (contact / penetration)


@dataclass
class IKParams:
    tol_position: float = 1e-9
    tol_orientation: float = 1e-9
    max_iter: int = 10
    task_rows: tuple[int, ...] = (0, 1, 2, 3, 4, 5)
    relax_weight: float = 1e6
    cond_max: float = 1e4
    singular_cond: float = 1e10
    eps_conf: float = 1e-6  # RECONFIGURATION ends when ‖θ(t) − θ(t−Δt)‖ < eps_conf
    solver: str = "quadprog"
    warm_start: bool = True  # first iterate θ_s + d (see newton); not for self-motion
    scalar_qp: bool = True  # one null-space dimension: closed-form QP (False: always solver)
    accel: bool | None = None  # compiled cycle (numba): None = as IRLC_ENGINE says (engine.py)
    obstacle: ObstacleParams = field(default_factory=ObstacleParams)

    @classmethod
    def for_robot(cls, model: RobotModel, **overrides) -> IKParams:
        """Defaults with the robot file's task selection (``extra['ik']['task']``)."""
        params = cls(**overrides)
        if "task_rows" not in overrides:
            params.task_rows = task_rows_for(model)
        return params


@dataclass
class CycleOptions:
    """What the program has switched on for this cycle (all SI, 0-based joints).

    ``position``/``speed``/``accel``: ``(n, 2)`` [min, max] arrays already intersected
    with the robot's own limits (:func:`~irlc.runtime.ik.limits.intersect_limits`);
    ``None`` means the robot's limits. ``reference``: θ⁰ for CYCLIC / WITH
    RECONFIGURATION (``None``: default criterion). ``self_motion``: RECONFIGURATION k
    (``reference = k``, the TCP is held at ``target``). ``frozen``: joint → held value.
    ``obstacles``: every obstacle whose clearance is reported; ``active_obstacles``: the
    names avoided (OBSTACLE … OBSTACLEEND). ``jacobian``: keep the cycle's Jacobian in
    the result for ``manipulability``/``sigma_min`` (a copy; the executor asks only on
    the cycles it samples them — an unconverged cycle keeps it anyway). ``criterion``:
    ``R_CRITERION`` — ``"DISTANCE"`` (the weighted joint displacement), ``"ENERGY"`` (the
    kinetic energy, :mod:`~irlc.runtime.ik.energy`) or ``"MVR"`` (the manipulator velocity
    ratio, :mod:`~irlc.runtime.ik.mvr`); how each combines with θ⁰ and the obstacles:
    :mod:`~irlc.runtime.ik.criteria`.
    ``clearance``:
    ``R_CLEARANCE`` > 0, the distance the links keep (:mod:`~irlc.runtime.ik.clearance`;
    ``None``: not kept).
    """

    position: np.ndarray | None = None
    speed: np.ndarray | None = None
    accel: np.ndarray | None = None
    reference: np.ndarray | None = None
    self_motion: bool = False
    frozen: dict[int, float] = field(default_factory=dict)
    obstacles: Sequence = ()
    active_obstacles: frozenset[str] = frozenset()
    jacobian: bool = True
    criterion: str = "DISTANCE"
    clearance: ClearanceSpec | None = None
