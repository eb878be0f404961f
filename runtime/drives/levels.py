"""The simulation levels of the joint drives (``--drives``; docs/drives.md), the one list.

- ``ideal``: actual = set point (torques by RNEA when the robot has inertial data);
- ``decoupled``: each motor its cascade against a constant inertia and ``G(q)``;
- ``coupled``: the cascades against the full ``M(q)``, ``C(q, q̇)q̇``, ``G(q)``;
- ``pwm``: as ``coupled`` with the switching (PWM) power stage.

Kept free of heavy imports so that the command line can offer the choice cheaply.
"""

LEVELS: tuple[str, ...] = ("ideal", "decoupled", "coupled", "pwm")
