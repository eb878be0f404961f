"""Reading a robot description file's TOML tree: typed values, units and error messages.

:class:`Reader` gives typed access to the parsed tree; every failure is a
:class:`RobotFileError` naming the file, the key (``joints[3].axis``) and the expected
shape. It holds the file's units (``[robot].units``: ``angle`` deg | rad, ``length`` m |
mm); the readers multiply by them, so everything past the reader is SI. Robot geometry
(transform offsets, link vectors, collision shapes) must lie in the physical range of
geometry that obstacles share (:func:`irlc.lang.geometry_range.geometry_problem`).
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np
from irlc.lang.errors import IrlcError
from irlc.lang.file_access import describe, is_finite_number, shown_key
from irlc.lang.geometry_range import geometry_problem
from irlc.lang.toml_keys import key_line
from irlc.runtime.model.spatial import zyx_to_matrix

ANGLE_UNITS = {"deg": math.pi / 180.0, "rad": 1.0}
LENGTH_UNITS = {"m": 1.0, "mm": 1e-3}
TRANSFORM_KEYS = {"xyz", "zyx", "matrix", "assumed", "reason"}


class RobotFileError(IrlcError, LookupError):
    """A robot description file is malformed: ``FILE: key 'K': expected ..., got ...``.

    A ``LookupError``: the robot cannot be had, which is what the compiler's robot
    resolvers raise (``irlc.lang.signature``)."""

    def __init__(self, file: str, key: str, message: str, line: int | None = None):
        if line is None and key:
            line = _key_line(file, key)
        self.file, self.key, self.message, self.line = file, key, message, line
        where = f"{file}:{line}" if line else file
        text = f"{where}: key '{shown_key(key)}': {message}" if key else f"{where}: {message}"
        super().__init__(text)


def _key_line(file: str, key: str) -> int | None:
    """The line of ``key`` in the TOML file ``file`` (:func:`irlc.lang.toml_keys.key_line`),
    ``None`` when the file is not a TOML file that can be read again."""
    if not file.lower().endswith(".toml"):
        return None
    try:
        text = Path(file).read_text(encoding="utf-8-sig")
    except (OSError, UnicodeDecodeError, ValueError):
        return None
    return key_line(text, key)


class MissingExtraError(RobotFileError):
    """The file needs an optional extra of irlc that is not installed (``extra``: its name,
    as in ``pip install 'irlc[EXTRA]'``)."""

    def __init__(self, file: str, extra: str, package: str, what: str):
        self.extra, self.package = extra, package
        super().__init__(
            file, "", f"{what} needs the optional package {package}: pip install 'irlc[{extra}]'"
        )


class Reader:
    """Typed access to a parsed TOML tree with error messages that name file and key."""

    def __init__(self, file: str, angle: str = "deg", length: str = "m"):
        self.file = file
        self.set_units(angle, length)

    def set_units(self, angle: str, length: str) -> None:
        """The file's units by name (keys of :data:`ANGLE_UNITS`, :data:`LENGTH_UNITS`);
        ``angle`` / ``length`` are their sizes in rad / m."""
        self.angle, self.length = ANGLE_UNITS[angle], LENGTH_UNITS[length]
        self.length_unit = length

    def scale(self, kind: str) -> float:
        """The SI size of one file unit of a joint of ``kind`` (revolute: angle, else length)."""
        return self.angle if kind == "revolute" else self.length

    def in_range(self, key: str, what: str, values_m) -> None:
        """Fail unless robot geometry ``values_m`` (SI) is in the physical range."""
        if problem := robot_geometry_problem(what, np.atleast_1d(values_m), self.length_unit):
            raise self.fail(key, problem)

    def fail(self, key: str, message: str) -> RobotFileError:
        return RobotFileError(self.file, key, message)

    def table(self, value: Any, key: str, allowed: set[str] | None = None) -> dict:
        if not isinstance(value, dict):
            raise self.fail(key, f"expected a table, got {show(value)}")
        if allowed is not None:
            unknown = sorted(set(value) - allowed)
            if unknown:
                raise self.fail(
                    join_key(key, unknown[0]),
                    f"unknown key; expected one of {', '.join(sorted(allowed))}",
                )
        return value

    def number(self, value: Any, key: str) -> float:
        if isinstance(value, bool) or not isinstance(value, int | float):
            raise self.fail(key, f"expected a number, got {show(value)}")
        if not is_finite_number(value):
            raise self.fail(key, f"expected a finite number, got {show(value)}")
        return float(value)

    def positive(self, value: Any, key: str) -> float:
        v = self.number(value, key)
        if v <= 0.0:
            raise self.fail(key, f"expected a positive number, got {v:g}")
        return v

    def non_negative(self, value: Any, key: str) -> float:
        v = self.number(value, key)
        if v < 0.0:
            raise self.fail(key, f"expected a non-negative number, got {v:g}")
        return v

    def string(self, value: Any, key: str, choices: tuple[str, ...] | None = None) -> str:
        if not isinstance(value, str):
            raise self.fail(key, f"expected a string, got {show(value)}")
        if choices is not None and value not in choices:
            raise self.fail(key, f"expected one of {', '.join(choices)}, got {show(value)}")
        return value

    def boolean(self, value: Any, key: str) -> bool:
        if not isinstance(value, bool):
            raise self.fail(key, f"expected true or false, got {show(value)}")
        return value

    def vector(self, value: Any, key: str, size: int) -> np.ndarray:
        if not isinstance(value, list) or len(value) != size:
            raise self.fail(key, f"expected {size} numbers, got {show(value)}")
        return np.array([self.number(v, f"{key}[{i}]") for i, v in enumerate(value)])

    def numbers(self, value: Any, key: str) -> np.ndarray:
        if not isinstance(value, list):
            raise self.fail(key, f"expected a list of numbers, got {show(value)}")
        return np.array([self.number(v, f"{key}[{i}]") for i, v in enumerate(value)])

    def array_of_tables(self, value: Any, key: str) -> list[dict]:
        if not isinstance(value, list) or not all(isinstance(v, dict) for v in value):
            raise self.fail(key, f"expected an array of tables ([[{key}]]), got {show(value)}")
        return value

    def transform(self, value: Any, key: str) -> np.ndarray:
        """``{xyz = [..], zyx = [a, b, c]}`` (R = Rz(a)Ry(b)Rx(c)) or ``{matrix = 4×4}``."""
        t = self.table(value, key, TRANSFORM_KEYS)
        self.assumption(t, key)
        if "matrix" in t:
            if "xyz" in t or "zyx" in t:
                raise self.fail(key, "give either matrix or xyz/zyx, not both")
            rows = t["matrix"]
            if not isinstance(rows, list) or len(rows) != 4:
                raise self.fail(join_key(key, "matrix"), f"expected 4 rows of 4, got {show(rows)}")
            m = np.array([self.vector(r, f"{key}.matrix[{i}]", 4) for i, r in enumerate(rows)])
            m[:3, 3] *= self.length
            check_rigid(self, m, join_key(key, "matrix"))
            self.in_range(join_key(key, "matrix"), "point", m[:3, 3])
            return m
        out = np.eye(4)
        if "zyx" in t:
            a, b, c = self.vector(t["zyx"], join_key(key, "zyx"), 3) * self.angle
            out[:3, :3] = zyx_to_matrix(a, b, c)
        if "xyz" in t:
            out[:3, 3] = self.vector(t["xyz"], join_key(key, "xyz"), 3) * self.length
            self.in_range(join_key(key, "xyz"), "point", out[:3, 3])
        return out

    def assumption(self, t: dict, key: str) -> tuple[bool, str]:
        """``assumed = true`` must come with a non-empty ``reason``."""
        assumed = self.boolean(t.get("assumed", False), join_key(key, "assumed"))
        reason = t.get("reason", "")
        reason = self.string(reason, join_key(key, "reason"))
        if assumed and not reason.strip():
            raise self.fail(join_key(key, "reason"), "assumed = true needs a reason (a string)")
        return assumed, reason


def join_key(key: str, sub: str) -> str:
    return f"{key}.{sub}" if key else sub


def show(value: Any) -> str:
    return describe(value)  # never the text of the file (irlc.lang.file_access)


def robot_geometry_problem(what: str, values_m, unit: str = "m") -> str | None:
    """:func:`~irlc.lang.geometry_range.geometry_problem` of robot geometry given in SI metres,
    the message speaking ``unit`` (the file's length unit)."""
    scale = LENGTH_UNITS[unit]
    values = np.asarray(values_m, dtype=float).ravel() / scale
    if not np.all(np.isfinite(values)):
        return "expected finite numbers"
    return geometry_problem(what, values, unit, scale * 1e3)


def check_rigid(rd: Reader, m: np.ndarray, key: str) -> None:
    r = m[:3, :3]
    if not np.allclose(r @ r.T, np.eye(3), atol=1e-6) or np.linalg.det(r) < 0.0:
        raise rd.fail(key, "expected a rigid transform (orthonormal rotation, det +1)")
    if not np.allclose(m[3], [0.0, 0.0, 0.0, 1.0]):
        raise rd.fail(key, "expected last row [0, 0, 0, 1]")
