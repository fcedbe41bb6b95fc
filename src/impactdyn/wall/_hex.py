"""Geometry of the 8-node hexahedron with one-point (uniform-strain) integration.

Local node a = 0…7 sits at the isoparametric corner (ξ_a, η_a, ζ_a) of :data:`XI`, :data:`ETA`,
:data:`ZETA` (DYNGEN's order, :mod:`._mesh`).  Arrays of one element: coordinates X (8, 3),
velocities v (8, 3), volume gradient B (8, 3), hourglass shape vectors γ (4, 8).

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
    """FB's 12 ∂V/∂x_1 in terms of the y and z of nodes 2…6 and 8 (module docstring)."""
    return (y2 * ((z6 - z3) - (z4 - z5)) + y3 * (z2 - z4) + y4 * ((z3 - z8) - (z5 - z2))
            + y5 * ((z8 - z6) - (z2 - z4)) + y6 * (z5 - z2) + y8 * (z4 - z5))


@njit(cache=True, inline="always")
def _node_gradient(B, a, n2, n3, n4, n5, n6, n8):
    """B[a] from the nodes in the places 2…6, 8 of FB's formula (coordinate tuples (x, y, z))."""
    B[a, 0] = _fb(n2[1], n3[1], n4[1], n5[1], n6[1], n8[1], n2[2], n3[2], n4[2], n5[2], n6[2], n8[2]) / 12.0
    B[a, 1] = _fb(n2[2], n3[2], n4[2], n5[2], n6[2], n8[2], n2[0], n3[0], n4[0], n5[0], n6[0], n8[0]) / 12.0
    B[a, 2] = _fb(n2[0], n3[0], n4[0], n5[0], n6[0], n8[0], n2[1], n3[1], n4[1], n5[1], n6[1], n8[1]) / 12.0


@njit(cache=True, inline="always")
def volume_gradient(X, B):
    """B[a, i] = ∂V/∂x_ia of the brick X (8, 3) (FB's formula, module docstring); returns V.

    Row a below passes the nodes of row a of :data:`PERM` in the places 2, 3, 4, 5, 6, 8.
    """
    c0 = (X[0, 0], X[0, 1], X[0, 2])
    c1 = (X[1, 0], X[1, 1], X[1, 2])
    c2 = (X[2, 0], X[2, 1], X[2, 2])
    c3 = (X[3, 0], X[3, 1], X[3, 2])
    c4 = (X[4, 0], X[4, 1], X[4, 2])
    c5 = (X[5, 0], X[5, 1], X[5, 2])
    c6 = (X[6, 0], X[6, 1], X[6, 2])
    c7 = (X[7, 0], X[7, 1], X[7, 2])
    _node_gradient(B, 0, c1, c2, c3, c4, c5, c7)
    _node_gradient(B, 1, c2, c3, c0, c5, c6, c4)
    _node_gradient(B, 2, c3, c0, c1, c6, c7, c5)
    _node_gradient(B, 3, c0, c1, c2, c7, c4, c6)
    _node_gradient(B, 4, c7, c6, c5, c0, c3, c1)
    _node_gradient(B, 5, c4, c7, c6, c1, c0, c2)
    _node_gradient(B, 6, c5, c4, c7, c2, c1, c3)
    _node_gradient(B, 7, c6, c5, c4, c3, c2, c0)
    return (c0[0] * B[0, 0] + c1[0] * B[1, 0] + c2[0] * B[2, 0] + c3[0] * B[3, 0]
            + c4[0] * B[4, 0] + c5[0] * B[5, 0] + c6[0] * B[6, 0] + c7[0] * B[7, 0])


@njit(cache=True, inline="always")
def largest_face_area(X):
    """A_max: the largest face area of the brick X (8, 3), cm²."""
    amax2 = 0.0
    for f in range(6):
        a, b, c, d = FACES[f, 0], FACES[f, 1], FACES[f, 2], FACES[f, 3]
        p0, p1, p2 = X[c, 0] - X[a, 0], X[c, 1] - X[a, 1], X[c, 2] - X[a, 2]
        q0, q1, q2 = X[d, 0] - X[b, 0], X[d, 1] - X[b, 1], X[d, 2] - X[b, 2]
        cx, cy, cz = p1 * q2 - p2 * q1, p2 * q0 - p0 * q2, p0 * q1 - p1 * q0
        amax2 = max(amax2, cx * cx + cy * cy + cz * cz)
    return 0.5 * math.sqrt(amax2)


@njit(cache=True, inline="always")
def hourglass_shapes(X, B, vol, G):
    """FB's hourglass shape vectors G[α, a] = γ_αa = h_αa − (h_α·x_i) B[a, i]/V (module docstring)."""
    for al in range(4):
        hx = 0.0
        hy = 0.0
        hz = 0.0
        for a in range(8):
            h = HOURGLASS[al, a]
            hx += h * X[a, 0]
            hy += h * X[a, 1]
            hz += h * X[a, 2]
        for a in range(8):
            G[al, a] = HOURGLASS[al, a] - (hx * B[a, 0] + hy * B[a, 1] + hz * B[a, 2]) / vol


@njit(parallel=True, cache=True)
def element_volumes(coords, conn):
    """Volume of every element of a mesh, (n_elements,), from the node coordinates (n_nodes, 3)."""
    ne = conn.shape[0]
    out = np.empty(ne)
    for e in prange(ne):
        X = np.empty((8, 3))
        B = np.empty((8, 3))
        for a in range(8):
            for i in range(3):
                X[a, i] = coords[conn[e, a], i]
        out[e] = volume_gradient(X, B)
    return out


@njit(cache=True)
def brick_gradient(X):
    """(B (8, 3), V) of one brick: the volume gradient ∂V/∂x_ia and the volume (for tests and tools)."""
    B = np.empty((8, 3))
    vol = volume_gradient(X, B)
    return B, vol


@njit(cache=True)
def brick_hourglass(X):
    """γ (4, 8) of one brick (for tests and tools)."""
    B = np.empty((8, 3))
    vol = volume_gradient(X, B)
    G = np.empty((4, 8))
    hourglass_shapes(X, B, vol, G)
    return G
