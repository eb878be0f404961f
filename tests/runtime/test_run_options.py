"""run.check_run_option: the checks run_code applies to its options, as a message naming
the option (a study's [run] values use it: frontdoor/study/paths.py)."""

from __future__ import annotations

import math

import pytest
from irlc.runtime.run import RunSetupError, check_run_option, run_code

from .conftest import Ird

CASES = [  # (option, a value run_code accepts, one it rejects)
    ("ipo", 0.01, -1.0),
    ("override", 50.0, 150.0),
    ("drives", "ideal", "fast"),
    ("instruction_budget", 1000, 0),
    ("path_tolerance", 0.1, 0.0),
    ("orientation_tolerance", 0.5, -1.0),
    ("max_time", 10.0, float("inf")),
]


@pytest.mark.parametrize(("key", "good", "bad"), CASES)
def test_the_option_checks_are_run_codes(planar3, key, good, bad):
    code = Ird("planar3", "RRR").op(1, "END").code_object()
    assert check_run_option(key, good) is None
    run_code(code, robot=planar3, **{key: good})  # accepted by the run itself
    message = check_run_option(key, bad)
    assert isinstance(message, str) and message
    with pytest.raises(RunSetupError):
        run_code(code, robot=planar3, **{key: bad})


def test_messages_name_the_option():
    assert check_run_option("max_time", 0) == "max_time must be a positive number of seconds, got 0"
    assert check_run_option("instruction_budget", 1.5) == (
        "instruction_budget must be a positive integer, got 1.5"
    )
    assert check_run_option("drives", "fast").startswith("expected one of ideal")
    assert check_run_option("seed_config", [0, "x"]).startswith("expected a list of finite")
    assert check_run_option("seed_config", [0.0, 90, -90]) is None
    assert check_run_option("colour", 1) == "unknown run option 'colour'"


@pytest.mark.parametrize("key", ["max_time", "path_tolerance", "orientation_tolerance"])
@pytest.mark.parametrize("value", [10**400, -(10**400)], ids=["huge", "minus_huge"])
def test_an_integer_beyond_a_float_is_refused_not_an_overflow(key, value):
    # a golden expectation's or a study's options hold integers of any size (JSON, TOML):
    # an OverflowError, exit 4, before; the number is described, never echoed
    message = check_run_option(key, value)
    assert message.startswith(f"{key} must be a positive number of"), message
    assert message.endswith("got an integer of about 401 digits")
    assert check_run_option("seed_config", [value, 0.0]) == (
        "expected a list of finite numbers (deg | mm), got [an integer of about 401 digits, 0.0]"
    )
    assert "401 digits" in check_run_option("max_cycles", -abs(value))


@pytest.mark.parametrize(
    ("key", "value", "shown"),
    [("ipo", math.nan, "not-a-number"), ("override", math.inf, "infinity"), ("ipo", -1.0, "-1.0")],
)
def test_a_bad_ipo_or_override_is_described_never_nan_or_inf(planar3, key, value, shown):
    code = Ird("planar3", "RRR").op(1, "END").code_object()
    with pytest.raises(RunSetupError) as err:
        run_code(code, robot=planar3, **{key: value})
    assert str(err.value).startswith(f"--{key} {shown}: the value must be in")


def test_a_seed_configuration_beyond_the_limits_is_a_setup_error(planar3):
    """Regression (adversarial probe): `--seed-config "1e5 0 0"` failed the program's first
    statement at run time (exit 2), not the option (exit 3)."""
    code = Ird("planar3", "RRR").op(1, "END").code_object()
    upper = math.degrees(planar3.position_limits[0, 1])
    with pytest.raises(RunSetupError) as info:
        run_code(code, robot=planar3, seed_config=[upper + 1.0, 0.0, 0.0])
    assert str(info.value) == (
        f"--seed-config: joint a1 (J1) = {upper + 1.0:g} deg is above the upper bound "
        f"{upper:g} deg of the robot's position limits"
    )
    run_code(code, robot=planar3, seed_config=[upper, 0.0, 0.0])  # on the bound: inside
