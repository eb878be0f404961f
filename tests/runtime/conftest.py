"""Helpers for the runtime tests: small robots built from the model dataclasses, and a
tiny IRDATA builder so that the pipeline is tested on *code* (independently of the
compiler)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from irlc.lang.irdata import read_code
from irlc.robots.model import Capsule, Joint, Limits, RobotModel

DEG = math.pi / 180.0


def _trans(x: float, y: float, z: float) -> np.ndarray:
    t = np.eye(4)
    t[:3, 3] = (x, y, z)
    return t


def planar_robot(
    n: int = 3,
    link: float = 1.0,
    *,
    speed_deg: float = 90.0,
    accel_deg: float = 500.0,
    home_deg=None,
    name: str | None = None,
    position_deg: float = 180.0,
) -> RobotModel:
    """Planar nR arm in the xy plane (axes z, links along x); task = TCP x, y."""
    lim = Limits(
        (-position_deg * DEG, position_deg * DEG),
        (-speed_deg * DEG, speed_deg * DEG),
        (-accel_deg * DEG, accel_deg * DEG),
    )
    joints = tuple(
        Joint(
            f"J{i + 1}",
            "revolute",
            np.eye(4) if i == 0 else _trans(link, 0, 0),
            np.array([0.0, 0.0, 1.0]),
            lim,
            weight=float(n - i),
        )
        for i in range(n)
    )
    geometry = tuple(Capsule(i + 1, np.zeros(3), np.array([link, 0, 0]), 0.05) for i in range(n))
    home = None if home_deg is None else np.radians(home_deg)
    return RobotModel(
        name or f"planar{n}t",
        joints,
        flange=_trans(link, 0, 0),
        home=home,
        geometry=geometry,
        extra={"ik": {"task": ["x", "y"]}},
    )


class Ird:
    """Builds IRDATA text: constants, one MAIN routine, instructions with source lines."""

    def __init__(
        self, robot: str, kinds: str, names: tuple[str, ...] | None = None, program: str = "t"
    ):
        self.robot, self.kinds, self.program = robot, kinds, program
        self.names = names or tuple(f"a{i + 1}" for i in range(len(kinds)))
        self.consts: list[str] = []
        self.code: list[str] = []
        self.obstacles: list[str] = []

    def const(self, type_: str, *data: float) -> int:
        self.consts.append(" ".join([type_, *(repr(float(d)) for d in data)]))
        return len(self.consts) - 1

    def pose(self, x, y, z, a=0.0, b=0.0, c=0.0) -> int:
        return self.const("POSE", x, y, z, a, b, c)

    def joints(self, *values, type_: str = "MAIN_JOINT") -> int:
        return self.const(type_, *values)

    def obstacle(self, name: str, kind: str, **fields) -> None:
        parts = [f"OBSTACLE {name} {kind}"]
        for key, vals in fields.items():
            vals = vals if isinstance(vals, list | tuple) else [vals]
            parts.append(key + " " + " ".join(repr(float(v)) for v in vals))
        self.obstacles.append(" ".join(parts))

    def op(self, line: int, *words) -> Ird:
        self.code.append(" ".join([f"L{line}", *map(str, words)]))
        return self

    def push(self, line: int, k: int) -> Ird:
        return self.op(line, "PUSHC", k)

    def sys(self, line: int, name: str, value: float) -> Ird:
        return self.push(line, self.const("REAL", value)).op(line, "POPSYS", name)

    def move(self, line: int, kind: str, *targets: int, clauses=()) -> Ird:
        """``clauses``: (word, const indices…) pairs, e.g. ("SPEED", k) or
        ("RECONF:1", k) or ("JOINTLIMIT", kmin, kmax)."""
        for t in targets:
            self.push(line, t)
        words = []
        for word, *operands in clauses:
            for k in operands:
                self.push(line, k)
            words.append(word)
        return self.op(line, "MOVE", kind, len(targets), *words)

    def text(self) -> str:
        recs = [
            f"PROGRAM {self.program}",
            f"SOURCE '{self.program}.irl'",
            f"ROBOT r {self.robot} {len(self.kinds)} {self.kinds}",
            "JOINTS " + " ".join(self.names),
            "UNITS mm deg s",
        ]
        recs += [f"CONST {i} {c}" for i, c in enumerate(self.consts)]
        recs += self.obstacles
        entry = len(recs) + 3  # ROUTINE and CODE records, then the first instruction
        recs.append(f"ROUTINE 0 {self.program} MAIN 0 0 @{entry}")
        recs.append("CODE")
        code = [*self.code, "L0 END"]
        lines = ["IRDATA 1"]
        lines += [f"{i + 1} {r}" for i, r in enumerate(recs + code)]
        return "\n".join(lines) + "\n"

    def code_object(self):
        return read_code(self.text(), f"{self.program}.ird")

    def write(self, folder: Path) -> Path:
        path = folder / f"{self.program}.ird"
        path.write_text(self.text(), encoding="utf-8")
        return path


def square_lap(p: Ird, corners: list[int], line0: int = 10) -> None:
    for i, c in enumerate(corners):
        p.move(line0 + i, "LIN", c)


@pytest.fixture
def planar3() -> RobotModel:
    return planar_robot(3, home_deg=(0.0, 90.0, -90.0))
