"""Fixtures of the tool tests (synthetic runs from tool_fixtures.py)."""

from __future__ import annotations

import pytest

from .tool_fixtures import make_run, small_robot


@pytest.fixture
def demo_run():
    return make_run()


@pytest.fixture
def robot4():
    return small_robot()
