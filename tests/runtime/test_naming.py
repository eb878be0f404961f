"""The joint naming rule: program names first, the robot file's name beside where it differs."""

from irlc.runtime.model.naming import JointNaming, default_names


def test_default_names_are_a1_to_an():
    assert default_names(3) == ("a1", "a2", "a3")


def test_label_shows_robot_name_only_where_it_differs():
    naming = JointNaming.of(["panda_joint1", "A2", "x"], ["a1", "a2", "x"])
    assert naming.label(0) == "a1 (panda_joint1)"
    assert naming.label(1) == "a2"  # case-insensitively the same
    assert naming.label(2) == "x"
    assert naming.labels([0, 2]) == "a1 (panda_joint1), x"


def test_program_names_of_wrong_length_fall_back_to_defaults():
    naming = JointNaming.of(["J1", "J2"], ["only_one"])
    assert naming.program == ("a1", "a2")
    assert naming.name(1) == "a2"


def test_joint_label_without_a_known_robot_name_is_the_program_name():
    from irlc.runtime.model.naming import joint_label

    assert joint_label("a5", "A3") == "a5 (A3)"
    assert joint_label("a5", None) == "a5" and joint_label("a5", "") == "a5"
