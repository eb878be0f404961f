"""The runtime: IRDATA code → recorded motion, in the stages of docs/runtime.md.

* :mod:`~irlc.runtime.interpreter` runs the code and hands motion commands
  (:mod:`~irlc.runtime.commands`) to the controller;
* :mod:`~irlc.runtime.plan` turns a command into profiled segments and setpoints;
* :mod:`~irlc.runtime.control` runs them cycle by cycle through the inverse
  transformation (:mod:`~irlc.runtime.ik`) on the robot model (:mod:`~irlc.runtime.model`);
* :mod:`~irlc.runtime.drives` simulates the joint drives on the recorded set points;
* :mod:`~irlc.runtime.outputs` keeps the samples and builds the verdict, report and trace.

:mod:`~irlc.runtime.run` makes the stages one call each; :mod:`~irlc.runtime.units` is
the one place where program units meet SI.
"""

if __name__ != "irlc.runtime":  # this folder imported by its own name (from the repository root)
    raise ImportError(f"import irlc.runtime, not {__name__}: this folder is irlc.runtime")
