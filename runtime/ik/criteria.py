"""The cost of one IPO cycle: ``R_CRITERION`` with the reference θ⁰ and the obstacles.

Each criterion word names a quadratic form of the cycle displacement — its *metric* —
and the other criteria of the cycle are measured in it:

==============  =====================================  ===========================================
R_CRITERION     without θ⁰: ``g``, ``H``               with θ⁰ (CYCLIC, WITH RECONFIGURATION,
                                                       RECONFIGURATION k): ``g``, ``H``
==============  =====================================  ===========================================
``DISTANCE``    ``W·Σ``, ``W`` (:mod:`weighted`)        ``W(θ_k − θ⁰)``, ``W`` (:mod:`cyclic`)
``MVR``         ``ŵ∘Σ``, ``diag ŵ`` (:mod:`mvr`)        ``ŵ∘(θ_k − θ⁰)``, ``diag ŵ``
``ENERGY``      ``Ĝ(θ_s)Σ``, ``Ĝ(θ_s)`` (:mod:`energy`)  ``Ĝ(θ⁰)(θ_k − θ⁰)``, ``Ĝ(θ⁰)``
==============  =====================================  ===========================================

``Ĝ(θ) = M(θ)·Σw/tr M(θ)`` is the links' inertia matrix scaled to the trace of ``W``, and
``ŵ = Σw/n`` the MVR's unit weights scaled alike (see the modules). Avoided obstacles
(OBSTACLE) add their terms and the seed's ``a_conf`` times the displacement term of the
criterion (eq. 48–49: ``a_conf·W`` for DISTANCE, ``a_conf·diag ŵ`` for MVR,
``a_conf·Ĝ(θ_s)`` for ENERGY), with θ⁰ too. FREEZE and the joint box act on the step as
for any cost.

Why the reference term takes the metric *at the reference* for ENERGY: a reference term
makes the configuration a function of the pose (a closed path closes, CYCLIC's promise);
``Ĝ(θ⁰)`` is constant while θ⁰ is, so that stays true, and the heavy joints are the ones
kept near θ⁰. (With ``Ĝ(θ_s)`` the metric would follow the arm and a closed path would
not close exactly.) The kinetic energy of the displacement is not added to the reference
term (as DISTANCE's ``W·Σ`` is not): CYCLIC and RECONFIGURATION decide where the arm goes,
the criterion how that distance is measured.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from irlc.lang.settings import setting_message
from irlc.robots.model import RobotModel
from irlc.runtime.errors import RunFailure
from irlc.runtime.ik import mvr
from irlc.runtime.ik.cyclic import CyclicReference, MetricReference
from irlc.runtime.ik.energy import InertiaMetric, KineticEnergy
from irlc.runtime.ik.params import CycleOptions
from irlc.runtime.ik.weighted import WeightedDisplacement


class DiagonalTerms:
    """The terms of a criterion with a diagonal metric ``diag(w)`` (DISTANCE: the robot's
    weights; MVR: ``ŵ``), made once and reused (only θ⁰ changes)."""

    def __init__(self, w: np.ndarray, a_conf: float):
        self.w = np.asarray(w, dtype=float)
        self.displacement = WeightedDisplacement(self.w)
        self.conf = WeightedDisplacement(self.w, a_conf)
        self.cyclic = CyclicReference(self.w, np.zeros(self.w.size))
        self.only = [self.displacement]


class CycleCriteria:
    """The criteria of one chain (module doc): ``terms`` gives a cycle's list."""

    def __init__(
        self,
        model: RobotModel,
        weights: np.ndarray,
        a_conf: float,
        robots: Sequence[tuple[RobotModel, np.ndarray]] | None = None,
    ):
        self.model = model
        self.robots = robots  # the chain's robots and their columns (ENERGY's links)
        self.weights = np.asarray(weights, dtype=float)
        self.a_conf = a_conf
        self.distance = DiagonalTerms(self.weights, a_conf)
        self._mvr: DiagonalTerms | None = None
        self._inertia: InertiaMetric | None = None
        self._reference: tuple[bytes, np.ndarray] | None = None  # θ⁰ → Ĝ(θ⁰)

    def diagonal(self, criterion: str) -> DiagonalTerms | None:
        """The diagonal terms of DISTANCE or MVR; ``None`` for ENERGY (a full metric)."""
        if criterion == "DISTANCE":
            return self.distance
        if criterion == "MVR":
            if self._mvr is None:
                self._mvr = DiagonalTerms(mvr.joint_weights(self.weights), self.a_conf)
            return self._mvr
        if criterion == "ENERGY":
            return None
        raise RunFailure(setting_message("criterion", criterion, "R_CRITERION") or criterion)

    @property
    def inertia(self) -> InertiaMetric:
        """``Ĝ(θ)`` of the chain's links (raises ``EnergyNeedsInertia`` when they have no
        inertial data)."""
        if self._inertia is None:
            self._inertia = InertiaMetric(self.model, self.weights, self.robots)
        return self._inertia

    def reference_metric(self, reference: np.ndarray) -> np.ndarray:
        """``Ĝ(θ⁰)``, kept while θ⁰ stays the same (CYCLIC: computed once)."""
        key = np.asarray(reference, dtype=float).tobytes()
        if self._reference is None or self._reference[0] != key:
            self._reference = (key, self.inertia(np.asarray(reference, dtype=float)))
        return self._reference[1]

    def terms(self, opts: CycleOptions, q_start: np.ndarray, avoided: bool) -> list:
        """The criterion terms of a cycle from ``q_start`` (``avoided``: obstacles are
        avoided, whose own terms the caller adds)."""
        diag = self.diagonal(opts.criterion)
        if diag is not None:
            if opts.reference is not None:
                cyclic = diag.cyclic  # reused: only the reference changes per cycle
                cyclic.reference = np.asarray(opts.reference, dtype=float)
                return [cyclic, diag.conf] if avoided else [cyclic]
            return [diag.conf if avoided else diag.displacement]
        out: list = []
        if opts.reference is not None:
            out.append(MetricReference(self.reference_metric(opts.reference), opts.reference))
            if not avoided:
                return out
        out.append(KineticEnergy(self.inertia(q_start), self.a_conf if avoided else 1.0))
        return out
