"""The robot library: description files (TOML, URDF) loaded into :class:`RobotModel`.

``resolve_robot(name_or_path, base_dir)`` is THE rule for naming a robot (programs'
``ROBOT`` clauses, ``--robot``, the API):

* a *path* (ends in ``.toml`` / ``.urdf``, or contains a path separator) is looked up
  relative to ``base_dir`` (the program's folder) first, then as given;
* for a path a *program* names (``resolver``, ``restricted=True``) only the first: the file
  must then lie inside the program's folder or the robot library once resolved
  (``irlc.lang.file_access``), unless ``allow_any_path``;
* anything else is a *library name*, case-insensitive: ``KOCH11`` → ``robots/koch11.toml``.

Loaded models are cached by resolved file path and modification time, so one run
(compile + simulate) reads the robot file once and an edited file is read again.
``load_robot(x)`` is ``resolve_robot(x)``; ``list_robots()`` names the shipped robots.
"""

from __future__ import annotations

if __name__ != "irlc.robots":  # this folder imported by its own name (from the repository root)
    raise ImportError(f"import irlc.robots, not {__name__}: this folder is irlc.robots")

from collections.abc import Callable
from pathlib import Path

from irlc.lang.file_access import (
    ALLOW_HINT,
    inside_roots,
    is_file,
    path_kind,
    read_regular_bytes,
    refusal,
    shown,
)
from irlc.robots.loader import RobotFileError, load_toml
from irlc.robots.model import Capsule, Inertial, Joint, Limits, RobotModel, Sphere

ROBOTS_DIR = Path(__file__).resolve().parent
DATALISTS_DIR = ROBOTS_DIR / "datalists"
ROBOT_SUFFIXES = (".toml", ".urdf")
_CACHE_SIZE = 16

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
    "UnknownRobotError",
    "clear_cache",
    "list_robots",
    "load_robot",
    "resolve_robot",
    "resolver",
]

_cache: dict[tuple, tuple[RobotModel, tuple]] = {}


class UnknownRobotError(RobotFileError):
    """A library name that names no shipped robot."""

    def __init__(self, name: str):
        known = ", ".join(list_robots())
        super().__init__(name, "", f"unknown robot (known: {known})")
        self.args = (f"unknown robot '{name}' (known: {known})",)  # str(): the whole sentence


def list_robots() -> list[str]:
    """Names of the robots shipped in ``robots/`` (sorted)."""
    return sorted(p.stem for p in ROBOTS_DIR.glob("*.toml"))


def is_robot_path(name_or_path: str | Path) -> bool:
    """True when ``name_or_path`` names a file rather than a library robot."""
    text = str(name_or_path)
    return text.lower().endswith(ROBOT_SUFFIXES) or "/" in text or "\\" in text


def robot_file(
    name_or_path: str | Path, base_dir: str | Path | None = None, *, restricted: bool = False
) -> Path:
    """The description file ``name_or_path`` resolves to (see the module doc).

    ``restricted``: the path is a program's (``ROBOT r := 'file'``): relative to ``base_dir``
    only, and refused outside :func:`program_roots`. Raises :class:`UnknownRobotError` for an
    unknown library name and :class:`RobotFileError` for a missing or refused file."""
    text = str(name_or_path)
    if is_robot_path(text):
        given = Path(text)
        if restricted:
            return _program_robot_file(text, Path(base_dir) if base_dir is not None else Path())
        if base_dir is not None and not given.is_absolute():
            candidate = Path(base_dir) / given
            if is_file(candidate):
                return candidate
        if is_file(given):
            return given
        raise RobotFileError(text, "", _not_found(given))
    path = ROBOTS_DIR / f"{text.lower()}.toml"
    if not text or not is_file(path):
        raise UnknownRobotError(text)
    return path


def program_roots(base_dir: Path) -> tuple[Path, ...]:
    """The folders a program's robot file may lie in: its own folder, the robot library."""
    return (base_dir, ROBOTS_DIR)


def _program_robot_file(text: str, base_dir: Path) -> Path:
    """A robot file a program names: ``base_dir / text``, inside :func:`program_roots`
    (checked before existence, so a refusal says nothing about files outside)."""
    candidate = base_dir / text  # an absolute ``text`` stays as written
    roots = program_roots(base_dir)
    if not inside_roots(candidate, roots):
        if (library := _library_copy(candidate)) is not None:
            return library
        raise RobotFileError(shown(candidate), "", f"{refusal(roots)}; {ALLOW_HINT}")
    if not is_file(candidate):
        raise RobotFileError(text, "", _not_found(candidate, " (looked in the program's folder)"))
    return candidate


def _not_found(path: Path, where: str = "") -> str:
    """Why ``path`` is no robot file: a folder, a device or pipe (never read), or nothing."""
    kind = path_kind(path)
    if kind == "folder":
        return "a folder, not a file"
    return "not a regular file" if kind == "other" else f"file not found{where}"


def _library_copy(path: Path) -> Path | None:
    """The library robot file ``path`` is a byte-identical copy of (same file name), else
    None. A program in a source tree may name the tree's ``robots/planar3.toml`` by a
    relative path; installed without ``-e``, that file lies outside the installed library
    but holds the same bytes, so the program gets the library's file — the robot it
    named, read from inside the allowed folders. Only a regular file no larger than the
    library's is read, and the answer says nothing of its text."""
    library = ROBOTS_DIR / path.name
    if path.suffix.lower() != ".toml" or not is_file(library):
        return None
    expected = library.read_bytes()
    return library if read_regular_bytes(path, len(expected)) == expected else None


def resolve_robot(
    name_or_path: str | Path, base_dir: str | Path | None = None, *, restricted: bool = False
) -> RobotModel:
    """Load a robot by library name or description file (cached; see the module doc).

    Raises :class:`RobotFileError` (or its :class:`UnknownRobotError`) for an unknown name,
    a missing, refused (``restricted``, see :func:`robot_file`) or malformed file."""
    path = robot_file(name_or_path, base_dir, restricted=restricted)
    try:
        stat = path.stat()
        real = str(path.resolve())
    except (OSError, RuntimeError, ValueError) as e:
        reason = getattr(e, "strerror", None) or "it cannot be resolved"
        raise RobotFileError(str(path), "", f"cannot read the file ({reason})") from None
    # a program's robot file may name a URDF only inside the same folders
    folder = Path(base_dir) if base_dir is not None else Path()
    roots = program_roots(folder) if restricted else None
    key = (real, stat.st_mtime_ns, stat.st_size, roots)
    cached = _cache.get(key)
    if cached is not None and cached[1] == _parent_stamps(cached[0]):
        return cached[0]
    model = _load_file(path, roots)
    if len(_cache) >= _CACHE_SIZE and key not in _cache:
        _cache.pop(next(iter(_cache)))
    _cache[key] = (model, _parent_stamps(model))
    return model


def clear_cache() -> None:
    """Forget every loaded model: the next load reads its file again (after an optional
    extra was installed or removed, which changes how a URDF-backed file loads)."""
    _cache.clear()


def _parent_stamps(model: RobotModel) -> tuple:
    """Modification stamps of the files ``model`` extends (``[robot] extends``): a cached
    variant is read again when its parent changes."""
    stamps = []
    for parent in model.extra.get("extends", ()):
        try:
            st = Path(parent).stat()
            stamps.append((st.st_mtime_ns, st.st_size))
        except OSError:
            stamps.append(None)
    return tuple(stamps)


def resolver(
    base_dir: str | Path | None = None,
    *,
    allow_any_path: bool = False,
    user_robot: str | None = None,
) -> Callable[[str], RobotModel]:
    """``name → RobotModel`` for the robot a *program* names: :func:`resolve_robot` relative
    to ``base_dir`` (the program's folder; None: the working folder), restricted to
    :func:`program_roots` unless ``allow_any_path``; ``user_robot`` (``--robot``, the
    user's choice) is never restricted. The compiler's robot resolver (its errors are
    LookupErrors)."""

    def resolve(name: str) -> RobotModel:
        users = user_robot is not None and name.lower() == user_robot.lower()
        return resolve_robot(name, base_dir, restricted=not (allow_any_path or users))

    return resolve


def _load_file(path: Path, roots: tuple[Path, ...] | None = None) -> RobotModel:
    if path.suffix.lower() == ".urdf":
        from irlc.robots.urdf_import import load_urdf

        return load_urdf(path)
    return load_toml(path, roots)


def load_robot(name_or_path: str | Path) -> RobotModel:
    """Load a robot by library name or from a ``.toml`` / ``.urdf`` file (relative to the
    working directory); see :func:`resolve_robot`."""
    return resolve_robot(name_or_path)
