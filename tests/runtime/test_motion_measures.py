"""The trace's ``kinetic_energy_j`` and ``mvr`` columns and the report's ``kinetic_energy`` and
``mvr`` (runtime/outputs/measures.py), each against a second computation:

* the kinetic energy against ``½ θ̇ᵀ M(θ) θ̇`` with ``M`` from the composite-rigid-body
  algorithm of ``Dynamics.mass_matrix`` (the column uses a velocity recursion), and against
  per-link sums ``Σ ½ m_i |v_i|² + ½ ω_iᵀ I_i ω_i`` with each link's velocities from central
  differences of its own frames (forward kinematics at ``θ ± h θ̇``) — both from the trace's
  own joint and speed columns, converted from program units;
* the velocity ratio against ``‖J θ̇‖/‖θ̇‖`` with the geometric Jacobian of
  ``Kinematics.jacobian``;
* the report's extremes and integral against the trace's columns.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from irlc import run_program
from irlc.robots import load_robot
from irlc.runtime import units
from irlc.runtime.model.chain import task_rows_for
from irlc.runtime.model.dynamics import Dynamics
from irlc.runtime.model.kinematics import Kinematics
from irlc.runtime.model.spatial import rotation_vector

ROOT = Path(__file__).resolve().parents[2]
PROGRAMS = {
    "koch11": """PROGRAM m;
ROBOT r := koch11;
IMPORT DATALIST square_cell;
BEGIN
  R_SPEED := 1000;  R_ACC := 2000;  R_SPEED_ORI := 50;
  MOVE PTP konf_0;
  MOVE LIN poz_1;
  MOVE LIN poz_2;
  WAIT 0.1 SEC;
ENDPROGRAM
""",
    "mobile8": """PROGRAM m;
ROBOT r := mobile8;
BEGIN
  MOVE_INC LIN (300, 200, -100, 0, 0, 20);
  MOVE_INC PTP (100, -50, 10, 10, 10, 10, 10, 10);
ENDPROGRAM
""",
    "l1": """PROGRAM m;
ROBOT r := l1;
BEGIN
  R_SPEED := 20;  R_ACC := 20;
  MOVE PTP (205, 300, 300, 90, 25, 95);
  MOVE_INC LIN (20, -10, 15, 0, 0, 0);
ENDPROGRAM
""",
}


def _run(tmp_path, name, source=None, **options):
    program = tmp_path / f"{name}.irl"
    program.write_text(source or PROGRAMS[name], encoding="utf-8")
    return run_program(program, datalist_path=[str(ROOT / "programs")], **options)


def _joints_si(run, model):
    """Joints and speeds from the trace's columns (program units → SI)."""
    cols, t = run.trace_columns, run.trace
    scale = units.joint_scale(model.joint_kinds)
    names = run.report["joint_names"]
    unit = [units.joint_unit(k) for k in model.joint_kinds]
    q = np.column_stack([t[:, cols.index(f"{n}_{u}")] for n, u in zip(names, unit, strict=True)])
    qd = np.column_stack(
        [t[:, cols.index(f"{n}_speed_{u}_s")] for n, u in zip(names, unit, strict=True)]
    )
    return q * scale, qd * scale


def _per_link_energy(model, q, qd, h=1e-6):
    """Σ ½ m |v_c|² + ½ ωᵀ I ω with each link's velocities from central differences of its
    frames along θ̇ (Dynamics.frames: the forward kinematics)."""
    dyn = Dynamics(model)
    ahead, behind = dyn.frames(q + h * qd).copy(), dyn.frames(q - h * qd).copy()
    energy = 0.0
    for inertial in model.inertials:
        i = inertial.link
        if not 1 <= i <= model.n:
            continue
        fa, fb = ahead[i], behind[i]
        ca = fa[:3, 3] + fa[:3, :3] @ inertial.com
        cb = fb[:3, 3] + fb[:3, :3] @ inertial.com
        v = (ca - cb) / (2 * h)
        w = rotation_vector(fa[:3, :3] @ fb[:3, :3].T) / (2 * h)  # world ω
        rot = dyn.frames(q).copy()[i, :3, :3]
        inertia = rot @ inertial.inertia @ rot.T
        energy += 0.5 * inertial.mass * v @ v + 0.5 * w @ inertia @ w
    return energy


@pytest.mark.parametrize("name", sorted(PROGRAMS))
def test_kinetic_energy_column_against_two_other_computations(tmp_path, name):
    run = _run(tmp_path, name)
    assert run.status == "ok", run.error
    model = load_robot(name)
    q, qd = _joints_si(run, model)
    column = run.trace[:, run.trace_columns.index("kinetic_energy_j")]
    dyn = Dynamics(model)  # rotor 0: the links alone
    crba = np.array([0.5 * v @ dyn.mass_matrix(x) @ v for x, v in zip(q, qd, strict=True)])
    assert column.max() > 0.0  # it moved
    # the trace prints 10 significant digits of each column
    assert np.allclose(column, crba, rtol=1e-8, atol=1e-9 * column.max())
    rows = np.linspace(1, len(q) - 1, 12).astype(int)
    links = np.array([_per_link_energy(model, q[k], qd[k]) for k in rows])
    assert np.allclose(column[rows], links, rtol=1e-6, atol=1e-7 * column.max())
    assert column[0] == 0.0  # at rest before the first sample


@pytest.mark.parametrize("name", sorted(PROGRAMS))
def test_mvr_column_is_the_velocity_ratio(tmp_path, name):
    run = _run(tmp_path, name)
    model = load_robot(name)
    q, qd = _joints_si(run, model)
    column = run.trace[:, run.trace_columns.index("mvr")]
    kin = Kinematics(model)
    rows = list(task_rows_for(model))
    expected = np.zeros(len(q))
    for k, (x, v) in enumerate(zip(q, qd, strict=True)):
        if np.abs(v).max() >= 1e-6:
            expected[k] = np.linalg.norm(kin.jacobian(x)[rows] @ v) / np.linalg.norm(v)
    assert np.allclose(column, expected, rtol=1e-7, atol=1e-12)
    assert (column > 0).sum() > 10 and column[0] == 0.0


def test_report_extremes_and_integral_follow_the_trace(tmp_path):
    run = _run(tmp_path, "koch11")
    cols, t = run.trace_columns, run.trace
    times = t[:, cols.index("t_s")]
    energy, ratio = t[:, cols.index("kinetic_energy_j")], t[:, cols.index("mvr")]
    report = run.report
    ke, mv = report["kinetic_energy"], report["mvr"]
    assert ke["max_j"] == pytest.approx(energy.max(), rel=1e-8)
    assert ke["max_at_time_s"] == pytest.approx(times[np.argmax(energy)])
    assert ke["integral_j_s"] == pytest.approx(float(np.sum(energy[1:] * np.diff(times))), rel=1e-7)
    moving = ratio > 0.0
    assert mv["min"] == pytest.approx(ratio[moving].min(), rel=1e-8)
    assert mv["max"] == pytest.approx(ratio[moving].max(), rel=1e-8)
    assert mv["min_at_time_s"] == pytest.approx(times[moving][np.argmin(ratio[moving])])
    # the WAIT at the end: standing, zero energy and no ratio
    assert energy[-1] == 0.0 and ratio[-1] == 0.0


def test_a_robot_without_inertials_has_no_energy_column(tmp_path):
    text = (ROOT / "robots" / "planar3.toml").read_text(encoding="utf-8")
    start, end = text.index("[[inertials]]"), text.index("# The arm moves in the xy plane")
    (tmp_path / "arm.toml").write_text(text[:start] + text[end:], encoding="utf-8")
    source = (
        "PROGRAM p;\nROBOT r := 'arm.toml';\nBEGIN\n"
        "  MOVE LIN POSE(2100, 900, 0, 0, 0, 0);\nENDPROGRAM\n"
    )
    run = _run(tmp_path, "bare", source)
    assert run.status == "ok"
    assert "kinetic_energy_j" not in run.trace_columns and "mvr" in run.trace_columns
    assert run.report["kinetic_energy"] is None and run.report["mvr"]["max"] > 0


def test_drive_runs_measure_the_actual_motion(tmp_path):
    run = _run(tmp_path, "koch11", drives="coupled", path_tolerance=5.0, orientation_tolerance=1.0)
    model = load_robot("koch11")
    q, qd = _joints_si(run, model)
    column = run.trace[:, run.trace_columns.index("kinetic_energy_j")]
    dyn = Dynamics(model)
    crba = np.array([0.5 * v @ dyn.mass_matrix(x) @ v for x, v in zip(q, qd, strict=True)])
    assert np.allclose(column, crba, rtol=1e-8, atol=1e-9 * column.max())
    assert np.isfinite(run.trace).all() and run.report["kinetic_energy"]["integral_j_s"] > 0
