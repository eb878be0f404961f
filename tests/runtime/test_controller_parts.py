"""The simulated controller's parts (runtime/control/): an undone blend restores EVERY
field of the controller state and of both segments' progress — compared field by field
over ``dataclasses.fields``, so a field added later is covered without touching this
test — and the parts' records are typed."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
from irlc.runtime.control.approximation import ApproximatePositioning
from irlc.runtime.control.segment_run import RunMark, SegmentRun
from irlc.runtime.control.state import ControllerState
from irlc.runtime.plan.interpolator import JointPeaks, Segment
from irlc.runtime.run import run_file

# a blend the joint limits forbid (as test_blending's, mirrored: y → −y), so every
# bisection trial but the last is run and undone
SHORTENED = "\n".join(
    [
        "PROGRAM mirrored; ROBOT r := planar3;",
        "BEGIN R_SPEED := 300; R_ACC := 30;",
        "  MOVE PTP (122.26, -95.38, 0);",
        "  JOINTLIMIT (-180, -150, -0.5), (180, -30, 0.5);",
        "  R_APPROX := 1500;",
        "  MOVE LIN POSE(1250, -1250, 0, 0, 0, 0);",
        "  R_APPROX := 0;",
        "  MOVE LIN POSE(-1750, -1250, 0, 0, 0, 0);",
        "  JOINTLIMITEND;",
        "ENDPROGRAM",
    ]
)


def _same(a, b) -> bool:
    if isinstance(a, np.ndarray) or isinstance(b, np.ndarray):
        return a is not None and b is not None and np.array_equal(a, b)
    return a is b or a == b


def _differing(x, y, cls) -> list[str]:
    names = [f.name for f in dataclasses.fields(cls)]
    return [n for n in names if not _same(getattr(x, n), getattr(y, n))]


def test_an_undone_blend_restores_every_field(tmp_path: Path, monkeypatch):
    trials = []
    real = ApproximatePositioning._try_blend

    def checked(self, pending, run, overlap, *, keep):
        before = self.state.snapshot()
        marks = (pending.run.mark(), run.mark())
        samples = len(self.recorder)
        seen = {}
        restore = ControllerState.restore

        def spy(state, snap):  # the state the trial left, just before the undo
            seen["after_trial"] = state.snapshot()
            restore(state, snap)

        monkeypatch.setattr(ControllerState, "restore", spy)
        try:
            failure = real(self, pending, run, overlap, keep=keep)
        finally:
            monkeypatch.setattr(ControllerState, "restore", restore)
        if "after_trial" in seen:  # undone (failed, or a trial not kept)
            trials.append(
                (
                    _differing(seen["after_trial"], before, ControllerState),
                    _differing(self.state, before, ControllerState),
                    [
                        _differing(r.mark(), m, RunMark)
                        for r, m in zip((pending.run, run), marks, strict=True)
                    ],
                    len(self.recorder) - samples,
                    failure is not None,
                )
            )
        return failure

    monkeypatch.setattr(ApproximatePositioning, "_try_blend", checked)
    path = tmp_path / "sh.irl"
    path.write_text(SHORTENED, encoding="utf-8")
    run = run_file(path)
    assert run.status == "ok", run.error
    (entry,) = run.report["approximations"]
    assert entry["blended"] and entry["note"].startswith("shortened: the longer blend failed")
    assert any(failed for *_, failed in trials)  # a trial failed and was undone
    for changed, left, runs, extra_samples, _ in trials:
        assert {"q", "q_prev", "t", "cycles"} <= set(changed)  # the trial did move
        assert left == [], left  # … and every field is back
        assert runs == [[], []], runs
        assert extra_samples == 0


def test_state_snapshot_is_a_copy_and_restore_covers_every_field():
    state = ControllerState.at(np.zeros(3))
    snap = state.snapshot()
    values = {
        "q": np.ones(3),
        "q_prev": np.full(3, 2.0),
        "t": 1.5,
        "cycles": 7,
        "line": 12,
        "last_reference": np.full(3, 3.0),
        "segment_start": np.full(3, 4.0),
        "active_obstacles": frozenset({"box"}),
        "pending": object(),
    }
    assert set(values) == {f.name for f in dataclasses.fields(ControllerState)}
    for name, value in values.items():
        setattr(state, name, value)
    state.q_prev[:] = 9.0  # in place: the snapshot holds its own arrays
    assert not snap.q_prev.any()
    state.restore(snap)
    assert _differing(state, snap, ControllerState) == []
    state.q[:] = 5.0
    assert not snap.q.any()  # restore copies too


def test_segment_records_are_typed():
    """A PTP segment carries its joint peaks and the override factor it was planned with
    (no untyped ``info`` dict); a segment run takes its Δt and cycle options as inputs."""
    fields = {f.name: f.type for f in dataclasses.fields(Segment)}
    assert "info" not in fields and fields["peaks"] == "JointPeaks | None"
    assert fields["override"] == "float"
    assert {f.name for f in dataclasses.fields(JointPeaks)} == {"speed", "accel", "at_bounds"}
    assert list(SegmentRun.__init__.__code__.co_varnames[1:6]) == [
        "seg",
        "solver",
        "dt",
        "cycle_opts",
        "obstacles",
    ]
