"""Joint names whose trace columns would coincide with another column are refused.

Regression (adversarial probe): joints named ``a, b, c`` on planar3 wrote ``a_deg``,
``b_deg``, ``c_deg`` twice each (the joints' and the TCP's), and ``--compare``/``--plot``
then misread irlc's own trace.
"""

from __future__ import annotations

import itertools

import pytest
from hypothesis import given
from hypothesis import strategies as st
from irlc.lang import trace_columns as tc

from .conftest import compile_text

PROGRAM = "PROGRAM p;\nROBOT r := {robot};\nTYPE RECORD REAL: {names}; ENDRECORD = MAIN_JOINT;\nBEGIN\nENDPROGRAM\n"  # noqa: E501


def _errors(robot: str, names: str) -> list[str]:
    result = compile_text(PROGRAM.format(robot=robot, names=names))
    return [d.header() for d in result.diagnostics if d.is_error]


@pytest.mark.parametrize(
    ("robot", "names", "error"),
    [
        ("planar3", "a, b, c", "test.irl:3:19: error: joint name 'a' gives the trace column "
                               "a_deg, which is also the TCP's a"),
        ("planar3", "s1, S1_CMD, s3", "test.irl:3:23: error: joint name 'S1_CMD' gives the "
                                      "trace column S1_CMD_deg, which is also a column of "
                                      "joint 's1'"),
        ("planar3", "s1, orientation_error, s3", "joint name 'orientation_error' gives the "
                                                 "trace column orientation_error_deg"),
        ("koch11", "q1, q2, q3, q4, q5, q6, q7, q8, q9, X, q11", "joint name 'X' gives the "
                                                                "trace column X_mm, which is "
                                                                "also the TCP's x"),
    ],
)  # fmt: skip
def test_clashing_joint_names_are_compile_errors(robot, names, error):
    errors = _errors(robot, names)
    assert len(errors) == 1 and error in errors[0], errors


@pytest.mark.parametrize(
    ("robot", "names"),
    [
        ("planar3", "shoulder, elbow, wrist"),
        ("planar3", "path_error, s1_speed, t"),  # revolute: path_error_deg, s1_speed_deg, t_deg
        ("koch11", "q1, q2, q3, q4, q5, q6, q7, q8, q9, a, q11"),  # prismatic a: a_mm
    ],
)
def test_names_with_distinct_columns_compile(robot, names):
    assert _errors(robot, names) == []


_NAME = st.from_regex(r"[A-Za-z][A-Za-z0-9_]{0,6}", fullmatch=True)


@given(st.lists(_NAME, min_size=1, max_size=4), st.lists(st.sampled_from("RP"), min_size=4))
def test_first_clash_is_none_exactly_when_every_column_is_distinct(names, kinds):
    kinds = kinds[: len(names)]
    columns = [c.lower() for c in tc.FIXED]
    for name, kind in zip(names, kinds, strict=True):
        columns += [c.lower() for c in tc.joint_columns(name, kind)]
    distinct = len(set(columns)) == len(columns)
    assert (tc.first_clash(names, kinds) is None) == distinct


def test_the_runtime_header_is_built_from_these_names():
    from irlc.runtime.outputs.results import trace_header

    names, kinds = ("s1", "slide"), ("revolute", "prismatic")
    header = trace_header(names, kinds, drives=True, obstacles={"box": None})
    per_joint = set(
        itertools.chain.from_iterable(
            tc.joint_columns(n, k) for n, k in zip(names, kinds, strict=True)
        )
    )
    assert set(header) - per_joint == {*tc.FIXED} - {"partial"} | {"clearance_box_mm"}
    assert len(header) == len(set(header))
