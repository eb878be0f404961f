"""Every exception class irlc defines derives from :class:`irlc.lang.errors.IrlcError`.

The test imports every module of the four packages (front door, lang, runtime, robots)
and checks each exception class defined there (warnings excepted: they are not errors)."""

from __future__ import annotations

import importlib
import inspect
import pkgutil

import pytest
from irlc.lang.errors import IrlcError

PACKAGES = ("irlc", "irlc.lang", "irlc.runtime", "irlc.robots")


def _module_names() -> list[str]:
    names = set()
    for pkg_name in PACKAGES:
        pkg = importlib.import_module(pkg_name)
        names.add(pkg_name)
        for info in pkgutil.walk_packages(pkg.__path__, prefix=pkg_name + "."):
            if not info.name.endswith("__main__"):
                names.add(info.name)
    return sorted(names)


def _exception_classes() -> list[type]:
    found = []
    for name in _module_names():
        try:
            module = importlib.import_module(name)
        except ModuleNotFoundError as exc:  # an optional third-party extra, not irlc
            if (exc.name or "").startswith("irlc"):
                raise
            continue
        for _, obj in inspect.getmembers(module, inspect.isclass):
            if (
                obj.__module__ == name
                and issubclass(obj, BaseException)
                and not issubclass(obj, Warning)
            ):
                found.append(obj)
    return found


def test_the_walk_finds_the_known_errors():
    names = {cls.__name__ for cls in _exception_classes()}
    assert {"CompileError", "RunFailure", "RobotFileError", "UsageError"} <= names


@pytest.mark.parametrize("cls", _exception_classes(), ids=lambda c: f"{c.__module__}.{c.__name__}")
def test_every_exception_derives_from_irlc_error(cls):
    assert issubclass(cls, IrlcError), f"{cls.__module__}.{cls.__name__} is no IrlcError"
