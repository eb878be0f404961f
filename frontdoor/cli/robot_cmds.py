"""Robot commands: ``irlc robots``, ``irlc robot NAME``, ``irlc fk``, ``irlc ik``.

Program units on the command line and in the output (mm, deg, ZYX angles), also the
translation of the ``fk --json`` matrix; every JSON names them in a ``units`` key.
``--euler zyz`` adds (fk) or takes (ik) Z-Y-Z Euler angles Φ Θ Ψ (``pose_zyz``) beside
ZYX; ``--motors`` adds the motor angles of the robot's motor maps (``motor_angles_rad``,
rad, motor side — :mod:`irlc.runtime.outputs.motor_coords`). Joints
follow the naming rule of :mod:`irlc.runtime.model.naming`: program names ``a1 … aN`` with the
robot file's names beside them (``a4 (panda_joint4)``; in JSON ``joint_names`` and
``robot_joint_names``).
"""

from __future__ import annotations

import json
import math

import click
import numpy as np
from irlc.cli.app import cli
from irlc.cli.console import Console
from irlc.errors import EXIT_RUN, UsageError
from irlc.lang.joint_kinds import kind_letters
from irlc.robots import RobotFileError, list_robots, load_robot
from irlc.robots.loader import MissingExtraError
from irlc.robots.model import RobotModel
from irlc.runtime import units
from irlc.runtime.errors import RunFailure
from irlc.runtime.model import spatial
from irlc.runtime.model.naming import JointNaming
from irlc.runtime.model.reachability import check_vertical_plane
from rich import box
from rich.markup import escape
from rich.table import Table

RAW = {"ignore_unknown_options": True}
MAX_POSITION_MM = 1e9  # 1000 km: beyond it a target is a typo, and squares overflow
MAX_JOINT_VALUE = 1e9  # deg | mm: beyond it a joint value is a typo


def _robot(name: str) -> RobotModel:
    try:
        return load_robot(name)
    except RobotFileError as e:
        raise UsageError(str(e)) from None


def _numbers(values: list[str], what: str) -> list[float]:
    out = []
    for i, v in enumerate(values, 1):
        try:
            x = float(v)
        except ValueError:
            raise UsageError(f"{what} {i}: {v!r} is not a number") from None
        if not math.isfinite(x):
            raise UsageError(f"{what} {i}: {v!r} is not a finite number")
        out.append(x)
    return out


def _joint_values(model: RobotModel, values: list[str], what: str = "joint value") -> np.ndarray:
    numbers = _numbers(values, what)
    if len(numbers) != model.n:
        raise UsageError(
            f"robot {model.name} has {model.n} joints "
            f"({JointNaming.for_model(model).labels(range(model.n))}); "
            f"got {len(numbers)} {what}s"
        )
    naming = JointNaming.for_model(model)
    for j, (v, kind) in enumerate(zip(numbers, model.joint_kinds, strict=True)):
        if abs(v) > MAX_JOINT_VALUE:  # (a typo: the tables printed 300 digits for 1e308)
            unit = units.joint_unit(kind)
            raise UsageError(
                f"{what} {j + 1} ({naming.program[j]}) = {v:g} {unit} is out of range "
                f"(|value| ≤ 1e9 {unit})"
            )
    return units.joints_to_si(numbers, model.joint_kinds)


def _fmt(values) -> list[float]:
    return [units.shown(round(units.shown(v), 9)) for v in values]  # no "-0.0", no 1e-32


def _print_json(data: dict) -> None:
    click.echo(json.dumps(data, indent=2))


JSON_UNITS = {"length": "mm", "angle": "deg"}  # of every fk/ik JSON number


def _joints_json(model: RobotModel) -> dict:
    """The joints' names (program ``a1 … aN``, the robot file's) and units, for JSON."""
    naming = JointNaming.for_model(model)
    return {
        "joint_names": list(naming.program),
        "robot_joint_names": list(naming.robot),
        "joint_units": [units.joint_unit(k) for k in model.joint_kinds],
    }


def _matrix_mm(t: np.ndarray) -> list[list[float]]:
    """A 4×4 transform with its translation in mm (the pose's unit), rotation unitless."""
    m = np.array(t, dtype=float)
    m[:3, 3] /= units.MM
    return [_fmt(row) for row in m]


# ----------------------------------------------------------------------------- robots


def _robot_row(name: str) -> tuple[str, str, str, str]:
    """One row of ``irlc robots``; a robot that cannot load says why in its row (a missing
    optional extra: the ``pip install`` that adds it) instead of failing the listing."""
    try:
        model = load_robot(name)
    except MissingExtraError as e:
        return name, "?", "?", f"needs the optional extra: pip install 'irlc[{e.extra}]'"
    except RobotFileError as e:
        return name, "?", "?", f"cannot load: {e}"
    kinds = kind_letters(model.joint_kinds)
    return name, str(model.n), kinds, model.description


@cli.command("robots")
def robots_cmd() -> None:
    """List the robots of the library (every one, with what a robot that cannot load needs)."""
    table = Table(title="irlc robots")
    for col in ("name", "joints", "kinds", "description"):
        table.add_column(col)
    for name in list_robots():
        table.add_row(*(escape(cell) for cell in _robot_row(name)))
    Console().print(table)


def _range(lo: float, hi: float, kind: str, scale: float = 1.0) -> str:
    """``-166..166`` in program units (4 digits); ``±124.6`` for a symmetric range."""
    lo, hi = (units.shown(v) for v in units.joints_from_si([lo * scale, hi * scale], [kind] * 2))
    if f"{-lo:.4g}" == f"{hi:.4g}":
        return f"±{hi:.4g}"
    return f"{lo:.4g}..{hi:.4g}"


@cli.command("robot")
@click.argument("name")
@click.option(
    "--sensitivity",
    is_flag=True,
    help="Also print |S_k p_k|: the end pose's sensitivity to each kinematic parameter.",
)
@click.option(
    "--samples",
    type=click.IntRange(1, 100_000),
    default=200,
    show_default=True,
    help="With --sensitivity: configurations sampled inside the limits (home included).",
)
def robot_cmd(name: str, sensitivity: bool, samples: int) -> None:
    """Show one robot: joints, units, limits, weights, home, drives."""
    model = _robot(name)
    console = Console()
    console.print(f"[bold]{model.name}[/bold] — {model.description}")
    console.print(f"file: {model.source}")
    for parent in model.extra.get("extends", ()):  # [robot] extends (docs/robots.md)
        console.print(escape(f"  extends {parent} (what the file does not change)"))
    table = Table(
        title="joints (deg: revolute, mm: prismatic; speeds /s, accelerations /s²)",
        box=box.SIMPLE_HEAD,
        pad_edge=False,
    )
    table.add_column("joint", no_wrap=True)
    table.add_column("name in file", no_wrap=True)
    for col in ("unit", "position", "speed", "accel", "weight", "home"):
        table.add_column(col, justify="left" if col == "unit" else "right", no_wrap=True)
    home = units.joints_from_si(model.home_q(), model.joint_kinds)
    naming = JointNaming.for_model(model)
    for i, (j, h) in enumerate(zip(model.joints, home, strict=True)):
        table.add_row(
            naming.name(i),
            j.name,
            units.joint_unit(j.kind),
            _range(*j.limits.position, j.kind),
            _range(*j.limits.speed, j.kind),
            _range(*j.limits.accel, j.kind),
            f"{j.weight:g}",
            f"{h:.4g}",
        )
    console.print(table)
    jerks = [
        f"{naming.name(i)} {units.joints_from_si([j.limits.jerk], [j.kind])[0]:.6g}"
        for i, j in enumerate(model.joints)
        if j.limits.jerk is not None
    ]
    if jerks:  # the S-curve's PTP jerk bounds (the others are derived, docs/runtime.md)
        console.print(escape(f"jerk limits [deg/s³ | mm/s³]: {', '.join(jerks)}"))
    console.print(escape(f"gravity [m/s²]: {_fmt(model.gravity)}"))
    for label, t in (("tool (flange → TCP)", model.tool), ("base (in the world)", model.base)):
        console.print(escape(f"{label} [mm, deg]: {_fmt(units.pose_from_si(t))}"))
    console.print("  a program's R_TOOL is composed after this tool: TCP = flange · tool · R_TOOL")
    _platform_lines(console, model, naming)
    for c in model.extra.get("coupled_limits", []):
        console.print(escape(f"coupled limit {c['name']}: {c['text'] or c['coeffs']}"))
        if "assumed" in c:
            console.print(escape(f"  assumed: {c['assumed']}"))
    _joint_notes(console, model, naming)
    if model.limit_sets:
        console.print(f"limit sets: {', '.join(model.limit_sets)}")
    _closed_form_line(console, model)
    console.print(
        f"geometry: {len(model.geometry)} shapes; inertials: {len(model.inertials)} links"
    )
    if "transmission" in model.extra:
        kinds = sorted({t["type"] for t in model.extra["transmission"]})
        console.print(f"transmission: {', '.join(kinds)}")
        console.print(escape(_motor_limits_line(model)))
    drives = model.extra.get("drives")
    if isinstance(drives, dict):
        console.print(f"drives: {', '.join(sorted(drives)) or '(empty table)'}")
    else:
        console.print("drives: none in the file")
    assumed = model.extra.get("assumed", {})
    if assumed:
        console.print(f"assumed values ({len(assumed)}): {', '.join(assumed)} — see the file")
    if sensitivity:
        from irlc.cli.sensitivity import print_sensitivity

        print_sensitivity(console, model, samples)
    refused = _drive_data_refusal(model)
    if refused:
        click.echo(f"irlc: warning: {refused}", err=True)


def _platform_lines(console: Console, model: RobotModel, naming: JointNaming) -> None:
    """The robot's platform ([platform], docs/robots.md): its joints, the point whose world
    coordinates WITH PLATFORM sets, and their ranges."""
    platform = model.platform
    if platform is None:
        console.print("platform: none in the file (WITH PLATFORM and R_PLATFORM need one)")
        return
    joints = ", ".join(naming.label(j) for j in platform.joints)
    point = _fmt(platform.point / units.MM)
    ranges = ", ".join(
        f"{c} {lo:.6g} … {hi:.6g}"
        for c, (lo, hi) in zip(platform.coordinates, platform.ranges() / units.MM, strict=True)
    )
    what = f" — {platform.description}" if platform.description else ""
    console.print(escape(f"platform{what}: joints {joints}"))
    console.print(
        escape(
            f"  WITH PLATFORM := {_platform_form(platform.coordinates)} [mm]: the world "
            f"{', '.join(platform.coordinates)} of point {point} mm of link {platform.link}; "
            f"range {ranges} mm"
        )
    )


def _platform_form(coordinates) -> str:
    """``y`` / ``(x, y)``: how a target of a platform with these coordinates is written."""
    return coordinates[0] if len(coordinates) == 1 else f"({', '.join(coordinates)})"


def _drive_data_refusal(model: RobotModel) -> str | None:
    """What ``irlc run`` would refuse in the robot's drive data, said where the robot is
    shown: every run reads the motor limits of a coupled transmission from it; only a run
    with ``--drives`` reads the rest."""
    from irlc.runtime.drives.params import drive_params
    from irlc.runtime.model.motor_limits import motor_limits

    try:
        motor_limits(model)
    except (RobotFileError, ValueError) as e:
        return (
            f"{e} — irlc run refuses this robot, even with ideal drives: its coupled "
            "transmission takes the motor limits from the drive data"
        )
    if "drives" not in model.extra:
        return None
    try:
        drive_params(model)
    except (RobotFileError, ValueError) as e:
        return f"{e} — irlc run --drives refuses this robot (an ideal run does not read them)"
    return None


def _closed_form_line(console: Console, model: RobotModel) -> None:
    """``closed-form IK: parallel_5r (branches for irlc ik --branch: …)`` when it has one."""
    from irlc.runtime.ik import closed_form

    family = closed_form.family(model)
    if family:
        labels = ", ".join(closed_form.branch_labels(model))
        console.print(escape(f"closed-form IK: {family} (irlc ik --branch: {labels})"))


def _joint_notes(console: Console, model: RobotModel, naming: JointNaming) -> None:
    """The robot file's reasons for assumed joint values (``joints[i]`` entries of
    ``[assumptions]``), e.g. why the IRb-6's a4 range is what it is."""
    assumed = model.extra.get("assumed", {})
    for i in range(model.n):
        reason = assumed.get(f"joints[{i + 1}]")
        if reason:
            console.print(escape(f"note on {naming.label(i)}: {reason}"))


def _motor_limits_line(model: RobotModel) -> str:
    """What bounds the motors of a coupled transmission (:mod:`motor_limits`)."""
    from irlc.runtime.model.motor_limits import motor_limits

    try:
        limits = motor_limits(model)
    except RobotFileError as e:
        return f"motor limits: unknown ({e})"
    if limits is None:
        return "motor limits: none beyond the joint limits (no coupled transmission with limits)"
    speeds = ", ".join(f"{v:.6g}" for v in limits.speed)
    return f"motor limits [rad/s] ({limits.source}): {speeds} — the timing and the IK respect them"


# ----------------------------------------------------------------------------- fk / ik


MOTORS_HELP = "also print the motor angles (rad, motor side) of the robot's motor maps"
EULER_HELP = (
    "orientation convention of the printed (fk) or given (ik) angles beside the default "
    "ZYX a b c: zyz = Z-Y-Z Euler angles Φ Θ Ψ, R = Rz(Φ)·Ry(Θ)·Rz(Ψ)"
)
EULER_CHOICE = click.Choice(sorted(spatial.EULER), case_sensitive=False)
ZYZ_LABELS = ("Φ (zyz) [deg]", "Θ (zyz) [deg]", "Ψ (zyz) [deg]")


@cli.command("fk", context_settings=RAW)
@click.argument("robot")
@click.argument("q", nargs=-1, type=click.UNPROCESSED)
@click.option("--json", "as_json", is_flag=True, help="print JSON")
@click.option("--motors", is_flag=True, help=MOTORS_HELP)
@click.option("--euler", type=EULER_CHOICE, default="zyx", show_default=True, help=EULER_HELP)
def fk_cmd(robot: str, q: tuple[str, ...], as_json: bool, motors: bool, euler: str) -> None:
    """Forward kinematics: joint values (deg, mm) → TCP pose (mm, deg ZYX) in the world."""
    from irlc.runtime.model.kinematics import Kinematics

    model = _robot(robot)
    q_si = _joint_values(model, list(q))
    t = Kinematics(model).tcp(q_si)
    pose = units.pose_from_si(t)
    joints = units.joints_from_si(q_si, model.joint_kinds)
    extra = _extras(model, q_si, t, motors, euler.lower())
    outside, warnings = _outside_limits(model, q_si)
    for warning in warnings:
        click.echo(f"irlc: warning: {warning}", err=True)
    if as_json:
        _print_json(
            {
                "robot": model.name,
                "units": JSON_UNITS,
                **_joints_json(model),
                "joints": _fmt(joints),
                "pose": _fmt(pose),
                "matrix": _matrix_mm(t),
                "outside_limits": outside,
                **extra,
            }
        )
        return
    _pose_table(model, joints, pose, "forward kinematics", extra)


def _reached_pose(model: RobotModel, q_si) -> list[float]:
    """The TCP pose (mm, deg ZYX) the joints ``q_si`` reach."""
    from irlc.runtime.model.kinematics import Kinematics

    return list(units.pose_from_si(Kinematics(model).tcp(q_si)))


def _outside_limits(model: RobotModel, q_si) -> tuple[list[dict], list[str]]:
    """The joints beyond the robot's position limits (runtime/model/limit_check.py): the JSON key
    ``outside_limits`` (program name, value, bound in deg | mm, side ``min``/``max``, unit)
    and one warning each."""
    from irlc.runtime.model.limit_check import each_outside

    limits = model.position_limits
    naming = JointNaming.for_model(model)
    found, warnings = [], []
    for o in each_outside(q_si, limits[:, 0], limits[:, 1]):
        kind = model.joint_kinds[o.joint]
        unit = units.joint_unit(kind)
        value, bound = _fmt(units.joints_from_si([o.value, o.bound], [kind, kind]))
        found.append(
            {"joint": naming.program[o.joint], "value": value, "bound": bound,
             "side": o.side, "unit": unit}
        )  # fmt: skip
        warnings.append(
            f"joint {naming.label(o.joint)} is at {value:g} {unit}, {o.where} bound {bound:g} "
            f"{unit} of the robot's position limits (the pose is computed all the same)"
        )
    return found, warnings


def _extras(model: RobotModel, q_si, t, motors: bool, euler: str) -> dict:
    """The JSON keys of ``--euler zyz`` (``pose_zyz``: x y z mm, Φ Θ Ψ deg) and
    ``--motors`` (``motor_angles_rad``, per joint, motor side; rad)."""
    out: dict = {}
    if euler != "zyx":
        out[f"pose_{euler}"] = _fmt(units.pose_from_si(t, euler))
    if motors:
        from irlc.runtime.outputs.motor_coords import has_motors, motor_angles

        if not has_motors(model):
            raise UsageError(
                f"--motors: robot {model.name} has no motor maps (no [transmission] table "
                "in its robot file)"
            )
        out["units"] = {**JSON_UNITS, "motor_angle": "rad"}
        out["motor_angles_rad"] = _fmt(motor_angles(model, q_si))
    return out


POSE_LABELS = ("x [mm]", "y [mm]", "z [mm]", "a [deg]", "b [deg]", "c [deg]")


def _pose_table(
    model: RobotModel,
    joints,
    pose,
    title: str,
    extra: dict | None = None,
    reached=None,
) -> None:
    """Joints and pose; with ``reached`` (an IK that did not converge) the pose rows are
    the target's and the pose the joints reach follows."""
    table = Table(title=f"{model.name}: {title}")
    table.add_column("quantity")
    table.add_column("value")
    naming = JointNaming.for_model(model)
    for j, (kind, v) in enumerate(zip(model.joint_kinds, joints, strict=True)):
        label = f"{naming.label(j)} [{units.joint_unit(kind)}]"
        table.add_row(escape(label), units.fixed(v, 4))
    for label, v in zip(POSE_LABELS, pose, strict=True):
        table.add_row(escape(label if reached is None else f"target {label}"), units.fixed(v, 4))
    for label, v in zip(POSE_LABELS, reached if reached is not None else (), strict=False):
        table.add_row(escape(f"reached {label}"), units.fixed(v, 4))
    extra = extra or {}
    if "pose_zyz" in extra:
        for label, v in zip(ZYZ_LABELS, extra["pose_zyz"][3:], strict=True):
            table.add_row(escape(label), units.fixed(v, 4))
    for j, v in enumerate(extra.get("motor_angles_rad", [])):
        table.add_row(escape(f"motor {naming.label(j)} [rad]"), units.fixed(v, 6))
    Console().print(table)


def _error_value(value: float) -> float | None:
    """An IK error for the output: rounded like the other fields; ``None`` (JSON ``null``)
    when the solver could not evaluate it (never ``Infinity`` / ``NaN`` in JSON)."""
    return _fmt([value])[0] if math.isfinite(value) else None


def _show(value: float | None) -> str:
    return "unknown" if value is None else f"{value:.3g}"


def _start_line(found) -> str:
    """Where the solution came from, and the closed-form branches (within the limits?)."""
    start = {"seed": "from the seed"}.get(found.start, f"from {found.start}")
    if not found.solution.converged:
        text = f"starts tried: {found.tried}"
    elif found.tried > 1:
        text = f"solved {start} ({found.tried} starts tried)"
    else:
        text = f"solved {start}"
    if found.branches:
        marks = ", ".join(
            f"{b.label}{'' if b.within_limits else ' (outside the limits)'}" for b in found.branches
        )
        text += f"; closed-form branches: {marks}"
        if found.branch and found.solution.converged:
            text += f"; solution on {found.branch}"
    return text


def _split_seed(args: list[str]) -> tuple[list[str], list[str] | None]:
    if "--seed" not in args:
        return args, None
    k = args.index("--seed")
    return args[:k], args[k + 1 :]


@cli.command("ik", context_settings=RAW)
@click.argument("robot")
@click.argument("args", nargs=-1, type=click.UNPROCESSED)
@click.option("--json", "as_json", is_flag=True, help="print JSON")
@click.option(
    "--branch",
    default=None,
    help="closed-form branch to take (robots with a closed form, e.g. irb6: "
    "front-elbow-up; l1: noflip | flip); default: the solution found from the seed",
)
@click.option("--motors", is_flag=True, help=MOTORS_HELP)
@click.option("--euler", type=EULER_CHOICE, default="zyx", show_default=True, help=EULER_HELP)
def ik_cmd(
    robot: str, args: tuple[str, ...], as_json: bool, branch: str | None, motors: bool, euler: str
) -> None:
    """Inverse kinematics: pose x y z a b c (mm, deg ZYX; with --euler zyz: x y z Φ Θ Ψ)
    [--seed q...] → joints.

    Tries the seed (default: home), then the closed-form solutions and other starts.
    Exit code 2 when no solution is found ("target not reachable" when none exists
    within the limits)."""
    euler = euler.lower()
    model = _robot(robot)
    pose_args, seed_args = _split_seed(list(args))
    if len(pose_args) != 6:
        raise UsageError(f"expected a pose x y z a b c (6 numbers), got {len(pose_args)} values")
    pose = _numbers(pose_args, "pose value")
    seed = model.home_q() if seed_args is None else _joint_values(model, seed_args, "seed value")
    from irlc.runtime.ik.find import BranchError, find_pose
    from irlc.runtime.ik.seed import seed_problem

    problem = seed_problem(model, seed) if seed_args is not None else None
    if problem is not None:
        raise UsageError(problem)
    for label, v in zip("xyz", pose[:3], strict=False):
        if abs(v) > MAX_POSITION_MM:
            raise UsageError(f"pose {label} = {v:g} mm is out of range (|{label}| ≤ 1e9 mm)")
    target = units.pose_to_si(*pose, euler=euler)
    pose_zyx = units.pose_from_si(target) if euler != "zyx" else pose
    try:
        found = find_pose(model, target, seed, branch=branch)
        sol = found.solution
    except BranchError as e:
        raise UsageError(str(e)) from None
    except RunFailure as e:
        click.echo(f"irlc: ik failed: {e.message}", err=True)
        raise click.exceptions.Exit(EXIT_RUN) from None
    message = str(sol.message)
    if not sol.converged and "reachability" in model.extra:
        check = check_vertical_plane(model, target)
        if not check.reachable and check.message not in message:
            message = f"{message}; {check.message}"
    joints = units.joints_from_si(sol.q, model.joint_kinds)
    pos_mm = _error_value(float(sol.position_error) / units.MM)
    ori_deg = _error_value(float(sol.orientation_error) / units.DEG)
    if not np.all(np.isfinite(joints)):
        raise click.ClickException("the IK solver returned non-finite joint values (a bug)")
    extra = _extras(model, sol.q, target, motors, euler)
    if as_json:
        _print_json(
            {
                "robot": model.name,
                "units": JSON_UNITS,
                "pose": _fmt(pose_zyx),
                "reached_pose": _fmt(_reached_pose(model, sol.q)),
                **extra,
                **_joints_json(model),
                "joints": _fmt(joints),
                "converged": bool(sol.converged),
                "position_error_mm": pos_mm,
                "orientation_error_deg": ori_deg,
                "iterations": int(sol.iterations),
                "message": message,
                "start": found.start,
                "branch": found.branch,
                "branches": [
                    {"label": b.label, "within_limits": b.within_limits} for b in found.branches
                ],
            }
        )
    else:
        reached = None if sol.converged else _reached_pose(model, sol.q)
        _pose_table(model, joints, pose_zyx, "inverse kinematics", extra, reached)
        state = "converged" if sol.converged else "NOT converged"
        detail = "" if sol.converged else f" {message}"  # the solver's diagnosis
        click.echo(
            f"{state} after {sol.iterations} iterations: position error {_show(pos_mm)} mm, "
            f"orientation error {_show(ori_deg)} deg.{detail}"
        )
        click.echo(_start_line(found))
    if not sol.converged:
        raise click.exceptions.Exit(EXIT_RUN)
