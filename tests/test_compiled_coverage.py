"""Every kernel of the compiled engine (runtime/ik/compiled/, runtime/drives/compiled/) has
an equivalence test against its numpy reference: each public ``@njit`` function is called
by name in a ``test_compiled_*.py`` file (random inputs, tight tolerances), except the
three entry kernels, which their drivers run against the whole numpy path (IK cycles,
drive runs). A module-private helper (``_name``) is tested through the kernel that calls
it. Read from the sources: no numba needed."""

from __future__ import annotations

import ast
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = (ROOT / "runtime" / "ik" / "compiled", ROOT / "runtime" / "drives" / "compiled")
TESTS = sorted((ROOT / "tests" / "ik").glob("test_compiled_*.py")) + sorted(
    (ROOT / "tests" / "drives").glob("test_compiled_*.py")
)
ENTRY_KERNELS = {  # tested through their driver, against the numpy path as a whole
    "newton_cycle": ("tests/ik/test_compiled_cycle.py", "InverseTransformation"),
    "run_segment": ("tests/drives/test_compiled_loop.py", "simulate_drives"),
    "run_pwm_segment": ("tests/drives/test_compiled_pwm.py", "simulate_drives"),
}


def kernels() -> dict[str, str]:
    """Public ``@njit`` functions of the compiled packages → their file."""
    out = {}
    for package in PACKAGES:
        for path in sorted(package.glob("*.py")):
            for node in ast.parse(path.read_text(encoding="utf-8")).body:
                if isinstance(node, ast.FunctionDef) and not node.name.startswith("_"):
                    decorators = [ast.unparse(d) for d in node.decorator_list]
                    if any(d.startswith("njit") for d in decorators):
                        out[node.name] = str(path.relative_to(ROOT))
    return out


def called(name: str, text: str) -> bool:
    """``name(`` or ``module.name(`` in ``text``, not numpy's (``np.clip(``)."""
    return re.search(rf"(?<![\w.]){name}\(|(?<!\bnp)\.{name}\(", text) is not None


def test_every_kernel_has_an_equivalence_test():
    found = kernels()
    assert {"newton_cycle", "forward_chain", "run_segment", "karnopp"} <= found.keys()
    text = "\n".join(p.read_text(encoding="utf-8") for p in TESTS)
    untested = [f"{found[n]}: {n}" for n in found if n not in ENTRY_KERNELS and not called(n, text)]
    assert untested == []
    for name, (test, driver) in ENTRY_KERNELS.items():
        assert name in found, name
        body = (ROOT / test).read_text(encoding="utf-8")
        assert driver in body and "accel=True" in body, (name, test)


def test_the_check_sees_numpys_functions_as_no_test():
    assert called("clip", "k.clip(x, 0, 1)") and called("clip", "clip(x, 0, 1)")
    assert not called("clip", "np.clip(x, 0, 1)") and not called("clip", "clipped(x)")
