"""Fuzz runs of hostile values (issue 11): a compiled planar3 program whose constants are
replaced by hostile numbers (huge, denormal, negative, zero) must end ``ok`` or with a
positioned run failure — never another exception — within its simulated-time budget."""

from __future__ import annotations

from hypothesis import given
from hypothesis import strategies as st
from irlc.lang import read_code, write_code
from irlc.lang.compiler import compile_source
from irlc.robots import RobotFileError, resolver
from irlc.runtime.run import RunSetupError, run_code

from ..fuzz_budget import fuzz_settings, warm_up_kernels

SOURCE = """PROGRAM f;
ROBOT r := planar3;
VAR POSE: p; REAL: t;
BEGIN
  R_SPEED := 500;
  R_ACC := 2000;
  t := 0.05;
  p := POSE(1500, 500, 0, 0, 0, 0);
  MOVE LIN p;
  WAIT t SEC;
  MOVE PTP (10, 20, 30) WITH TIME := 5;
  R_TOOL := POSE(10, 0, 0, 0, 0, 0);
  MOVE_INC LIN POSE(-10, 20, 0, 0, 0, 0);
  RECONFIGURATION (0, 60, -60);
  MOVE PTP R_ACT_JOINT;
ENDPROGRAM
"""
warm_up_kernels()  # at import: the kernels' one-time compile is no case's hang
IRD = write_code(compile_source(SOURCE, "f.irl", resolve_robot=resolver()).code)
CONSTS = [k for k, line in enumerate(IRD.split("\n")) if " CONST " in line]
HOSTILE = st.sampled_from(
    [0.0, -0.0, -1.0, 1e-320, 4.9e-324, 1e-300, 1e300, -1e308, 1e308, 1e6, 1e9, 200.0, -200.0]
)


@fuzz_settings(80)
@given(st.lists(st.tuples(st.integers(0, 10**6), st.integers(0, 5), HOSTILE), max_size=3))
def test_fuzz_hostile_values_in_motion(edits) -> None:
    lines = IRD.split("\n")
    for where, pos, value in edits:
        k = CONSTS[where % len(CONSTS)]
        words = lines[k].split(" ")
        numbers = [i for i, w in enumerate(words[4:], start=4) if w[:1] in "-0123456789"]
        if not numbers:
            continue
        i = numbers[pos % len(numbers)]
        words[i] = str(int(value)) if words[3] == "INTEGER" else repr(value)
        lines[k] = " ".join(words)
    code = read_code("\n".join(lines), "f.ird")
    try:
        run = run_code(code, max_time=60.0)
    except (RunSetupError, RobotFileError):
        return
    assert run.status in ("ok", "error") or run.error is not None
    if run.error is not None:
        assert run.error.line is not None, run.error
