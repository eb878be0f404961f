"""A failure names its one cause (issue 24 §4).

On main: FREEZE together with a JOINTLIMIT was blamed on FREEZE alone ("too few free
joints") though each alone passes; "bound by a6 speed max 20 deg/s; cause: a joint
acceleration bound" named two causes where the lower speed alone resolves it; a WITH
TIME failure named no joint (and a WITH TIME motion the joints could not follow was told
to lower R_SPEED, which WITH TIME overrides); "1422.66 mm the arm can stretch" was the
sum of the link lengths, not a reach.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from irlc.runtime.run import load_model, run_file

CELL8 = "[joints]\nhome = [0, 0, 0, -30, 60, 0, -30, 0]\n"


def _run(tmp_path, name: str, robot: str, body: list[str], cell: str | None = None):
    head = f"PROGRAM {name};\nROBOT r := {robot};\n"
    if cell is not None:
        (tmp_path / f"{name}_cell.toml").write_text(cell)
        head += f"IMPORT DATALIST {name}_cell;\n"
    path = tmp_path / f"{name}.irl"
    path.write_text(head + "BEGIN\n" + "\n".join(f"  {s}" for s in body) + "\nENDPROGRAM\n")
    return run_file(path)


def _freeze_and_limit(tmp_path, name, limit: str, before: list[str], motion: str):
    """The same motion with FREEZE and JOINTLIMIT, FREEZE alone, JOINTLIMIT alone."""
    runs = {}
    for variant in ("both", "freeze", "limit"):
        body = ["MOVE PTP home;"]
        body += ["FREEZESTART 1, 2;"] if variant != "limit" else []
        body += before
        body += [f"JOINTLIMIT {limit};"] if variant != "freeze" else []
        body += [motion]
        body += ["JOINTLIMITEND;"] if variant != "freeze" else []
        body += ["FREEZEEND;"] if variant != "limit" else []
        runs[variant] = _run(tmp_path, f"{name}_{variant}", "mobile8", body, CELL8)
    return runs


A3_NARROW = (
    "(-5000, -5000, -10, -120, -150, -180, -120, -180), (5000, 5000, 10, 90, 150, 180, 120, 180)"
)


def test_freeze_with_jointlimit_at_the_target_names_both(tmp_path):
    runs = _freeze_and_limit(tmp_path, "pre", A3_NARROW, [], "MOVE LIN (900, 400, 900, 0, 90, 0);")
    assert runs["freeze"].status == "ok" and runs["limit"].status == "ok"
    err = runs["both"].report["error"]
    assert err["cause"] == "freeze_jointlimit" and err["time_s"] == 0.0, err
    assert err["joints"] == ["a1", "a2"] and err["limited_joints"] == ["a3"]
    msg = err["message"]
    assert "FREEZE of joints a1 (X), a2 (Y) together with the active JOINTLIMIT" in msg
    assert "a3 (A1) -10…10 deg" in msg and "each alone leaves it reachable" in msg
    assert "too few free joints" not in msg


@pytest.mark.parametrize("upper", [62, 66])
def test_freeze_with_jointlimit_on_the_path_names_both(tmp_path, upper):
    """The platform frozen and the elbow a5 kept below 62 (66) deg: the middle of the line
    comes too close for the arm; with the platform free it backs up, without the
    JOINTLIMIT the elbow folds. At 62 deg the failing cycle presses on the bound, at 66
    the walk finds the path out of reach: the combination either way."""
    limit = (
        "(-5000, -5000, -180, -120, -150, -180, -120, -180), "
        f"(5000, 5000, 180, 90, {upper}, 180, 120, 180)"
    )
    runs = _freeze_and_limit(
        tmp_path,
        f"path{upper}",
        limit,
        ["MOVE LIN (950, -350, 800, 0, 90, 0);"],
        "MOVE LIN (950, 350, 800, 0, 90, 0);",
    )
    assert runs["freeze"].status == "ok" and runs["limit"].status == "ok"
    err = runs["both"].report["error"]
    assert err["cause"] == "freeze_jointlimit" and err["time_s"] > 0.5, err
    assert err["limited_joints"] == ["a5"] and err["joints"] == ["a1", "a2"]
    assert f"a5 (A3) -150…{upper} deg" in err["message"]


def _panda():
    pytest.importorskip("yourdfpy")


SPEED_BODY = [
    "R_SPEED := {speed};",
    "R_ACC := {acc};",
    "JOINTSPEEDLIMIT (-20, -20, -20, -20, -20, -20, -20), (20, 20, 20, 20, 20, 20, 20);",
    "MOVE LIN (500, -300, 300, 0, 0, 180);",
    "JOINTSPEEDLIMITEND;",
]


def test_the_bound_that_binds_is_the_one_cause(tmp_path):
    """The cycle is bound by a6's speed; the estimate would also lower R_ACC. The cause is
    the speed bound, and the suggested speed alone (R_ACC unchanged) runs."""
    _panda()
    body = [s.format(speed=300, acc=2000) for s in SPEED_BODY]
    err = _run(tmp_path, "two", "panda", body).report["error"]
    assert "speed max 20 deg/s" in err["constraint"], err
    assert err["cause"] == "speed_limit"
    assert "cause: that joint speed bound" in err["message"]
    assert "acceleration bound" not in err["message"]
    speed = err["suggested_speed_mm_s"]
    again = _run(
        tmp_path, "one", "panda", [s.format(speed=f"{speed:g}", acc=2000) for s in SPEED_BODY]
    )
    assert again.status == "ok", again.error


def _trapezoid_time(d: float, v: float, a: float) -> float:
    return d / v + v / a if d >= v * v / a else 2.0 * math.sqrt(d / a)


def test_a_with_time_ptp_names_the_joint_that_sets_the_time(tmp_path):
    # planar3 from (0, 90, -90) to (60, 80, -80) at the default 50 % speed and acceleration:
    # the joint with the longest time of its own sets the PTP's (computed here)
    model = load_model("planar3", None)
    delta = np.radians([60.0, 10.0, 10.0])
    times = [
        _trapezoid_time(d, 0.5 * j.limits.speed[1], 0.5 * j.limits.accel[1])
        for d, j in zip(delta, model.joints, strict=True)
    ]
    slowest = int(np.argmax(times))
    body = ["MOVE PTP (0, 90, -90);", "MOVE PTP (60, 80, -80) WITH TIME := 0.1;"]
    err = _run(tmp_path, "wt", "planar3", body).report["error"]
    name = f"a{slowest + 1} (J{slowest + 1})"
    assert err["constraint"] == f"joint {name} speed/acceleration", err
    assert f"({err['constraint']} sets it)" in err["message"]
    assert f"{max(times):.6g} s" in err["message"]


def test_a_with_time_path_names_what_sets_it(tmp_path):
    body = ["MOVE PTP (0, 90, -90);", "MOVE LIN (1500, 1000, 0, 0, 0, 0) WITH TIME := 0.1;"]
    err = _run(tmp_path, "wtl", "planar3", body).report["error"]
    assert err["constraint"] == "path speed/acceleration"
    assert "(path speed/acceleration sets it)" in err["message"]


def test_a_with_time_motion_the_joints_cannot_follow_suggests_a_time(tmp_path):
    """WITH TIME fixes the speed, so lowering R_SPEED cannot help: the suggestion is a
    longer time (with R_ACC where the ramps are too steep), and the program runs with it."""
    _panda()
    motion = "MOVE LIN (500, -300, 300, 0, 0, 180) WITH TIME := {t};"
    body = ["R_SPEED := 3000;", "R_ACC := {acc};", motion]
    err = _run(tmp_path, "wtp", "panda", [s.format(t=0.3, acc=100000) for s in body])
    err = err.report["error"]
    assert err["cause"] in ("speed_limit", "accel_limit"), err
    assert "R_SPEED ≤" not in err["message"] and "WITH TIME :=" in err["message"]
    longer, acc = err["suggested_time_s"], err["suggested_acc_mm_s2"]
    assert longer > 0.3
    fixed = [s.format(t=f"{longer:g}", acc=f"{acc:g}") for s in body]
    again = _run(tmp_path, "wtp2", "panda", fixed)
    assert again.status == "ok", again.error


def test_the_reach_bound_says_what_it_is(tmp_path):
    # planar3: three 1 m links, so 3000 mm laid end to end (the true reach here)
    body = ["MOVE PTP (0, 90, -90);", "MOVE LIN (4000, 1000, 0, 0, 0, 0);"]
    err = _run(tmp_path, "far", "planar3", body).report["error"]
    assert "beyond the 3000 mm of its links laid end to end" in err["message"], err
    assert "can stretch" not in err["message"]


def test_the_panda_bound_is_a_bound_of_the_reach():
    """panda's 1422.66 mm is its links end to end: no configuration within its limits
    gets its TCP that far from the base (sampled), though it is not a reach."""
    _panda()
    from irlc.runtime.ik.unreachable import reach_bound
    from irlc.runtime.model.kinematics import Kinematics

    model = load_model("panda", None)
    box = model.position_limits
    bound = reach_bound(model, None, box)
    kin = Kinematics(model, None)
    rng = np.random.default_rng(3)
    far = max(
        float(
            np.linalg.norm(
                kin.tcp(box[:, 0] + rng.random(model.n) * (box[:, 1] - box[:, 0]))[:3, 3]
            )
        )
        for _ in range(2000)
    )
    assert far < bound
    assert bound == pytest.approx(1.42266, abs=1e-5)
