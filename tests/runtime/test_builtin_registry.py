"""The checker's built-in functions (lang/builtins.py) and the runtime's implementations
(runtime/interpreter/builtins.py; FK in the interpreter, it needs the controller) are the same set:
a function the compiler accepts always runs, and none runs that the compiler rejects."""

from __future__ import annotations

from irlc.lang.builtins import BUILTINS
from irlc.runtime.interpreter import builtins as B


def test_checker_and_runtime_know_the_same_builtins():
    checked = set(BUILTINS) | {"POSE"}  # POSE(...) is special-cased by the checker
    assert checked == set(B.BUILTIN_NAMES)  # the runtime's registry (FK included)
