"""Explicit Lagrangian time step of the wall: element pass, node pass, loads, the step loop.

Central differences on a lumped-mass mesh with velocities at half steps (Belytschko, Liu &
Moran 2000, "BLM", Box 6.1; Hallquist, LS-DYNA Theory Manual)::

    a^n       = M⁻¹ (f_ext^n − f_int^n)
    v^{n+½}   = v^{n−½} + Δt^n a^n + M⁻¹ I^n,      Δt^n = ½(Δt^{n−½} + Δt^{n+½})
    x^{n+1}   = x^n + Δt^{n+½} v^{n+½}

I^n are the impulses of the deposition records due at t^n (:mod:`._load`), added to free
degrees of freedom only; fixed translations keep v = 0 and their share of an impulse goes
to the support (counted, :mod:`._solver`).

Element pass (one-point hexahedron, Flanagan & Belytschko, IJNME 17 (1981) 679, "FB";
:mod:`._hex` for the geometry), for element e at step n+1 with the nodal velocities
v = v^{n+½}:

* strain rate d = sym L and spin Ω = skew L from the midstep velocity gradient
  L = G (I − ½Δt G)⁻¹ of the element's uniform motion (:mod:`._kinematics`);
* bulk viscosity on compression (Hallquist, LS-DYNA Theory Manual, "artificial bulk
  viscosity"; defaults Q1 = 1.5, Q2 = 0.06)::

      q = ρ ℓ (Q1 ℓ (tr d)² − Q2 c tr d)    if tr d < 0,   else 0

  (LS-DYNA's form: Q1, not Q1², multiplies the quadratic term.)  The
  length ℓ is the element's characteristic length L_e = V/A_max, the one of the time step
  below: with ℓ = V^{1/3} a flat element (the report's are 0.16 × 0.079 × 0.16 cm) gets a
  quadratic viscosity (ℓ/L_e)² times stronger than its step allows, and a compression front
  through flat elements ran away (q grew without bound within 20 steps) — a one-dimensional
  column of 0.05 × 0.01 × 0.05 cm elements under a 4 GPa pulse, tests/wall/test_wave.py.
* the material update of the element's model — its own kernel,
  :attr:`impactdyn.wall.WallModel.update_kernel`, compiled into the pass by :func:`step_kernels`
  (:mod:`._mat13`, :mod:`._johnson_cook`) — gives S^{n+1}, p^{n+1}, the sound speed c and the
  failure state;
* internal force with the end-of-step geometry, σ = S − (p + q) I::

      f_int,iI = σ_ij ∂V/∂x_jI = σ_ij b_jI V

* hourglass forces Q_αi of the run's form (:mod:`._hourglass`: Flanagan–Belytschko viscous or
  stiffness, or assumed strain), f_hg,iI = Σ_α Q_αi γ_αI;
* the element's stable step (Hallquist): Δt_e = L_e / (Q + √(Q² + c²)),
  Q = Q1 L_e|tr d| + Q2 c on compression (0 otherwise), L_e = V/A_max.

The global step is Δt^{n+½} = (Courant factor) · min_e Δt_e.

Race-free nodal assembly: the element pass writes its 8 × 3 nodal forces into its own
rows F[e] (n_elements, 8, 3); the node pass then gathers, for each node, the rows listed
in the mesh's node → (element, corner) CSR map.  No two threads write the same memory in
either pass (no atomics, no colouring), the sum for a node is taken in a fixed order (the
result does not depend on the thread count), and both passes are plain ``prange`` loops.
The price is one extra write and read of 24 doubles per element, cheap next to the
element's arithmetic.

Energy bookkeeping, exact: the force f^n of an element acts over Δt^n, so its work is
Δt^n f^n·½(v^{n−½} + v^{n+½}).  The element pass that makes f^n knows v^{n−½} and stores the
first half's power P₁ = f^n·v^{n−½}, split by kind (stress σ = S − pI, bulk viscosity,
hourglass); the next pass, which sees v^{n+½} and still has f^n in F[e], adds
½Δt^n (P₁ + P₂) with P₂ = f^n·v^{n+½} to the element's works W_σ (elastic + plastic),
W_q and W_hg.  P₂ is exact in total; its split takes the bulk-viscous part as −qⁿ V̄ tr d and
the hourglass part as Qⁿ·q̇ with the current shape vectors (both a step's geometry change
off), the stress part as the rest.  With the kinetic energy ½ Σ m |v^{n+½}|² and the load's
work Σ I·½(v^{n−½} + v^{n+½}) (|I|²/2m on a node at rest), the balance
K + W_σ + W_q + W_hg = W_load closes to round-off (:mod:`._solver`).  The plastic work
W_p += σ_eq Δεₚ V̄ is kept beside, for the elastic/plastic split.  (The kinetic energy
½ Σ m v^{n−½}·v^{n+½} is the one the central-difference scheme conserves together with the
strain energy of a linear system, at a constant step; :func:`._diagnostics.nodal_energy` returns both.)

Element failure and erosion: a failed element keeps what its model says (mat13: compressive
pressure only); it is eroded — its forces are zero from then on — when its model erodes
failed elements, when its volume becomes non-positive, or when its time step falls below
``erode_dt``.  A non-positive volume or a step below ``min_dt`` of an element that has not
failed is a breakdown: the element is marked in ``bad`` and the pass returns a non-zero
status (1: volume, 2: step, 3: non-finite force).
"""

from __future__ import annotations

import functools
import math
from typing import Any, NamedTuple

import numpy as np
from numba import get_thread_id, njit, prange

from impactdyn._jitcache import bind_globals, in_package
from impactdyn.constitutive import von_mises
from impactdyn.wall._blocks import (
    R_B, R_BV, R_C, R_DTE, R_F, R_FLOW, R_G, R_LE, R_LM, R_OK, R_P1, R_P2, R_Q, R_QD, R_QN, R_RATIO, R_SHG, R_SIG,
    R_SPIN, R_TRD, R_V, R_VOL, R_X, block_column)
from impactdyn.wall._hex import BLOCK, characteristic_lengths, hourglass_shapes, volume_gradient
from impactdyn.wall._hourglass import (
    HG_ASSUMED_STRAIN, HG_STIFFNESS, assumed_strain_forces, flanagan_belytschko_forces, tangent_ratio)
from impactdyn.wall._kinematics import midstep_gradients, reciprocal_vectors, velocity_gradients
from impactdyn.wall._state import (
    C, DT_E, EPS_P, ERODED, FAILED, N_SHG, P, P1_HG, P1_Q, P1_SIGMA, Q, VOL, W_HG, W_PLASTIC, W_Q, W_SIGMA)

#: Breakdown codes of :func:`_element_pass`.
BAD_VOLUME, BAD_STEP, BAD_FORCE = 1, 2, 3

#: Columns of the clock array of :func:`_advance`: time t^n, Δt^{n−½}, Δt^{n+½}, steps taken,
#: next deposition record, and Δt^{n−1} (the full step of the last node pass).
T_NOW, DT_PREV, DT_NEXT, STEPS, CURSOR, DT_FULL = range(6)

#: Columns of the accumulator array of :func:`_advance`: load work, impulse applied to the wall
#: (x, y, z), impulse taken by the supports (x, y, z), largest rear-face outward velocity.
(A_LOAD_WORK, A_APPLIED, A_SUPPORT, A_REAR_VMAX) = (0, 1, 4, 7)
N_ACC = 8


@njit(cache=True, inline="always")
def _erase(F, es, Shg, e):
    """An eroded element: no forces, no step limit, no pending work, no hourglass stress."""
    if e // BLOCK < Shg.shape[0]:
        for c in range(Shg.shape[1]):
            Shg[e // BLOCK, c, e % BLOCK] = 0.0
    for a in range(8):
        F[e, a, 0] = 0.0
        F[e, a, 1] = 0.0
        F[e, a, 2] = 0.0
    es[e, DT_E] = np.inf
    es[e, P1_SIGMA] = 0.0
    es[e, P1_Q] = 0.0
    es[e, P1_HG] = 0.0


@njit(cache=True, error_model="numpy")
def nodal_forces(A):
    """The nodal forces (rows R_F + 8i + a) of the bricks of the block array A (module docstring)::

        f_iI = σ_ij B_jI − q B_iI + Σ_α Q_αi γ_αI        (σ = S − pI, B_jI = ∂V/∂x_jI)

    and, for the work bookkeeping, p1 = f_σ·v^{n+½} (row R_P1) and B·v^{n+½} (row R_BV).
    """
    for k in range(BLOCK):
        A[R_P1 * BLOCK + k] = 0.0
        A[R_BV * BLOCK + k] = 0.0
    for a in range(8):
        for k in range(BLOCK):
            sxx, syy, szz = A[R_SIG * BLOCK + k], A[(R_SIG + 1) * BLOCK + k], A[(R_SIG + 2) * BLOCK + k]
            sxy, syz, szx = A[(R_SIG + 3) * BLOCK + k], A[(R_SIG + 4) * BLOCK + k], A[(R_SIG + 5) * BLOCK + k]
            b0, b1, b2 = block_column(A, R_B, a, k)
            v0, v1, v2 = block_column(A, R_V, a, k)
            f0 = sxx * b0 + sxy * b1 + szx * b2
            f1 = sxy * b0 + syy * b1 + syz * b2
            f2 = szx * b0 + syz * b1 + szz * b2
            A[R_P1 * BLOCK + k] += f0 * v0 + f1 * v1 + f2 * v2
            A[R_BV * BLOCK + k] += b0 * v0 + b1 * v1 + b2 * v2
            q = A[R_Q * BLOCK + k]
            g0, g1, g2, g3 = (A[(R_G + a) * BLOCK + k], A[(R_G + 8 + a) * BLOCK + k],
                              A[(R_G + 16 + a) * BLOCK + k], A[(R_G + 24 + a) * BLOCK + k])
            A[(R_F + a) * BLOCK + k] = f0 - q * b0 + _hourglass_sum(A, 0, k, g0, g1, g2, g3)
            A[(R_F + 8 + a) * BLOCK + k] = f1 - q * b1 + _hourglass_sum(A, 1, k, g0, g1, g2, g3)
            A[(R_F + 16 + a) * BLOCK + k] = f2 - q * b2 + _hourglass_sum(A, 2, k, g0, g1, g2, g3)


@njit(cache=True, inline="always")
def _hourglass_sum(A, i, k, g0, g1, g2, g3):
    """Σ_α Q_αi γ_α of brick k of the block array A: component i of the hourglass force at the local
    node whose γ_α are g0 … g3."""
    return (A[(R_QN + i) * BLOCK + k] * g0 + A[(R_QN + 3 + i) * BLOCK + k] * g1
            + A[(R_QN + 6 + i) * BLOCK + k] * g2 + A[(R_QN + 9 + i) * BLOCK + k] * g3)


@njit(cache=True, error_model="numpy")
def stable_steps(A, q1, q2):
    """The stable step of the bricks of the block array A (row R_DTE; Hallquist, module docstring)::

        Δt_e = L_e / (Q + √(Q² + c²)),   Q = Q1 L_e |tr d| + Q2 c on compression (tr d < 0), else 0
    """
    for k in range(BLOCK):
        ell, c, trd = A[R_LE * BLOCK + k], A[R_C * BLOCK + k], A[R_TRD * BLOCK + k]
        qs = q1 * ell * abs(trd) + q2 * c if trd < 0.0 else 0.0
        A[R_DTE * BLOCK + k] = ell / (qs + math.sqrt(qs * qs + c * c))


def material_update(e, L, dt, vbar, mass, rho, vratio, q, S, es, flags, table, params):
    """The calling convention of a model's update kernel (:attr:`impactdyn.wall.WallModel.update_kernel`),
    which :func:`step_kernels` binds to this name in the element pass; never called itself.

    Element ``e``'s state S[e], es[e], flags[e] (:mod:`._state`) updated in place over ``dt``
    with its midstep velocity gradient L[e], mean volume ``vbar`` over the step, mass, density
    ``rho`` and volume ratio V/V₀ ``vratio`` at the step's end and bulk viscosity ``q``; the
    model's constants ``table``, ``params`` (:class:`._state.MaterialConstants`).  Returns (sound
    speed c, the element's work increment, its plastic work increment).
    """
    raise NotImplementedError("the element pass calls the model's update kernel (step_kernels)")


def _element_pass(nodes, elements, material, controls, blocks, dt, dt_full_prev):
    """Stress update and nodal forces of every element over the half step Δt = ``dt`` (module docstring).

    nodes.x (n_nodes, 3) at the step's end, nodes.v the half-step velocities v^{n+½}; element
    state S, es, flags, Lbuf, Qhg, Shg (:class:`._state.Elements`; Shg blocked,
    :func:`._blocks.hourglass_stress_array`) updated in place; F (n_elements, 8, 3) holds the
    previous forces f^n on entry and receives f^{n+1} = f_int + f_hg.  ``dt_full_prev`` is Δt^n,
    the interval the previous forces acted over (their work is completed here).
    ``controls.hg_form`` is one of HG_VISCOUS, HG_STIFFNESS, HG_ASSUMED_STRAIN (``qh``: the
    coefficient of the first two).  ``dt = 0`` computes the forces of the current state without
    updating it (the first step).  The material update is the model's kernel that
    :func:`step_kernels` compiled this pass with (:func:`material_update`).

    The elements are taken in blocks of :data:`BLOCK` (one block per parallel iteration), in the
    thread's row of ``blocks`` (n_threads, N_ROWS · BLOCK), :func:`._blocks.work_arrays`: the
    geometry, velocity gradients, hourglass velocities and forces of a block are computed in loops
    over its bricks that vectorise (rows R_X …, component-first, :mod:`._blocks`); the material
    update runs brick by brick.

    Returns (status, min_e Δt_e): status 0, or the largest breakdown code (``bad`` marks the
    elements).
    """
    # the records' fields as local arrays before the parallel loop: with numba 0.68, writes inside a
    # prange loop to an array reached through a NamedTuple field are lost (v[i] = … left v unchanged)
    x, v = nodes.x, nodes.v
    conn, vol0, emass, S, es, flags, bad, Lbuf, Qhg, Shg, F = (
        elements.conn, elements.vol0, elements.mass, elements.S, elements.es, elements.flags, elements.bad,
        elements.Lbuf, elements.Qhg, elements.Shg, elements.F)
    mprm, table, bulk, shear = material
    lam0 = bulk - 2.0 / 3.0 * shear     # Lamé's λ of the assumed-strain form
    hg_form, qh, q1, q2, erode_failed, erode_dt, min_dt = (
        controls.hg_form, controls.qh, controls.q1, controls.q2, controls.erode_failed, controls.erode_dt,
        controls.min_dt)
    ne = conn.shape[0]
    status = 0
    dtmin = np.inf
    half = 0.5 * dt_full_prev
    for blk in prange((ne + BLOCK - 1) // BLOCK):
        A = blocks[get_thread_id()]
        e0 = blk * BLOCK
        nb = min(BLOCK, ne - e0)
        # gather the block; p2 = f^n · v^{n+½}, the second half of the previous forces' work
        for k in range(nb):
            e = e0 + k
            p2 = 0.0
            for a in range(8):
                n = conn[e, a]
                for i in range(3):
                    vv = v[n, i]
                    A[(R_X + 8 * i + a) * BLOCK + k] = x[n, i]
                    A[(R_V + 8 * i + a) * BLOCK + k] = vv
                    p2 += F[e, a, i] * vv
            A[R_P2 * BLOCK + k] = p2
        # geometry at the step's end, velocity gradient and hourglass velocities
        volume_gradient(A)
        hourglass_shapes(A)
        if hg_form == HG_ASSUMED_STRAIN:
            reciprocal_vectors(A)
        velocity_gradients(A)
        midstep_gradients(A, 0.5 * dt)
        characteristic_lengths(A)
        # brick by brick: work of the previous forces, bulk viscosity, material, hourglass forces
        bstatus = 0
        for k in range(nb):
            e = e0 + k
            A[R_OK * BLOCK + k] = 0.0
            if flags[e, ERODED] != 0:
                continue
            vol = A[R_VOL * BLOCK + k]
            vbar = 0.5 * (es[e, VOL] + vol)
            p2 = A[R_P2 * BLOCK + k]
            if not (vol > 0.0 and vbar > 0.0):
                es[e, W_SIGMA] += half * (es[e, P1_SIGMA] + es[e, P1_Q] + es[e, P1_HG] + p2)
                _erase(F, es, Shg, e)
                if flags[e, FAILED] != 0:
                    flags[e, ERODED] = 1
                else:
                    bad[e] = BAD_VOLUME
                    bstatus = max(bstatus, BAD_VOLUME)
                continue
            for r in range(9):
                Lbuf[e, r // 3, r % 3] = A[(R_LM + r) * BLOCK + k]
            trd = Lbuf[e, 0, 0] + Lbuf[e, 1, 1] + Lbuf[e, 2, 2]
            # complete the work of the previous forces over Δt^n: ½Δt^n f^n·(v^{n−½} + v^{n+½}), by kind
            p2_hg = 0.0
            for al in range(4):
                for i in range(3):
                    p2_hg += Qhg[e, al, i] * A[(R_QD + 3 * al + i) * BLOCK + k]
            p2_q = -es[e, Q] * vbar * trd
            es[e, W_SIGMA] += half * (es[e, P1_SIGMA] + p2 - p2_q - p2_hg)
            es[e, W_Q] += half * (es[e, P1_Q] + p2_q)
            es[e, W_HG] += half * (es[e, P1_HG] + p2_hg)
            # bulk viscosity and the material update
            rho = emass[e] / vol
            ell = A[R_LE * BLOCK + k]
            q = 0.0
            if trd < 0.0:
                q = rho * ell * (q1 * ell * trd * trd - q2 * es[e, C] * trd)
            seq_old = von_mises(S, e) if hg_form == HG_ASSUMED_STRAIN else 0.0  # for the tangent ratio only
            eps_p_old = es[e, EPS_P]
            c, dw, dwp = material_update(e, Lbuf, dt, vbar, emass[e], rho, vol / vol0[e], q, S, es, flags, table,
                                         mprm)
            es[e, C] = c
            es[e, Q] = q
            es[e, VOL] = vol
            A[R_C * BLOCK + k] = c
            A[R_TRD * BLOCK + k] = trd
            es[e, W_PLASTIC] += dwp
            # generalised hourglass forces Q_αi: the viscous force or the stiffness form's increment here,
            # the assumed-strain form's forces for the whole block below
            if hg_form == HG_ASSUMED_STRAIN:
                seq = von_mises(S, e)
                ratio = tangent_ratio(seq_old, seq, es[e, EPS_P] - eps_p_old, shear)
                A[R_RATIO * BLOCK + k] = ratio
                A[R_FLOW * BLOCK + k] = seq if ratio < 1.0 else np.inf
                A[R_SPIN * BLOCK + k] = 0.5 * dt * (Lbuf[e, 0, 1] - Lbuf[e, 1, 0])
                A[(R_SPIN + 1) * BLOCK + k] = 0.5 * dt * (Lbuf[e, 1, 2] - Lbuf[e, 2, 1])
                A[(R_SPIN + 2) * BLOCK + k] = 0.5 * dt * (Lbuf[e, 0, 2] - Lbuf[e, 2, 0])
            else:
                flanagan_belytschko_forces(A, k, hg_form, qh, rho, c, vol, dt)
            p = es[e, P]
            A[R_SIG * BLOCK + k] = S[e, 0] - p
            A[(R_SIG + 1) * BLOCK + k] = S[e, 1] - p
            A[(R_SIG + 2) * BLOCK + k] = S[e, 2] - p
            A[(R_SIG + 3) * BLOCK + k] = S[e, 3]
            A[(R_SIG + 4) * BLOCK + k] = S[e, 4]
            A[(R_SIG + 5) * BLOCK + k] = S[e, 5]
            A[R_Q * BLOCK + k] = q
            A[R_OK * BLOCK + k] = 1.0
        if hg_form == HG_ASSUMED_STRAIN:
            # the block's stored stresses in, its forces and stresses updated, the stresses of live bricks out
            for k in range(nb):
                if A[R_OK * BLOCK + k] == 0.0:  # eroded: a harmless state for the vectorised arithmetic, not stored
                    A[R_RATIO * BLOCK + k] = 1.0
                    A[R_FLOW * BLOCK + k] = np.inf
                    for m in range(3):
                        A[(R_SPIN + m) * BLOCK + k] = 0.0
            for c in range(N_SHG):
                for k in range(nb):
                    A[(R_SHG + c) * BLOCK + k] = Shg[blk, c, k]
            assumed_strain_forces(A, dt, lam0, shear)
            for c in range(N_SHG):
                for k in range(nb):
                    if A[R_OK * BLOCK + k] != 0.0:
                        Shg[blk, c, k] = A[(R_SHG + c) * BLOCK + k]
        # the hourglass forces kept (the stiffness form's running sum) and their power on v^{n+½}
        for k in range(nb):
            if A[R_OK * BLOCK + k] == 0.0:
                continue
            e = e0 + k
            p1_hg = 0.0
            for al in range(4):
                for i in range(3):
                    r = 3 * al + i
                    qnew = (Qhg[e, al, i] if hg_form == HG_STIFFNESS else 0.0) + A[(R_QN + r) * BLOCK + k]
                    Qhg[e, al, i] = qnew
                    A[(R_QN + r) * BLOCK + k] = qnew
                    p1_hg += qnew * A[(R_QD + r) * BLOCK + k]
            es[e, P1_HG] = p1_hg
        nodal_forces(A)
        stable_steps(A, q1, q2)
        # store the forces and the stable step, erosion and breakdown checks
        bmin = np.inf
        for k in range(nb):
            if A[R_OK * BLOCK + k] == 0.0:
                continue
            e = e0 + k
            for a in range(8):
                for i in range(3):
                    F[e, a, i] = A[(R_F + 8 * i + a) * BLOCK + k]
            es[e, P1_SIGMA] = A[R_P1 * BLOCK + k]
            es[e, P1_Q] = -A[R_Q * BLOCK + k] * A[R_BV * BLOCK + k]
            dte = A[R_DTE * BLOCK + k]
            es[e, DT_E] = dte
            if flags[e, FAILED] != 0 and (erode_failed or dte < erode_dt):
                flags[e, ERODED] = 1
                _erase(F, es, Shg, e)
                continue
            if dte < min_dt:
                bad[e] = BAD_STEP
                bstatus = max(bstatus, BAD_STEP)
            if not math.isfinite(A[R_F * BLOCK + k] + A[(R_F + 23) * BLOCK + k] + A[(R_F + 12) * BLOCK + k] + dte):
                bad[e] = BAD_FORCE
                bstatus = max(bstatus, BAD_FORCE)
            bmin = min(bmin, dte)
        status = max(status, bstatus)
        dtmin = min(dtmin, bmin)
    return status, dtmin


@njit(cache=True, inline="always")
def nodal_force(F_flat, ptr, entry, n):
    """The force on node ``n``: the sum of its elements' corner forces (node → (element, corner)
    CSR map ``ptr``/``entry`` into F_flat (8 n_elements, 3), :class:`._state.Elements`), as (f_x, f_y, f_z)."""
    f0 = 0.0
    f1 = 0.0
    f2 = 0.0
    for k in range(ptr[n], ptr[n + 1]):
        j = entry[k]
        f0 += F_flat[j, 0]
        f1 += F_flat[j, 1]
        f2 += F_flat[j, 2]
    return f0, f1, f2


#: Nodes one parallel iteration of a pass over the nodes takes, in order (:func:`node_pass`,
#: :func:`._diagnostics.nodal_energy`): a sum over the nodes is the ordered sum of the blocks' ordered
#: partial sums, the same whatever the thread count (a prange reduction adds each thread's share, and
#: the shares move with the threads), so a run's numbers do not depend on the cores it ran on.
NODE_BLOCK = 4096


@njit(cache=True)
def node_blocks(n_nodes):
    """The number of blocks of :data:`NODE_BLOCK` nodes that cover ``n_nodes``."""
    return (n_nodes + NODE_BLOCK - 1) // NODE_BLOCK


@njit(cache=True)
def ordered_sum(values):
    """Σ values, added first to last (:data:`NODE_BLOCK`)."""
    total = 0.0
    for value in values:
        total += value
    return total


@njit(parallel=True, cache=True)
def node_pass(nodes, elements, has_ext, dt_full, dt_next):
    """Gather the nodal forces, kick and drift every node (module docstring).

    The impulses nodes.pext are read only when ``has_ext``.  Returns (work of the impulses
    Σ I·½(v^{n−½} + v^{n+½}), summed by blocks of :data:`NODE_BLOCK`; largest rear-face v_y).
    """
    # fields as local arrays before the parallel loop (:func:`_element_pass`)
    x, v, mass, free, pext, rear = nodes.x, nodes.v, nodes.mass, nodes.free, nodes.pext, nodes.rear
    F_flat, ptr, entry = elements.F_flat, elements.node_ptr, elements.node_entry
    n_nodes = x.shape[0]
    work = np.zeros(node_blocks(n_nodes))
    vrear = np.full(work.size, -np.inf)
    for blk in prange(work.size):
        block_work = 0.0
        block_vrear = -np.inf
        for n in range(blk * NODE_BLOCK, min(n_nodes, (blk + 1) * NODE_BLOCK)):
            f0, f1, f2 = nodal_force(F_flat, ptr, entry, n)
            m = mass[n]
            for d in range(3):
                f = f0 if d == 0 else (f1 if d == 1 else f2)
                vo = v[n, d]
                dv = -dt_full * f
                if has_ext:
                    dv += pext[n, d]
                vn = vo + free[n, d] * dv / m
                if has_ext:
                    block_work += pext[n, d] * 0.5 * (vo + vn)
                v[n, d] = vn
                x[n, d] += dt_next * vn
            if rear[n]:
                block_vrear = max(block_vrear, v[n, 1])
        work[blk] = block_work
        vrear[blk] = block_vrear
    return ordered_sum(work), vrear.max()


@njit(cache=True)
def _apply_loads(t, clock, acc, loads, nodes):
    """Impulses of the records due at ``t`` into nodes.pext (free translations) or the support sum;
    True if any."""
    any_ = False
    c = int(clock[CURSOR])
    while c < loads.time.size and loads.time[c] <= t:
        s = loads.stencil[c]
        for k in range(loads.ptr[s], loads.ptr[s + 1]):
            n = loads.node[k]
            w = loads.weight[k]
            for d in range(3):
                imp = w * loads.impulse[c, d]
                if nodes.fixed[n, d]:
                    acc[A_SUPPORT + d] += imp
                else:
                    nodes.pext[n, d] += imp
                    acc[A_APPLIED + d] += imp
        any_ = True
        c += 1
    clock[CURSOR] = c
    return any_


@njit(cache=True)
def _clear_loads(c0, c1, loads, pext):
    """Zero the impulses of records c0 … c1 − 1 in pext."""
    for c in range(c0, c1):
        s = loads.stencil[c]
        for k in range(loads.ptr[s], loads.ptr[s + 1]):
            n = loads.node[k]
            pext[n, 0] = 0.0
            pext[n, 1] = 0.0
            pext[n, 2] = 0.0


def _advance(t_stop, max_steps, clock, acc, nodes, elements, material, controls, loads, blocks):
    """Steps from t^n (element pass done) until t ≥ ``t_stop`` or ``max_steps`` steps (module docstring).

    Each step: loads due at t^n, node pass (kick to v^{n+½}, drift to x^{n+1}), t ← t^{n+1},
    element pass at t^{n+1}, next step Δt^{n+3/2} = courant · min Δt_e.  clock and acc
    (columns above) carry the time, steps, load cursor and the load/support sums between
    calls.  Returns (status, steps taken).
    """
    steps = 0
    while clock[T_NOW] < t_stop and steps < max_steps:
        c0 = int(clock[CURSOR])
        has_ext = _apply_loads(clock[T_NOW], clock, acc, loads, nodes)
        dt_full = 0.5 * (clock[DT_PREV] + clock[DT_NEXT])
        work, vrear = node_pass(nodes, elements, has_ext, dt_full, clock[DT_NEXT])
        if has_ext:
            _clear_loads(c0, int(clock[CURSOR]), loads, nodes.pext)
        acc[A_LOAD_WORK] += work
        acc[A_REAR_VMAX] = max(acc[A_REAR_VMAX], vrear)
        clock[T_NOW] += clock[DT_NEXT]
        clock[DT_PREV] = clock[DT_NEXT]
        clock[DT_FULL] = dt_full
        status, dtmin = _element_pass(nodes, elements, material, controls, blocks, clock[DT_PREV], dt_full)
        steps += 1
        clock[STEPS] += 1
        if status != 0:
            return status, steps
        clock[DT_NEXT] = controls.courant * dtmin if math.isfinite(dtmin) else clock[DT_PREV]
    return 0, steps


class StepKernels(NamedTuple):
    """The compiled element pass and step loop of one material update kernel (:func:`step_kernels`)."""

    element_pass: Any
    advance: Any


@functools.cache
def step_kernels(update) -> StepKernels:
    """:func:`_element_pass` and :func:`_advance` compiled for the model update kernel ``update``
    (an ``@njit`` function with the convention of :func:`material_update`; a model's
    :attr:`~impactdyn.wall.WallModel.update_kernel`), once per process and kernel.

    The update is bound as a global of the compiled code, not passed as an argument or closed
    over: numba keys a cached kernel by its argument types, and a closure by its pickled cells,
    and both carry the update's dispatcher, whose identity (a uuid when pickled) is new in every
    process, so their cache never hits (and grows a file per run).  A copy of the template with
    its own globals is keyed by its code alone; its qualified name, which names numba's cache
    file, carries the update's module and name, so each update kernel has a file of its own.  The cache is stamped with the digest of every impactdyn source
    (:mod:`impactdyn._jitcache`), so an edit of a model's update recompiles its pass; a kernel
    from outside the package would not be covered by that stamp, so its pass is not cached (nor that of an
    update whose ``cacheable`` attribute is false: a package kernel with a plug-in's code bound in,
    :func:`impactdyn.wall._johnson_cook.jc_kernel`).
    """
    cache = in_package(update.py_func.__code__.co_filename) and getattr(update, "cacheable", True)
    # no fused multiply-adds (fastmath 'contract'): with them the kernels compiled in a process and the same
    # kernels loaded from numba's cache fused differently, and a run's numbers moved with the cache's state
    # (tests/wall/test_reproducible.py; benchmarks/BENCHMARKS.md, "Reproducible bit for bit")
    name = f"{update.py_func.__module__}.{update.py_func.__qualname__}"
    element_pass = njit(parallel=True, cache=cache, error_model="numpy")(
        bind_globals(_element_pass, name, material_update=update))
    advance = njit(cache=cache)(bind_globals(_advance, name, _element_pass=element_pass))
    return StepKernels(element_pass, advance)
