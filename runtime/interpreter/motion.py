"""The motion instructions: MOVE, RECONFIGURATION and the modal options (OPTON / OPTOFF of
JOINTLIMIT, JOINTSPEEDLIMIT, JOINTACCELLIMIT, CYCLIC, OBSTACLE, FREEZE); ``WITH PLATFORM``'s
target becomes ``MotionCommand.platform_target``.

A part of the interpreter (:class:`MotionInstructions`, through
:class:`~irlc.runtime.interpreter.context.Machine`). A motion instruction
builds a :class:`~irlc.runtime.commands.MotionCommand` from its operands (targets, then
the WITH clauses in the order of the instruction: ``docs/irdata.md``) and hands it to the
controller with a snapshot of the current :class:`Settings` (system variables) and
:class:`ModalOptions`; the controller plans and executes it and advances simulated time.

The WITH words and the system variables are rows of :mod:`irlc.lang.settings`; the limit
options' rows are :data:`LIMIT_OPTIONS`. A limit option's bounds are checked here, where the
program's units are known: lower ≤ upper, speed and acceleration bounds contain 0 (the
robot must be able to stand still), position bounds contain the current joints (the one
check, tolerance and message: :mod:`irlc.runtime.model.limit_check`).
"""

from __future__ import annotations

from irlc.lang.file_access import shown_key, shown_names
from irlc.lang.irdata_robots import VERTICAL, move_parts, robot_index, robot_operand
from irlc.lang.joint_kinds import kind_from_letter
from irlc.lang.platform import WORD as PLATFORM_WORD
from irlc.lang.settings import (
    ALL_KINDS,
    BY_WITH_WORD,
    PATH_KINDS,
    reconfiguration_counts,
)
from irlc.lang.settings import LIMIT_OPTIONS as LIMIT_ROWS
from irlc.runtime import units
from irlc.runtime import values as V
from irlc.runtime.commands import MotionCommand, RobotMotion, check_setting
from irlc.runtime.errors import RunFailure
from irlc.runtime.interpreter import builtins as B
from irlc.runtime.interpreter.context import Machine
from irlc.runtime.interpreter.datatypes import number
from irlc.runtime.model.limit_check import first_outside, limit_failure, program_tolerances
from irlc.runtime.values import JointTuple, Pose

MOVE_NUMBERS = {word: s.field for word, s in BY_WITH_WORD.items()}  # WITH word → field
# option → (field of MotionCommand / ModalOptions, derivative): the rows of lang/settings.py
LIMIT_OPTIONS = {o.word: (o.field, o.derivative) for o in LIMIT_ROWS}
LIMIT_TOLERANCE = 1e-6  # deg/s | mm/s (per derivative): how far a rate bound may exclude 0
_POINT_COUNTS = {"CIRCLE": 2, "PTP": 1, "PTPINC": 1, "LININC": 1}  # LIN, LINPATH: any


class MotionInstructions:
    """``MOVE``, ``RECONF``, ``OPTON``, ``OPTOFF``; see the module docstring."""

    def __init__(self, machine: Machine):
        self.m = machine
        self.stack, self.state, self.code = machine.stack, machine.state, machine.code
        self.pop_n = machine.pop_n

    # ------------------------------------------------------------------ MOVE

    def decode_move(self, args: tuple) -> tuple:
        """``MOVE part [AND part …]`` → one ``(robot, kind, npts, ((word, field, operands),
        …))`` per part (``lang/irdata_robots.py``: ``KIND npts [ROBOT:k] clause…``); the
        robot is ``None`` in code of one robot (which may name it ``ROBOT:0``)."""
        if len(args) < 2 or not isinstance(args[1], int) or args[1] < 1:
            raise B.malformed("MOVE needs a kind and a positive number of points")
        parts, problems = move_parts(args)
        if problems:
            raise B.malformed(problems[0][1])
        return tuple(
            (part.robot if self.m.cell else None, part.kind, part.points,
             tuple(_clause(word) for word in part.clauses))
            for part in parts
        )  # fmt: skip

    def op_move(self, parts) -> None:
        """Pop each part's targets and clause operands (the last part's on top), hand the
        motion to the controller: one robot's :meth:`Controller.move`, a cell's
        :meth:`CellController.move_group` (one part, or a group move's parts)."""
        m = self.m
        motions = []
        for robot, kind, npts, clauses in reversed(parts):
            fields: dict[str, object] = {}
            for word, name, count in reversed(clauses):
                operands = self.pop_n(count)
                fields[name] = self._move_clause(word, operands, kind, npts, robot)
            who = m.robot_joints(robot)
            targets = tuple(self._move_target(kind, t, who) for t in self.pop_n(npts))
            _check_point_count(kind, npts)
            cmd = MotionCommand(kind, targets, m.line(), call=m.call_site(), **fields)
            motions.append(RobotMotion(robot or 0, cmd))
        motions.reverse()
        if m.cell:
            m.call(m.controller.move_group, motions, *m.snapshot())
        else:
            m.call(m.controller.move, motions[0].command, *m.snapshot())
        m.moved()

    def _move_target(self, kind: str, t: object, who: tuple[str, int] | None) -> object:
        if kind in PATH_KINDS:  # a Cartesian path goes to POSE targets
            if not isinstance(t, Pose):
                raise B.malformed(f"MOVE {kind} needs POSE targets, got {V.type_name(t)}")
            return t
        if kind == "PTP" and isinstance(t, Pose):
            return t
        return self.m.types.main_joint(t, f"MOVE {kind} target", who)

    def _move_clause(
        self, word: str, operands: list, kind: str, npts: int, robot: int | None
    ) -> object:
        if word in MOVE_NUMBERS:
            what = f"WITH {word}"
            return check_setting(MOVE_NUMBERS[word], number(operands[0], what), what)
        if word in LIMIT_OPTIONS:
            return self._checked_limits(word, operands[0], operands[1], robot)
        if word == PLATFORM_WORD:
            return platform_target(operands[0])
        if len(operands) not in reconfiguration_counts(kind, npts):
            raise B.malformed(f"{len(operands)} RECONFIGURATION targets for {npts} points")
        who = self.m.robot_joints(robot)
        return tuple(self.m.types.main_joint(k, "RECONFIGURATION", who) for k in operands)

    def decode_reconf(self, args: tuple) -> tuple:
        """``RECONF [ROBOT:k]`` → ``(robot,)`` (``None``: code of one robot)."""
        robot, _ = robot_operand("RECONF", args)
        return (robot if self.m.cell else None,)

    def op_reconf(self, args) -> None:
        (robot,) = args
        m = self.m
        k = m.types.main_joint(self.stack.pop(), "RECONFIGURATION", m.robot_joints(robot))
        if m.cell:
            m.call(m.controller.reconfigure, k, m.line(), *m.snapshot(), robot or 0)
        else:
            m.call(m.controller.reconfigure, k, m.line(), *m.snapshot())
        m.moved()

    # ------------------------------------------------------------------ limit options

    def _kinds(self, robot: int | None) -> str:
        """The joint kinds (``R``/``P`` letters) of the robot an instruction names."""
        return self.code.robots[robot or 0].joint_kinds if self.m.cell else self.code.joint_kinds

    def _joint_unit(self, i: int, derivative: int, robot: int | None = None) -> str:
        return units.joint_unit_label(kind_from_letter(self._kinds(robot)[i]), derivative)

    def _joint_labels(self, robot: int | None = None) -> tuple[str, ...]:
        """Joint names for messages (the naming rule: the program's name, the robot's in
        parentheses where it differs), from the controller's naming when it has one (a
        cell's: :meth:`robot_naming` of the instruction's robot)."""
        controller = self.m.controller
        if self.m.cell:
            of = getattr(controller, "robot_naming", None)
            naming = of(robot or 0) if of is not None else None
            names = self.code.robots[robot or 0].joint_names
        else:
            naming, names = getattr(controller, "naming", None), self.code.joint_names
        if naming is None or len(naming.program) != len(names):
            return tuple(names)
        return tuple(naming.label(i) for i in range(len(naming.program)))

    def _joints_now(self, robot: int | None) -> tuple[float, ...]:
        """The robot's joints now (R_ACT_JOINT: the controller's)."""
        m = self.m
        if m.cell:
            return m.call(m.controller.joints, robot or 0)
        return m.call(m.controller.joints)

    def _checked_limits(
        self, option: str, lo: object, hi: object, robot: int | None = None
    ) -> tuple[JointTuple, JointTuple]:
        who = self.m.robot_joints(robot)
        lo = self.m.types.joint_tuple(lo, f"{option} lower bounds", who)
        hi = self.m.types.joint_tuple(hi, f"{option} upper bounds", who)
        derivative = LIMIT_OPTIONS[option][1]
        names = self._joint_labels(robot)
        fmt = V.format_real
        for i, (a, b) in enumerate(zip(lo.values, hi.values, strict=True)):
            unit = self._joint_unit(i, derivative, robot)
            if a > b:
                raise RunFailure(
                    f"{option}: joint {names[i]} has the lower bound {fmt(a)} {unit}"
                    f" above the upper bound {fmt(b)} {unit}"
                )
            if derivative and (a > LIMIT_TOLERANCE or b < -LIMIT_TOLERANCE):
                raise RunFailure(
                    f"{option} must allow standing still: joint {names[i]} has the bounds"
                    f" [{fmt(a)}, {fmt(b)}] {unit}, which exclude 0",
                    constraint=f"joint {names[i]} {('speed', 'accel')[derivative - 1]}"
                    f" {'min' if a > 0 else 'max'} {fmt(a if a > 0 else b)} {unit}",
                )
        if derivative == 0:
            self._check_joints_inside(option, lo, hi, robot)
        return lo, hi

    def _check_joints_inside(
        self, option: str, lo: JointTuple, hi: JointTuple, robot: int | None
    ) -> None:
        """The current joints inside ``[lo, hi]`` (program units): runtime/model/limit_check.py."""
        kinds = [kind_from_letter(k) for k in self._kinds(robot)]
        q = self._joints_now(robot)
        out = first_outside(q, lo.values, hi.values, program_tolerances(kinds))
        if out is not None:
            names = self._joint_labels(robot)
            name, unit = names[out.joint], self._joint_unit(out.joint, 0, robot)
            fmt = V.format_real
            subject = f"{option} excludes the current state"
            raise limit_failure(
                subject, out, name, f"{fmt(out.value)} {unit}", f"{fmt(out.bound)} {unit}"
            )

    # ------------------------------------------------------------------ OPTON / OPTOFF

    def decode_opton(self, args: tuple) -> tuple:
        """``OPTON OPT [ROBOT:k] operand…`` → ``(option, robot, operands)`` (robot ``None``:
        code of one robot)."""
        robot, rest = robot_operand("OPTON", args)
        return rest[0], robot if self.m.cell else None, tuple(rest[1:])

    def decode_optoff(self, args: tuple) -> tuple:
        robot, rest = robot_operand("OPTOFF", args)
        return rest[0], robot if self.m.cell else None, tuple(rest[1:])

    def op_opton(self, args) -> None:
        option, robot, rest = args
        self.m.stop_advance(f"{option} switched on at line {self.m.line()}")
        opts = self.m.robot_options(robot)
        if option in LIMIT_OPTIONS:
            hi = self.stack.pop()
            lo = self.stack.pop()
            attr = LIMIT_OPTIONS[option][0]
            if getattr(opts, attr) is not None:
                raise RunFailure(f"{option} is already on (close it with {option}END first)")
            setattr(opts, attr, self._checked_limits(option, lo, hi, robot))
        elif option == "CYCLIC":
            if opts.cyclic_reference is not None:
                raise RunFailure("CYCLICSTART while CYCLIC is already on")
            opts.cyclic_reference = tuple(float(x) for x in self._joints_now(robot))
        elif option == "OBSTACLE":
            self._obstacle_on(rest, opts)
            self._check_switch_on(option, robot)
        elif option == "FREEZE":
            self._freeze_on(rest, robot, opts)
            self._check_switch_on(option, robot)
        elif option == "COOPERATE" and self.m.cell:
            m = self.m
            holder = robot_index(rest[0]) if rest else None
            if robot is None or holder is None:
                raise B.malformed("OPTON COOPERATE needs ROBOT:w ROBOT:h")
            vertical = tuple(str(x) for x in rest[1:]) == (VERTICAL,)
            m.call(m.controller.cooperate, robot, holder, vertical, m.line(), *m.snapshot())
        else:
            raise B.malformed(f"unknown modal option {option!r}")

    def _check_switch_on(self, option: str, robot: int | None) -> None:
        """Let the controller reject an option that cannot hold from this very statement
        (an obstacle the arm is inside, too many frozen joints); optional for controllers."""
        m = self.m
        check = getattr(m.controller, "check_switch_on", None)
        if check is None:
            return
        if m.cell:
            m.call(check, option, m.line(), *m.snapshot(), robot or 0)
        else:
            m.call(check, option, m.line(), *m.snapshot())

    def _obstacle_on(self, rest: tuple, opts) -> None:
        if len(rest) != 1:
            raise B.malformed("OPTON OBSTACLE needs one obstacle name")
        obstacle = self.code.obstacle(str(rest[0]))
        if obstacle is None:
            known = shown_names(o.name for o in self.code.obstacles) or "none"
            raise RunFailure(f"unknown obstacle '{shown_key(str(rest[0]))}' (known: {known})")
        if obstacle.name in opts.obstacles:
            raise RunFailure(f"OBSTACLE {obstacle.name} is already on")
        opts.obstacles = (*opts.obstacles, obstacle.name)

    def _freeze_on(self, rest: tuple, robot: int | None, opts) -> None:
        if opts.frozen:
            raise RunFailure("FREEZESTART while joints are already frozen")
        n = len(self._kinds(robot))
        if not rest or any(not isinstance(j, int) or not 1 <= j <= n for j in rest):
            raise B.malformed(
                f"FREEZE needs joint numbers in 1..{n}, got {' '.join(map(str, rest))}"
            )
        q = self._joints_now(robot)
        opts.frozen = {j - 1: float(q[j - 1]) for j in rest}

    def op_optoff(self, args) -> None:
        option, robot, rest = args
        self.m.stop_advance(f"{option} switched off at line {self.m.line()}")
        opts = self.m.robot_options(robot)
        if option in LIMIT_OPTIONS:
            attr = LIMIT_OPTIONS[option][0]
            _require_on(getattr(opts, attr) is not None, option)
            setattr(opts, attr, None)
        elif option == "CYCLIC":
            _require_on(opts.cyclic_reference is not None, "CYCLIC")
            opts.cyclic_reference = None
        elif option == "OBSTACLE":
            if len(rest) != 1:
                raise B.malformed("OPTOFF OBSTACLE needs one obstacle name")
            key = str(rest[0]).lower()
            active = [o for o in opts.obstacles if o.lower() == key]
            _require_on(bool(active), f"OBSTACLE {rest[0]}")
            opts.obstacles = tuple(o for o in opts.obstacles if o.lower() != key)
        elif option == "FREEZE":
            _require_on(bool(opts.frozen), "FREEZE")
            opts.frozen = {}
        elif option == "COOPERATE" and self.m.cell:
            m = self.m
            holder = robot_index(rest[0]) if rest else None
            if robot is None or holder is None:
                raise B.malformed("OPTOFF COOPERATE needs ROBOT:w ROBOT:h")
            m.call(m.controller.end_cooperation, robot, holder, m.line())
        else:
            raise B.malformed(f"unknown modal option {option!r}")


def platform_target(value: object) -> tuple[float, ...]:
    """``WITH PLATFORM``'s operand — a number, or an ARRAY of numbers — as the platform's
    coordinates (mm); the controller checks their count and limits (its robot's platform)."""
    items = value.items if isinstance(value, V.ArrayValue) else (value,)
    return tuple(number(x, "WITH PLATFORM") for x in items)


def _clause(word: str) -> tuple[str, str, int]:
    """A MOVE clause word → ``(word, field, operand count)``."""
    if word in MOVE_NUMBERS:
        return (word, MOVE_NUMBERS[word], 1)
    if word in LIMIT_OPTIONS:
        return (word, LIMIT_OPTIONS[word][0], 2)
    if word == PLATFORM_WORD:
        return (word, "platform_target", 1)
    if word.startswith("RECONF:") and word[7:].isdigit() and int(word[7:]) > 0:
        return ("RECONFIGURATION", "reconfiguration", int(word[7:]))
    raise B.malformed(f"unknown MOVE clause {word!r}")


def _check_point_count(kind: str, npts: int) -> None:
    if kind not in ALL_KINDS:
        raise B.malformed(f"unknown motion kind {kind!r}")
    expected = _POINT_COUNTS.get(kind)
    if expected is not None and npts != expected:
        raise B.malformed(f"MOVE {kind} with {npts} points")


def _require_on(on: bool, what: str) -> None:
    if not on:
        raise RunFailure(f"{what} is switched off but it is not on")
