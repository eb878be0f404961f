"""The ROS-like trajectory export: structure, SI units, consistency with the trace."""

from __future__ import annotations

import json
import math

import numpy as np
from irlc.export import sample_derivatives, write_trajectory
from irlc.run_data import run_data

from .tool_fixtures import AMPL, DT, FREQ, make_run


def _load(path):
    return json.loads(path.read_text())


def test_document_structure(tmp_path, demo_run):
    path = write_trajectory(demo_run, tmp_path / "traj.json")
    doc = _load(path)
    assert doc["joint_names"] == ["J1", "J2", "J3", "J4"]  # the robot's own names (ROS)
    assert doc["program_joint_names"] == ["a1", "a2", "a3", "a4"]
    assert doc["units"] == {"revolute": "rad", "prismatic": "m", "time": "s"}
    assert doc["joint_kinds"] == ["revolute", "revolute", "prismatic", "revolute"]
    assert len(doc["points"]) == len(demo_run.times)
    for p in doc["points"]:
        assert set(p) == {"positions", "velocities", "accelerations", "time_from_start"}
        assert len(p["positions"]) == len(p["velocities"]) == len(p["accelerations"]) == 4
        assert 0 <= p["time_from_start"]["nanosec"] < 1_000_000_000
    last = doc["points"][-1]["time_from_start"]
    assert last["sec"] + last["nanosec"] * 1e-9 == 3.0


def test_the_document_says_whether_it_is_finished_and_what_it_holds(tmp_path, capsys):
    """Regression (adversarial probe): a failed run's export ended mid-motion with nothing
    to say so, and a drive run's was the simulated actual motion, unlabelled."""
    from irlc.cli import main

    assert _load(write_trajectory(make_run(), tmp_path / "a.json"))["motion"] == "commanded"
    lagging = _load(write_trajectory(make_run(drives=True), tmp_path / "b.json"))
    assert (lagging["motion"], lagging["drives"]) == ("actual", "decoupled")
    program = tmp_path / "p.irl"
    program.write_text(
        "PROGRAM p;\nROBOT r := planar3;\nVAR REAL: x;\nBEGIN\n  MOVE PTP (10, 80, -80);\n"
        "  x := -1;\n  WAIT x SEC;\nENDPROGRAM\n",
        encoding="utf-8",
    )
    out = tmp_path / "e.json"
    assert main(["run", str(program), "-q", "--export-trajectory", str(out)]) == 2
    doc = _load(out)
    assert (doc["status"], doc["partial"], doc["motion"]) == ("failed", True, "commanded")
    program.write_text(program.read_text().replace("x := -1", "x := 0.1"), encoding="utf-8")
    assert main(["run", str(program), "-q", "--export-trajectory", str(out)]) == 0
    assert (_load(out)["status"], _load(out)["partial"]) == ("ok", False)


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


def test_velocities_are_derivatives_at_the_sample_times(tmp_path, demo_run):
    """Against the closed form q = A·sin(ωt) of the fixture (not against the trace's speed
    columns: those are backward differences in real runs, half a cycle late)."""
    doc = _load(write_trajectory(demo_run, tmp_path / "t.json"))
    t = np.array([p["time_from_start"]["sec"] + 1e-9 * p["time_from_start"]["nanosec"]
                  for p in doc["points"]])  # fmt: skip
    qd = np.array([p["velocities"] for p in doc["points"]])
    qdd = np.array([p["accelerations"] for p in doc["points"]])
    scale = np.array([math.pi / 180, math.pi / 180, 1e-3, math.pi / 180])
    a, w = AMPL * scale, FREQ
    arg = np.outer(t, w)
    h = DT
    # central differences: error <= h²/6·Aω³; one-sided second order at the ends <= h²/3·Aω³
    bound_v = h**2 / 3 * np.max(a * w**3) + 2e-9
    assert np.max(np.abs(qd - a * w * np.cos(arg))) < bound_v
    # 3-point second difference inside: <= h²/12·Aω⁴; the ends repeat the neighbour: <= h·Aω³
    true_a = -a * w**2 * np.sin(arg)
    assert np.max(np.abs(qdd[1:-1] - true_a[1:-1])) < h**2 / 12 * np.max(a * w**4) + 1e-7
    assert np.max(np.abs(qdd[[0, -1]] - true_a[[0, -1]])) < h * np.max(a * w**3) * 1.01


def test_trajectory_starting_and_ending_at_rest_says_so():
    """Regression (acceptance): a stop was exported with the last cycle's mean speed."""
    t = np.arange(0.0, 1.0 + 1e-9, 0.01)
    q = np.where(t < 0.5, 2 * t**2, 1 - 2 * (1 - t) ** 2)[:, None]  # rest → rest, |q̈| = 4
    qd, qdd = sample_derivatives(q, t)
    assert abs(qd[0, 0]) < 1e-12 and abs(qd[-1, 0]) < 1e-12
    assert np.allclose(qd[1:-1, 0], np.where(t < 0.5, 4 * t, 4 * (1 - t))[1:-1], atol=0.02)
    assert abs(qdd[0, 0] - 4) < 1e-9 and abs(qdd[-1, 0] + 4) < 1e-9


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
