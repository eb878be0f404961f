"""How hard the hypothesis fuzz tests try (issue 11).

In CI each fuzz target runs ``IRLC_FUZZ_EXAMPLES`` examples (default: a few seconds per
target). The long fuzz run (documented in docs/interfaces.md, not in CI)::

    IRLC_FUZZ_EXAMPLES=100000 pytest tests -k fuzz -p no:cacheprovider

runs 100,000 cases per target; every example must finish within ``IRLC_FUZZ_DEADLINE_MS``
(default: none in CI, 5,000 ms in the long run): a slower one is a hang.
"""

from __future__ import annotations

import os

from hypothesis import HealthCheck, settings


def fuzz_settings(ci_examples: int) -> settings:
    """``ci_examples`` in CI, ``IRLC_FUZZ_EXAMPLES`` when set (the long run)."""
    long_run = os.environ.get("IRLC_FUZZ_EXAMPLES")
    examples = int(long_run) if long_run else ci_examples
    deadline = os.environ.get("IRLC_FUZZ_DEADLINE_MS", "5000" if long_run else "")
    return settings(
        max_examples=examples,
        deadline=int(deadline) if deadline else None,
        suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
        database=None,
    )
