"""Equations of motion of the hub–beam system (DESIGN §4; seed 001, listing EQNS).

Coordinates: hub angle θ and modal amplitudes q₁…qₙ of ``w(x,t) = Σ φᵢ(x/L) qᵢ(t)``.
The state vector used everywhere (shape ``(2n + 7,)``)::

    y = [θ, q₁…qₙ, θ̇, q̇₁…q̇ₙ, W_τ, D_joint, D_modal, W_contact, I_contact]

where the last five are running integrals: work of the torque ∫τθ̇, joint-damping
loss ∫cθ̇², modal-damping loss ∫Σcᵢq̇ᵢ², work of the contact force ∫F_c J_F·v, and
its impulse ∫F_c dt (impulsive impacts add their jumps separately).

Kinetic energy of the inextensible beam with foreshortening, to second order in
the elastic motion (P = ρL I − G, G = ρL k + ρA h)::

    T = ½ M₀₀(q) θ̇² + θ̇ Σ M₀ᵢ q̇ᵢ + ½ ρL Σ q̇ᵢ²,   M₀₀(q) = J₀ + qᵀ P q,
    J₀ = ρL(A² + AL + L²/3)(1 + IR),   M₀ᵢ = ρL(L aᵢ + A bᵢ),
    V = ρg[L(A + L/2) sin θ + L cos θ bᵀq − ½ sin θ qᵀ h q] + ½ Σ Kᵢ qᵢ²,   Kᵢ = EI βᵢ⁴/L³.

**Linearised model** (default, the listing's EQNS): M₀₀ = J₀ and

    M [θ̈; q̈] = Q,
    Q₀ = τ(t) − c θ̇ − ρLg(A + L/2) cos θ + F_c (A + x_p),
    Qᵢ = −Kᵢ qᵢ − Σⱼ (Gᵢⱼ − ρL δᵢⱼ) θ̇² qⱼ − 2ζᵢ√(KᵢρL) q̇ᵢ − ρLg bᵢ cos θ + F_c φᵢ(x_p/L).

**Coupled model** (``coupled = true``): Lagrange's equations of T − V above, i.e.
additionally M₀₀(q) = J₀ + qᵀPq, the Coriolis moment −2θ̇ qᵀP q̇ in Q₀, and the
gravity terms ρg[½ cos θ qᵀhq + L sin θ bᵀq] in Q₀ and ρg sin θ (hq)ᵢ in Qᵢ.
The modal equations need no new inertial term: ∂T/∂q = θ̇² P q is already the
centrifugal term of the linearised equations. With no damping and no torque the
coupled model conserves E = T + V exactly; the linearised one does not (it drops
d/dt of the θ̇²qᵀPq term from the hub equation), which the energy-balance residual
of a run shows.

The mass matrix has the arrow structure [[M₀₀, M₀ᵀ], [M₀, ρL I]], solved in O(n)
by its Schur complement s = M₀₀ − |M₀|²/ρL.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numba import njit

from impactdyn.beam._case import BeamCase
from impactdyn.beam._contact import force_kernel, release_kernel
from impactdyn.beam._modes import modal_integrals, shapes

# slots of the packed scalar parameter array ``sc``
RHO_L, J0, C_JOINT, TORQUE, GRAV_THETA, GRAV_MODAL, RHO_G, LENGTH, MOMENT_ARM, GAP_ARM, \
    STOP_OFFSET, COUPLED, IN_CONTACT, V0 = range(14)
N_SCALARS = 14


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
def _p_times(y, sc, G, i, off):
    """(P z)ᵢ = ρL zᵢ − (G z)ᵢ for z = y[off : off + n], P = ρL I − G."""
    pz = sc[RHO_L] * y[off + i]
    for j in range(G.shape[0]):
        pz -= G[i, j] * y[off + j]
    return pz


@njit(cache=True, inline="always")
def accelerations_kernel(y, sc, m0, kd, cd, G, h, b, phi_p, work):
    """Free accelerations a₀ = M⁻¹Q (no contact) and the unit-force response u = M⁻¹J_F.

    J_F = [moment arm, φ₁(x_p/L), …] is the generalized direction of the contact
    force, so the accelerations under a contact force F are a₀ + F u. Both (n + 1,),
    written to rows 0 and 1 of ``work`` (2n + 4, n + 1). Returns M₀₀(q).
    """
    n = m0.shape[0]
    theta = y[0]
    thd = y[n + 1]
    cth, sth = np.cos(theta), np.sin(theta)
    m00 = sc[J0]
    work[0, 0] = sc[TORQUE] - sc[C_JOINT] * thd - sc[GRAV_THETA] * cth
    work[1, 0] = sc[MOMENT_ARM]
    for i in range(n):
        pq_i = _p_times(y, sc, G, i, 1)
        work[0, 1 + i] = -kd[i] * y[1 + i] + thd * thd * pq_i - cd[i] * y[n + 2 + i] - sc[GRAV_MODAL] * b[i] * cth
        work[1, 1 + i] = phi_p[i]
        if sc[COUPLED] > 0.0:
            hq_i = 0.0
            for j in range(n):
                hq_i += h[i, j] * y[1 + j]
            m00 += y[1 + i] * pq_i
            work[0, 0] += -2.0 * thd * y[n + 2 + i] * pq_i + sc[RHO_G] * (
                0.5 * cth * y[1 + i] * hq_i + sc[LENGTH] * sth * b[i] * y[1 + i])
            work[0, 1 + i] += sc[RHO_G] * sth * hq_i
    _mass_solve(m00, sc[RHO_L], m0, work, 0)
    _mass_solve(m00, sc[RHO_L], m0, work, 1)
    return m00


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
def contact_force_kernel(y, sc, m0, kd, cd, G, h, b, phi_p, work, law_id, lawp):
    """F_c in the segment's mode (:func:`_mode_force`); leaves a₀ and u in ``work``."""
    accelerations_kernel(y, sc, m0, kd, cd, G, h, b, phi_p, work)
    return _mode_force(y, sc, phi_p, work, law_id, lawp)


@njit(cache=True)
def rhs_kernel(t, y, sc, m0, kd, cd, G, h, b, phi_p, work, law_id, lawp):
    """dy/dt of the state (module docstring), allocated; see :func:`rhs_into`."""
    dy = np.empty_like(y)
    rhs_into(t, y, dy, sc, m0, kd, cd, G, h, b, phi_p, work, law_id, lawp)
    return dy


@njit(cache=True)
def rhs_into(t, y, dy, sc, m0, kd, cd, G, h, b, phi_p, work, law_id, lawp):
    """dy/dt of the state into ``dy``; shapes: y, dy (2n+7,), m0/kd/cd/b/phi_p (n,),
    G/h (n,n), work (2n+4, n+1)."""
    n = m0.shape[0]
    f_c = contact_force_kernel(y, sc, m0, kd, cd, G, h, b, phi_p, work, law_id, lawp)
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


@njit(cache=True)
def jacobian_kernel(t, y, sc, m0, kd, cd, G, h, b, phi_p, work, law_id, lawp, jac):
    """∂f/∂y of :func:`rhs_into` into ``jac`` (2n + 7, 2n + 7), analytically.

    The right-hand side is autonomous within a segment (the torque is constant
    between the pulse corners), so ``t`` is unused. With x = [θ, q, θ̇, q̇] (2n + 2)
    and the accelerations a = M(q)⁻¹(Q(x) + F J_F)::

        ∂a/∂xₖ = Bₖ + u ∂F/∂xₖ,   Bₖ = M⁻¹(∂Q/∂xₖ − e₀ a₀ ∂M₀₀/∂xₖ),   u = M⁻¹J_F,

    a₀ the hub acceleration and ∂M₀₀/∂qⱼ = 2(Pq)ⱼ (coupled model; 0 otherwise).
    The derivatives of the generalized forces (module docstring; [·] coupled only)::

        ∂Q₀/∂θ = ρLg(A + L/2) sin θ [+ ρg(L cos θ bᵀq − ½ sin θ qᵀhq)],
        ∂Qᵢ/∂θ = ρLg bᵢ sin θ [+ ρg cos θ (hq)ᵢ],
        ∂Q₀/∂qⱼ = [−2θ̇ (Pq̇)ⱼ + ρg(cos θ (hq)ⱼ + L sin θ bⱼ)],
        ∂Qᵢ/∂qⱼ = −Kᵢ δᵢⱼ + θ̇² Pᵢⱼ [+ ρg sin θ hᵢⱼ],
        ∂Q₀/∂θ̇ = −c [− 2 q̇ᵀPq],   ∂Qᵢ/∂θ̇ = 2θ̇ (Pq)ᵢ,
        ∂Q₀/∂q̇ⱼ = [−2θ̇ (Pq)ⱼ],    ∂Qᵢ/∂q̇ⱼ = −cᵢ δᵢⱼ.

    The contact force adds a rank-one term: in contact ∂F/∂x = −F_δ [J, 0] − F_δ̇ [0, J]
    (δ = −g, δ̇ = −ġ, J the gap row, slopes by :func:`_law_slopes`; 0 where F is
    clipped); at rest λ keeps J a = 0 for every x, so ∂λ/∂xₖ = −J·Bₖ / J·u. The rows
    of the running integrals follow by the chain rule; their columns are zero (they
    do not feed back). ``work`` rows 2…2n+3 hold Bₖ.
    """
    n = m0.shape[0]
    nd = 2 * n + 2
    rho_l, rho_g = sc[RHO_L], sc[RHO_G]
    theta, thd = y[0], y[n + 1]
    cth, sth = np.cos(theta), np.sin(theta)
    m00 = accelerations_kernel(y, sc, m0, kd, cd, G, h, b, phi_p, work)
    f_c = _mode_force(y, sc, phi_p, work, law_id, lawp)
    hub_acc = work[0, 0] + f_c * work[1, 0]
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
    if sc[COUPLED] > 0.0:
        for j in range(n):
            pq_j = _p_times(y, sc, G, j, 1)
            pqd_j = _p_times(y, sc, G, j, n + 2)
            hq_j = 0.0
            for i in range(n):
                hq_j += h[j, i] * y[1 + i]
                work[3 + j, 1 + i] += rho_g * sth * h[i, j]
            work[2, 0] += rho_g * (-0.5 * sth * y[1 + j] * hq_j + sc[LENGTH] * cth * b[j] * y[1 + j])
            work[2, 1 + j] += rho_g * cth * hq_j
            work[3 + j, 0] = -2.0 * thd * pqd_j + rho_g * (cth * hq_j + sc[LENGTH] * sth * b[j]) - 2.0 * pq_j * hub_acc
            work[n + 3, 0] -= 2.0 * y[n + 2 + j] * pq_j
            work[n + 4 + j, 0] = -2.0 * thd * pq_j
    for k in range(nd):
        _mass_solve(m00, rho_l, m0, work, 2 + k)
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
def event_kernel(y, sc, m0, kd, cd, G, h, b, phi_p, work, law_id, lawp):
    """The two event functions of the current mode: free: (g, 0); contact:
    (g, release indicator); resting: (λ, 0)."""
    mode = sc[IN_CONTACT]
    if mode == 2.0:
        return contact_force_kernel(y, sc, m0, kd, cd, G, h, b, phi_p, work, law_id, lawp), 0.0
    g = gap_kernel(y, sc, phi_p)
    if mode == 1.0:
        return g, release_kernel(law_id, -g, -gap_rate_kernel(y, sc, phi_p), sc[V0], lawp)
    return g, 0.0


@dataclass(frozen=True)
class BeamModel:
    """Assembled coefficients of one case (SI); see the module docstring.

    Attributes
    ----------
    n : number of modes.
    sc : (14,) packed scalars (slots ``RHO_L`` … ``V0``); a template, copied per segment.
    m0 : (n,) coupling M₀ᵢ.      kd : (n,) modal stiffness Kᵢ.
    cd : (n,) modal damping coefficients.      G : (n, n) centrifugal matrix ρL k + ρA h.
    h : (n, n) the integral h (for the coupled gravity terms).      b : (n,) ∫φᵢ.
    phi_p : (n,) φᵢ(x_p/L), the gap Jacobian's modal part.
    phi_r, phi2_r : (n,) φᵢ and φᵢ'' at the response point (for deflection and strain).
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
        sc[COUPLED] = 1.0 if case.model.coupled else 0.0
        sc[V0] = 1.0
        xr = case.output.response_point_m / L
        impact_j00 = rho_l * (A * A + L * L / 3.0) * (1.0 + bm.inertia_ratio) if lg.impact_inertia_drops_AL else j0
        return cls(
            n=n, sc=sc, m0=m0, kd=kd, cd=cd, G=G, h=np.array(h), b=mi.b.copy(),
            phi_p=shapes(mi.beta, np.float64(case.stop.x_m / L)).reshape(n),
            phi_r=shapes(mi.beta, np.float64(xr)).reshape(n),
            phi2_r=(shapes(mi.beta, np.float64(xr), 2) / L**2).reshape(n),
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

    def rhs(self, sc: np.ndarray, law_id: int = 0, lawp: np.ndarray | None = None):
        """A ``f(t, y)`` for SciPy solvers with the given segment parameters."""
        args = (*self.kernel_args(sc), law_id, np.zeros(1) if lawp is None else lawp)

        def f(t, y):
            return rhs_kernel(t, y, *args)

        return f

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
        """M(q), shape (n + 1, n + 1)."""
        th, q, _, _ = self.split(y)
        n = self.n
        M = np.zeros((n + 1, n + 1))
        M[0, 0] = self.sc[J0] if j00 is None else j00
        if self.sc[COUPLED] > 0:
            M[0, 0] += q @ self._p_matrix() @ q
        M[0, 1:] = M[1:, 0] = self.m0
        M[1:, 1:] = np.eye(n) * self.sc[RHO_L]
        return M

    def _p_matrix(self) -> np.ndarray:
        return self.sc[RHO_L] * np.eye(self.n) - self.G

    def energy(self, y: np.ndarray) -> np.ndarray:
        """E = T + V of the module docstring (the coupled model's invariant), any leading shape."""
        th, q, thd, qd = self.split(y)
        sc = self.sc
        qpq = np.einsum("...i,ij,...j->...", q, self._p_matrix(), q)
        qhq = np.einsum("...i,ij,...j->...", q, self.h, q)
        T = 0.5 * (sc[J0] + qpq) * thd**2 + thd * (qd @ self.m0) + 0.5 * sc[RHO_L] * np.sum(qd**2, axis=-1)
        V = (sc[GRAV_THETA] * np.sin(th) + sc[GRAV_MODAL] * np.cos(th) * (q @ self.b)
             - 0.5 * sc[RHO_G] * np.sin(th) * qhq + 0.5 * np.sum(self.kd * q**2, axis=-1))
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
        M = self.mass_matrix(y, j00=self.impact_j00 if self.sc[COUPLED] == 0 else None)
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

    def kernel_args(self, sc: np.ndarray) -> tuple:
        """The model arrays after ``sc``, in the order every kernel takes them."""
        return (sc, self.m0, self.kd, self.cd, self.G, self.h, self.b, self.phi_p,
                np.empty((2 * self.n + 4, self.n + 1)))

    def jacobian(self, y: np.ndarray, sc: np.ndarray, law_id: int = 0, lawp=None) -> np.ndarray:
        """∂f/∂y of the right-hand side in the segment mode of ``sc``, shape (2n + 7, 2n + 7)."""
        jac = np.empty((self.n_state, self.n_state))
        jacobian_kernel(0.0, y, *self.kernel_args(sc), law_id, np.zeros(1) if lawp is None else lawp, jac)
        return jac

    def contact_force(self, y: np.ndarray, sc: np.ndarray, law_id: int = 0, lawp=None) -> float:
        """F_c (N) in the segment's contact mode; in resting contact the multiplier λ
        (positive: the stop pushes, so contact persists)."""
        return contact_force_kernel(y, *self.kernel_args(sc), law_id, np.zeros(1) if lawp is None else lawp)
