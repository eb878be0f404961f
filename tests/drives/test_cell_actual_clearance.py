"""A cell's drive run is judged on the actual motion: the clearance between robots measured
from the drives' actual joints (runtime/outputs/actual_clearance.py).

The case: an IRb-6 (fast drives, position loop K_v = 30 1/s) swings its forearm with A1 over
the place of an AS arm's upper arm (slow drives, K_v = 5 1/s), which tilts out of the way in
the same group move. The set points keep the two apart by ≈ 10 mm; the AS arm's drives lag
≈ 0.2 s behind, the IRb-6's ≈ 0.03 s, so the actual forearm reaches the actual upper arm
first. Every distance is checked against an independent computation: the capsules of the
robot files, placed by the robots' own forward kinematics of the trace's joint columns,
and their distance pair by pair by ``closest_segment_segment``."""

from __future__ import annotations

import numpy as np
import pytest
from irlc.lang import compile_source
from irlc.robots import load_robot
from irlc.runtime.model.distance import closest_segment_segment, robot_segments
from irlc.runtime.model.kinematics import Kinematics
from irlc.runtime.run import run_code

PROGRAM = """PROGRAM lag;
ROBOT a := irb6;
ROBOT b := as6 AT (0, 500, 0, 90, 0, 0);
BEGIN
  {setting}
  MOVE b PTP (0, {tilt}, 0, 0, 0, 0) AND a PTP (0, 0, 0, 0, 0);
  WRITELN('after the move');
  WAIT 0.2 SEC;
ENDPROGRAM
"""
SEED = [60.0, 0, 0, 0, 0] + [0.0] * 6  # the IRb-6's forearm 60 deg before the AS arm


def _run(tilt: float = -69.0, setting: str = "", **options):
    text = PROGRAM.format(tilt=tilt, setting=setting)
    result = compile_source(text, "lag.irl", resolve_robot=load_robot)
    assert result.ok, [d.header() for d in result.diagnostics]
    return run_code(result.code, seed_config=SEED, drives="decoupled", **options)


def _between(run, commanded: bool = False) -> np.ndarray:
    """Per trace row the least distance (mm) between the two robots' capsules, from the
    trace's joint columns (``a_a1_deg`` …: the actual joints with drives) or, ``commanded``,
    the recorded set points, each capsule placed by its robot's own kinematics, pair by
    pair."""
    cols = run.trace_columns
    ends = []
    for name in ("a", "b"):
        robot = run.robots[name]
        kin = Kinematics(robot.model)
        seg = robot_segments(kin)
        joints = [f"{name}_{j}_deg" for j in robot.joint_names]
        q = np.radians(run.trace[:, [cols.index(c) for c in joints]])
        if commanded:
            q = robot.recorded.q[: len(q)]
        ends.append([(seg.world(kin, kin.link_frames(row)), seg.radius) for row in q])
    out = []
    for (ea, ra), (eb, rb) in zip(ends[0], ends[1], strict=True):
        best = np.inf
        for i in range(len(ra)):
            for j in range(len(rb)):
                _, _, p, q = closest_segment_segment(ea[0][i], ea[1][i], eb[0][j], eb[1][j])
                best = min(best, float(np.linalg.norm(p - q)) - ra[i] - rb[j])
        out.append(best * 1e3)
    return np.array(out)


@pytest.fixture(scope="module")
def allowed():
    return _run(allow_collisions=True)


def test_the_set_points_keep_apart_the_lagging_drives_collide_and_the_run_stops_there():
    run = _run()
    err = run.error
    assert run.status == "failed" and err.cause == "clearance" and err.line == 6
    assert err.message.startswith("the actual motion (simulated drives): a link 5 and b link 3 "
                                  "collide: they are ")  # fmt: skip
    assert "slow down (the drives lag the set points)" in err.message
    assert "allow collisions (--allow-collisions)" in err.message
    assert err.details["actual"] is True and err.details["required_mm"] == 0.0
    assert (err.details["robot_a"], err.details["robot_b"]) == ("a", "b")
    # the run stops at the failure (issue 24): trace, output, statements, duration
    t = run.trace[:, 0]
    assert t[-1] == pytest.approx(err.time_s) and run.report["duration_s"] == pytest.approx(t[-1])
    assert run.output == [] and run.report["statements"][-1]["stop"] == "failed"
    assert len(run.report["statements"]) == 1
    # the failing sample is the first whose actual capsules penetrate (independent distances)
    actual = _between(run)
    assert actual[-1] < 0.0 <= actual[:-1].min()
    assert actual[-1] == pytest.approx(err.details["distance_mm"], abs=1e-6)
    assert run.trace[-1, run.trace_columns.index("clearance_mm")] == pytest.approx(actual[-1])
    # the set points up to there were clear (they were judged during the run)
    assert _between(run, commanded=True).min() > 0.0
    for name in ("a", "b"):  # a violation of both robots' verdicts; their drive rows end there
        entry = next(e for e in run.report["robots"] if e["name"] == name)
        assert entry["verdict"]["could_follow"] is False
        assert [v["criterion"] for v in entry["verdict"]["violations"]] == ["clearance"]
        assert run.robots[name].drive.t[-1] <= err.time_s + 1e-9


def test_allowed_collisions_report_the_actual_clearance_and_the_set_points_under_ideal(allowed):
    run = allowed
    assert run.ok, run.error
    actual, commanded = _between(run), _between(run, commanded=True)
    assert commanded.min() == pytest.approx(10.0, abs=8.0)  # the set points: a few mm apart
    assert actual.min() < -10.0  # the actual motion: well inside
    between = next(p for p in run.report["clearance"]["pairs"] if p["robot_a"] != p["robot_b"])
    ideal = next(p for p in run.report["ideal"]["clearance"]["pairs"]
                 if p["robot_a"] != p["robot_b"])  # fmt: skip
    assert between["min_distance_mm"] == pytest.approx(actual.min(), abs=1e-6)
    assert ideal["min_distance_mm"] == pytest.approx(commanded.min(), abs=1e-6)
    k = int(np.argmin(actual))
    assert between["at_time_s"] == pytest.approx(run.trace[k, 0])
    assert (between["link_a"], between["link_b"]) == (5, 3)
    col = run.trace[:, run.trace_columns.index("clearance_mm")]
    assert np.all(col <= actual + 1e-6)  # the least over all pairs, own ones included
    for entry in run.report["robots"]:
        assert entry["verdict"]["could_follow"] and entry["verdict"]["criteria"][
            "clearance_tolerance_mm"] == pytest.approx(0.1)  # fmt: skip
    assert run.report["ideal"]["max_path_error_mm"] == 0.0  # PTP: no path
    assert any(w.startswith("collisions allowed (--allow-collisions): the actual motion "
                            "(simulated drives) brings a link 5 and b link 3") for w in
               run.report["warnings"])  # fmt: skip


def test_r_clearance_kept_by_the_set_points_but_not_by_the_drives_fails():
    """At a tilt of −74° the set points keep ≈ 44 mm, the actual motion ≈ 12 mm: a
    R_CLEARANCE of 30 mm is kept by the set points and fails on the actual motion."""
    run = _run(tilt=-74.0, setting="R_CLEARANCE := 30;")
    err = run.error
    assert run.status == "failed" and err.cause == "clearance", err
    assert "closer than R_CLEARANCE 30 mm by more than 0.1 mm" in err.message
    assert "the set points keep it, the lagging drives do not" in err.message
    assert err.details["required_mm"] == 30.0 and err.details["actual"] is True
    actual = _between(run)
    assert actual[-1] < 30.0 - 0.1 <= actual[:-1].min()
    assert _between(run, commanded=True).min() >= 30.0 - 0.1


def test_ideal_drives_runs_are_unchanged():
    """Without drives the clearance is the set points' and nothing is added."""
    text = PROGRAM.format(tilt=-69.0, setting="")
    code = compile_source(text, "lag.irl", resolve_robot=load_robot).code
    run = run_code(code, seed_config=SEED)
    assert run.ok and "ideal" not in run.report
    assert run.report["clearance"]["pairs"][1]["min_distance_mm"] == pytest.approx(
        _between(run).min(), abs=1e-6
    )
