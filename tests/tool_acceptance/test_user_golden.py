"""`irlc test DIR` for a user's own programs (interfaces.md § Golden tests; docs/golden.md)."""

from __future__ import annotations

import json

import pytest

from .heldout import write_heldout
from .helpers import assert_clean, irlc

pytestmark = pytest.mark.scenario

SHORT = """\
PROGRAM acc_short;
ROBOT r := planar3;
IMPORT DATALIST acc_cell;
VAR INTEGER: n;
BEGIN
  R_SPEED := 800;
  MOVE PTP start;
  MOVE LIN p_a;
  FOR n := 1 TO 2 DO
    WRITELN('step ', n);
  ENDFOR;
ENDPROGRAM
"""


@pytest.fixture(scope="module")
def golden(tmp_path_factory):
    """Walk the user's workflow once: missing → --update → pass → change → fail."""
    d = tmp_path_factory.mktemp("user_golden")
    write_heldout(d)
    (d / "acc_short.irl").write_text(SHORT)
    steps = {"missing": irlc("test", d)}
    steps["update"] = irlc("test", d, "--update")
    steps["files"] = sorted(p.name for p in d.glob("*.expected.*"))
    steps["short_json"] = json.loads((d / "acc_short.expected.json").read_text())
    steps["pass"] = irlc("test", d)
    # change the path: the short program now goes to p_b instead of p_a
    (d / "acc_short.irl").write_text(SHORT.replace("MOVE LIN p_a;", "MOVE LIN p_b;"))
    steps["path_changed"] = irlc("test", d)
    # restore the path, change only the printed output
    (d / "acc_short.irl").write_text(SHORT.replace("'step '", "'Step '"))
    steps["output_changed"] = irlc("test", d)
    return steps


def test_missing_expectations_fail_readably(golden):
    res = golden["missing"]
    assert_clean(res)
    assert res.rc == 1
    assert res.out.count("MISSING") >= 2 or res.both.count("MISSING") >= 2, res.both
    assert "--update" in res.both, "tell the user how to create the expectations"


def test_update_writes_expectations(golden):
    assert golden["update"].rc == 0, golden["update"].both
    assert golden["files"] == [
        "acc_short.expected.json",
        "acc_short.expected.txt",
        "acc_tri.expected.json",
        "acc_tri.expected.txt",
    ]
    short = golden["short_json"]
    assert short["status"] == "ok" and short["output"] == ["step 1", "step 2"]
    assert set(short["joints"]) == {"a1", "a2", "a3"}


def test_then_passes(golden):
    res = golden["pass"]
    assert res.rc == 0, res.both
    assert res.both.count("PASS") >= 2


def test_changed_path_gives_a_readable_diff(golden):
    res = golden["path_changed"]
    assert_clean(res)
    assert res.rc != 0
    assert "FAIL" in res.both and "acc_short" in res.both
    assert "joints.a" in res.both, "the table names the changed joint keys"
    assert "acc_tri" in res.both and "PASS" in res.both, "the untouched program still passes"


def test_changed_output_shows_a_text_diff(golden):
    res = golden["output_changed"]
    assert res.rc != 0
    assert "-step 1" in res.both and "+Step 1" in res.both, res.both
