"""Every number of the seeds irlc can compute, laid beside the book's (docs/fidelity.md).

``python bench/fidelity.py`` prints one line per published reference — the reference, then
irlc's numbers in the book's units and order — and writes the table of docs/fidelity.md.
The modules compute the rows: :mod:`.kinematics_rows` (IRb-6 (5.1b), (5.3), (5.5), (5.6),
(5.22); L-1 (4.21), (4.22); koch11's arm table; the sensitivity tables),
:mod:`.steppers` (the L-1's stepper drives), :mod:`.dc_drives` (the IRb-6 drive chain,
the model-simplification tables), :mod:`.chapter6` (the 11-joint robot's observations and
figures); :mod:`.references` lists them with the book's numbers, :mod:`.table` formats.
:func:`without_position_limits` runs a robot as the books' drive studies did. The rows run
the programs of a source checkout (``programs/``, ``programs/fidelity/``), as the bench does.
"""

from irlc.fidelity.unlimited import without_position_limits

__all__ = ["without_position_limits"]
