"""The robot library: description files (TOML, URDF) loaded into :class:`RobotModel`.

``load_robot("koch11")`` reads ``robots/koch11.toml``; a path ending in ``.toml`` or
``.urdf`` loads that file. ``list_robots()`` names the shipped robots.
"""

from __future__ import annotations

from pathlib import Path

from irlc.robots.loader import RobotFileError, load_toml
from irlc.robots.model import Capsule, Inertial, Joint, Limits, RobotModel, Sphere

ROBOTS_DIR = Path(__file__).resolve().parent
DATALISTS_DIR = ROBOTS_DIR / "datalists"

__all__ = [
    "DATALISTS_DIR",
    "ROBOTS_DIR",
    "Capsule",
    "Inertial",
    "Joint",
    "Limits",
    "RobotFileError",
    "RobotModel",
    "Sphere",
    "list_robots",
    "load_robot",
]


def list_robots() -> list[str]:
    """Names of the robots shipped in ``robots/`` (sorted)."""
    return sorted(p.stem for p in ROBOTS_DIR.glob("*.toml"))


def load_robot(name_or_path: str | Path) -> RobotModel:
    """Load a robot by library name or from a ``.toml`` / ``.urdf`` file.

    Raises :class:`RobotFileError` for a malformed file, an unknown name or a missing file.
    """
    text = str(name_or_path)
    if text.endswith((".toml", ".urdf")) or "/" in text or "\\" in text:
        path = Path(text)
        if not path.is_file():
            raise RobotFileError(text, "", "file not found")
        if path.suffix == ".urdf":
            from irlc.robots.urdf_import import load_urdf

            return load_urdf(path)
        return load_toml(path)
    path = ROBOTS_DIR / f"{text}.toml"
    if not path.is_file():
        known = ", ".join(list_robots())
        raise RobotFileError(text, "", f"unknown robot; known robots: {known}")
    return load_toml(path)
