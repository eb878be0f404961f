"""Task parts: extra equality rows of a chain's task (seed 001, ch. 3.2 and 4.2).

The seed writes a redundant chain's task as ``f(θ) = x`` plus conditions ``Φ(θ) = 0``
that the chain's category or the job adds — a mobile robot's platform following its own
path, a cooperating robot's tool kept vertical — and integrates both into one system
``F(θ) = [f(θ) − x; Φ(θ)] = 0`` solved by the same Newton–Raphson iteration (its
4.2(a)): ``J = [J_f; ∂Φ/∂θ]``. Each condition is a small class here (the protocol is
:class:`~irlc.runtime.model.chain.EqualityTask`: ``size`` rows of one ``kind``, their
``residual`` and ``jacobian`` at a :class:`~irlc.runtime.model.chain.ChainPoint`), with
its math in its docstring; a chain carries them (``Chain.tasks``) and
:class:`~irlc.runtime.ik.newton.InverseTransformation` stacks them under the pose rows.

* :class:`~irlc.runtime.ik.tasks.platform.PlatformTask` — ``Φ = f_platform(θ_a) −
  x_platform(s)``: a frame of the chain (a mobile robot's platform) follows its own path;
* :class:`~irlc.runtime.ik.tasks.axis.AxisTask` — a body axis (the tool's z axis) held
  along a world direction (vertical): two orientation rows.

A new condition (a relation ``k(x_I, x_II) = K(t)`` between two tools, a heading of a
wheeled platform) is a new module here with the same two methods.
"""

from irlc.runtime.ik.tasks.axis import AxisTask
from irlc.runtime.ik.tasks.platform import PlatformTask

__all__ = ["AxisTask", "PlatformTask"]
