"""One range table for the numeric settings (lang/settings.py, re-exported as
controller.SETTING_RANGES), used by the checker for constants, POPSYS, WITH clauses, the
executor and ``--ipo`` (regression: ``R_IPO := 1e-7`` was accepted by the interpreter and
failed at the next MOVE, naming that line)."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from irlc.runtime.commands import SETTING_RANGES, check_setting, setting_error
from irlc.runtime.errors import RunFailure
from irlc.runtime.run import RunSetupError, run_code

from .conftest import Ird


@pytest.mark.parametrize(
    ("field", "value", "ok"),
    [
        ("speed", 0.0, False),
        ("speed", 1e-12, True),
        ("speed", math.inf, False),  # sane upper bounds (lang/settings.py)
        ("speed", 1e5, True),
        ("speed", 1e5 * (1 + 1e-12), False),
        ("time", 86400.0, True),
        ("time", 86401.0, False),
        ("speed_ptp", 100.0, True),
        ("speed_ptp", 100.0000001, False),
        ("acc_ptp", -1.0, False),
        ("ipo", 1e-5, True),
        ("ipo", 0.99999e-5, False),
        ("ipo", 1.0, True),
        ("ipo", 1.0 + 1e-12, False),
        ("ipo", math.nan, False),
        ("ipo", True, False),
        ("time", 0.0, False),
    ],
)
def test_range_table_bounds(field, value, ok):
    assert (setting_error(field, value) is None) is ok
    assert (value in SETTING_RANGES[field]) is ok or isinstance(value, bool)


def test_check_setting_message_names_the_setting_and_the_range():
    with pytest.raises(RunFailure) as info:
        check_setting("ipo", 1e-7, "R_IPO")
    assert info.value.message == "R_IPO := 1e-07: the value must be in [1e-05, 1] s"
    assert check_setting("speed_ptp", 100, "WITH SPEED_PTP") == 100


def _ipo_program(ipo: float) -> Ird:
    p = Ird("planar3t", "RRR")
    p.push(3, p.const("REAL", ipo)).op(3, "POPSYS", "R_IPO")
    p.push(5, p.const("REAL", 0.001)).op(5, "WAIT")
    p.move(6, "LIN", p.pose(1800, 900, 0))
    return p


def test_r_ipo_out_of_range_fails_at_its_own_line(planar3):
    run = run_code(_ipo_program(1e-7).code_object(), robot=planar3)
    assert run.status == "failed"
    assert run.error.line == 3, run.error
    assert "R_IPO" in run.error.message and "[1e-05, 1] s" in run.error.message
    assert run.times[-1] == 0.0  # nothing ran after the assignment


def test_r_ipo_at_the_lower_bound_is_used(planar3):
    p = Ird("planar3t", "RRR")
    p.push(3, p.const("REAL", 1e-5)).op(3, "POPSYS", "R_IPO")
    p.push(5, p.const("REAL", 0.001)).op(5, "WAIT")
    run = run_code(p.code_object(), robot=planar3)
    assert run.status == "ok", run.error
    assert len(run.times) == 101  # t = 0 and 100 cycles of 10 µs
    np.testing.assert_allclose(np.diff(run.times), 1e-5, rtol=0, atol=1e-9)


@pytest.mark.parametrize("ipo", [1e-7, 2.0])
def test_ipo_option_uses_the_same_range(planar3, ipo):
    with pytest.raises(RunSetupError):
        run_code(_ipo_program(0.01).code_object(), robot=planar3, ipo=ipo)
    assert setting_error("ipo", ipo) is not None


def test_one_table_feeds_checker_interpreter_and_controller():
    """Each setting is one row: the runtime's tables are the lang table's (not copies)."""
    from irlc.lang import builtins, irdata, settings
    from irlc.runtime import commands as controller
    from irlc.runtime.interpreter import data, motion

    assert controller.SETTING_RANGES is settings.SETTING_RANGES
    assert controller.setting_error is settings.setting_error
    assert set(motion.MOVE_NUMBERS) == {s.with_word for s in settings.SETTINGS if s.with_word}
    for name, var in settings.SYSTEM_VARIABLES.items():
        assert name in irdata.SYSTEM_VARIABLES and name in builtins.SYSTEM_VARIABLES
        assert data.SETTINGS_FIELDS.get(name) == var.field
    command_fields = {f.name for f in dataclasses.fields(controller.MotionCommand)}
    for row in settings.SETTINGS:  # every row has its field where the runtime keeps it
        if row.with_word:
            assert row.field in command_fields
        if row.system_variable:
            assert getattr(controller.Settings(), row.field) == row.default


def test_runtime_and_compile_time_use_the_same_words(planar3):
    """A non-constant out-of-range value fails at run time with the compiler's wording."""
    from irlc.lang.settings import setting_message

    p = Ird("planar3t", "RRR")
    p.push(3, p.const("REAL", -5.0)).op(3, "POPSYS", "R_SPEED")
    run = run_code(p.code_object(), robot=planar3)
    assert run.error.line == 3
    assert run.error.message == setting_message("speed", -5.0, "R_SPEED")
    assert run.error.message == "R_SPEED := -5.0: the value must be in (0, 100000] mm/s"


def test_language_doc_lists_the_table():
    """docs/language.md shows the settings table as generated from lang/settings.py."""
    from pathlib import Path

    from irlc.lang.settings import ranges_table

    doc = Path(__file__).resolve().parents[2] / "docs" / "language.md"
    assert ranges_table() in doc.read_text(encoding="utf-8")
