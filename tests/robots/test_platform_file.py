"""A robot file's ``[platform]`` (docs/robots.md) and the library's platform robots.

* mobile8's platform is X, Y (world x, y of link 2); as6_track's is the track T (world y of
  link 1) — and as6_track is as6 on that track: its FK equals as6's FK moved along y by
  the track's value (the file's claim), at random configurations;
* the affine map ``c = c₀ + A·θ_a`` agrees with the robot's own FK at random
  configurations, ``joints_for`` inverts it, ``problem`` names the joint and bound;
* a bad ``[platform]`` is a ``RobotFileError`` naming the key and its line;
* ``irlc robot`` shows the platform.
"""

from __future__ import annotations

import numpy as np
import pytest
from irlc.cli import main
from irlc.robots import RobotFileError, load_robot
from irlc.runtime.model.kinematics import Kinematics

rng = np.random.default_rng(27)


def _random_q(model) -> np.ndarray:
    lim = model.position_limits
    return rng.uniform(lim[:, 0], lim[:, 1])


def test_as6_track_is_as6_moved_along_the_track():
    track, arm = load_robot("as6_track"), load_robot("as6")
    kin_t, kin_a = Kinematics(track), Kinematics(arm)
    for _ in range(20):
        q = _random_q(track)
        expected = kin_a.tcp(q[1:])
        expected[1, 3] += q[0]  # the carriage slides along the world y axis
        np.testing.assert_allclose(kin_t.tcp(q), expected, atol=1e-12)
        # every arm link too (link i+1 of the track robot is as6's link i ≥ 1; the
        # carriage, link 1, is where as6's base is)
        frames_t, frames_a = kin_t.link_frames(q), kin_a.link_frames(q[1:])
        moved = frames_a.copy()
        moved[:, 1, 3] += q[0]
        np.testing.assert_allclose(frames_t[2:], moved[1:], atol=1e-12)
        np.testing.assert_allclose(frames_t[1][:3, 3], moved[0][:3, 3], atol=1e-12)
    assert [j.name for j in track.joints[1:]] == [j.name for j in arm.joints]
    for jt, ja in zip(track.joints[1:], arm.joints, strict=True):
        assert jt.limits == ja.limits


@pytest.mark.parametrize(
    ("name", "joints", "coords", "link"),
    [("mobile8", ("X", "Y"), ("x", "y"), 2), ("as6_track", ("T",), ("y",), 1)],
)
def test_library_platforms_match_the_robots_own_kinematics(name, joints, coords, link):
    model = load_robot(name)
    platform = model.platform
    assert platform.joint_names == joints and platform.coordinates == coords
    assert platform.link == link and platform.dimension == len(joints)
    kin = Kinematics(model)
    rows = [("x", "y", "z").index(c) for c in coords]
    for _ in range(20):
        q = _random_q(model)
        frame = kin.link_frames(q)[link]
        point = frame[:3, :3] @ platform.point + frame[:3, 3]
        np.testing.assert_allclose(platform.coordinates_at(q), point[rows], atol=1e-12)
        np.testing.assert_allclose(platform.joints_for(point[rows]), q[: len(joints)], atol=1e-12)
    lo, hi = model.position_limits[: len(joints)].T
    np.testing.assert_allclose(platform.ranges(), np.column_stack((lo, hi)), atol=1e-12)


def test_problem_names_the_joint_and_the_bound():
    platform = load_robot("mobile8").platform
    assert platform.problem([4999.0, -4999.0]) is None
    assert platform.problem([0.0, 5000.5]) == (
        "the platform target (x 0, y 5000.5) mm is outside the platform's limits: it needs "
        "joint Y at 5000.5 mm, beyond its limit (max 5000 mm)"
    )
    narrowed = np.tile([-0.1, 0.1], (8, 1))
    message = platform.problem([150.0, 0.0], narrowed, ["a1 (X)", "a2 (Y)"], "the JOINTLIMIT")
    assert "needs joint a1 (X) at 150 mm, beyond the JOINTLIMIT (max 100 mm)" in message
    assert "2 finite coordinates" in platform.problem([1.0])
    assert "2 finite coordinates" in platform.problem([1.0, float("nan")])
    track = load_robot("as6_track").platform
    assert track.problem([0.0]) is None and "(min 0 mm)" in track.problem([-0.5])


BAD = [
    ('joints = ["Y"]\ncoordinates = ["y"]', "platform.joints[0]",
     "the platform's joints are the chain's first joints, in order: joint 1 is 'X', not 'Y'"),
    ('joints = ["W"]\ncoordinates = ["y"]', "platform.joints[0]", "no joint named 'W'"),
    ('joints = ["X", "Y", "A1"]\ncoordinates = ["x", "y", "z"]', "platform.joints[2]",
     "joint 'A1' is revolute: a platform of prismatic joints only"),
    ('joints = ["X", "Y"]\ncoordinates = ["x"]', "platform.coordinates",
     "one coordinate per platform joint: 2 joint(s), 1 coordinate(s)"),
    ('joints = ["X", "Y"]\ncoordinates = ["x", "z"]', "platform.coordinates",
     "the platform joints X, Y do not move the platform point along x, z independently"),
    ('joints = ["X", "Y"]\ncoordinates = ["x", "x"]', "platform.coordinates",
     "a name is listed twice"),
    ('joints = ["X", "Y"]\ncoordinates = ["x", "w"]', "platform.coordinates[1]",
     "expected one of x, y, z"),
    ('joints = ["X", "Y"]', "platform", "missing key 'coordinates'"),
    ('joints = ["X", "Y"]\ncoordinates = ["x", "y"]\nheading = 1', "platform.heading",
     "unknown key"),
    ('joints = ["X", "Y"]\ncoordinates = ["x", "y"]\npoint = [0, 0]', "platform.point",
     "expected 3 numbers"),
]  # fmt: skip


@pytest.mark.parametrize(("table", "key", "message"), BAD)
def test_a_bad_platform_table_names_the_key_and_its_line(tmp_path, table, key, message):
    path = tmp_path / "m.toml"
    path.write_text(f'[robot]\nextends = "mobile8"\n\n[platform]\n{table}\n')
    with pytest.raises(RobotFileError) as info:
        load_robot(str(path))
    err = info.value
    assert err.key == key and message in err.message
    assert err.line is not None and err.line >= 4  # in the [platform] table


def test_the_platform_needs_the_task_rows_left_to_the_arm(tmp_path):
    """A slide carrying 3 revolute joints (4 joints) with a 4-row task: the platform's row
    makes 5 rows for 4 joints — refused."""
    path = tmp_path / "p.toml"
    path.write_text(
        '[robot]\nname = "p"\nchain = "axes"\n[ik]\ntask = ["x", "y", "z", "rx"]\n'
        '[platform]\njoints = ["S"]\ncoordinates = ["x"]\n'
        '[[joints]]\nname = "S"\nkind = "prismatic"\naxis = "x"\nposition = [-1, 1]\n'
        "speed = 1\naccel = 1\n"
        + "".join(
            f'[[joints]]\nname = "R{i}"\nkind = "revolute"\naxis = "z"\nlink = [0.3, 0, 0]\n'
            "position = [-90, 90]\nspeed = 90\naccel = 90\n"
            for i in range(3)
        )
    )
    rows = "the task's 4 pose rows and the platform's 1 rows are more than the robot's 4"
    with pytest.raises(RobotFileError, match=rows):
        load_robot(str(path))


def test_irlc_robot_shows_the_platform(capsys):
    assert main(["robot", "as6_track"]) == 0
    out = " ".join(capsys.readouterr().out.split())
    assert "platform — overhead linear track along the world y axis: joints a1 (T)" in out
    assert "WITH PLATFORM := y [mm]: the world y of point [0.0, 0.0, 0.0] mm of link 1" in out
    assert "range y 0 … 2500 mm" in out
    assert main(["robot", "mobile8"]) == 0
    out = " ".join(capsys.readouterr().out.split())
    assert "WITH PLATFORM := (x, y) [mm]" in out and "range x -5000 … 5000, y -5000 … 5000" in out
    assert main(["robot", "koch11"]) == 0
    assert "platform: none in the file" in capsys.readouterr().out
