"""One range table for the numeric settings (lang/settings.py, re-exported as
controller.SETTING_RANGES), used by the checker for constants, POPSYS, WITH clauses, the
executor and ``--ipo`` (regression: ``R_IPO := 1e-7`` was accepted by the interpreter and
failed at the next MOVE, naming that line)."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from irlc.lang.settings import SETTINGS, SettingChoices, setting_message
from irlc.runtime.commands import (
    SETTING_RANGES,
    MotionCommand,
    Settings,
    check_setting,
    setting_error,
)
from irlc.runtime.errors import RunFailure
from irlc.runtime.plan.motion_values import motion_values
from irlc.runtime.run import RunSetupError, check_run_option, run_code

from ..lang.conftest import compile_text
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


def _row_values(row):
    """Values for a row: around and between its bounds (the bounds, their neighbours,
    negatives, huge), or words for a choice."""
    if isinstance(row.range, SettingChoices):
        words = [*row.range.words, *(w.lower() for w in row.range.words), "SMOOTH", ""]
        return st.sampled_from(words)
    r = row.range
    edges = [r.low, r.high] if math.isfinite(r.high) else [r.low, 1e300]
    near = [math.nextafter(e, d) for e in edges for d in (-math.inf, math.inf)]
    return st.one_of(
        st.sampled_from([*edges, *near, 0.0, -1.0]),
        st.floats(min_value=-2 * edges[1], max_value=2 * edges[1], allow_nan=False),
    )


def _literal(value) -> str:
    return "'" + value + "'" if isinstance(value, str) else repr(float(value))


@pytest.mark.parametrize("row", SETTINGS, ids=lambda r: r.field)
def test_every_row_has_one_range_check_for_compiler_interpreter_controller_and_options(row):
    """Property: for any value, the compiler (a constant), the interpreter (an assignment or
    a WITH clause), the controller (the motion's values) and the command-line options
    (``--ipo``, ``--override``, ``--path-tolerance``) accept exactly the values of the
    row's range, and refuse the others in the table's words."""
    what = row.system_variable or f"WITH {row.with_word}"
    option = {"ipo": "ipo", "override": "override", "path_tol": "path_tolerance"}.get(row.field)

    @settings(max_examples=40, deadline=None, database=None)
    @given(_row_values(row))
    def check(value):
        error = setting_error(row.field, value)
        try:  # the interpreter's check (POPSYS, a WITH clause)
            check_setting(row.field, value, what)
            refused = None
        except RunFailure as exc:
            refused = exc.message
        assert refused == (None if error is None else setting_message(row.field, value, what))
        kind = row.kinds[0] if row.kinds else "PTP"  # the controller's one check per motion
        with_value = {row.field: value} if row.with_word else {}
        cmd = MotionCommand(kind, (), 7, **with_value)
        held = Settings(**({row.field: value} if not row.with_word else {}))
        try:
            motion_values(cmd, held)
            refused = None
        except RunFailure as exc:
            refused = exc.message
            assert exc.line == 7
        said = f"WITH {row.with_word}" if row.with_word else what
        assert refused == (None if error is None else setting_message(row.field, value, said))
        if option is not None:  # run_code's options and a study's [run] values
            assert (check_run_option(option, value) is None) == (error is None)
        if row.system_variable:  # the compiler, on a constant
            statement = f"{row.system_variable} := {_literal(value)};"
        else:
            statement = f"MOVE PTP (0, 0, 0) WITH {row.with_word} := {_literal(value)};"
        result = compile_text(
            f"PROGRAM p;\nROBOT r := planar3;\nBEGIN\n  {statement}\nENDPROGRAM\n"
        )
        errors = [d.message for d in result.errors]
        if error is None:
            assert errors == []
        else:
            assert len(errors) == 1 and errors[0].endswith(": " + error), errors

    check()


def test_each_value_is_checked_once_per_motion(planar3, monkeypatch):
    """The controller checks each setting once per motion (motion_values.py): R_IPO was
    checked three times per motion (the blend context, the plan state, every segment run),
    R_OVERRIDE once per scaled setting. Every check reads the range table, so counting its
    reads counts the checks."""
    from irlc.lang import settings as table

    reads: dict[str, int] = {}

    class Counting(dict):
        def __getitem__(self, key):
            reads[key] = reads.get(key, 0) + 1
            return super().__getitem__(key)

    monkeypatch.setattr(table, "SETTING_RANGES", Counting(table.SETTING_RANGES))
    p = Ird("planar3t", "RRR")
    p.move(3, "LIN", p.pose(1800, 900, 0))
    p.move(4, "PTP", p.joints(10.0, 80.0, -80.0))
    p.move(5, "LIN", p.pose(1700, 900, 0), p.pose(1700, 800, 0))  # two segments
    run = run_code(p.code_object(), robot=planar3)
    assert run.status == "ok", run.error
    assert reads == {row.field: 3 for row in SETTINGS if row.system_variable}


def test_limit_options_are_one_table():
    """The joint-limit options are the rows of lang/settings.py: the grammar's words (on,
    off) and tuple types are the table's, and every layer keeps them in the row's field."""
    import dataclasses

    from irlc.lang.grammar import lark_parser
    from irlc.lang.irdata_model import JOINT_TUPLE_TYPES, MODAL_OPTIONS
    from irlc.lang.settings import LIMIT_OPTIONS, LIMIT_TUPLE_TYPES
    from irlc.runtime.commands import ModalOptions
    from irlc.runtime.interpreter import motion

    terminals = {t.name for t in lark_parser().terminals}
    grammar_words = {t for t in terminals if t.startswith("JOINT") and "LIMIT" in t}
    assert grammar_words == {w for o in LIMIT_OPTIONS for w in (o.word, o.end_word)}
    grammar_types = {t for t in terminals if t.startswith("MAIN_JOINT_")}
    assert grammar_types == set(LIMIT_TUPLE_TYPES)
    assert ("MAIN_JOINT", *LIMIT_TUPLE_TYPES) == JOINT_TUPLE_TYPES
    assert MODAL_OPTIONS[: len(LIMIT_OPTIONS)] == tuple(o.word for o in LIMIT_OPTIONS)
    for cls in (MotionCommand, ModalOptions):
        assert {o.field for o in LIMIT_OPTIONS} <= {f.name for f in dataclasses.fields(cls)}
    assert {o.word: (o.field, o.derivative) for o in LIMIT_OPTIONS} == motion.LIMIT_OPTIONS
