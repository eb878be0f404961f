"""The actual (simulated drive) motion of a run, measured against the commanded path.

Inputs: the recorded IPO samples ``k`` (commanded joints ``θ_k``, their TCP ``T_k`` with the
tool in effect, the desired pose ``x_d(t_k)`` where a Cartesian path is commanded) and the
drive's actual joints ``θ̂(t)`` at times ``t``.

**Actual TCP.** With ``K(θ)`` the forward kinematics of the robot file (its tool ``X``),
``T_k = B F(θ_k) X'`` (``X'`` = the tool in effect, R_TOOL composed after the file's) and
``K(θ) = B F(θ) X``, the actual pose is

    T̂(t) = K(θ̂(t)) · K(θ_k)⁻¹ · T_k = B F(θ̂) X',

``k`` the sample at or before ``t``: the program's tool is used without knowing it.

**Path error** (contour error at the sample, not the shortest distance to the path): the
norms of the position and orientation parts of ``T̂(t) ⊖ x_d(t)`` on the controlled task
components (a planar arm's task is ``x, y``), where ``x_d(t)`` is the *commanded* TCP at the
same time. Between two IPO samples (every-step traces) ``x_d`` is interpolated: position
linearly, orientation by slerp. PTP motion and standing still command no TCP path: their
path error is 0, as in ideal runs; there the drives are judged by their following error.

**Clearances** are those of the actual link frames ``F(θ̂)`` (``runtime.distance``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from irlc.runtime import spatial
from irlc.runtime.recorder import RecordedRun


@dataclass
class ActualMotion:
    """The actual motion at ``times`` (SI)."""

    times: np.ndarray  # (m,)
    sample: np.ndarray  # (m,) index of the IPO sample at or before each time
    q: np.ndarray  # (m, n)
    tcp: np.ndarray  # (m, 4, 4) world
    pos_error: np.ndarray  # (m,) m
    ori_error: np.ndarray  # (m,) rad
    on_path: np.ndarray  # (m,) bool
    clearance: dict[str, np.ndarray]  # name → (m,) m


def measure(
    model, rec: RecordedRun, times: np.ndarray, q: np.ndarray, task_rows, obstacles: dict
) -> ActualMotion:
    """The actual TCP, path errors and clearances of joints ``q`` at ``times`` (module doc)."""
    from irlc.runtime.kinematics import Kinematics

    kin = Kinematics(model)
    m = len(times)
    idx = np.clip(
        np.searchsorted(rec.times, times, side="right") - 1, 0, max(len(rec.times) - 1, 0)
    )
    tcp = np.empty((m, 4, 4))
    for i in range(m):
        k = idx[i]
        tcp[i] = kin.tcp(q[i]) @ spatial.inverse(kin.tcp(rec.q[k])) @ rec.tcp[k]
    desired, on_path = _desired(rec, times, idx)
    rows = np.array(tuple(task_rows), dtype=int)
    pos_rows, ori_rows = rows[rows < 3], rows[rows >= 3]
    pos = np.zeros(m)
    ori = np.zeros(m)
    for i in np.flatnonzero(on_path):
        e = spatial.pose_error(tcp[i], desired[i])
        pos[i] = np.linalg.norm(e[pos_rows])
        ori[i] = np.linalg.norm(e[ori_rows])
    return ActualMotion(times, idx, q, tcp, pos, ori, on_path, _clearances(kin, q, obstacles))


def _desired(rec: RecordedRun, times: np.ndarray, idx: np.ndarray):
    """``x_d(t)`` and whether a path is commanded there (module doc)."""
    k_last = len(rec.times) - 1
    desired = rec.desired[idx].copy()
    on_path = rec.on_path[idx].copy()
    for i, t in enumerate(times):
        k = idx[i]
        if k >= k_last or t <= rec.times[k] or not on_path[i]:
            continue
        if not rec.on_path[k + 1]:
            continue
        s = (t - rec.times[k]) / (rec.times[k + 1] - rec.times[k])
        a, b = rec.desired[k], rec.desired[k + 1]
        desired[i, :3, 3] = (1.0 - s) * a[:3, 3] + s * b[:3, 3]
        quat = spatial.slerp(
            spatial.matrix_to_quat(a[:3, :3]), spatial.matrix_to_quat(b[:3, :3]), s
        )
        desired[i, :3, :3] = spatial.quat_to_matrix(quat)
    return desired, on_path


def _clearances(kin, q: np.ndarray, obstacles: dict) -> dict[str, np.ndarray]:
    if not obstacles:
        return {}
    from irlc.runtime.distance import critical_points

    shapes = tuple(obstacles.values())
    out = {name: np.empty(len(q)) for name in obstacles}
    for i, qi in enumerate(q):
        for cp in critical_points(kin, kin.link_frames(qi), shapes):
            out[cp.name][i] = cp.distance
    return out
