"""The DC axis cascade as one bank of axes: position P → velocity PI → current controller
with armature → power stage (averaged or PWM). One call advances every DC axis one step.

Averaged stage, fused: between saturations the whole cascade is linear. With the state
``s = [x_v, i, u]`` (PI integral, armature current, controller output) and the inputs
``d = θ_ref − θ``, ``ω`` held over the step, one per-axis matrix ``G`` (built once from
the gains and the exact current-loop map ``[Φ Γ; Ψ̄ₓ Ψ̄_w]`` of :class:`.current.CurrentLoop`)
gives every quantity of the step at once::

    [u_ω, u_i^raw, u_end, i_end, ī, x_v', ū] = G · [d, ω, x_v, i, u]
    u_ω = kz d,   e = u_ω − ke ω,   u_i = kp e + ki x_v,   x_v' = x_v + h e,
    [i, u]_end, [ī, ū] = [Φ Γ; Ψ̄ₓ Ψ̄_w] · [i, u, u_i, ω]

If no limit is reached (``|u_ω|, |u_i| ≤ u_ref_max``, ``|u_end| ≤ U``,
``|i_end|, |ī| ≤ i_max``) this *is* the step; otherwise the step is redone element by
element (:func:`.position.position_p`, :class:`.velocity.VelocityPI`,
:func:`.power_stage.averaged`), which handles every saturation exactly.

Start: at rest with the current (and PI integral, controller output) that holds the
given motor torque, so a run does not begin with the arm sagging.
"""

from __future__ import annotations

import numpy as np
from irlc.runtime.drives import motor, power_stage
from irlc.runtime.drives.current import CurrentLoop
from irlc.runtime.drives.params import DcDrives
from irlc.runtime.drives.position import position_p
from irlc.runtime.drives.velocity import VelocityPI

# rows of the flat map (:attr:`DcBank.flat`), as rows of ``fused_matrix``: the limited
# quantities and the means first, then the new state [x_v', i_end, u_end] in one block
FLAT_ROWS = (0, 1, 4, 6, 5, 3, 2)  # [u_ω, u_i, ī, ū, x_v', i_end, u_end]


class DcBank:
    def __init__(self, c: DcDrives, h: float, pwm: bool, holding_torque: np.ndarray):
        self.c, self.h, self.pwm = c, h, pwm
        i0 = np.clip(holding_torque / c.ks, -c.i_max, c.i_max)
        self.pi = VelocityPI(c.ke, c.kp, c.ki, c.u_ref_max, len(i0))
        self.pi.x = np.clip(c.k * i0, -c.u_ref_max, c.u_ref_max) / c.ki
        if pwm:
            self.stage = power_stage.PwmStage(
                c.R, c.L, c.ks, c.k, c.kiwzm, c.U, c.i_max, c.pwm_frequency
            )
            self.stage.i, self.stage.u_c = i0.copy(), c.R * i0
        else:
            self.loop = CurrentLoop(c.R, c.L, c.ks, c.k, c.kiwzm, h)
            self.loop.x[:, 0], self.loop.x[:, 1] = i0, c.R * i0
            self.fused = fused_matrix(c, h, self.loop.big)
            self.limits = np.stack([c.u_ref_max, c.u_ref_max, c.U, c.i_max, c.i_max], axis=1)
            self._init_flat(c)
            self._no_sat = np.zeros(len(i0), dtype=bool)
            self._try_fused = True

    def _init_flat(self, c: DcDrives) -> None:
        """The fused map of all axes as one block matrix ``flat`` (7m × 5m) on the stacked
        ``z = [d; ω; x_v; i; u]`` (blocks of m axes), rows :data:`FLAT_ROWS`, so that a step
        is one matrix–vector product and the new state one slice copy; ``z[2m:]`` holds the
        state ``[x_v; i; u]`` between steps (:attr:`pi` and :attr:`loop` are synced from it
        around an element-wise step)."""
        m = len(c.kz)
        self.flat = np.zeros((7 * m, 5 * m))
        ax = np.arange(m)
        for r, row in enumerate(FLAT_ROWS):
            for col in range(5):
                self.flat[r * m + ax, col * m + ax] = self.fused[:, row, col]
        inf = np.full(m, np.inf)
        self.flat_limits = np.concatenate(
            [c.u_ref_max, c.u_ref_max, c.i_max, inf, inf, c.i_max, c.U]
        )
        self.z = np.zeros(5 * m)
        self.z[2 * m : 3 * m] = self.pi.x
        self.z[3 * m : 4 * m] = self.loop.x[:, 0]
        self.z[4 * m :] = self.loop.x[:, 1]
        self._abs = np.zeros(7 * m)

    def step(self, theta_ref, theta, omega, t: float):
        """Motor torque, mean current, mean voltage, saturation flags, electrical energy in
        and copper loss over the step."""
        if not self.pwm:
            out = self.fused_step(theta_ref, theta, omega)
            if out is not None:
                m, c, h = len(self._no_sat), self.c, self.h
                i_mean, u_mean = out[2 * m : 3 * m], out[3 * m : 4 * m]
                return (
                    c.ks * i_mean,
                    i_mean,
                    u_mean,
                    self._no_sat,
                    u_mean * i_mean * h,
                    c.R * i_mean * i_mean * h,
                )
        return self.limited_step(theta_ref, theta, omega)

    def fused_step(self, theta_ref, theta, omega):
        """The step as one linear map (averaged stage) when no limit is reached: the flat
        output ``[u_ω, u_i, ī, ū, x_v', i_end, u_end]`` (blocks of m axes), else ``None``
        with the state kept (then :meth:`limited_step`). After a limited step the next one
        goes element-wise directly (it mostly is limited too), the one after tries again."""
        if not self._try_fused:
            self._try_fused = True
            return None
        z = self.z
        m = len(self._no_sat)
        np.subtract(theta_ref, theta, out=z[:m])
        z[m : 2 * m] = omega
        out = self.flat @ z
        np.abs(out, out=self._abs)
        if np.count_nonzero(self._abs > self.flat_limits):
            self._try_fused = False
            return None
        z[2 * m :] = out[4 * m :]
        return out

    def limited_step(self, theta_ref, theta, omega, t: float = 0.0):
        """The step element by element, every saturation handled exactly (same tuple as
        :meth:`step`)."""
        c = self.c
        flat = not self.pwm
        if flat:  # the state lives in z between fused steps
            m = len(self._no_sat)
            z = self.z
            self.pi.x = z[2 * m : 3 * m].copy()
            self.loop.x[:, 0], self.loop.x[:, 1] = z[3 * m : 4 * m], z[4 * m :]
        u_w, sat_p = position_p(c.kz, theta_ref, theta, c.u_ref_max)
        u_i, sat_v = self.pi.step(u_w, omega, self.h)
        if self.pwm:
            i_mean, u_mean, energy, copper, sat_s = self.stage.period(u_i, omega)
        else:
            i_mean, u_mean, energy, copper, sat_s = power_stage.averaged(
                self.loop, u_i, omega, c, self.h
            )
            z[2 * m : 3 * m] = self.pi.x
            z[3 * m : 4 * m], z[4 * m :] = self.loop.x[:, 0], self.loop.x[:, 1]
        return motor.torque(c.ks, i_mean), i_mean, u_mean, sat_p | sat_v | sat_s, energy, copper


def fused_matrix(c: DcDrives, h: float, big: np.ndarray) -> np.ndarray:
    """``G`` (axes, 7, 5): rows ``[u_ω, u_i^raw, u_end, i_end, ī, x_v', ū]``, columns
    ``[d, ω, x_v, i, u]``; ``big`` the current loop's ``[Φ Γ; Ψ̄ₓ Ψ̄_w]`` (axes, 4, 4) on
    ``[i, u, u_i, ω]`` with rows ``[i_end, u_end, ī, ū]``."""
    m = len(c.kz)
    g = np.zeros((m, 7, 5))
    g[:, 0, 0] = c.kz
    raw = np.stack([c.kp * c.kz, -c.kp * c.ke, c.ki, np.zeros(m), np.zeros(m)], axis=1)
    g[:, 1] = raw
    g[:, 5] = np.stack([h * c.kz, -h * c.ke, np.ones(m), np.zeros(m), np.zeros(m)], axis=1)
    for row, b in ((2, 1), (3, 0), (4, 2), (6, 3)):  # current-loop rows through u_i = raw
        g[:, row] = big[:, b, 2, None] * raw
        g[:, row, 1] += big[:, b, 3]
        g[:, row, 3] += big[:, b, 0]
        g[:, row, 4] += big[:, b, 1]
    return g
