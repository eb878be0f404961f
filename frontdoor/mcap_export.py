"""``irlc run … --mcap FILE.mcap``: the run as an MCAP file of ROS 2 messages.

Foxglove, PlotJuggler and the ROS 2 tools (``ros2 bag play``) open it as it is. Every
message is stamped in simulated time (``t`` of the run → ``sec``/``nanosec``; the
MCAP log and publish times are the same nanoseconds), in SI as ROS wants it:

==================== ================================ ==========================================
topic                type                             content
==================== ================================ ==========================================
``/joint_states``    ``sensor_msgs/msg/JointState``   per trace row: the robot file's joint names
                                                      (as the trajectory export), ``position``
                                                      rad | m, ``velocity`` at the sample
                                                      (:func:`irlc.export.sample_derivatives`)
``/tf``              ``tf2_msgs/msg/TFMessage``       per trace row: ``base`` → ``tcp``
``/tf_static``       ``tf2_msgs/msg/TFMessage``       at the start: ``world`` → ``base`` (the
                                                      robot file's base), ``world`` →
                                                      ``obstacle/NAME`` per obstacle
``/markers``         ``visualization_msgs/msg/        at the start, in ``world``: the obstacles
                     MarkerArray``                    (ns ``obstacles``), the programmed path of
                                                      the Cartesian motions (``programmed_path``,
                                                      one line strip per stretch) and the TCP's
                                                      path (``tcp_path``)
``/outputs/out_N``   ``std_msgs/msg/Bool``            digital output N: FALSE at the start (its
                                                      value before the first switch), then one
                                                      message per switch (``OUT[N]``, ``PULSE``)
``/signals/NAME``    ``std_msgs/msg/Bool``            SIGNAL variable NAME, likewise
==================== ================================ ==========================================

A cell (several robots): per robot ``/NAME/joint_states``, its frames ``NAME/base`` (placed
by its ``AT``: ``world`` → ``NAME/base`` in ``/tf_static``) and ``NAME/tcp`` (``/tf``: one
message per trace row with every robot's ``NAME/base`` → ``NAME/tcp``), its paths in the
marker namespaces ``NAME/programmed_path`` and ``NAME/tcp_path``; the metadata names the
robots.

With ``--drives`` the joints and the TCP are the actual (simulated) motion, as in the trace
(per drive step with ``--trace-every-step``); the programmed path is the commanded one.

The writer is ``mcap`` + ``mcap-ros2-support`` (the optional extra ``irlc[mcap]``). Every
time it writes is given (it would take the wall clock for a message without one), and the
file is built in memory and renamed into place (:func:`irlc.files.atomic_write_bytes`):
the same run gives the same bytes.
"""

from __future__ import annotations

import io
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from irlc import __version__, ros2_messages
from irlc.export import sample_derivatives
from irlc.files import atomic_write_bytes
from irlc.lang.errors import IrlcError
from irlc.runtime.model import spatial

WORLD, BASE, TCP = "world", "base", "tcp"
EXTRA_HINT = "pip install 'irlc[mcap]'"
PATH_WIDTH_M = 0.004  # line width of the path markers
POINT_SIZE_M = 0.02  # a point obstacle is drawn as a sphere of this diameter
OBSTACLE_COLOR = (0.9, 0.3, 0.2, 0.6)
PROGRAMMED_COLOR = (0.2, 0.8, 0.3, 1.0)
TCP_COLOR = (0.2, 0.5, 1.0, 1.0)

_TYPES = {
    "joint_state": "sensor_msgs/msg/JointState",
    "tf": "tf2_msgs/msg/TFMessage",
    "markers": "visualization_msgs/msg/MarkerArray",
    "bool": "std_msgs/msg/Bool",
}


class MissingWriter(IrlcError, ImportError):
    """The MCAP writer is not installed (the message says which extra adds it)."""


def require_writer() -> None:
    """Raise :class:`MissingWriter` unless ``mcap`` and ``mcap-ros2-support`` import."""
    try:
        import mcap  # noqa: F401
        import mcap_ros2.writer  # noqa: F401
    except ImportError:
        raise MissingWriter(
            f"the MCAP export needs mcap and mcap-ros2-support: {EXTRA_HINT}"
        ) from None


@dataclass(frozen=True)
class Message:
    """One message to write: its time (ns), topic, type key and body (a dict)."""

    time_ns: int
    topic: str
    kind: str
    body: dict


def write_mcap(run: Any, path: str | Path) -> Path:
    """Write ``run`` (a :class:`~irlc.runtime.run.RunResult`) as MCAP to ``path``,
    atomically; returns the path."""
    return atomic_write_bytes(Path(path), mcap_bytes(run))


def mcap_bytes(run: Any) -> bytes:
    """The MCAP file of ``run`` (deterministic: see the module doc)."""
    require_writer()
    from mcap_ros2.writer import Writer

    buffer = io.BytesIO()
    writer = Writer(buffer)
    schemas = {
        kind: writer.register_msgdef(name, ros2_messages.definition(name))
        for kind, name in _TYPES.items()
    }
    writer.add_metadata("irlc", _metadata(run))
    sequence: dict[str, int] = {}
    for m in sorted(messages(run), key=lambda m: m.time_ns):  # stable: topic order kept
        sequence[m.topic] = sequence.get(m.topic, -1) + 1
        writer.write_message(
            m.topic, schemas[m.kind], m.body, log_time=m.time_ns, publish_time=m.time_ns,
            sequence=sequence[m.topic],
        )  # fmt: skip
    writer.finish()
    return buffer.getvalue()


def _metadata(run: Any) -> dict[str, str]:
    report = run.report
    drives = str(report.get("drives", "ideal"))
    return {
        "program": str(report.get("program", "")),
        "robot": str(report.get("robot", "")),
        "status": str(report.get("status", "")),
        "drives": drives,
        "motion": "commanded" if drives == "ideal" else "actual",
        **({"robots": ", ".join(run.robots)} if getattr(run, "is_cell", False) else {}),
        "time": "simulated, s from the start of the run",
        "writer": f"irlc {__version__}",
    }


@dataclass(frozen=True)
class Robot:
    """One robot's part of the file: its frame and topic ``prefix`` (``""`` for a program of
    one robot, ``NAME/`` in a cell), joint names (the robot file's), samples (SI) and base."""

    prefix: str
    names: list[str]
    q: np.ndarray  # (k, n) rad | m
    tcp: np.ndarray  # (k, 4, 4) world, m
    base: np.ndarray  # 4×4: world → base (a cell's robot: its placement · the file's base)
    recorded: Any  # RecordedRun (the programmed path), or None


def robots_of(run: Any) -> list[Robot]:
    """The robots of ``run``: one for a program of one robot, a cell's in the ``ROBOT``
    clauses' order (their frames and topics under ``NAME/``)."""
    if not getattr(run, "is_cell", False):
        names = [str(n) for n in run.report.get("robot_joint_names") or run.model.joint_names]
        q, tcp = np.asarray(run.q, dtype=float), np.asarray(run.tcp, dtype=float)
        return [Robot("", names, q, tcp, np.asarray(run.model.base, dtype=float), run.recorded)]
    out = []
    for name, r in run.robots.items():
        names = [str(n) for n in r.report.get("robot_joint_names") or r.model.joint_names]
        q, tcp = np.asarray(r.q, dtype=float), np.asarray(r.tcp, dtype=float)
        out.append(Robot(f"{name}/", names, q, tcp, np.asarray(r.model.base, float), r.recorded))
    return out


def messages(run: Any) -> Iterator[Message]:
    """Every message of the file, per topic in time order (see the module doc)."""
    times = np.asarray(run.times, dtype=float)
    start = nanoseconds(float(times[0])) if len(times) else 0
    robots = robots_of(run)
    yield Message(start, "/tf_static", "tf", {"transforms": _static_frames(run, robots, start)})
    yield Message(start, "/markers", "markers", {"markers": _markers(run, robots, start)})
    yield from _switches(run.report.get("events") or [], start)
    speeds = [sample_derivatives(r.q, times)[0] for r in robots]
    inverse = [spatial.inverse(r.base) for r in robots]
    for i, t in enumerate(times):
        ns = nanoseconds(float(t))
        transforms = []
        for r, qd, base_inverse in zip(robots, speeds, inverse, strict=True):
            yield Message(ns, f"/{r.prefix}joint_states", "joint_state", {
                "header": _header(ns, ""),
                "name": r.names,
                "position": [float(v) for v in r.q[i]],
                "velocity": [float(v) for v in qd[i]],
                "effort": [],
            })  # fmt: skip
            tcp = base_inverse @ r.tcp[i]
            transforms.append(_transform(ns, r.prefix + BASE, r.prefix + TCP, tcp))
        yield Message(ns, "/tf", "tf", {"transforms": transforms})


def nanoseconds(t: float) -> int:
    """Simulated seconds → integer nanoseconds."""
    return round(t * 1e9)


def _stamp(ns: int) -> dict:
    return {"sec": ns // 1_000_000_000, "nanosec": ns % 1_000_000_000}


def _header(ns: int, frame: str) -> dict:
    return {"stamp": _stamp(ns), "frame_id": frame}


def _pose_fields(t: np.ndarray) -> tuple[dict, dict]:
    """A 4×4 transform as ROS ``(x, y, z)`` and quaternion ``(x, y, z, w)`` dicts."""
    w, x, y, z = spatial.matrix_to_quat(t[:3, :3])
    p = t[:3, 3]
    vector = {"x": float(p[0]), "y": float(p[1]), "z": float(p[2])}
    return vector, {"x": float(x), "y": float(y), "z": float(z), "w": float(w)}


def _transform(ns: int, parent: str, child: str, t: np.ndarray) -> dict:
    translation, rotation = _pose_fields(t)
    return {
        "header": _header(ns, parent),
        "child_frame_id": child,
        "transform": {"translation": translation, "rotation": rotation},
    }


def _static_frames(run: Any, robots: list[Robot], ns: int) -> list[dict]:
    frames = [_transform(ns, WORLD, r.prefix + BASE, r.base) for r in robots]
    for o in run.obstacles:
        frames.append(_transform(ns, WORLD, f"obstacle/{o.name}", obstacle_frame(o)))
    return frames


def _z_towards(direction: np.ndarray) -> np.ndarray:
    """A rotation whose z axis points along ``direction`` (any length > 0)."""
    z = direction / np.linalg.norm(direction)
    helper = np.array([1.0, 0.0, 0.0]) if abs(z[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    x = np.cross(helper, z)
    x /= np.linalg.norm(x)
    return np.column_stack([x, np.cross(z, x), z])


def obstacle_frame(o: Any) -> np.ndarray:
    """The frame of an obstacle (world, m): at its centre (a point's position, a capsule's
    midpoint, a plane's point), with z along a capsule's axis or a plane's normal and a
    box's own rotation."""
    if o.kind == "point":
        return spatial.transform(None, o.position)
    if o.kind == "sphere":
        return spatial.transform(None, o.center)
    if o.kind == "box":
        return spatial.transform(np.asarray(o.rotation, dtype=float), o.center)
    if o.kind == "capsule":
        a, b = np.asarray(o.a, dtype=float), np.asarray(o.b, dtype=float)
        axis = b - a if np.linalg.norm(b - a) > 0.0 else np.array([0.0, 0.0, 1.0])
        return spatial.transform(_z_towards(axis), 0.5 * (a + b))
    return spatial.transform(_z_towards(np.asarray(o.normal, dtype=float)), o.point)


def _marker(ns: int, space: str, ident: int, shape: int, pose: np.ndarray, scale, color) -> dict:
    position, orientation = _pose_fields(pose)
    r, g, b, a = color
    return {
        "header": _header(ns, WORLD),
        "ns": space,
        "id": ident,
        "type": shape,
        "action": ros2_messages.ADD,
        "pose": {"position": position, "orientation": orientation},
        "scale": {"x": float(scale[0]), "y": float(scale[1]), "z": float(scale[2])},
        "color": {"r": r, "g": g, "b": b, "a": a},
        "frame_locked": False,
    }


def _line(ns: int, space: str, ident: int, points: np.ndarray, color) -> dict:
    m = _marker(ns, space, ident, ros2_messages.LINE_STRIP, np.eye(4), (PATH_WIDTH_M, 0, 0), color)
    m["points"] = [{"x": float(p[0]), "y": float(p[1]), "z": float(p[2])} for p in points]
    return m


def _obstacle_markers(ns: int, o: Any, first_id: int, extent: float) -> list[dict]:
    frame = obstacle_frame(o)
    color = OBSTACLE_COLOR
    m = ros2_messages
    if o.kind == "point":
        return [_marker(ns, "obstacles", first_id, m.SPHERE, frame, (POINT_SIZE_M,) * 3, color)]
    if o.kind == "sphere":
        return [_marker(ns, "obstacles", first_id, m.SPHERE, frame, (2 * o.radius,) * 3, color)]
    if o.kind == "box":
        return [_marker(ns, "obstacles", first_id, m.CUBE, frame, tuple(o.size), color)]
    if o.kind == "capsule":
        length = float(np.linalg.norm(np.asarray(o.b) - np.asarray(o.a)))
        d = 2 * o.radius
        out = [_marker(ns, "obstacles", first_id, m.CYLINDER, frame, (d, d, length), color)]
        for k, end in enumerate((o.a, o.b)):  # the round ends
            cap = spatial.transform(None, end)
            out.append(_marker(ns, "obstacles", first_id + 1 + k, m.SPHERE, cap, (d,) * 3, color))
        return out
    # a plane: a thin square around its point, large enough for the scene
    return [_marker(ns, "obstacles", first_id, m.CUBE, frame, (extent, extent, 0.001), color)]


def _markers(run: Any, robots: list[Robot], ns: int) -> list[dict]:
    tcp = np.concatenate([r.tcp[:, :3, 3] for r in robots]) if len(run.times) else np.zeros((0, 3))
    out: list[dict] = []
    for o in run.obstacles:
        center = obstacle_frame(o)[:3, 3]
        reach = float(np.max(np.linalg.norm(tcp - center, axis=1))) if len(tcp) else 1.0
        out += _obstacle_markers(ns, o, len(out), 2.0 * reach + 1.0)
    for r in robots:
        for k, stretch in enumerate(programmed_path(r.recorded)):
            out.append(_line(ns, f"{r.prefix}programmed_path", k, stretch, PROGRAMMED_COLOR))
        if len(r.tcp) >= 2:
            out.append(_line(ns, f"{r.prefix}tcp_path", 0, r.tcp[:, :3, 3], TCP_COLOR))
    return out


def programmed_path(rec: Any) -> list[np.ndarray]:
    """The programmed TCP path (world, m) of a robot's Cartesian motions (LIN, CIRCLE, LIN
    PATH): the desired positions ``x_d(t)`` its recorder kept (``rec``, a
    :class:`~irlc.runtime.outputs.recorder.RecordedRun`), one array per stretch of
    consecutive Cartesian samples (a PTP or a WAIT between them ends a stretch)."""
    if rec is None or rec.desired is None or rec.on_path is None:
        return []
    on = np.asarray(rec.on_path, dtype=bool)
    points = np.asarray(rec.desired, dtype=float)[:, :3, 3]
    edges = np.flatnonzero(np.diff(np.r_[0, on.astype(int), 0]))
    return [points[a:b] for a, b in zip(edges[::2], edges[1::2], strict=True) if b - a >= 2]


def _switches(events: list[dict], start: int) -> Iterator[Message]:
    """The outputs' and SIGNALs' Bool messages: FALSE at the start, then each switch."""
    timelines: dict[str, list[tuple[int, bool]]] = {}
    for e in events:
        if e.get("kind") == "output":
            topic = f"/outputs/out_{int(e['output'])}"
        elif e.get("kind") == "signal":
            topic = f"/signals/{e['name']}"
        else:
            continue
        timelines.setdefault(topic, []).append((nanoseconds(float(e["time_s"])), bool(e["value"])))
    for topic in sorted(timelines, key=_topic_order):
        switches = timelines[topic]
        if switches[0][0] > start:
            yield Message(start, topic, "bool", {"data": False})
        for ns, value in switches:
            yield Message(ns, topic, "bool", {"data": value})


def _topic_order(topic: str) -> tuple[str, int, str]:
    """Outputs by number (``out_2`` before ``out_10``), signals by name."""
    stem, _, last = topic.rpartition("_")
    return (stem, int(last), "") if last.isdigit() else (topic, 0, "")
