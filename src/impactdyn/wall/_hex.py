"""Geometry of the 8-node hexahedron with one-point (uniform-strain) integration.

Local node a = 0…7 sits at the isoparametric corner (ξ_a, η_a, ζ_a) of :data:`XI`, :data:`ETA`,
:data:`ZETA` (DYNGEN's order, :mod:`._mesh`).  The kernels work on blocks of :data:`BLOCK`
bricks stored component-first in one flat array, so that the loops over the bricks of a block
are contiguous and vectorise: row r of brick k at A[r·BLOCK + k], the rows :data:`ROW_X` …
(coordinates, volume gradient, hourglass shape vectors γ, volume, characteristic length).
:func:`brick_gradient` and :func:`brick_hourglass` are the one-brick forms (X (8, 3)) for tests
and tools.

Uniform-strain mean gradient (Flanagan & Belytschko, IJNME 17 (1981) 679, "FB")::

    b_iI = (1/V) ∫_V ∂N_I/∂x_i dV = (1/V) ∂V/∂x_iI

The volume of a trilinear brick is a polynomial of degree one in each of the x-, y- and
z-coordinate sets, so ∂V/∂x_iI is exact and closed-form (FB's formula, below), and
V = Σ_I x_iI ∂V/∂x_iI for each i.  FB give, for node 1::

    12 ∂V/∂x_1 = y2[(z6 − z3) − (z4 − z5)] + y3(z2 − z4) + y4[(z3 − z8) − (z5 − z2)]
               + y5[(z8 − z6) − (z2 − z4)] + y6(z5 − z2) + y8(z4 − z5)

with ∂V/∂y_1, ∂V/∂z_1 by the cyclic permutation x → y → z → x, and the other nodes by the
node permutation :data:`PERM`.  The mean gradient integrates the linear fields exactly:
Σ_I b_iI x_jI = δ_ij and Σ_I b_iI = 0 (tests/wall/test_hex.py checks both and the formula
against 2 × 2 × 2 Gauss quadrature on a distorted brick).

Hourglass base vectors h_α (α = 1…4: ηζ, ζξ, ξη, ξηζ at the nodes) and FB's hourglass
shape vectors, orthogonal to every linear velocity field::

    γ_αI = h_αI − (Σ_J h_αJ x_iJ) b_iI

Characteristic length (Hallquist, LS-DYNA Theory Manual, time-step control for solids):
L_e = V / A_max, A_max the largest of the six face areas (a face's area is half the
norm of the cross product of its diagonals).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

#: Bricks per block of the element kernels (32: the element pass took 20 % less time than with
#: 16, and the same as with 64, on the report's wall).  The block functions below are called once
#: per block (plain calls, not inlined: the call costs little against a block's work, and
#: inlining them made the element kernel take minutes to compile).
BLOCK = 32

#: Isoparametric corner coordinates of local nodes 0…7.
XI = np.array([-1.0, 1.0, 1.0, -1.0, -1.0, 1.0, 1.0, -1.0])
ETA = np.array([-1.0, -1.0, 1.0, 1.0, -1.0, -1.0, 1.0, 1.0])
ZETA = np.array([-1.0, -1.0, -1.0, -1.0, 1.0, 1.0, 1.0, 1.0])

#: Hourglass base vectors h_α (4, 8): ηζ, ζξ, ξη, ξηζ.
HOURGLASS = np.stack([ETA * ZETA, ZETA * XI, XI * ETA, XI * ETA * ZETA])

#: Row a: the local nodes that take the places of nodes 1…8 of FB's formula for node a.
PERM = np.array([
    [0, 1, 2, 3, 4, 5, 6, 7],
    [1, 2, 3, 0, 5, 6, 7, 4],
    [2, 3, 0, 1, 6, 7, 4, 5],
    [3, 0, 1, 2, 7, 4, 5, 6],
    [4, 7, 6, 5, 0, 3, 2, 1],
    [5, 4, 7, 6, 1, 0, 3, 2],
    [6, 5, 4, 7, 2, 1, 0, 3],
    [7, 6, 5, 4, 3, 2, 1, 0],
], dtype=np.int64)

#: The six faces by local nodes (bottom, top, four sides).
FACES = np.array([[0, 1, 2, 3], [4, 5, 6, 7], [0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7]],
                 dtype=np.int64)


#: Rows of a flat block array that the kernels below read and write; row r of brick k of the block is
#: A[r·BLOCK + k]: coordinates (ROW_X + 8i + a: component i at local node a), volume gradient ∂V/∂x
#: (ROW_B + 8i + a), hourglass shape vectors γ (ROW_G + 8α + a), volume, 4 rows of work space, characteristic
#: length.  The element pass puts its own rows after these, N_GEOMETRY_ROWS on (:mod:`._blocks`).  One flat
#: array with rows a compile-time multiple of BLOCK apart, and loops over all BLOCK bricks (a compile-time
#: trip count), are what let LLVM see that the rows never overlap and vectorise the loops over the bricks.
(ROW_X, ROW_B, ROW_G, ROW_VOL, ROW_TMP, ROW_LE) = (0, 24, 48, 80, 81, 85)
N_GEOMETRY_ROWS = 86


@njit(cache=True, inline="always")
def _fb(y2, y3, y4, y5, y6, y8, z2, z3, z4, z5, z6, z8):
    """FB's 12 ∂V/∂x_1 in terms of the y and z of the nodes in places 2…6 and 8 (module docstring)."""
    return (y2 * ((z6 - z3) - (z4 - z5)) + y3 * (z2 - z4) + y4 * ((z3 - z8) - (z5 - z2))
            + y5 * ((z8 - z6) - (z2 - z4)) + y6 * (z5 - z2) + y8 * (z4 - z5))


@njit(cache=True, inline="always")
def _x(A, i, a, k):
    """Coordinate i of local node a of brick k of the block array A."""
    return A[(ROW_X + 8 * i + a) * BLOCK + k]


@njit(cache=True, inline="always")
def _fb_rows(A, j, l, n2, n3, n4, n5, n6, n8, k):
    """FB's formula for brick k with the coordinates j in the place of y and l in the place of z."""
    return _fb(_x(A, j, n2, k), _x(A, j, n3, k), _x(A, j, n4, k), _x(A, j, n5, k), _x(A, j, n6, k), _x(A, j, n8, k),
               _x(A, l, n2, k), _x(A, l, n3, k), _x(A, l, n4, k), _x(A, l, n5, k), _x(A, l, n6, k), _x(A, l, n8, k))


@njit(cache=True, inline="always")
def _node_gradient(A, a, n2, n3, n4, n5, n6, n8, k):
    """∂V/∂x_ia (rows ROW_B + 8i + a) of brick k from the local nodes in places 2…6, 8 of FB's formula
    (∂V/∂y and ∂V/∂z by the cyclic permutation x → y → z → x)."""
    A[(ROW_B + a) * BLOCK + k] = _fb_rows(A, 1, 2, n2, n3, n4, n5, n6, n8, k) / 12.0
    A[(ROW_B + 8 + a) * BLOCK + k] = _fb_rows(A, 2, 0, n2, n3, n4, n5, n6, n8, k) / 12.0
    A[(ROW_B + 16 + a) * BLOCK + k] = _fb_rows(A, 0, 1, n2, n3, n4, n5, n6, n8, k) / 12.0


@njit(cache=True, error_model="numpy")
def volume_gradient(A):
    """∂V/∂x_ia (rows ROW_B + 8i + a) and V (row ROW_VOL) of the bricks of the block array A (module docstring).

    Row a below passes the nodes of row a of :data:`PERM` in the places 2, 3, 4, 5, 6, 8.
    """
    for k in range(BLOCK):
        _node_gradient(A, 0, 1, 2, 3, 4, 5, 7, k)
        _node_gradient(A, 1, 2, 3, 0, 5, 6, 4, k)
        _node_gradient(A, 2, 3, 0, 1, 6, 7, 5, k)
        _node_gradient(A, 3, 0, 1, 2, 7, 4, 6, k)
        _node_gradient(A, 4, 7, 6, 5, 0, 3, 1, k)
        _node_gradient(A, 5, 4, 7, 6, 1, 0, 2, k)
        _node_gradient(A, 6, 5, 4, 7, 2, 1, 3, k)
        _node_gradient(A, 7, 6, 5, 4, 3, 2, 0, k)
    for k in range(BLOCK):
        s = 0.0
        for a in range(8):
            s += A[(ROW_X + a) * BLOCK + k] * A[(ROW_B + a) * BLOCK + k]
        A[ROW_VOL * BLOCK + k] = s


@njit(cache=True, error_model="numpy")
def hourglass_shapes(A):
    """FB's hourglass shape vectors γ_αa = h_αa − (h_α·x_i) ∂V/∂x_ia / V (rows ROW_G + 8α + a) of the bricks of
    the block array A, from its rows ROW_X, ROW_B and ROW_VOL; rows ROW_TMP are work space (h_α·x, h_α·y,
    h_α·z, 1/V of each brick)."""
    for k in range(BLOCK):
        A[(ROW_TMP + 3) * BLOCK + k] = 1.0 / A[ROW_VOL * BLOCK + k]
    for al in range(4):
        for k in range(BLOCK):
            t0 = 0.0
            t1 = 0.0
            t2 = 0.0
            for a in range(8):
                h = HOURGLASS[al, a]
                t0 += h * _x(A, 0, a, k)
                t1 += h * _x(A, 1, a, k)
                t2 += h * _x(A, 2, a, k)
            A[ROW_TMP * BLOCK + k] = t0
            A[(ROW_TMP + 1) * BLOCK + k] = t1
            A[(ROW_TMP + 2) * BLOCK + k] = t2
        for a in range(8):
            h = HOURGLASS[al, a]
            for k in range(BLOCK):
                A[(ROW_G + 8 * al + a) * BLOCK + k] = h - (
                    A[ROW_TMP * BLOCK + k] * A[(ROW_B + a) * BLOCK + k]
                    + A[(ROW_TMP + 1) * BLOCK + k] * A[(ROW_B + 8 + a) * BLOCK + k]
                    + A[(ROW_TMP + 2) * BLOCK + k] * A[(ROW_B + 16 + a) * BLOCK + k]) * A[(ROW_TMP + 3) * BLOCK + k]


@njit(cache=True, inline="always")
def _face_area2(A, a, b, c, d, k):
    """(2 × area)² of the face a, b, c, d of brick k: |(x_c − x_a) × (x_d − x_b)|²."""
    p0, p1, p2 = _x(A, 0, c, k) - _x(A, 0, a, k), _x(A, 1, c, k) - _x(A, 1, a, k), _x(A, 2, c, k) - _x(A, 2, a, k)
    q0, q1, q2 = _x(A, 0, d, k) - _x(A, 0, b, k), _x(A, 1, d, k) - _x(A, 1, b, k), _x(A, 2, d, k) - _x(A, 2, b, k)
    cx, cy, cz = p1 * q2 - p2 * q1, p2 * q0 - p0 * q2, p0 * q1 - p1 * q0
    return cx * cx + cy * cy + cz * cz


@njit(cache=True, inline="always")
def _larger(a, b):
    """max(a, b) as a select (numba lowers max() of floats to a call, which stops vectorisation)."""
    return a if a > b else b


@njit(cache=True, error_model="numpy")
def characteristic_lengths(A):
    """L_e = V/A_max (row ROW_LE, cm) of the bricks of the block array A (A_max: the largest face area;
    the faces of :data:`FACES`, written out so that the node rows are constants)."""
    for k in range(BLOCK):
        amax2 = _larger(_larger(_face_area2(A, 0, 1, 2, 3, k), _face_area2(A, 4, 5, 6, 7, k)),
                        _larger(_face_area2(A, 0, 1, 5, 4, k), _face_area2(A, 1, 2, 6, 5, k)))
        amax2 = _larger(amax2, _larger(_face_area2(A, 2, 3, 7, 6, k), _face_area2(A, 3, 0, 4, 7, k)))
        A[ROW_LE * BLOCK + k] = A[ROW_VOL * BLOCK + k] / (0.5 * math.sqrt(amax2))


@njit(cache=True)
def gather_coordinates(A, coords, conn, e0):
    """Rows ROW_X of the block array A from the coordinates (n_nodes, 3) of elements e0 … e0 + BLOCK − 1
    (conn (n_elements, 8)); past the last element the block repeats it, so that every brick is valid."""
    last = conn.shape[0] - 1
    for k in range(BLOCK):
        e = min(e0 + k, last)
        for a in range(8):
            for i in range(3):
                A[(ROW_X + 8 * i + a) * BLOCK + k] = coords[conn[e, a], i]


@njit(parallel=True, cache=True)
def element_volumes(coords, conn):
    """Volume of every element of a mesh, (n_elements,), from the node coordinates (n_nodes, 3)."""
    ne = conn.shape[0]
    out = np.empty(ne)
    for blk in prange((ne + BLOCK - 1) // BLOCK):
        A = np.zeros(N_GEOMETRY_ROWS * BLOCK)
        e0 = blk * BLOCK
        gather_coordinates(A, coords, conn, e0)
        volume_gradient(A)
        for k in range(min(BLOCK, ne - e0)):
            out[e0 + k] = A[ROW_VOL * BLOCK + k]
    return out


@njit(cache=True)
def _one_brick(X):
    """One brick X (8, 3) in every brick of a geometry block array, its gradient and volume filled."""
    A = np.zeros(N_GEOMETRY_ROWS * BLOCK)
    for k in range(BLOCK):
        for a in range(8):
            for i in range(3):
                A[(ROW_X + 8 * i + a) * BLOCK + k] = X[a, i]
    volume_gradient(A)
    return A


@njit(cache=True)
def brick_gradient(X):
    """(B (8, 3), V) of one brick X (8, 3): the volume gradient ∂V/∂x_ia and the volume (tests, tools)."""
    A = _one_brick(X)
    B = np.empty((8, 3))
    for a in range(8):
        for i in range(3):
            B[a, i] = A[(ROW_B + 8 * i + a) * BLOCK]
    return B, A[ROW_VOL * BLOCK]


@njit(cache=True)
def brick_hourglass(X):
    """γ (4, 8) of one brick X (8, 3) (tests, tools)."""
    A = _one_brick(X)
    hourglass_shapes(A)
    G = np.empty((4, 8))
    for al in range(4):
        for a in range(8):
            G[al, a] = A[(ROW_G + 8 * al + a) * BLOCK]
    return G
