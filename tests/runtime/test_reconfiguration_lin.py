"""``MOVE LIN a, b WITH RECONFIGURATION k``: one configuration for a LIN through several
points compiles (``RECONF:1``) and runs: the reference θ⁰ is spread along the path by arc
length, i.e. it equals giving the per-point configurations
``(q0 + f·(k − q0), k)`` with ``f = |a − p0| / (|a − p0| + |b − a|)``. LIN PATH and CIRCLE
need one per point (docs/language.md §6) — in the compiler and the interpreter alike."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from irlc.lang import compile_source, write_code
from irlc.robots import resolver
from irlc.runtime.errors import RunFailure
from irlc.runtime.run import run_file

from .test_interpreter_fakes import FakeController, main_program, run

Q0 = (60.0, -60.0, -30.0, 0.0)  # planar4, links 300 mm
A, B = (900.0, 100.0), (850.0, 250.0)
K = (90.0, -80.0, -60.0, 20.0)


def _program(tmp_path: Path, clause: str, name: str = "rc") -> Path:
    prog = tmp_path / f"{name}.irl"
    prog.write_text(
        f"PROGRAM {name};\nROBOT r := planar4;\nVAR POSE: a, b; MAIN_JOINT: k;\nBEGIN\n"
        f"  MOVE PTP ({', '.join(map(repr, Q0))});\n"
        f"  a := POSE({A[0]}, {A[1]}, 0, -30, 0, 0);\n"
        f"  b := POSE({B[0]}, {B[1]}, 0, -30, 0, 0);\n"
        f"  k := ({', '.join(map(repr, K))});\n"
        f"  MOVE LIN a, b{clause};\nENDPROGRAM\n"
    )
    return prog


def _tcp0() -> tuple[float, float]:
    angles = np.cumsum(np.radians(Q0))
    return float(300 * np.cos(angles).sum()), float(300 * np.sin(angles).sum())


def test_one_configuration_for_several_points_compiles_to_reconf_1(tmp_path):
    prog = _program(tmp_path, " WITH RECONFIGURATION k")
    result = compile_source(prog.read_text(), str(prog), resolve_robot=resolver(tmp_path))
    assert result.code is not None, result.diagnostics
    assert "MOVE LIN 2 RECONF:1" in write_code(result.code)


def test_one_configuration_is_spread_by_arc_length(tmp_path):
    """The single-k run equals the run with the per-point configurations of the rule."""
    p0 = _tcp0()
    assert math.isclose(p0[0], 969.6152422706632) and math.isclose(p0[1], -40.19237886466843)
    l1, l2 = math.dist(p0, A), math.dist(A, B)
    f = l1 / (l1 + l2)
    kmid = tuple(q + f * (k - q) for q, k in zip(Q0, K, strict=True))
    single = run_file(_program(tmp_path, " WITH RECONFIGURATION k", "one"))
    per_point = run_file(
        _program(tmp_path, f" WITH RECONFIGURATION ({', '.join(map(repr, kmid))}), k", "two")
    )
    without = run_file(_program(tmp_path, "", "none"))
    assert single.ok and per_point.ok and without.ok, (single.error, per_point.error)
    assert single.q.shape == per_point.q.shape
    np.testing.assert_allclose(single.q, per_point.q, rtol=0, atol=1e-9)
    # and the reference acts: the arm ends nearer k than without it
    k_si = np.radians(K)
    assert np.linalg.norm(single.q[-1] - k_si) < 0.5 * np.linalg.norm(without.q[-1] - k_si)


@pytest.mark.parametrize(
    ("motion", "configs", "points"),
    [
        ("MOVE LIN PATH (a, b)", "k", 2),
        ("MOVE CIRCLE a, b", "k", 2),
        ("MOVE LIN a, b, a", "k, k", 3),  # LIN: one, or one per point
    ],
)
def test_path_and_circle_need_one_per_point(tmp_path, motion, configs, points):
    clause = f" WITH RECONFIGURATION {configs}"
    src = _program(tmp_path, clause).read_text().replace("MOVE LIN a, b", motion)
    result = compile_source(src, "t.irl", resolve_robot=resolver(tmp_path))
    assert result.code is None
    (d,) = result.errors
    n = len(configs.split(","))
    plural = "s" if n > 1 else ""
    assert d.message == f"WITH RECONFIGURATION gives {n} configuration{plural} for {points} points"
    assert d.span.line == 9


def test_interpreter_applies_the_same_counts():
    consts = "CONST 0 POSE 1000.0 0.0 0.0 0.0 0.0 0.0\nCONST 1 MAIN_JOINT 1.0 2.0 3.0"
    lin = "main: L4 PUSHC 0\nL4 PUSHC 0\nL4 PUSHC 1\nL4 MOVE LIN 2 RECONF:1\nL5 END"
    ctl = FakeController()
    run(main_program(lin, consts=consts), ctl)
    assert [k.values for k in ctl.moves[0][0].reconfiguration] == [(1.0, 2.0, 3.0)]
    path = lin.replace("MOVE LIN 2", "MOVE LINPATH 2")
    with pytest.raises(RunFailure, match="1 RECONFIGURATION targets for 2 points"):
        run(main_program(path, consts=consts), FakeController())
