"""The ROS-like trajectory export: structure, SI units, consistency with the trace."""

from __future__ import annotations

import json
import math

import numpy as np

from irlc.export import run_data, write_trajectory

from .tool_fixtures import make_run


def _load(path):
    return json.loads(path.read_text())


def test_document_structure(tmp_path, demo_run):
    path = write_trajectory(demo_run, tmp_path / "traj.json")
    doc = _load(path)
    assert doc["joint_names"] == ["a1", "a2", "a3", "a4"]
    assert doc["joint_kinds"] == ["revolute", "revolute", "prismatic", "revolute"]
    assert len(doc["points"]) == len(demo_run.times)
    for p in doc["points"]:
        assert set(p) == {"positions", "velocities", "accelerations", "time_from_start"}
        assert len(p["positions"]) == len(p["velocities"]) == len(p["accelerations"]) == 4
        assert 0 <= p["time_from_start"]["nanosec"] < 1_000_000_000
    last = doc["points"][-1]["time_from_start"]
    assert last["sec"] + last["nanosec"] * 1e-9 == 3.0


def test_positions_are_si_from_the_trace_in_program_units(tmp_path, demo_run):
    """Convert the trace columns (deg, mm) independently and compare."""
    doc = _load(write_trajectory(demo_run, tmp_path / "t.json"))
    cols = demo_run.trace_columns
    table = demo_run.trace
    expected = np.column_stack(
        [
            np.radians(table[:, cols.index("a1_deg")]),
            np.radians(table[:, cols.index("a2_deg")]),
            table[:, cols.index("a3_mm")] / 1000.0,
            np.radians(table[:, cols.index("a4_deg")]),
        ]
    )
    got = np.array([p["positions"] for p in doc["points"]])
    assert np.max(np.abs(got - expected)) < 1e-8
    speeds = np.array([p["velocities"] for p in doc["points"]])
    assert math.isclose(speeds[0, 2], table[0, cols.index("a3_speed_mm_s")] / 1000.0, rel_tol=1e-9)


def test_velocities_are_finite_differences_of_positions(tmp_path, demo_run):
    doc = _load(write_trajectory(demo_run, tmp_path / "t.json"))
    t = np.array([p["time_from_start"]["sec"] + 1e-9 * p["time_from_start"]["nanosec"]
                  for p in doc["points"]])  # fmt: skip
    q = np.array([p["positions"] for p in doc["points"]])
    qd = np.array([p["velocities"] for p in doc["points"]])
    qdd = np.array([p["accelerations"] for p in doc["points"]])
    fd = (q[2:] - q[:-2]) / (t[2:] - t[:-2])[:, None]  # central differences
    # central-difference error ≤ h²/6·max|q'''| (A ω³ ≤ 0.35 rad/s³ here) + rounding
    assert np.max(np.abs(fd - qd[1:-1])) < 1e-4
    fdd = (qd[2:] - qd[:-2]) / (t[2:] - t[:-2])[:, None]
    assert np.max(np.abs(fdd - qdd[1:-1])) < 1e-3


def test_derivatives_without_speed_columns_come_from_positions(tmp_path):
    run = make_run()
    keep = [i for i, c in enumerate(run.trace_columns) if "_speed_" not in c and "_accel_" not in c]
    run.trace_columns = [run.trace_columns[i] for i in keep]
    run.trace = run.trace[:, keep]
    d = run_data(run)
    assert np.allclose(d.qd, np.gradient(d.q, d.times, axis=0))
    assert np.allclose(d.qdd, np.gradient(d.qd, d.times, axis=0))


def test_export_is_deterministic_and_atomic(tmp_path, demo_run):
    a = write_trajectory(demo_run, tmp_path / "a.json").read_bytes()
    b = write_trajectory(make_run(), tmp_path / "b.json").read_bytes()
    assert a == b
    assert [p.name for p in tmp_path.iterdir()] == sorted(["a.json", "b.json"]) or len(
        list(tmp_path.iterdir())
    ) == 2
    assert b"-0.0," not in a


def test_run_from_trace_only(tmp_path, demo_run):
    """A run with only the trace (no q array, no model) still exports in SI."""
    demo_run.q = None
    demo_run.model = None
    demo_run.tcp = None
    demo_run.report["robot"] = ""
    d = run_data(demo_run)
    assert d.joint_kinds[2] == "prismatic"
    assert np.isclose(d.q[-1, 2], 150.0 * math.sin(0.4 * 3.0) / 1000.0)
    assert d.tcp is not None  # from x_mm, y_mm, z_mm
