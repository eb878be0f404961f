"""Fixtures: a planar 3R built from the dataclasses, and the shipped koch11."""

from __future__ import annotations

import pytest
from irlc.robots.model import RobotModel

from .ik_robots import planar_arm


@pytest.fixture
def planar3() -> RobotModel:
    return planar_arm(3)


@pytest.fixture(scope="session")
def koch11() -> RobotModel:
    from irlc.robots import load_robot

    return load_robot("koch11")
