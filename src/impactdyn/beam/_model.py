"""Equations of motion of the hub–beam system (docs/theory/beam.md, eqs. (4), (5); the 1988 report, listing EQNS).

Coordinates: hub angle θ and modal amplitudes q₁…qₙ of ``w(x,t) = Σ φᵢ(x/L) qᵢ(t)``.
The state vector used everywhere (shape ``(2n + 7,)``)::

    y = [θ, q₁…qₙ, θ̇, q̇₁…q̇ₙ, W_τ, D_joint, D_modal, W_contact, I_contact]

where the last five are running integrals: work of the torque ∫τθ̇, joint-damping
loss ∫cθ̇², modal-damping loss ∫Σcᵢq̇ᵢ², work of the contact force ∫F_c J_F·v, and
its impulse ∫F_c dt (impulsive impacts add their jumps separately). ẋ = [θ̇, q̇] below.

**Kinematics.** x is the arc length from the root, e_r the hub radius through the root
and e_t its normal, both turning with θ. The inextensible beam's point x sits at
r = (A + x + u) e_r + w e_t, where (1 + u')² + w'² = 1 gives the foreshortening

    u(x) = −½ ∫₀ˣ w'² dη + u₄ + O(w⁶) = −(1/2L) Σⱼₖ Sⱼₖ(ξ) qⱼqₖ + u₄,   Sⱼₖ(ξ) = ∫₀^ξ φⱼ'φₖ' dη

(Kane, Ryan & Banerjee, J. Guidance 10 (1987) 139; primes on φ are d/dξ, ξ = x/L;
S and the integrals c, e, f, d below are in ``_modes``), and its velocity is
ṙ = (u̇ − θ̇w) e_r + (ẇ + θ̇(A + x + u)) e_t. The kinetic energy uses u to second order;
u₄ = −⅛∫₀ˣ w'⁴ enters the gravity potential only (*Order*, below).

**Kinetic energy.** T = ½J_h θ̇² + ½∫ρ|ṙ|² dx = ½ ẋᵀ M(q) ẋ, M the Gram matrix of the
velocity fields ∂ṙ/∂θ̇ = (A + x + u) e_t − w e_r and ∂ṙ/∂q̇ᵢ = φᵢ e_t − sᵢ e_r
(sᵢ = −∂u/∂qᵢ = Σₖ Sᵢₖqₖ/L)::

    M₀₀ = J₀ + qᵀPq + ¼ qᵀΨ(q)q,        J₀ = ρL(A² + AL + L²/3)(1 + IR),
    M₀ᵢ = M₀ᵢ⁰ + Σⱼₖ (Cⱼᵢₖ − ½Cᵢⱼₖ) qⱼqₖ,   M₀ᵢ⁰ = ρL(L aᵢ + A bᵢ),
    Mᵢⱼ = ρL δᵢⱼ + Ψᵢⱼ(q),               Ψₐᵦ(q) = Σₖₗ Eₐₖᵦₗ qₖqₗ,

with P = ρL I − G, G = ρL k + ρA h, C = ρc (kg/m) and E = (ρ/L)e (kg/m²). In powers of
the deflection: T₂ = ½θ̇² qᵀPq (∫ρ(w² + 2(A + x)u)), T₃ = θ̇ q̇ᵀ(M₀ − M₀⁰) (∫ρθ̇(ẇu − wu̇):
the foreshortened moment arm), T₄ = ½∫ρ(u̇² + θ̇²u²) (the foreshortening's own motion).

**Potential energy.** Bending of the inextensible beam, curvature w''/√(1 − w'²)
(Crespo da Silva & Glynn, J. Struct. Mech. 6 (1978) 437), and gravity along −e(π/2),
ρg∫[(A + x + u) sin θ + w cos θ] dx with u to fourth order (u₄ = −⅛∫₀ˣ w'⁴)::

    V = ½ Σ Kᵢqᵢ² + ¼ Σᵢⱼₖₗ Fᵢⱼₖₗ qᵢqⱼqₖqₗ + ρg[L(A + L/2) sin θ + L cos θ bᵀq − ½ sin θ qᵀhq]
        − ¼ sin θ Σᵢⱼₖₗ Dᵢⱼₖₗ qᵢqⱼqₖqₗ,

Kᵢ = EIβᵢ⁴/L³, F = (2EI/L⁵) f from ½EI∫w''²(1 + w'²) dx, D = (ρg/2L²) d from
ρg sin θ ∫u₄ dx (ρ∫u dx = −½ρ qᵀhq − (ρ/8L²) Σ dᵢⱼₖₗ qᵢqⱼqₖqₗ).

**Linearised model** (default, the listing's EQNS): M = M(0) and, of all the above,
only the centrifugal term θ̇²(Pq)ᵢ of ∂T₂/∂qᵢ::

    M(0) [θ̈; q̈] = Q,
    Q₀ = τ(t) − c θ̇ − ρLg(A + L/2) cos θ + F_c (A + x_p),
    Qᵢ = −Kᵢ qᵢ + θ̇² (Pq)ᵢ − 2ζᵢ√(KᵢρL) q̇ᵢ − ρLg bᵢ cos θ + F_c φᵢ(x_p/L).

Its arrow-shaped mass matrix [[J₀, M₀⁰ᵀ], [M₀⁰, ρL I]] is solved in O(n) by its Schur
complement s = J₀ − |M₀⁰|²/ρL.

**Coupled model** (``coupled = true``): Lagrange's equations of T − V,

    M(q) ẍ = Q − h + [ρg(½ cos θ qᵀhq + L sin θ bᵀq) + ¼ cos θ qᵀΔq;
                      ρg sin θ (hq)ᵢ + sin θ (Δq)ᵢ − (Φq)ᵢ],
    h₀ = 2θ̇ q̇ᵀPq + θ̇ q̇ᵀΨq + q̇ᵀΛq̇,
    hᵢ = −θ̇²(Pq)ᵢ − ½θ̇²(Ψq)ᵢ + 2θ̇(Bq̇)ᵢ + (Ξq̇)ᵢ,

with Q as above but Qᵢ without θ̇²(Pq)ᵢ (it is the first term of hᵢ), Λₐᵦ = Σⱼ Cⱼₐᵦ qⱼ,
Γₐᵦ = Σⱼ Cₐᵦⱼ qⱼ, B = Γᵀ − Γ (antisymmetric: gyroscopic, no work), Ξₐᵦ = Σₖₗ Eₐₖᵦₗ qₖq̇ₗ,
Φₐᵦ = Σₖₗ Fₐᵦₖₗ qₖqₗ, Δₐᵦ = Σₖₗ Dₐᵦₖₗ qₖqₗ. The velocity terms h = Ṁẋ − ½∇(ẋᵀMẋ) are written as d'Alembert's
∫ρ (∂r/∂xₐ)·r̈ dx with the acceleration r̈ = a_r e_r + a_t e_t, R = A + x + u::

    a_r = ü − θ̈w − 2θ̇ẇ − θ̇²R,   a_t = ẅ + θ̈R + 2θ̇u̇ − θ̇²w,   ü = −Σ q̈ⱼsⱼ − Σⱼₖ q̇ⱼq̇ₖSⱼₖ/L.

*Order.* Counting q and θ̇ as first order (a torque pulse drives both; g is not small),
the Lagrangian holds every term through fourth order: T₂, T₃, ½∫ρu̇², the quartic
bending term and the gravity potential of u₄ (the linearised model keeps only second
order and the centrifugal part of T₂; dropping
T₃ and ½∫ρu̇² while keeping T₂, as this option did before, leaves M₀₀ with an O(q²)
correction but the Schur complement M₀₀ − M₀ᵀM_qq⁻¹M₀ without its equally large ones, and
with a light hub it turns negative). It also keeps ½θ̇²∫ρu² (sixth order) so that T is
the exact kinetic energy of the displacement field: M(q) is then a Gram matrix, positive
definite for every q, and the hub can be as light as the user likes. Left out, sixth
order: u₄ in the kinetic energy (θ̇²∫ρ(A + x)u₄, θ̇∫ρ(ẇu₄ − wu̇₄), …) and ½EI∫w''²w'⁴ in V;
added on their own (no five-index integrals for the kinetic ones) they move the hub
angle away from the rigid-link chain of ``_chain``, not toward it
(docs/vv/analytic.md, "The coupled beam model against a rigid-link chain"). The gap stays linear in the coordinates (the stop lies at
θ ≈ 0, where u sin θ is negligible).

With no damping, torque or contact the coupled model conserves E = ½ẋᵀMẋ + V exactly,
and an impact with e = 1 keeps it (the momentum balance uses M(q)). The linearised one
does not conserve its energy (:meth:`BeamModel.energy`), which the energy-balance
residual of a run shows. The coupled mass matrix is factorised by Cholesky,
(n + 1)³/6 operations.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
from numba import njit

from impactdyn.beam._case import BeamCase
from impactdyn.beam._contact import force_kernel, release_kernel
from impactdyn.beam._modes import large_deflection_integrals, modal_integrals, shapes

# slots of the packed scalar parameter array ``sc``
RHO_L, J0, C_JOINT, TORQUE, GRAV_THETA, GRAV_MODAL, RHO_G, LENGTH, MOMENT_ARM, GAP_ARM, \
    STOP_OFFSET, IN_CONTACT, V0 = range(13)
N_SCALARS = 13
# slots of the coupled model's workspace ``fw`` (N_FW + 3n, n + 1, n + 1): the mass matrix
# (Cholesky factor after assembly), n × n matrices of the module docstring and of the
# Jacobian (:func:`_coupled_jacobian`), vectors (rows of VECTORS), then from N_FW the
# partial contractions E·q, F·q and D·q, n slots each (:func:`_contract_last`)
MASS, LAMBDA, GAMMA, PSI, XI, PHI, DELTA, PI, OMEGA, B_DOT, PHI_CROSS, E_ACC, VECTORS = range(13)
N_FW = 13


class CoupledTerms(NamedTuple):
    """The coupled model's arrays, one argument ``coupled`` of every kernel: C (n, n, n),
    E, F, D (n, n, n, n) (:class:`BeamModel`) and the workspace fw (N_FW + 3n, n + 1, n + 1).

    The linearised model passes None instead. numba compiles each kernel once per
    argument type and drops the ``coupled is not None`` branches from the None version,
    so the default path neither runs nor passes anything of the coupled model: passing
    its five arrays through every kernel call and testing a flag at run time made the
    linearised IMPACTB sample 1.64x slower (benchmarks/BENCHMARKS.md, "Rotating beam: sample runs against SciPy").
    It stays an argument of its own, not a field of :class:`SegmentModel`: numba drops those
    branches only where ``coupled`` is a compiled function's argument, not a record's field.
    """

    C: np.ndarray
    E: np.ndarray
    F: np.ndarray
    D: np.ndarray
    fw: np.ndarray


class SegmentModel(NamedTuple):
    """What the model's kernels read in one smooth segment besides ``coupled``, one argument
    ``model`` of each: the packed scalars ``sc`` of the segment (torque, contact mode, V0 among
    them), the arrays m0 … phi_p of :class:`BeamModel`, the workspace ``work`` (2n + 4, n + 1),
    and the contact law's registry id ``law_id`` and parameters ``lawp`` (:mod:`._contact`).
    Built by :meth:`BeamModel.segment`; a kernel reads a field at most once, into the name the
    maths uses (every read of an array field costs a reference count, in the step loop too)."""

    sc: np.ndarray
    m0: np.ndarray
    kd: np.ndarray
    cd: np.ndarray
    G: np.ndarray
    h: np.ndarray
    b: np.ndarray
    phi_p: np.ndarray
    work: np.ndarray
    law_id: int
    lawp: np.ndarray


@njit(cache=True, inline="always")
def gap_kernel(y, sc, phi_p):
    """g = (A + x_p) θ + Σ φᵢ(x_p/L) qᵢ − y_p (negative: penetration)."""
    n = phi_p.shape[0]
    g = sc[GAP_ARM] * y[0] - sc[STOP_OFFSET]
    for i in range(n):
        g += phi_p[i] * y[1 + i]
    return g


@njit(cache=True, inline="always")
def gap_rate_kernel(y, sc, phi_p):
    """ġ = J·[θ̇; q̇], J = [A + x_p, φ₁(x_p/L), …]."""
    n = phi_p.shape[0]
    gd = sc[GAP_ARM] * y[n + 1]
    for i in range(n):
        gd += phi_p[i] * y[n + 2 + i]
    return gd


@njit(cache=True, inline="always")
def _mass_solve(m00, rho_l, m0, work, r):
    """work[r] ← M⁻¹ work[r] for the arrow matrix M = [[m00, m0ᵀ], [m0, ρL I]].

    By its Schur complement s = m00 − |m0|²/ρL: x₀ = (r₀ − m0·r_q/ρL)/s,
    x_q = (r_q − m0 x₀)/ρL, O(n). ``work`` (rows, n + 1); rows, not slices,
    because numba's reference counting of views costs more than the maths.
    """
    n = m0.shape[0]
    s = m00
    x0 = work[r, 0]
    for i in range(n):
        s -= m0[i] * m0[i] / rho_l
        x0 -= m0[i] * work[r, 1 + i] / rho_l
    x0 /= s
    work[r, 0] = x0
    for i in range(n):
        work[r, 1 + i] = (work[r, 1 + i] - m0[i] * x0) / rho_l


@njit(cache=True, inline="always")
def _cholesky(a):
    """a ← L, its lower Cholesky factor (a = L Lᵀ symmetric positive definite; the
    lower triangle is read). A non-positive pivot gives NaN, which the step
    control rejects."""
    m = a.shape[0]
    for j in range(m):
        d = a[j, j]
        for k in range(j):
            d -= a[j, k] * a[j, k]
        a[j, j] = np.sqrt(d)
        for i in range(j + 1, m):
            s = a[i, j]
            for k in range(j):
                s -= a[i, k] * a[j, k]
            a[i, j] = s / a[j, j]


@njit(cache=True, inline="always")
def _cholesky_solve(lf, work, r):
    """work[r] ← (L Lᵀ)⁻¹ work[r] with the factor L = ``lf`` of :func:`_cholesky`."""
    m = lf.shape[0]
    for i in range(m):
        s = work[r, i]
        for k in range(i):
            s -= lf[i, k] * work[r, k]
        work[r, i] = s / lf[i, i]
    for i in range(m - 1, -1, -1):
        s = work[r, i]
        for k in range(i + 1, m):
            s -= lf[k, i] * work[r, k]
        work[r, i] = s / lf[i, i]


@njit(cache=True, inline="always")
def _solve(sc, m0, work, coupled, r):
    """work[r] ← M⁻¹ work[r]: the linearised model's arrow matrix, or the coupled
    model's M(q), factorised in fw[MASS] by :func:`accelerations_kernel`."""
    if coupled is not None:
        _cholesky_solve(coupled.fw[MASS], work, r)
    else:
        _mass_solve(sc[J0], sc[RHO_L], m0, work, r)


@njit(cache=True, inline="always")
def _p_times(y, sc, G, i, off):
    """(P z)ᵢ = ρL zᵢ − (G z)ᵢ for z = y[off : off + n], P = ρL I − G."""
    pz = sc[RHO_L] * y[off + i]
    for j in range(G.shape[0]):
        pz -= G[i, j] * y[off + j]
    return pz


@njit(cache=True, inline="always")
def _contract_last(T, v, out):
    """out[a, k, b] = Σₗ T[a, k, b, l] vₗ for T symmetric in (a, k) (e, f and d), a, k, b < n.

    Every contraction of E, F or D with q in the kernels is one of out·q or out·(a
    vector) (n³ each), using the pair symmetry T[a, k, b, l] = T[b, l, a, k]."""
    n = v.shape[0]
    for a in range(n):
        for k in range(a, n):
            for b in range(n):
                s = 0.0
                for l in range(n):
                    s += T[a, k, b, l] * v[l]
                out[a, k, b] = s
                out[k, a, b] = s


@njit(cache=True)
def mass_matrix_kernel(y, sc, m0, G, C, E, F, D, fw):
    """The coupled model's M(q) into fw[MASS] (module docstring), Λ, Γ, Ψ, Φ, Δ (n × n)
    into their slots, and E·q, F·q, D·q (:func:`_contract_last`) after N_FW."""
    n = m0.shape[0]
    q = y[1 : n + 1]
    lam, gam, psi, phi, delta, M = fw[LAMBDA], fw[GAMMA], fw[PSI], fw[PHI], fw[DELTA], fw[MASS]
    e_q, f_q, d_q = fw[N_FW : N_FW + n], fw[N_FW + n : N_FW + 2 * n], fw[N_FW + 2 * n : N_FW + 3 * n]
    _contract_last(E, q, e_q)
    _contract_last(F, q, f_q)
    _contract_last(D, q, d_q)
    for a in range(n):
        for c in range(n):
            lam_ac = gam_ac = psi_ac = phi_ac = delta_ac = 0.0
            for j in range(n):
                lam_ac += C[j, a, c] * q[j]
                gam_ac += C[a, c, j] * q[j]
                psi_ac += e_q[a, j, c] * q[j]  # Ψ = Σⱼₗ E[a, j, c, l] qⱼqₗ
                phi_ac += f_q[a, c, j] * q[j]  # Φ = Σⱼₗ F[a, c, j, l] qⱼqₗ
                delta_ac += d_q[a, c, j] * q[j]  # Δ = Σⱼₗ D[a, c, j, l] qⱼqₗ
            lam[a, c] = lam_ac
            gam[a, c] = gam_ac
            psi[a, c] = psi_ac
            phi[a, c] = phi_ac
            delta[a, c] = delta_ac
    m00 = sc[J0]
    for a in range(n):
        psi_q = 0.0
        m0a = m0[a]
        for c in range(n):
            psi_q += psi[a, c] * q[c]
            m0a += (lam[a, c] - 0.5 * gam[a, c]) * q[c]
            M[1 + a, 1 + c] = psi[a, c]
        M[1 + a, 1 + a] += sc[RHO_L]
        M[0, 1 + a] = m0a
        M[1 + a, 0] = m0a
        m00 += q[a] * (_p_times(y, sc, G, a, 1) + 0.25 * psi_q)
    M[0, 0] = m00


@njit(cache=True, inline="always")
def _coupled_forces(y, sc, m0, G, h, b, C, E, F, D, work, fw):
    """Turn the linearised model's generalized forces in work[0] into the coupled
    model's (module docstring: gravity terms with Δ, −h without its first term, −Φq),
    and factorise M(q) in fw[MASS]."""
    n = m0.shape[0]
    q, qd, thd = y[1 : n + 1], y[n + 2 : 2 * n + 2], y[n + 1]
    cth, sth = np.cos(y[0]), np.sin(y[0])
    rho_g = sc[RHO_G]
    mass_matrix_kernel(y, sc, m0, G, C, E, F, D, fw)
    lam, gam, psi, xi, phi, delta = fw[LAMBDA], fw[GAMMA], fw[PSI], fw[XI], fw[PHI], fw[DELTA]
    e_q = fw[N_FW : N_FW + n]
    for a in range(n):
        for c in range(n):
            xi_ac = 0.0
            for l in range(n):
                xi_ac += e_q[c, l, a] * qd[l]  # Ξ = Σₖₗ E[a, k, c, l] qₖq̇ₗ, E[a, k, c, l] = E[c, l, a, k]
            xi[a, c] = xi_ac
    h0 = 0.0
    for a in range(n):
        psi_q = hq = lam_qd = b_qd = xi_qd = phi_q = delta_q = 0.0
        for c in range(n):
            psi_q += psi[a, c] * q[c]
            hq += h[a, c] * q[c]
            lam_qd += lam[a, c] * qd[c]
            b_qd += (gam[c, a] - gam[a, c]) * qd[c]
            xi_qd += xi[a, c] * qd[c]
            phi_q += phi[a, c] * q[c]
            delta_q += delta[a, c] * q[c]
        h0 += qd[a] * (2.0 * thd * _p_times(y, sc, G, a, 1) + thd * psi_q + lam_qd)
        work[0, 0] += rho_g * (0.5 * cth * q[a] * hq + sc[LENGTH] * sth * b[a] * q[a]) + 0.25 * cth * q[a] * delta_q
        work[0, 1 + a] += (rho_g * sth * hq + sth * delta_q + 0.5 * thd * thd * psi_q - 2.0 * thd * b_qd - xi_qd
                           - phi_q)
    work[0, 0] -= h0
    _cholesky(fw[MASS])


@njit(cache=True, inline="always")
def accelerations_kernel(y, sc, m0, kd, cd, G, h, b, phi_p, work, coupled):
    """Free accelerations a₀ = M⁻¹Q (no contact) and the unit-force response u = M⁻¹J_F.

    J_F = [moment arm, φ₁(x_p/L), …] is the generalized direction of the contact
    force, so the accelerations under a contact force F are a₀ + F u. Both (n + 1,),
    written to rows 0 and 1 of ``work`` (2n + 4, n + 1); the coupled model leaves its
    terms in ``coupled.fw``.
    """
    n = m0.shape[0]
    thd = y[n + 1]
    cth = np.cos(y[0])
    work[0, 0] = sc[TORQUE] - sc[C_JOINT] * thd - sc[GRAV_THETA] * cth
    work[1, 0] = sc[MOMENT_ARM]
    for i in range(n):
        pq_i = _p_times(y, sc, G, i, 1)
        work[0, 1 + i] = -kd[i] * y[1 + i] + thd * thd * pq_i - cd[i] * y[n + 2 + i] - sc[GRAV_MODAL] * b[i] * cth
        work[1, 1 + i] = phi_p[i]
    if coupled is not None:
        _coupled_forces(y, sc, m0, G, h, b, coupled.C, coupled.E, coupled.F, coupled.D, work, coupled.fw)
    _solve(sc, m0, work, coupled, 0)
    _solve(sc, m0, work, coupled, 1)


@njit(cache=True, inline="always")
def _mode_force(y, sc, phi_p, work, law_id, lawp):
    """F_c of the segment's mode, given a₀ and u in ``work``: 0 in free flight
    (IN_CONTACT = 0), the compliant law's force clipped at 0 (1), or the
    resting-contact multiplier λ (2), which keeps g̈ = J a₀ + λ J u = 0 (the gap
    is linear in the coordinates)."""
    mode = sc[IN_CONTACT]
    if mode == 1.0:
        delta = -gap_kernel(y, sc, phi_p)
        if delta > 0.0:
            return max(force_kernel(law_id, delta, -gap_rate_kernel(y, sc, phi_p), sc[V0], lawp), 0.0)
    elif mode == 2.0:
        n = phi_p.shape[0]
        ja = sc[GAP_ARM] * work[0, 0]
        ju = sc[GAP_ARM] * work[1, 0]
        for i in range(n):
            ja += phi_p[i] * work[0, 1 + i]
            ju += phi_p[i] * work[1, 1 + i]
        return -ja / ju
    return 0.0


@njit(cache=True, inline="always")
def _contact_force(y, sc, m0, kd, cd, G, h, b, phi_p, work, coupled, law_id, lawp):
    """F_c in the segment's mode (:func:`_mode_force`); leaves a₀ and u in ``work``."""
    accelerations_kernel(y, sc, m0, kd, cd, G, h, b, phi_p, work, coupled)
    return _mode_force(y, sc, phi_p, work, law_id, lawp)


@njit(cache=True, inline="always")
def contact_force_kernel(y, model, coupled):
    """F_c in the segment ``model`` (:func:`_contact_force`); leaves a₀ and u in ``model.work``."""
    return _contact_force(y, model.sc, model.m0, model.kd, model.cd, model.G, model.h, model.b, model.phi_p,
                          model.work, coupled, model.law_id, model.lawp)


@njit(cache=True)
def rhs_kernel(t, y, model, coupled):
    """dy/dt of the state (module docstring), allocated; see :func:`rhs_into`."""
    dy = np.empty_like(y)
    rhs_into(t, y, dy, model, coupled)
    return dy


@njit(cache=True)
def rhs_into(t, y, dy, model, coupled):
    """dy/dt of the state y (2n + 7,) into ``dy`` (2n + 7,) in the segment ``model`` (a
    :class:`SegmentModel`), ``coupled`` a :class:`CoupledTerms` or None."""
    sc, m0, kd, cd, G, h, b = model.sc, model.m0, model.kd, model.cd, model.G, model.h, model.b
    phi_p, work, law_id, lawp = model.phi_p, model.work, model.law_id, model.lawp
    n = m0.shape[0]
    f_c = _contact_force(y, sc, m0, kd, cd, G, h, b, phi_p, work, coupled, law_id, lawp)
    thd = y[n + 1]
    dy[0] = thd
    dy[n + 1] = work[0, 0] + f_c * work[1, 0]
    dmodal = 0.0
    p_contact = sc[MOMENT_ARM] * thd
    for i in range(n):
        dy[1 + i] = y[n + 2 + i]
        dy[n + 2 + i] = work[0, 1 + i] + f_c * work[1, 1 + i]
        dmodal += cd[i] * y[n + 2 + i] ** 2
        p_contact += phi_p[i] * y[n + 2 + i]
    base = 2 * n + 2
    dy[base] = sc[TORQUE] * thd
    dy[base + 1] = sc[C_JOINT] * thd * thd
    dy[base + 2] = dmodal
    dy[base + 3] = f_c * p_contact
    dy[base + 4] = f_c


@njit(cache=True, inline="always")
def _law_slopes(law_id, delta, delta_dot, v0, lawp, force):
    """(∂F/∂δ, ∂F/∂δ̇) of the unclipped law at (δ, δ̇), F = ``force``, by forward
    differences of its kernel: the laws stay defined once, in the registry of
    ``_contact``, and a scalar difference costs two law evaluations (error ~1e-8
    relative, far below what the Rosenbrock method's order conditions feel)."""
    d_delta = (delta + 1.5e-8 * delta) - delta
    d_rate = (delta_dot + 1.5e-8 * max(abs(delta_dot), v0)) - delta_dot
    return ((force_kernel(law_id, delta + d_delta, delta_dot, v0, lawp) - force) / d_delta,
            (force_kernel(law_id, delta, delta_dot + d_rate, v0, lawp) - force) / d_rate)


@njit(cache=True, inline="always")
def _coupled_jacobian(y, sc, G, h, b, C, E, F, D, work, fw, hub_acc, f_c):
    """Add the coupled model's terms to ∂Q/∂xₖ − (∂M/∂xₖ) a in work[2 + k] (columns θ,
    q_m, θ̇, q̇_m; :func:`jacobian_kernel`), a = [hub_acc, a_q] the accelerations under
    the contact force f_c. With Λ, Γ, B, Ψ, Ξ, Φ of the module docstring and
    Π = Σₖₗ E[:, :, k, l] qₖqₗ, Ω = Σₖₗ E[:, :, k, l] q̇ₖq̇ₗ, Φˣ = Σₖₗ F[:, k, :, l] qₖqₗ,
    Ḃₐₘ = Σₖ (Cₖₐₘ − Cₐₖₘ) q̇ₖ = ∂(Bq̇)ₐ/∂qₘ, νₘ = Σₐₖ Cₘₐₖ q̇ₐq̇ₖ = ∂(q̇ᵀΛq̇)/∂qₘ::

        ∂M₀₀/∂qₘ = 2(Pq)ₘ + (Ψq)ₘ,    ∂M₀ₐ/∂qₘ = (Λ + B)ₐₘ,
        Σ_b ∂Mₐᵦ/∂qₘ a_b = Σₖₗ (Eₐₘₖₗ a_k qₗ + Eₐₖₘₗ qₖ a_l),
        ∂h₀/∂qₘ = 2θ̇(Pq̇)ₘ + θ̇(Πq̇ + 2Ψq̇)ₘ + νₘ,   ∂h₀/∂θ̇ = 2q̇ᵀPq + q̇ᵀΨq,
        ∂h₀/∂q̇ₘ = 2θ̇(Pq)ₘ + θ̇(Ψq)ₘ + 2(Λq̇)ₘ,
        ∂hₐ/∂qₘ = −θ̇²Pₐₘ − ½θ̇²(Π + 2Ψ)ₐₘ + 2θ̇Ḃₐₘ + Ωₐₘ,   ∂hₐ/∂θ̇ = −2θ̇(Pq)ₐ − θ̇(Ψq)ₐ + 2(Bq̇)ₐ,
        ∂hₐ/∂q̇ₘ = 2θ̇Bₐₘ + 2Ξₐₘ,   ∂(Φq)ₐ/∂qₘ = (Φ + 2Φˣ)ₐₘ

    (the θ̇²P and 2θ̇Pq parts of hₐ's derivatives are the linearised model's, already
    in ``work``), plus the derivatives of the gravity terms, among them ∂(Δq)ₐ/∂qₘ = 3Δₐₘ
    (d is symmetric in all four indices).
    """
    n = G.shape[0]
    q, qd, thd = y[1 : n + 1], y[n + 2 : 2 * n + 2], y[n + 1]
    cth, sth = np.cos(y[0]), np.sin(y[0])
    rho_g = sc[RHO_G]
    lam, gam, psi, xi, phi, delta = fw[LAMBDA], fw[GAMMA], fw[PSI], fw[XI], fw[PHI], fw[DELTA]
    pi, omega, b_dot, phi_x, e_acc = fw[PI], fw[OMEGA], fw[B_DOT], fw[PHI_CROSS], fw[E_ACC]
    e_q, f_q = fw[N_FW : N_FW + n], fw[N_FW + n : N_FW + 2 * n]
    a_q, nu = fw[VECTORS, 0, :n], fw[VECTORS, 1, :n]
    for a in range(n):
        a_q[a] = work[0, 1 + a] + f_c * work[1, 1 + a]
    for a in range(n):
        for m in range(a, n):
            omega_am = 0.0
            for k in range(n):
                e_qd = 0.0
                for l in range(n):
                    e_qd += E[a, m, k, l] * qd[l]
                omega_am += e_qd * qd[k]
            omega[a, m] = omega_am
            omega[m, a] = omega_am
    for m in range(n):
        nu_m = 0.0
        for a in range(n):
            b_dot_am = pi_am = phi_x_am = e_acc_am = 0.0
            for k in range(n):
                b_dot_am += (C[k, a, m] - C[a, k, m]) * qd[k]
                nu_m += C[m, a, k] * qd[a] * qd[k]
                pi_am += e_q[a, m, k] * q[k]
                phi_x_am += f_q[a, k, m] * q[k]
                e_acc_am += (e_q[a, m, k] + e_q[m, k, a]) * a_q[k]
            b_dot[a, m] = b_dot_am
            pi[a, m] = pi_am
            phi_x[a, m] = phi_x_am
            e_acc[a, m] = e_acc_am
        nu[m] = nu_m
    for m in range(n):
        pq_m = _p_times(y, sc, G, m, 1)
        pqd_m = _p_times(y, sc, G, m, n + 2)
        psi_q = psi_qd = pi_qd = lam_qd = b_qd = hq = delta_q = m_acc = 0.0
        for c in range(n):
            psi_q += psi[m, c] * q[c]
            delta_q += delta[m, c] * q[c]
            psi_qd += psi[m, c] * qd[c]
            pi_qd += pi[m, c] * qd[c]
            lam_qd += lam[m, c] * qd[c]
            b_qd += (gam[c, m] - gam[m, c]) * qd[c]
            hq += h[m, c] * q[c]
            m_acc += (lam[c, m] + gam[m, c] - gam[c, m]) * a_q[c]
        # θ column (gravity)
        work[2, 0] += rho_g * (-0.5 * sth * q[m] * hq + sc[LENGTH] * cth * b[m] * q[m]) - 0.25 * sth * q[m] * delta_q
        work[2, 1 + m] += rho_g * cth * hq + cth * delta_q
        # θ̇ column
        work[n + 3, 0] -= qd[m] * (2.0 * pq_m + psi_q)
        work[n + 3, 1 + m] += thd * psi_q - 2.0 * b_qd
        # q̇ₘ column
        work[n + 4 + m, 0] -= 2.0 * thd * pq_m + thd * psi_q + 2.0 * lam_qd
        # qₘ column
        work[3 + m, 0] += (rho_g * (cth * hq + sc[LENGTH] * sth * b[m]) + cth * delta_q
                           - 2.0 * thd * pqd_m - thd * (pi_qd + 2.0 * psi_qd) - nu[m]
                           - (2.0 * pq_m + psi_q) * hub_acc - m_acc)
        for a in range(n):
            b_am = gam[m, a] - gam[a, m]
            work[n + 4 + m, 1 + a] -= 2.0 * thd * b_am + 2.0 * xi[a, m]
            work[3 + m, 1 + a] += (rho_g * sth * h[a, m] + 3.0 * sth * delta[a, m] - phi[a, m] - 2.0 * phi_x[a, m]
                                   + 0.5 * thd * thd * (pi[a, m] + 2.0 * psi[a, m]) - 2.0 * thd * b_dot[a, m]
                                   - omega[a, m] - (lam[a, m] + b_am) * hub_acc
                                   - e_acc[a, m])


@njit(cache=True)
def jacobian_kernel(t, y, model, coupled, jac):
    """∂f/∂y of :func:`rhs_into` into ``jac`` (2n + 7, 2n + 7), analytically.

    The right-hand side is autonomous within a segment (the torque is constant
    between the pulse corners), so ``t`` is unused. With x = [θ, q, θ̇, q̇] (2n + 2)
    and the accelerations a = M(q)⁻¹(Q(x) + F J_F)::

        ∂a/∂xₖ = Bₖ + u ∂F/∂xₖ,   Bₖ = M⁻¹(∂Q/∂xₖ − (∂M/∂xₖ) a),   u = M⁻¹J_F,

    Q all the generalized forces but the contact's (velocity terms included; M and
    Q as in the module docstring). The linearised model's derivatives::

        ∂Q₀/∂θ = ρLg(A + L/2) sin θ,   ∂Qᵢ/∂θ = ρLg bᵢ sin θ,
        ∂Qᵢ/∂qⱼ = −Kᵢ δᵢⱼ + θ̇² Pᵢⱼ,   ∂Q₀/∂θ̇ = −c,   ∂Qᵢ/∂θ̇ = 2θ̇ (Pq)ᵢ,   ∂Qᵢ/∂q̇ⱼ = −cᵢ δᵢⱼ,

    ∂M/∂x = 0; the coupled model adds :func:`_coupled_jacobian`'s terms.

    The contact force adds a rank-one term: in contact ∂F/∂x = −F_δ [J, 0] − F_δ̇ [0, J]
    (δ = −g, δ̇ = −ġ, J the gap row, slopes by :func:`_law_slopes`; 0 where F is
    clipped); at rest λ keeps J a = 0 for every x, so ∂λ/∂xₖ = −J·Bₖ / J·u. The rows
    of the running integrals follow by the chain rule; their columns are zero (they
    do not feed back). ``model.work`` rows 2…2n+3 hold Bₖ.
    """
    sc, m0, kd, cd, G, h, b = model.sc, model.m0, model.kd, model.cd, model.G, model.h, model.b
    phi_p, work, law_id, lawp = model.phi_p, model.work, model.law_id, model.lawp
    n = m0.shape[0]
    nd = 2 * n + 2
    rho_l = sc[RHO_L]
    thd = y[n + 1]
    sth = np.sin(y[0])
    accelerations_kernel(y, sc, m0, kd, cd, G, h, b, phi_p, work, coupled)
    f_c = _mode_force(y, sc, phi_p, work, law_id, lawp)
    # ∂Q/∂xₖ into work[2 + k]: θ, q_j, θ̇, q̇_j columns
    for k in range(nd):
        for i in range(n + 1):
            work[2 + k, i] = 0.0
    work[2, 0] = sc[GRAV_THETA] * sth
    work[n + 3, 0] = -sc[C_JOINT]
    for i in range(n):
        work[2, 1 + i] = sc[GRAV_MODAL] * b[i] * sth
        work[n + 3, 1 + i] = 2.0 * thd * _p_times(y, sc, G, i, 1)
        work[n + 4 + i, 1 + i] = -cd[i]
        for j in range(n):
            work[3 + j, 1 + i] = -thd * thd * G[i, j]
        work[3 + i, 1 + i] += thd * thd * rho_l - kd[i]
    if coupled is not None:
        _coupled_jacobian(y, sc, G, h, b, coupled.C, coupled.E, coupled.F, coupled.D, work, coupled.fw,
                          work[0, 0] + f_c * work[1, 0], f_c)
    for k in range(nd):
        _solve(sc, m0, work, coupled, 2 + k)
    ns = nd + 5
    for r in range(ns):
        for k in range(ns):
            jac[r, k] = 0.0
    # ∂F/∂x into the last row (dI_contact/dt = F)
    d_f = nd + 4
    mode = sc[IN_CONTACT]
    if mode == 1.0 and f_c > 0.0:
        delta, rate = -gap_kernel(y, sc, phi_p), -gap_rate_kernel(y, sc, phi_p)
        s_delta, s_rate = _law_slopes(law_id, delta, rate, sc[V0], lawp,
                                      force_kernel(law_id, delta, rate, sc[V0], lawp))
        jac[d_f, 0] = -s_delta * sc[GAP_ARM]
        jac[d_f, n + 1] = -s_rate * sc[GAP_ARM]
        for i in range(n):
            jac[d_f, 1 + i] = -s_delta * phi_p[i]
            jac[d_f, n + 2 + i] = -s_rate * phi_p[i]
    elif mode == 2.0:
        ju = sc[GAP_ARM] * work[1, 0]
        for i in range(n):
            ju += phi_p[i] * work[1, 1 + i]
        for k in range(nd):
            jb = sc[GAP_ARM] * work[2 + k, 0]
            for i in range(n):
                jb += phi_p[i] * work[2 + k, 1 + i]
            jac[d_f, k] = -jb / ju
    # d(θ, q)/dt = (θ̇, q̇); the accelerations; the running integrals W_τ, D_joint, D_modal, W_contact
    for r in range(n + 1):
        jac[r, n + 1 + r] = 1.0
        for k in range(nd):
            jac[n + 1 + r, k] = work[2 + k, r] + work[1, r] * jac[d_f, k]
    p_contact = sc[MOMENT_ARM] * thd
    for i in range(n):
        p_contact += phi_p[i] * y[n + 2 + i]
    for k in range(nd):
        jac[nd + 3, k] = p_contact * jac[d_f, k]
    jac[nd, n + 1] = sc[TORQUE]
    jac[nd + 1, n + 1] = 2.0 * sc[C_JOINT] * thd
    jac[nd + 3, n + 1] += f_c * sc[MOMENT_ARM]
    for i in range(n):
        jac[nd + 2, n + 2 + i] = 2.0 * cd[i] * y[n + 2 + i]
        jac[nd + 3, n + 2 + i] += f_c * phi_p[i]


@njit(cache=True)
def coupled_energy_kernel(states, sc, m0, G, C, E, F, D, fw):
    """½ẋᵀM(q)ẋ + ¼ qᵀΦq − ¼ sin θ qᵀΔq (the coupled model's kinetic energy and quartic
    potential terms) of each row of ``states`` (m, 2n + 7); returns (m,)."""
    n = m0.shape[0]
    out = np.empty(states.shape[0])
    for r in range(states.shape[0]):
        y = states[r]
        mass_matrix_kernel(y, sc, m0, G, C, E, F, D, fw)
        M, phi, delta = fw[MASS], fw[PHI], fw[DELTA]
        sth = np.sin(y[0])
        e = 0.0
        for a in range(n + 1):
            for c in range(n + 1):
                e += 0.5 * y[n + 1 + a] * M[a, c] * y[n + 1 + c]
        for a in range(n):
            for c in range(n):
                e += 0.25 * y[1 + a] * (phi[a, c] - sth * delta[a, c]) * y[1 + c]
        out[r] = e
    return out


@njit(cache=True, inline="always")
def event_kernel(y, model, coupled):
    """The two event functions of the current mode: free: (g, 0); contact:
    (g, release indicator); resting: (λ, 0). Inlined into the step's event scan, which
    calls it nine times a step: a call would count references to every array of ``model``."""
    sc, phi_p = model.sc, model.phi_p
    mode = sc[IN_CONTACT]
    if mode == 2.0:
        return contact_force_kernel(y, model, coupled), 0.0
    g = gap_kernel(y, sc, phi_p)
    if mode == 1.0:
        return g, release_kernel(model.law_id, -g, -gap_rate_kernel(y, sc, phi_p), sc[V0], model.lawp)
    return g, 0.0


@dataclass(frozen=True)
class BeamModel:
    """Assembled coefficients of one case (SI); see the module docstring.

    Attributes
    ----------
    n : number of modes.
    sc : (13,) packed scalars (slots ``RHO_L`` … ``V0``); a template, copied per segment.
    m0 : (n,) coupling M₀ᵢ.      kd : (n,) modal stiffness Kᵢ.
    cd : (n,) modal damping coefficients.      G : (n, n) centrifugal matrix ρL k + ρA h.
    h : (n, n) the integral h (for the coupled gravity terms).      b : (n,) ∫φᵢ.
    phi_p : (n,) φᵢ(x_p/L), the gap Jacobian's modal part.
    phi_r, phi2_r : (n,) φᵢ and φᵢ'' at the response point (for deflection and strain).
    coupled : the large-deflection model (``model.coupled``) instead of the linearised one.
    C : (n, n, n) ρc,  E, F, D : (n, n, n, n) (ρ/L)e, (2EI/L⁵)f, (ρg/2L²)d: the coupled
        model's large-deflection coefficients (``_modes``); size 0 for the linearised model.
    impact_j00 : M₀₀ used by the momentum balance (differs only under the legacy option).
    """

    n: int
    sc: np.ndarray
    m0: np.ndarray
    kd: np.ndarray
    cd: np.ndarray
    G: np.ndarray
    h: np.ndarray
    b: np.ndarray
    phi_p: np.ndarray
    phi_r: np.ndarray
    phi2_r: np.ndarray
    coupled: bool
    C: np.ndarray
    E: np.ndarray
    F: np.ndarray
    D: np.ndarray
    impact_j00: float
    length: float
    strain_radius: float

    @classmethod
    def from_case(cls, case: BeamCase) -> "BeamModel":
        bm, lg = case.beam, case.legacy
        rho, L, A = bm.mass_per_length_kg_m, bm.length_m, bm.hub_radius_m
        n = case.model.n_modes
        mi = modal_integrals(n)
        rho_l = rho * L
        g = case.model.gravity_m_s2
        a = mi.a.copy()
        m0 = rho_l * (L * a + A * mi.b)
        if lg.sr7_typo and n >= 7:
            m0[6] = rho_l * (L * a[6] + A * a[6])
        k = np.diag(np.diag(mi.k)) if lg.diagonal_centrifugal else mi.k
        h = np.diag(np.diag(mi.h)) if lg.diagonal_centrifugal else mi.h
        G = rho_l * k + rho * A * h
        kd = bm.EI_N_m2 * mi.beta**4 / L**3
        zeta = case.damping.modal_ratio
        cd = zeta * np.sqrt(2.0 * kd * rho_l) if lg.modal_damping_sqrt_2km else 2.0 * zeta * np.sqrt(kd * rho_l)
        j_beam = rho_l * (A * A + A * L + L * L / 3.0)
        j0 = j_beam * (1.0 + bm.inertia_ratio)
        arm = case.stop.x_m if lg.moment_arms_ignore_hub else A + case.stop.x_m
        sc = np.zeros(N_SCALARS)
        sc[RHO_L] = rho_l
        sc[J0] = j0
        sc[C_JOINT] = case.damping.joint_N_m_s
        sc[GRAV_THETA] = rho_l * g * ((L / 2.0) if lg.moment_arms_ignore_hub else (A + L / 2.0))
        sc[GRAV_MODAL] = rho_l * g
        sc[RHO_G] = rho * g
        sc[LENGTH] = L
        sc[MOMENT_ARM] = arm
        sc[GAP_ARM] = A + case.stop.x_m
        sc[STOP_OFFSET] = case.stop.y_m
        sc[V0] = 1.0
        xr = case.output.response_point_m / L
        impact_j00 = rho_l * (A * A + L * L / 3.0) * (1.0 + bm.inertia_ratio) if lg.impact_inertia_drops_AL else j0
        if case.model.coupled:
            li = large_deflection_integrals(n)
            C, E, F, D = rho * li.c, (rho / L) * li.e, (2.0 * bm.EI_N_m2 / L**5) * li.f, (rho * g / (2 * L**2)) * li.d
        else:
            C, E, F, D = np.zeros((0, 0, 0)), np.zeros((0, 0, 0, 0)), np.zeros((0, 0, 0, 0)), np.zeros((0, 0, 0, 0))
        return cls(
            n=n, sc=sc, m0=m0, kd=kd, cd=cd, G=G, h=np.array(h), b=mi.b.copy(),
            phi_p=shapes(mi.beta, np.float64(case.stop.x_m / L)).reshape(n),
            phi_r=shapes(mi.beta, np.float64(xr)).reshape(n),
            phi2_r=(shapes(mi.beta, np.float64(xr), 2) / L**2).reshape(n),
            coupled=case.model.coupled, C=C, E=E, F=F, D=D,
            impact_j00=impact_j00, length=L, strain_radius=bm.strain_radius_m,
        )

    # ------------------------------------------------------------------ state helpers
    @property
    def n_state(self) -> int:
        return 2 * self.n + 7

    def split(self, y: np.ndarray):
        """(θ, q, θ̇, q̇) views of a state (last axis)."""
        n = self.n
        return y[..., 0], y[..., 1 : n + 1], y[..., n + 1], y[..., n + 2 : 2 * n + 2]

    def params(self, torque: float, in_contact: bool = False, v0: float = 1.0) -> np.ndarray:
        sc = self.sc.copy()
        sc[TORQUE] = torque
        sc[IN_CONTACT] = 1.0 if in_contact else 0.0
        sc[V0] = v0
        return sc

    def gap(self, y: np.ndarray) -> np.ndarray:
        th, q, _, _ = self.split(y)
        return self.sc[GAP_ARM] * th + q @ self.phi_p - self.sc[STOP_OFFSET]

    def gap_rate(self, y: np.ndarray) -> np.ndarray:
        _, _, thd, qd = self.split(y)
        return self.sc[GAP_ARM] * thd + qd @ self.phi_p

    def jacobian_row(self) -> np.ndarray:
        """J = [A + x_p, φ₁(x_p/L), …], shape (n + 1,)."""
        return np.concatenate([[self.sc[GAP_ARM]], self.phi_p])

    def mass_matrix(self, y: np.ndarray, j00: float | None = None) -> np.ndarray:
        """M of the model at the state ``y`` (module docstring), shape (n + 1, n + 1);
        ``j00`` replaces the linearised model's M₀₀ (the legacy impact inertia)."""
        n = self.n
        if self.coupled:
            fw = self._workspace()
            mass_matrix_kernel(np.ascontiguousarray(y, dtype=float), self.sc, self.m0, self.G, self.C, self.E,
                               self.F, self.D, fw)
            return fw[MASS].copy()
        M = np.zeros((n + 1, n + 1))
        M[0, 0] = self.sc[J0] if j00 is None else j00
        M[0, 1:] = M[1:, 0] = self.m0
        M[1:, 1:] = np.eye(n) * self.sc[RHO_L]
        return M

    def energy(self, y: np.ndarray) -> np.ndarray:
        """E = T + V (module docstring) of states ``y`` (..., 2n + 7).

        Coupled model: ½ẋᵀM(q)ẋ + V with its quartic terms, its invariant.
        Linearised model: T = ½(J₀ + qᵀPq)θ̇² + θ̇ M₀⁰·q̇ + ½ρL|q̇|² (its centrifugal term is
        −∂/∂q of −½θ̇²qᵀPq) and the quadratic V; its equations do not conserve this E.
        """
        th, q, thd, qd = self.split(y)
        sc = self.sc
        qhq = np.einsum("...i,ij,...j->...", q, self.h, q)
        V = (sc[GRAV_THETA] * np.sin(th) + sc[GRAV_MODAL] * np.cos(th) * (q @ self.b)
             - 0.5 * sc[RHO_G] * np.sin(th) * qhq + 0.5 * np.sum(self.kd * q**2, axis=-1))
        if self.coupled:
            states = np.ascontiguousarray(y, dtype=float).reshape(-1, self.n_state)
            kinetic_and_quartic = coupled_energy_kernel(states, sc, self.m0, self.G, self.C, self.E, self.F,
                                                        self.D, self._workspace())
            return kinetic_and_quartic.reshape(np.shape(y)[:-1]) + V
        P = sc[RHO_L] * np.eye(self.n) - self.G
        qpq = np.einsum("...i,ij,...j->...", q, P, q)
        T = 0.5 * (sc[J0] + qpq) * thd**2 + thd * (qd @ self.m0) + 0.5 * sc[RHO_L] * np.sum(qd**2, axis=-1)
        return T + V

    def deflection(self, y: np.ndarray) -> np.ndarray:
        """w at the response point (m)."""
        return self.split(y)[1] @ self.phi_r

    def strain(self, y: np.ndarray) -> np.ndarray:
        """R₁ w''(x) at the response point (listing STRAIN)."""
        return self.strain_radius * (self.split(y)[1] @ self.phi2_r)

    def stop_displacement(self, y: np.ndarray) -> np.ndarray:
        """(A + x_p) θ + w(x_p): displacement of the stop point normal to θ = 0 (m)."""
        return self.gap(y) + self.sc[STOP_OFFSET]

    def impact(self, y: np.ndarray, e: float) -> tuple[np.ndarray, float]:
        """Velocity jump of a momentum-balance impact (IMPACTC).

        Solves ``M Δv = Jᵀ P``, ``J v⁺ = −e J v⁻``:  P = −(1 + e) J v⁻ / (J M⁻¹ Jᵀ).
        Returns the new state and the impulse P (N·s).
        """
        n = self.n
        M = self.mass_matrix(y, j00=None if self.coupled else self.impact_j00)
        J = self.jacobian_row()
        v = y[n + 1 : 2 * n + 2]
        minv_j = np.linalg.solve(M, J)
        P = -(1.0 + e) * (J @ v) / (J @ minv_j)
        out = y.copy()
        out[n + 1 : 2 * n + 2] = v + minv_j * P
        return out, float(P)

    def rotating_frequencies(self, omega: float) -> np.ndarray:
        """Natural frequencies (rad/s, ascending) of the modal equations with the hub
        held at constant speed Ω: eigenvalues of ρL q̈ + [diag(Kᵢ) + Ω²(G − ρL I)] q = 0."""
        k_eff = np.diag(self.kd) + omega**2 * (self.G - self.sc[RHO_L] * np.eye(self.n))
        return np.sqrt(np.sort(np.linalg.eigvalsh(k_eff / self.sc[RHO_L])))

    def _workspace(self) -> np.ndarray:
        """fw (N_FW + 3n, n + 1, n + 1) of the coupled kernels."""
        return np.empty((N_FW + 3 * self.n, self.n + 1, self.n + 1))

    def segment(self, sc: np.ndarray, law_id: int = 0, lawp: np.ndarray | None = None) -> SegmentModel:
        """The kernels' :class:`SegmentModel` of a segment with the scalars ``sc`` and the
        contact law ``law_id``, ``lawp``, with a fresh workspace ``work``."""
        return SegmentModel(sc=sc, m0=self.m0, kd=self.kd, cd=self.cd, G=self.G, h=self.h, b=self.b,
                            phi_p=self.phi_p, work=np.empty((2 * self.n + 4, self.n + 1)), law_id=law_id,
                            lawp=np.zeros(1) if lawp is None else lawp)

    def coupled_terms(self) -> CoupledTerms | None:
        """The kernels' argument ``coupled``: the :class:`CoupledTerms` with a fresh workspace
        ``fw``, or None for the linearised model."""
        return CoupledTerms(self.C, self.E, self.F, self.D, self._workspace()) if self.coupled else None

    def jacobian(self, y: np.ndarray, sc: np.ndarray, law_id: int = 0, lawp=None) -> np.ndarray:
        """∂f/∂y of the right-hand side in the segment mode of ``sc``, shape (2n + 7, 2n + 7)."""
        jac = np.empty((self.n_state, self.n_state))
        jacobian_kernel(0.0, y, self.segment(sc, law_id, lawp), self.coupled_terms(), jac)
        return jac

    def contact_force(self, y: np.ndarray, sc: np.ndarray, law_id: int = 0, lawp=None) -> float:
        """F_c (N) in the segment's contact mode; in resting contact the multiplier λ
        (positive: the stop pushes, so contact persists)."""
        return contact_force_kernel(y, self.segment(sc, law_id, lawp), self.coupled_terms())
