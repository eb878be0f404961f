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
timing error, judged by the following-error bound). The commanded path joins the desired
poses ``x_d(t_k)`` of the Cartesian samples; for the actual sample at ``t`` its segments
within ``[t − 2 s, t + 0.5 s]`` are searched (a closed path is not matched with its next
lap) for the nearest pose, position and orientation together (:class:`_CommandedPath`),
and the position and orientation errors are those of ``T̂`` against that pose, on the
controlled task components (a planar arm's task is ``x, y``).
PTP motion and standing still command no TCP path: their path error is 0, as in ideal
runs; there the drives are judged by their following error.

**Clearances** are those of the actual link frames ``F(θ̂)`` (``runtime.distance``), with
the nearest link per obstacle.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from irlc.runtime.model import spatial
from irlc.runtime.outputs.recorder import RecordedRun
from irlc.runtime.plan.interpolator import CartesianLine


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
    clearance_link: dict[str, np.ndarray] | None = None  # name → (m,) the nearest link


def measure(
    model, rec: RecordedRun, times: np.ndarray, q: np.ndarray, task_rows, obstacles: dict
) -> ActualMotion:
    """The actual TCP, path errors and clearances of joints ``q`` at ``times`` (module doc)."""
    from irlc.runtime.model.distance import critical_points
    from irlc.runtime.model.kinematics import Kinematics

    kin = Kinematics(model)
    m = len(times)
    idx = np.clip(
        np.searchsorted(rec.times, times, side="right") - 1, 0, max(len(rec.times) - 1, 0)
    )
    tcp = np.empty((m, 4, 4))
    program_tool: dict[int, np.ndarray] = {}  # K(θ_k)⁻¹·T_k per IPO sample, once each
    shapes = tuple(obstacles.values())
    clearance = {name: np.empty(m) for name in obstacles}
    links = {name: np.zeros(m, dtype=int) for name in obstacles}
    for i in range(m):
        k = int(idx[i])
        if k not in program_tool:
            program_tool[k] = spatial.inverse(kin.tcp(rec.q[k])) @ rec.tcp[k]
        frames = kin.link_frames(q[i])  # one forward kinematics for the TCP and clearances
        tcp[i] = kin.tcp_from_frames(frames) @ program_tool[k]
        if shapes:
            for cp in critical_points(kin, frames, shapes):
                clearance[cp.name][i] = cp.distance
                links[cp.name][i] = cp.link
    on_path = rec.on_path[idx].copy()
    rows = np.array(tuple(task_rows), dtype=int)
    pos_rows, ori_rows = rows[rows < 3], rows[rows >= 3]
    pos = np.zeros(m)
    ori = np.zeros(m)
    path = _CommandedPath(rec)
    for i in np.flatnonzero(on_path):
        pos[i], ori[i] = path.contour_error(times[i], tcp[i], pos_rows, ori_rows)
    return ActualMotion(times, idx, q, tcp, pos, ori, on_path, clearance, links)


WINDOW_BACK_S = 2.0  # how far back along the path the nearest point is searched
WINDOW_AHEAD_S = 0.5  # and how far ahead (overshoot)
# ... but over at most this many segments (4/5 back, 1/5 ahead): the search costs the
# window's samples for each measured one, so a small IPO cycle made the measurement
# quadratic in the run's length (--ipo 0.0001: minutes). Every window of an IPO cycle
# ≥ 1 ms is whole; below, it is shorter in time (0.2 s back at 0.1 ms) — a drive
# lagging more than that would be measured against a later point, an error larger than
# the true one (a run may fail, never pass, because of it).
WINDOW_MAX_SEGMENTS = 2500
RAD_AS_M = 0.3  # nearest point: 1 rad of orientation weighs like 0.3 m of position


class _CommandedPath:
    """The commanded path as segments between the desired TCP poses of consecutive
    samples (module doc): position linear, orientation along the geodesic
    ``R(s) = exp(s·w)·R_a`` with ``w = log(R_b R_aᵀ)`` (world frame).

    The nearest point of a segment to the actual pose ``(p, R)`` minimises, to first
    order, ``|p − a − s·d|² + ℓ²|v − s·w|²`` (``d = b − a``, ``v = log(R R_aᵀ)``,
    ``ℓ = RAD_AS_M``; orientation terms only where the task controls orientation):

        s* = clamp(((p − a)·d + ℓ² v·w) / (|d|² + ℓ²|w|²), 0, 1),

    so a turn on the spot (``d = 0``) is matched by its orientation. The segment with the
    smallest such distance is the nearest; the errors are then measured exactly against
    the pose at ``s*`` (``spatial.pose_error``).
    """

    def __init__(self, rec: RecordedRun) -> None:
        self.times = rec.times
        self.desired = rec.desired
        self.points = rec.desired[:, :3, 3]
        self.rot = rec.desired[:, :3, :3]
        # segment k joins samples k and k + 1 where k + 1 commands a path: a path starts at
        # the sample before its first one (the commanded TCP where the motion begins)
        self.joined = rec.on_path[1:].copy()
        self.step = np.diff(self.points, axis=0)
        self.turn = _log(self.rot[1:] @ np.swapaxes(self.rot[:-1], 1, 2))

    def contour_error(self, t: float, tcp: np.ndarray, pos_rows, ori_rows) -> tuple[float, float]:
        """(position, orientation) error of ``tcp`` against the nearest commanded point."""
        lo = int(np.searchsorted(self.times, t - WINDOW_BACK_S, side="left"))
        hi = int(np.searchsorted(self.times, t + WINDOW_AHEAD_S, side="right"))
        if hi - lo - 1 > WINDOW_MAX_SEGMENTS:  # segments join consecutive samples
            now = int(np.searchsorted(self.times, t, side="right"))
            lo = max(lo, now - WINDOW_MAX_SEGMENTS * 4 // 5)
            hi = min(hi, now + WINDOW_MAX_SEGMENTS // 5 + 1)
        seg = lo + np.flatnonzero(self.joined[lo : max(hi - 1, lo)])
        if seg.size:
            best, s = self._nearest(seg, tcp, pos_rows, len(ori_rows) > 0)
            desired = CartesianLine(self.desired[best], self.desired[best + 1]).at(s)
        else:  # a single Cartesian sample in reach: its own pose
            k = lo + int(np.argmin(np.abs(self.times[lo:hi] - t))) if hi > lo else 0
            desired = self.desired[k]
        e = spatial.pose_error(tcp, desired)
        return float(np.linalg.norm(e[pos_rows])), float(np.linalg.norm(e[ori_rows]))

    def _nearest(self, seg: np.ndarray, tcp: np.ndarray, pos_rows, oriented: bool):
        """The nearest segment of ``seg`` and ``s*`` on it (class doc)."""
        rel = (tcp[:3, 3] - self.points[seg])[:, pos_rows]
        d = self.step[seg][:, pos_rows]
        num = np.einsum("ij,ij->i", rel, d)
        den = np.einsum("ij,ij->i", d, d)
        if oriented:
            v = _log(tcp[:3, :3] @ np.swapaxes(self.rot[seg], 1, 2))
            w = self.turn[seg]
            num = num + RAD_AS_M**2 * np.einsum("ij,ij->i", v, w)
            den = den + RAD_AS_M**2 * np.einsum("ij,ij->i", w, w)
        s = np.clip(np.where(den > 0.0, num / np.where(den > 0.0, den, 1.0), 0.0), 0.0, 1.0)
        cost = np.einsum("ij,ij->i", rel - s[:, None] * d, rel - s[:, None] * d)
        if oriented:
            gap = v - s[:, None] * w
            cost = cost + RAD_AS_M**2 * np.einsum("ij,ij->i", gap, gap)
        i = int(np.argmin(cost))
        return int(seg[i]), float(s[i])


def _log(r: np.ndarray) -> np.ndarray:
    """Rotation vectors of a stack of rotation matrices (``spatial.rotation_vector``,
    vectorised; near π the axis is approximate, which only affects the choice of the
    nearest point, not the error measured there)."""
    cos_t = np.clip((np.trace(r, axis1=1, axis2=2) - 1.0) / 2.0, -1.0, 1.0)
    theta = np.arccos(cos_t)
    w = np.stack([r[:, 2, 1] - r[:, 1, 2], r[:, 0, 2] - r[:, 2, 0], r[:, 1, 0] - r[:, 0, 1]], 1)
    sin_t = np.sin(theta)
    scale = np.where(sin_t > 1e-6, theta / (2.0 * np.where(sin_t > 1e-6, sin_t, 1.0)), 0.5)
    return scale[:, None] * w
