"""Shared pytest options. ``--update-golden`` rewrites the golden expectations of programs/."""

from __future__ import annotations


def pytest_addoption(parser):
    parser.addoption(
        "--update-golden",
        action="store_true",
        default=False,
        help="rewrite programs/NAME.expected.json (and .txt) from the current runs",
    )
