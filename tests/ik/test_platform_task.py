"""The platform task of a robot file's platform (``runtime/control/platform.py``:
``platform_chain``) — its rows against finite differences of its residual, its residual
against the file's affine map ``c(θ_a) − target``, on the library's platform robots, and
one IK cycle meeting the pose rows and the platform rows together."""

from __future__ import annotations

import numpy as np
import pytest
from irlc.robots import load_robot
from irlc.runtime.control.platform import platform_chain
from irlc.runtime.ik.newton import InverseTransformation
from irlc.runtime.ik.params import CycleOptions, IKParams
from irlc.runtime.model import spatial
from irlc.runtime.model.chain import SerialChain
from irlc.runtime.model.kinematics import Kinematics

H = 1e-6
rng = np.random.default_rng(2727)


@pytest.mark.parametrize("name", ["as6_track", "mobile8"])
def test_platform_rows_match_finite_differences_and_the_files_map(name):
    model = load_robot(name)
    chain, task = platform_chain(SerialChain(model), model.platform)
    assert chain.rows == 6 + model.platform.dimension and chain.tasks == (task,)
    lim = model.position_limits
    for _ in range(5):
        theta = rng.uniform(lim[:, 0], lim[:, 1])
        task.target = rng.uniform(-1.0, 1.0, model.platform.dimension)
        at = chain.point(theta)
        expected = model.platform.coordinates_at(theta) - task.target
        np.testing.assert_allclose(task.residual(at), expected, atol=1e-12)
        cols = []
        for e in np.eye(model.n):
            plus = task.residual(chain.point(theta + H * e))
            minus = task.residual(chain.point(theta - H * e))
            cols.append((plus - minus) / (2 * H))
        jac = task.jacobian(at)
        np.testing.assert_allclose(jac, np.column_stack(cols), atol=1e-8)
        k = len(model.platform.joints)
        np.testing.assert_allclose(jac[:, :k], model.platform.matrix, atol=1e-12)
        assert not jac[:, k:].any()  # the arm's joints do not move the platform


def test_one_cycle_meets_the_tcp_and_the_platform_target():
    """as6_track: a TCP target 5 mm along y with the carriage asked to go 20 mm: the cycle
    converges on both (the arm takes the difference)."""
    model = load_robot("as6_track")
    chain, task = platform_chain(SerialChain(model), model.platform)
    ik = InverseTransformation(chain, params=IKParams(max_iter=20))
    q = np.radians([0.0, 126, -66, 66, -39, 211, 17])
    q[0] = 0.3
    target = Kinematics(model).tcp(q)
    target[1, 3] += 0.005
    task.target = np.array([0.32])
    wide = np.tile([-1e6, 1e6], (model.n, 1))  # one cycle from rest: no rate bounds
    res = ik.step(q, q, target, 0.01, CycleOptions(speed=wide, accel=wide))
    assert res.converged and len(res.task_errors) == 1 and res.task_errors[0] < 1e-9
    np.testing.assert_allclose(res.q[0], 0.32, atol=1e-9)
    err = spatial.pose_error(Kinematics(model).tcp(res.q), target)  # both below 1e-9
    assert np.linalg.norm(err[:3]) < 1e-9 and np.linalg.norm(err[3:]) < 1e-9
