"""Round-off of a zero is shown as 0 (runtime/units.py ``shown``/``fixed``): no
"1.99e-32 deg" in reports and limit messages, no "-0.0000" in ``irlc fk`` tables."""

from __future__ import annotations

import math

from irlc.cli import main
from irlc.robots import load_robot
from irlc.runtime import units
from irlc.runtime.ik.limits import format_joint_value
from irlc.runtime.outputs.results import rnd
from irlc.summary import shown_number


def test_values_below_the_threshold_are_zero_without_a_sign():
    for v in (1.99e-32, -1.99e-32, -1e-17, 4.9e-13, -0.0):
        out = units.shown(v)
        assert out == 0.0 and math.copysign(1.0, out) == 1.0
    assert units.shown(1e-12) == 1e-12  # above the threshold: kept
    assert units.shown(-2.5) == -2.5
    assert math.isnan(units.shown(math.nan)) and units.shown(math.inf) == math.inf
    # the threshold scales with the unit: 1e-14 m is 1e-11 mm (kept), 1e-14 mm is not
    assert units.shown(1e-14, units.MM) == 1e-14 and units.shown(1e-14) == 0.0


def test_fixed_decimals_never_print_a_negative_zero():
    assert units.fixed(-1e-17, 4) == "0.0000"
    assert units.fixed(-0.00004, 4) == "0.0000"  # rounds to −0 at 4 decimals
    assert units.fixed(-0.00006, 4) == "-0.0001"
    assert units.fixed(915.0, 2) == "915.00"


def test_report_summary_and_limit_messages_snap():
    assert rnd(1.99e-32) == 0.0 and rnd(-3e-20) == 0.0 and rnd(-0.5) == -0.5
    assert shown_number(-1e-17, ".2f") == "0.00" and shown_number(1.99e-32) == "0"
    model = load_robot("irb6")
    assert format_joint_value(model, 0, 1.99e-32 * units.DEG, 0) == "0 deg"


def test_fk_table_has_no_negative_zero(capsys):
    # irb6 at a1 = 90° (a = −0° before) and a1 = 180° (x = −0 mm before)
    for a1 in ("90", "180"):
        assert main(["fk", "irb6", a1, "0", "0", "0", "0"]) == 0
        out = capsys.readouterr().out
        assert "-0.0000" not in out and "0.0000" in out
