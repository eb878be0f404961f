"""``R_TOOL`` set before the first motion holds from t = 0: the start sample's TCP is the
forward kinematics of the start joints with the program's tool (robot file's tool, then
``R_TOOL``), so the trace has no jump and the path speed no spike at the first cycle."""

from __future__ import annotations

import numpy as np
import pytest
from irlc.api import compile_program
from irlc.plots import path_length_and_speed
from irlc.run_data import run_data
from irlc.runtime import units
from irlc.runtime.model.kinematics import Kinematics
from irlc.runtime.run import run_code

PROGRAM = """PROGRAM rtool;
ROBOT r := {robot};
BEGIN
  R_TOOL := POSE(0, 0, 150, 0, 0, 0);
  {first}
ENDPROGRAM
"""


def _run(tmp_path, robot: str, first: str):
    code = compile_program(tmp_path / "rtool.irl", source=PROGRAM.format(robot=robot, first=first))
    run = run_code(code)
    assert run.status == "ok", run.error
    return run


@pytest.mark.parametrize(
    "first",
    ["MOVE PTP (0, -30, 0, -120, 0, 90, 45);", "WAIT 0.05 SEC;"],
)
def test_first_sample_uses_the_program_tool(tmp_path, first):
    run = _run(tmp_path, "panda", first)
    model = run.model
    tool = model.tool @ units.pose_to_si(0.0, 0.0, 150.0, 0.0, 0.0, 0.0)
    fk = Kinematics(model, tool).tcp(run.q[0])
    np.testing.assert_allclose(run.tcp[0], fk, atol=1e-12)
    # independent: the program tool is 150 mm along the flange z past the file's TCP
    plain = Kinematics(model).tcp(run.q[0])
    np.testing.assert_allclose(fk[:3, 3], plain[:3, 3] + 0.150 * plain[:3, 2], atol=1e-12)
    # the first step of the trace is a small motion, not the 150 mm tool change
    step = np.linalg.norm(run.tcp[1, :3, 3] - run.tcp[0, :3, 3])
    assert step < 1e-3, step  # m


def test_path_speed_has_no_spike_at_the_start(tmp_path):
    run = _run(tmp_path, "panda", "MOVE PTP (0, -30, 0, -120, 0, 90, 45);")
    _, speed = path_length_and_speed(run_data(run))
    # a PTP of 15 deg on two joints: the TCP moves at a few hundred mm/s at most
    assert speed.max() < 1000.0, speed[:3]
    assert speed[:2].max() < 50.0  # starts at rest


def test_drive_runs_keep_the_program_tool(tmp_path):
    """With simulated drives the TCP is recomputed from the actual joints: with R_TOOL, not
    the robot file's tool alone (which put it 150 mm off in every sample)."""
    code = compile_program(
        tmp_path / "ktool.irl",
        source=PROGRAM.format(robot="koch11", first="WAIT 0.1 SEC;"),
    )
    ideal = run_code(code)
    driven = run_code(code, drives="decoupled")
    assert ideal.status == driven.status == "ok"
    tool = driven.model.tool @ units.pose_to_si(0.0, 0.0, 150.0, 0.0, 0.0, 0.0)
    kin = Kinematics(driven.model, tool)
    for q, tcp in zip(driven.q, driven.tcp, strict=True):
        np.testing.assert_allclose(tcp, kin.tcp(q), atol=1e-12)
    # standing still: the actual TCP is where the ideal run's is (drive error ≪ 0.1 mm)
    gap = np.linalg.norm(driven.tcp[:, :3, 3] - ideal.tcp[: len(driven.tcp), :3, 3], axis=1)
    assert gap.max() < 1e-4, gap.max()
    z_mm = driven.trace[:, driven.trace_columns.index("z_mm")]
    np.testing.assert_allclose(z_mm, ideal.trace[:, ideal.trace_columns.index("z_mm")], atol=0.1)
