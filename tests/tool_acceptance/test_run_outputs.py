"""`irlc run` on a held-out program: report, trace, plots, --compare, animation, trajectory
export, --json / --quiet and the plain (non-terminal) output. interfaces.md § Commands,
Report, Trace; tutorial § 2."""

from __future__ import annotations

import json
import math
import re

import pytest
from irlc.runtime import units

from .heldout import JMAX, JMIN, OBSTACLE_CENTER, OBSTACLE_RADIUS, write_heldout
from .helpers import assert_clean, irlc, read_trace

pytestmark = pytest.mark.scenario
PNG = b"\x89PNG\r\n\x1a\n"


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    """The twin (no limit, no obstacle avoidance: its arm passes through the post, so it
    runs with collisions allowed) traced first, then the full run compared with it."""
    tmp = tmp_path_factory.mktemp("heldout")
    prog = write_heldout(tmp)
    twin = write_heldout(tmp, "acc_free", free=True)
    out = tmp / "out"
    twin_run = irlc("run", twin, "-q", "--trace", out / "free.csv", "--plot", out / "free_figs",
                    "--allow-collisions")  # fmt: skip
    main = irlc(
        "run", prog, "--plot", out / "figs", "--animate", out / "a.html",
        "--export-trajectory", out / "t.json", "--report", out / "r.json",
        "--trace", out / "c.csv", "--compare", out / "free.csv",
    )  # fmt: skip
    plain = irlc("run", prog, "--plot", out / "plain_figs", "-q")
    return {"dir": tmp, "out": out, "prog": prog, "twin": twin_run, "main": main, "plain": plain}


def test_runs_succeed_cleanly(runs):
    for key in ("twin", "main", "plain"):
        assert runs[key].rc == 0, runs[key].both
        assert_clean(runs[key])


def test_report_keys_limits_and_obstacle(runs):
    report = json.loads((runs["out"] / "r.json").read_text())
    for key in (
        "status",
        "error",
        "program",
        "robot",
        "units",
        "ipo_s",
        "drives",
        "duration_s",
        "samples",
        "joints",
        "start_joints",
        "end_joints",
        "max_path_error_mm",
        "max_orientation_error_deg",
        "obstacles",
        "ik",
        "output",
        "warnings",
    ):
        assert key in report, key
    assert report["status"] == "ok" and report["error"] is None
    assert report["robot"] == "planar3" and report["output"] == ["triangle done"]
    for joint, lo, hi in zip(report["joints"], JMIN, JMAX, strict=True):
        assert lo - 1e-6 <= joint["min"] <= joint["max"] <= hi + 1e-6, joint
    assert report["obstacles"]["post"]["min_distance_mm"] > 0
    assert report["max_path_error_mm"] < 0.05


def test_trace_matches_report_and_obstacle_clearance(runs):
    header, rows = read_trace(runs["out"] / "c.csv")
    report = json.loads((runs["out"] / "r.json").read_text())
    col = {h: i for i, h in enumerate(header)}
    assert len(rows) == report["samples"]
    assert abs(rows[-1][col["t_s"]] - report["duration_s"]) < 1e-9
    for i, joint in enumerate(report["joints"], start=1):
        values = [r[col[f"a{i}_deg"]] for r in rows]
        assert abs(min(values) - joint["min"]) < 1e-4 and abs(max(values) - joint["max"]) < 1e-4
    # independent clearance: planar3 links are unit capsules of radius 50 mm in the xy plane
    clearance = min(_planar3_clearance([r[col[f"a{i}_deg"]] for i in (1, 2, 3)]) for r in rows)
    reported = report["obstacles"]["post"]["min_distance_mm"]
    assert abs(clearance - reported) < 1.0, (clearance, reported)


def _planar3_clearance(q_deg) -> float:
    cx, cy = OBSTACLE_CENTER[:2]
    x = y = angle = 0.0
    best = math.inf
    for q in q_deg:
        angle += math.radians(q)
        nx, ny = x + 1000 * math.cos(angle), y + 1000 * math.sin(angle)
        t = max(0.0, min(1.0, ((cx - x) * (nx - x) + (cy - y) * (ny - y)) / 1e6))
        px, py = x + t * (nx - x), y + t * (ny - y)
        best = min(best, math.hypot(cx - px, cy - py) - 50 - OBSTACLE_RADIUS)
        x, y = nx, ny
    return best


def test_plot_set(runs):
    names = {p.name for p in (runs["out"] / "figs").glob("*.png")}
    for want in (
        "joint_positions_1-3.png",
        "joint_speeds_1-3.png",
        "joint_accels_1-3.png",
        "tcp_path_3d.png",
        "tcp_path_speed.png",
    ):
        assert want in names, sorted(names)
    for p in (runs["out"] / "figs").glob("*.png"):
        assert p.read_bytes()[:8] == PNG


def test_compare_overlays_the_twin(runs):
    """--compare draws the twin: the figures differ from the same run without --compare, and
    carry more ink (a second curve)."""
    import matplotlib.image as mpimg
    import numpy as np

    with_cmp = runs["out"] / "figs" / "joint_positions_1-3.png"
    without = runs["out"] / "plain_figs" / "joint_positions_1-3.png"
    a, b = mpimg.imread(with_cmp), mpimg.imread(without)
    ink = lambda img: float((img[..., :3].mean(axis=2) < 0.8).mean())  # noqa: E731
    assert a.shape == b.shape and not np.array_equal(a, b)
    assert ink(a) > ink(b) * 1.05, (ink(a), ink(b))
    assert "free.csv" in runs["main"].out, "the summary names the compared run"


def test_animation_is_offline(runs):
    html = (runs["out"] / "a.html").read_text()
    assert html.lstrip().lower().startswith("<!doctype html")
    for bad in ("http:", "https:", "//cdn", "<link ", 'src="//'):
        assert bad not in html.lower(), bad
    assert not re.search(r"<script[^>]+src=", html, re.I), "external script"
    assert "post" in html, "the obstacle's name is in the scene data"


def test_trajectory_export_si_and_velocities(runs):
    traj = json.loads((runs["out"] / "t.json").read_text())
    header, rows = read_trace(runs["out"] / "c.csv")
    col = {h: i for i, h in enumerate(header)}
    # the robot file's own names (ROS tooling), the program's beside them (issue 9 §3)
    assert traj["joint_names"] == ["J1", "J2", "J3"]
    assert traj["program_joint_names"] == ["a1", "a2", "a3"]
    points = traj["points"]
    assert len(points) == len(rows)
    times = [p["time_from_start"]["sec"] + 1e-9 * p["time_from_start"]["nanosec"] for p in points]
    assert all(abs(t - r[col["t_s"]]) < 1e-9 for t, r in zip(times, rows, strict=True))
    deg = [[r[col[f"a{i}_deg"]] for i in (1, 2, 3)] for r in rows]
    rad = [list(units.joints_to_si(q, traj["joint_kinds"])) for q in deg]
    for p, q in zip(points, rad, strict=True):
        assert all(abs(a - b) < 1e-8 for a, b in zip(p["positions"], q, strict=True))
    # velocities: my central differences of the trace positions (rad/s); an estimate that is
    # good to O(a·dt²) in the interior — a half-cycle lag (backward differences) is O(a·dt)
    dt = times[1] - times[0]
    accel_max = max(abs(a) for p in points for a in p["accelerations"])
    worst = 0.0
    for k in range(1, len(points) - 1):
        for j in range(3):
            central = (rad[k + 1][j] - rad[k - 1][j]) / (2 * dt)
            worst = max(worst, abs(points[k]["velocities"][j] - central))
    assert worst < 0.05 * accel_max * dt, (worst, accel_max * dt)
    # accelerations: central second differences
    worst_a = 0.0
    for k in range(1, len(points) - 1):
        for j in range(3):
            second = (rad[k + 1][j] - 2 * rad[k][j] + rad[k - 1][j]) / dt**2
            worst_a = max(worst_a, abs(points[k]["accelerations"][j] - second))
    jerk_room = 0.2 * accel_max
    assert worst_a < jerk_room, (worst_a, accel_max)
    # the program starts and ends at rest: a follower must be told so (|q̇| < 1e-4 rad/s;
    # backward differences would give the last cycle's mean speed, ~3e-3 rad/s here)
    for point in (points[0], points[-1]):
        assert all(abs(v) < 1e-4 for v in point["velocities"]), point


def test_json_equals_report_file(runs, tmp_path):
    res = irlc("run", runs["prog"], "--json", "--report", tmp_path / "r.json")
    assert res.rc == 0, res.both
    printed = json.loads(res.out)  # stdout is only JSON: no summary, no program output
    assert printed == json.loads((tmp_path / "r.json").read_text())


def test_quiet_and_no_progress_when_piped(runs, tmp_path):
    quiet = irlc("run", runs["prog"], "--quiet")
    assert quiet.rc == 0 and quiet.out.strip() == "", quiet.out
    loud = runs["main"]
    assert "triangle done" in loud.out and "status" in loud.out
    # no progress bar when stdout/stderr are not terminals: no carriage returns, no spinners
    assert "\r" not in loud.out and "\r" not in loud.err
    assert loud.err.strip() == "", loud.err
