"""ik.reach.LimitedModels: the narrowed model and its kinematics, built once per
(position limits, tool) and reused by every pose search of a run (same solutions)."""

from __future__ import annotations

import numpy as np
from irlc import load_robot
from irlc.runtime.ik.reach import LimitedModels, Reach, solve_within
from irlc.runtime.model.kinematics import Kinematics
from irlc.runtime.model.naming import JointNaming


def test_built_once_per_limits_and_tool():
    model = load_robot("panda")
    models = LimitedModels(model)
    pos = model.position_limits
    limited, kin = models.get(pos, model.tool)
    again = models.get(pos.copy(), model.tool.copy())
    assert again[0] is limited and again[1] is kin  # the same objects
    assert np.array_equal(limited.position_limits, pos) and kin.model is limited
    narrow = pos.copy()
    narrow[3] = (-2.0, -1.0)
    other, _ = models.get(narrow, model.tool)
    assert other is not limited and np.array_equal(other.position_limits, narrow)
    tool = model.tool.copy()
    tool[2, 3] += 0.1
    assert models.get(pos, tool)[1] is not kin  # another tool: other kinematics
    for k in range(LimitedModels.MAX_KEPT + 5):  # bounded: the oldest are dropped
        wide = pos.copy()
        wide[0, 1] -= 1e-3 * (k + 1)
        models.get(wide, model.tool)
    assert len(models._built) == LimitedModels.MAX_KEPT


def test_reused_models_give_the_same_solutions():
    model = load_robot("panda")
    q0 = np.radians([0, -30, 0, -120, 0, 90, 45])
    kin = Kinematics(model, model.tool)
    pos = model.position_limits
    shared = LimitedModels(model)
    for k in range(5):
        target = kin.tcp(q0 + 0.1 * np.sin(np.arange(7) + k))
        fresh = solve_within(model, target, q0, pos, {3: q0[3]}, model.tool)
        again = solve_within(model, target, q0, pos, {3: q0[3]}, model.tool, models=shared)
        assert fresh.converged == again.converged and np.array_equal(fresh.q, again.q)
    reach = Reach(model, pos, {}, model.tool, (0, 1, 2, 3, 4, 5), JointNaming.for_model(model))
    assert reach.models.model is model  # a Reach without one builds its own
    assert Reach(model, pos, {}, model.tool, (0,), reach.naming, models=shared).models is shared


def test_a_run_builds_the_narrowed_model_once_per_limits(tmp_path, monkeypatch):
    """The pre-check solves every LIN target; the run's searches share one LimitedModels
    (the PreInterpolator's), so one (limits, tool) pair is built once, not per target."""
    from irlc.runtime.ik import reach
    from irlc.runtime.run import run_file

    built = []
    original = reach._with_position_limits
    monkeypatch.setattr(
        reach, "_with_position_limits", lambda m, p: built.append(p.copy()) or original(m, p)
    )
    lins = "".join(
        f"  MOVE LIN POSE({1500 + 100 * (k % 2)}, {200 * k}, 0, 0, 0, 0);\n" for k in range(6)
    )
    path = tmp_path / "lins.irl"
    path.write_text(
        "PROGRAM lins;\nROBOT r := planar3;\nBEGIN\n  MOVE PTP (0, 90, -90);\n"
        f"{lins}  JOINTLIMIT (-90, -180, -180), (90, 180, 180);\n{lins}  JOINTLIMITEND;\n"
        "ENDPROGRAM\n"
    )
    run = run_file(path)
    assert run.status == "ok", run.error
    assert len(built) == 2  # the robot's limits, then the JOINTLIMIT's
    assert not np.array_equal(built[0], built[1])
