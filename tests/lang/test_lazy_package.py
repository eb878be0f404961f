"""``irlc.lang`` loads its public names on first use: a small module of the package does not
pull in the parser, and every name in ``__all__`` is reachable (``from irlc.lang import *``)."""

from __future__ import annotations

import subprocess
import sys

import irlc.lang


def test_every_public_name_resolves_to_its_home_module() -> None:
    for name in irlc.lang.__all__:
        value = getattr(irlc.lang, name)
        assert value.__module__.startswith("irlc.lang."), name
    assert sorted(irlc.lang.__all__) == sorted(irlc.lang._HOME_OF)


def test_an_unknown_name_is_an_attribute_error() -> None:
    try:
        irlc.lang.no_such_name  # noqa: B018
    except AttributeError as exc:
        assert "no_such_name" in str(exc)
    else:
        raise AssertionError("irlc.lang.no_such_name resolved")


def test_units_and_joint_kinds_do_not_load_the_parser() -> None:
    code = (
        "import sys, irlc.runtime.units, irlc.lang.joint_kinds;"
        "print(sorted(m for m in ('lark', 'irlc.lang.compiler', 'irlc.lang.parser')"
        " if m in sys.modules))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]"
