"""The one base class of every exception irlc defines.

``except IrlcError`` catches any failure the project raises on purpose — a compile error,
a run failure, a bad robot file, a usage error — and nothing else (not an ``OSError`` of a
missing file, not a bug). Each subclass keeps its other bases (``ValueError``,
``LookupError`` …) where callers catch it by them; ``tests/test_errors.py`` checks that
every exception class of the package derives from it. It lives in the front end, the one
package that lang, runtime, robots and the front door all import without a cycle (lang
imports none of the others).
"""

from __future__ import annotations


class IrlcError(Exception):
    """Base of all irlc exceptions (see the module docstring)."""
