"""Import a serial robot from URDF (needs the optional ``yourdfpy``: ``irlc[urdf]``).

The chain runs from the root link to a tip link (``tip``; default: the one leaf reached
through the most movable joints). Conversion into :class:`RobotModel` (SI throughout):

* revolute, continuous, prismatic joints become model joints; ``origin_i`` = the product
  of the fixed joints' origins since the previous movable joint times joint ``i``'s own
  origin; the axis is normalised. Fixed joints after the last movable one form the flange.
* limits: position (continuous joints: ±2π, so the IK box stays finite), velocity;
  URDF has no accelerations: ``accel = 5·velocity`` per second (full speed in 0.2 s),
  recorded in ``extra["assumed"]``.
* links rigidly attached through fixed joints are merged into their chain link:
  inertials combined (mass, centre of mass, parallel-axis inertia), geometry moved.
* collision shapes: sphere → sphere; cylinder (radius r, length L) → capsule over the
  axis segment of length L (it bulges r past the flat ends: conservative); box →
  the bounding capsule along its longest edge (radius = half the diagonal of the
  cross-section); meshes are skipped. Each approximation is listed in
  ``extra["urdf_notes"]``.
* unsupported: mimic joints, floating/planar joints, several moving branches without a
  chosen tip — these raise :class:`RobotFileError` with the joint or link name.
"""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path

import numpy as np
from irlc.lang.file_access import describe
from irlc.robots.inertia import inertial_problem
from irlc.robots.limits import limit_problem
from irlc.robots.model import Capsule, Inertial, Joint, Limits, RobotModel, Sphere
from irlc.robots.toml_reader import MissingExtraError, RobotFileError, robot_geometry_problem

MOVABLE = {"revolute": "revolute", "continuous": "revolute", "prismatic": "prismatic"}
ACCEL_PER_VELOCITY = 5.0  # 1/s: assumed acceleration limit = 5 × velocity limit


def _yourdfpy(file: str):
    try:
        import yourdfpy
    except ImportError:
        raise MissingExtraError(file, "urdf", "yourdfpy", "URDF import") from None
    return yourdfpy


def load_urdf(path: str | Path, tip: str | None = None, name: str | None = None) -> RobotModel:
    """Load a serial chain from a URDF file (see the module docstring).

    Non-finite numbers are reported by the checks of :func:`_convert`, so numpy's warnings
    about them (from the parser's transforms) are silenced; a parse error names its type
    and, for XML, its position — not the parser's message, which quotes the file."""
    file = str(path)
    yourdfpy = _yourdfpy(file)
    with np.errstate(all="ignore"):
        try:
            urdf = yourdfpy.URDF.load(
                file,
                build_scene_graph=False,
                build_collision_scene_graph=False,
                load_meshes=False,
                load_collision_meshes=False,
            )
        except Exception as e:
            if problem := _attribute_problem(file):  # the parser's ValueError, positioned
                raise RobotFileError(file, problem[1], problem[2], problem[0]) from None
            raise RobotFileError(file, "", f"cannot parse the URDF ({_parse_error(e)})") from None
        robot = urdf.robot
        return _convert(robot, file, tip, name or robot.name or Path(file).stem)


class _Source:
    """The URDF file for error messages: an element is named by its ``name`` where that is
    a short word (``joint 'ja'``; :func:`~irlc.lang.file_access.describe`), else by its
    place (``joint #3 (a string of 40 characters)``), and every error carries the
    element's line — never arbitrary text of the file."""

    def __init__(self, file: str, robot):
        self.file = file
        self.place = {id(e): ("joint", k) for k, e in enumerate(robot.joints, 1)}
        self.place.update({id(e): ("link", k) for k, e in enumerate(robot.links, 1)})
        self.lines = _element_lines(file)

    def key(self, element, sub: str = "") -> str:
        kind, k = self.place.get(id(element), ("element", 0))
        shown = describe(element.name)
        name = f"{kind} {shown}" if shown.startswith("'") else f"{kind} #{k} (its name is {shown})"
        return name + sub

    def error(self, element, sub: str, message: str) -> RobotFileError:
        line = self.lines.get(self.place.get(id(element), ("", 0)))
        return RobotFileError(self.file, self.key(element, sub), message, line)

    def fail(self, message: str) -> RobotFileError:
        return RobotFileError(self.file, "", message)


def _element_lines(file: str) -> dict[tuple[str, int], int]:
    """The line of the k-th ``<joint>`` / ``<link>`` of the file's ``<robot>`` (the order
    the parser reads them in), ``{}`` when lxml cannot say (no entities are resolved)."""
    try:
        from lxml import etree

        parser = etree.XMLParser(resolve_entities=False, no_network=True, huge_tree=False)
        root = etree.parse(file, parser=parser).getroot()
        return {
            (tag, k): el.sourceline
            for tag in ("joint", "link")
            for k, el in enumerate(root.findall(tag), 1)
            if el.sourceline
        }
    except Exception:  # a best-effort position: any failure leaves it out
        return {}


# Numeric attributes of URDF elements (tag, attribute) → how many numbers they hold.
_NUMBERS = {
    **{("origin", a): 3 for a in ("xyz", "rpy")},
    ("axis", "xyz"): 3,
    ("box", "size"): 3,
    ("sphere", "radius"): 1,
    **{("cylinder", a): 1 for a in ("radius", "length")},
    ("mass", "value"): 1,
    **{("inertia", a): 1 for a in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")},
    **{("limit", a): 1 for a in ("lower", "upper", "velocity", "effort")},
    ("color", "rgba"): 4,
    **{("dynamics", a): 1 for a in ("damping", "friction")},
    **{("mimic", a): 1 for a in ("multiplier", "offset")},
}


_REQUIRED = {
    "link": ("name",),
    "joint": ("name", "type"),
    "parent": ("link",),
    "child": ("link",),
    "sphere": ("radius",),
    "cylinder": ("radius", "length"),
    "box": ("size",),
    "mimic": ("joint",),
}


def _attribute_problem(file: str) -> tuple[int | None, str, str] | None:
    """Why the parser failed, positioned: (line, key, message), else None. The parser
    says neither where nor which for a malformed file (it retries with a recovering
    parser and fails later with a ``ValueError``, ``KeyError``, ``TypeError`` …): XML that
    is not well-formed, a missing required attribute or ``<parent>``/``<child>``, a
    numeric attribute (:data:`_NUMBERS`) that is not its count of numbers."""
    try:
        from lxml import etree

        parser = etree.XMLParser(resolve_entities=False, no_network=True, huge_tree=False)
        root = etree.parse(file, parser=parser).getroot()
    except ImportError:
        return None
    except Exception as e:
        line, column = getattr(e, "position", (None, None))
        return line, "", f"not well-formed XML ({type(e).__name__} at column {column})"
    for el in root.iter():
        if isinstance(el.tag, str) and (problem := _element_problem(el)):
            return el.sourceline, *problem
    return None


def _element_problem(el) -> tuple[str, str] | None:
    """(key, message) of one element's missing or malformed attribute, else None."""
    for attr in _REQUIRED.get(el.tag, ()):
        if attr not in el.attrib:
            return f"<{el.tag}>", f"missing the attribute '{attr}'"
    if el.tag == "geometry" and any(
        isinstance(c.tag, str) and c.tag not in ("box", "cylinder", "sphere", "mesh") for c in el
    ):
        return "<geometry>", "expected a box, cylinder, sphere or mesh element"
    if el.tag == "joint" and el.getparent() is not None and el.getparent().tag == "robot":
        for end in ("parent", "child"):
            if el.find(end) is None:
                return "<joint>", f"missing its <{end}> element"
    for attr, text in el.attrib.items():
        count = _NUMBERS.get((el.tag, attr))
        if count is None:
            continue
        try:
            ok = len([float(w) for w in text.split()]) == count
        except ValueError:
            ok = False
        if not ok:
            return f"<{el.tag}> {attr}", f"expected {count} number(s), got {describe(text)}"
    return None


def _names(names: list[str], most: int = 4) -> str:
    """Element names for a message: each described (short words shown), at most ``most``."""
    shown = ", ".join(describe(n) for n in names[:most])
    return shown + (f" and {len(names) - most} more" if len(names) > most else "")


def _parse_error(e: Exception) -> str:
    """``XMLSyntaxError at line 3, column 12`` (lxml's position), else the error's type."""
    position = getattr(e, "position", None)
    if isinstance(position, tuple) and len(position) == 2:
        return f"{type(e).__name__} at line {position[0]}, column {position[1]}"
    return type(e).__name__


def _convert(robot, file: str, tip: str | None, name: str) -> RobotModel:
    src = _Source(file, robot)
    by_child = {j.child: j for j in robot.joints}
    links = {link.name: link for link in robot.links}
    _check_tree(robot, src, links)
    for j in robot.joints:
        if j.mimic is not None:
            raise src.error(j, "", "mimic joints are not supported")
        if j.type not in MOVABLE and j.type != "fixed":
            raise src.error(
                j,
                "",
                f"joint type {describe(j.type)} is not supported"
                " (revolute, continuous, prismatic, fixed)",
            )
    roots = [n for n in links if n not in by_child]
    path = _chain(robot, src, roots[0], by_child, tip)
    notes: list[str] = []
    assumed: dict[str, str] = {}
    joints: list[Joint] = []
    owner = {roots[0]: 0}  # link name → model link index
    frame_of = {roots[0]: np.eye(4)}  # link name → pose in its model link's frame
    for j in path:
        if j.type == "fixed":
            owner[j.child] = len(joints)
            frame_of[j.child] = frame_of[j.parent] @ _origin(j)
            continue
        joints.append(_joint(j, src, frame_of[j.parent] @ _origin(j), assumed))
        owner[j.child] = len(joints)
        frame_of[j.child] = np.eye(4)
    flange = frame_of[path[-1].child] if path else np.eye(4)
    _attach_fixed_branches(robot, owner, frame_of)
    geometry, inertials = [], []
    for link_name, index in owner.items():
        link = links[link_name]
        geometry += _shapes(link, index, frame_of[link_name], notes, src)
    for index in range(len(joints) + 1):
        parts = [(links[n], frame_of[n]) for n, k in owner.items() if k == index]
        merged = _merged_inertial(parts, index, src)
        if merged is not None:
            inertials.append(merged)
    if not joints:
        tip_link = links[path[-1].child] if path else links[roots[0]]
        raise src.error(tip_link, "", "no movable joint between the root link and this tip")
    n = len(joints)
    joints = [replace(j, weight=float(n - i)) for i, j in enumerate(joints)]  # w_i = n − i + 1
    home = np.array([_home_value(j) for j in joints])
    return RobotModel(
        name=name,
        joints=tuple(joints),
        flange=flange,
        home=home,
        geometry=tuple(geometry),
        inertials=tuple(inertials),
        extra={"assumed": assumed, "urdf_notes": notes, "urdf": file},
        source=file,
        description=f"imported from URDF {Path(file).name}",
    )


def _check_tree(robot, src: _Source, links: dict) -> None:
    """Every joint joins two declared links, each link has at most one parent joint, and
    every link hangs from the one root (no cycle): the walks below rely on a tree."""
    parent_joint: dict[str, object] = {}
    for j in robot.joints:
        for end in ("parent", "child"):
            if getattr(j, end) not in links:
                raise src.error(j, f".{end}", f"no link named {describe(getattr(j, end))}")
        if j.child in parent_joint:
            raise src.error(
                j,
                ".child",
                f"link {describe(j.child)} already hangs from {src.key(parent_joint[j.child])}",
            )
        parent_joint[j.child] = j
    roots = [n for n in links if n not in parent_joint]
    if len(roots) > 1:  # at the second: the link no joint holds that the user must join
        raise src.error(
            links[roots[1]],
            "",
            f"a second root link (no joint has it as its child; roots: {_names(roots)})",
        )
    if not roots:
        raise src.fail("no root link: every link is some joint's child (a cycle)")
    children: dict[str, list[str]] = {}
    for j in robot.joints:
        children.setdefault(j.parent, []).append(j.child)
    reached, todo = {roots[0]}, [roots[0]]
    while todo:
        for child in children.get(todo.pop(), []):
            if child not in reached:
                reached.add(child)
                todo.append(child)
    if len(reached) != len(links):
        loose = next(lk for lk in robot.links if lk.name not in reached)
        raise src.error(loose, "", "not connected to the root link (the joints form a cycle)")


def _chain(robot, src: _Source, root: str, by_child: dict, tip: str | None) -> list:
    """Joints from the root to the tip, in order."""
    children: dict[str, list] = {}
    for j in robot.joints:
        children.setdefault(j.parent, []).append(j)
    leaves = [lk.name for lk in robot.links if lk.name not in children]
    if tip is not None:
        if tip not in {lk.name for lk in robot.links}:
            raise RobotFileError(src.file, "tip", f"no link named {describe(tip)}")
        chosen = tip
    else:

        def movable(leaf: str) -> list[str]:
            return [j.name for j in _path(root, leaf, by_child) if j.type != "fixed"]

        ranked = sorted(leaves, key=lambda lf: (len(movable(lf)), len(_path(root, lf, by_child))))
        best = ranked[-1]
        best_set = set(movable(best))
        for other in ranked[:-1]:
            if not set(movable(other)) <= best_set:
                raise RobotFileError(
                    src.file,
                    "tip",
                    f"the tree branches (leaves {_names(leaves)});"
                    " choose the tip link (load_urdf(path, tip=...) or "
                    '[robot] tip = "...")',
                )
        chosen = best
    return _path(root, chosen, by_child)


def _path(root: str, leaf: str, by_child: dict) -> list:
    out = []
    link = leaf
    while link != root:
        j = by_child[link]
        out.append(j)
        link = j.parent
    return out[::-1]


def _attach_fixed_branches(robot, owner: dict, frame_of: dict) -> None:
    """Links hanging off the chain through fixed joints belong to the chain link."""
    changed = True
    while changed:
        changed = False
        for j in robot.joints:
            if j.type == "fixed" and j.parent in owner and j.child not in owner:
                owner[j.child] = owner[j.parent]
                frame_of[j.child] = frame_of[j.parent] @ _origin(j)
                changed = True


def _origin(j) -> np.ndarray:
    return np.eye(4) if j.origin is None else np.asarray(j.origin, dtype=float)


def _joint(j, src: _Source, origin: np.ndarray, assumed: dict) -> Joint:
    kind = MOVABLE[j.type]
    _check_point(src, j, ".origin", origin[:3, 3])
    _check_finite(src, j, ".origin", origin)
    axis = np.array([1.0, 0.0, 0.0]) if j.axis is None else np.asarray(j.axis, dtype=float)
    if axis.shape != (3,):
        raise src.error(j, ".axis", "expected 3 numbers")
    _check_finite(src, j, ".axis", axis)
    axis = axis / max(float(np.max(np.abs(axis))), 1e-300)  # no overflow in the norm below
    norm = float(np.linalg.norm(axis))
    if norm < 1e-12:
        raise src.error(j, ".axis", "expected a non-zero axis")
    lim = j.limit
    if j.type == "continuous":
        position = (-2 * math.pi, 2 * math.pi)
    else:
        if lim is None or lim.lower is None or lim.upper is None:
            raise src.error(j, ".limit", "expected lower and upper")
        position = (float(lim.lower), float(lim.upper))
        _check_finite(src, j, ".limit", np.array(position))
        if position[0] > position[1]:
            raise src.error(j, ".limit", "expected lower ≤ upper")
    velocity = None if lim is None else lim.velocity
    if velocity is None or not velocity > 0.0:
        raise src.error(
            j,
            ".limit.velocity",
            "expected a positive velocity limit (the runtime needs one)",
        )
    v = float(velocity)
    _check_finite(src, j, ".limit.velocity", np.array([ACCEL_PER_VELOCITY * v]))
    for sub, values in ((".limit", position), (".limit.velocity", (ACCEL_PER_VELOCITY * v,))):
        if problem := limit_problem(values, 1.0):
            raise src.error(j, sub, problem)
    a = ACCEL_PER_VELOCITY * v
    assumed[f"joint '{j.name}' acceleration"] = (
        f"URDF has no acceleration limit: {ACCEL_PER_VELOCITY:g} × velocity = {a:g}/s²"
    )
    return Joint(j.name, kind, origin, axis / norm, Limits(position, (-v, v), (-a, a)))


def _home_value(j: Joint) -> float:
    lo, hi = j.limits.position
    return 0.0 if lo <= 0.0 <= hi else 0.5 * (lo + hi)


def _shapes(link, index: int, frame: np.ndarray, notes: list[str], src: _Source) -> list:
    out: list[Capsule | Sphere] = []
    for c in link.collisions or []:
        key = ".collision"
        local = np.eye(4) if c.origin is None else np.asarray(c.origin, dtype=float)
        _check_finite(src, link, f"{key}.origin", local)
        _check_point(src, link, f"{key}.origin", local[:3, 3])
        t = frame @ local
        g = c.geometry
        if g.sphere is not None:
            radius = _length(src, link, f"{key}.sphere.radius", g.sphere.radius)
            out.append(Sphere(index, t[:3, 3].copy(), radius))
        elif g.cylinder is not None:
            half = 0.5 * _length(src, link, f"{key}.cylinder.length", g.cylinder.length)
            a, b = _segment(t, 2, half)
            radius = _length(src, link, f"{key}.cylinder.radius", g.cylinder.radius)
            out.append(Capsule(index, a, b, radius))
            notes.append(f"{link.name}: cylinder → capsule (ends bulge by the radius)")
        elif g.box is not None:
            size = np.asarray(g.box.size, dtype=float)
            if size.shape != (3,):
                raise src.error(link, f"{key}.box.size", "expected 3 numbers")
            for s in size:
                _length(src, link, f"{key}.box.size", s)
            k = int(np.argmax(size))
            others = [s for i, s in enumerate(size) if i != k]
            radius = 0.5 * math.hypot(*others)
            a, b = _segment(t, k, 0.5 * size[k])
            out.append(Capsule(index, a, b, radius))
            notes.append(f"{link.name}: box → bounding capsule along its longest edge")
        else:
            notes.append(f"{link.name}: mesh/unknown collision shape skipped")
    return out


def _check_finite(src: _Source, element, sub: str, values: np.ndarray) -> None:
    if not np.all(np.isfinite(values)):
        raise src.error(element, sub, "expected finite numbers")


def _check_point(src: _Source, element, sub: str, xyz: np.ndarray) -> None:
    """A position (m) inside the physical range of geometry (irdata.geometry_problem)."""
    if problem := robot_geometry_problem("point", xyz):
        raise src.error(element, sub, problem)


def _length(src: _Source, element, sub: str, value) -> float:
    """A length (m): a number inside the physical range of geometry."""
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise src.error(element, sub, f"expected a number, got {describe(value)}") from None
    if problem := robot_geometry_problem("length", np.array([v])):
        raise src.error(element, sub, problem)
    return v


def _segment(t: np.ndarray, axis: int, half: float) -> tuple[np.ndarray, np.ndarray]:
    d = t[:3, axis] * half
    return t[:3, 3] - d, t[:3, 3] + d


def _merged_inertial(parts: list, index: int, src: _Source) -> Inertial | None:
    """Combine the inertials of rigidly joined links (in the chain link's frame)."""
    items = []
    for link, frame in parts:
        inertial = link.inertial
        if inertial is None or inertial.mass is None or inertial.mass <= 0.0:
            continue
        t = frame @ (np.eye(4) if inertial.origin is None else np.asarray(inertial.origin))
        r = t[:3, :3]
        inertia = np.zeros((3, 3)) if inertial.inertia is None else np.asarray(inertial.inertia)
        values = np.array([inertial.mass, *t.ravel(), *inertia.ravel()])
        _check_finite(src, link, ".inertial", values)
        _check_point(src, link, ".inertial.origin", t[:3, 3])
        if problem := inertial_problem(float(inertial.mass), inertia):
            raise src.error(link, ".inertial", problem)
        items.append((float(inertial.mass), t[:3, 3], r @ inertia @ r.T))
    if not items:
        return None
    mass = sum(m for m, _, _ in items)
    com = sum(m * c for m, c, _ in items) / mass
    total = np.zeros((3, 3))
    for m, c, inertia in items:
        d = c - com
        total += inertia + m * (float(d @ d) * np.eye(3) - np.outer(d, d))
    return Inertial(index, mass, com, total)
