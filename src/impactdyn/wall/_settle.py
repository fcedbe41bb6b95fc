"""After the run: let the wall swing back, bring it to rest by kinetic damping and measure its
permanent bulge (:func:`settle`).

1. The rebound: the run's own steps (no load left, bulk viscosity and Courant factor as in
   the run) go on until the wall has swung back from its outward deflection and turns
   outward again — until its momentum along y (outward), having been negative, turns
   positive (past :data:`SWING_HYSTERESIS` of its largest magnitude each way, so that the
   higher modes' flicker about zero at a turning point does not count).  The plastic work
   of the rest of the first swing and the reverse yielding of the rebound are computed, as
   the run computes them.  Without this phase the first reset came at the run's end, where
   the kinetic energy of a wall still swinging out is falling: it took away the energy of
   the swing's remaining plastic work (a clamped plate settled from 3 µs, mid-swing, kept
   0.059 cm against the 0.105 about which it rings once yielding is over; settled at its
   first turning point, 0.109, +4 %, the rebound's reverse yielding missed; after the
   rebound 0.1045, −0.4 %, from any start in the first swing; tests/wall/test_ending.py).
2. Kinetic damping (Cundall 1976; Barnes, Int. J. Space Structures 14 (1999) 89, "form
   finding and analysis of tension structures by dynamic relaxation"): the steps go on;
   whenever the kinetic energy of the wall nodes passes a peak (a rise, then a fall), every
   wall node's velocity is set to zero.  Each reset removes the energy of the motion then
   dominant, so the wall creeps to static equilibrium with its plastic state (further
   yielding on the way is computed as usual) without a damping constant.  It stops at a
   reset where the wall is in equilibrium (``settled``): the out-of-balance force on its
   free nodes below ``settle_tolerance`` of the element forces that balance there (norms
   over the nodes and over the elements' corners, :func:`force_balance`; the
   latter the largest seen at a reset, so that a wall springing back to no stress at all
   settles too).  Not on the kinetic energy: after 7a's rebound the first peak came from
   a local mode (6e-4 of it three resets later, bulge 0.373 cm), and the plate's bending
   mode, slower, then rose to 5 times it and carried the bulge to 0.657 cm.

Reverse yielding in later swings is left out: a wall at rest after one swing out and back
is the model's permanent shape.  Both phases together take at most ``max_settle_steps``
steps (else ``settled`` is false).  The energy balance is not kept through it: call it
after the run's measures are taken.  The damping steps take a Courant factor of at most
:data:`SETTLE_COURANT`: the positions are not moved back to the peak (the stresses are
incremental and would no longer match them), so a mode of frequency ω whose kinetic energy
peaks every second step is reset every third, and each such cycle multiplies its amplitude
by |1 − 6θ² + 5θ⁴ − θ⁶|, θ = Δt ω (central differences, from rest), more than 1 for
θ > 0.78: at the run's factor 0.9, where θ reaches ~1.8, a wall of a few elements drifted
away instead of settling.  The bulk viscosity is off while damping: on the way to rest it
only turned each reset's motion into heat, which the Mie–Grüneisen pressure turned into an
expansion the resets then kept.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np
from numba import njit, prange

from impactdyn.wall._diagnostics import nodal_energy
from impactdyn.wall._options import WallSolverError
from impactdyn.wall._step import DT_NEXT, NODE_BLOCK, nodal_force, node_blocks, ordered_sum
from impactdyn.wall._verdict import WALL

#: The largest Courant factor of the damping steps (module docstring): central differences
#: are stable at the run's factor 0.9, so Δt_e ω_max < 2/0.9 and at 0.35 θ = Δt ω_max < 0.78.
SETTLE_COURANT = 0.35

#: A swing of the wall turns (the rebound, module docstring) when its momentum along y has
#: passed this fraction of its largest magnitude in the other direction.
SWING_HYSTERESIS = 0.05


def settle(solver, progress: Callable[[float, float], None] | None = None) -> dict[str, Any]:
    """Let the wall of ``solver`` (a :class:`impactdyn.wall.WallSolver` after its run) swing back and
    come to rest, and measure its permanent bulge (module docstring).

    ``progress(done, 1)`` is called at the start, at every reset and at the end, with ``done``
    how far the out-of-balance force has come from the first reset's to the tolerance (on a
    log scale).

    Returns ``permanent_rear_bulge_cm`` (the largest outward u_y of a rear-face wall node at
    rest), ``settled``, ``settle_steps`` (both phases), ``rebound_end_us`` (the time phase 1
    ended) and ``settle_resets``.  A breakdown of the solver on the way (the wall's free swing
    goes on far past the run) does not raise: the run's own measures stand, and
    ``permanent_rear_bulge_cm`` is None with the message in ``settle_error``.
    """
    report = progress if progress is not None else (lambda done, total: None)
    report(0.0, 1.0)
    first_step = solver.steps
    try:
        out = _damp(solver, report)
    except WallSolverError as err:  # the run's measures stand; only the permanent bulge is lost
        out = {"permanent_rear_bulge_cm": None, "settled": False, "settle_steps": solver.steps - first_step,
               "rebound_end_us": None, "settle_resets": None, "settle_error": str(err)}
    report(1.0, 1.0)
    return out


def _damp(solver, report: Callable[[float, float], None]) -> dict[str, Any]:
    """The two phases of :func:`settle`: the rebound, then kinetic damping."""
    o = solver.options
    steps = rebound(solver, o.max_settle_steps)
    rebound_end = solver.time
    solver.clock[DT_NEXT] *= min(o.courant, SETTLE_COURANT) / o.courant
    solver.update_categories()
    last = _wall_kinetic(solver)
    rising = False
    resets = 0
    largest = 0.0
    first_ratio = None
    settled = last == 0.0 and steps < o.max_settle_steps
    while not settled and steps < o.max_settle_steps:
        solver.advance(math.inf, 1, settling=True)
        steps += 1
        k = _wall_kinetic(solver)
        if rising and k < last:          # a peak has passed: stop every wall node
            solver.update_categories()
            solver.v[solver.category == WALL] = 0.0
            resets += 1
            k = 0.0
            residual, corners = force_balance(solver.nodes, solver.elements)
            largest = max(largest, corners)
            settled = residual <= o.settle_tolerance ** 2 * largest
            ratio = math.sqrt(residual / largest) if largest > 0.0 else 0.0
            first_ratio = ratio if first_ratio is None else first_ratio
            if 0.0 < ratio < first_ratio and first_ratio > o.settle_tolerance:
                report(min(1.0, math.log(first_ratio / ratio) / math.log(first_ratio / o.settle_tolerance)), 1.0)
        rising = k > last
        last = k
    bulge, _ = solver.surface()
    return {"permanent_rear_bulge_cm": bulge, "settled": bool(settled), "settle_steps": steps,
            "rebound_end_us": rebound_end, "settle_resets": resets}


def rebound(solver, max_steps: int) -> int:
    """Phase 1 of :func:`settle`: step until the wall's outward momentum turns from negative to
    positive; returns the steps taken."""
    swing = 0.0          # sign of the current swing: +1 out, −1 back, 0 not yet known
    largest = 0.0
    steps = 0
    solver.update_categories()
    if _wall_kinetic(solver) == 0.0:  # at rest already: no swing to finish
        return 0
    while steps < max_steps:
        p = wall_momentum_y(solver.nodes)
        largest = max(largest, abs(p))
        if abs(p) > SWING_HYSTERESIS * largest:
            if swing < 0.0 < p:
                break
            swing = math.copysign(1.0, p)
        solver.advance(math.inf, 1)
        steps += 1
        solver.update_categories()
    return steps


def _wall_kinetic(solver) -> float:
    """½ Σ m |v|² over the wall nodes (category WALL), now."""
    return float(nodal_energy(solver.nodes, solver.elements, 0.0)[1])


@njit(cache=True)
def wall_momentum_y(nodes):
    """Σ m v_y over the wall nodes (``category`` 0): the wall's outward momentum (:func:`settle`).

    Called every step of the rebound: a loop over the nodes instead of ``mass[wall] @ v[wall, 1]``, which
    copied both masked arrays each step (0.2 ms against a step's ~2 ms on the report's wall).
    """
    mass, v, category = nodes.mass, nodes.v, nodes.category
    p = 0.0
    for n in range(mass.shape[0]):
        if category[n] == 0:
            p += mass[n] * v[n, 1]
    return p


@njit(parallel=True, cache=True)
def force_balance(nodes, elements):
    """How far the wall is from static equilibrium (:func:`settle`).

    Returns (Σ f_i² over the free translations of the wall nodes (``category`` 0) — the
    out-of-balance force, squared — and Σ F_ea,i² over every element corner: the element forces
    that balance each other at rest).
    """
    # fields as local arrays before the parallel loops (:func:`._step._element_pass`)
    free, category = nodes.free, nodes.category
    F_flat, ptr, entry = elements.F_flat, elements.node_ptr, elements.node_entry
    # summed by blocks in a fixed order, the same whatever the thread count (:data:`._step.NODE_BLOCK`)
    n_nodes, n_corners = free.shape[0], F_flat.shape[0]
    residual = np.zeros(node_blocks(n_nodes))
    for blk in prange(residual.size):
        block = 0.0
        for n in range(blk * NODE_BLOCK, min(n_nodes, (blk + 1) * NODE_BLOCK)):
            if category[n] == 0:
                f0, f1, f2 = nodal_force(F_flat, ptr, entry, n)
                block += free[n, 0] * f0 * f0 + free[n, 1] * f1 * f1 + free[n, 2] * f2 * f2
        residual[blk] = block
    corners = np.zeros(node_blocks(n_corners))
    for blk in prange(corners.size):
        block = 0.0
        for j in range(blk * NODE_BLOCK, min(n_corners, (blk + 1) * NODE_BLOCK)):
            block += F_flat[j, 0] ** 2 + F_flat[j, 1] ** 2 + F_flat[j, 2] ** 2
        corners[blk] = block
    return ordered_sum(residual), ordered_sum(corners)
