"""Failure laws shared by the solvers: the floored Johnson–Cook fracture strain and Tuler–Butcher spall.

Pure scalar functions, inlined into the material kernels (the wall's
:func:`impactdyn.wall._johnson_cook.jc_update`; the SPH shield stage can call the same).
Units as the package: Mbar, µs.
"""

import math

from numba import njit


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
