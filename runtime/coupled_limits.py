"""Coupled joint limits: linear inequalities ``lower ≤ c·q ≤ upper`` from the robot file.

The IRb-6's piecewise bounds of θ3 over θ2 (robots.md) are exactly
``max(−40, −40−θ2) ≤ θ3 ≤ min(40, 25−θ2)``: the box of θ3 plus ``−40 ≤ θ2+θ3 ≤ 25``;
with ``−90 ≤ θ2+θ3+θ4 ≤ 90`` the set is convex, so all of it is ``A q ≥ b``:

    A = [ C ; −C ],  b = [ lower ; −upper ]     (rows with an infinite bound dropped)

For an increment ``Δq`` from ``q``: ``A Δq ≥ b − A q`` — the form the IK's QP takes.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from irlc.robots.model import RobotModel


@dataclass(frozen=True)
class CoupledLimit:
    name: str
    coeffs: np.ndarray  # (n,)
    lower: float  # SI; -inf when absent
    upper: float  # SI; +inf when absent
    text: str = ""


@dataclass(frozen=True)
class Violation:
    """``amount`` > 0 is how far (SI) ``c·q`` lies beyond the ``side`` bound."""

    name: str
    side: str  # "lower" | "upper"
    value: float
    bound: float
    amount: float
    text: str = ""


def coupled_limits(model: RobotModel) -> tuple[CoupledLimit, ...]:
    rows = model.extra.get("coupled_limits", [])
    return tuple(
        CoupledLimit(
            r["name"],
            np.asarray(r["coeffs"], dtype=float),
            r["lower"],
            r["upper"],
            r.get("text", ""),
        )
        for r in rows
    )


def violations(
    limits: tuple[CoupledLimit, ...], q: np.ndarray, tol: float = 1e-12
) -> list[Violation]:
    """Every violated inequality at ``q`` with the amount (empty list: all satisfied)."""
    out = []
    for c in limits:
        v = float(c.coeffs @ q)
        if v < c.lower - tol:
            out.append(Violation(c.name, "lower", v, c.lower, c.lower - v, c.text))
        if v > c.upper + tol:
            out.append(Violation(c.name, "upper", v, c.upper, v - c.upper, c.text))
    return out


def as_inequalities(limits: tuple[CoupledLimit, ...], n: int) -> tuple[np.ndarray, np.ndarray]:
    """``(A, b)`` with ``A q ≥ b`` equivalent to all coupled limits (``A`` is m×n)."""
    rows, rhs = [], []
    for c in limits:
        if math.isfinite(c.lower):
            rows.append(c.coeffs)
            rhs.append(c.lower)
        if math.isfinite(c.upper):
            rows.append(-c.coeffs)
            rhs.append(-c.upper)
    if not rows:
        return np.zeros((0, n)), np.zeros(0)
    return np.array(rows), np.array(rhs)


def describe(v: Violation) -> str:
    """One line for a report: which inequality, by how much (degrees for angles)."""
    return (
        f"coupled limit {v.name} ({v.text or v.side}) violated: value {math.degrees(v.value):.3f}"
        f" beyond {v.side} bound {math.degrees(v.bound):.3f} by {math.degrees(v.amount):.3f} deg"
    )
