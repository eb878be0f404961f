"""Geometry and inertia of a robot file: ``[[geometry]]`` (collision capsules and spheres
per link) and ``[[inertials]]`` (mass, centre of mass, inertia per link — given, or of a
uniform solid filling the link's collision shapes).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from irlc.robots.model import Capsule, Inertial, Sphere
from irlc.robots.toml_reader import Reader, show


def read_geometry(rd: Reader, value: Any, n: int, assumed: dict) -> list[Capsule | Sphere]:
    rows = rd.array_of_tables(value, "geometry")
    out: list[Capsule | Sphere] = []
    for i, row in enumerate(rows):
        key = f"geometry[{i + 1}]"
        rd.table(row, key, {"link", "shape", "a", "b", "center", "radius", "assumed", "reason"})
        if rd.assumption(row, key)[0]:
            assumed[key] = row["reason"]
        link = link_index(rd, row.get("link"), f"{key}.link", n)
        shape = rd.string(row.get("shape"), f"{key}.shape", ("capsule", "sphere"))
        radius = rd.positive(row.get("radius"), f"{key}.radius") * rd.length
        rd.in_range(f"{key}.radius", "length", radius)
        if shape == "capsule":
            for k in ("a", "b"):
                if k not in row:
                    raise rd.fail(f"{key}.{k}", "missing; expected 3 numbers (segment end)")
            a = rd.vector(row["a"], f"{key}.a", 3) * rd.length
            b = rd.vector(row["b"], f"{key}.b", 3) * rd.length
            rd.in_range(f"{key}.a", "point", a)
            rd.in_range(f"{key}.b", "point", b)
            out.append(Capsule(link, a, b, radius))
        else:
            if "center" not in row:
                raise rd.fail(f"{key}.center", "missing; expected 3 numbers")
            c = rd.vector(row["center"], f"{key}.center", 3) * rd.length
            rd.in_range(f"{key}.center", "point", c)
            out.append(Sphere(link, c, radius))
    return out


def link_index(rd: Reader, value: Any, key: str, n: int) -> int:
    if not isinstance(value, int) or isinstance(value, bool) or not 0 <= value <= n:
        raise rd.fail(key, f"expected a link number 0..{n} (0 = base), got {show(value)}")
    return value


MASS_RANGE_KG = (1e-9, 1e9)  # a link's mass: a microgram grain to a million tonnes
INERTIA_MAX_KG_M2 = 1e15  # |entry| of an inertia: that mass spread over ±1 km (geometry)


def inertial_problem(mass: float | None, inertia=None) -> str | None:
    """Why a link's mass (kg) or inertia entries (kg·m²) are outside the physical range,
    else ``None`` (``None`` arguments are not checked). Beyond it the combined inertia of
    a link (m·d², ρ·V) overflows to inf and NaN."""
    low, high = MASS_RANGE_KG
    if mass is not None and not low <= mass <= high:
        return f"a mass of {mass:g} kg is outside the physical range ({low:g} to {high:g} kg)"
    top = INERTIA_MAX_KG_M2
    if inertia is not None and not np.all(np.abs(np.asarray(inertia, dtype=float)) <= top):
        return f"an inertia entry is outside the physical range (within ±{top:g} kg·m²)"
    return None


def read_inertials(rd: Reader, value: Any, n: int, geometry, assumed: dict) -> list[Inertial]:
    """``[[inertials]]``: ``link``, ``mass`` (kg), ``com`` (length unit) and ``inertia``
    ``[ixx, iyy, izz, ixy, ixz, iyz]`` (kg·m², about the com) — or
    ``inertia = "from_geometry"``: a uniform solid filling the link's collision shapes."""
    rows = rd.array_of_tables(value, "inertials")
    default_reason = assumed.get("inertials", "")
    out = []
    seen: set[int] = set()
    for i, row in enumerate(rows):
        key = f"inertials[{i + 1}]"
        rd.table(row, key, {"link", "mass", "com", "inertia", "assumed", "reason"})
        flag, _ = rd.assumption(row, key)
        flag = flag or (bool(default_reason) and "assumed" not in row)
        link = link_index(rd, row.get("link"), f"{key}.link", n)
        if link in seen:
            raise rd.fail(f"{key}.link", f"link {link} already has an inertial entry")
        seen.add(link)
        mass = rd.positive(row.get("mass"), f"{key}.mass")
        if problem := inertial_problem(mass):
            raise rd.fail(f"{key}.mass", problem)
        raw = row.get("inertia")
        if raw == "from_geometry":
            shapes = [g for g in geometry if g.link == link]
            if not shapes:
                raise rd.fail(f"{key}.inertia", f"'from_geometry' but link {link} has no geometry")
            com, inertia = solid_inertia(shapes, mass)
            if "com" in row:
                raise rd.fail(f"{key}.com", "not used with inertia = 'from_geometry'")
        else:
            com = rd.vector(row.get("com"), f"{key}.com", 3) * rd.length
            rd.in_range(f"{key}.com", "point", com)
            inertia = _inertia_matrix(rd, raw, f"{key}.inertia")
        out.append(Inertial(link, mass, com, inertia, assumed=flag))
    return out


def _inertia_matrix(rd: Reader, raw: Any, key: str) -> np.ndarray:
    ixx, iyy, izz, ixy, ixz, iyz = rd.vector(raw, key, 6)
    if problem := inertial_problem(None, [ixx, iyy, izz, ixy, ixz, iyz]):
        raise rd.fail(key, problem)
    m = np.array([[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]])
    ev = np.linalg.eigvalsh(m)
    if ev[0] < -1e-12 or ev[0] + ev[1] < ev[2] - 1e-9 * max(1.0, ev[2]):
        raise rd.fail(key, "expected a physical inertia (positive, triangle inequality)")
    return m


def solid_inertia(shapes, mass: float) -> tuple[np.ndarray, np.ndarray]:
    """Centre of mass and inertia (about it) of uniform solids filling ``shapes``."""
    parts = []  # (volume, com, inertia per unit density about own com)
    for g in shapes:
        if isinstance(g, Sphere):
            v = 4.0 / 3.0 * math.pi * g.radius**3
            parts.append((v, g.center, 0.4 * v * g.radius**2 * np.eye(3)))
            continue
        r, axis = g.radius, g.b - g.a
        h = float(np.linalg.norm(axis))
        u = axis / h if h > 0 else np.array([0.0, 0.0, 1.0])
        m_cyl = math.pi * r * r * h
        m_hs = 2.0 / 3.0 * math.pi * r**3
        i_ax = m_cyl * r * r / 2.0 + 2 * m_hs * 0.4 * r * r
        i_perp = m_cyl * (r * r / 4 + h * h / 12) + 2 * m_hs * (
            0.4 * r * r + h * h / 4 + 3 * h * r / 8
        )
        inertia = i_perp * (np.eye(3) - np.outer(u, u)) + i_ax * np.outer(u, u)
        parts.append((m_cyl + 2 * m_hs, (g.a + g.b) / 2, inertia))
    volume = sum(p[0] for p in parts)
    rho = mass / volume
    com = sum(p[0] * p[1] for p in parts) / volume
    total = np.zeros((3, 3))
    for v, c, inertia in parts:
        d = c - com
        total += rho * (inertia + v * (float(d @ d) * np.eye(3) - np.outer(d, d)))
    return com, total
