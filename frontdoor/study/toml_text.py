"""A small TOML writer for parsed documents (``tomllib`` reads only): ``loads(dumps(d)) == d``
for the values TOML documents hold here — tables, arrays of tables, lists, strings, numbers,
booleans. Used to hand a varied data list to the compiler as the file it reads."""

from __future__ import annotations

import json
import math
import re
from typing import Any

_BARE = re.compile(r"[A-Za-z0-9_\-]+")


def _key(k: str) -> str:
    return k if _BARE.fullmatch(k) else json.dumps(k)


def _value(v: Any) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if math.isnan(v):  # TOML's own words: the document's loader refuses them
            return "nan"
        return repr(v + 0.0) if math.isfinite(v) else ("inf" if v > 0 else "-inf")
    if isinstance(v, str):
        return json.dumps(v, ensure_ascii=False)  # a JSON string is a TOML basic string
    if isinstance(v, list):
        return "[" + ", ".join(_value(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{ " + ", ".join(f"{_key(k)} = {_value(x)}" for k, x in v.items()) + " }"
    raise ValueError(f"cannot write {type(v).__name__} as TOML")


def _is_table_array(v: Any) -> bool:
    return isinstance(v, list) and bool(v) and all(isinstance(x, dict) for x in v)


def dumps(doc: dict, prefix: str = "") -> str:
    """The TOML text of ``doc`` (plain values first, then sub-tables, then table arrays)."""
    lines = [f"{_key(k)} = {_value(v)}" for k, v in doc.items() if not _nested(v)]
    out = "\n".join(lines) + ("\n" if lines else "")
    for k, v in doc.items():
        name = f"{prefix}.{_key(k)}" if prefix else _key(k)
        if isinstance(v, dict):
            out += f"\n[{name}]\n" + dumps(v, name)
        elif _is_table_array(v):
            for row in v:
                out += f"\n[[{name}]]\n" + dumps(row, name)
    return out


def _nested(v: Any) -> bool:
    return isinstance(v, dict) or _is_table_array(v)
