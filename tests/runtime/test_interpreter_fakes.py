"""Test helpers for the interpreter: a fake controller and a tiny IRDATA assembler.

(Named ``test_interpreter_*`` to stay inside the interpreter's test files; it holds no
tests itself.)

The fake robot has three joints ``a1 a2`` (revolute, deg) and ``a3`` (prismatic, mm):
a planar 2R arm with links 1000 mm and 500 mm in the XY plane, and a vertical slide:

    x = 1000 cos a1 + 500 cos(a1 + a2),  y = 1000 sin a1 + 500 sin(a1 + a2),  z = a3,
    orientation = Rz(a1 + a2).
"""

from __future__ import annotations

import math
import re

from irlc.lang.irdata import Code, read_code
from irlc.runtime import values as V
from irlc.runtime.commands import ModalOptions, MotionCommand, Settings
from irlc.runtime.errors import RunFailure
from irlc.runtime.interpreter import ExecutionResult, Interpreter, MachineState
from irlc.runtime.values import JointTuple, Pose

L1, L2 = 1000.0, 500.0


def planar_fk(q: tuple[float, ...]) -> tuple[float, float, float, float]:
    """(x, y, z, yaw) of the fake robot, mm and degrees — the closed form above."""
    a1, a2 = math.radians(q[0]), math.radians(q[1])
    x = L1 * math.cos(a1) + L2 * math.cos(a1 + a2)
    y = L1 * math.sin(a1) + L2 * math.sin(a1 + a2)
    return x, y, q[2], q[0] + q[1]


class FakeController:
    """Records what the interpreter asks for; PTP to joints moves the joints at once."""

    def __init__(self, joints=(0.0, 0.0, 0.0), move_time: float = 1.0, ipo: float | None = None):
        self.q = [float(v) for v in joints]
        self.t = 0.0
        self.move_time = move_time
        self.ipo = ipo  # if set, WAIT advances in IPO steps (like the real controller)
        self.moves: list[tuple[MotionCommand, Settings, ModalOptions]] = []
        self.reconfs: list[tuple[JointTuple, int, ModalOptions]] = []
        self.waits: list[tuple[float, int]] = []
        self.events: list[dict] = []
        self.fail_move: RunFailure | None = None

    @property
    def time(self) -> float:
        return self.t

    def joints(self) -> tuple[float, ...]:
        return tuple(self.q)

    def pose(self, settings: Settings) -> Pose:
        return self.forward(JointTuple("MAIN_JOINT", tuple(self.q)), settings)

    def forward(self, joints: JointTuple, settings: Settings) -> Pose:
        x, y, z, yaw = planar_fk(joints.values)
        return V.pose_from_zyx(x, y, z, yaw, 0.0, 0.0)

    def move(self, cmd: MotionCommand, settings: Settings, options: ModalOptions) -> None:
        if self.fail_move is not None:
            raise self.fail_move
        self.moves.append((cmd, settings, options))
        target = cmd.targets[-1]
        if cmd.kind == "PTP" and isinstance(target, JointTuple):
            self.q = list(target.values)
        elif cmd.kind == "PTPINC":
            self.q = [a + b for a, b in zip(self.q, target.values, strict=True)]
        self.t += self.move_time

    def reconfigure(self, target, line, settings, options) -> None:
        self.reconfs.append((target, line, options))
        self.q = list(target.values)
        self.t += self.move_time

    def wait(self, seconds, line, settings, options) -> None:
        self.waits.append((seconds, line))
        if self.ipo is None:
            self.t += seconds
            return
        for _ in range(math.ceil(seconds / self.ipo - 1e-9)):
            self.t += self.ipo  # accumulates rounding like a real cycle counter

    def log_event(self, kind: str, line: int, **data) -> None:
        self.events.append({"kind": kind, "line": line, "time_s": self.t, **data})


HEADER = """PROGRAM t
SOURCE 't.irl'
ROBOT r fake 3 RRP
JOINTS a1 a2 a3
UNITS mm deg s"""

_LABEL = re.compile(r"^([A-Za-z_]\w*):\s+(.*)$")


def assemble(text: str, header: str = HEADER) -> str:
    """IRDATA text from records without numbers; ``name: L1 OP`` labels, ``@name`` targets."""
    records = [r.strip() for r in (header + "\n" + text).strip().splitlines() if r.strip()]
    labels: dict[str, int] = {}
    body = []
    for n, rec in enumerate(records, start=1):
        while (m := _LABEL.match(rec)) is not None:
            labels[m.group(1)] = n
            rec = m.group(2)
        body.append(rec)
    out = ["IRDATA 1"]
    for n, rec in enumerate(body, start=1):
        rec = re.sub(r"@([A-Za-z_]\w*)", lambda m: f"@{labels[m.group(1)]}", rec)
        out.append(f"{n} {rec}")
    return "\n".join(out) + "\n"


def code_of(text: str, header: str = HEADER) -> Code:
    return read_code(assemble(text, header), "t.ird")


def main_program(
    body: str, decls: str = "", consts: str = "", routines: str = "", nlocals: int = 0
) -> Code:
    """A program whose main routine (entry label ``main``) runs ``body``."""
    text = f"{consts}\n{decls}\nROUTINE 0 t MAIN 0 {nlocals} @main\n{routines}\nCODE\n{body}"
    return code_of(text)


def run(
    code: Code,
    controller: FakeController | None = None,
    *,
    check: bool = True,
    state: MachineState | None = None,
    **kwargs,
) -> ExecutionResult:
    ctl = controller if controller is not None else FakeController()
    return Interpreter(code, ctl, state=state, **kwargs).run(check=check)


def failure(code: Code, controller: FakeController | None = None, **kwargs) -> RunFailure:
    result = run(code, controller, check=False, **kwargs)
    assert result.status == "failed", result
    assert result.error is not None
    return result.error
