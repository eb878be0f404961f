"""The obstacle record's fields and the physical range of geometry (mm).

One table (:data:`OBSTACLE_KEYS`) names each obstacle kind's fields; one rule
(:func:`geometry_problem`) bounds coordinates and lengths for obstacles (data lists, ``.ird``
files, the runtime) and robot geometry (robot files, URDF).
"""

from __future__ import annotations

# The OBSTACLE record's keys per kind, in record order: (key, number count, required).
# The data-list loader and the runtime both validate against this one table.
OBSTACLE_KEYS: dict[str, tuple[tuple[str, int, bool], ...]] = {
    "point": (("center", 3, True),),
    "sphere": (("center", 3, True), ("radius", 1, True)),
    "box": (("center", 3, True), ("size", 3, True), ("rotation", 3, False)),
    "capsule": (("a", 3, True), ("b", 3, True), ("radius", 1, True)),
    "plane": (("point", 3, True), ("normal", 3, True)),
}
OBSTACLE_KINDS = tuple(OBSTACLE_KEYS)
# The physical range of obstacle geometry (mm): coordinates within ±1 km of the world origin,
# lengths (radius, box size) from 1 µm to 1 km. Far outside it a distance (a clearance in the
# trace) or a squared length overflows a float.
GEOMETRY_MAX_MM = 1e6
GEOMETRY_MIN_LENGTH_MM = 1e-3
_OBSTACLE_LENGTHS = ("radius", "size")
_OBSTACLE_POINTS = ("center", "a", "b", "point")


def geometry_problem(what: str, values, unit: str = "mm", unit_mm: float = 1.0) -> str | None:
    """Why one of ``values`` (finite numbers in ``unit``, one ``unit`` being ``unit_mm`` mm)
    is outside the physical range of geometry, else ``None``: ``what = "point"`` is a
    coordinate, within ``±GEOMETRY_MAX_MM``; ``what = "length"`` (a radius, a size, a link
    length) lies in ``[GEOMETRY_MIN_LENGTH_MM, GEOMETRY_MAX_MM]``. The one rule for
    obstacles (data lists, the runtime) and robot geometry (robot files, URDF)."""
    top, low = GEOMETRY_MAX_MM / unit_mm, GEOMETRY_MIN_LENGTH_MM / unit_mm
    for v in values:
        if what == "length" and not low <= v <= top:
            return (
                f"{v:g} {unit} is outside the physical range of a length "
                f"({low:g} to {top:g} {unit})"
            )
        if what == "point" and not abs(v) <= top:
            return (
                f"{v:g} {unit} is outside the physical range of a coordinate "
                f"(within ±{top:g} {unit})"
            )
    return None


def obstacle_range_problem(key: str, nums: tuple[float, ...]) -> str | None:
    """Why an obstacle field's numbers (mm; finite, positive where required) are outside
    the physical range (:func:`geometry_problem`), or ``None``."""
    if key in _OBSTACLE_LENGTHS:
        return geometry_problem("length", nums)
    if key in _OBSTACLE_POINTS:
        return geometry_problem("point", nums)
    return None


def obstacle_field_problem(key: str, nums: tuple[float, ...]) -> str | None:
    """Why an obstacle field's finite numbers (mm) are not valid, or ``None``: box sizes
    must be positive, a plane normal must not be zero, and every field lies in the physical
    range (:func:`obstacle_range_problem`). The one rule for the data-list loader and the
    runtime, so a hand-written ``.ird`` cannot pass what a data list would reject (each
    reader checks that a radius is a positive number while reading it)."""
    if key == "size" and min(nums) <= 0:
        return "box sizes must be positive"
    if key == "normal" and not any(nums):
        return "the plane normal must not be zero"
    return obstacle_range_problem(key, nums)
