"""The one "position limits contain the state" check (runtime/model/limit_check.py): one
tolerance (1e-9 m | rad, the IK box's slack), one message, used by the interpreter."""

from __future__ import annotations

import math

import numpy as np
from irlc.runtime.model.limit_check import (
    TOLERANCE,
    first_outside,
    limit_failure,
    program_tolerances,
)

from .test_interpreter_fakes import FakeController, failure, run
from .test_interpreter_motion import program

OPTON = "main: L1 PUSHC 11\nL1 PUSHC 13\nL1 OPTON JOINTLIMIT\nL2 END"  # a1 ≥ 15 deg


def test_the_tolerance_in_program_units_is_the_si_one_converted():
    tol = program_tolerances(["revolute", "prismatic"])
    assert np.allclose(tol, [math.degrees(TOLERANCE), TOLERANCE * 1e3], rtol=1e-12, atol=0)


def test_first_outside_names_the_first_joint_beyond_its_tolerance():
    lo, hi = [0.0, 0.0, 0.0], [1.0, 1.0, 1.0]
    assert first_outside([1.0 + 0.5e-9, -0.5e-9, 0.5], lo, hi) is None
    out = first_outside([0.5, 1.0 + 2e-9, -1.0], lo, hi)
    assert (out.joint, out.value, out.bound, out.below, out.side) == (1, 1.0 + 2e-9, 1.0, 0, "max")
    out = first_outside([0.5, 0.5, -2e-9], lo, hi)
    assert (out.joint, out.bound, out.side) == (2, 0.0, "min")


def test_the_message_names_joint_value_and_bound():
    out = first_outside([30.0], [-10.0], [25.0])
    err = limit_failure("JOINTLIMIT excludes the current state", out, "a3", "30 deg", "25 deg")
    assert err.message == (
        "JOINTLIMIT excludes the current state: joint a3 is at 30 deg, above the upper bound 25 deg"
    )
    assert err.constraint == "joint a3 position max 25 deg"


def test_jointlimit_uses_the_one_tolerance():
    # 1e-7 deg below the bound is 1.7e-9 rad: outside (the next motion's check and the IK
    # box, at 1e-9 rad, exclude it too); 1e-8 deg (1.7e-10 rad) is rounding, inside.
    err = failure(program(OPTON), FakeController(joints=(15.0 - 1e-7, 0.0, 0.0)))
    assert err.message.startswith("JOINTLIMIT excludes the current state: joint a1 is at")
    assert err.constraint == "joint a1 position min 15.0 deg"
    run(program(OPTON), FakeController(joints=(15.0 - 1e-8, 0.0, 0.0)))
