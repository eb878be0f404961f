"""The step-size rule: the fixed step must be at most 1/10 of the fastest time constant of
the states integrated explicitly.

The electrical states (armature current, current controller; the stepper phases) are
discretised exactly and are exempt. What remains, per DC axis (motor-side inertia
``J``)::

    τ_v = J·k / (kp·ke·k_s)   velocity loop with an ideal current loop (its bandwidth⁻¹)
    τ_p = ke / kz             position loop (1/K_v)
    τ_i = kp / ki             PI corner

and per stepper axis the detent oscillation ``τ = 1/√(z·M_max/J)``. With the coupled
dynamics the velocity loops act through the full inertia matrix: the fastest coupled mode
is ``τ_c = 1/λ_max(M⁻¹ B)``, ``B = Kᵀ diag(kp·ke·k_s/k) K`` (joint side), which can be much
faster than any single axis when links nearly cancel (koch11's folding boom).
``h > τ_min/10`` warns (:class:`StepSizeWarning`); ``h > τ_min`` is refused
(:class:`StepSizeError`): the explicit loop would not be a simulation of the drive.
"""

from __future__ import annotations

import warnings

import numpy as np
from irlc.lang.errors import IrlcError
from irlc.runtime.drives.params import DcDrives, StepperDrives


class StepSizeWarning(UserWarning):
    pass


class StepSizeError(IrlcError, ValueError):
    pass


def fastest_time_constant(chain: DcDrives | StepperDrives, inertia: np.ndarray) -> np.ndarray:
    """Per driven axis, the fastest explicitly integrated time constant (s)."""
    if isinstance(chain, StepperDrives):
        return 1.0 / np.sqrt(chain.teeth * chain.M_max / inertia)
    tau_v = inertia * chain.k / (chain.kp * chain.ke * chain.ks)
    tau_p = chain.ke / chain.kz
    tau_i = chain.kp / chain.ki
    return np.minimum(np.minimum(tau_v, tau_p), tau_i)


def coupled_time_constant(chain: DcDrives, mass: np.ndarray, jac: np.ndarray) -> float:
    """``1/λ_max(M⁻¹ B)`` with ``B = Kᵀ diag(kp·ke·k_s/k) K`` (joint side; ``K`` the
    transmission Jacobian of the driven axes, ``M`` with rotors)."""
    gain = jac.T @ ((chain.kp * chain.ke * chain.ks / chain.k)[:, None] * jac)
    lam = np.linalg.eigvals(np.linalg.solve(mass, gain)).real
    return float(1.0 / lam.max())


def check_step(step: float, tau: np.ndarray, names: list[str]) -> None:
    """Apply the rule; ``names`` label the axes in the message."""
    k = int(np.argmin(tau))
    where = f"axis {names[k]}: fastest time constant {tau[k] * 1e3:.3g} ms"
    if step > tau[k]:
        raise StepSizeError(
            f"drive step {step * 1e3:.3g} ms exceeds the {where}; "
            f"use a step ≤ {tau[k] * 1e2:.3g} ms"
        )
    if step > tau[k] / 10.0:
        warnings.warn(
            f"drive step {step * 1e3:.3g} ms is more than 1/10 of the {where}; "
            f"results may be inaccurate (≤ {tau[k] * 1e2:.3g} ms recommended)",
            StepSizeWarning,
            stacklevel=3,
        )


def check_generator(step: float, interval: np.ndarray) -> None:
    """A stepper's step generator must be resolved: at most one step period per drive step."""
    if step > interval.min() * (1 + 1e-9):
        raise StepSizeError(
            f"drive step {step * 1e6:.4g} µs is longer than the step generator's period "
            f"{interval.min() * 1e6:.4g} µs; use a step ≤ that period"
        )


def default_step(tau_min: float, cap: float) -> float:
    """The largest step ``cap / m`` (``m`` integer) within 1/10 of ``tau_min``."""
    m = max(1, int(np.ceil(cap / (tau_min / 10.0) - 1e-9)))
    return cap / m
