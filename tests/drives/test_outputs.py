"""What the motion executor wires: per-axis summary in program units, trace columns, ideal
joints made visible, clear errors, no NaN."""

from __future__ import annotations

import numpy as np
import pytest
from irlc.runtime import units
from irlc.runtime.drives import (
    DriveInputError,
    report_axes,
    simulate_drives,
    trace_columns,
)
from irlc.runtime.model.dynamics import MissingInertialData

from .drive_models import dc_drives, planar

TIMES = np.linspace(0.0, 0.3, 31)
PROF = (TIMES / TIMES[-1]) ** 2 * (3 - 2 * TIMES / TIMES[-1])


def test_report_and_trace_in_program_units():
    model = planar(
        2, mass=0.5, prismatic=(1,), gravity=(0.0, 0.0, -9.81), drives=dc_drives(2, 20.0)
    )
    q = np.column_stack([0.2 * PROF, 0.01 * PROF])
    run = simulate_drives(model, TIMES, q, level="coupled", hold=0.2)
    rows = report_axes(run, model)
    assert rows[0]["joint"] == "a1" and "max_following_error_deg" in rows[0]
    assert "max_following_error_mm" in rows[1] and "peak_force_N" in rows[1]
    assert rows[0]["max_following_error_deg"] == pytest.approx(
        run.axes[0].max_following_error / units.DEG
    )
    assert rows[1]["max_following_error_mm"] == pytest.approx(
        run.axes[1].max_following_error / units.MM
    )
    cols = trace_columns(run, model, TIMES)
    assert set(cols) == {"a1_cmd_deg", "a1_current_A", "a2_cmd_mm", "a2_current_A"}
    assert cols["a1_cmd_deg"][-1] == pytest.approx(0.2 / units.DEG)
    assert cols["a2_cmd_mm"][-1] == pytest.approx(10.0)
    assert np.max(np.abs(cols["a1_current_A"])) > 0.1
    for a in run.axes:
        assert a.drive == "dc" and a.could_follow and a.settling_time is not None
    arrays = (run.q_actual, run.qd_actual, run.current, run.torque, run.voltage)
    assert all(np.all(np.isfinite(x)) for x in arrays)


def test_joints_without_drive_data_run_ideal_and_say_so():
    drives = dc_drives(1, 30.0)
    drives["axes"] = [1]
    model = planar(2, mass=0.5, drives=drives)
    q = np.column_stack([0.2 * PROF, -0.3 * PROF])
    run = simulate_drives(model, TIMES, q, level="coupled", hold=0.1)
    assert list(run.driven) == [True, False]
    assert [a.drive for a in run.axes] == ["dc", "ideal"]
    assert np.allclose(run.q_actual[:, 1], run.q_cmd_interp[:, 1])
    assert any("run ideal: a2" in note for note in run.notes)
    assert np.max(np.abs(run.torque[:, 1])) > 0.0  # the torque its motion needs


def test_robot_without_drives_runs_ideal():
    model = planar(2)
    run = simulate_drives(model, TIMES, np.column_stack([PROF, PROF]), level="coupled")
    assert not run.driven.any() and run.could_follow
    assert any("no [drives]" in note for note in run.notes)


def test_could_not_follow_and_tolerance():
    model = planar(1, mass=0.5, gravity=(0, 0, 0), drives=dc_drives(1, 30.0))
    q = (0.3 * PROF)[:, None]
    ok = simulate_drives(model, TIMES, q, level="decoupled")
    assert ok.could_follow
    strict = simulate_drives(model, TIMES, q, level="decoupled", tolerance=1e-5)
    assert not strict.could_follow and not strict.axes[0].could_follow


def test_record_ipo_decimates():
    model = planar(1, mass=0.5, gravity=(0, 0, 0), drives=dc_drives(1, 30.0))
    run = simulate_drives(
        model, TIMES, (0.1 * PROF)[:, None], level="decoupled", hold=0.1, record="ipo"
    )
    assert np.allclose(run.t[: len(TIMES)], TIMES, atol=run.step)
    assert len(run.t) == len(TIMES) + 10


def test_bad_input_is_a_clear_error():
    model = planar(1, drives=dc_drives(1))
    with pytest.raises(DriveInputError, match="unknown drive level"):
        simulate_drives(model, TIMES, PROF[:, None], level="fast")
    with pytest.raises(DriveInputError, match="no NaN"):
        simulate_drives(model, TIMES, np.full((len(TIMES), 1), np.nan), level="decoupled")
    with pytest.raises(DriveInputError, match="expected times"):
        simulate_drives(model, TIMES, PROF[:, None, None], level="decoupled")
    bare = planar(1, drives=dc_drives(1))
    bare = type(bare)(bare.name, bare.joints, extra=bare.extra)
    message = "has no inertial data; --drives coupled needs it"
    with pytest.raises(MissingInertialData, match=message):
        simulate_drives(bare, TIMES, PROF[:, None], level="coupled")


def test_trapezoid_setpoint_is_the_slave_profile():
    """Linear with parabolic blends of width T_pr: velocity piecewise linear, lag T_pr/2."""
    from irlc.runtime.drives import setpoint

    times = np.array([0.0, 0.4, 1.0])
    q = np.array([[0.0], [0.4], [0.4]])  # 1 rad/s, then stop
    grid = np.arange(0.0, 1.2, 1e-3)
    s = setpoint.trapezoid(times, q, grid, 0.04)[:, 0]
    v = np.gradient(s, grid)
    assert v[(grid > 0.05) & (grid < 0.4)] == pytest.approx(1.0, abs=1e-6)
    blend = (grid > 0.4) & (grid < 0.44)  # constant deceleration 1/T_pr = 25 rad/s²
    assert np.gradient(v, grid)[blend][2:-2] == pytest.approx(-25.0, rel=1e-3)
    assert s[-1] == pytest.approx(0.4)
    assert np.interp(0.3, grid, s) == pytest.approx(0.3 - 0.02, abs=1e-9)  # lag T_pr/2


def test_decoupled_without_inertials_needs_load_inertia():
    drives = dc_drives(1, 30.0)
    model = planar(1, drives=drives)
    bare = type(model)(model.name, model.joints, extra=model.extra, source="<bare>")
    message = "decoupled needs it or \\[drives\\] load_inertia"
    with pytest.raises(MissingInertialData, match=message):
        simulate_drives(bare, TIMES, (0.1 * PROF)[:, None], level="decoupled")
    drives = dict(drives, load_inertia=0.5)
    bare = type(model)(model.name, model.joints, extra={"drives": drives}, source="<bare>")
    run = simulate_drives(bare, TIMES, (0.1 * PROF)[:, None], level="decoupled")
    assert run.could_follow and run.axes[0].peak_current > 0.0
