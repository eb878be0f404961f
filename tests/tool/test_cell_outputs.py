"""The figures, the animation and the exports of a cell (several robots), from the command
line, checked against the run's own trace and against placements and forward kinematics
computed here: each robot's library model (unplaced) and its ``AT`` pose built with scipy."""

from __future__ import annotations

import csv
import json
import re
import subprocess
import tempfile

import numpy as np
import pytest
from irlc.animate import STATUS_ID
from irlc.cli import main
from irlc.robots import load_robot
from irlc.runtime.model.kinematics import Kinematics
from scipy.spatial.transform import Rotation

from tests.tool.test_animate import CHROMIUM, FLAGS

PROGRAM = """PROGRAM mixed;
ROBOT arm := panda AT (0, -1500, 100, 90, 0, 10);
ROBOT flat := planar3 AT (2500, 0, 300, 180, 0, 0);
VAR POSE: p;
BEGIN
  R_SPEED := 300;
  p := arm.R_ACT_POSE;
  MOVE arm LIN p : (0, -150, 0, 0, 0, 0);
  MOVE flat PTP (20, 70, -60) AND arm LIN p;
  OUT[2] := TRUE;
  MOVE flat LIN POSE(1000, 500, 300, 0, 0, 0);
ENDPROGRAM
"""
AT = {"arm": (0, -1500, 100, 90, 0, 10), "flat": (2500, 0, 300, 180, 0, 0)}
LIBRARY = {"arm": "panda", "flat": "planar3"}
JOINTS = {"arm": 7, "flat": 3}


def placement(at) -> np.ndarray:
    """AT (mm, ZYX deg) as a 4×4 transform in m, by scipy."""
    t = np.eye(4)
    t[:3, :3] = Rotation.from_euler("ZYX", at[3:], degrees=True).as_matrix()
    t[:3, 3] = np.array(at[:3]) / 1000.0
    return t


@pytest.fixture(scope="module")
def cell(tmp_path_factory):
    folder = tmp_path_factory.mktemp("cell_outputs")
    program = folder / "mixed.irl"
    program.write_text(PROGRAM, encoding="utf-8")
    files = {k: folder / v for k, v in (("report", "r.json"), ("trace", "t.csv"),
             ("animate", "a.html"), ("export", "e.json"), ("plot", "figs"))}  # fmt: skip
    args = [str(program), "-q", "--report", str(files["report"]), "--trace", str(files["trace"]),
            "--animate", str(files["animate"]), "--export-trajectory", str(files["export"]),
            "--plot", str(files["plot"])]  # fmt: skip
    assert main(args) == 0
    with files["trace"].open(encoding="utf-8") as f:
        rows = list(csv.DictReader(f))
    return files, rows


def _joints(rows, name: str) -> np.ndarray:
    """A robot's joint columns of the trace, rad (every joint here is revolute)."""
    return np.radians([[float(r[f"{name}_a{j}_deg"]) for j in range(1, JOINTS[name] + 1)]
                       for r in rows])  # fmt: skip


def test_the_trajectory_export_holds_each_robot_its_names_placement_and_the_trace(cell):
    files, rows = cell
    doc = json.loads(files["export"].read_text(encoding="utf-8"))
    assert doc["format"] == "irlc-joint-trajectory 1" and doc["status"] == "ok"
    assert [r["name"] for r in doc["robots"]] == ["arm", "flat"]
    arm, flat = doc["robots"]
    assert arm["joint_names"] == [f"panda_joint{i}" for i in range(1, 8)]
    assert flat["joint_names"] == ["J1", "J2", "J3"]
    assert flat["program_joint_names"] == ["a1", "a2", "a3"]
    times = np.array([float(r["t_s"]) for r in rows])
    for robot in doc["robots"]:
        name = robot["name"]
        assert robot["robot"] == LIBRARY[name] and robot["at"] == list(AT[name])
        want = placement(AT[name])
        p = robot["placement"]
        got = np.eye(4)
        got[:3, :3] = Rotation.from_quat(p["rotation"]).as_matrix()
        got[:3, 3] = p["translation"]
        np.testing.assert_allclose(got, want, atol=1e-8)
        positions = np.array([pt["positions"] for pt in robot["points"]])
        np.testing.assert_allclose(positions, _joints(rows, name), atol=1e-8)
        stamps = [pt["time_from_start"] for pt in robot["points"]]
        np.testing.assert_allclose([s["sec"] + s["nanosec"] * 1e-9 for s in stamps], times)


def test_the_animation_places_every_robot_by_at_and_shows_the_clearance(cell):
    files, rows = cell
    html = files["animate"].read_text(encoding="utf-8")
    text = re.search(r'<script id="irlc-data" type="application/json">(.*?)</script>', html, re.S)
    data = json.loads(text.group(1))
    assert [r["name"] for r in data["robots"]] == ["arm", "flat"]
    times = np.array([float(r["t_s"]) for r in rows])
    assert data["t"] == [round(float(t), 3) for t in times]  # all frames kept (< 2000)
    for robot in data["robots"]:
        name = robot["name"]
        q = _joints(rows, name)
        np.testing.assert_allclose(np.radians(robot["joints"]), q, atol=np.radians(0.006))
        kin = Kinematics(load_robot(LIBRARY[name]))  # the file's robot, unplaced
        at = placement(AT[name])
        for k in (0, len(rows) // 2, len(rows) - 1):
            origins = at @ kin.link_frames(q[k])[:, :, 3].T  # (4, n + 1) homogeneous
            pts = np.array(robot["points"][k])
            assert np.abs(pts[: kin.n + 1] - origins[:3].T * 1000).max() <= 0.6, (name, k)
            tcp = [float(rows[k][f"{name}_{c}_mm"]) for c in "xyz"]
            assert np.abs(pts[kin.n + 1] - tcp).max() <= 0.6
    c = data["clearance"]
    trace_mm = np.array([float(r["clearance_mm"]) for r in rows])
    np.testing.assert_allclose(c["mm"], trace_mm, atol=0.051)
    gaps = [np.linalg.norm(np.subtract(a, b)) for a, b in zip(c["a"], c["b"], strict=True)]
    np.testing.assert_allclose(gaps, np.abs(c["mm"]), atol=1.0)  # rounded to 1 mm points
    k = int(np.argmin(trace_mm))
    report = json.loads(files["report"].read_text(encoding="utf-8"))["clearance"]
    assert c["pair"][k] == (f"{report['robot_a']} link {report['link_a']} – "
                            f"{report['robot_b']} link {report['link_b']}")  # fmt: skip


def test_the_figures_of_a_cell(cell):
    files, _ = cell
    names = sorted(p.name for p in files["plot"].iterdir())
    per_robot = [f"{r}_{f}" for r, n in (("arm", "1-6"), ("flat", "1-3"))
                 for f in (f"joint_positions_{n}.png", f"joint_speeds_{n}.png",
                           f"joint_accels_{n}.png", "tcp_path_speed.png")]  # fmt: skip
    per_robot += ["arm_joint_positions_7-7.png", "arm_joint_speeds_7-7.png",
                  "arm_joint_accels_7-7.png"]  # fmt: skip
    assert names == sorted([*per_robot, "tcp_path_3d.png", "clearance.png", "cycle_time.png"])
    for path in files["plot"].iterdir():
        assert path.read_bytes().startswith(b"\x89PNG") and path.stat().st_size > 5000


def test_the_mcap_file_of_a_cell_read_back(cell, tmp_path):
    pytest.importorskip("mcap_ros2", reason="the MCAP writer is the optional extra irlc[mcap]")
    pytest.importorskip("rosbags.rosbag2.storage_mcap", reason="rosbags reads back")
    from tests.tool.test_mcap import _matrix, read_back

    files, rows = cell
    out = tmp_path / "cell.mcap"
    assert main([str(files["report"].parent / "mixed.irl"), "-q", "--mcap", str(out)]) == 0
    topics = read_back(out)
    assert {"/arm/joint_states", "/flat/joint_states", "/tf", "/tf_static", "/markers",
            "/outputs/out_2"} == set(topics)  # fmt: skip
    ((_, static),) = topics["/tf_static"]
    frames = {(f.header.frame_id, f.child_frame_id): f.transform for f in static.transforms}
    for name in ("arm", "flat"):
        states = topics[f"/{name}/joint_states"]
        assert len(states) == len(rows)
        q = np.array([msg.position for _, msg in states])
        np.testing.assert_allclose(q, _joints(rows, name), atol=1e-9)
        base = _matrix(frames[("world", f"{name}/base")])
        file_base = np.asarray(load_robot(LIBRARY[name]).base, dtype=float)
        np.testing.assert_allclose(base, placement(AT[name]) @ file_base, atol=1e-9)
        for k in (0, len(rows) - 1):
            _, msg = topics["/tf"][k]
            tf = {(f.header.frame_id, f.child_frame_id): f.transform for f in msg.transforms}
            pose = base @ _matrix(tf[(f"{name}/base", f"{name}/tcp")])
            want = [float(rows[k][f"{name}_{c}_mm"]) for c in "xyz"]
            np.testing.assert_allclose(pose[:3, 3] * 1000, want, atol=1e-5)
    ((_, markers),) = topics["/markers"]
    spaces = {m.ns for m in markers.markers}
    assert {
        "arm/programmed_path",
        "arm/tcp_path",
        "flat/programmed_path",
        "flat/tcp_path",
    } <= spaces


def test_a_cell_s_outputs_are_deterministic(cell, tmp_path):
    files, _ = cell
    export, page = tmp_path / "e.json", tmp_path / "a.html"
    program = str(files["report"].parent / "mixed.irl")
    assert main([program, "-q", "--export-trajectory", str(export), "--animate", str(page)]) == 0
    assert export.read_bytes() == files["export"].read_bytes()
    assert page.read_bytes() == files["animate"].read_bytes()


@pytest.mark.skipif(CHROMIUM is None, reason="chromium is not installed")
def test_the_cell_animation_runs_in_headless_chromium(cell):
    files, _ = cell
    url = files["animate"].resolve().as_uri() + "#t=1.5"
    with tempfile.TemporaryDirectory() as profile:
        dom = subprocess.run(
            [CHROMIUM, *FLAGS, f"--user-data-dir={profile}", "--virtual-time-budget=3000",
             "--dump-dom", url],
            capture_output=True, text=True, timeout=90,
        ).stdout  # fmt: skip
    assert f'<div id="{STATUS_ID}">ok</div>' in dom
    info = re.search(r'<span id="info">([^<]*)</span>', dom).group(1)
    assert "t = 1.50 s" in info and "clearance" in info and " mm (" in info
    assert "arm a1 (panda_joint1)" in dom and "flat a3 (J3)" in dom
