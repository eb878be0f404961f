"""Two-phase hybrid stepper motor with an open-loop step generator (the L-1's drives).

Step generator: the motor target ``θ_t(t) = i·q_ref(t)`` is followed in full steps
``Δ = 2π/(4·z)`` (``z`` rotor teeth, 1.8° for 50) at most once every ``Δ / step_rate``; a
step is issued while ``|θ_t − θ_gen| ≥ Δ/2``. Each step switches a phase on (target
``θ_c1 = θ_gen``) and the previous one off (``θ_c2`` = the previous target); the off phase
keeps its current, the new phase starts from zero current.

Phases (Szkodny's two-phase model, "just switched on" 1 / "just switched off" 2)::

    u1 = R i1 + L di1/dt + L12 di2/dt + e1,   u1 = R·I   (rated current)
    u2 = R i2 + L di2/dt + L12 di1/dt + e2,   u2 = 0
    e_j = (∂Ψ_j/∂θ) ω,   ∂Ψ_j/∂θ = −z Ψmax sin(z(θ − θ_cj))
    M_j = −(i_j / I) M_max sin(z(θ − θ_cj)),  τ_m = M_1 + M_2

The inductance matrix has the modes ``i1 ± i2`` with inductances ``L ± L12``, each a
first-order circuit solved exactly over the step (back-EMF held). The rotor has stable
equilibria every tooth pitch ``2π/z``: a rotor that lags its target by more than half a
pitch falls into the next one and the axis has lost steps — the model's point.
"""

from __future__ import annotations

import numpy as np
from irlc.runtime.drives.params import StepperDrives


class StepperBank:
    def __init__(self, p: StepperDrives, theta0: np.ndarray, h: float):
        self.p, self.h = p, h
        self.delta = p.step_angle
        self.interval = self.delta / p.step_rate
        self.gen = theta0.copy()
        self.cmd1 = theta0.copy()
        self.cmd2 = theta0.copy()
        self.i1 = p.I.copy()  # holding current in the on phase at the start
        self.i2 = np.zeros_like(theta0)
        self.last = np.full_like(theta0, -np.inf)
        self.u1 = p.R * p.I
        self._u1_full = self.u1 * np.ones_like(theta0)
        self._no_sat = np.zeros(len(theta0), dtype=bool)
        # exact first-order modes s = i1 + i2 (L + L12), d = i1 − i2 (L − L12)
        self.decay_s = np.exp(-p.R * h / (p.L + p.L12))
        self.decay_d = np.exp(-p.R * h / (p.L - p.L12))
        self.mean_s = (p.L + p.L12) / (p.R * h) * (1.0 - self.decay_s)
        self.mean_d = (p.L - p.L12) / (p.R * h) * (1.0 - self.decay_d)

    def generate(self, target: np.ndarray, t: float) -> None:
        """Issue at most one full step per axis towards ``target`` (rate-limited)."""
        go = (np.abs(target - self.gen) >= 0.5 * self.delta) & (
            t - self.last >= self.interval - 1e-12
        )
        if go.any():
            self.cmd2 = np.where(go, self.cmd1, self.cmd2)
            self.gen = self.gen + np.where(go, np.sign(target - self.gen) * self.delta, 0.0)
            self.cmd1 = np.where(go, self.gen, self.cmd1)
            self.i2 = np.where(go, self.i1, self.i2)
            self.i1 = np.where(go, 0.0, self.i1)
            self.last = np.where(go, t, self.last)

    def step(self, theta_ref, theta, omega, t: float):
        """Generate steps towards ``theta_ref``, advance the phases one step; returns the
        same tuple as :meth:`.cascade.DcBank.step` (current = the on phase)."""
        self.generate(theta_ref, t)
        tau, i1, i2, energy = self.phases(theta, omega)
        copper = self.p.R * (i1 * i1 + i2 * i2) * self.h
        return tau, i1, self._u1_full, self._no_sat, energy, copper

    def phases(self, theta, omega):
        """Advance the phase currents one step; returns mean torque, mean i1, mean i2 and
        the electrical energy delivered (J)."""
        p = self.p
        z = p.teeth
        s1 = np.sin(z * (theta - self.cmd1))
        s2 = np.sin(z * (theta - self.cmd2))
        e1 = -z * p.psi_max * s1 * omega
        e2 = -z * p.psi_max * s2 * omega
        v1, v2 = self.u1 - e1, -e2
        # steady currents of the modes, then exact first-order relaxation
        s_inf, d_inf = (v1 + v2) / p.R, (v1 - v2) / p.R
        s0, d0 = self.i1 + self.i2, self.i1 - self.i2
        s_end = s_inf + (s0 - s_inf) * self.decay_s
        d_end = d_inf + (d0 - d_inf) * self.decay_d
        s_mean = s_inf + (s0 - s_inf) * self.mean_s
        d_mean = d_inf + (d0 - d_inf) * self.mean_d
        self.i1, self.i2 = 0.5 * (s_end + d_end), 0.5 * (s_end - d_end)
        i1m, i2m = 0.5 * (s_mean + d_mean), 0.5 * (s_mean - d_mean)
        tau = -(i1m / p.I) * p.M_max * s1 - (i2m / p.I) * p.M_max * s2
        return tau, i1m, i2m, self.u1 * i1m * self.h

    def lost_steps(self, theta: np.ndarray) -> np.ndarray:
        """Whole steps between the generator and the rotor (positive: rotor behind)."""
        return np.rint((self.gen - theta) / self.delta).astype(int)
