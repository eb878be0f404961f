"""The actual (simulated drive) motion of a run, measured against the commanded path.

Inputs: the recorded IPO samples ``k`` (commanded joints ``θ_k``, their TCP ``T_k`` with the
tool in effect, the desired pose ``x_d(t_k)`` where a Cartesian path is commanded) and the
drive's actual joints ``θ̂(t)`` at times ``t``.

**Actual TCP.** With ``K(θ)`` the forward kinematics of the robot file (its tool ``X``),
``T_k = B F(θ_k) X'`` (``X'`` = the tool in effect, R_TOOL composed after the file's) and
``K(θ) = B F(θ) X``, the actual pose is

    T̂(t) = K(θ̂(t)) · K(θ_k)⁻¹ · T_k = B F(θ̂) X',

``k`` the sample at or before ``t``: the program's tool is used without knowing it.

**Path error** is the *contour error*: the distance from the actual TCP to the commanded
TCP path, not to the set point of the same instant (the drives' lag *along* the path is a
timing error, judged by the following-error bound). The commanded path is the polyline of
the desired poses ``x_d(t_k)`` of the Cartesian samples; for the actual sample at ``t`` its
segments within ``[t − 2 s, t + 0.5 s]`` are searched (a closed path is not matched with
its next lap). With ``a, b`` a segment's ends and ``p`` the actual position,

    s* = clamp(((p − a)·(b − a)) / |b − a|², 0, 1),   e_p = min over segments |p − (a + s*(b − a))|

on the controlled position components (a planar arm's task is ``x, y``); the orientation
error is that of ``T̂`` against the desired pose at the nearest point (orientation by slerp).
PTP motion and standing still command no TCP path: their path error is 0, as in ideal
runs; there the drives are judged by their following error.

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
    on_path = rec.on_path[idx].copy()
    rows = np.array(tuple(task_rows), dtype=int)
    pos_rows, ori_rows = rows[rows < 3], rows[rows >= 3]
    pos = np.zeros(m)
    ori = np.zeros(m)
    path = _CommandedPath(rec)
    for i in np.flatnonzero(on_path):
        pos[i], ori[i] = path.contour_error(times[i], tcp[i], pos_rows, ori_rows)
    return ActualMotion(times, idx, q, tcp, pos, ori, on_path, _clearances(kin, q, obstacles))


WINDOW_BACK_S = 2.0  # how far back along the path the nearest point is searched
WINDOW_AHEAD_S = 0.5  # and how far ahead (overshoot)


class _CommandedPath:
    """The polyline of the desired TCP positions of the Cartesian samples (module doc)."""

    def __init__(self, rec: RecordedRun) -> None:
        self.times = rec.times
        self.desired = rec.desired
        self.points = rec.desired[:, :3, 3]
        # segment k joins samples k and k + 1 where k + 1 commands a path: a path starts at
        # the sample before its first one (the commanded TCP where the motion begins)
        self.joined = rec.on_path[1:].copy()
        self.on_path = rec.on_path

    def contour_error(self, t: float, tcp: np.ndarray, pos_rows, ori_rows) -> tuple[float, float]:
        """(position, orientation) error of ``tcp`` against the nearest commanded point."""
        lo = int(np.searchsorted(self.times, t - WINDOW_BACK_S, side="left"))
        hi = int(np.searchsorted(self.times, t + WINDOW_AHEAD_S, side="right"))
        p = tcp[:3, 3]
        seg = lo + np.flatnonzero(self.joined[lo : max(hi - 1, lo)])
        if seg.size:
            a, b = self.points[seg], self.points[seg + 1]
            d = b - a
            length2 = np.einsum("ij,ij->i", d, d)
            s = np.where(
                length2 > 0.0,
                np.einsum("ij,ij->i", p - a, d) / np.where(length2 > 0.0, length2, 1.0),
                0.0,
            )
            s = np.clip(s, 0.0, 1.0)
            gap = (p - (a + s[:, None] * d))[:, pos_rows]
            dist = np.linalg.norm(gap, axis=1)
            best = int(np.argmin(dist))
            desired = _between(self.desired[seg[best]], self.desired[seg[best] + 1], s[best])
        else:  # a single Cartesian sample in reach: its own pose
            k = lo + int(np.argmin(np.abs(self.times[lo:hi] - t))) if hi > lo else 0
            desired = self.desired[k]
        e = spatial.pose_error(tcp, desired)
        return float(np.linalg.norm(e[pos_rows])), float(np.linalg.norm(e[ori_rows]))


def _between(a: np.ndarray, b: np.ndarray, s: float) -> np.ndarray:
    """The pose at ``s ∈ [0, 1]`` from ``a`` to ``b``: position linear, orientation slerp."""
    out = a.copy()
    out[:3, 3] = (1.0 - s) * a[:3, 3] + s * b[:3, 3]
    if s > 0.0:
        quat = spatial.slerp(
            spatial.matrix_to_quat(a[:3, :3]), spatial.matrix_to_quat(b[:3, :3]), s
        )
        out[:3, :3] = spatial.quat_to_matrix(quat)
    return out


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
