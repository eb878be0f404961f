"""``irlc run … --mcap``: the run as MCAP with ROS 2 messages, read back with an independent
reader (rosbags' own MCAP reader and CDR decoder; irlc writes with mcap + mcap-ros2-support)
and compared with the trace CSV of the same run."""

from __future__ import annotations

import csv
import itertools
import math
import shutil
import sys
from pathlib import Path

import numpy as np
import pytest
from irlc.cli import main

pytest.importorskip("mcap_ros2", reason="the MCAP writer is the optional extra irlc[mcap]")
storage_mcap = pytest.importorskip("rosbags.rosbag2.storage_mcap", reason="rosbags reads back")
from rosbags.typesys import Stores, get_typestore  # noqa: E402
from scipy.spatial.transform import Rotation  # noqa: E402

PROGRAMS = Path(__file__).resolve().parents[2] / "programs"
# planar4 beside the box of planar4_cell.toml: a PTP, LINs around the box, outputs switched
# between the motions (OUT, PULSE ending after the next motion started), a SIGNAL
PROGRAM = """PROGRAM cell_io;
ROBOT r := planar4;
IMPORT DATALIST planar4_cell;
VAR SIGNAL: gripper;
BEGIN
  R_SPEED := 300;
  R_ACC := 1000;
  MOVE PTP home;
  OUT[3] := TRUE;
  OBSTACLE box;
  MOVE LIN right;
  PULSE(OUT[12], 0.3);
  gripper := TRUE;
  MOVE LIN above;
  OUT[3] := FALSE;
  MOVE LIN right;
  OBSTACLEEND box;
ENDPROGRAM
"""
TYPESTORE = get_typestore(Stores.ROS2_JAZZY)


def _run(folder: Path, *options: str) -> tuple[Path, list[dict]]:
    program = folder / "cell_io.irl"
    if not program.exists():
        program.write_text(PROGRAM, encoding="utf-8")
        shutil.copy(PROGRAMS / "planar4_cell.toml", folder)
    mcap, trace = folder / "run.mcap", folder / "run.csv"
    assert main([str(program), "-q", "--mcap", str(mcap), "--trace", str(trace), *options]) == 0
    with trace.open(encoding="utf-8") as f:
        return mcap, list(csv.DictReader(f))


def read_back(path: Path) -> dict[str, list[tuple[int, object]]]:
    """topic → [(log time ns, message)], decoded by rosbags, each connection's message
    definition checked against the ROS 2 one rosbags knows."""
    reader = storage_mcap.McapReader(path)
    reader.open()
    try:
        out: dict[str, list[tuple[int, object]]] = {}
        for conn in reader.connections:
            expected, _ = TYPESTORE.generate_msgdef(conn.msgtype, ros_version=2)
            assert conn.msgdef.data == expected, conn.msgtype
            out[conn.topic] = []
        for conn, t, data in reader.messages(reader.connections):
            out[conn.topic].append((t, TYPESTORE.deserialize_cdr(data, conn.msgtype)))
        return out
    finally:
        reader.close()


@pytest.fixture(scope="module")
def ideal(tmp_path_factory):
    folder = tmp_path_factory.mktemp("mcap")
    mcap, rows = _run(folder)
    return read_back(mcap), rows, mcap


def _stamp_ns(header) -> int:
    return header.stamp.sec * 1_000_000_000 + header.stamp.nanosec


def _joint_columns(rows: list[dict]) -> np.ndarray:
    return np.array([[float(r[f"a{j}_deg"]) for j in range(1, 5)] for r in rows])


def test_topics_and_their_types(ideal):
    topics, _, _ = ideal
    assert set(topics) == {
        "/joint_states", "/tf", "/tf_static", "/markers", "/outputs/out_3",
        "/outputs/out_12", "/signals/gripper",
    }  # fmt: skip


def test_joint_states_are_the_trace_in_si_stamped_in_simulated_time(ideal):
    topics, rows, _ = ideal
    states = topics["/joint_states"]
    assert len(states) == len(rows)
    times = np.array([float(r["t_s"]) for r in rows])
    for (log_ns, msg), t in zip(states, times, strict=True):
        assert log_ns == _stamp_ns(msg.header) == round(t * 1e9)
        assert list(msg.name) == ["J1", "J2", "J3", "J4"]  # planar4's own names
    q = np.array([msg.position for _, msg in states])
    np.testing.assert_allclose(np.degrees(q), _joint_columns(rows), rtol=1e-9, atol=1e-7)
    qd = np.array([msg.velocity for _, msg in states])
    np.testing.assert_allclose(qd, np.gradient(q, times, axis=0, edge_order=2), atol=1e-9)
    assert np.abs(qd).max() > 0.1  # it moves


def test_base_to_tcp_with_the_static_base_is_the_traces_tcp_pose(ideal):
    topics, rows, _ = ideal
    ((_, static),) = topics["/tf_static"]
    frames = {(f.header.frame_id, f.child_frame_id): f.transform for f in static.transforms}
    world_base = _matrix(frames[("world", "base")])
    tf = topics["/tf"]
    assert len(tf) == len(rows)
    for (_, msg), row in zip(tf, rows, strict=True):
        (f,) = msg.transforms
        assert (f.header.frame_id, f.child_frame_id) == ("base", "tcp")
        pose = world_base @ _matrix(f.transform)
        np.testing.assert_allclose(pose[:3, 3] * 1000, [float(row[k]) for k in ("x_mm", "y_mm",
                                   "z_mm")], atol=1e-5)  # fmt: skip
        a, b, c = Rotation.from_matrix(pose[:3, :3]).as_euler("ZYX", degrees=True)
        want = [float(row[k]) for k in ("a_deg", "b_deg", "c_deg")]
        wrapped = (np.array([a, b, c]) - want + 180.0) % 360.0 - 180.0
        assert np.abs(wrapped).max() < 1e-6


def _matrix(transform) -> np.ndarray:
    r = transform.rotation
    m = np.eye(4)
    m[:3, :3] = Rotation.from_quat([r.x, r.y, r.z, r.w]).as_matrix()
    v = transform.translation
    m[:3, 3] = [v.x, v.y, v.z]
    return m


def test_outputs_and_signals_are_bools_whose_values_are_the_traces_columns(ideal):
    topics, rows, _ = ideal
    for topic, column in (("/outputs/out_3", "out_3"), ("/outputs/out_12", "out_12"),
                          ("/signals/gripper", "signal_gripper")):  # fmt: skip
        switches = [(t, bool(msg.data)) for t, msg in topics[topic]]
        assert switches[0][0] == 0  # a value from the start (FALSE before the first switch)
        assert any(v for _, v in switches)
        for row in rows:
            t = round(float(row["t_s"]) * 1e9)
            value = [v for ts, v in switches if ts <= t + 1][-1]
            assert value == (row[column] == "1"), (topic, row["t_s"])
    pulse = [t for t, _ in topics["/outputs/out_12"]]
    assert pulse[2] - pulse[1] == 300_000_000  # PULSE(OUT[12], 0.3): 0.3 s later FALSE


def test_markers_show_the_box_and_the_programmed_path(ideal):
    topics, rows, _ = ideal
    ((_, msg),) = topics["/markers"]
    by_ns: dict[str, list] = {}
    for m in msg.markers:
        by_ns.setdefault(m.ns, []).append(m)
        assert m.header.frame_id == "world"
    (box,) = by_ns["obstacles"]
    assert box.type == 1  # CUBE, at the data list's centre and size (mm → m)
    p = box.pose.position
    np.testing.assert_allclose([p.x, p.y, p.z], [0.6, -0.15, 0.0], atol=1e-12)
    np.testing.assert_allclose([box.scale.x, box.scale.y, box.scale.z], [0.4, 0.3, 0.2])
    ((_, static),) = topics["/tf_static"]
    assert "obstacle/box" in [f.child_frame_id for f in static.transforms]
    stretches = by_ns["programmed_path"]  # the three LINs: one stretch (no PTP between)
    assert len(stretches) == 1
    points = np.array([[q.x, q.y, q.z] for s in stretches for q in s.points]) * 1000
    assert len(points) > 20
    home = np.array([float(rows[0][k]) for k in ("x_mm", "y_mm", "z_mm")])  # the PTP's
    right, above = np.array([1050.0, -200, 0]), np.array([1000.0, 250, 0])
    corners = [home, right, above, right]
    segments = list(itertools.pairwise(corners))
    off = [min(_distance_to_segment(x, a, b) for a, b in segments) for x in points]
    assert max(off) < 1e-6  # every programmed point lies on the LINs' segments
    for corner in corners:
        assert min(np.linalg.norm(points - corner, axis=1)) < 1.0  # a sample's step
    (tcp,) = by_ns["tcp_path"]
    assert len(tcp.points) == len(rows)


def _distance_to_segment(x, a, b) -> float:
    s = np.clip(np.dot(x - a, b - a) / np.dot(b - a, b - a), 0.0, 1.0)
    return float(np.linalg.norm(x - (a + s * (b - a))))


def test_same_run_same_bytes_and_no_wall_clock(ideal, tmp_path):
    topics, rows, first = ideal
    again, _ = _run(tmp_path)
    assert again.read_bytes() == first.read_bytes()
    end = round(float(rows[-1]["t_s"]) * 1e9)
    assert all(t <= end + 1_000_000_000 for msgs in topics.values() for t, _ in msgs)
    assert [p.name for p in tmp_path.iterdir() if p.name.startswith(".")] == []  # no temp


# a PTP and a short LIN of the track robot (tests/drives_acceptance/programs/line.irl)
DRIVE_PROGRAM = """PROGRAM drive;
ROBOT r := irb6_track;
BEGIN
  MOVE PTP (400, 90, 0, 0, -45, 0);
  { within the A3 drive's 27 deg/s }
  MOVE LIN (-653.063, 934.597, 400, 135, 0, -90) WITH SPEED := 60 WITH ACC := 250;
ENDPROGRAM
"""


@pytest.mark.parametrize("every_step", [False, True])
def test_with_drives_the_joints_are_the_actual_motion_as_in_the_trace(tmp_path, every_step):
    program, mcap, trace = tmp_path / "drive.irl", tmp_path / "d.mcap", tmp_path / "d.csv"
    program.write_text(DRIVE_PROGRAM, encoding="utf-8")
    step = ["--trace-every-step"] if every_step else []
    tolerances = ["--path-tolerance", "200", "--orientation-tolerance", "10"]  # drives lag
    argv = [str(program), "-q", "--drives", "decoupled", *tolerances, "--mcap", str(mcap),
            "--trace", str(trace), *step]  # fmt: skip
    assert main(argv) == 0
    with trace.open(encoding="utf-8") as f:
        rows = list(csv.DictReader(f))
    topics = read_back(mcap)
    states = topics["/joint_states"]
    assert len(states) == len(rows)
    assert [t for t, _ in states] == [round(float(r["t_s"]) * 1e9) for r in rows]
    units = ["mm" if f"a{j}_mm" in rows[0] else "deg" for j in range(1, 7)]  # a track, arms
    scale = np.array([1000.0 if u == "mm" else 180.0 / math.pi for u in units])
    q = np.array([msg.position for _, msg in states]) * scale
    actual = np.array([[float(r[f"a{j}_{u}"]) for j, u in enumerate(units, 1)] for r in rows])
    np.testing.assert_allclose(q, actual, rtol=1e-9, atol=1e-7)
    commanded = np.array([[float(r[f"a{j}_cmd_{u}"]) for j, u in enumerate(units, 1)]
                          for r in rows])  # fmt: skip
    assert np.abs(q - commanded).max() > 1e-6  # the actual motion, not the setpoints
    world_base = _matrix(next(f.transform for f in topics["/tf_static"][0][1].transforms
                               if f.child_frame_id == "base"))  # fmt: skip
    for (_, msg), row in zip(topics["/tf"], rows, strict=True):
        pose = world_base @ _matrix(msg.transforms[0].transform)
        want = [float(row[k]) for k in ("x_mm", "y_mm", "z_mm")]
        np.testing.assert_allclose(pose[:3, 3] * 1000, want, atol=1e-5)


def test_a_missing_writer_is_a_usage_error_naming_the_extra(tmp_path, monkeypatch, capsys):
    (tmp_path / "p.irl").write_text(PROGRAM, encoding="utf-8")
    monkeypatch.setitem(sys.modules, "mcap_ros2.writer", None)  # import fails
    assert main([str(tmp_path / "p.irl"), "--mcap", str(tmp_path / "r.mcap")]) == 3
    err = capsys.readouterr().err
    assert "pip install 'irlc[mcap]'" in err and "Traceback" not in err
    assert not (tmp_path / "r.mcap").exists()


def test_failed_runs_are_written_up_to_the_failure(tmp_path):
    program = tmp_path / "far.irl"
    program.write_text(
        "PROGRAM far;\nROBOT r := planar3;\nBEGIN\n  MOVE LIN POSE(9000, 0, 0, 0, 0, 0);\n"
        "ENDPROGRAM\n",
        encoding="utf-8",
    )
    assert main([str(program), "-q", "--mcap", str(tmp_path / "f.mcap")]) == 2
    topics = read_back(tmp_path / "f.mcap")
    assert len(topics["/joint_states"]) >= 1
    assert all(math.isfinite(v) for _, m in topics["/joint_states"] for v in m.position)
