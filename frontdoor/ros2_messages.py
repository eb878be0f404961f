"""The ROS 2 message definitions the MCAP export writes (:mod:`irlc.mcap_export`).

Each type's own fields, as its ``.msg`` file has them (ROS 2 Jazzy; the wire format is the
same since Humble); :func:`definition` joins a type with every type it uses, in the layout
rosbag2 and Foxglove read from an MCAP schema: the type's text, then per dependency (depth
first, each once) a line of 80 ``=``, ``MSG: pkg/Name`` and that type's text.
"""

from __future__ import annotations

import re

_FIELDS: dict[str, str] = {
    "builtin_interfaces/Time": "int32 sec\nuint32 nanosec\n",
    "builtin_interfaces/Duration": "int32 sec\nuint32 nanosec\n",
    "std_msgs/Header": "builtin_interfaces/Time stamp\nstring frame_id\n",
    "std_msgs/Bool": "bool data\n",
    "std_msgs/ColorRGBA": "float32 r\nfloat32 g\nfloat32 b\nfloat32 a\n",
    "geometry_msgs/Vector3": "float64 x\nfloat64 y\nfloat64 z\n",
    "geometry_msgs/Point": "float64 x\nfloat64 y\nfloat64 z\n",
    "geometry_msgs/Quaternion": "float64 x\nfloat64 y\nfloat64 z\nfloat64 w\n",
    "geometry_msgs/Pose": "geometry_msgs/Point position\ngeometry_msgs/Quaternion orientation\n",
    "geometry_msgs/Transform": (
        "geometry_msgs/Vector3 translation\ngeometry_msgs/Quaternion rotation\n"
    ),
    "geometry_msgs/TransformStamped": (
        "std_msgs/Header header\nstring child_frame_id\ngeometry_msgs/Transform transform\n"
    ),
    "tf2_msgs/TFMessage": "geometry_msgs/TransformStamped[] transforms\n",
    "sensor_msgs/JointState": (
        "std_msgs/Header header\nstring[] name\nfloat64[] position\nfloat64[] velocity\n"
        "float64[] effort\n"
    ),
    "sensor_msgs/CompressedImage": "std_msgs/Header header\nstring format\nuint8[] data\n",
    "visualization_msgs/UVCoordinate": "float32 u\nfloat32 v\n",
    "visualization_msgs/MeshFile": "string filename\nuint8[] data\n",
    "visualization_msgs/Marker": (
        "int32 ARROW=0\nint32 CUBE=1\nint32 SPHERE=2\nint32 CYLINDER=3\nint32 LINE_STRIP=4\n"
        "int32 LINE_LIST=5\nint32 CUBE_LIST=6\nint32 SPHERE_LIST=7\nint32 POINTS=8\n"
        "int32 TEXT_VIEW_FACING=9\nint32 MESH_RESOURCE=10\nint32 TRIANGLE_LIST=11\n"
        "int32 ARROW_STRIP=12\nint32 ADD=0\nint32 MODIFY=0\nint32 DELETE=2\nint32 DELETEALL=3\n"
        "std_msgs/Header header\nstring ns\nint32 id\nint32 type\nint32 action\n"
        "geometry_msgs/Pose pose\ngeometry_msgs/Vector3 scale\nstd_msgs/ColorRGBA color\n"
        "builtin_interfaces/Duration lifetime\nbool frame_locked\n"
        "geometry_msgs/Point[] points\nstd_msgs/ColorRGBA[] colors\n"
        "string texture_resource\nsensor_msgs/CompressedImage texture\n"
        "visualization_msgs/UVCoordinate[] uv_coordinates\nstring text\n"
        "string mesh_resource\nvisualization_msgs/MeshFile mesh_file\n"
        "bool mesh_use_embedded_materials\n"
    ),
    "visualization_msgs/MarkerArray": "visualization_msgs/Marker[] markers\n",
}

# Marker.type and Marker.action values (visualization_msgs/Marker)
CUBE, SPHERE, CYLINDER, LINE_STRIP = 1, 2, 3, 4
ADD = 0

_SEPARATOR = "=" * 80
_COMPLEX = re.compile(r"^([a-z0-9_]+/[A-Za-z0-9]+)(\[\])? ", re.MULTILINE)


def _short(name: str) -> str:
    """``sensor_msgs/msg/JointState`` → ``sensor_msgs/JointState``."""
    return name.replace("/msg/", "/")


def definition(name: str) -> str:
    """The full definition of ``name`` (``sensor_msgs/msg/JointState``) with its
    dependencies (see the module doc)."""
    root = _short(name)
    order: list[str] = []

    def visit(type_name: str) -> None:
        for dep, _ in _COMPLEX.findall(_FIELDS[type_name]):
            if dep != root and dep not in order:
                order.append(dep)
                visit(dep)

    visit(root)
    parts = [_FIELDS[root]]
    parts += [f"{_SEPARATOR}\nMSG: {dep}\n{_FIELDS[dep]}" for dep in order]
    return "".join(parts)
