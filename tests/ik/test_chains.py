"""The chain abstraction (runtime/model/chain.py) on the seed's three categories of
redundant chains (ch. 3.2): one robot (SerialChain: the solver's own numbers), two
cooperating robots as ONE serial chain (CooperatingChain), and extra equality rows of
task parts (a mobile robot's platform task, a tool held vertical).

Every check is against an independent computation: the two robots' own forward
kinematics (``T_I⁻¹·T_II``), finite differences of the chain's FK and of the task rows,
each robot's own link frames and distances."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from irlc.robots import load_robot
from irlc.runtime.ik.energy import EnergyNeedsInertia, InertiaMetric
from irlc.runtime.ik.newton import InverseTransformation
from irlc.runtime.ik.params import CycleOptions, IKParams
from irlc.runtime.ik.tasks import AxisTask, PlatformTask
from irlc.runtime.model import spatial
from irlc.runtime.model.chain import SerialChain
from irlc.runtime.model.cooperating import CellRobot, CooperatingChain
from irlc.runtime.model.distance import critical_points
from irlc.runtime.model.kinematics import Kinematics
from irlc.runtime.model.link_velocities import LinkVelocities
from irlc.runtime.model.obstacles import SphereObstacle

H = 1e-6  # finite-difference step (rad | m)
WIDE = 1e6  # speed/accel bounds that leave the Newton iteration alone (rad/s, rad/s²)


def _placement(rng) -> np.ndarray:
    rot = spatial.zyx_to_matrix(*rng.uniform(-math.pi, math.pi, 3))
    return spatial.transform(rot, rng.uniform(-1.5, 1.5, 3))


def _random_q(model, rng) -> np.ndarray:
    lo, hi = model.position_limits.T
    lo, hi = np.maximum(lo, -3.0), np.minimum(hi, 3.0)
    return lo + (hi - lo) * rng.uniform(0.1, 0.9, model.n)


def _pair(rng, holder="as6", worker="as6", tools=True) -> CooperatingChain:
    def robot(name, file):
        model = load_robot(file)
        tool = _placement(rng) if tools else None
        return CellRobot(name, model, _placement(rng), tool)

    return CooperatingChain(robot("holder", holder), robot("welder", worker))


def _own_tcp(robot: CellRobot, q: np.ndarray) -> np.ndarray:
    """A robot's TCP in the cell from its own model (base placed by hand, own FK)."""
    tool = robot.model.tool if robot.tool is None else robot.tool
    return robot.at @ _frames_in_base(robot.model, q)[-1] @ robot.model.flange @ tool


def _frames_in_base(model, q: np.ndarray) -> np.ndarray:
    """Link frames of ``model`` at ``q`` written out from the joint data (base first)."""
    out = [np.array(model.base, dtype=float)]
    for j, v in zip(model.joints, q, strict=True):
        angle = v + j.offset
        if j.kind == "revolute":
            motion = spatial.transform(spatial.axis_angle(j.axis, angle))
        else:
            motion = spatial.transform(None, angle * np.asarray(j.axis, dtype=float))
        out.append(out[-1] @ j.origin @ motion)
    return np.array(out)


def _relative(chain: CooperatingChain, theta: np.ndarray) -> np.ndarray:
    """The welder's tool in the holder's tool frame, from each robot's own FK."""
    q_h, q_w = chain.split(theta)
    return spatial.inverse(_own_tcp(chain.holder, q_h)) @ _own_tcp(chain.worker, q_w)


def _fd_jacobian(pose_of, theta: np.ndarray) -> np.ndarray:
    """Central differences of a pose function: linear rows from the position, angular
    rows from the rotation vector of R(θ+h)·R(θ−h)ᵀ / 2h (world / base frame)."""
    jac = np.empty((6, theta.size))
    for i in range(theta.size):
        step = np.zeros(theta.size)
        step[i] = H
        plus, minus = pose_of(theta + step), pose_of(theta - step)
        jac[:3, i] = (plus[:3, 3] - minus[:3, 3]) / (2 * H)
        jac[3:, i] = spatial.rotation_vector(plus[:3, :3] @ minus[:3, :3].T) / (2 * H)
    return jac


# ---------------------------------------------------------------------- one robot


def test_a_serial_chain_is_the_solver_of_one_robot(koch11):
    """InverseTransformation(SerialChain) and InverseTransformation(model, kin) are one
    solver: the same cycle, bit for bit."""
    rng = np.random.default_rng(3)
    kin = Kinematics(koch11)
    q0 = koch11.home_q()
    a = InverseTransformation(koch11, kin, IKParams(accel=False))
    b = InverseTransformation(SerialChain(koch11, Kinematics(koch11)), params=IKParams(accel=False))
    assert b.chain.compiled and b.m == 6
    q_prev = q = q0
    for _ in range(20):
        target = kin.tcp(q)
        target[:3, 3] += rng.uniform(-2e-3, 2e-3, 3)
        ra, rb = a.step(q, q_prev, target, 0.01), b.step(q, q_prev, target, 0.01)
        assert np.array_equal(ra.q, rb.q) and ra.iterations == rb.iterations
        q_prev, q = q, ra.q


# ---------------------------------------------------------------------- cooperating


@pytest.mark.parametrize(
    ("holder", "worker", "seed"),
    [("as6", "as6", 1), ("mobile8", "panda", 2), ("irb6", "as6", 3), ("panda", "mobile8", 4)],
)
def test_cooperating_fk_is_the_holders_tool_inverse_times_the_welders(holder, worker, seed):
    """FK of the joined chain = T_I(θ_I)⁻¹·T_II(θ_II) from each robot's own kinematics,
    on random placements, tools and joints (prismatic joints reversed too: mobile8)."""
    rng = np.random.default_rng(seed)
    chain = _pair(rng, holder, worker)
    assert chain.n == chain.holder.model.n + chain.worker.model.n
    for _ in range(5):
        q_h, q_w = _random_q(chain.holder.model, rng), _random_q(chain.worker.model, rng)
        theta = chain.join(q_h, q_w)
        back = chain.split(theta)
        assert np.array_equal(back[0], q_h) and np.array_equal(back[1], q_w)
        np.testing.assert_allclose(chain.tcp(theta), _relative(chain, theta), atol=1e-12)


@pytest.mark.parametrize(("holder", "worker"), [("as6", "as6"), ("mobile8", "panda")])
def test_cooperating_jacobian_matches_finite_differences(holder, worker):
    rng = np.random.default_rng(11)
    chain = _pair(rng, holder, worker)
    theta = chain.join(_random_q(chain.holder.model, rng), _random_q(chain.worker.model, rng))
    analytic = chain.kin.jacobian(theta)
    np.testing.assert_allclose(analytic, _fd_jacobian(chain.tcp, theta), atol=1e-7)
    # and of the independent FK: the derivative of T_I⁻¹·T_II itself
    np.testing.assert_allclose(analytic, _fd_jacobian(lambda t: _relative(chain, t), theta),
                               atol=1e-7)  # fmt: skip


def test_cooperating_world_frames_are_each_robots_own():
    rng = np.random.default_rng(5)
    chain = _pair(rng, "as6", "mobile8")
    q_h, q_w = _random_q(chain.holder.model, rng), _random_q(chain.worker.model, rng)
    world = chain.world_frames(chain.join(q_h, q_w))
    own_h = chain.holder.at @ _frames_in_base(chain.holder.model, q_h)
    own_w = chain.worker.at @ _frames_in_base(chain.worker.model, q_w)
    np.testing.assert_allclose(world, np.concatenate((own_h, own_w)), atol=1e-12)
    link, tool = chain.tool_body()
    np.testing.assert_allclose(world[link] @ tool, _own_tcp(chain.worker, q_w), atol=1e-12)
    assert chain.bodies.link_label(link) == f"welder link {chain.worker.model.n}"


def test_cooperating_point_jacobian_scatters_into_the_chain_columns():
    """∂(world point on a link)/∂θ by finite differences, for a link of each robot: the
    other robot's columns are zero."""
    rng = np.random.default_rng(8)
    chain = _pair(rng, "as6", "panda")
    theta = chain.join(_random_q(chain.holder.model, rng), _random_q(chain.worker.model, rng))
    n_h = chain.holder.model.n
    for link in (3, n_h + 1 + 5):
        local = rng.uniform(-0.2, 0.2, 3)

        def point(t, link=link, local=local):
            f = chain.world_frames(t)[link]
            return f[:3, :3] @ local + f[:3, 3]

        p = point(theta)
        jac = chain.bodies.jacobian(chain.world_frames(theta), link, p)[:3]
        fd = np.column_stack([(point(theta + H * e) - point(theta - H * e)) / (2 * H)
                              for e in np.eye(chain.n)])  # fmt: skip
        np.testing.assert_allclose(jac, fd, atol=1e-7)
        other = chain.members[1 if link <= n_h else 0].columns
        assert not jac[:, other].any()


def _scene():
    """The monograph's scene (fig. 3.4): an as6 holds the workpiece, a second as6 1.4 m
    away, facing it, works on it."""
    holder = CellRobot("holder", load_robot("as6"))
    face = spatial.transform(spatial.rot_z(math.pi), (1.4, 0.0, 0.0))
    welder = CellRobot("welder", load_robot("as6"), face)
    return CooperatingChain(holder, welder)


def _compiled_available() -> bool:
    from irlc.runtime import accel_support

    return accel_support.AVAILABLE


@pytest.mark.parametrize("compiled", [False, True])
def test_cooperating_cycles_follow_a_line_on_the_workpiece_over_both_robots(compiled):
    """A line in the holder's tool frame, 100 IPO cycles: every cycle the welder's tool in
    the holder's tool frame — from the two robots' own FK — is on the line, and both
    robots move (the redundancy of the 12-joint chain). The compiled engine runs the
    joined chain too (it reads the packed task chain) and gives the numpy path's joints."""
    if compiled and not _compiled_available():
        pytest.skip("no numba or IRLC_ENGINE=numpy")
    chain = _scene()
    ik = InverseTransformation(chain, params=IKParams(accel=compiled))
    reference = InverseTransformation(chain, params=IKParams(accel=False))
    assert ik.accelerated == compiled and not reference.accelerated
    theta0 = chain.join(chain.holder.model.home_q(), chain.worker.model.home_q())
    start = chain.tcp(theta0)
    q_prev = q = theta0
    for k in range(1, 101):
        s = 0.5 - 0.5 * math.cos(math.pi * k / 100)  # rest to rest
        target = start.copy()
        target[:3, 3] += start[:3, :3] @ np.array([0.1 * s, 0.05 * s, 0.0])
        r = ik.step(q, q_prev, target, 0.01)
        assert r.converged and not r.relaxed
        err = spatial.pose_error(_relative(chain, r.q), target)
        assert np.linalg.norm(err[:3]) < 1e-8 and np.linalg.norm(err[3:]) < 1e-8
        np.testing.assert_allclose(r.q, reference.step(q, q_prev, target, 0.01).q, atol=1e-10)
        q_prev, q = q, r.q
    moved = [np.linalg.norm(a - b) for a, b in zip(chain.split(q), chain.split(theta0),
                                                    strict=True)]  # fmt: skip
    assert min(moved) > 1e-3, moved


def test_cooperating_clearances_are_each_robots_own_distances():
    chain = _scene()
    theta = chain.join(chain.holder.model.home_q(), chain.worker.model.home_q())
    q_h, q_w = chain.split(theta)
    world = chain.world_frames(theta)
    own = {}
    for robot, q, offset in ((chain.holder, q_h, 0), (chain.worker, q_w, 7)):
        frames = Kinematics(robot.placed()).link_frames(q)
        centre = frames[3][:3, 3] + np.array([0.0, 0.0, 0.3])
        ball = SphereObstacle(f"near_{robot.name}", centre, 0.05)
        (cp,) = critical_points(Kinematics(robot.placed()), frames, [ball])
        own[ball.name] = (ball, cp.distance, cp.link + offset)
    found = chain.bodies.critical_points(world, [o for o, _, _ in own.values()])
    for cp in found:
        _, distance, link = own[cp.name]
        assert cp.distance == pytest.approx(distance, abs=1e-12) and cp.link == link
    ik = InverseTransformation(chain)
    r = ik.step(theta, theta, chain.tcp(theta), 0.01,
                CycleOptions(obstacles=[o for o, _, _ in own.values()]))  # fmt: skip
    for name, (_, distance, link) in own.items():
        assert r.clearances[name][1] == link
        assert r.clearances[name][0] == pytest.approx(distance, abs=1e-6)


@pytest.mark.parametrize("compiled", [False, True])
def test_cooperating_chain_avoids_an_obstacle_with_both_robots(compiled):
    """OBSTACLE through the chain: a ball beside the welder's forearm; holding the relative
    pose, the criterion moves the chain so that the clearance grows. With obstacles the
    chain's cycles run on the numpy path (its bodies are the robots' own links, not the
    task chain's frames that the kernel would measure)."""
    chain = _scene()
    theta = chain.join(chain.holder.model.home_q(), chain.worker.model.home_q())
    frames = chain.world_frames(theta)
    link = chain.holder.model.n + 1 + 3
    ball = SphereObstacle("ball", frames[link][:3, 3] + np.array([0.0, 0.25, 0.0]), 0.05)
    opts = CycleOptions(obstacles=[ball], active_obstacles=frozenset({"ball"}))
    ik = InverseTransformation(chain, params=IKParams(accel=compiled and _compiled_available()))
    reference = InverseTransformation(chain, params=IKParams(accel=False))
    target = chain.tcp(theta)
    q_prev = q = theta
    first = None
    for _ in range(30):
        r = ik.step(q, q_prev, target, 0.01, opts)
        assert r.converged
        want = reference.step(q, q_prev, target, 0.01, opts)
        assert np.array_equal(r.q, want.q) and r.clearances == want.clearances
        first = r.clearances["ball"][0] if first is None else first
        q_prev, q = q, r.q
    assert r.clearances["ball"][0] > first + 1e-3
    np.testing.assert_allclose(_relative(chain, q), target, atol=1e-8)


def test_cooperating_chain_carries_both_robots_coupled_limits():
    """irb6's coupled rows become rows of the chain over its columns: the same values."""
    rng = np.random.default_rng(21)
    chain = _pair(rng, "irb6", "irb6")
    from irlc.runtime.model.coupled_limits import coupled_limits

    own = coupled_limits(load_robot("irb6"))
    rows = coupled_limits(chain.model)
    assert len(rows) == 2 * len(own)
    q_h, q_w = _random_q(chain.holder.model, rng), _random_q(chain.worker.model, rng)
    theta = chain.join(q_h, q_w)
    for i, c in enumerate(own):
        assert rows[i].coeffs @ theta == pytest.approx(c.coeffs @ q_h, abs=1e-12)
        assert rows[len(own) + i].coeffs @ theta == pytest.approx(c.coeffs @ q_w, abs=1e-12)
        assert rows[i].name == f"holder_{c.name}"


# ---------------------------------------------------------------------- task parts


def _rows_fd(task, chain, theta) -> np.ndarray:
    cols = []
    for e in np.eye(chain.n):
        plus = task.residual(chain.point(theta + H * e))
        minus = task.residual(chain.point(theta - H * e))
        cols.append((plus - minus) / (2 * H))
    return np.column_stack(cols)


def test_platform_task_rows_match_finite_differences_and_depend_on_the_platform_only():
    model = load_robot("mobile8")
    rng = np.random.default_rng(4)
    task = PlatformTask(link=2, coords=(0, 1), point=np.array([0.1, -0.2, 0.3]))
    chain = SerialChain(model, tasks=(task,))
    theta = _random_q(model, rng)
    frame = _frames_in_base(model, theta)[2]
    task.target = np.array([0.4, -0.3])
    p = frame[:3, :3] @ task.local + frame[:3, 3]
    np.testing.assert_allclose(task.residual(chain.point(theta)), p[:2] - task.target, atol=1e-12)
    jac = task.jacobian(chain.point(theta))
    np.testing.assert_allclose(jac, _rows_fd(task, chain, theta), atol=1e-7)
    assert not jac[:, 2:].any()  # the arm's joints do not move the platform


def test_axis_task_rows_match_finite_differences():
    rng = np.random.default_rng(6)
    for name in ("panda", "mobile8"):
        model = load_robot(name)
        chain = SerialChain(model)
        task = AxisTask.vertical(chain)
        theta = _random_q(model, rng)
        tool_z = (_frames_in_base(model, theta)[-1] @ model.flange @ model.tool)[:3, 2]
        res = task.residual(chain.point(theta))
        assert np.linalg.norm(res) == pytest.approx(math.hypot(tool_z[0], tool_z[1]), abs=1e-12)
        np.testing.assert_allclose(task.jacobian(chain.point(theta)),
                                   _rows_fd(task, chain, theta), atol=1e-7)  # fmt: skip
    # on the cooperating chain: the welder's tool in the world, the holder's columns zero
    chain = _scene()
    task = AxisTask.vertical(chain)
    theta = chain.join(_random_q(chain.holder.model, rng), _random_q(chain.worker.model, rng))
    jac = task.jacobian(chain.point(theta))
    np.testing.assert_allclose(jac, _rows_fd(task, chain, theta), atol=1e-7)
    assert not jac[:, chain.members[0].columns].any()


def _mobile_walk(with_task: bool):
    """mobile8: the TCP draws 50 mm along x while the platform is asked to go 20 mm along
    x and 10 mm along y, in step (the same s), rest to rest over 1 s."""
    model = load_robot("mobile8")
    task = PlatformTask(link=2)
    chain = SerialChain(model, tasks=(task,) if with_task else ())
    ik = InverseTransformation(chain, params=IKParams(accel=True))
    q0 = model.home_q()
    kin = Kinematics(model)
    tcp0, platform0 = kin.tcp(q0), kin.link_frames(q0)[2][:2, 3]
    q_prev = q = q0
    out = []
    for k in range(1, 101):
        s = 0.5 - 0.5 * math.cos(math.pi * k / 100)
        target = tcp0.copy()
        target[0, 3] += 0.05 * s
        task.target = platform0 + s * np.array([0.02, 0.01])
        r = ik.step(q, q_prev, target, 0.01)
        out.append((r, target, task.target.copy(), ik))
        q_prev, q = q, r.q
    return out


def test_platform_task_moves_the_platform_along_its_own_line_in_step_with_the_tcp():
    model = load_robot("mobile8")
    kin = Kinematics(model)
    walk = _mobile_walk(True)
    assert not walk[0][3].accelerated  # extra rows: the numpy path
    for r, target, platform, _ in walk:
        assert r.converged and not r.relaxed and len(r.task_errors) == 1
        frames = kin.link_frames(r.q)  # independent: the robot's own FK of the result
        np.testing.assert_allclose(frames[2][:2, 3], platform, atol=1e-9)
        err = spatial.pose_error(kin.tcp(r.q), target)
        assert np.linalg.norm(err) < 1e-9
    # without the rows the platform goes its own way (the redundancy moves it)
    r, _, platform, _ = _mobile_walk(False)[-1]
    assert np.linalg.norm(kin.link_frames(r.q)[2][:2, 3] - platform) > 1e-3


def test_vertical_tool_rows_hold_while_the_cooperating_chain_follows_its_path():
    """The seed's welding condition on the 12-joint chain: 6 pose rows + 2 rows keeping
    the welder's tool z axis vertical in the cell. From a tilted start one cycle with room
    for iterations (a pose search's) makes it vertical, holding the relative pose; then a
    line on the workpiece is followed, cycle by cycle, with both met."""
    chain = _scene()
    theta = chain.join(chain.holder.model.home_q(), chain.worker.model.home_q())
    vertical = AxisTask.vertical(chain)
    both = chain.with_tasks((vertical,))
    assert both.rows == 8 and chain.rows == 6 and chain.tasks == ()
    wide = np.tile([-WIDE, WIDE], (chain.n, 1))
    opts = CycleOptions(speed=wide, accel=wide)
    start = chain.tcp(theta)
    assert np.linalg.norm(vertical.residual(both.point(theta))) > 0.1  # home is tilted
    settle = InverseTransformation(both, params=IKParams(max_iter=50))
    theta = settle.step(theta, theta, start, 0.01, opts).q
    ik = InverseTransformation(both)
    q_prev = q = theta
    for k in range(1, 41):
        s = 0.5 - 0.5 * math.cos(math.pi * k / 40)
        target = start.copy()
        target[:3, 3] += start[:3, :3] @ np.array([0.0, 0.05 * s, 0.02 * s])
        r = ik.step(q, q_prev, target, 0.01, opts)
        assert r.converged and not r.relaxed
        _, q_w = chain.split(r.q)
        tool = _own_tcp(chain.worker, q_w)  # independent: the welder's own FK
        assert math.hypot(tool[0, 2], tool[1, 2]) < 1e-9  # its z axis: no x, y part
        assert r.task_errors[0] < 1e-9
        err = spatial.pose_error(_relative(chain, r.q), target)
        assert np.linalg.norm(err) < 1e-8
        q_prev, q = q, r.q


def test_freeze_with_task_rows_counts_every_row():
    """FREEZE leaving fewer free joints than the pose rows plus the extra rows fails."""
    from irlc.runtime.ik.freeze import FreezeError

    model = load_robot("mobile8")
    task = PlatformTask(link=2, target=np.zeros(2))
    ik = InverseTransformation(SerialChain(model, tasks=(task,)))
    q = model.home_q()
    frozen = {i: float(q[i]) for i in (3, 4)}  # 8 − 2 = 6 free < 6 + 2 rows
    with pytest.raises(FreezeError, match="8-dimensional task"):
        ik.step(q, q, Kinematics(model).tcp(q), 0.01, CycleOptions(frozen=frozen))


def test_the_links_kinetic_energy_of_a_cooperating_chain_is_the_sum_of_both_robots():
    """ENERGY on two cooperating robots: ``½ θ̇ᵀ M(θ) θ̇`` of the chain's metric equals the
    two robots' own kinetic energies, each from its own Newton–Euler link velocities
    (:class:`LinkVelocities`, not the inertia matrix) at its own joints — the holder's
    columns taken in reverse by the chain included."""
    rng = np.random.default_rng(11)
    chain = _pair(rng, "as6", "panda")
    metric = InertiaMetric(chain.model, chain.weights, chain.robot_columns())
    robots = (chain.holder, chain.worker)
    for _ in range(5):
        theta, theta_d = _random_q(chain.model, rng), rng.normal(size=chain.n)
        chain_energy = 0.5 * theta_d @ metric.mass_matrix(theta) @ theta_d
        own = sum(
            LinkVelocities(robot.placed()).kinetic_energy(q[None], qd[None])[0]
            for robot, q, qd in zip(robots, chain.split(theta), chain.split(theta_d), strict=True)
        )
        assert chain_energy == pytest.approx(own, rel=1e-9)
    # one robot without inertials: named, as for a program of one robot
    bare = CellRobot("welder", dataclasses.replace(load_robot("panda"), inertials=()))
    pair = CooperatingChain(CellRobot("holder", load_robot("as6")), bare)
    with pytest.raises(EnergyNeedsInertia, match="robot panda has no"):
        InertiaMetric(pair.model, pair.weights, pair.robot_columns())
