"""Sensitivity of the end pose to the kinematic parameters (Szkodny's tables 3.5, 4.3, 5.6).

The end pose ``X(q; p)`` (the TCP with the robot file's tool) depends on the kinematic
parameters ``p_k`` of the chain. ``S_k = ∂X/∂p_k`` is the sensitivity to parameter ``k``;
``|S_k p_k|`` — the first-order change of the pose if ``p_k`` were wrong by 100 % of its
value — makes the parameters of different units comparable: a millimetre of end-point
displacement for every parameter, and degrees of end-orientation change for the angular
ones. That is this module's reading of the book's ``|S_k^½ p_k|``; the book's exact
definition and its table values are not in the sources at hand (docs/fidelity.md).

Parameters:

* **DH rows** (``[robot] chain = "dh"``; recognised from the model: every joint axis is
  ``z`` and each fixed transform decomposes exactly as ``F = Tz(d) Rz(θ) Tx(a) Rx(α)``):
  per row ``a`` (Szkodny's ``l``), the fixed one of ``d`` (``λ``) or ``θ``, ``α``, and the
  joint's ``offset`` (the zero of its variable). A change of ``d`` or ``θ`` moves everything
  after the row along / about the ``z`` axis of the row's joint frame; a change of ``a`` or
  ``α`` along / about the ``x`` axis of the frame after ``F``.
* **Other chains** (``axes``, URDF): the non-zero translation components of each joint
  origin and of the flange, in the frame before them, and the joints' offsets.
* **The tool**: the non-zero components of its translation.

Derivatives are exact (a parameter change is an infinitesimal rigid motion of the rest of
the chain: a translation ``v`` moves the TCP by ``v``, a rotation ``ω`` about an axis
through ``o`` by ``ω × (p − o)`` and turns it by ``ω``); the tests compare them with
finite differences of robot files whose values were changed.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from irlc.robots.model import RobotModel
from irlc.runtime.model import spatial
from irlc.runtime.model.coupled_limits import coupled_limits, violations
from irlc.runtime.model.kinematics import Kinematics

DH_TOL = 1e-9

_X, _Z = np.array([1.0, 0.0, 0.0]), np.array([0.0, 0.0, 1.0])


@dataclass(frozen=True)
class Parameter:
    """One kinematic parameter: ``name`` (``"A2 a"``), ``symbol`` (``a`` | ``d`` | ``α`` |
    ``θ`` | ``offset`` | ``x`` | ``y`` | ``z``), ``kind`` (``"length"`` | ``"angle"``),
    ``value`` (SI), and how a change moves the rest of the chain: ``motion``
    (``"translate"`` | ``"rotate"``) along / about ``axis`` (a unit vector in the frame
    ``frame`` names: ``("link", i)`` link ``i``'s frame, ``("after", i)`` that frame times
    the fixed transform after joint ``i``, ``("flange", 0)``)."""

    name: str
    symbol: str
    kind: str
    value: float
    motion: str
    axis: np.ndarray
    frame: tuple[str, int]


@dataclass(frozen=True)
class Sensitivity:
    """``|S_k p_k|`` of one parameter: ``position_m`` (end-point displacement, m) and
    ``orientation_rad`` at the home configuration and their maxima over the sampled
    configurations (``*_max``)."""

    parameter: Parameter
    position_m: float
    orientation_rad: float
    position_max_m: float
    orientation_max_rad: float


def dh_row(f: np.ndarray) -> tuple[float, float, float, float] | None:
    """``(d, θ, a, α)`` with ``f = Tz(d) Rz(θ) Tx(a) Rx(α)``, or None when ``f`` has no
    such form (to :data:`DH_TOL`)."""
    r, t = f[:3, :3], f[:3, 3]
    theta = float(np.arctan2(r[1, 0], r[0, 0]))
    alpha = float(np.arctan2(r[2, 1], r[2, 2]))
    a = float(t[0] * np.cos(theta) + t[1] * np.sin(theta))
    d = float(t[2])
    rebuilt = (
        spatial.transform(None, (0.0, 0.0, d))
        @ spatial.transform(spatial.rot_z(theta))
        @ spatial.transform(None, (a, 0.0, 0.0))
        @ spatial.transform(spatial.rot_x(alpha))
    )
    return (d, theta, a, alpha) if np.allclose(rebuilt, f, atol=DH_TOL, rtol=0.0) else None


def _is_dh(model: RobotModel) -> bool:
    return all(np.allclose(j.axis, _Z) for j in model.joints) and np.allclose(
        model.joints[0].origin, np.eye(4)
    )


def parameters(model: RobotModel) -> list[Parameter]:
    """The kinematic parameters of ``model``, in chain order (see the module doc)."""
    n = model.n
    dh = _is_dh(model)
    fixed = [j.origin for j in model.joints[1:]] + [model.flange]  # F_i after joint i
    out = [] if dh else _translations(f"{model.joints[0].name} origin", model.joints[0].origin, 0)
    for i, joint in enumerate(model.joints, start=1):
        var = "θ" if joint.kind == "revolute" else "d"
        motion, unit = ("rotate", "angle") if joint.kind == "revolute" else ("translate", "length")
        out.append(Parameter(f"{joint.name} {var}0", "offset", unit, joint.offset, motion, None,
                             ("joint", i)))  # fmt: skip
        row = dh_row(fixed[i - 1]) if dh else None
        if row is not None:
            out += _dh_parameters(joint.name, joint.kind, i, row)
        else:
            after = model.joints[i].name if i < n else "flange"
            out += _translations(f"{after} origin", fixed[i - 1], i)
    for k, axis_name in enumerate("xyz"):
        if (value := float(model.tool[k, 3])) != 0.0:
            out.append(Parameter(f"tool {axis_name}", axis_name, "length", value, "translate",
                                 np.eye(3)[k], ("flange", 0)))  # fmt: skip
    return out


def _dh_parameters(name: str, kind: str, i: int, row) -> list[Parameter]:
    """Row ``i``'s fixed ``d`` (revolute) or ``θ`` (prismatic), ``a`` and ``α``."""
    d, theta, a, alpha = row
    if kind == "revolute":
        fixed = Parameter(f"{name} d", "d", "length", d, "translate", _Z, ("link", i))
    else:
        fixed = Parameter(f"{name} θ", "θ", "angle", theta, "rotate", _Z, ("link", i))
    return [
        fixed,
        Parameter(f"{name} a", "a", "length", a, "translate", _X, ("after", i)),
        Parameter(f"{name} α", "α", "angle", alpha, "rotate", _X, ("after", i)),
    ]


def _translations(name: str, f: np.ndarray, before: int) -> list[Parameter]:
    """The non-zero translation components of the fixed transform ``f`` (a chain that is
    not DH), along the axes of link ``before``'s frame (the frame ``f`` is given in)."""
    return [
        Parameter(
            f"{name} {axis_name}",
            axis_name,
            "length",
            float(f[k, 3]),
            "translate",
            np.eye(3)[k],
            ("link", before),
        )
        for k, axis_name in enumerate("xyz")
        if f[k, 3] != 0.0
    ]


def derivatives(
    model: RobotModel, params: list[Parameter], q: np.ndarray, kin: Kinematics | None = None
) -> tuple[np.ndarray, np.ndarray]:
    """``(∂p/∂p_k, ∂ω/∂p_k)``, each ``(len(params), 3)`` (world; m or rad per unit of the
    parameter): the TCP's displacement and turn per unit change of each parameter at ``q``."""
    kin = kin or Kinematics(model)
    frames = kin.link_frames(q)
    tcp = kin.tcp_from_frames(frames)[:3, 3]
    flange = kin.flange_from_frames(frames)
    after = [frames[i] @ f for i, f in enumerate(_fixed_after(model), start=1)]
    dp, dw = np.zeros((len(params), 3)), np.zeros((len(params), 3))
    axes_world, origins = kin.joint_axes_world(frames)
    for k, p in enumerate(params):
        kind, i = p.frame
        if kind == "joint":
            v, o = axes_world[i - 1], origins[i - 1]
        else:
            frame = frames[i] if kind == "link" else after[i - 1] if kind == "after" else flange
            v, o = frame[:3, :3] @ p.axis, frame[:3, 3]
        if p.motion == "translate":
            dp[k] = v
        else:
            dp[k], dw[k] = np.cross(v, tcp - o), v
    return dp, dw


def _fixed_after(model: RobotModel) -> list[np.ndarray]:
    return [j.origin for j in model.joints[1:]] + [model.flange]


def sample_configurations(model: RobotModel, count: int, seed: int = 0) -> np.ndarray:
    """``count`` configurations drawn uniformly inside the position limits (and the coupled
    limits), seeded — the home configuration first."""
    rng = np.random.default_rng(seed)
    lim = model.position_limits
    coupled = coupled_limits(model)
    out = [model.home_q()]
    tries = 0
    while len(out) < count and tries < 200 * count:
        tries += 1
        q = rng.uniform(lim[:, 0], lim[:, 1])
        if not violations(coupled, q):
            out.append(q)
    return np.array(out)


def sensitivities(model: RobotModel, samples: int = 200, seed: int = 0) -> list[Sensitivity]:
    """``|S_k p_k|`` of every parameter at the home configuration and at most over
    ``samples`` configurations (home included)."""
    params = parameters(model)
    kin = Kinematics(model)
    values = np.array([abs(p.value) for p in params])
    pos, ori = [], []
    for q in sample_configurations(model, samples, seed):
        dp, dw = derivatives(model, params, q, kin)
        pos.append(np.linalg.norm(dp, axis=1) * values)
        ori.append(np.linalg.norm(dw, axis=1) * values)
    pos_a, ori_a = np.array(pos), np.array(ori)
    return [
        Sensitivity(p, pos_a[0, k], ori_a[0, k], pos_a[:, k].max(), ori_a[:, k].max())
        for k, p in enumerate(params)
    ]
