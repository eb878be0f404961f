"""The engine policy (issue 24 §6, runtime/engine_policy.py): with numba installed and
IRLC_ENGINE unset, a long run goes on on the compiled IK kernels from a fixed IK cycle, a
long drive run's loop and a large study's variants run compiled — decided by the
installation, the documented settings and the run's own length only, so the same program
gives the same bytes on every run; an explicit IRLC_ENGINE decides by itself."""

from __future__ import annotations

import json

import numpy as np
import pytest
from irlc.runtime import accel_support, engine_policy
from irlc.runtime.engine_policy import EngineChoice
from irlc.runtime.run import run_file

needs_numba = pytest.mark.skipif(not accel_support.NUMBA_INSTALLED, reason="numba not installed")


@pytest.fixture
def policy(monkeypatch):
    """IRLC_ENGINE unset and numba installed: the policy decides."""
    monkeypatch.delenv("IRLC_ENGINE", raising=False)
    monkeypatch.setattr(accel_support, "NUMBA_INSTALLED", True)
    return monkeypatch


def test_the_policy_decides_only_where_irlc_engine_is_unset(policy):
    assert engine_policy.deciding()
    assert engine_policy.for_run() == EngineChoice(
        ik_from=engine_policy.SWITCH_IK_CYCLES, drive_steps=engine_policy.DRIVE_STEPS
    )
    for value in ("numpy", "compiled", "auto"):
        policy.setenv("IRLC_ENGINE", value)
        assert not engine_policy.deciding() and engine_policy.for_run() == EngineChoice()
    policy.setenv("IRLC_ENGINE", "turbo")  # an invalid value stays an error
    with pytest.raises(accel_support.EngineChoiceError):
        engine_policy.deciding()
    policy.delenv("IRLC_ENGINE")
    policy.setattr(accel_support, "NUMBA_INSTALLED", False)  # the core install: numpy
    assert not engine_policy.deciding() and engine_policy.for_study(10**6) is None


def test_drive_and_study_thresholds(policy):
    choice = engine_policy.for_run()
    assert engine_policy.drive_kernels(choice, engine_policy.DRIVE_STEPS - 1) is None
    assert engine_policy.drive_kernels(choice, engine_policy.DRIVE_STEPS) is True
    assert engine_policy.drive_kernels(None, 10**9) is None
    assert engine_policy.for_study(engine_policy.STUDY_VARIANTS - 1) is None
    assert engine_policy.for_study(engine_policy.STUDY_VARIANTS) == "compiled"
    assert engine_policy.for_run("compiled") == EngineChoice(ik_from=0, drives=True)
    policy.setenv("IRLC_ENGINE", "numpy")  # an explicit numpy wins over a study's choice
    assert engine_policy.for_run("compiled") == EngineChoice()


def test_a_study_records_its_engine_in_the_plan_and_its_token(policy, tmp_path):
    from irlc.study import read_study
    from irlc.study.plan import build_plan

    (tmp_path / "p.irl").write_text(
        "PROGRAM p;\nROBOT r := planar3;\nBEGIN\n  MOVE LIN (1500, 1000, 0, 0, 0, 0);\nENDPROGRAM\n"
    )
    weights = ", ".join(str(1 + i) for i in range(engine_policy.STUDY_VARIANTS))
    study = tmp_path / "s.toml"
    study.write_text(f'program = "p.irl"\n[grid]\n"robot.joints.2.weight" = [{weights}]\n')
    compiled = build_plan(read_study(study))
    assert compiled.engine == "compiled"
    policy.setenv("IRLC_ENGINE", "numpy")
    reference = build_plan(read_study(study))
    assert reference.engine is None
    assert reference.token != compiled.token  # --resume across engines: another study


LONG = """PROGRAM long;
ROBOT r := planar3;
VAR INTEGER: i;
BEGIN
  FOR i := 1 TO {laps} DO
    MOVE LIN (1500, 1000, 0, 0, 0, 0);
    MOVE LIN (2000, 1000, 0, 0, 0, 0);
  ENDFOR;
ENDPROGRAM
"""


@needs_numba
@pytest.mark.scenario
def test_a_long_run_goes_on_compiled_from_the_switch_and_gives_the_same_bytes(policy, tmp_path):
    """The switch moved to 200 IK cycles: a 100-cycle run stays numpy; a 600-cycle run
    builds the compiled cycle at its first motion after 200 cycles, its samples before
    that are the numpy run's bit for bit, all within round-off of it, and two runs give
    the same report bytes."""
    from irlc.runtime.ik.compiled import driver

    built = []
    original = driver.CompiledCycle

    def spy(ik):
        built.append(ik)
        return original(ik)

    policy.setattr(driver, "CompiledCycle", spy)
    policy.setattr(engine_policy, "SWITCH_IK_CYCLES", 200)
    path = tmp_path / "long.irl"
    path.write_text(LONG.format(laps=1).replace("    MOVE LIN (2000, 1000, 0, 0, 0, 0);\n", ""))
    short = run_file(path)  # one LIN of 0.5 m: 150 IK cycles
    assert short.ok and short.report["ik"]["cycles"] < 200 and not built
    path.write_text(LONG.format(laps=3))  # six LINs: 900 IK cycles
    runs = [run_file(path) for _ in range(2)]
    assert built  # the kernels took over
    policy.setenv("IRLC_ENGINE", "numpy")
    ref = run_file(path)
    first = runs[0]
    assert first.ok and ref.ok and first.report["ik"]["cycles"] == 900
    assert np.array_equal(first.q[:300], ref.q[:300])  # the two LINs before the switch
    assert np.allclose(first.q, ref.q, atol=1e-9, rtol=0.0)
    dumps = [json.dumps(r.report, sort_keys=True) for r in runs]
    assert dumps[0] == dumps[1]
