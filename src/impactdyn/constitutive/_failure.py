"""Failure laws shared by the solvers: the floored Johnson–Cook fracture strain, Tuler–Butcher spall,
and the tensile (Grady–Kipp, flaws per unit volume) and ductile damage of the SPH shield stage's
fragmentation.

Pure scalar functions, inlined into the material kernels (the wall's
:func:`impactdyn.wall._johnson_cook.jc_update`, the SPH shield stage's
:mod:`impactdyn.shield._equations`), and :func:`pack_damage`, the damage constants' table those
kernels read.  Units as the package: cm, g, µs, Mbar.
"""

import math
from collections.abc import Sequence

import numpy as np
from numba import njit

from impactdyn.materials import Material

#: Columns of the damage table (:func:`pack_damage`): Weibull k (cm⁻³) and m, Young's modulus E
#: (Mbar), crack-growth speed c_g (cm/µs), Johnson–Cook D1…D5 and ε_f,min, and two flags.
(DM_K, DM_M, DM_YOUNG, DM_GROWTH, DM_D1, DM_D2, DM_D3, DM_D4, DM_D5, DM_EFMIN, DM_HAS_WEIBULL,
 DM_HAS_DUCTILE) = range(12)
N_DAMAGE = 12

#: Stress triaxiality below which no ductile fracture occurs: σ* = −1/3 (Bao & Wierzbicki,
#: *On the cut-off value of negative triaxiality for fracture*, Eng. Fract. Mech. 72 (2005) 1049).
#: Below it the Johnson–Cook damage of the shield stage does not accumulate: compression does not
#: break metal.
TRIAXIALITY_CUTOFF = -1.0 / 3.0


def pack_damage(materials: Sequence[Material]) -> np.ndarray:
    """The damage table (n, N_DAMAGE) of ``materials`` (index = material id): each material's
    :attr:`~impactdyn.materials.Material.weibull_flaws`, its
    :attr:`~impactdyn.materials.Material.johnson_cook_damage` (floor ε_f,min where the alloy has one, else 0),
    E and c_g (:attr:`~impactdyn.materials.Material.young_modulus`, :attr:`~impactdyn.materials.Material.crack_speed`).
    A material without such data has its flag 0 (no such damage)."""
    table = np.zeros((len(materials), N_DAMAGE))
    for k, mat in enumerate(materials):
        row = table[k]
        row[DM_YOUNG], row[DM_GROWTH] = mat.young_modulus, mat.crack_speed
        flaws = mat.weibull_flaws
        if flaws is not None:
            row[[DM_K, DM_M, DM_HAS_WEIBULL]] = flaws.k, flaws.m, 1.0
        ductile = mat.johnson_cook_damage
        if ductile is not None:
            row[[DM_D1, DM_D2, DM_D3, DM_D4, DM_D5, DM_HAS_DUCTILE]] = (
                ductile.D1, ductile.D2, ductile.D3, ductile.D4, ductile.D5, 1.0)
            row[DM_EFMIN] = ductile.efmin or 0.0
    return table


@njit(cache=True, inline="always")
def largest_principal_stress(p, sxx, syy, szz, sxy, syz, szx):
    """σ₁, the largest principal stress of σ = −pI + S (S deviatoric), in closed form::

        J₂ = ½ S:S,  J₃ = det S,  cos 3θ = (3√3/2) J₃ / J₂^{3/2},  σ₁ = −p + 2 √(J₂/3) cos θ

    (θ ∈ [0, π/3]: the largest root of the deviator's characteristic equation).  Near a double root
    (cos 3θ → ±1) arccos costs half the digits: the error is O(√ε_machine) ≈ 10⁻⁸ of the deviator's
    size, far below what the damage law resolves.
    """
    j2 = 0.5 * (sxx * sxx + syy * syy + szz * szz) + sxy * sxy + syz * syz + szx * szx
    size = j2 * math.sqrt(j2)
    if size == 0.0:  # no deviator (or one so small that J₂^{3/2} underflows)
        return -p
    j3 = (sxx * (syy * szz - syz * syz) - sxy * (sxy * szz - syz * szx) + szx * (sxy * syz - syy * szx))
    c3 = min(max(1.5 * math.sqrt(3.0) * j3 / size, -1.0), 1.0)
    return -p + 2.0 * math.sqrt(j2 / 3.0) * math.cos(math.acos(c3) / 3.0)


#: Columns of a particle's flaw record (:func:`grady_kipp_damage`): the largest tensile strain so far
#: ε_max, and the moments M₀ … M₃ of its activated flaws (cm⁻³·µsᵏ).
FLAW_STRAIN, FLAW_M0, FLAW_M1, FLAW_M2, FLAW_M3 = range(5)
N_FLAW = 5


@njit(cache=True, inline="always")
def grady_kipp_damage(flaws, i, strain, k, m, growth_speed, dt):
    """Tensile damage from flaws per unit volume (Grady & Kipp 1980, the continuum form), after a step Δt
    under the tensile strain ε; updates the flaw record flaws[i] (``FLAW_*``) and returns D.

    n(ε) = k εᵐ flaws per unit volume activate as the largest tensile strain ε_max so far passes their
    strain; a flaw's crack grows at c_g (``growth_speed``) while the strain is at or above the flaw's
    activation strain (Benz & Asphaug, Icarus 107 (1994) 98: the flaws active at the current strain
    grow).  The moments keep all activated flaws together, so the rule is applied to them together:
    they grow while ε ≥ ε_a = 2^{−1/m} ε_max, the median activation strain of the flaws activated so far
    (n(ε_a) = n(ε_max)/2; 0.97 ε_max for m = 23, where their strains lie within a few per cent of
    ε_max).  With τ the time they have grown since activation, the cracks' volume per unit volume is
    the damage::

        D = (4π/3) c_g³ M₃,   M_j(τ) = ∫ (τ − τ')ʲ dn(τ')

    advanced exactly for the flaws already active (dM₃/dt = 3M₂, dM₂/dt = 2M₁, dM₁/dt = M₀ = n) and with
    the step's new flaws Δn activated at mid-step.  Under the ramp ε = ε̇t this is Grady & Kipp's
    D = 8π c_g³ k ε̇ᵐ t^{m+3} / ((m+1)(m+2)(m+3)).  Nothing here depends on the particle's size: a
    finer particle is neither weaker nor stronger (the Weibull size effect belongs to specimens, whose
    volume a particle is not).  The cracks do not grow below ε_a (nor in compression) and D never heals.
    """
    new = 0.0
    if strain > flaws[i, FLAW_STRAIN]:
        new = max(k * strain ** m - flaws[i, FLAW_M0], 0.0)
        flaws[i, FLAW_STRAIN] = strain
    if strain > 0.0 and strain >= 0.5 ** (1.0 / m) * flaws[i, FLAW_STRAIN]:
        m0, m1, m2 = flaws[i, FLAW_M0], flaws[i, FLAW_M1], flaws[i, FLAW_M2]
        half = 0.5 * dt
        flaws[i, FLAW_M3] += dt * (3.0 * m2 + dt * (3.0 * m1 + dt * m0)) + new * half * half * half
        flaws[i, FLAW_M2] += dt * (2.0 * m1 + dt * m0) + new * half * half
        flaws[i, FLAW_M1] += dt * m0 + new * half
    flaws[i, FLAW_M0] += new
    return min(1.0, 4.0 * math.pi / 3.0 * growth_speed ** 3 * flaws[i, FLAW_M3])


@njit(cache=True, inline="always")
def ductile_damage_increment(table, k, plastic_increment, triaxiality, rate_ratio, tstar):
    """The Johnson–Cook damage increment Δεₚ/ε_f of material k (:func:`fracture_strain` with the
    table's floor), zero below the triaxiality cut-off σ* = −1/3 (:data:`TRIAXIALITY_CUTOFF`) and for
    a material without Johnson–Cook damage constants."""
    if plastic_increment <= 0.0 or triaxiality <= TRIAXIALITY_CUTOFF or table[k, DM_HAS_DUCTILE] == 0.0:
        return 0.0
    eps_f, _ = fracture_strain(table[k, DM_D1], table[k, DM_D2], table[k, DM_D3], table[k, DM_D4],
                               table[k, DM_D5], triaxiality, rate_ratio, tstar, table[k, DM_EFMIN])
    return plastic_increment / eps_f


@njit(cache=True, inline="always")
def fracture_strain(d1, d2, d3, d4, d5, triaxiality, rate_ratio, tstar, efmin):
    """Johnson–Cook fracture strain with a floor (Johnson & Cook, Eng. Fract. Mech. 21 (1985) 31, eq. 2)::

        ε_f = max(D1 + D2 exp(D3 σ*), ε_f,min) [1 + D4 ln max(ε̇*, 1)] [1 + D5 T*]

    σ* = ``triaxiality`` (mean stress over von Mises stress, positive in tension), ε̇* =
    ``rate_ratio`` (ε̇/ε̇₀), T* = ``tstar`` (homologous temperature, in [0, 1]).  ε_f,min =
    ``efmin`` holds the bracket where the fit falls below it (beyond its data); the product is
    bounded by it too, so that ε_f > 0 for any D4, D5.  Returns (ε_f, at_floor), at_floor when the
    fit's bracket was at or below the floor.
    """
    fit = d1 + d2 * math.exp(d3 * triaxiality)
    eps_f = max(fit, efmin) * (1.0 + d4 * math.log(max(rate_ratio, 1.0))) * (1.0 + d5 * tstar)
    return max(eps_f, efmin), fit <= efmin


@njit(cache=True, inline="always")
def tuler_butcher_rate(stress, sigma0, lam):
    """The Tuler–Butcher damage rate max(0, σ_t − σ₀)^λ (Tuler & Butcher, Int. J. Fract. Mech. 4 (1968) 431).

    ``stress`` the tensile stress σ_t, ``sigma0`` the threshold σ₀ (Mbar); Mbar^λ.
    """
    over = stress - sigma0
    return over ** lam if over > 0.0 else 0.0


@njit(cache=True, inline="always")
def tuler_butcher_increment(stress_old, stress_new, sigma0, lam, dt):
    """The increment of ∫ max(0, σ_t − σ₀)^λ dt over a step Δt, by the trapezoidal rule.

    σ_t at the step's start (``stress_old``) and end (``stress_new``); second-order in Δt
    (the damage integral of a linear ramp is exact to O(Δt²)).  Mbar^λ·µs.
    """
    return 0.5 * dt * (tuler_butcher_rate(stress_old, sigma0, lam) + tuler_butcher_rate(stress_new, sigma0, lam))
