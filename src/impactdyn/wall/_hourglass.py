"""Hourglass control of the one-point hexahedron: the three forms of :data:`HOURGLASS_FORMS`.

Flanagan & Belytschko (IJNME 17 (1981) 679, "FB") hourglass control with the shape vectors γ_α
(:mod:`._hex`) and the hourglass velocities q̇_αi = Σ_I v_iI γ_αI::

    viscous   (LS-DYNA IHQ 2):  Q_αi = a_h q̇_αi,           a_h = QH ρ c V^{2/3} / 4
    stiffness (LS-DYNA IHQ 4):  Q_αi ← Q_αi + κ Δt q̇_αi,   κ = QH ρc² (Σ_iI B_iI²)/(3V) / 8
    assumed_strain:             Q_α = ∂U/∂q̄_α from stored stresses,  :func:`assumed_strain_forces`
    f_hg,iI = Σ_α Q_αi γ_αI

(the stiffness form is FB's, with their 1/√8-normalised γ folded into κ; QH = 0.1 is
LS-DYNA's default coefficient.  The assumed-strain form, after Belytschko & Bindeman,
CMAME 105 (1993) 225, takes the element's own bending and twisting stiffness from its
current shape and elastic constants, with no coefficient; it keeps the hourglass stresses
of each element, loads them at the material's tangent and unloads them elastically, so
its hourglass work cannot be negative).

The kernels work on the block array of :mod:`._blocks` (rows R_…); the element pass
(:mod:`._step`) sums f_hg into the nodal forces.
"""

import math

import numpy as np
from numba import njit

from impactdyn.constitutive import spin_terms
from impactdyn.wall._blocks import (
    R_B, R_FLOW, R_J, R_QD, R_QN, R_RATIO, R_SHG, R_SPIN, R_VOL, block_vector)
from impactdyn.wall._hex import BLOCK
from impactdyn.wall._options import HOURGLASS_FORMS
from impactdyn.wall._state import SHG_MODE4, SHG_PLANE

#: Codes of the hourglass forms in the kernels (``hg_form``): their index in HOURGLASS_FORMS.
HG_VISCOUS, HG_STIFFNESS, HG_ASSUMED_STRAIN = (HOURGLASS_FORMS.index(name) for name in
                                               ("viscous", "stiffness", "assumed_strain"))


@njit(cache=True, inline="always")
def _dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


@njit(cache=True, inline="always")
def _in_plane(a, n):
    """(I − n⊗n) a: the part of a in the plane normal to the unit vector n."""
    s = _dot(a, n)
    return (a[0] - s * n[0], a[1] - s * n[1], a[2] - s * n[2])



@njit(cache=True, inline="always")
def tangent_ratio(seq_old, seq_new, dep, shear):
    """G_t/G of this step's return mapping: the share of the elastic trial increment of σ_eq kept.

    Both models return radially, σ_eq* = σ_eqⁿ⁺¹ + 3G Δεₚ (the trial value), so

        G_t/G = (σ_eqⁿ⁺¹ − σ_eqⁿ) / (σ_eq* − σ_eqⁿ)

    is 1 in an elastic step, E_h/(3G + E_h) in a step of continued plastic flow with linear
    hardening (the uniaxial tangent E_t/E of an incompressible flow, 3G_t = E_t), between the two
    in a step that reaches the yield surface, and 0 when the yield stress fell (softening).
    """
    if dep <= 0.0:
        return 1.0
    trial = seq_new + 3.0 * shear * dep - seq_old
    if trial <= 0.0:
        return 0.0
    return min(1.0, max(0.0, (seq_new - seq_old) / trial))


@njit(cache=True, inline="always")
def _lam_bar(lam, mu):
    """λ̄ = 2λμ/(λ + 2μ): the plane-stress Lamé modulus."""
    den = lam + 2.0 * mu
    return 2.0 * lam * mu / den if den > 0.0 else 0.0


@njit(cache=True, inline="always")
def _young(lam, mu):
    """E = μ(3λ + 2μ)/(λ + μ)."""
    den = lam + mu
    return mu * (3.0 * lam + 2.0 * mu) / den if den > 0.0 else 0.0


# a plain call from the parallel element pass, once per block (not inlined: inlined, its tuple arithmetic
# upset numba's parfor analysis).  The loops over the block's bricks are innermost, branch-free (selects, no min/max calls)
# and read and write one flat array: they vectorise (3x faster than brick by brick on AVX2).
@njit(cache=True, error_model="numpy")
def assumed_strain_forces(H, dt, lam, shear):
    """The assumed-strain hourglass forces Q_α of the bricks of a block after ``dt``.

    H is the block array of the element pass (:mod:`._blocks`; row r of brick k at r·BLOCK + k):
    in, the reciprocal vectors, hourglass velocities q̇_αi, tangent ratio and flow stress (below),
    spin Δt Ω and volume of each brick; in and out, its stored hourglass stresses (``Shg``'s
    columns); out, its forces Q_αi (rows R_QN + 3α + i).

    Belytschko & Bindeman, "Assumed strain stabilization of the eight node hexahedral element",
    CMAME 105 (1993) 225 (LS-DYNA IHQ 6), derived here for a parallelepiped with edges a, b, c
    along ξ, η, ζ (reciprocal vectors j_m = ∇ξ_m, |j_m| = 2/edge, :func:`._kinematics.reciprocal_vectors`).
    The hourglass part of the displacement is u = Σ_α q_α h_α(ξ, η, ζ), h = ηζ, ζξ, ξη, ξηζ
    (α = 0…3; mode m < 3 lacks coordinate m), with q_α = q̄_α / 8 for FB's q̄_α = Σ_I γ_αI u_I
    (Σ_I γ_αI h_αI = 8).  Its gradient ∇u = Σ_α q_α ⊗ ∇h_α groups by the coordinate ξ_k it
    varies with: for k with the other two coordinates j, l,

        ∇u ∋ ξ_k (q_j ⊗ j_l + q_l ⊗ j_j)        (modes j and l, differentiated along l and j)
           + ξ_jξ_l q_3 ⊗ j_k                     (mode ξηζ)

    Assumed strain (the method's choice): of group k keep the strain in the plane normal to
    j_k, ε_k = P_k sym(q_j ⊗ j_l + q_l ⊗ j_j) P_k, P_k = I − n_k⊗n_k, n_k = j_k/|j_k| — the
    normal (bending) strains and the shear in that plane (twist) — and drop the shear
    components with n_k (the parasitic shear that locks the element in bending); the stress
    normal to n_k is free (σ·n_k = 0: plane stress, which the incompatible modes ξ_k² of
    B&B's QBI element give), so σ_k = λ̄ (tr ε_k) P_k + 2μ ε_k, λ̄ = 2λμ/(λ + 2μ).  Of mode
    ξηζ keep the normal strains e_k = (q_3·j_k) ξ_jξ_l, uniaxial (free in both directions it
    varies in): s_k = E e_k, E = μ(3λ + 2μ)/(λ + μ).  With ∫ξ_k² dV = V/3, ∫(ξ_jξ_l)² dV = V/9
    and the groups orthogonal in L², the hourglass strain energy of an elastic element is

        U = Σ_k [ V/6 ε_k : σ_k  +  V/18 (q_3·j_k) s_k ]

    — the element's exact energy in pure bending (ε ∝ ξ_k, the beam or plate's linear
    variation through its depth) and twisting at any aspect ratio: bending stiffness
    ∝ E V/a², with a the length along the bending fibre, where FB's κ ∝ ΣB²/V grows with the
    largest face.  The generalised forces Q_α = ∂U/∂q̄_α = ⅛ ∂U/∂q_α, written with the stresses:

        Q_j += V/24 σ_k j_l,   Q_l += V/24 σ_k j_j   (over the groups k),
        Q_3  = V/72 Σ_k s_k j_k

    Stored stresses (total form): the element keeps σ_k (6 components, global axes) and s_k
    (``Shg``, :mod:`._state`); each step they are rotated with the element's spin (Jaumann,
    Ω = skew L of the midstep gradient), σ_k projected on the current plane P_k σ_k P_k,
    incremented with Δε_k, Δe_k from Δq = Δt q̇/8, and Q is computed from them with the current
    j_k and V as above.  A linear velocity field has q̇ = 0 (FB's γ), so nothing changes.
    λ = K₀ − 2G/3 is the model's reference (undeformed) Lamé constant, fixed, so the elastic
    moduli do not change with compression.

    Moduli, loading and unloading: μ follows the step's return mapping, μ_t = G·ratio
    (:func:`tangent_ratio`): the hourglass strain is the strain's variation inside the element,
    which in a yielding element loads along with its mean strain at the material's tangent
    (CalculiX's C3D8R scales its hourglass stiffness by the current tangent C₁₁₁₁ likewise);
    with the elastic G the plastically bending plate of verification/verify_wall_calculix.py kept
    its hourglass energy elastic and came out 30 % stiff (0.177 cm against 0.249 at h 0.1).
    The tangent is used only for LOADING increments; unloading uses the elastic moduli, the
    rule of an elastic–hardening spring.  The plane-stress tangent is not proportional to the
    elastic one (λ̄(μ) + μ and μ scale differently), so σ_k is split into its two eigenparts
    under C = λ̄ P⊗P + 2μ 𝕀: the in-plane spherical part ½(tr σ_k) P_k (modulus 2(λ̄ + μ) on
    ½(tr ε) P) and the in-plane deviator (modulus 2μ), and each part is tested on its own:

        spherical:  loading if tr σ_k · tr Δε_k ≥ 0   → λ̄_t + μ_t,   else λ̄_e + G
        deviator:   loading if σ'_k : Δε'_k ≥ 0        → μ_t,         else G
        mode ξηζ:   loading if s_k Δe_k ≥ 0            → E(μ_t),      else E(G)

    (σ_k the stored stress before the increment; a step that crosses zero is an unloading
    step, elastic throughout; from zero stress it loads.)  λ̄(μ) + μ and E(μ) increase with μ,
    so every loading slope is at most its unloading slope.  Why the form cannot create energy:
    for each part, with elastic stiffness c_e and D = W − σ²/(2c_e) (W the work Q·dq done on
    it, σ²/(2c_e) the elastic energy its stress would give back), dD = σ dε (1 − c/c_e): zero
    when unloading (c = c_e), ≥ 0 when loading (σ dε ≥ 0, c ≤ c_e).  So D never decreases:
    from a stress-free start W ≥ σ²/(2c_e) ≥ 0 at every instant, and over any closed path in q
    ∮Q·dq ≥ 0 — at fixed geometry (j_k, V) and up to the time discretisation of the work.  (With
    the element's tangent applied to unloading as well, a mode loaded at G and unloaded at a
    small plastic tangent gave back more than it stored: −10 % of the internal energy as
    hourglass work with mat13, −470 % with johnson_cook, on the synthetic deposition load of
    benchmarks/bench_wall.py; tests/wall/test_hourglass_forms.py drives that cycle.)

    Bounded by the yield stress: in an element that flows in this step (``ratio`` < 1) each
    hourglass stress is scaled back radially onto ``flow``, the element's current flow stress
    σ_eq (after the return mapping): von Mises of σ_k ≤ σ_flow, |s_k| ≤ σ_flow — the stress
    cannot vary across a yielding element by more than the flow stress (an elastic–perfectly
    plastic hourglass stress, the solid counterpart of Radioss's elasto-plastic hourglass
    shells).  Without the bound a mode loaded at G while its element was elastic kept that
    stress after the element yielded and went on deforming: the synthetic load's hourglass
    work reached 25–39 % of the internal energy (mat13).  The scaling only lowers the stored
    energy at fixed work, so the form stays dissipative.  flow = ∞ in an elastic step.
    """
    f = 0.125 * dt
    kb_e = _lam_bar(lam, shear) + shear
    y_e = _young(lam, shear)
    for r in range(R_QN * BLOCK, (R_QN + 12) * BLOCK):
        H[r] = 0.0
    # the groups k = 0, 1, 2 with their other two coordinates (j, l), as literals: constant rows
    for k in range(BLOCK):
        _plane_group(0, 1, 2, k, H, f, lam, shear, kb_e)
    for k in range(BLOCK):
        _plane_group(1, 2, 0, k, H, f, lam, shear, kb_e)
    for k in range(BLOCK):
        _plane_group(2, 0, 1, k, H, f, lam, shear, kb_e)
    # mode ξηζ along j_k: s_k += E Δe_k, Q_3 += V/72 s_k j_k
    for g in range(3):
        rg = (R_J + 3 * g) * BLOCK
        rs = (R_SHG + SHG_MODE4 + g) * BLOCK
        for k in range(BLOCK):
            y_t = _young(lam, shear * H[R_RATIO * BLOCK + k])
            flow = H[R_FLOW * BLOCK + k]
            jg0, jg1, jg2 = H[rg + k], H[rg + BLOCK + k], H[rg + 2 * BLOCK + k]
            e4 = f * (H[(R_QD + 9) * BLOCK + k] * jg0 + H[(R_QD + 10) * BLOCK + k] * jg1
                      + H[(R_QD + 11) * BLOCK + k] * jg2)
            s4 = H[rs + k]
            s4 += (y_t if s4 * e4 >= 0.0 else y_e) * e4
            s4 = s4 if s4 < flow else flow
            s4 = s4 if s4 > -flow else -flow
            H[rs + k] = s4
            w4 = H[R_VOL * BLOCK + k] / 72.0
            H[(R_QN + 9) * BLOCK + k] += w4 * s4 * jg0
            H[(R_QN + 10) * BLOCK + k] += w4 * s4 * jg1
            H[(R_QN + 11) * BLOCK + k] += w4 * s4 * jg2


@njit(cache=True, inline="always")
def _plane_group(g, j, l, k, H, f, lam, shear, kb_e):
    """Group g (other coordinates j, l) of brick k in the flat block array H: its plane-stress
    hourglass stress σ_g rotated, projected, incremented, bounded and stored, and its forces added
    to Q_j and Q_l (:func:`assumed_strain_forces`)."""
    mu_t = shear * H[R_RATIO * BLOCK + k]
    kb_t = _lam_bar(lam, mu_t) + mu_t
    jg = block_vector(H, R_J + 3 * g, k)
    jj = block_vector(H, R_J + 3 * j, k)
    jl = block_vector(H, R_J + 3 * l, k)
    r = 1.0 / math.sqrt(_dot(jg, jg))
    n0, n1, n2 = jg[0] * r, jg[1] * r, jg[2] * r
    n = (n0, n1, n2)
    c0 = (R_SHG + SHG_PLANE + 6 * g) * BLOCK + k
    sxx, syy, szz = H[c0], H[c0 + BLOCK], H[c0 + 2 * BLOCK]
    sxy, syz, szx = H[c0 + 3 * BLOCK], H[c0 + 4 * BLOCK], H[c0 + 5 * BLOCK]
    # rotated with the spin: σ + Δt (Ωσ − σΩ) (as :func:`impactdyn.constitutive.jaumann_rate`)
    wxy, wyz, wxz = block_vector(H, R_SPIN, k)
    rxx, ryy, rzz, rxy, ryz, rzx = spin_terms(sxx, syy, szz, sxy, syz, szx, wxy, wyz, wxz)
    sxx, syy, szz, sxy, syz, szx = sxx + rxx, syy + ryy, szz + rzz, sxy + rxy, syz + ryz, szx + rzx
    # on the current plane: P σ P = σ − n⊗t − t⊗n + (n·t) n⊗n, t = σ n
    t0 = sxx * n0 + sxy * n1 + szx * n2
    t1 = sxy * n0 + syy * n1 + syz * n2
    t2 = szx * n0 + syz * n1 + szz * n2
    tn = t0 * n0 + t1 * n1 + t2 * n2
    sxx += tn * n0 * n0 - 2.0 * n0 * t0
    syy += tn * n1 * n1 - 2.0 * n1 * t1
    szz += tn * n2 * n2 - 2.0 * n2 * t2
    sxy += tn * n0 * n1 - n0 * t1 - t0 * n1
    syz += tn * n1 * n2 - n1 * t2 - t1 * n2
    szx += tn * n2 * n0 - n2 * t0 - t2 * n0
    # the strain increment Δε = sym(a⊗b + c⊗d) of in-plane a = P Δq_j, b = P j_l, c = P Δq_l, d = P j_j
    qj = block_vector(H, R_QD + 3 * j, k)
    ql = block_vector(H, R_QD + 3 * l, k)
    a = _in_plane((f * qj[0], f * qj[1], f * qj[2]), n)
    b = _in_plane(jl, n)
    c = _in_plane((f * ql[0], f * ql[1], f * ql[2]), n)
    d = _in_plane(jj, n)
    exx = a[0] * b[0] + c[0] * d[0]
    eyy = a[1] * b[1] + c[1] * d[1]
    ezz = a[2] * b[2] + c[2] * d[2]
    exy = 0.5 * (a[0] * b[1] + b[0] * a[1] + c[0] * d[1] + d[0] * c[1])
    eyz = 0.5 * (a[1] * b[2] + b[1] * a[2] + c[1] * d[2] + d[1] * c[2])
    ezx = 0.5 * (a[2] * b[0] + b[2] * a[0] + c[2] * d[0] + d[2] * c[0])
    tre = exx + eyy + ezz
    trs = sxx + syy + szz
    # σ':Δε' = σ:Δε − ½ tr σ tr Δε (both in the plane, P:P = 2)
    dev = sxx * exx + syy * eyy + szz * ezz + 2.0 * (sxy * exy + syz * eyz + szx * ezx) - 0.5 * trs * tre
    kb = kb_t if trs * tre >= 0.0 else kb_e
    mu = mu_t if dev >= 0.0 else shear
    # Δσ = (λ̄ + μ)_s tr Δε P + 2μ_d (Δε − ½ tr Δε P)
    cp = (kb - mu) * tre
    sxx += 2.0 * mu * exx + cp * (1.0 - n0 * n0)
    syy += 2.0 * mu * eyy + cp * (1.0 - n1 * n1)
    szz += 2.0 * mu * ezz + cp * (1.0 - n2 * n2)
    sxy += 2.0 * mu * exy - cp * n0 * n1
    syz += 2.0 * mu * eyz - cp * n1 * n2
    szx += 2.0 * mu * ezx - cp * n2 * n0
    mean = (sxx + syy + szz) / 3.0
    dx, dy, dz = sxx - mean, syy - mean, szz - mean
    seq = math.sqrt(1.5 * (dx * dx + dy * dy + dz * dz) + 3.0 * (sxy * sxy + syz * syz + szx * szx))
    # back onto the flow stress: a factor 1 inside it (1.0 · σ is exact)
    back = H[R_FLOW * BLOCK + k] / seq
    back = (back if back < 1.0 else 1.0) if seq > 0.0 else 1.0
    sxx, syy, szz, sxy, syz, szx = back * sxx, back * syy, back * szz, back * sxy, back * syz, back * szx
    H[c0], H[c0 + BLOCK], H[c0 + 2 * BLOCK] = sxx, syy, szz
    H[c0 + 3 * BLOCK], H[c0 + 4 * BLOCK], H[c0 + 5 * BLOCK] = sxy, syz, szx
    # Q_j += V/24 σ j_l, Q_l += V/24 σ j_j (σ in the plane: σ j = σ P j)
    w1 = H[R_VOL * BLOCK + k] / 24.0
    rj, rl = (R_QN + 3 * j) * BLOCK + k, (R_QN + 3 * l) * BLOCK + k
    H[rj] += w1 * (sxx * jl[0] + sxy * jl[1] + szx * jl[2])
    H[rj + BLOCK] += w1 * (sxy * jl[0] + syy * jl[1] + syz * jl[2])
    H[rj + 2 * BLOCK] += w1 * (szx * jl[0] + syz * jl[1] + szz * jl[2])
    H[rl] += w1 * (sxx * jj[0] + sxy * jj[1] + szx * jj[2])
    H[rl + BLOCK] += w1 * (sxy * jj[0] + syy * jj[1] + syz * jj[2])
    H[rl + 2 * BLOCK] += w1 * (szx * jj[0] + syz * jj[1] + szz * jj[2])


@njit(cache=True, inline="always")
def flanagan_belytschko_forces(A, k, hg_form, qh, rho, c, vol, dt):
    """FB's generalised forces Q_αi (rows R_QN + 3α + i) of brick k of the block array A from its
    hourglass velocities (module docstring): the viscous form's force, or the stiffness form's
    increment over ``dt`` (the element pass adds it to the running sum)."""
    if hg_form == HG_STIFFNESS:
        bb = 0.0
        for r in range(24):
            bb += A[(R_B + r) * BLOCK + k] ** 2
        coef = qh * rho * c * c * bb / (3.0 * vol) / 8.0 * dt
    else:
        cb = np.cbrt(vol)
        coef = 0.25 * qh * rho * c * cb * cb
    for r in range(12):
        A[(R_QN + r) * BLOCK + k] = coef * A[(R_QD + r) * BLOCK + k]
