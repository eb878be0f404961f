"""The compiled IK engine (numba; ``pip install 'irlc[fast]'``): one IPO cycle of
:mod:`irlc.runtime.ik.newton` — the numpy reference — fused into machine code.

Chosen by :func:`irlc.runtime.engine.compiled_cycle` (``IRLC_ENGINE``, ``IKParams.accel``);
nothing here is imported on the numpy path (numba's import alone costs ≈ 0.2 s). One
module per concept; each kernel is the same arithmetic as its numpy reference (named in
its docstring), written as loops, and is tested alone against it
(``tests/ik/test_compiled_kernels.py``, ``tests/ik/test_compiled_distance.py``):

* :mod:`.layout` — the state's slots: phase and status codes, the ``ist`` / ``fst`` state
  arrays, the rows of the vector workspace ``V``, the one-buffer layout ``lay``, the
  tolerances (plain constants, no numba);
* :mod:`.chain` — ``forward_chain``: ``Kinematics.chain`` (``L_i = A0 + cos v·A1 + sin
  v·A2 + v·A3``, ``T_i = T_{i−1}·L_i``); ``tcp_jacobian``: ``Kinematics.tcp_jacobian``
  (``[z_i × (p − o_i); z_i]`` revolute, ``[z_i; 0]`` prismatic); ``pose_error``:
  ``spatial.pose_error`` (near-π branch included); ``evaluate``: FK, task error, norms;
* :mod:`.box` — ``joint_box``: ``JointBox.prepare`` (signed candidates, braking bound
  ``2R/(1 + √(1 + 2R/ε))``); ``active_codes``: ``limits.active_codes``;
* :mod:`.qp` — ``split``: ``CompactBasis`` (``−J_m⁻¹[J_free F]`` by LU with partial
  pivoting, the pivot spread as the degradation test); ``scalar_qp`` / ``square_step`` /
  ``hard_data``: ``NewtonStep.hard_diagonal``; ``hard_data_general``: ``compact_box_qp``
  with the coupled rows (``NewtonStep.hard``); ``relaxed_data``:
  ``NewtonStep.relaxed_diagonal`` / ``relaxed`` (the QP data); ``unconstrained_qp``: the
  compact QP's answer when no constraint binds (else quadprog is called from Python);
* :mod:`.cycle` — ``newton_cycle``, the resumable state machine of one cycle, with
  ``general_cost`` (``InverseTransformation``'s cost: CYCLIC, ``a_conf·W``, obstacle
  terms) and ``reduce_frozen`` (the FREEZE reduction);
* :mod:`.distance` — the obstacle queries: ``critical_points``
  (``model.distance.critical_points``) and ``obstacle_terms`` (``ik.obstacle``);
* :mod:`.driver` — :class:`~.driver.CompiledCycle`, the Python side: the workspace, the
  resumes (quadprog, a new basis, obstacle terms, the error paths).

:func:`~.cycle.newton_cycle` runs Newton iterations until the cycle is done or it needs
Python (a quadprog call, a new basis by QR pivoting, the obstacle terms, the error path
of the joint box); the driver does that and resumes it with a phase code. numba's
on-disk cache of a function is keyed by its own source file only, so :mod:`.cycle`
records the digest of the modules it calls (``SOURCES_DIGEST``, checked by a test).
"""
