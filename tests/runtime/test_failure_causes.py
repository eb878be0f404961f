"""Run failures name their cause from the solver's state (issue 9 §2).

Each scenario is a small program (written to a temporary file) that failed on main with
a misleading "bound by … speed/accel max" (or that reported a bound that did not bind):

* an unreachable LIN/CIRCLE/MOVE_INC target fails at its own line before moving, with the
  distance of the closest pose — the same number the PTP search gives for that pose;
* a path through a singular configuration names ``singular`` with σ_min;
* FREEZE leaving too few joints names ``freeze``;
* a PTP at 50 % of the acceleration limit has no active acceleration bound;
* a speed-bound failure suggests a path speed, and the program then runs at that speed;
* joint names in messages are the summary's (program name, robot name in parentheses).
"""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
from irlc.runtime.run import run_code, run_file

from tests.runtime.conftest import Ird, planar_robot

MOBILE8_CELL = """
[poses]
p_far = [2200, 300, 800, 0, 90, 0]
[joints]
home = [0, 0, 0, -30, 60, 0, -30, 0]
"""


def _run(tmp_path, name: str, body: str, robot: str, cell: str | None = None):
    head = f"PROGRAM {name};\nROBOT r := {robot};\n"
    if cell is not None:
        (tmp_path / f"{name}_cell.toml").write_text(cell)
        head += f"IMPORT DATALIST {name}_cell;\n"
    path = tmp_path / f"{name}.irl"
    path.write_text(head + "BEGIN\n" + body + "ENDPROGRAM\n")
    return run_file(path)


def _panda():
    pytest.importorskip("yourdfpy")


# ------------------------------------------------------------------ unreachable targets
FAR = "(1500, 0, 500, 180, 0, 0)"


def test_unreachable_lin_on_panda_fails_at_its_line_before_moving(tmp_path):
    _panda()
    body = f"  R_SPEED := 200;\n  MOVE LIN (300, 100, 450, 0, 0, 180);\n  MOVE LIN {FAR};\n"
    run = _run(tmp_path, "lin_far", body, "panda")
    assert run.status == "failed"
    err = run.report["error"]
    assert err["line"] == 6 and err["cause"] == "unreachable"
    # before the robot moves: the failure is at the end of the previous motion and no
    # sample of the failing line was recorded
    assert err["time_s"] == pytest.approx(float(run.times[run.lines == 5][-1]))
    assert 6 not in set(run.lines.tolist())
    assert "target not reachable" in err["message"] and "mm" in err["message"]
    assert err["distance_mm"] > 500.0
    assert f"{err['distance_mm']:.4g} mm" in err["message"]
    # the same search as PTP: the same pose from the same configuration, the same distance
    ptp = _run(tmp_path, "ptp_far", body.replace(f"LIN {FAR}", f"PTP {FAR}"), "panda")
    assert ptp.report["error"]["cause"] == "unreachable"
    assert ptp.report["error"]["distance_mm"] == pytest.approx(err["distance_mm"], rel=1e-9)


def test_unreachable_distance_matches_the_closed_form_on_the_planar_arm(tmp_path):
    # planar3: three 1 m links, the reachable set is the 3 m disc; (4000, 1000) mm is
    # √(4000² + 1000²) − 3000 = 1123.1 mm outside it
    body = "  MOVE LIN (1500, 1000, 0, 0, 0, 0);\n  MOVE LIN (4000, 1000, 0, 0, 0, 0);\n"
    run = _run(tmp_path, "disc", body, "planar3")
    err = run.report["error"]
    assert err["cause"] == "unreachable" and err["line"] == 5
    exact = math.hypot(4000.0, 1000.0) - 3000.0
    assert exact - 1e-6 <= err["distance_mm"] <= exact * 1.01


@pytest.mark.parametrize(
    ("motion", "what"),
    [
        ("MOVE CIRCLE (1500, 3500, 0, 0, 0, 0), (1000, 1000, 0, 0, 0, 0);", "via point"),
        ("MOVE_INC LIN (2500, 0, 0, 0, 0, 0);", "target"),
    ],
)
def test_unreachable_circle_via_and_inc_target_fail_before_moving(tmp_path, motion, what):
    body = f"  MOVE LIN (1500, 1000, 0, 0, 0, 0);\n  {motion}\n"
    run = _run(tmp_path, "circle_far", body, "planar3")
    err = run.report["error"]
    assert err["cause"] == "unreachable" and err["line"] == 5, err
    assert f"{what} not reachable" in err["message"]
    assert 5 not in set(run.lines.tolist())


def test_reachable_far_targets_are_not_rejected(tmp_path):
    # a far pose on another branch of the arm (the search from the seed alone stalls at
    # a joint limit) is reachable: the pre-check must let the motion start
    body = "  MOVE PTP (0, 90, -90);\n  MOVE LIN (0, 2500, 0, 0, 0, 0);\n"
    run = _run(tmp_path, "far_ok", body, "planar3")
    assert run.status == "ok", run.error


# ------------------------------------------------------------------ singular
def test_singular_path_names_singular_and_sigma_min(tmp_path):
    # planar3 stretched along x (q = 0): J's x row is zero (every joint moves the TCP
    # along y only), σ_min = 0; a radial line needs exactly that direction
    body = "  MOVE PTP (0, 0, 0);\n  WAIT 0.1 SEC;\n  MOVE LIN (2500, 0, 0, 0, 0, 0);\n"
    run = _run(tmp_path, "stretched", body, "planar3")
    err = run.report["error"]
    assert err["line"] == 6 and err["cause"] == "singular", err
    assert err["sigma_min_si"] == pytest.approx(0.0, abs=1e-9)
    assert "σ_min" in err["message"] and "lower speed does not help" in err["message"]
    assert err["lost_directions"] == ["x"]


def test_line_through_the_folded_singularity_names_singular():
    # a 2R arm with unit links: a line through the base passes the folded configuration
    # (q2 = 180 deg, J = [[−s1, 0], [c1, 0]]·0 … rank 1, σ_min = 0) where q1 would have
    # to turn by 180 deg at once; the pre-check passes (both ends are reachable)
    robot = planar_robot(2, position_deg=181.0)
    p = Ird("planar2t", "RR")
    p.move(10, "LIN", p.pose(-1000, 0, 0))
    run = run_code(p.code_object(), robot=robot, seed_config=(-60.0, 120.0))
    err = run.report["error"]
    assert run.status == "failed" and err["line"] == 10
    assert err["time_s"] > 0.1  # it moved: the singularity is in the middle of the line
    assert err["cause"] == "singular", err
    assert err["sigma_ratio"] < 1e-3 and "σ_min" in err["message"]


# ------------------------------------------------------------------ freeze
def test_freeze_leaving_too_few_joints_on_mobile8_names_freeze(tmp_path):
    body = "  MOVE PTP home;\n  FREEZESTART 1, 2;\n  MOVE LIN p_far;\n  FREEZEEND;\n"
    run = _run(tmp_path, "fz", body, "mobile8", MOBILE8_CELL)
    err = run.report["error"]
    assert err["cause"] == "freeze" and err["line"] == 7, err
    assert err["time_s"] == pytest.approx(float(run.times[-1]))  # before moving
    assert "a1 (X), a2 (Y)" in err["message"] and err["joints"] == ["a1", "a2"]


def test_freeze_near_the_arms_reach_names_freeze_not_a_bound(tmp_path):
    # the end pose is within the arm's reach, but the arm alone must stretch towards its
    # elbow singularity: the bound the relaxed step touches is a symptom
    body = (
        "  R_SPEED := 300;\n  MOVE PTP home;\n  FREEZESTART 1, 2;\n"
        "  MOVE LIN (1140, 0, 800, 0, 90, 0);\n  FREEZEEND;\n"
    )
    run = _run(tmp_path, "fz2", body, "mobile8", MOBILE8_CELL)
    err = run.report["error"]
    assert err["cause"] == "freeze" and err["line"] == 8, err
    assert "with them free the path can be followed" in err["message"]
    # without the freeze the same line runs
    unfrozen = body.replace("FREEZESTART 1, 2;\n", "").replace("  FREEZEEND;\n", "")
    free = _run(tmp_path, "fz3", unfrozen, "mobile8", MOBILE8_CELL)
    assert free.status == "ok", free.error


# ------------------------------------------------------------------ limit activity
def test_ptp_at_half_the_acceleration_limit_has_no_active_accel_bound(tmp_path):
    _panda()
    motion = "  MOVE PTP (30, -20, 10, -100, 5, 100, 30);\n"
    half = _run(tmp_path, "half", "  R_ACC_PTP := 50;\n" + motion, "panda")
    assert half.status == "ok"
    for joint in half.report["joints"]:
        assert not any(k.startswith("accel") for k in joint["limit_activity"]), joint
    # at 100 % the joint that reaches its acceleration limit is reported, and only that
    # one: independently, the joints whose trace acceleration peaks at the limit
    full = _run(tmp_path, "full", "  R_ACC_PTP := 100;\n" + motion, "panda")
    limits = np.degrees([j.limits.accel[1] for j in _panda_model().joints])
    peaks = np.array([j["max_abs_accel"] for j in full.report["joints"]])
    at_limit = set(np.flatnonzero(peaks >= limits * (1 - 1e-6)).tolist())
    active = {i for i, j in enumerate(full.report["joints"]) if j["limit_activity"]}
    assert at_limit and active == at_limit


def _panda_model():
    from irlc.runtime.run import load_model

    return load_model("panda", None)


# ------------------------------------------------------------------ speed suggestion
SPEED_BODY = """  R_SPEED := {speed};
  R_ACC := 1000;
  JOINTSPEEDLIMIT (-30, -30, -30, -30, -30, -30, -30), (30, 30, 30, 30, 30, 30, 30);
  MOVE LIN (500, -300, 300, 0, 0, 180);
  JOINTSPEEDLIMITEND;
"""


def test_speed_bound_failure_suggests_a_speed_that_works(tmp_path):
    _panda()
    run = _run(tmp_path, "fast", SPEED_BODY.format(speed=1000), "panda")
    err = run.report["error"]
    assert err["cause"] == "speed_limit", err
    suggested = err["suggested_speed_mm_s"]
    assert 0.05 * 1000 <= suggested < 1000
    assert f"R_SPEED ≤ {suggested:g} mm/s" in err["message"]
    again = _run(tmp_path, "slow", SPEED_BODY.format(speed=f"{suggested:g}"), "panda")
    assert again.status == "ok", again.error


def test_suggestions_at_an_override_are_programmed_values(tmp_path):
    """R_OVERRIDE 50 % halves the speeds and quarters the accelerations: the suggested
    R_SPEED (R_ACC) is the actual bound over k (k²), so it is twice the one at 100 % (to
    the two digits of the rounding), and the program runs with it at the same override."""
    _panda()
    full = _run(tmp_path, "fast", SPEED_BODY.format(speed=1000), "panda").report["error"]
    half = "  R_OVERRIDE := 50;\n" + SPEED_BODY
    err = _run(tmp_path, "fast50", half.format(speed=1000), "panda").report["error"]
    assert err["cause"] == "speed_limit", err
    suggested = err["suggested_speed_mm_s"]
    assert 0.5 * suggested == pytest.approx(full["suggested_speed_mm_s"], rel=0.1)
    assert f"R_SPEED ≤ {suggested:g} mm/s at R_OVERRIDE 50 % (" in err["message"]
    assert f"({0.5 * suggested:.4g} mm/s actual; the segment peaks at" in err["message"]
    again = _run(tmp_path, "slow50", half.format(speed=f"{suggested:g}"), "panda")
    assert again.status == "ok", again.error
    # an acceleration bound: R_SPEED and R_ACC, both programmed values at 50 %
    body = (
        "  R_OVERRIDE := 50;\n  R_SPEED := {speed};\n  R_ACC := {acc};\n"
        "  MOVE PTP (0, -30, 0, -120, 0, 90, 45);\n  MOVE LIN (500, -200, 450, 0, 0, 180);\n"
    )
    err = _run(tmp_path, "acc50", body.format(speed=2000, acc=16000), "panda").report["error"]
    assert err["cause"] == "accel_limit", err
    speed, acc = err["suggested_speed_mm_s"], err["suggested_acc_mm_s2"]
    msg = err["message"]
    assert f"R_ACC ≤ {acc:g} mm/s² at R_OVERRIDE 50 % ({0.25 * acc:.4g} mm/s² actual;" in msg
    again = _run(tmp_path, "acc50", body.format(speed=f"{speed:g}", acc=f"{acc:g}"), "panda")
    assert again.status == "ok", again.error


# ------------------------------------------------------------------ naming
def test_message_joint_names_are_the_summarys(tmp_path):
    _panda()
    run = _run(tmp_path, "names", SPEED_BODY.format(speed=1000), "panda")
    msg = run.report["error"]["message"]
    names = run.report["joint_names"]
    robot = _panda_model().joint_names
    pairs = re.findall(r"\b(a\d+) \((panda_joint\d+)\)", msg)
    assert pairs
    for program, own in pairs:
        assert robot.index(own) == names.index(program)
    assert len(re.findall(r"panda_joint\d", msg)) == len(pairs)  # never the robot name alone


def test_interpreter_limit_messages_follow_the_naming_rule(tmp_path):
    # mobile8's fifth joint is "A3" in the robot file and a5 in the program and summary
    body = (
        "  MOVE PTP home;\n"
        "  JOINTLIMIT (-1000, -1000, -90, -90, -90, -90, -90, -90),"
        " (1000, 1000, 90, 90, 50, 90, 90, 90);\n"
        "  JOINTLIMITEND;\n"
    )
    run = _run(tmp_path, "jl", body, "mobile8", MOBILE8_CELL)
    err = run.report["error"]
    assert "joint a5 (A3) is at 60" in err["message"], err
    assert run.report["joint_names"][4] == "a5"


def test_target_excluded_by_jointlimit_names_the_position_limit(tmp_path):
    # (0, 2500) mm needs a1 well above 20 deg on planar3 (|p| = 2.5 m with the other
    # links bent ≤ 180 deg): reachable with the robot's limits, not within the JOINTLIMIT
    body = (
        "  MOVE PTP (0, 90, -90);\n"
        "  JOINTLIMIT (-20, -180, -180), (20, 180, 180);\n"
        "  MOVE LIN (0, 2500, 0, 0, 0, 0);\n"
        "  JOINTLIMITEND;\n"
    )
    run = _run(tmp_path, "jl_far", body, "planar3")
    err = run.report["error"]
    assert err["cause"] == "position_limit" and err["line"] == 6, err
    assert "JOINTLIMIT excludes it" in err["message"]
    assert 6 not in set(run.lines.tolist())


def test_obstacle_failure_names_obstacle():
    from pathlib import Path

    folder = Path(__file__).resolve().parents[1] / "runtime_acceptance" / "failing"
    run = run_file(folder / "f05_obstacle_inside.irl")
    assert run.report["error"]["cause"] == "obstacle", run.report["error"]


def test_path_needing_a_joint_past_its_limit_is_not_blamed_on_the_speed(tmp_path):
    """The turn needs panda_joint7 beyond 166°: at 45 deg/s its braking bound binds a
    little before the limit. Main blamed the acceleration and suggested R_SPEED_ORI ≤ 21,
    where the run then failed on the position limit; both speeds must name the limit."""
    body = "  R_TOOL := (0, 0, 150, 0, 0, 0);\n  MOVE LIN (400, 0, 400, 180, 0, 180);\n"
    for speed in ("", "  R_SPEED_ORI := 21;\n"):
        run = _run(tmp_path, "turn", speed + body, "panda")
        err = run.report["error"]
        assert run.status == "failed" and err["cause"] == "position_limit", err["message"]
        assert err["joints"] == ["a7"] and "lower speed does not" in err["message"]
