"""The shared state of the compiled IK kernels: the phase and status codes of
:func:`.cycle.newton_cycle`, the slots of its integer / float state arrays ``ist`` /
``fst``, the rows of the vector workspace ``V``, the slots of the one-buffer layout
``lay`` (:class:`.driver.Workspace` cuts the same views) and the kernels' tolerances.

Plain module constants: numba freezes them into the machine code of every kernel that
reads them (a change here must touch :data:`.cycle.SOURCES_DIGEST`, see there).
"""

# phases (ist[PHASE]) the caller resumes with (P_START_CHECKED: start a cycle whose
# inputs Python has checked; P_START checks them first and may return S_NOT_FINITE)
P_START, P_APPLY, P_APPLY_Z, P_SPLIT, P_RELAX, P_TERMS, P_START_CHECKED = 0, 1, 2, 3, 4, 5, 6
# statuses returned
S_DONE, S_BOX_CHECK, S_NEED_BASIS, S_NEED_QP, S_NEED_RELAXED, S_BAD_STEP = 0, 1, 2, 3, 4, 5
S_NEED_TERMS, S_FROZEN_FAR, S_NOT_FINITE = 6, 7, 8
# ist indices
(
    PHASE,
    K,
    RELAXED,
    SINGULAR,
    LAST_SINGULAR,
    BASIS_VALID,
    BASIS_STAGE,
    BASIS_REASON,
    N_ACTIVE,
    MAX_ITER,
    SELF_MOTION,
    WARM,
    SCALAR,
    HAS_REF,
    ACCEL_BOUNDED,
    BOX_READY,
    NPOS,
    HAVE_J,
    GENERAL,
    NEED_TERMS,
    FULL_METRIC,
    N_IST,
) = range(22)
# fst indices (E0 … E0 + 5: the last task error, all six components)
TOL_P, TOL_O, COND_MAX, SINGULAR_COND, COND_LIMIT, RELAX_W, PE, OE, SCALE, DTOL, COND, E0 = range(
    12
)
N_FST = E0 + 6
# rows of the (NV, n) vector workspace V (WC: the extra diagonal a_conf·W of the general
# cost; CFZ: the fixed steps θ⁰ − θ_k of the frozen joints, first n_frozen entries)
Q_START, Q_PREV, THETA, DTHETA, SIGMA, G, W, REF, DP, LOWER, UPPER, Z, WC, CFZ, NV = range(15)

BIG = 1e30
TOL = 1e-9
BOX_TOL = 1e-12


# ---------------------------------------------------------------------- one-buffer entry
# Slots of the layout ``lay`` (int64): offsets of each array in the float workspace ``fw``
# or the int workspace ``iw``, then the sizes. One Python→numba call unboxes every array
# argument (≈ 0.15–0.3 µs each), so the cycle passes two buffers and a layout instead of
# forty arrays; :func:`.cycle.newton_cycle` cuts the same views the driver's Workspace
# uses.
(
    F_V, F_FRAMES, F_TCP, F_J6, F_JT, F_F, F_H, F_A, F_BOUND_D, F_BOUNDS, F_CAND, F_TARGET,
    F_VR, F_JR, F_FR, F_HR, F_AR, F_BOUND_R, F_AUG, F_N, F_HT, F_GT, F_CT, F_BT, F_HREL,
    F_GREL, F_MULT, F_FTARGET, F_FST, F_MA, F_MC,
    I_ROWS, I_FREE, I_FZ, I_PERM, I_ACTIVE, I_IST, I_CODES,
    Z_N, Z_M, Z_NF, Z_R, Z_NFZ,
    N_LAY,
) = range(44)  # fmt: skip
# ist[FULL_METRIC]: the criterion's metric is a full matrix (R_CRITERION := 'ENERGY'):
# g = MA·x + MC·Σ (x = θ − θ⁰ with a reference, else Σ), H = MA + MC (F_MA, F_MC, (n, n)),
# in place of the diagonal weights V[W], V[WC] (cycle.metric_cost)
ANY_CODE = N_IST  # ist[ANY_CODE]: some joint's displacement is at a box bound (codes set)
N_IST_ALL = N_IST + 1
