"""Settings whose motion cannot be planned are positioned run failures (issue 24 §10).

On main a subnormal R_JERK or R_ACC under R_PROFILE := 'SCURVE' (and R_ACC := 1e-320
before a CIRCLE) ended in an internal error (exit 4: a ProfileError from profiles.py or
scurve.py), and ``R_PROFILE := 'SCURVE'; R_ACC := 1e-320; MOVE LIN …`` reported ``ok``
after 0.0 s with the robot never moving: the S-curve's closed form underflowed to a
minimum time of 0 s and the segment was skipped as if it had no length.
"""

from __future__ import annotations

import pytest
from irlc.runtime.plan import scurve
from irlc.runtime.plan.profiles import minimum_time
from irlc.runtime.run import run_file

LIN = "MOVE LIN (1500, 1000, 0, 0, 0, 0);"
CIRCLE = "MOVE CIRCLE (1800, 1200, 0, 0, 0, 0), (1500, 1000, 0, 0, 0, 0);"
PTP = "MOVE PTP (10, 80, -80);"
SCURVE = "R_PROFILE := 'SCURVE'; "
NEVER = "the motion would take"  # … longer than the simulated-time budget


@pytest.mark.parametrize(
    ("settings", "motion", "says"),
    [
        (SCURVE + "R_ACC := 1e-320;", LIN, NEVER),
        (SCURVE + "R_ACC := 1e-320;", CIRCLE, NEVER),
        (SCURVE + "R_ACC := 1e-320;", PTP, "jerk bound θ̈max·R_JERK/R_ACC is inf"),
        (SCURVE + "R_JERK := 1e-320;", LIN, NEVER),
        (SCURVE + "R_JERK := 1e-320;", PTP, NEVER),
        (SCURVE + "R_JERK := 5e-324;", CIRCLE, "the path jerk (R_JERK"),
        (SCURVE + "R_JERK := 5e-324;", PTP, "jerk bound θ̈max·R_JERK/R_ACC is 0"),
        ("R_ACC := 1e-320;", CIRCLE, NEVER),
        ("R_OVERRIDE := 50; R_ACC := 1e-320;", CIRCLE, NEVER),
        ("R_OVERRIDE := 50; " + SCURVE + "R_JERK := 1e-308;", PTP, NEVER),
        ("R_OVERRIDE := 1; " + SCURVE + "R_ACC := 1e-300;", CIRCLE, NEVER),
    ],
)
def test_unplannable_settings_fail_at_the_motion(tmp_path, settings, motion, says):
    path = tmp_path / "sn.irl"
    path.write_text(
        f"PROGRAM sn;\nROBOT r := planar3;\nBEGIN\n  {settings}\n  {motion}\nENDPROGRAM\n"
    )
    run = run_file(path)
    assert run.status == "failed", "a motion that never arrives ran 'ok'"
    err = run.report["error"]
    assert err["line"] == 5 and err["time_s"] == 0.0, err
    assert says in err["message"], err["message"]


@pytest.mark.parametrize("accel", [1e-323, 1e-310, 2e-308, 1e-300, 1e-3, 1.0])
def test_an_s_curve_is_never_faster_than_the_trapezoid(accel):
    """The jerk bound only adds time: with the same speed and acceleration the S-curve's
    minimum time is at least the trapezoid's — also where ``4/a`` overflows."""
    for jerk in (1e-300, 1.0, 1e6):
        t_s = scurve.minimum_time(1.0, accel, jerk)
        assert t_s >= minimum_time(1.0, accel) > 0.0
