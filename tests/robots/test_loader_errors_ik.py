"""The [ik] table: which pose-error components the inverse transformation controls."""

from __future__ import annotations

import pytest
from irlc.robots import ROBOTS_DIR, RobotFileError, load_robot
from irlc.runtime.ik import IKParams

# planar3's own file without its [ik] table: a valid robot to add bad tables to.
BASE = (ROBOTS_DIR / "planar3.toml").read_text().split("\n[ik]")[0].rsplit("\n#", 2)[0] + "\n"


def test_planar_robots_control_only_their_plane():
    for name in ("planar3", "planar4"):
        model = load_robot(name)
        assert model.extra["ik"]["task"] == ["x", "y"]
        assert IKParams.for_robot(model).task_rows == (0, 1)
    assert IKParams.for_robot(load_robot("koch11")).task_rows == (0, 1, 2, 3, 4, 5)


@pytest.mark.parametrize(
    ("table", "fragment"),
    [
        ('[ik]\ntask = ["x", "w"]\n', "ik.task[1]"),
        ("[ik]\ntask = []\n", "ik.task"),
        ('[ik]\ntask = ["x", "x"]\n', "twice"),
        ("[ik]\nweights = [1]\n", "ik"),
    ],
)
def test_bad_ik_table_names_file_and_key(tmp_path, table, fragment):
    path = tmp_path / "one.toml"
    path.write_text(BASE + table)
    with pytest.raises(RobotFileError) as info:
        load_robot(str(path))
    assert str(path) in str(info.value)
    assert fragment in str(info.value)
