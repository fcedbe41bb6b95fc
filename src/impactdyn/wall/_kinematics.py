"""Kinematics of a block of bricks: velocity gradient, hourglass velocities, midstep gradient.

For element e at step n+1 with the nodal velocities v = v^{n+½}, the strain rate is taken at
the midstep configuration x^{n+½} = x^{n+1} − ½Δt^{n+½} v (Flanagan & Belytschko, IJNME 17 (1981)
679, "FB"; Hughes & Winget's midpoint rule, with which a spinning element gains no strain).
With the gradient G = Σ_I v_I ⊗ b_I(x^{n+1}) of the element's uniform motion in the end
configuration, v = G x^{n+1} + c, the midstep gradient of that motion is exactly
(:func:`midstep_gradients`)::

    L = G (I − ½Δt G)⁻¹,   d = sym L,   Ω = skew L

the same as Σ_I v_I ⊗ b_I(x^{n+½}) for every linear (uniform) velocity field — all the
one-point element strains with — at the price of a 3 × 3 inverse instead of a second volume
gradient; for a rigid rotation it is exactly skew (the Cayley form).

The kernels work on the block array of :mod:`._blocks` (rows R_…), over all its BLOCK bricks.
"""

from numba import njit

from impactdyn.wall._blocks import R_B, R_G, R_J, R_LB, R_LM, R_QD, R_V, R_VOL, block_vector
from impactdyn.wall._hex import BLOCK, ETA, XI, ZETA

@njit(cache=True, error_model="numpy")
def midstep_gradients(A, h):
    """L = G (I − h G)⁻¹ (rows R_LM + 3i + j): the midstep velocity gradient of the uniform motion of the
    bricks of the block array A (h = ½Δt).

    G (rows R_LB + 3i + j) is the gradient of a brick's velocities in the end configuration x^{n+1}.
    For the linear (uniform) part of the motion, v = G x^{n+1} + c and x^{n+½} = x^{n+1} − h v,
    so v = G (I − h G)⁻¹ x^{n+½} + c': this is the mean gradient in the midstep configuration,
    exactly, for all the motion the one-point element strains with (the hourglass part aside).
    For a rigid rotation it is the Cayley form (2/Δt)(I − Q)(I + Q)⁻¹, Q = Rⁿ(Rⁿ⁺¹)ᵀ, exactly
    skew: no strain.
    """
    for k in range(BLOCK):
        g00, g01, g02 = block_vector(A, R_LB, k)
        g10, g11, g12 = block_vector(A, R_LB + 3, k)
        g20, g21, g22 = block_vector(A, R_LB + 6, k)
        m00, m01, m02 = 1.0 - h * g00, -h * g01, -h * g02
        m10, m11, m12 = -h * g10, 1.0 - h * g11, -h * g12
        m20, m21, m22 = -h * g20, -h * g21, 1.0 - h * g22
        c00, c01, c02 = m11 * m22 - m12 * m21, m02 * m21 - m01 * m22, m01 * m12 - m02 * m11
        c10, c11, c12 = m12 * m20 - m10 * m22, m00 * m22 - m02 * m20, m02 * m10 - m00 * m12
        c20, c21, c22 = m10 * m21 - m11 * m20, m01 * m20 - m00 * m21, m00 * m11 - m01 * m10
        r = 1.0 / (m00 * c00 + m01 * c10 + m02 * c20)
        for i in range(3):
            g0, g1, g2 = block_vector(A, R_LB + 3 * i, k)
            A[(R_LM + 3 * i) * BLOCK + k] = (g0 * c00 + g1 * c10 + g2 * c20) * r
            A[(R_LM + 3 * i + 1) * BLOCK + k] = (g0 * c01 + g1 * c11 + g2 * c21) * r
            A[(R_LM + 3 * i + 2) * BLOCK + k] = (g0 * c02 + g1 * c12 + g2 * c22) * r


@njit(cache=True, error_model="numpy")
def reciprocal_vectors(A):
    """∇ξ_m = Σ_I ξ_mI B_iI / V (rows R_J + 3m + i) of the bricks of the block array A
    (ξ_m = ξ, η, ζ at the corners).

    For a parallelepiped b_I = ∇N_I = ⅛ Σ_m ξ_mI ∇ξ_m, so Σ_I ξ_mI b_I = ∇ξ_m exactly
    (|∇ξ| = 2/a, a the edge length along ξ); for other bricks, the mean-gradient image of it.
    """
    for m in range(3):
        corner = XI if m == 0 else (ETA if m == 1 else ZETA)
        for i in range(3):
            for k in range(BLOCK):
                s = 0.0
                for a in range(8):
                    s += corner[a] * A[(R_B + 8 * i + a) * BLOCK + k]
                A[(R_J + 3 * m + i) * BLOCK + k] = s / A[R_VOL * BLOCK + k]


@njit(cache=True, error_model="numpy")
def velocity_gradients(A):
    """The velocity gradient G_ij = Σ_I v_iI b_jI (rows R_LB + 3i + j) in the end configuration and the
    hourglass velocities q̇_αi = Σ_I γ_αI v_iI (rows R_QD + 3α + i) of the bricks of the block array A."""
    for i in range(3):
        for j in range(3):
            for k in range(BLOCK):
                A[(R_LB + 3 * i + j) * BLOCK + k] = _node_sum(A, R_V + 8 * i, R_B + 8 * j, k) / A[R_VOL * BLOCK + k]
    for al in range(4):
        for i in range(3):
            for k in range(BLOCK):
                A[(R_QD + 3 * al + i) * BLOCK + k] = _node_sum(A, R_G + 8 * al, R_V + 8 * i, k)


@njit(cache=True, inline="always")
def _node_sum(A, row1, row2, k):
    """Σ_a A[row1 + a] A[row2 + a] over the local nodes a = 0…7 of brick k: two (·, 8) rows contracted."""
    s = 0.0
    for a in range(8):
        s += A[(row1 + a) * BLOCK + k] * A[(row2 + a) * BLOCK + k]
    return s
