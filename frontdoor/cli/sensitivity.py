"""``irlc robot NAME --sensitivity``: the table of :mod:`irlc.runtime.model.sensitivity`.

One row per kinematic parameter: its value (mm | deg), ``|S_k p_k|`` — the end-point
displacement (mm) and, for parameters that turn the chain, the end-orientation change
(deg) a 100 % error of the parameter would cause to first order — at the home
configuration and the largest over the sampled configurations.
"""

from __future__ import annotations

import math

from irlc.cli.console import Console
from irlc.robots.model import RobotModel
from irlc.runtime.model.sensitivity import sensitivities
from rich import box
from rich.markup import escape
from rich.table import Table


def _value(kind: str, value: float) -> str:
    return f"{value * 1e3:.4g} mm" if kind == "length" else f"{math.degrees(value):.4g}°"


def print_sensitivity(console: Console, model: RobotModel, samples: int) -> None:
    rows = sensitivities(model, samples=samples)
    table = Table(
        title=f"|S_k p_k| of the kinematic parameters (home, and max over {samples} "
        "configurations inside the limits)",
        box=box.SIMPLE_HEAD,
        pad_edge=False,
    )
    for col in ("parameter", "value", "mm (home)", "mm (max)", "deg (home)", "deg (max)"):
        table.add_column(col, justify="left" if col == "parameter" else "right", no_wrap=True)
    for s in rows:
        p = s.parameter
        table.add_row(
            escape(p.name),
            _value(p.kind, p.value),
            f"{s.position_m * 1e3:.4g}",
            f"{s.position_max_m * 1e3:.4g}",
            f"{math.degrees(s.orientation_rad):.4g}",
            f"{math.degrees(s.orientation_max_rad):.4g}",
        )
    console.print(table)
    console.print(
        "  |S_k p_k|: the first-order change of the TCP pose (tool included) if the parameter "
        "were wrong by 100 % of its value (docs/fidelity.md)"
    )
