"""The engine switch ``IRLC_ENGINE`` (runtime/accel_support.py): its values, the exit code
of a bad one, the numpy default that never touches numba, the one-line message of a
process that compiles, and the same bytes from a compiling and a loading run."""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest
from irlc.runtime import accel_support

ROOT = Path(__file__).resolve().parents[2]
SQUARE = ROOT / "programs" / "square.irl"
needs_numba = pytest.mark.skipif(not accel_support.NUMBA_INSTALLED, reason="numba not installed")


def _irlc(args, **env):
    code = "import sys; from irlc.cli import main; sys.exit(main(sys.argv[1:]))"
    full = {k: v for k, v in os.environ.items() if k != "IRLC_ENGINE"}
    full.update(env, OPENBLAS_NUM_THREADS="1")
    return subprocess.run(
        [sys.executable, "-c", code, *args], env=full, capture_output=True, text=True, cwd=ROOT
    )


def test_engine_values(monkeypatch):
    monkeypatch.delenv("IRLC_ENGINE", raising=False)
    assert accel_support.engine() == "numpy"
    for value, expected in (("numpy", "numpy"), (" AUTO ", "auto"), ("", "numpy")):
        monkeypatch.setenv("IRLC_ENGINE", value)
        assert accel_support.engine() == expected
    monkeypatch.setenv("IRLC_ENGINE", "fast")
    with pytest.raises(accel_support.EngineChoiceError, match="numpy, compiled, auto"):
        accel_support.engine()
    with pytest.raises(accel_support.EngineChoiceError):
        accel_support.decide(None)  # a bad value is not silently the default


def test_compiled_without_numba_is_an_environment_error(monkeypatch):
    monkeypatch.setattr(accel_support, "NUMBA_INSTALLED", False)
    monkeypatch.setenv("IRLC_ENGINE", "compiled")
    with pytest.raises(accel_support.EngineChoiceError, match=r"irlc\[fast\]"):
        accel_support.engine()
    monkeypatch.setenv("IRLC_ENGINE", "auto")
    assert accel_support.decide(None) is False and accel_support.decide(True) is False


def test_bad_engine_exits_3_with_a_message():
    out = _irlc(["programs/square.irl", "--quiet"], IRLC_ENGINE="turbo")
    assert out.returncode == 3, out.stderr
    assert out.stderr.strip() == (
        "irlc: error: IRLC_ENGINE='turbo' is not an engine; use one of numpy, compiled, auto"
    )
    assert "Traceback" not in out.stderr


def test_default_engine_never_imports_numba():
    """A run with the switch unset is the numpy reference whatever numba's cache holds:
    numba is not even imported (so no compile, no cache read)."""
    code = textwrap.dedent(
        """
        import sys
        from irlc import run_program
        run = run_program(sys.argv[1])
        print(run.status, 'numba' in sys.modules)
        """
    )
    env = {k: v for k, v in os.environ.items() if k != "IRLC_ENGINE"}
    out = subprocess.run(
        [sys.executable, "-c", code, str(SQUARE)], env=env, capture_output=True, text=True
    )
    assert out.returncode == 0, out.stderr
    assert out.stdout.split() == ["ok", "False"]
    assert "compiling" not in out.stderr


def test_irlc_engine_numpy_overrides_accel_true():
    """IRLC_ENGINE=numpy wins over a caller's ``accel=True``: the solver and the drive loop
    run the numpy reference, and numba is not even imported."""
    code = textwrap.dedent(
        """
        import sys
        import numpy as np
        from irlc.robots import load_robot
        from irlc.runtime.accel_support import AVAILABLE
        from irlc.runtime.drives import simulate_drives
        from irlc.runtime.ik import IKParams, InverseTransformation
        from irlc.runtime.model.kinematics import Kinematics
        m = load_robot('koch11')
        ik = InverseTransformation(m, Kinematics(m), IKParams(accel=True))
        q = np.tile(m.home_q(), (2, 1))
        r = simulate_drives(m, np.array([0.0, 0.01]), q, level='coupled', accel=True)
        print(AVAILABLE, ik.accelerated, 'numba' in sys.modules, r.could_follow)
        """
    )
    env = dict(os.environ, IRLC_ENGINE="numpy")
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    assert out.stdout.split() == ["False", "False", "False", "True"]


KERNEL = """
from numba import njit


@njit(cache=True)
def twice(x):
    return 2.0 * x
"""


@needs_numba
def test_a_compiling_process_says_so_once(tmp_path):
    """The first process with an empty cache prints the message (once, though it loads
    twice); the next process, which finds the kernel cached, prints nothing."""
    (tmp_path / "tiny_kernels.py").write_text(KERNEL, encoding="utf-8")
    code = textwrap.dedent(
        """
        from irlc.runtime.accel_support import Kernels
        k = Kernels("tiny_kernels", "twice", "tiny kernels")
        print(k.cache_warm(), k.load().twice(2.0), k.load().twice(3.0))
        """
    )
    env = dict(os.environ, PYTHONPATH=str(tmp_path), NUMBA_CACHE_DIR=str(tmp_path / "cache"))
    runs = [
        subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True)
        for _ in range(2)
    ]
    for out in runs:
        assert out.returncode == 0, out.stderr
    assert runs[0].stdout.split() == ["False", "4.0", "6.0"]
    assert runs[0].stderr.splitlines() == [accel_support.compile_message("tiny kernels")]
    assert runs[1].stdout.split() == ["True", "4.0", "6.0"]
    assert runs[1].stderr == ""


@needs_numba
@pytest.mark.scenario
def test_compiled_bytes_do_not_depend_on_the_cache(tmp_path):
    """IRLC_ENGINE=compiled with an empty numba cache (compiles, and says so) and again with
    the filled cache (loads): the same trace and report bytes."""
    cache = tmp_path / "numba-cache"
    outputs = []
    for k in range(2):
        trace, report = tmp_path / f"t{k}.csv", tmp_path / f"r{k}.json"
        out = _irlc(
            ["programs/square.irl", "--quiet", "--trace", str(trace), "--report", str(report)],
            IRLC_ENGINE="compiled",
            NUMBA_CACHE_DIR=str(cache),
        )
        assert out.returncode == 0, out.stderr
        outputs.append((out.stderr, trace.read_bytes(), report.read_bytes()))
    assert "irlc: compiling the IK kernels" in outputs[0][0]
    assert outputs[1][0] == ""  # warm: silent
    assert outputs[0][1] == outputs[1][1] and outputs[0][2] == outputs[1][2]


def test_warmup_refuses_under_numpy_and_its_message_points_nowhere_else(monkeypatch):
    out = _irlc(["warmup"], IRLC_ENGINE="numpy")
    assert out.returncode == 3
    assert out.stderr.strip() == "irlc: error: warmup: IRLC_ENGINE=numpy disables the kernels"
    assert "irlc warmup" in accel_support.compile_message("IK kernels")
    monkeypatch.setattr(accel_support, "WARMING_UP", True)  # (set by the command itself)
    assert "irlc warmup" not in accel_support.compile_message("IK kernels")
