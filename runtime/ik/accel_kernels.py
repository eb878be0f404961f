"""Compiled kernels (numba) of one IPO cycle — the numbers of :mod:`newton`, fused.

Imported only through :mod:`accel` when numba is available. Each function here is the
same arithmetic as its numpy reference (named in its docstring), written as loops:

* ``_chain``: ``Kinematics.chain`` — ``L_i = A0 + cos v·A1 + sin v·A2 + v·A3``,
  ``T_i = T_{i−1}·L_i``; ``_jacobian``: ``Kinematics.tcp_jacobian`` —
  ``[z_i × (p − o_i); z_i]`` (revolute), ``[z_i; 0]`` (prismatic), ``z_i = R_i·k_i``;
* ``_pose_error``: ``task_error.pose_error_list`` / ``spatial.pose_error`` (near-π branch
  included);
* ``_box``: ``JointBox.prepare`` (signed candidates, braking bound ``2R/(1 + √(1 + 2R/ε))``);
* ``_split``: ``CompactBasis._solve`` — ``−J_m⁻¹[J_free F]`` by LU with partial pivoting,
  the pivot spread as the degradation test;
* ``_scalar_qp`` / ``_checked`` / ``_hard_data``: ``NewtonStep.hard_diagonal``;
  ``_hard_data_general``: ``compact_box_qp`` + ``_with_rows`` (``NewtonStep.hard``);
  ``_relaxed_data``: ``NewtonStep.relaxed_diagonal`` / ``relaxed`` (the QP data only);
  ``_unconstrained_qp``: the compact QP's answer when no constraint binds (else quadprog
  is called from Python);
* ``_general_cost``: ``InverseTransformation._cost`` (CYCLIC, ``a_conf·W``, obstacle
  terms); ``_reduce``: the FREEZE reduction of ``InverseTransformation._solve``;
* ``_active_codes``: ``limits.active_codes``.

:func:`newton_cycle` is a resumable state machine: it runs Newton iterations until the
cycle is done or it needs Python (a quadprog call, a new basis by QR pivoting, the
obstacle terms, the error path of the joint box); the caller does that and resumes it
with a phase code. State lives in the integer / float arrays ``ist`` / ``fst`` (indices
below); every array is a view of one workspace (``accel.Workspace``, layout below).

The kernels live in one module per concept: :mod:`accel_layout` (the state's slots),
:mod:`accel_chain` (FK, Jacobian, pose error), :mod:`accel_box` (the joint box),
:mod:`accel_qp` (basis split and the compact QP's data) and :mod:`accel_cycle` (the fused
cycle). numba's on-disk cache of a function is keyed by its own source file only, so
:mod:`accel_cycle` records the digest of the modules it calls (its ``SOURCES_DIGEST``,
checked by a test): a change in them changes that file and recompiles the cycle. This
module re-exports them all (``accel_kernels.newton_cycle``, ``accel_kernels._box``, …).
"""

from __future__ import annotations

from irlc.runtime.ik.accel_box import (  # noqa: F401 (re-exported)
    _active_codes,
    _box,
)
from irlc.runtime.ik.accel_chain import (  # noqa: F401 (re-exported)
    _chain,
    _evaluate,
    _jacobian,
    _matmul44,
    _pose_error,
)
from irlc.runtime.ik.accel_cycle import (  # noqa: F401 (re-exported)
    _general_cost,
    _reduce,
    _v1,
    _v2,
    _v3,
    newton_cycle,
)
from irlc.runtime.ik.accel_layout import (  # noqa: F401 (re-exported)
    _BIG,
    _BOX_TOL,
    _TOL,
    ACCEL_BOUNDED,
    ANY_CODE,
    BASIS_REASON,
    BASIS_STAGE,
    BASIS_VALID,
    BOX_READY,
    CFZ,
    COND,
    COND_LIMIT,
    COND_MAX,
    DP,
    DTHETA,
    DTOL,
    E0,
    F_A,
    F_AR,
    F_AUG,
    F_BOUND_D,
    F_BOUND_R,
    F_BOUNDS,
    F_BT,
    F_CAND,
    F_CT,
    F_F,
    F_FR,
    F_FRAMES,
    F_FST,
    F_FTARGET,
    F_GREL,
    F_GT,
    F_H,
    F_HR,
    F_HREL,
    F_HT,
    F_J6,
    F_JR,
    F_JT,
    F_MULT,
    F_N,
    F_TARGET,
    F_TCP,
    F_V,
    F_VR,
    GENERAL,
    HAS_REF,
    HAVE_J,
    I_ACTIVE,
    I_CODES,
    I_FREE,
    I_FZ,
    I_IST,
    I_PERM,
    I_ROWS,
    LAST_SINGULAR,
    LOWER,
    MAX_ITER,
    N_ACTIVE,
    N_FST,
    N_IST,
    N_IST_ALL,
    N_LAY,
    NEED_TERMS,
    NPOS,
    NV,
    OE,
    P_APPLY,
    P_APPLY_Z,
    P_RELAX,
    P_SPLIT,
    P_START,
    P_START_CHECKED,
    P_TERMS,
    PE,
    PHASE,
    Q_PREV,
    Q_START,
    REF,
    RELAX_W,
    RELAXED,
    S_BAD_STEP,
    S_BOX_CHECK,
    S_DONE,
    S_FROZEN_FAR,
    S_NEED_BASIS,
    S_NEED_QP,
    S_NEED_RELAXED,
    S_NEED_TERMS,
    S_NOT_FINITE,
    SCALAR,
    SCALE,
    SELF_MOTION,
    SIGMA,
    SINGULAR,
    SINGULAR_COND,
    THETA,
    TOL_O,
    TOL_P,
    UPPER,
    WARM,
    WC,
    Z_M,
    Z_N,
    Z_NF,
    Z_NFZ,
    Z_R,
    G,
    K,
    W,
    Z,
)
from irlc.runtime.ik.accel_qp import (  # noqa: F401 (re-exported)
    _checked,
    _compact_rest,
    _hard_data,
    _hard_data_general,
    _relaxed_data,
    _row_terms,
    _scalar_qp,
    _split,
    _unconstrained_qp,
)
