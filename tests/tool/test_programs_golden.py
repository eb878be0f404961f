"""Every program in programs/ against its golden expectation (``docs/golden.md``).

``pytest --update-golden`` rewrites the expectations instead of checking them.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from irlc.golden import find_programs, run_case

PROGRAMS = Path(__file__).resolve().parents[2] / "programs"


def _runtime_available() -> bool:
    try:
        from irlc.runtime.run import run_file  # noqa: F401
    except ImportError:
        return False
    return True


_CASES = find_programs(PROGRAMS)


@pytest.mark.scenario
@pytest.mark.skipif(not _runtime_available(), reason="the runtime (irlc.runtime.run) is missing")
@pytest.mark.parametrize("program", _CASES, ids=lambda p: p.stem)
def test_program_matches_golden(program, request):
    update = request.config.getoption("--update-golden")
    result = run_case(program, update=update)
    details = "\n".join(f"{m.path}: expected {m.expected!r}, got {m.actual!r} {m.note}"
                        for m in result.mismatches)  # fmt: skip
    details += "\n".join(result.output_diff)
    assert result.ok, f"{program.name}: {result.status} {result.message}\n{details}"


KOCH11_V1 = Path(__file__).resolve().parents[1] / "runtime" / "koch11_v1_programs"


@pytest.mark.scenario
@pytest.mark.skipif(not _runtime_available(), reason="the runtime (irlc.runtime.run) is missing")
@pytest.mark.parametrize("program", find_programs(KOCH11_V1), ids=lambda p: p.stem)
def test_koch11_v1_reproduces_the_first_reconstructions_results(program):
    """The chapter-6 programs and cells as they were before koch11 was revised (issue 16),
    run with ``--robot koch11_v1`` (each expectation's ``options.robot``): the figures the
    goldens held for the first reconstruction, unchanged. Never ``--update-golden`` these."""
    result = run_case(program, update=False)
    details = "\n".join(f"{m.path}: expected {m.expected!r}, got {m.actual!r} {m.note}"
                        for m in result.mismatches)  # fmt: skip
    assert result.ok, f"{program.name}: {result.status} {result.message}\n{details}"
