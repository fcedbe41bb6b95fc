"""The wall's energies now: the nodes' kinetic energies and momentum, the elements' works.

The terms of the energy balance of :mod:`._solver`; how each work is accumulated so that the
balance closes to round-off is in :mod:`._step`.
"""

import numpy as np
from numba import njit, prange

from impactdyn.wall._state import ERODED, W_HG, W_PLASTIC, W_Q, W_SIGMA
from impactdyn.wall._step import NODE_BLOCK, nodal_force, node_blocks, ordered_sum


@njit(parallel=True, cache=True)
def nodal_energy(nodes, elements, dt_full):
    """Kinetic energies and momentum of the nodes now (after an element pass).

    K = ½ Σ m |v^{n+½}|² (the one the work bookkeeping balances exactly, split into wall and
    orphan nodes by ``category``: 0 wall, 2 orphan) and the central-difference energy
    K× = ½ Σ m v^{n+½}·(v^{n+½} − Δt f/m) at t^{n+1} (without impulses due then), which with
    the elastic strain energy is conserved exactly by a linear system at a constant step.

    Returns (K, K_wall, K_orphan, K×, momentum (3,)).
    """
    # fields as local arrays before the parallel loop (:func:`._step._element_pass`)
    v, mass, free, category = nodes.v, nodes.mass, nodes.free, nodes.category
    F_flat, ptr, entry = elements.F_flat, elements.node_ptr, elements.node_entry
    n_nodes = v.shape[0]
    # per block of nodes: K, K_wall, K_orphan, K×, p_x, p_y, p_z (summed in a fixed order, :data:`._step.NODE_BLOCK`)
    sums = np.zeros((7, node_blocks(n_nodes)))
    for blk in prange(sums.shape[1]):
        kin = 0.0
        kin_wall = 0.0
        kin_orphan = 0.0
        kin_cross = 0.0
        px = 0.0
        py = 0.0
        pz = 0.0
        for n in range(blk * NODE_BLOCK, min(n_nodes, (blk + 1) * NODE_BLOCK)):
            f0, f1, f2 = nodal_force(F_flat, ptr, entry, n)
            m = mass[n]
            kh = 0.5 * m * (v[n, 0] ** 2 + v[n, 1] ** 2 + v[n, 2] ** 2)
            kin += kh
            kin_wall += kh if category[n] == 0 else 0.0
            kin_orphan += kh if category[n] == 2 else 0.0
            kin_cross += 0.5 * (v[n, 0] * (m * v[n, 0] - free[n, 0] * dt_full * f0)
                                + v[n, 1] * (m * v[n, 1] - free[n, 1] * dt_full * f1)
                                + v[n, 2] * (m * v[n, 2] - free[n, 2] * dt_full * f2))
            px += m * v[n, 0]
            py += m * v[n, 1]
            pz += m * v[n, 2]
        sums[0, blk] = kin
        sums[1, blk] = kin_wall
        sums[2, blk] = kin_orphan
        sums[3, blk] = kin_cross
        sums[4, blk] = px
        sums[5, blk] = py
        sums[6, blk] = pz
    return (ordered_sum(sums[0]), ordered_sum(sums[1]), ordered_sum(sums[2]), ordered_sum(sums[3]),
            np.array([ordered_sum(sums[4]), ordered_sum(sums[5]), ordered_sum(sums[6])]))


@njit(cache=True)
def energy_sums(elements):
    """Σ over live and over eroded elements of (W_σ, W_p, W_hg, W_q): two arrays (4,)."""
    es, flags = elements.es, elements.flags
    live = np.zeros(4)
    gone = np.zeros(4)
    for e in range(es.shape[0]):
        out = gone if flags[e, ERODED] != 0 else live
        out[0] += es[e, W_SIGMA]
        out[1] += es[e, W_PLASTIC]
        out[2] += es[e, W_HG]
        out[3] += es[e, W_Q]
    return live, gone
