"""Hostile data lists (issue 11): every malformed file is an error naming the file and key.

And the runtime, which reads the same OBSTACLE record from a (hand-written) .ird, applies
the same physical range (``irdata.obstacle_range_problem``).
"""

from __future__ import annotations

from pathlib import Path

import pytest
from irlc.runtime.model.obstacles import from_program_units

from .conftest import compile_text

SOURCE = "PROGRAM t;\nROBOT r := six;\nIMPORT DATALIST cell;\nBEGIN\nENDPROGRAM\n"


def _errors(tmp_path: Path, toml: str) -> list[str]:
    (tmp_path / "cell.toml").write_text(toml, encoding="utf-8")
    result = compile_text(SOURCE, str(tmp_path / "t.irl"))
    assert not result.ok
    for d in result.errors:
        assert d.file.endswith("cell.toml") and d.span is not None, d
    return [d.message for d in result.errors]


@pytest.mark.parametrize(
    ("body", "message"),
    [
        (  # unhashable: `kind not in OBSTACLE_KEYS` was a TypeError
            "kind = [1, 2]\ncenter = [0, 0, 0]",
            "key 'obstacles.o.kind': expected one of point, sphere, box, capsule, plane, "
            "got [1, 2]",
        ),
        (  # crashed the trace writer (a non-finite clearance)
            'kind = "sphere"\ncenter = [0, 0, 1e308]\nradius = 10',
            "key 'obstacles.o.center': 1e+308 mm is outside the physical range of a "
            "coordinate (within ±1e+06 mm)",
        ),
        (
            'kind = "sphere"\ncenter = [0, 0, 0]\nradius = 1e300',
            "key 'obstacles.o.radius': 1e+300 mm is outside the physical range of a length "
            "(0.001 to 1e+06 mm)",
        ),
        (
            'kind = "capsule"\na = [0, 0, 0]\nb = [0, 0, 1]\nradius = 1e-320',
            "key 'obstacles.o.radius': 9.99989e-321 mm is outside the physical range of a "
            "length (0.001 to 1e+06 mm)",
        ),
        (
            'kind = "box"\ncenter = [0, 0, 0]\nsize = [1, 1, 2e6]',
            "key 'obstacles.o.size': 2e+06 mm is outside the physical range of a length "
            "(0.001 to 1e+06 mm)",
        ),
        (
            'kind = "plane"\npoint = [-1e7, 0, 0]\nnormal = [0, 0, 1]',
            "key 'obstacles.o.point': -1e+07 mm is outside the physical range of a "
            "coordinate (within ±1e+06 mm)",
        ),
    ],
)
def test_bad_obstacle_is_an_error_at_its_key(tmp_path: Path, body: str, message: str) -> None:
    assert _errors(tmp_path, f"[obstacles.o]\n{body}\n") == [message]


def test_obstacles_at_the_ends_of_the_range_load(tmp_path: Path) -> None:
    (tmp_path / "cell.toml").write_text(
        '[obstacles.s]\nkind = "sphere"\ncenter = [1e6, -1e6, 0]\nradius = 1e-3\n'
        '[obstacles.p]\nkind = "plane"\npoint = [0, 0, 0]\nnormal = [1e308, 1e308, 0]\n',
        encoding="utf-8",
    )
    assert compile_text(SOURCE, str(tmp_path / "t.irl")).ok


def test_the_runtime_applies_the_same_range() -> None:
    with pytest.raises(ValueError, match=r"obstacle o\.center: 1e\+308 mm is outside"):
        from_program_units("o", {"kind": "point", "center": (0.0, 0.0, 1e308)})
    with pytest.raises(ValueError, match=r"obstacle o\.size: 1e\+300 mm is outside"):
        from_program_units("o", {"kind": "box", "center": (0, 0, 0), "size": (1, 1, 1e300)})
    with pytest.raises(ValueError, match=r"obstacle o\.radius must be > 0"):
        from_program_units("o", {"kind": "sphere", "center": (0, 0, 0), "radius": (1.0, 2.0)})
    with pytest.raises(ValueError, match="kind must be one of"):
        from_program_units("o", {"kind": [1, 2]})


def test_a_huge_plane_normal_is_normalised_without_overflow() -> None:
    plane = from_program_units(
        "o", {"kind": "plane", "point": (0, 0, 0), "normal": (1e308, 1e308, 0.0)}
    )
    assert plane.normal == pytest.approx([0.5**0.5, 0.5**0.5, 0.0])


def test_a_300_character_data_list_name_is_not_found_at_its_clause(tmp_path: Path) -> None:
    # Path.is_file() raised OSError (ENAMETOOLONG) in datalist.find.
    name = "d" * 300
    src = f"PROGRAM t;\nROBOT r := six;\nIMPORT DATALIST {name};\nBEGIN\nENDPROGRAM\n"
    result = compile_text(src, str(tmp_path / "t.irl"))
    (err,) = result.errors
    assert (err.line, err.column) == (3, 17)
    assert err.message == f"data list '{name}.toml' not found"


@pytest.mark.parametrize("robot", ["d" * 300, "'" + "d" * 300 + ".toml'"])
def test_a_300_character_robot_name_is_an_error_at_the_robot_clause(robot: str) -> None:
    from irlc.lang import compile_source
    from irlc.robots import resolver

    src = f"PROGRAM t;\nROBOT r := {robot};\nBEGIN\nENDPROGRAM\n"
    result = compile_source(src, "t.irl", resolve_robot=resolver("."))
    (err,) = result.errors
    assert (err.line, err.column) == (2, 12)
    assert err.message.startswith("cannot use robot 'ddd")


@pytest.mark.parametrize(
    ("entry", "message"),
    [
        ('k1 = [0, 90, "x", 0, 0, 0]', "key 'joints.k1': value 3 is not a number: 'x' (one value "
                                       "per joint)"),
        ("k1 = [0, 90, true, 0, 0, 0]", "key 'joints.k1': value 3 is not a number: true (one "
                                        "value per joint)"),
        ('k1 = "home"', "key 'joints.k1': expected one value per joint, got 'home'"),
    ],
)  # fmt: skip
def test_a_value_that_is_no_number_is_named_by_its_place(tmp_path, entry, message):
    """Regression (probe): `[0, 90, "x"]` read "expected one value per joint, got a list of
    3 values" — for a list of one value per joint."""
    assert _errors(tmp_path, f"[joints]\n{entry}\n") == [message]


def test_a_rejected_entry_is_one_error_not_also_an_unknown_name(tmp_path):
    """Regression (probe): a data-list entry that failed its check was a second error,
    "unknown name 'k1'", wherever the program used it."""
    (tmp_path / "cell.toml").write_text('[joints]\nk1 = [0, 90, "x", 0, 0, 0]\n', encoding="utf-8")
    source = SOURCE.replace("BEGIN\n", "BEGIN\n  MOVE PTP k1;\n")
    result = compile_text(source, str(tmp_path / "t.irl"))
    assert [d.message for d in result.errors] == [
        "key 'joints.k1': value 3 is not a number: 'x' (one value per joint)"
    ]
