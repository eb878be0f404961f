"""Coupled joint limits: linear inequalities ``lower ≤ c·q ≤ upper`` from the robot file.

The IRb-6's piecewise bounds of θ3 over θ2 (Szkodny; docs/robots.md) are exactly
``max(−40, −40−θ2) ≤ θ3 ≤ min(40, 25−θ2)``: the box of θ3 plus ``−40 ≤ θ2+θ3 ≤ 25``;
with ``−90 ≤ θ2+θ3+θ4 ≤ 90`` and the θ5 window ``−180 ≤ θ5 − θ234/k5 ≤ 180`` of (5.1b)
the set is convex, so all of it is ``A q ≥ b``:

    A = [ C ; −C ],  b = [ lower ; −upper ]     (rows with an infinite bound dropped)

For an increment ``Δq`` from ``q``: ``A Δq ≥ b − A q`` — the form the IK's QP takes.

A row couples joints of one kind (the loader checks it), so its bounds are angles or
lengths; :func:`row_label` / :func:`describe` print them in program units (deg | mm)
through :mod:`irlc.runtime.units` — the one place messages about a row are built.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from irlc.robots.model import RobotModel
from irlc.runtime import units


@dataclass(frozen=True)
class CoupledLimit:
    name: str
    coeffs: np.ndarray  # (n,)
    lower: float  # SI; -inf when absent
    upper: float  # SI; +inf when absent
    text: str = ""
    kind: str = units.REVOLUTE  # the kind of the row's joints: the bounds' unit


@dataclass(frozen=True)
class Violation:
    """``amount`` > 0 is how far (SI) ``c·q`` lies beyond the ``side`` bound."""

    name: str
    side: str  # "lower" | "upper"
    value: float
    bound: float
    amount: float
    text: str = ""
    kind: str = units.REVOLUTE


def coupled_limits(model: RobotModel) -> tuple[CoupledLimit, ...]:
    rows = model.extra.get("coupled_limits", [])
    return tuple(
        CoupledLimit(
            r["name"],
            np.asarray(r["coeffs"], dtype=float),
            r["lower"],
            r["upper"],
            r.get("text", ""),
            r.get("kind", units.REVOLUTE),
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
            out.append(Violation(c.name, "lower", v, c.lower, c.lower - v, c.text, c.kind))
        if v > c.upper + tol:
            out.append(Violation(c.name, "upper", v, c.upper, v - c.upper, c.text, c.kind))
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


def _program_units(value: float, kind: str) -> float:
    return float(units.joints_from_si([value], [kind])[0])


def row_label(c: CoupledLimit, side: str) -> str:
    """``"theta2+theta3 max 25 deg"``: one bound (``side`` ``"min"`` | ``"max"``) of a row."""
    value = c.lower if side == "min" else c.upper
    return f"{c.name} {side} {_program_units(value, c.kind):.6g} {units.joint_unit(c.kind)}"


def describe(v: Violation) -> str:
    """One line for a report: which inequality, by how much (program units: deg | mm)."""
    value, bound, amount = (_program_units(x, v.kind) for x in (v.value, v.bound, v.amount))
    return (
        f"coupled limit {v.name} ({v.text or v.side}) violated: value {value:.3f} beyond "
        f"{v.side} bound {bound:.3f} by {amount:.3f} {units.joint_unit(v.kind)}"
    )
