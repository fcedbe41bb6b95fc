"""Mie–Grüneisen equation of state about a linear Us–up Hugoniot, and the packed material table.

With μ = ρ/ρ₀ − 1 and Γρ = Γ₀ρ₀ (the usual constant-ρΓ assumption; Steinberg
1991; the LS-DYNA ``*EOS_GRUNEISEN`` form with a = 0)::

    p(ρ, e) = ρ₀c₀²μ [1 + (1 − Γ₀/2) μ] / [1 − (s − 1) μ]² + Γ₀ρ₀ e     μ ≥ 0 (compression)
    p(ρ, e) = ρ₀c₀²μ + Γ₀ρ₀ e                                          μ < 0 (tension)

The compression branch is p_H(ρ) + Γ₀ρ₀ (e − e_H(ρ)) with the Hugoniot
p_H = ρ₀c₀²μ(1 + μ)/[1 − (s − 1)μ]² and e_H = p_H μ / (2ρ₀(1 + μ)) of
Us = c₀ + s up, so (ρ_H, e_H) gives p_H exactly. The tension branch is the linear
(bulk-modulus ρ₀c₀²) extension, continuous with its slope at μ = 0.

Isentropic sound speed c² = (∂p/∂ρ)_e + (p/ρ²)(∂p/∂e)_ρ::

    c² = A'(μ)/ρ₀ + Γ₀ρ₀ p/ρ²,   A(μ) = p(ρ, 0),
    A'(μ) = ρ₀c₀² [N'(μ) D + 2 (s − 1) N(μ)] / D³,   N = μ[1 + (1 − Γ₀/2)μ], D = 1 − (s − 1)μ

floored at (c₀/10)², a floor reached only in tension far beyond any spall strength.

Temperature (constant c_v, the same Γρ = Γ₀ρ₀): relative to the isentrope
through (ρ₀, e = 0, T_room), along which de = −p dV and T_s = T_room exp(Γ₀μ/(1 + μ)),

    T = T_s(μ) + max(e − e_s(μ), 0)/c_v     μ > 0,
    T = T_room + max(e, 0)/c_v              μ ≤ 0,

e_s(μ) being the cold compression energy (de_s/dμ = p(μ, e_s)/(ρ₀(1 + μ)²),
e_s(0) = 0), integrated once per material and tabulated. Expanded material uses
the second form because the density of failed, expanding particles is a bulk
density of fragments, not the material's (:mod:`impactdyn.shield._equations`).

Material table: the kernels read material parameters from a float64 array
``params`` (n_materials, N_PARAMS + N_COLD) with the column indices below, the
cold-energy table e_s(μ) at μ = k·MU_COLD/(N_COLD − 1) in the last N_COLD
columns; absent criteria are stored as +inf.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
from numba import njit

from impactdyn.materials import Material

(RHO0, C0, SLOPE, GAMMA0, SHEAR, YIELD, CV, P_SPALL, EPS_FAIL,
 JC_A, JC_B, JC_N, JC_C, JC_M, JC_TMELT, JC_TROOM, JC_RATE0, HAS_JC) = range(18)
N_PARAMS = 18
N_COLD = 129
MU_COLD = 1.5  # the table's range of μ; beyond it e_s is held at its last value

#: Room temperature of the temperature estimate, K.
T_ROOM = 294.0


def pack_materials(materials: Sequence[Material]) -> np.ndarray:
    """The kernels' material table (n, N_PARAMS) of ``materials`` (index = material id)."""
    table = np.zeros((len(materials), N_PARAMS + N_COLD))
    for k, mat in enumerate(materials):
        row = table[k]
        row[[RHO0, C0, SLOPE, GAMMA0, SHEAR, YIELD, CV]] = (
            mat.rho0, mat.c0, mat.s, mat.gamma0, mat.shear_modulus, mat.yield_stress, mat.specific_heat)
        row[P_SPALL] = math.inf if mat.spall_strength is None else mat.spall_strength
        row[EPS_FAIL] = math.inf if mat.failure_strain is None else mat.failure_strain
        jc = mat.johnson_cook
        if jc is not None:
            row[[JC_A, JC_B, JC_N, JC_C, JC_M, JC_TMELT, JC_TROOM, JC_RATE0, HAS_JC]] = (
                jc.A, jc.B, jc.n, jc.C, jc.m, jc.t_melt, jc.t_room, jc.reference_strain_rate, 1.0)
        row[N_PARAMS:] = _cold_energy(mat)
    return table


def _cold_energy(mat: Material, substeps: int = 32) -> np.ndarray:
    """e_s(μ) at the N_COLD table points: RK4 of de/dμ = p(μ, e)/(ρ₀(1 + μ)²), e(0) = 0 (:func:`isentrope_step`)."""
    h = MU_COLD / ((N_COLD - 1) * substeps)
    out = np.zeros(N_COLD)
    mu = e = 0.0
    for k in range(1, N_COLD):
        for _ in range(substeps):
            e = isentrope_step(mu, e, h, mat.rho0, mat.c0, mat.s, mat.gamma0)
            mu += h
        out[k] = e
    return out


@njit(cache=True)
def pressure(rho, e, rho0, c0, s, gamma0):
    """Mie–Grüneisen pressure p(ρ, e), Mbar (module docstring)."""
    mu = rho / rho0 - 1.0
    k = rho0 * c0 * c0
    if mu >= 0.0:
        d = 1.0 - (s - 1.0) * mu
        ref = k * mu * (1.0 + (1.0 - 0.5 * gamma0) * mu) / (d * d)
    else:
        ref = k * mu
    return ref + gamma0 * rho0 * e


@njit(cache=True)
def _isentrope_rate(mu, e, rho0, c0, s, gamma0):
    """de/dμ = p(μ, e)/(ρ₀(1 + μ)²) along an isentrope (de = −p dV)."""
    return pressure(rho0 * (1.0 + mu), e, rho0, c0, s, gamma0) / (rho0 * (1.0 + mu) ** 2)


@njit(cache=True)
def isentrope_step(mu, e, h, rho0, c0, s, gamma0):
    """e after one RK4 step of length h in μ along the isentrope through (μ, e): the cold curve's table
    here, the release to zero pressure in :mod:`._phase`."""
    k1 = _isentrope_rate(mu, e, rho0, c0, s, gamma0)
    k2 = _isentrope_rate(mu + 0.5 * h, e + 0.5 * h * k1, rho0, c0, s, gamma0)
    k3 = _isentrope_rate(mu + 0.5 * h, e + 0.5 * h * k2, rho0, c0, s, gamma0)
    k4 = _isentrope_rate(mu + h, e + h * k3, rho0, c0, s, gamma0)
    return e + h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4)


@njit(cache=True)
def sound_speed(rho, p, rho0, c0, s, gamma0):
    """Isentropic sound speed c(ρ, p), cm/µs, floored at c₀/10 (module docstring)."""
    mu = rho / rho0 - 1.0
    k = rho0 * c0 * c0
    if mu >= 0.0:
        d = 1.0 - (s - 1.0) * mu
        n = mu * (1.0 + (1.0 - 0.5 * gamma0) * mu)
        dn = 1.0 + 2.0 * (1.0 - 0.5 * gamma0) * mu
        dref = k * (dn * d + 2.0 * (s - 1.0) * n) / (d * d * d)
    else:
        dref = k
    c2 = dref / rho0 + gamma0 * rho0 * p / (rho * rho)
    return math.sqrt(max(c2, 0.01 * c0 * c0))


# inline="always": called per particle in the SPH kernels with array arguments; as calls, passing the
# arrays cost about as much as the work (the predictor ran twice as long)
@njit(cache=True, inline="always")
def temperature(rho, e, params, k):
    """Temperature estimate of material k at (ρ, e), K (module docstring).

    Used for Johnson–Cook thermal softening and the HydroGrid's temperature field.
    """
    mu = rho / params[k, RHO0] - 1.0
    if mu <= 0.0:
        return T_ROOM + max(e, 0.0) / params[k, CV]
    e_s = _cold_energy_at(mu, params, k)
    return T_ROOM * math.exp(params[k, GAMMA0] * mu / (1.0 + mu)) + max(e - e_s, 0.0) / params[k, CV]


@njit(cache=True, inline="always")
def temperature_bound(rho, e, params, k):
    """An upper bound of :func:`temperature` without its exp(): exp(x) ≤ 1/(1 − x) for 0 ≤ x < 1
    (x = Γ₀μ/(1 + μ)); +inf where x ≥ 1.  For cheap tests that need T only when it is high."""
    mu = rho / params[k, RHO0] - 1.0
    if mu <= 0.0:
        return T_ROOM + max(e, 0.0) / params[k, CV]
    x = params[k, GAMMA0] * mu / (1.0 + mu)
    if x >= 1.0:
        return np.inf
    return T_ROOM / (1.0 - x) + max(e - _cold_energy_at(mu, params, k), 0.0) / params[k, CV]


@njit(cache=True, inline="always")
def _cold_energy_at(mu, params, k):
    """e_s(μ), μ > 0, interpolated in the material's table (module docstring)."""
    x = min(mu, MU_COLD) / MU_COLD * (N_COLD - 1)
    j = min(int(x), N_COLD - 2)
    w = x - j
    return (1.0 - w) * params[k, N_PARAMS + j] + w * params[k, N_PARAMS + j + 1]
