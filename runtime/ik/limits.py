"""Joint limits as a box on the Newton step Δθ (seed eq. 42–45 and the acceleration form).

Within one IPO cycle, with ``θ_s`` the configuration at the start of the cycle,
``θ_k`` the current Newton iterate, ``Σ = θ_k − θ_s`` the increments already taken,
``Δt`` the IPO cycle and ``d = θ_s − θ_prev`` the previous cycle's displacement::

    lower = max( θmin − θ_k,  Δt·θ̇min − Σ,  Δt²·θ̈min + d − Σ,  brake_min − Σ )
    upper = min( θmax − θ_k,  Δt·θ̇max − Σ,  Δt²·θ̈max + d − Σ,  brake_max − Σ )

Every candidate is "a bound on the cycle displacement ``δ = Σ + Δθ``" minus ``Σ``, so
the bounds on ``δ`` are computed once per cycle (:meth:`JointBox.prepare`) and each
iteration only subtracts ``Σ`` (:meth:`JointBox.at`).

**Braking distance.** Near a position limit the acceleration box can become empty
(the joint arrives too fast to stop in time). The speed is therefore also bounded by
the discrete form of ``θ̇ ≤ √(2·a·(θmax − θ))``: with ``ε = a·Δt²`` the per-cycle
speed change available for braking (``a = −θ̈min`` towards ``θmax``), a displacement
``δ`` this cycle can still be braked to rest before ``θmax`` if
``δ²/(2ε) ≤ θmax − θ_s − δ``, i.e.::

    δ ≤ brake_max = −ε + √(ε² + 2ε·(θmax − θ_s))

(and symmetrically ``δ ≥ brake_min = ε' − √(ε'² + 2ε'·(θ_s − θmin))``, ``ε' = θ̈max·Δt²``).
If the previous cycle obeyed this bound, ``d ≤ √(2ε·(θmax − θ_s))`` and the new box
``[d − ε, brake_max]`` is never empty — recursive feasibility. It is evaluated as
``2R/(1 + √(1 + 2R/ε))`` (``R = θmax − θ_s``), the same number without the cancellation
of ``−ε + √(…)`` for large ``ε``: an infinite acceleration limit gives ``brake_max = R``,
the position bound, instead of 0.

Both sides are computed at once in a signed ``(2, n)`` layout (``[−lower; upper]``), so
the box is one ``min`` over the candidates.

**States the limits exclude.** If ``θ_s`` is outside the position limits, the previous
speed ``d/Δt`` is outside the speed limits, or the candidates leave an empty box, the
limits exclude the current state: :meth:`JointBox.prepare` raises
:class:`LimitViolationError` naming the joint, value and bound (never a silent clamp).
"""

from __future__ import annotations

import operator
from dataclasses import dataclass

import numpy as np
from irlc.robots.model import RobotModel
from irlc.runtime import units
from irlc.runtime.errors import RunFailure
from irlc.runtime.model.limit_check import TOLERANCE  # slack for "outside the limits" (rounding)
from irlc.runtime.model.naming import JointNaming, naming_or_default

POSITION, SPEED, ACCEL, BRAKING = 0, 1, 2, 3
SOURCE_NAMES = ("position", "speed", "accel", "braking")
_DERIVATIVE = (0, 1, 2, 0)  # unit of the bound reported for each source
_BIG = 1e30  # stands for "no bound" in the QP


def format_joint_value(model: RobotModel, joint: int, value_si: float, derivative: int) -> str:
    """``"60 deg"``, ``"25 deg/s"``, ``"500 mm"`` — program units via :mod:`units`."""
    kind = model.joints[joint].kind
    value = units.shown(units.joints_from_si([value_si], [kind])[0])
    return f"{value:.6g} {units.joint_unit_label(kind, derivative)}"


@dataclass(frozen=True)
class LimitViolation:
    """A limit that excludes the current state: joint index (0-based), what, the value."""

    joint: int
    source: str  # "position" | "speed" | "accel" | "braking" | "box"
    side: str  # "min" | "max"
    value: float  # SI (the state, e.g. θ_s,i or d_i/Δt)
    bound: float  # SI

    def describe(self, model: RobotModel, naming: JointNaming | None = None) -> str:
        name = naming_or_default(naming, model).label(self.joint)
        deriv = {"speed": 1, "accel": 2}.get(self.source, 0)
        bound = format_joint_value(model, self.joint, self.bound, deriv)
        value = format_joint_value(model, self.joint, self.value, deriv)
        return f"{name} {self.source} {self.side} {bound} (value {value})"


_CAUSE = {"position": "position_limit", "speed": "speed_limit"}


class LimitViolationError(RunFailure):
    """Raised when the limits exclude the current state; carries the violation."""

    def __init__(
        self, violation: LimitViolation, model: RobotModel, naming: JointNaming | None = None
    ):
        text = violation.describe(model, naming)
        super().__init__(
            f"joint limit excludes the current state: {text}",
            constraint=text,
            cause=_CAUSE.get(violation.source, "accel_limit"),
        )
        self.violation = violation


def intersect_limits(
    model: RobotModel,
    position: np.ndarray | None = None,
    speed: np.ndarray | None = None,
    accel: np.ndarray | None = None,
    naming: JointNaming | None = None,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Robot limits intersected with optional program limits (each ``(n, 2)`` SI arrays;
    ``NaN`` entries mean "no program bound"). Returns ``(position, speed, accel)``.
    Raises ``ValueError`` if a program bound has min > max."""
    out = []
    for own, prog, what in (
        (model.position_limits, position, "position"),
        (model.speed_limits, speed, "speed"),
        (model.accel_limits, accel, "accel"),
    ):
        lim = np.array(own, dtype=float)
        if prog is not None:
            prog = np.asarray(prog, dtype=float)
            lim[:, 0] = np.fmax(lim[:, 0], prog[:, 0])
            lim[:, 1] = np.fmin(lim[:, 1], prog[:, 1])
        bad = np.flatnonzero(lim[:, 0] > lim[:, 1])
        if bad.size:
            j = int(bad[0])
            name = naming_or_default(naming, model).label(j)
            raise ValueError(f"{what} limits of joint {name} are empty: {lim[j]}")
        out.append(lim)
    return out[0], out[1], out[2]


@dataclass(frozen=True)
class BoxData:
    """The per-limits constants of the box as packed, read-only data (what compiled
    kernels take; :attr:`_BoxConstants.data`). ``signed`` ``(4, 2, n)``, rows 0 / 1 the
    lower side negated / the upper side:

    * ``[0]`` ``[−θmin; θmax]``, ``[1]`` ``[−Δt·θ̇min; Δt·θ̇max]``,
      ``[2]`` ``[−Δt²·θ̈min; Δt²·θ̈max]`` (limits clipped to ±1e30);
    * ``[3]`` ``2/ε`` of the braking bound, ``ε = [Δt²·θ̈max; −Δt²·θ̈min]``.

    With ``s = signed``, ``θ_s`` and ``d = θ_s − θ_prev`` the candidates on the cycle
    displacement are ``s[0] ∓ θ_s``, ``s[1]``, ``s[2] ± d`` and the braking bound
    ``2R/(1 + √(1 + R·s[3]))`` (``R = max(s[0] ∓ θ_s, 0)``); ``accel_bounded`` False: the
    last two never bind. ``dtol``: the displacement slack of the speed check."""

    signed: np.ndarray
    accel_bounded: bool
    dtol: float


class _BoxConstants:
    """Everything of the box that depends only on the limits and Δt (cached).

    Signed layout ``(2, n)``: row 0 is the lower side negated, row 1 the upper side, so
    both sides are "upper bounds" and one ``min`` over the candidates gives the box."""

    def __init__(self, position, speed, accel, dt):
        self.inputs = (position, speed, accel)
        self.dt = dt
        pos = np.clip(np.asarray(position, dtype=float), -_BIG, _BIG)  # inf → 1e30
        spd = np.clip(np.asarray(speed, dtype=float), -_BIG, _BIG)
        acc = np.clip(np.asarray(accel, dtype=float), -_BIG, _BIG)
        self.limits = (pos, spd, acc)
        dt2 = dt * dt
        self.pmin, self.pmax = pos[:, 0].copy(), pos[:, 1].copy()
        self.signed_pos = _SIGN * pos.T  # [−θmin; θmax]
        self.signed_speed = _SIGN * dt * spd.T  # [−Δt·θ̇min; Δt·θ̇max]
        self.signed_accel = _SIGN * dt2 * acc.T  # [−Δt²·θ̈min; Δt²·θ̈max]
        # braking: ε = [Δt²·θ̈max; −Δt²·θ̈min] (the deceleration away from each limit);
        # the bound is 2R/(1 + √(1 + 2R/ε)) = −ε + √(ε² + 2εR) without cancellation
        eps = dt2 * np.abs(acc[:, ::-1].T)
        self.two_over_eps = 2.0 / np.maximum(eps, 1e-300)
        # no finite acceleration limit: the acceleration and braking candidates never bind
        # (braking = the position bound), so they are not computed per cycle
        self.accel_bounded = bool(np.any(np.abs(acc) < _BIG))
        # room R from which the braking bound is ≥ the speed bound V (so never the least
        # candidate): the largest δ braked in time solves δ²/2ε + δ = R, so R ≥ V + V²/2ε
        # (a relative margin of 1e-9 covers rounding; V ≤ 0: any R; V "no bound": none)
        speed_v = self.signed_speed
        with np.errstate(over="ignore", invalid="ignore"):  # (V = 1e30: replaced below)
            free = (speed_v + speed_v * speed_v * self.two_over_eps / 4.0) * (1.0 + 1e-9)
        self.brake_free = np.where(speed_v <= 0.0, -np.inf, np.where(speed_v < _BIG, free, np.inf))
        # displacement slack of the speed check (same as _check_state's, in δ units)
        self.dtol = TOLERANCE + 1e-9 * float(np.max(np.abs(spd))) * dt
        signed = np.stack((self.signed_pos, self.signed_speed, self.signed_accel,
                           self.two_over_eps))  # fmt: skip
        signed.flags.writeable = False
        self.data = BoxData(signed, self.accel_bounded, self.dtol)


_SIGN = np.array([[-1.0], [1.0]])


class BoxSnapshot:
    """One cycle's box, kept for reports (copies: safe to hold after the next cycle)."""

    def __init__(self, lower, upper, cand, limits):
        self.lower, self.upper = lower, upper  # bounds on the cycle displacement δ
        self._cand = cand  # (4, 2, n) signed candidates (see _BoxConstants)
        self.limits = limits  # (position, speed, accel) SI arrays

    def source(self, joint: int, upper_side: bool) -> int:
        """Which candidate (POSITION, SPEED, ACCEL, BRAKING) sets this bound."""
        return int(np.argmin(self._cand[:, int(upper_side), joint]))


def active_codes(delta: np.ndarray, bounds: np.ndarray, cand: np.ndarray) -> np.ndarray | None:
    """Which box bound (``bounds = [lower; upper]``, 2×n) each joint's cycle displacement
    ``δ`` touches, as one small int per joint: 0 inside, else ``1 + 2·source + side``
    (source POSITION…BRAKING, side 0 = min, 1 = max; a joint at both bounds counts as
    max), with the tolerance ``1e-10 + 1e-9·|δ_j|``. ``None`` when no joint is at a bound
    (the common cycle: the least distance to a bound, ``min(δ − lower, upper − δ)``,
    exceeds twice the largest tolerance, a margin far above rounding; else the per-joint
    comparisons decide)."""
    if all_inside(delta, bounds):
        return None
    lower, upper = bounds
    tol = 1e-10 + 1e-9 * np.abs(delta)
    lo = delta <= lower + tol
    hi = delta >= upper - tol
    if not (np.count_nonzero(lo) or np.count_nonzero(hi)):  # (cheaper than .any())
        return None
    src = np.argmin(cand, axis=0)  # (2, n): the candidate that sets each bound
    codes = np.zeros(delta.size, dtype=np.int8)
    codes[lo] = 1 + 2 * src[0][lo]
    codes[hi] = 2 + 2 * src[1][hi]
    return codes


def all_inside(delta: np.ndarray, bounds: np.ndarray) -> bool:
    """True when every ``δ_j`` is farther than twice the largest tolerance of
    :func:`active_codes` from both bounds (then no joint is at a bound)."""
    d = delta.tolist()
    above, below = np.subtract(delta, bounds).tolist()  # δ − lower, δ − upper
    return min(min(above), -max(below)) > 2e-10 + 2e-9 * max(max(d), -min(d))


def active_label(code: int) -> str:
    """``"speed max"`` for an :func:`active_codes` entry (≥ 1)."""
    source, side = divmod(int(code) - 1, 2)
    return f"{SOURCE_NAMES[source]} {('min', 'max')[side]}"


def encode_active(source: int, upper_side: bool) -> int:
    """The :func:`active_codes` entry of one bound."""
    return 1 + 2 * source + int(upper_side)


def _limit_value(limits: tuple, joint: int, source: int, upper_side: bool) -> float:
    position, speed, accel = limits
    table = (position, speed, accel, position)[source]
    return float(table[joint, 1 if upper_side else 0])


def describe_box_bound(
    model: RobotModel,
    snapshot: BoxSnapshot,
    joint: int,
    upper_side: bool,
    naming: JointNaming | None = None,
) -> str:
    """``"a11 (J11) position max 60 deg"``: the candidate that sets one bound of a box
    snapshot, the joint named by ``naming`` (default ``a1 … aN``)."""
    src = snapshot.source(joint, upper_side)
    limit = _limit_value(snapshot.limits, joint, src, upper_side)
    side = "max" if upper_side else "min"
    value = format_joint_value(model, joint, limit, _DERIVATIVE[src])
    return f"{naming_or_default(naming, model).label(joint)} {SOURCE_NAMES[src]} {side} {value}"


class JointBox:
    """Per-cycle joint box. Arrays are reused from cycle to cycle (hot path)."""

    def __init__(self, n: int):
        self.n = n
        self._cand = np.empty((4, 2, n))  # signed candidates: [−lower; upper] per source
        self.bounds = np.zeros((2, n))  # [lower; upper] bounds on the cycle displacement δ
        self.lower_d, self.upper_d = self.bounds
        self.displacement = np.zeros(n)  # d = θ_s − θ_prev of the last prepare (callers may
        # overwrite it: it is a fresh array every cycle)
        self._signed_d = np.empty((2, n))
        self._room = np.empty((2, n))
        self._near = np.empty((2, n), dtype=bool)
        self._brake_unbounded = False  # cand[BRAKING] holds "no bound" (see _braking)
        self._brake_pending = False  # … and its values are still to be computed
        self._excess = np.empty((2, n))  # d·sign − speed candidate (the speed check)
        # views made once (indexing costs ~0.2 µs a time): the four candidates, flat
        # position candidates and excess for the builtin reductions
        self._cands = tuple(self._cand)
        self._pos_flat = self._cand[POSITION].reshape(-1)
        self._excess_flat = self._excess.reshape(-1)
        self._limits: tuple = ()
        self._cache: _BoxConstants | None = None
        self.naming: JointNaming | None = None  # joint names of failure messages

    def prepare(
        self,
        model: RobotModel,
        q_start: np.ndarray,
        q_prev: np.ndarray,
        dt: float,
        position: np.ndarray,
        speed: np.ndarray,
        accel: np.ndarray,
    ) -> None:
        """Bounds on ``δ`` for this cycle; raises :class:`LimitViolationError`.
        Infinite limits are allowed (they never bind)."""
        c = self.constants(position, speed, accel, dt)
        cand, sd = self._cand, self._signed_d
        c_pos, c_speed, c_accel, brake = self._cands
        np.multiply(_SIGN, q_start, out=sd)
        np.subtract(c.signed_pos, sd, out=c_pos)  # [θ_s − θmin; θmax − θ_s]
        self.displacement = d = q_start - q_prev
        np.multiply(_SIGN, d, out=sd)
        np.subtract(sd, c_speed, out=self._excess)
        # (builtins on lists: cheaper than numpy reductions for a handful of numbers)
        if min(self._pos_flat.tolist()) < -TOLERANCE or max(self._excess_flat.tolist()) > c.dtol:
            self._check_state(model, q_start, d, dt, c.limits[0], c.limits[1])
        if c.accel_bounded:  # (otherwise both candidates stay at "no bound", set once)
            np.add(c.signed_accel, sd, out=c_accel)
            self._braking(c, c_pos, brake)
        # [−lower; upper] (over all four candidates one reduction: min is exact, any order)
        bound = np.minimum.reduce(cand, axis=0) if c.accel_bounded else np.minimum(c_pos, c_speed)
        neg_lower, upper_list = bound.tolist()
        lower, upper = bound
        np.negative(lower, out=lower)
        self.bounds = bound  # [lower; upper], a fresh array every cycle
        self.lower_d, self.upper_d = lower, upper
        self._limits = c.limits
        if min(map(operator.add, upper_list, neg_lower)) < 0.0:  # upper − lower, exactly
            self._check_nonempty(model, q_start, d, dt)

    @property
    def cand(self) -> np.ndarray:
        """This cycle's signed candidates ``(4, 2, n)``, ``[−lower; upper]`` per source
        (the braking ones computed here if :meth:`_braking` could skip them)."""
        if self._brake_pending:
            self._brake_pending = False
            self._brake_values(self._cache, self._cand[POSITION], self._cand[BRAKING])
        return self._cand

    def _braking(self, c: _BoxConstants, c_pos: np.ndarray, brake: np.ndarray) -> None:
        """The braking candidates. When every room ``R`` reaches
        :attr:`_BoxConstants.brake_free` the braking bound is at least the speed bound and
        never the least candidate: the box's minimum then reads "no bound" there (the
        same box), and the values are computed only if :attr:`cand` is read."""
        if not np.count_nonzero(np.less(c_pos, c.brake_free, out=self._near)):
            if not self._brake_unbounded:
                brake.fill(_BIG)
                self._brake_unbounded = True
            self._brake_pending = True
            return
        self._brake_values(c, c_pos, brake)

    def _brake_values(self, c: _BoxConstants, c_pos: np.ndarray, brake: np.ndarray) -> None:
        """``brake = 2R/(1 + √(1 + 2R/ε))``, ``R = max(c_pos, 0)`` (no cancellation)."""
        self._brake_unbounded = self._brake_pending = False
        room = self._room
        np.maximum(c_pos, 0.0, out=room)  # braking: R = room to the limit ≥ 0
        np.multiply(room, c.two_over_eps, out=brake)
        brake += 1.0
        np.sqrt(brake, out=brake)
        brake += 1.0
        np.divide(room, brake, out=brake)
        brake += brake

    def active_codes(self, delta: np.ndarray) -> np.ndarray | None:
        """:func:`active_codes` of this cycle's box; the candidates (:attr:`cand`) are read
        only when some joint is near a bound."""
        if all_inside(delta, self.bounds):
            return None
        return active_codes(delta, self.bounds, self.cand)

    def constants(self, position, speed, accel, dt) -> _BoxConstants:
        """The per-limits constants, rebuilt only when the limit arrays or Δt change
        (the same arrays are passed cycle after cycle while an option is on)."""
        c = self._cache
        if (
            c is not None
            and c.inputs[0] is position
            and c.inputs[1] is speed
            and c.inputs[2] is accel
            and c.dt == dt
        ):
            return c
        c = self._cache = _BoxConstants(position, speed, accel, dt)
        self._cand[SPEED] = c.signed_speed
        self._brake_unbounded = not c.accel_bounded  # (set just below)
        self._brake_pending = False
        if not c.accel_bounded:
            self._cand[ACCEL] = _BIG
            self._cand[BRAKING] = _BIG
        return c

    def at(self, sigma: np.ndarray, lower: np.ndarray, upper: np.ndarray) -> None:
        """Box on Δθ at an iterate with increments ``sigma`` (written into lower/upper)."""
        np.subtract(self.lower_d, sigma, out=lower)
        np.subtract(self.upper_d, sigma, out=upper)

    def limit_value(self, joint: int, source: int, upper_side: bool) -> float:
        """The SI limit behind a candidate bound (braking: the position limit)."""
        return _limit_value(self._limits, joint, source, upper_side)

    def snapshot(self) -> BoxSnapshot:
        """This cycle's box for later reports (candidates copied)."""
        return BoxSnapshot(self.lower_d, self.upper_d, self.cand.copy(), self._limits)

    # --- helpers -----------------------------------------------------------------
    def _check_state(self, model, q_start, d, dt, position, speed) -> None:
        v = d / dt
        vtol = TOLERANCE / dt + 1e-9 * np.max(np.abs(speed), axis=1)
        bad_q = (q_start < position[:, 0] - TOLERANCE) | (q_start > position[:, 1] + TOLERANCE)
        bad_v = (v < speed[:, 0] - vtol) | (v > speed[:, 1] + vtol)
        if not (bad_q.any() or bad_v.any()):
            return
        checks = (
            ("position", "min", q_start, position[:, 0], q_start < position[:, 0] - TOLERANCE),
            ("position", "max", q_start, position[:, 1], q_start > position[:, 1] + TOLERANCE),
            ("speed", "min", v, speed[:, 0], v < speed[:, 0] - vtol),
            ("speed", "max", v, speed[:, 1], v > speed[:, 1] + vtol),
        )
        for source, side, value, bound, bad in checks:
            if bad.any():
                j = int(np.flatnonzero(bad)[0])
                violation = LimitViolation(j, source, side, float(value[j]), float(bound[j]))
                raise LimitViolationError(violation, model, self.naming)

    def _check_nonempty(self, model, q_start, d, dt) -> None:
        gap = self.lower_d - self.upper_d
        bad = np.flatnonzero(gap > 0.0)
        for j in bad:
            if gap[j] <= TOLERANCE:  # rounding: collapse to the midpoint
                mid = 0.5 * (self.lower_d[j] + self.upper_d[j])
                self.lower_d[j] = self.upper_d[j] = mid
                continue
            # name the bound the state cannot meet: the upper one unless it is the
            # acceleration bound (then the joint is decelerating too hard: the lower one)
            snap = self.snapshot()
            side = "max" if snap.source(int(j), True) != ACCEL else "min"
            code = snap.source(int(j), side == "max")
            value = q_start[j] if code == POSITION else d[j] / dt
            limit = self.limit_value(int(j), code, side == "max")
            violation = LimitViolation(int(j), SOURCE_NAMES[code], side, float(value), float(limit))
            raise LimitViolationError(violation, model, self.naming)
