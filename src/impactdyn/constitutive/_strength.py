"""Deviatoric stress: Jaumann rate, von Mises radial return, flow stress, artificial stress.

Symmetric tensors are stored as 6 components in the order (xx, yy, zz, xy, yz, zx).

Hypoelastic stress rate with the Jaumann derivative (Libersky & Petschek 1991,
1993; Gray, Monaghan & Swift 2001, eq. 4)::

    dS/dt = 2G (ε̇ − ⅓ tr(ε̇) I) + Ω S − S Ω,
    ε̇ = ½(L + Lᵀ),   Ω = ½(L − Lᵀ),   L_{αβ} = ∂v_α/∂x_β

Radial return to the von Mises surface (Wilkins 1964), elastic–perfectly-plastic
or with a Johnson–Cook flow stress Y::

    σ_eq = √(3 J₂) = √(3/2 S:S);   if σ_eq > Y:  S ← S·Y/σ_eq,   Δεₚ = (σ_eq − Y)/(3G)

Artificial stress against the tensile instability (Monaghan 2000; Gray,
Monaghan & Swift 2001, §4): in the principal frame of σ = −pI + S,
R'_{aa} = −ε σ'_{aa}/ρ² where σ'_{aa} > 0 (tension), else 0; R = Q R' Qᵀ. The pair
term (Rᵢ + Rⱼ) fᵢⱼⁿ, fᵢⱼ = W(rᵢⱼ)/W(Δp), enters the momentum equation
(:mod:`impactdyn.shield._equations`). Principal axes by cyclic Jacobi rotations.
"""

from __future__ import annotations

import math

from numba import njit

from impactdyn.constitutive._eos import HAS_JC, JC_A, JC_B, JC_C, JC_M, JC_N, JC_RATE0, JC_TMELT, JC_TROOM, YIELD


@njit(cache=True, inline="always")
def spin_terms(sxx, syy, szz, sxy, syz, szx, wxy, wyz, wxz):
    """The spin terms Ω S − S Ω of the Jaumann rate (xx, yy, zz, xy, yz, zx) of a symmetric S
    and the spin Ω with Ω_xy = wxy, Ω_yz = wyz, Ω_xz = wxz (= Ω S + (Ω S)ᵀ)."""
    return (2.0 * (wxy * sxy + wxz * szx), 2.0 * (wyz * syz - wxy * sxy), -2.0 * (wxz * szx + wyz * syz),
            wxy * (syy - sxx) + wxz * syz + wyz * szx, wyz * (szz - syy) - wxy * szx - wxz * sxy,
            wxz * (szz - sxx) - wyz * sxy + wxy * syz)


# not inlined (unlike the functions below): inlined into a prange loop, its nested-tuple result trips numba's
# parfor array analysis (numba 0.68)
@njit(cache=True)
def jaumann_rate(sxx, syy, szz, sxy, syz, szx, L, i, G):
    """dS/dt of particle i from its velocity gradient L[i] (3×3) and shear modulus G.

    Returns (dS (6-tuple), ε̇_eq = √(⅔ ε̇':ε̇')).
    """
    dxx, dyy, dzz = L[i, 0, 0], L[i, 1, 1], L[i, 2, 2]
    dxy = 0.5 * (L[i, 0, 1] + L[i, 1, 0])
    dyz = 0.5 * (L[i, 1, 2] + L[i, 2, 1])
    dzx = 0.5 * (L[i, 2, 0] + L[i, 0, 2])
    wxy = 0.5 * (L[i, 0, 1] - L[i, 1, 0])
    wyz = 0.5 * (L[i, 1, 2] - L[i, 2, 1])
    wxz = 0.5 * (L[i, 0, 2] - L[i, 2, 0])
    tr3 = (dxx + dyy + dzz) / 3.0
    exx, eyy, ezz = dxx - tr3, dyy - tr3, dzz - tr3
    rxx, ryy, rzz, rxy, ryz, rzx = spin_terms(sxx, syy, szz, sxy, syz, szx, wxy, wyz, wxz)
    rate = math.sqrt(2.0 / 3.0 * (exx * exx + eyy * eyy + ezz * ezz + 2.0 * (dxy * dxy + dyz * dyz + dzx * dzx)))
    return ((2.0 * G * exx + rxx, 2.0 * G * eyy + ryy, 2.0 * G * ezz + rzz,
             2.0 * G * dxy + rxy, 2.0 * G * dyz + ryz, 2.0 * G * dzx + rzx), rate)


# inline="always": called per particle in the parallel kernels with array arguments; as calls, passing the
# arrays cost about as much as the work (the predictor ran twice as long)
@njit(cache=True, inline="always")
def von_mises(S, i):
    """σ_eq = √(3/2 S:S) of S[i] (6 components)."""
    return math.sqrt(1.5 * (S[i, 0] ** 2 + S[i, 1] ** 2 + S[i, 2] ** 2)
                     + 3.0 * (S[i, 3] ** 2 + S[i, 4] ** 2 + S[i, 5] ** 2))


@njit(cache=True, inline="always")
def radial_return(S, i, Y, G):
    """Scale S[i] back onto σ_eq = Y when it lies outside; returns the plastic-strain increment."""
    seq = von_mises(S, i)
    if seq <= Y:
        return 0.0
    scale = Y / seq
    for k in range(6):
        S[i, k] *= scale
    return (seq - Y) / (3.0 * G)


@njit(cache=True, inline="always")
def flow_stress(params, k, johnson_cook, eps_p, rate, T):
    """Flow stress Y, Mbar, of material k of the table ``params`` (:mod:`._eos` columns).

    Elastic–perfectly-plastic: Y = Y₀. Johnson–Cook, when requested and material
    k has parameters (Johnson & Cook 1983)::

        Y = (A + B εₚⁿ)(1 + C ln max(ε̇/ε̇₀, 1))(1 − T*ᵐ),  T* = clip((T − T_r)/(T_m − T_r), 0, 1)
    """
    if not johnson_cook or params[k, HAS_JC] == 0.0:
        return params[k, YIELD]
    tstar = min(max((T - params[k, JC_TROOM]) / (params[k, JC_TMELT] - params[k, JC_TROOM]), 0.0), 1.0)
    # εₚ = 0 (an element or particle that has not yielded): no pow() call, the same value (0ⁿ = 0, n > 0)
    hardening = params[k, JC_A] + (params[k, JC_B] * eps_p ** params[k, JC_N] if eps_p > 0.0 else 0.0)
    rate_term = 1.0 + params[k, JC_C] * math.log(max(rate / params[k, JC_RATE0], 1.0))
    return hardening * rate_term * (1.0 - tstar ** params[k, JC_M])


@njit(cache=True, inline="always")
def flow_stress_floor(params, k, T_upper):
    """A lower bound of the Johnson–Cook :func:`flow_stress` of material k over every εₚ ≥ 0 and
    strain rate, at any temperature T ≤ ``T_upper``, with no pow() or log() call.

    B ≥ 0 and C ≥ 0 give (A + B εₚⁿ)(1 + C ln max(ε̇*, 1)) ≥ A; for m ≥ 1, T*ᵐ ≤ T* ≤ T*_upper
    gives 1 − T*ᵐ ≥ 1 − T*_upper.  For m < 1 the bound is A at T*_upper = 0 and 0 above it.
    """
    tstar = min(max((T_upper - params[k, JC_TROOM]) / (params[k, JC_TMELT] - params[k, JC_TROOM]), 0.0), 1.0)
    if params[k, JC_M] >= 1.0:
        return params[k, JC_A] * (1.0 - tstar)
    return params[k, JC_A] if tstar == 0.0 else 0.0


@njit(cache=True, inline="always")
def _jacobi_eigh(a, v, i):
    """Eigen-decomposition of the symmetric 3×3 a[i] in place: a[i] → diag(λ), v[i] → eigenvectors (columns)."""
    for r in range(3):
        for k in range(3):
            v[i, r, k] = 1.0 if r == k else 0.0
    scale = a[i, 0, 0] ** 2 + a[i, 1, 1] ** 2 + a[i, 2, 2] ** 2 + a[i, 0, 1] ** 2 + a[i, 1, 2] ** 2 + a[i, 0, 2] ** 2
    for _ in range(32):
        if a[i, 0, 1] ** 2 + a[i, 0, 2] ** 2 + a[i, 1, 2] ** 2 <= 1e-30 * scale:
            return
        for p, q in ((0, 1), (0, 2), (1, 2)):
            apq = a[i, p, q]
            if apq == 0.0:
                continue
            theta = (a[i, q, q] - a[i, p, p]) / (2.0 * apq)
            t = math.copysign(1.0, theta) / (abs(theta) + math.sqrt(theta * theta + 1.0))
            c = 1.0 / math.sqrt(t * t + 1.0)
            s = t * c
            a[i, p, p] -= t * apq
            a[i, q, q] += t * apq
            a[i, p, q] = 0.0
            a[i, q, p] = 0.0
            r = 3 - p - q
            arp, arq = a[i, r, p], a[i, r, q]
            a[i, r, p] = a[i, p, r] = c * arp - s * arq
            a[i, r, q] = a[i, q, r] = s * arp + c * arq
            for k in range(3):
                vkp, vkq = v[i, k, p], v[i, k, q]
                v[i, k, p] = c * vkp - s * vkq
                v[i, k, q] = s * vkp + c * vkq


@njit(cache=True, inline="always")
def artificial_stress(S, p, rho, eps, i, R, a, v):
    """R[i] = −ε/ρ² · (tensile part of σ = −pI + S[i]) (Gray, Monaghan & Swift 2001).

    ``a``, ``v``: (N, 3, 3) scratch; a[i], v[i] receive σ's principal values and axes.
    Returns whether σ has a tensile principal value (R[i] ≠ 0).
    """
    for k in range(6):
        R[i, k] = 0.0
    # largest principal stress ≤ −p + √(2/3)|S| (S traceless): no tension, no Jacobi
    if math.sqrt(2.0 / 3.0 * (S[i, 0] ** 2 + S[i, 1] ** 2 + S[i, 2] ** 2
                              + 2.0 * (S[i, 3] ** 2 + S[i, 4] ** 2 + S[i, 5] ** 2))) <= p:
        return False
    a[i, 0, 0], a[i, 1, 1], a[i, 2, 2] = S[i, 0] - p, S[i, 1] - p, S[i, 2] - p
    a[i, 0, 1] = a[i, 1, 0] = S[i, 3]
    a[i, 1, 2] = a[i, 2, 1] = S[i, 4]
    a[i, 0, 2] = a[i, 2, 0] = S[i, 5]
    _jacobi_eigh(a, v, i)
    f = -eps / (rho * rho)
    tensile = False
    for k in range(3):
        lam = a[i, k, k]
        if lam > 0.0:
            tensile = True
            r = f * lam
            R[i, 0] += r * v[i, 0, k] * v[i, 0, k]
            R[i, 1] += r * v[i, 1, k] * v[i, 1, k]
            R[i, 2] += r * v[i, 2, k] * v[i, 2, k]
            R[i, 3] += r * v[i, 0, k] * v[i, 1, k]
            R[i, 4] += r * v[i, 1, k] * v[i, 2, k]
            R[i, 5] += r * v[i, 2, k] * v[i, 0, k]
    return tensile
