"""The report's limit activity (``limit_active_s``, ``limit_activity``) from the per-cycle
activity codes equals the activity derived independently from each cycle's joint box:
a joint is active when its cycle displacement δ = θ_end − θ_start touches a box bound, the
source being the candidate (position, speed, accel, braking) that sets that bound, and it
counts the cycle's Δt (regression for the recorder keeping codes instead of labels)."""

from __future__ import annotations

from pathlib import Path

import pytest
from irlc.runtime.control import ptp_activity
from irlc.runtime.ik.limits import SOURCE_NAMES
from irlc.runtime.ik.newton import InverseTransformation
from irlc.runtime.run import run_file

PROGRAMS = Path(__file__).resolve().parents[2] / "programs"


def _box_activity(delta, lower, upper, cand) -> dict[int, str]:
    """Joint → "source side" straight from the box (the definition, one joint at a time)."""
    out = {}
    for j in range(delta.size):
        tol = 1e-10 + 1e-9 * abs(delta[j])
        hits = (delta[j] <= lower[j] + tol, delta[j] >= upper[j] - tol)
        for upper_side, hit in zip((False, True), hits, strict=True):
            if hit:
                source = min(range(4), key=lambda s: cand[s, int(upper_side), j])
                out[j] = f"{SOURCE_NAMES[source]} {'max' if upper_side else 'min'}"
    return out


@pytest.mark.parametrize("program", ["square_speed.irl", "square_limits.irl"])
def test_report_limit_activity_matches_the_box_of_every_cycle(program, monkeypatch):
    expected: dict[tuple[int, str], float] = {}

    def count(activity: dict[int, str] | None, dt: float) -> None:
        for j, label in (activity or {}).items():
            expected[(j, label)] = expected.get((j, label), 0.0) + dt

    step, at_bounds = InverseTransformation.step, ptp_activity.at_bounds

    def observed_step(self, q_start, q_prev, target, dt, options=None):
        res = step(self, q_start, q_prev, target, dt, options)
        snap = res._box  # kept when a bound may bind; else the live box of this cycle
        if snap is not None:
            box = (snap.lower, snap.upper, snap._cand)
        elif self.accelerated:  # the compiled path's own buffers
            box = (self._accel.bounds[0], self._accel.bounds[1], self._accel.cand)
        else:
            box = (self.box.lower_d, self.box.upper_d, self.box.cand)
        count(_box_activity(res.q - q_start, *box), dt)
        return res

    def observed_ptp(seg, k, dt):
        activity = at_bounds(seg, k, dt)
        count(activity, dt)
        return activity

    monkeypatch.setattr(InverseTransformation, "step", observed_step)
    monkeypatch.setattr(ptp_activity, "at_bounds", observed_ptp)
    run = run_file(PROGRAMS / program)
    assert run.status == "ok", run.error
    assert expected, "the program should touch some limit"
    for j, joint in enumerate(run.report["joints"]):
        mine = {label: t for (jj, label), t in expected.items() if jj == j}
        assert joint["limit_active_s"] == pytest.approx(sum(mine.values()), abs=1e-6)
        assert joint["limit_activity"].keys() == mine.keys()
        for label, t in mine.items():
            assert joint["limit_activity"][label] == pytest.approx(t, abs=1e-6)
