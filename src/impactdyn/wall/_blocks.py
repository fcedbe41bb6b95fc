"""The element pass's per-thread block array: its rows, their accessors, and the arrays to allocate.

The element pass (:mod:`._step`) takes the elements in blocks of :data:`~._hex.BLOCK` bricks and
works on each block in one flat array of its thread, component-first: row r of brick k at
A[r·BLOCK + k].  The rows of :mod:`._hex` (geometry) come first, then those below.
"""

import numpy as np
from numba import njit

from impactdyn.wall._hex import BLOCK, N_GEOMETRY_ROWS, ROW_B, ROW_G, ROW_LE, ROW_VOL, ROW_X
from impactdyn.wall._state import N_SHG

#: Rows of the per-thread flat block array ``A`` of :func:`._step._element_pass`; row r of brick k of the
#: block is A[r·BLOCK + k].  First the geometry rows of :mod:`._hex` (end coordinates R_X + 8i + a: component i
#: at local node a; volume gradient ∂V/∂x R_B + 8i + a; hourglass shape vectors γ R_G + 8α + a; volume; 4 rows
#: of work space; characteristic length), then per brick: velocities (R_V + 8i + a), nodal forces
#: (R_F + 8i + a), hourglass velocities q̇ and forces Q (R_QD + 3α + i, R_QN + 3α + i), velocity gradient in
#: the end configuration (R_LB + 3i + j), the reciprocal vectors ∇ξ_m (R_J + 3m + i), the midstep velocity
#: gradient (R_LM + 3i + j), the power p2 = fⁿ·v^{n+½}, the stress σ = S − pI (R_SIG + 6 components), bulk
#: viscosity q, live flag, power p1 = f_σ·v^{n+½}, B·v^{n+½}, sound speed, tr d, stable step Δt_e, and the
#: assumed-strain form's tangent ratio, flow stress, spin over the step Δt (Ω_xy, Ω_yz, Ω_xz) and stored
#: hourglass stresses (R_SHG + the ``Shg`` column).  One flat array with rows a compile-time multiple of BLOCK apart, and block kernels that
#: run over all BLOCK bricks (a compile-time trip count), are what let the compiler see that the rows never
#: overlap and vectorise the loops over the bricks.  Past the end of a short last block those kernels compute
#: on stale rows, whose results are never read.
(R_X, R_B, R_G, R_VOL, R_LE) = (ROW_X, ROW_B, ROW_G, ROW_VOL, ROW_LE)
(R_V, R_F, R_QD, R_QN, R_LB, R_J, R_LM) = (N_GEOMETRY_ROWS + r for r in (0, 24, 48, 60, 72, 81, 90))
(R_P2, R_SIG, R_Q, R_OK, R_P1, R_BV, R_C, R_TRD, R_DTE, R_RATIO, R_FLOW, R_SPIN, R_SHG) = (
    N_GEOMETRY_ROWS + r for r in (99, 100, 106, 107, 108, 109, 110, 111, 112, 113, 114, 115, 118))
N_ROWS = R_SHG + N_SHG


@njit(cache=True, inline="always")
def block_column(A, row, a, k):
    """Components 0, 1, 2 at local node a of brick k of the (3, 8) quantity at ``row`` of the block array A."""
    return A[(row + a) * BLOCK + k], A[(row + 8 + a) * BLOCK + k], A[(row + 16 + a) * BLOCK + k]


@njit(cache=True, inline="always")
def block_vector(H, row, k):
    """(H[row], H[row + 1], H[row + 2]) of brick k: three consecutive rows of the flat block array."""
    return H[row * BLOCK + k], H[(row + 1) * BLOCK + k], H[(row + 2) * BLOCK + k]


def work_arrays(n_threads: int) -> np.ndarray:
    """Per-thread block array of the element pass, (n_threads, N_ROWS · BLOCK) (rows :data:`R_X` …)."""
    return np.zeros((n_threads, N_ROWS * BLOCK))


def hourglass_stress_array(n_elements: int) -> np.ndarray:
    """Zeroed ``Shg`` of the assumed-strain form for ``n_elements`` elements, (n_blocks, N_SHG, BLOCK):
    element e's column c at [e // BLOCK, c, e % BLOCK] (blocked like the element pass, so that a block's
    stresses are contiguous rows)."""
    return np.zeros(((n_elements + BLOCK - 1) // BLOCK, N_SHG, BLOCK))

