"""Geometry of the 8-node hexahedron with one-point (uniform-strain) integration.

Local node a = 0…7 sits at the isoparametric corner (ξ_a, η_a, ζ_a) of :data:`XI`, :data:`ETA`,
:data:`ZETA` (DYNGEN's order, :mod:`._mesh`).  The kernels work on blocks of up to
:data:`BLOCK` bricks stored component-first, so that the loops over the bricks of a block
are contiguous and vectorise: coordinates X (3, 8, NB) — X[i, a, k] is coordinate i of
local node a of brick k —, volume gradient B (3, 8, NB), hourglass shape vectors
γ (4, 8, NB), volumes (NB,).  :func:`brick_gradient` and :func:`brick_hourglass` are the
one-brick forms (X (8, 3)) for tests and tools.

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


@njit(cache=True, inline="always")
def _fb(y2, y3, y4, y5, y6, y8, z2, z3, z4, z5, z6, z8):
    """FB's 12 ∂V/∂x_1 in terms of the y and z of the nodes in places 2…6 and 8 (module docstring)."""
    return (y2 * ((z6 - z3) - (z4 - z5)) + y3 * (z2 - z4) + y4 * ((z3 - z8) - (z5 - z2))
            + y5 * ((z8 - z6) - (z2 - z4)) + y6 * (z5 - z2) + y8 * (z4 - z5))


@njit(cache=True, inline="always")
def _node_gradient(B, a, X, n2, n3, n4, n5, n6, n8, nb):
    """B[:, a, k] of bricks k < nb from the local nodes in places 2…6, 8 of FB's formula."""
    for k in range(nb):
        B[0, a, k] = _fb(X[1, n2, k], X[1, n3, k], X[1, n4, k], X[1, n5, k], X[1, n6, k], X[1, n8, k],
                         X[2, n2, k], X[2, n3, k], X[2, n4, k], X[2, n5, k], X[2, n6, k], X[2, n8, k]) / 12.0
        B[1, a, k] = _fb(X[2, n2, k], X[2, n3, k], X[2, n4, k], X[2, n5, k], X[2, n6, k], X[2, n8, k],
                         X[0, n2, k], X[0, n3, k], X[0, n4, k], X[0, n5, k], X[0, n6, k], X[0, n8, k]) / 12.0
        B[2, a, k] = _fb(X[0, n2, k], X[0, n3, k], X[0, n4, k], X[0, n5, k], X[0, n6, k], X[0, n8, k],
                         X[1, n2, k], X[1, n3, k], X[1, n4, k], X[1, n5, k], X[1, n6, k], X[1, n8, k]) / 12.0


@njit(cache=True, fastmath={"contract"}, error_model="numpy")
def volume_gradient(X, B, vol, nb):
    """B[i, a, k] = ∂V/∂x_ia and vol[k] = V of the bricks k < nb of the block X (module docstring).

    Row a below passes the nodes of row a of :data:`PERM` in the places 2, 3, 4, 5, 6, 8.
    """
    _node_gradient(B, 0, X, 1, 2, 3, 4, 5, 7, nb)
    _node_gradient(B, 1, X, 2, 3, 0, 5, 6, 4, nb)
    _node_gradient(B, 2, X, 3, 0, 1, 6, 7, 5, nb)
    _node_gradient(B, 3, X, 0, 1, 2, 7, 4, 6, nb)
    _node_gradient(B, 4, X, 7, 6, 5, 0, 3, 1, nb)
    _node_gradient(B, 5, X, 4, 7, 6, 1, 0, 2, nb)
    _node_gradient(B, 6, X, 5, 4, 7, 2, 1, 3, nb)
    _node_gradient(B, 7, X, 6, 5, 4, 3, 2, 0, nb)
    for k in range(nb):
        s = 0.0
        for a in range(8):
            s += X[0, a, k] * B[0, a, k]
        vol[k] = s


@njit(cache=True, fastmath={"contract"}, error_model="numpy")
def hourglass_shapes(X, B, vol, G, T, nb):
    """FB's hourglass shape vectors G[α, a, k] = h_αa − (h_α·x_i) B[i, a, k]/V_k of bricks k < nb.

    T (4, NB) is work space (h_α·x, h_α·y, h_α·z, 1/V of each brick); the loops run over the
    bricks innermost.
    """
    for k in range(nb):
        T[3, k] = 1.0 / vol[k]
    for al in range(4):
        for k in range(nb):
            T[0, k] = 0.0
            T[1, k] = 0.0
            T[2, k] = 0.0
        for a in range(8):
            h = HOURGLASS[al, a]
            for k in range(nb):
                T[0, k] += h * X[0, a, k]
                T[1, k] += h * X[1, a, k]
                T[2, k] += h * X[2, a, k]
        for a in range(8):
            h = HOURGLASS[al, a]
            for k in range(nb):
                G[al, a, k] = h - (T[0, k] * B[0, a, k] + T[1, k] * B[1, a, k] + T[2, k] * B[2, a, k]) * T[3, k]


@njit(cache=True, fastmath={"contract"}, error_model="numpy")
def characteristic_lengths(X, vol, ell, nb):
    """ell[k] = L_e = V/A_max of bricks k < nb of the block X, cm (A_max: the largest face area)."""
    for k in range(nb):
        amax2 = 0.0
        for f in range(6):
            a, b, c, d = FACES[f, 0], FACES[f, 1], FACES[f, 2], FACES[f, 3]
            p0, p1, p2 = X[0, c, k] - X[0, a, k], X[1, c, k] - X[1, a, k], X[2, c, k] - X[2, a, k]
            q0, q1, q2 = X[0, d, k] - X[0, b, k], X[1, d, k] - X[1, b, k], X[2, d, k] - X[2, b, k]
            cx, cy, cz = p1 * q2 - p2 * q1, p2 * q0 - p0 * q2, p0 * q1 - p1 * q0
            a2 = cx * cx + cy * cy + cz * cz
            amax2 = a2 if a2 > amax2 else amax2      # a select, not max(): the loop over k vectorises
        ell[k] = vol[k] / (0.5 * math.sqrt(amax2))


@njit(parallel=True, cache=True)
def element_volumes(coords, conn):
    """Volume of every element of a mesh, (n_elements,), from the node coordinates (n_nodes, 3)."""
    ne = conn.shape[0]
    out = np.empty(ne)
    for e in prange(ne):
        X = np.empty((3, 8, 1))
        B = np.empty((3, 8, 1))
        vol = np.empty(1)
        for a in range(8):
            for i in range(3):
                X[i, a, 0] = coords[conn[e, a], i]
        volume_gradient(X, B, vol, 1)
        out[e] = vol[0]
    return out


@njit(cache=True)
def _one_brick(X):
    """One brick X (8, 3) in the kernels' blocked layout: (Xb (3, 8, 1), B (3, 8, 1), V (1,)), B and V filled."""
    Xb = np.ascontiguousarray(X.T).reshape(3, 8, 1)
    B = np.empty((3, 8, 1))
    vol = np.empty(1)
    volume_gradient(Xb, B, vol, 1)
    return Xb, B, vol


@njit(cache=True)
def brick_gradient(X):
    """(B (8, 3), V) of one brick X (8, 3): the volume gradient ∂V/∂x_ia and the volume (tests, tools)."""
    _, B, vol = _one_brick(X)
    return np.ascontiguousarray(B[:, :, 0].T), vol[0]


@njit(cache=True)
def brick_hourglass(X):
    """γ (4, 8) of one brick X (8, 3) (tests, tools)."""
    Xb, B, vol = _one_brick(X)
    G = np.empty((4, 8, 1))
    hourglass_shapes(Xb, B, vol, G, np.empty((4, 1)), 1)
    return np.ascontiguousarray(G[:, :, 0])
