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

* strain rate at the midstep configuration x^{n+½} = x^{n+1} − ½Δt^{n+½} v (FB; an exactly
  skew velocity gradient for a rigid rotation — the Hughes–Winget midpoint property — so a
  spinning element gains no strain)::

      L_ij = Σ_I v_iI b_iJ(x^{n+½}),   d = sym L,   Ω = skew L,   b = ∂V/∂x / V

* bulk viscosity on compression (Hallquist, LS-DYNA Theory Manual, "artificial bulk
  viscosity"; defaults Q1 = 1.5, Q2 = 0.06), ℓ = V^{1/3}::

      q = ρ ℓ (Q1 ℓ (tr d)² − Q2 c tr d)    if tr d < 0,   else 0

  (LS-DYNA's form: Q1 multiplies the quadratic term; DESIGN §9 writes Q1² there.)
* the material update of the element's model (:mod:`._mat13`, :mod:`._johnson_cook`)
  gives S^{n+1}, p^{n+1}, the sound speed c and the failure state;
* internal force with the end-of-step geometry, σ = S − (p + q) I::

      f_int,iI = σ_ij ∂V/∂x_jI = σ_ij b_jI V

* FB hourglass control with the shape vectors γ_α (:mod:`._hex`) and the hourglass
  velocities q̇_αi = Σ_I v_iI γ_αI::

      viscous   (LS-DYNA IHQ 2):  Q_αi = a_h q̇_αi,           a_h = QH ρ c V^{2/3} / 4
      stiffness (LS-DYNA IHQ 4):  Q_αi ← Q_αi + κ Δt q̇_αi,   κ = QH ρc² (Σ_iI B_iI²)/(3V) / 8
      f_hg,iI = Σ_α Q_αi γ_αI

  (the stiffness form is FB's, with their 1/√8-normalised γ folded into κ; QH = 0.1 is
  LS-DYNA's default coefficient);
* the element's stable step (Hallquist): Δt_e = L_e / (Q + √(Q² + c²)),
  Q = Q1 ℓ|tr d| + Q2 c on compression (0 otherwise), L_e = V/A_max.

The global step is Δt^{n+½} = (Courant factor) · min_e Δt_e.

Race-free nodal assembly: the element pass writes its 8 × 3 nodal forces into its own
rows F[e] (n_elements, 8, 3); the node pass then gathers, for each node, the rows listed
in the mesh's node → (element, corner) CSR map.  No two threads write the same memory in
either pass (no atomics, no colouring), the sum for a node is taken in a fixed order (the
result does not depend on the thread count), and both passes are plain ``prange`` loops.
The price is one extra write and read of 24 doubles per element, cheap next to the
element's arithmetic.

Energy bookkeeping (per element, in the state array, :mod:`._state`): the stress work
W_σ += ½(σⁿ + σⁿ⁺¹):d V̄Δt (elastic + plastic), the bulk-viscous work W_q += −q tr d V̄Δt,
the hourglass work W_hg += Q̄·q̇ Δt (Q̄ = Q for the viscous form, ½(Qⁿ + Qⁿ⁺¹) for the
stiffness form) and the plastic work W_p += σ_eq Δεₚ V̄.  Kinetic energy at t^n is the one
the central-difference scheme conserves with the trapezoidal work, ½ Σ m v^{n−½}·v^{n+½}
(exactly, for a linear system at a constant step).  The load's work is Σ I·½(v^{n−½} + v^{n+½})
over the loaded degrees of freedom (|I|²/2m for a node at rest).

Element failure and erosion: a failed element keeps what its model says (mat13: compressive
pressure only); it is eroded — its forces are zero from then on — when its model erodes
failed elements, when its volume becomes non-positive, or when its time step falls below
``erode_dt``.  A non-positive volume or a step below ``min_dt`` of an element that has not
failed is a breakdown: the element is marked in ``bad`` and the pass returns a non-zero
status (1: volume, 2: step, 3: non-finite force).
"""

from __future__ import annotations

import math

import numpy as np
from numba import get_thread_id, njit, prange

from impactdyn.wall._hex import hourglass_shapes, largest_face_area, volume_gradient
from impactdyn.wall._johnson_cook import KIND as JC_KIND
from impactdyn.wall._johnson_cook import jc_update
from impactdyn.wall._mat13 import KIND as MAT13_KIND
from impactdyn.wall._mat13 import mat13_update
from impactdyn.wall._state import (
    C, DT_E, ERODED, FAILED, P, P1_HG, P1_Q, P1_SIGMA, Q, VOL, W_HG, W_PLASTIC, W_Q, W_SIGMA)

#: Breakdown codes of :func:`element_pass`.
BAD_VOLUME, BAD_STEP, BAD_FORCE = 1, 2, 3

#: Columns of the clock array of :func:`advance`: time t^n, Δt^{n−½}, Δt^{n+½}, steps taken,
#: next deposition record, and Δt^{n−1} (the full step of the last node pass).
T_NOW, DT_PREV, DT_NEXT, STEPS, CURSOR, DT_FULL = range(6)

#: Columns of the accumulator array of :func:`advance`: load work, impulse applied to the wall
#: (x, y, z), impulse taken by the supports (x, y, z), largest rear-face outward velocity.
(A_LOAD_WORK, A_APPLIED, A_SUPPORT, A_REAR_VMAX) = (0, 1, 4, 7)
N_ACC = 8


@njit(cache=True, inline="always")
def _erase(F, es, e):
    """An eroded element: no forces, no step limit, no pending work."""
    for a in range(8):
        F[e, a, 0] = 0.0
        F[e, a, 1] = 0.0
        F[e, a, 2] = 0.0
    es[e, DT_E] = np.inf
    es[e, P1_SIGMA] = 0.0
    es[e, P1_Q] = 0.0
    es[e, P1_HG] = 0.0


@njit(parallel=True, cache=True)
def element_pass(x, v, conn, vol0, emass, S, es, flags, bad, Lbuf, Qhg, F, scratch, gam, qd, kind, mprm, table,
                 hg_stiffness, qh, q1, q2, erode_failed, erode_dt, min_dt, dt, dt_full_prev):
    """Stress update and nodal forces of every element over the half step Δt = ``dt`` (module docstring).

    x (n_nodes, 3) at the step's end, v (n_nodes, 3) the half-step velocities v^{n+½}; element
    state S, es, flags, Lbuf, Qhg (:mod:`._state`) updated in place; F (n_elements, 8, 3) holds
    the previous forces f^n on entry and receives f^{n+1} = f_int + f_hg.  ``dt_full_prev`` is
    Δt^n, the interval the previous forces acted over (their work is completed here).
    scratch (n_threads, 5, 8, 3), gam (n_threads, 4, 8) and qd (n_threads, 4, 3) are
    per-thread work space.  ``dt = 0`` computes the forces of the current state without
    updating it (the first step).

    Returns (status, min_e Δt_e): status 0, or the largest breakdown code (``bad`` marks the
    elements).
    """
    status = 0
    dtmin = np.inf
    for e in prange(conn.shape[0]):
        tid = get_thread_id()
        X = scratch[tid, 0]
        Xm = scratch[tid, 1]
        V = scratch[tid, 2]
        B = scratch[tid, 3]
        Bm = scratch[tid, 4]
        G = gam[tid]
        QD = qd[tid]
        if flags[e, ERODED] != 0:
            continue
        p2 = 0.0  # f^n · v^{n+½}: the second half of the previous forces' work
        for a in range(8):
            n = conn[e, a]
            for i in range(3):
                X[a, i] = x[n, i]
                V[a, i] = v[n, i]
                Xm[a, i] = x[n, i] - 0.5 * dt * v[n, i]
                p2 += F[e, a, i] * v[n, i]
        vol = volume_gradient(X, B)
        vmid = volume_gradient(Xm, Bm)
        half = 0.5 * dt_full_prev
        if not (vol > 0.0 and vmid > 0.0):
            es[e, W_SIGMA] += half * (es[e, P1_SIGMA] + es[e, P1_Q] + es[e, P1_HG] + p2)
            _erase(F, es, e)
            if flags[e, FAILED] != 0:
                flags[e, ERODED] = 1
            else:
                bad[e] = BAD_VOLUME
                status = max(status, BAD_VOLUME)
            continue
        # midstep velocity gradient L = Σ_I v_I ⊗ b_I
        for i in range(3):
            for j in range(3):
                s = 0.0
                for a in range(8):
                    s += V[a, i] * Bm[a, j]
                Lbuf[e, i, j] = s / vmid
        trd = Lbuf[e, 0, 0] + Lbuf[e, 1, 1] + Lbuf[e, 2, 2]
        # hourglass velocities q̇_αi = Σ_I γ_αI v_iI (end-of-step shape vectors)
        hourglass_shapes(X, B, vol, G)
        p2_hg = 0.0
        for al in range(4):
            for i in range(3):
                s = 0.0
                for a in range(8):
                    s += G[al, a] * V[a, i]
                QD[al, i] = s
                p2_hg += Qhg[e, al, i] * s
        # complete the work of the previous forces over Δt^n: ½Δt^n f^n·(v^{n−½} + v^{n+½}), split by kind
        p2_q = -es[e, Q] * vmid * trd
        es[e, W_SIGMA] += half * (es[e, P1_SIGMA] + p2 - p2_q - p2_hg)
        es[e, W_Q] += half * (es[e, P1_Q] + p2_q)
        es[e, W_HG] += half * (es[e, P1_HG] + p2_hg)
        # bulk viscosity and the material update
        rho = emass[e] / vol
        ell = np.cbrt(vol)
        q = 0.0
        if trd < 0.0:
            q = rho * ell * (q1 * ell * trd * trd - q2 * es[e, C] * trd)
        vbar = 0.5 * (es[e, VOL] + vol)
        if kind == MAT13_KIND:
            c, dw, dwp = mat13_update(e, Lbuf, dt, vbar, emass[e], rho, vol / vol0[e], q, S, es, flags, mprm)
        else:
            c, dw, dwp = jc_update(e, Lbuf, dt, vbar, emass[e], rho, q, S, es, flags, table, mprm)
        es[e, C] = c
        es[e, Q] = q
        es[e, VOL] = vol
        es[e, W_PLASTIC] += dwp
        # Flanagan–Belytschko hourglass forces f_hg,iI = Σ_α Q_αi γ_αI: the generalised forces Q first
        if hg_stiffness:
            bb = 0.0
            for a in range(8):
                bb += B[a, 0] * B[a, 0] + B[a, 1] * B[a, 1] + B[a, 2] * B[a, 2]
            coef = qh * rho * c * c * bb / (3.0 * vol) / 8.0 * dt
        else:
            coef = 0.25 * qh * rho * c * ell * ell
        p1_hg = 0.0
        for al in range(4):
            for i in range(3):
                qnew = (Qhg[e, al, i] if hg_stiffness else 0.0) + coef * QD[al, i]
                Qhg[e, al, i] = qnew
                p1_hg += qnew * QD[al, i]
        es[e, P1_HG] = p1_hg
        # nodal forces: f_iI = σ_ij B_jI (σ = S − p I), the bulk viscosity's −q B_iI, and f_hg,iI
        p = es[e, P]
        sxx, syy, szz = S[e, 0] - p, S[e, 1] - p, S[e, 2] - p
        sxy, syz, szx = S[e, 3], S[e, 4], S[e, 5]
        p1 = 0.0
        bv = 0.0
        for a in range(8):
            b0, b1, b2 = B[a, 0], B[a, 1], B[a, 2]
            f0 = sxx * b0 + sxy * b1 + szx * b2
            f1 = sxy * b0 + syy * b1 + syz * b2
            f2 = szx * b0 + syz * b1 + szz * b2
            p1 += f0 * V[a, 0] + f1 * V[a, 1] + f2 * V[a, 2]
            bv += b0 * V[a, 0] + b1 * V[a, 1] + b2 * V[a, 2]
            g0, g1, g2, g3 = G[0, a], G[1, a], G[2, a], G[3, a]
            F[e, a, 0] = f0 - q * b0 + Qhg[e, 0, 0] * g0 + Qhg[e, 1, 0] * g1 + Qhg[e, 2, 0] * g2 + Qhg[e, 3, 0] * g3
            F[e, a, 1] = f1 - q * b1 + Qhg[e, 0, 1] * g0 + Qhg[e, 1, 1] * g1 + Qhg[e, 2, 1] * g2 + Qhg[e, 3, 1] * g3
            F[e, a, 2] = f2 - q * b2 + Qhg[e, 0, 2] * g0 + Qhg[e, 1, 2] * g1 + Qhg[e, 2, 2] * g2 + Qhg[e, 3, 2] * g3
        es[e, P1_SIGMA] = p1
        es[e, P1_Q] = -q * bv
        # stable step
        qs = 0.0
        if trd < 0.0:
            qs = q1 * ell * abs(trd) + q2 * c
        dte = vol / largest_face_area(X) / (qs + math.sqrt(qs * qs + c * c))
        es[e, DT_E] = dte
        if flags[e, FAILED] != 0 and (erode_failed or dte < erode_dt):
            flags[e, ERODED] = 1
            _erase(F, es, e)
            continue
        if dte < min_dt:
            bad[e] = BAD_STEP
            status = max(status, BAD_STEP)
        if not math.isfinite(F[e, 0, 0] + F[e, 7, 1] + F[e, 4, 2] + dte):
            bad[e] = BAD_FORCE
            status = max(status, BAD_FORCE)
        dtmin = min(dtmin, dte)
    return status, dtmin


@njit(parallel=True, cache=True)
def node_pass(x, v, mass, free, pext, has_ext, Fflat, ptr, entry, rear, dt_full, dt_next):
    """Gather the nodal forces, kick and drift every node (module docstring).

    Fflat is F viewed as (8 n_elements, 3); ptr/entry the node → (element, corner) CSR map;
    free (n_nodes, 3) is 1.0 on free and 0.0 on fixed translations; pext (n_nodes, 3) the
    impulses due now (read only when ``has_ext``); rear (n_nodes,) marks the rear face.

    Returns (work of the impulses Σ I·½(v^{n−½} + v^{n+½}), largest rear-face v_y).
    """
    work = 0.0
    vrear = -np.inf
    for n in prange(x.shape[0]):
        f0 = 0.0
        f1 = 0.0
        f2 = 0.0
        for k in range(ptr[n], ptr[n + 1]):
            j = entry[k]
            f0 += Fflat[j, 0]
            f1 += Fflat[j, 1]
            f2 += Fflat[j, 2]
        m = mass[n]
        for d in range(3):
            f = f0 if d == 0 else (f1 if d == 1 else f2)
            vo = v[n, d]
            dv = -dt_full * f
            if has_ext:
                dv += pext[n, d]
            vn = vo + free[n, d] * dv / m
            if has_ext:
                work += pext[n, d] * 0.5 * (vo + vn)
            v[n, d] = vn
            x[n, d] += dt_next * vn
        if rear[n]:
            vrear = max(vrear, v[n, 1])
    return work, vrear


@njit(cache=True)
def _apply_loads(t, clock, rec_time, rec_ptr, rec_node, rec_weight, rec_imp, fixed, pext, acc):
    """Impulses of the records due at ``t`` into pext (free translations) or the support sum; True if any."""
    any_ = False
    c = int(clock[CURSOR])
    while c < rec_time.size and rec_time[c] <= t:
        for k in range(rec_ptr[c], rec_ptr[c + 1]):
            n = rec_node[k]
            w = rec_weight[k]
            for d in range(3):
                imp = w * rec_imp[c, d]
                if fixed[n, d]:
                    acc[A_SUPPORT + d] += imp
                else:
                    pext[n, d] += imp
                    acc[A_APPLIED + d] += imp
        any_ = True
        c += 1
    clock[CURSOR] = c
    return any_


@njit(cache=True)
def _clear_loads(c0, c1, rec_ptr, rec_node, pext):
    for c in range(c0, c1):
        for k in range(rec_ptr[c], rec_ptr[c + 1]):
            n = rec_node[k]
            pext[n, 0] = 0.0
            pext[n, 1] = 0.0
            pext[n, 2] = 0.0


@njit(cache=True)
def advance(t_stop, max_steps, clock, acc, x, v, mass, free, fixed, pext, rear, Fflat, ptr, entry, conn, vol0,
            emass, S, es, flags, bad, Lbuf, Qhg, F, scratch, gam, qd, kind, mprm, table, hg_stiffness, qh, q1, q2,
            courant, erode_failed, erode_dt, min_dt, rec_time, rec_ptr, rec_node, rec_weight, rec_imp):
    """Steps from t^n (element pass done) until t ≥ ``t_stop`` or ``max_steps`` steps (module docstring).

    Each step: loads due at t^n, node pass (kick to v^{n+½}, drift to x^{n+1}), t ← t^{n+1},
    element pass at t^{n+1}, next step Δt^{n+3/2} = courant · min Δt_e.  clock and acc
    (columns above) carry the time, steps, load cursor and the load/support sums between
    calls.  Returns (status, steps taken).
    """
    steps = 0
    while clock[T_NOW] < t_stop and steps < max_steps:
        c0 = int(clock[CURSOR])
        has_ext = _apply_loads(clock[T_NOW], clock, rec_time, rec_ptr, rec_node, rec_weight, rec_imp, fixed,
                               pext, acc)
        dt_full = 0.5 * (clock[DT_PREV] + clock[DT_NEXT])
        work, vrear = node_pass(x, v, mass, free, pext, has_ext, Fflat, ptr, entry, rear, dt_full, clock[DT_NEXT])
        if has_ext:
            _clear_loads(c0, int(clock[CURSOR]), rec_ptr, rec_node, pext)
        acc[A_LOAD_WORK] += work
        acc[A_REAR_VMAX] = max(acc[A_REAR_VMAX], vrear)
        clock[T_NOW] += clock[DT_NEXT]
        clock[DT_PREV] = clock[DT_NEXT]
        clock[DT_FULL] = dt_full
        status, dtmin = element_pass(x, v, conn, vol0, emass, S, es, flags, bad, Lbuf, Qhg, F, scratch, gam, qd,
                                     kind, mprm, table, hg_stiffness, qh, q1, q2, erode_failed, erode_dt, min_dt,
                                     clock[DT_PREV], dt_full)
        steps += 1
        clock[STEPS] += 1
        if status != 0:
            return status, steps
        clock[DT_NEXT] = courant * dtmin if math.isfinite(dtmin) else clock[DT_PREV]
    return 0, steps


@njit(parallel=True, cache=True)
def nodal_energy(v, mass, free, Fflat, ptr, entry, category, dt_full):
    """Kinetic energies and momentum of the nodes now (after an element pass).

    K = ½ Σ m |v^{n+½}|² (the one the work bookkeeping balances exactly, split into wall and
    orphan nodes by ``category``: 0 wall, 2 orphan) and the central-difference energy
    K× = ½ Σ m v^{n+½}·(v^{n+½} − Δt f/m) at t^{n+1} (without impulses due then), which with
    the elastic strain energy is conserved exactly by a linear system at a constant step.

    Returns (K, K_wall, K_orphan, K×, momentum (3,)).
    """
    kin = 0.0
    kin_wall = 0.0
    kin_orphan = 0.0
    kin_cross = 0.0
    px = 0.0
    py = 0.0
    pz = 0.0
    for n in prange(v.shape[0]):
        f0 = 0.0
        f1 = 0.0
        f2 = 0.0
        for k in range(ptr[n], ptr[n + 1]):
            j = entry[k]
            f0 += Fflat[j, 0]
            f1 += Fflat[j, 1]
            f2 += Fflat[j, 2]
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
    return kin, kin_wall, kin_orphan, kin_cross, np.array([px, py, pz])
