"""``cycle_time.code_text``: a statement line without its trailing comment, in linear time."""

from __future__ import annotations

import re
import time

from hypothesis import given
from hypothesis import strategies as st
from irlc.runtime.outputs.cycle_time import code_text

# the former definition (a regular expression, quadratic on long runs of blanks): the
# reference for short lines
_REFERENCE = re.compile(r"\s*(?:\{[^{}']*\}|\(\*(?:(?!\*\)).)*\*\)|//[^']*)\s*\Z")


def test_known_lines():
    assert code_text("  MOVE LIN p1;   { to the corner }  ") == "MOVE LIN p1;"
    assert code_text("x := 1; (* one (* two *)") == "x := 1;"
    assert code_text("WRITELN('a // b');") == "WRITELN('a // b');"  # inside a string
    assert code_text("WRITELN('x'); // done") == "WRITELN('x');"
    assert code_text("a := {b}; c;") == "a := {b}; c;"  # not at the end: code


@given(st.text(alphabet="{}()*/' a;\t", max_size=14))
def test_the_same_as_the_regular_expression(line):
    assert code_text(line) == _REFERENCE.sub("", line).strip()


def test_a_long_run_of_blanks_takes_linear_time():
    """Regression (adversarial probe): 40,000 blanks in a MOVE took 18 s in the report's
    statement table (80,000: 57 s); 400,000 now take milliseconds."""
    line = "MOVE PTP (10," + " " * 400_000 + "80, -80);" + " " * 400_000
    start = time.perf_counter()
    assert code_text(line) == line.strip()
    assert time.perf_counter() - start < 5  # (quadratic: hours; loose for a loaded machine)
