"""R_CRITERION's parts (runtime/ik/energy.py, mvr.py, criteria.py) checked independently.

* ``g`` and ``H`` of each term against central finite differences of the objective it
  stands for — the seed's kinetic energy of the cycle's mean speed with the inertia matrix
  of the composite-rigid-body algorithm (``Dynamics.mass_matrix``, not the Jacobian form
  the criterion uses), the seed's MVR⁻² with the cycle's mean speeds, the reference term —
  times the documented positive factor ``κ``;
* the converged cycle is the criterion's minimiser on the task manifold: the Lagrange
  condition ``Nᵀ G δ = 0`` (``N`` a basis of the Jacobian's null space at the result,
  from an SVD), and it beats the other criteria's cycles on its own measure;
* an unknown word and ENERGY without inertials fail with the words of the settings table.
"""

from __future__ import annotations

import numpy as np
import pytest
from irlc.robots import load_robot
from irlc.runtime.errors import RunFailure
from irlc.runtime.ik import CycleOptions, IKParams, InverseTransformation, energy, mvr
from irlc.runtime.ik.criteria import CycleCriteria
from irlc.runtime.ik.cyclic import MetricReference
from irlc.runtime.ik.state import IterationState
from irlc.runtime.model.dynamics import Dynamics

from .ik_robots import planar_arm

H_STEP = 1e-4


def _fd(objective, n):
    """Central differences: gradient and Hessian of ``objective`` at 0 (a quadratic:
    exact up to round-off)."""
    e = np.eye(n) * H_STEP
    grad = np.array([(objective(e[i]) - objective(-e[i])) / (2 * H_STEP) for i in range(n)])
    hess = np.empty((n, n))
    for i in range(n):
        for j in range(n):
            hess[i, j] = (
                objective(e[i] + e[j])
                - objective(e[i] - e[j])
                - objective(-e[i] + e[j])
                + objective(-e[i] - e[j])
            ) / (4 * H_STEP**2)
    return grad, hess


def _terms(term, state, n):
    g, H = np.zeros(n), np.zeros((n, n))
    term.accumulate(state, g, H)
    return g, H


def _close(a, b, rel):
    scale = max(float(np.abs(b).max()), 1e-300)
    assert np.abs(a - b).max() <= rel * scale, (np.abs(a - b).max(), scale)


@pytest.mark.parametrize("name", ["koch11", "panda", "mobile8", "irb6", "planar3"])
def test_energy_terms_are_the_seeds_times_kappa(name):
    """ENERGY: ``g = κ·∇E``, ``H = κ·∇²E`` for ``E(Δθ) = ½(Σ+Δθ)ᵀM(θ_s)(Σ+Δθ)/Δt²``,
    ``κ = Δt²·Σw/tr M``; ``energy.seed_terms`` are ``∇E``, ``∇²E`` themselves."""
    model = load_robot(name)
    rng, n, dt = np.random.default_rng(5), model.n, 0.01
    q_s = model.home_q() + rng.normal(size=n) * 0.1
    sigma = rng.normal(size=n) * 1e-3
    m = Dynamics(model).mass_matrix(q_s)  # CRBA: another algorithm than the criterion's

    def kinetic(d):
        v = (sigma + d) / dt
        return 0.5 * v @ m @ v

    grad, hess = _fd(kinetic, n)
    seed_g, seed_h = energy.seed_terms(m, sigma, dt)
    _close(seed_g, grad, 1e-6)
    _close(seed_h, hess, 1e-5)
    metric = energy.InertiaMetric(model, model.weights)(q_s)
    g, H = _terms(energy.KineticEnergy(metric), IterationState(q_s + sigma, q_s, sigma), n)
    kappa = dt**2 * model.weights.sum() / np.trace(m)
    _close(g, kappa * grad, 1e-6)
    _close(H, kappa * hess, 1e-5)
    assert np.isclose(np.trace(H), model.weights.sum())  # scaled to the trace of W
    assert np.allclose(H, H.T) and np.linalg.eigvalsh(H).min() > 0.0


@pytest.mark.parametrize("name", ["koch11", "panda", "planar3"])
def test_mvr_terms_are_the_seeds_times_kappa(name):
    """MVR: the criterion's ``g``, ``H`` (diagonal, ``ŵ = Σw/n``) are ``κ`` times the
    gradient and Hessian of ``MVR⁻²(Δθ) = ‖Σ+Δθ‖²/‖Δx‖²`` (the mean speeds over the cycle:
    Δt cancels), ``κ = ‖Δx‖²·Σw/(2n)``."""
    model = load_robot(name)
    rng, n = np.random.default_rng(6), model.n
    sigma = rng.normal(size=n) * 1e-3
    dx = rng.normal(size=6) * 1e-3

    def inverse_square_ratio(d):
        return float((sigma + d) @ (sigma + d)) / float(dx @ dx)

    grad, hess = _fd(inverse_square_ratio, n)
    seed_g, seed_h = mvr.seed_terms(sigma, dx)
    _close(seed_g, grad, 1e-6)
    _close(seed_h, hess, 1e-5)
    criteria = CycleCriteria(model, model.weights, 0.3)
    term = criteria.terms(CycleOptions(criterion="MVR"), np.zeros(n), False)[0]
    g, H = _terms(term, IterationState(sigma, np.zeros(n), sigma), n)
    kappa = float(dx @ dx) * model.weights.sum() / (2 * n)
    _close(g, kappa * grad, 1e-6)
    _close(H, kappa * hess, 1e-5)
    assert np.allclose(H, np.diag(np.diag(H)))  # the diagonal fast path applies


def test_reference_terms_measure_the_distance_to_the_reference_in_the_metric():
    """CYCLIC under ENERGY: ``½(θ − θ⁰)ᵀĜ(θ⁰)(θ − θ⁰)``, ``Ĝ`` at the reference."""
    model = load_robot("koch11")
    rng, n = np.random.default_rng(7), model.n
    theta = model.home_q() + rng.normal(size=n) * 0.05
    ref = model.home_q()
    criteria = CycleCriteria(model, model.weights, 0.3)
    term = criteria.terms(CycleOptions(criterion="ENERGY", reference=ref), theta, False)
    assert len(term) == 1 and isinstance(term[0], MetricReference)
    m = Dynamics(model).mass_matrix(ref)
    G = m * model.weights.sum() / np.trace(m)

    def distance(d):
        x = theta + d - ref
        return 0.5 * x @ G @ x

    grad, hess = _fd(distance, n)
    g, H = _terms(term[0], IterationState(theta, theta, np.zeros(n)), n)
    _close(g, grad, 1e-6)
    _close(H, hess, 1e-5)
    # the metric is kept while θ⁰ is (CYCLIC: computed once), recomputed when it moves
    again = criteria.terms(CycleOptions(criterion="ENERGY", reference=ref.copy()), theta, False)
    assert again[0].metric is term[0].metric
    moved = criteria.terms(CycleOptions(criterion="ENERGY", reference=ref + 0.1), theta, False)
    assert moved[0].metric is not term[0].metric


def test_terms_with_avoided_obstacles_scale_the_criterion_by_a_conf():
    model = load_robot("panda")
    rng, n = np.random.default_rng(8), model.n
    q_s = model.home_q()
    sigma = rng.normal(size=n) * 1e-3
    state = IterationState(q_s + sigma, q_s, sigma)
    criteria = CycleCriteria(model, model.weights, 0.3)
    for word in ("DISTANCE", "MVR", "ENERGY"):
        alone = _terms(criteria.terms(CycleOptions(criterion=word), q_s, False)[0], state, n)
        beside = _terms(criteria.terms(CycleOptions(criterion=word), q_s, True)[0], state, n)
        assert np.allclose(beside[0], 0.3 * alone[0]) and np.allclose(beside[1], 0.3 * alone[1])
        ref = q_s + 0.05
        both = criteria.terms(CycleOptions(criterion=word, reference=ref), q_s, True)
        assert len(both) == 2  # the reference term and a_conf × the displacement term


def _null_space(J: np.ndarray) -> np.ndarray:
    _, s, vt = np.linalg.svd(J)
    rank = int(np.sum(s > s[0] * 1e-10))
    return vt[rank:].T


METRICS = {
    "DISTANCE": lambda model, q_s: np.diag(model.weights),
    "MVR": lambda model, q_s: np.eye(model.n),
    "ENERGY": lambda model, q_s: Dynamics(model).mass_matrix(q_s),
}


@pytest.mark.parametrize("name", ["koch11", "panda", "mobile8"])
def test_each_cycle_is_its_criterions_minimiser(name):
    """The converged cycle minimises ``½δᵀGδ`` on the task manifold (G = W, I, M(θ_s)):
    ``Nᵀ G δ = 0`` at the result, and its own measure is the least of the three cycles'."""
    model = load_robot(name)
    rng, n = np.random.default_rng(9), model.n
    ik = InverseTransformation(model, None, IKParams.for_robot(model, accel=False))
    free = np.tile([-1e9, 1e9], (n, 1))  # no speed or acceleration bound: a free cycle
    for _ in range(4):
        q_s = model.home_q() + rng.normal(size=n) * 0.05
        target = ik.kin.tcp(q_s)
        target[:3, 3] += rng.normal(size=3) * 2e-3  # small: no box bound binds
        steps = {}
        for word in METRICS:
            opts = CycleOptions(speed=free, accel=free, criterion=word)
            res = ik.step(q_s, q_s, target, 0.01, opts)
            assert res.converged and not res.relaxed and res.active_codes is None
            steps[word] = res.q - q_s
            N = _null_space(ik.kin.jacobian(res.q)[list(ik.rows)])
            for other, G_of in METRICS.items():  # its own condition holds, not the others'
                G = G_of(model, q_s)
                lagrange = np.abs(N.T @ G @ steps[word]).max() / np.abs(G @ steps[word]).max()
                assert lagrange < 5e-5 if other == word else lagrange > 1e-3, (word, other)
        for word, G_of in METRICS.items():
            G = G_of(model, q_s)
            own = steps[word] @ G @ steps[word]
            for other in METRICS:
                assert own <= steps[other] @ G @ steps[other] * (1 + 1e-9), (word, other)


def test_unknown_criterion_and_energy_without_inertials_fail_in_the_tables_words():
    model = load_robot("planar3")
    criteria = CycleCriteria(model, model.weights, 0.3)
    with pytest.raises(RunFailure, match="R_CRITERION := 'POWER': the value must be one of"):
        criteria.terms(CycleOptions(criterion="POWER"), np.zeros(3), False)
    bare = planar_arm(3)  # no [[inertials]]
    with pytest.raises(energy.EnergyNeedsInertia) as err:
        CycleCriteria(bare, bare.weights, 0.3).terms(
            CycleOptions(criterion="ENERGY"), np.zeros(3), False
        )
    assert str(err.value) == (
        "R_CRITERION := 'ENERGY' needs the links' inertia matrix: robot planar3 has no "
        "[[inertials]] (the robot file)"
    )
