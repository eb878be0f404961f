"""numba caches :func:`cycle.newton_cycle` keyed by its own file only, while its machine
code includes the kernels and constants of the modules it imports: the digest of those
sources recorded in runtime/ik/compiled/cycle.py must be current (else a changed kernel
would run from stale cached machine code)."""

from __future__ import annotations

import pytest

pytest.importorskip("numba")

from irlc.runtime.ik.compiled import cycle


def test_recorded_digest_matches_the_callee_sources():
    assert cycle.sources_digest() == cycle.SOURCES_DIGEST, (
        "a kernel module newton_cycle calls changed: set SOURCES_DIGEST in "
        f"runtime/ik/compiled/cycle.py to {cycle.sources_digest()!r}"
    )


def test_the_digest_sees_a_change_in_a_callee(tmp_path, monkeypatch):
    """Independent check: one changed byte in a callee's source changes the digest."""
    for name in cycle.CALLEES:
        (tmp_path / f"{name}.py").write_bytes(
            (cycle.Path(cycle.__file__).with_name(f"{name}.py")).read_bytes()
        )
    (tmp_path / "cycle.py").write_text("")
    monkeypatch.setattr(cycle, "__file__", str(tmp_path / "cycle.py"))
    before = cycle.sources_digest()
    with open(tmp_path / "qp.py", "a") as f:
        f.write("\n")
    assert cycle.sources_digest() != before


def test_inertia_kernel_digest_matches_its_callees():
    """ENERGY's kernel (runtime/ik/compiled/inertia.py) calls forward_chain and the
    drives' mass_and_bias: the digest of their modules recorded there must be current."""
    from irlc.runtime.ik.compiled import inertia

    assert inertia.callees_digest() == inertia.CALLEES_DIGEST, (
        "a module inertia_metric calls changed: set CALLEES_DIGEST in "
        f"runtime/ik/compiled/inertia.py to {inertia.callees_digest()!r}"
    )
