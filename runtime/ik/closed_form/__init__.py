"""Closed-form inverse kinematics of robot families, selected by the robot file.

A robot file names its family in ``[ik] closed_form = "<family>"`` (never the code by the
robot's name); each family is one small module with a function
``solve(model, flange, kin) -> list[Branch]`` returning *every* configuration that puts
the robot's last link frame at ``flange`` (base frame of the chain), one per kinematic
branch, each angle brought into its joint's box where a turn of 2π allows:

* ``parallel_5r`` (:mod:`.parallel_5r`): the IRb-6 — Szkodny's (5.6), base turn, three
  parallel horizontal axes, approach roll. Branches ``front``/``back`` × ``elbow-up``/
  ``elbow-down``.
* ``cartesian_wrist`` (:mod:`.cartesian_wrist`): the L-1 — Szkodny's (4.4), three
  prismatic axes and a wrist of three intersecting axes. Branches ``noflip`` (middle
  wrist angle ≥ 0) and ``flip``.

:func:`branches` verifies every candidate by forward kinematics (a candidate that does
not reproduce the pose to 1e-6 m / 1e-6 rad is dropped, so a robot file that names the
wrong family loses the closed form, never gets a wrong answer) and says which lie
within the position and coupled limits. Because the families enumerate all solutions,
"no branch within the limits" proves the pose unreachable.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from irlc.robots.model import RobotModel
from irlc.runtime.model import spatial
from irlc.runtime.model.coupled_limits import coupled_limits, violations
from irlc.runtime.model.kinematics import Kinematics

VERIFY_POSITION = 1e-6  # m (a pose rounded to the 1e-6 mm, deg of a program still verifies)
VERIFY_ORIENTATION = 1e-6  # rad


@dataclass(frozen=True)
class Branch:
    """One closed-form configuration (SI, user coordinates) and its branch label."""

    label: str
    q: np.ndarray
    within_limits: bool = True


def _families() -> dict[str, Callable[[RobotModel, np.ndarray, Kinematics], list[Branch]]]:
    from irlc.runtime.ik.closed_form import cartesian_wrist, parallel_5r

    return {"parallel_5r": parallel_5r.solve, "cartesian_wrist": cartesian_wrist.solve}


FAMILY_NAMES = ("parallel_5r", "cartesian_wrist")


def family(model: RobotModel) -> str | None:
    """The robot file's ``[ik] closed_form`` family, or ``None``."""
    ik = model.extra.get("ik", {})
    return ik.get("closed_form") if isinstance(ik, dict) else None


def branch_labels(model: RobotModel) -> tuple[str, ...]:
    """The branch labels the robot's family can return (empty without a closed form)."""
    name = family(model)
    if name == "parallel_5r":
        return tuple(f"{s}-elbow-{e}" for s in ("front", "back") for e in ("up", "down"))
    if name == "cartesian_wrist":
        return ("noflip", "flip")
    return ()


def branches(
    model: RobotModel,
    target: np.ndarray,
    tool: np.ndarray | None = None,
    position: np.ndarray | None = None,
) -> list[Branch] | None:
    """Every configuration reaching the world TCP pose ``target`` (verified by FK), marked
    ``within_limits`` against ``position`` (``(n, 2)`` SI; default the robot's box) and
    the coupled rows; ``None`` when the robot has no closed form. Where a branch has
    several in-box values (a turn of 2π), the one within the limits comes first."""
    name = family(model)
    if name is None:
        return None
    kin = Kinematics(model, tool)
    end = model.flange @ kin.tool
    flange = spatial.inverse(model.base) @ np.asarray(target, dtype=float) @ spatial.inverse(end)
    box = model.position_limits if position is None else np.asarray(position, dtype=float)
    rows = coupled_limits(model)
    out: list[Branch] = []
    for b in _families()[name](model, flange, kin):
        if not np.all(np.isfinite(b.q)) or not _verified(kin, b.q, target):
            continue
        inside = bool(np.all(b.q >= box[:, 0] - 1e-12) and np.all(b.q <= box[:, 1] + 1e-12))
        inside = inside and not violations(rows, b.q, 1e-9)
        out.append(Branch(b.label, np.clip(b.q, box[:, 0], box[:, 1]) if inside else b.q, inside))
    return _first_within(out)


def _first_within(found: list[Branch]) -> list[Branch]:
    """One entry per label: the first within the limits, else the first found."""
    by_label: dict[str, Branch] = {}
    for b in found:
        old = by_label.get(b.label)
        if old is None or (b.within_limits and not old.within_limits):
            by_label[b.label] = b
    return list(by_label.values())


def _verified(kin: Kinematics, q: np.ndarray, target: np.ndarray) -> bool:
    e = spatial.pose_error(kin.tcp(q), target)
    return bool(
        np.linalg.norm(e[:3]) <= VERIFY_POSITION and np.linalg.norm(e[3:]) <= VERIFY_ORIENTATION
    )


def turns(value: float, lo: float, hi: float) -> list[float]:
    """``value + 2πk`` for every ``k`` that lands in ``[lo, hi]`` (ascending); when none
    does, the one nearest to the interval (so that the branch is reported outside)."""
    two_pi = 2.0 * np.pi
    k0 = np.ceil((lo - value) / two_pi - 1e-12)
    out = []
    v = value + k0 * two_pi
    while v <= hi + 1e-12 and len(out) < 8:
        out.append(float(v))
        v += two_pi
    if out:
        return out
    mid = 0.5 * (lo + hi)
    return [float(value + np.round((mid - value) / two_pi) * two_pi)]


def rotation_about(axis: np.ndarray, m: np.ndarray) -> float:
    """The angle of the rotation ``m`` about the unit ``axis`` (``m`` = Rot(axis, angle))."""
    vee = np.array([m[2, 1] - m[1, 2], m[0, 2] - m[2, 0], m[1, 0] - m[0, 1]])
    return float(np.arctan2(0.5 * axis @ vee, 0.5 * (np.trace(m) - 1.0)))


def starts(
    model: RobotModel,
    target: np.ndarray,
    seed: np.ndarray,
    position: np.ndarray | None = None,
    tool: np.ndarray | None = None,
) -> list[tuple[str, np.ndarray]]:
    """The closed-form configurations within the limits as search starts ``(label, q)``,
    the nearest to ``seed`` (weighted, ``Σ w_i (q_i − seed_i)²``) first; empty without a
    closed form."""
    found = branches(model, target, tool, position) or []
    inside = [b for b in found if b.within_limits]
    w = model.weights
    inside.sort(key=lambda b: float(np.sum(w * (b.q - np.asarray(seed)) ** 2)))
    return [(b.label, b.q) for b in inside]
