"""Shared pytest options. ``--update-golden`` rewrites the golden expectations of programs/."""

from __future__ import annotations

import pytest


def pytest_addoption(parser):
    parser.addoption(
        "--update-golden",
        action="store_true",
        default=False,
        help="rewrite programs/NAME.expected.json (and .txt) from the current runs",
    )


@pytest.fixture(autouse=True, scope="session")
def _one_terminal_width():
    """One terminal width for every test, whatever the caller's terminal: rich wraps
    diagnostics at ``COLUMNS``, and a pytest-xdist worker's tmp paths are longer. (A
    fixture, not ``pytest_configure``: pytest's own report keeps the real width.)"""
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("COLUMNS", "300")
        yield
