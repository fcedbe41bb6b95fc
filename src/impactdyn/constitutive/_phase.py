"""Melt and vapour on release: each state released along its isentrope to zero pressure, its phase
judged there with the latent heats.

A shocked state that is released keeps its entropy; what it is once the debris is at ambient pressure
(solid, liquid, vapour) is decided by its energy at p = 0 (the 1-D incipient- and complete-melt
criteria of shock physics: Ahrens & O'Keefe 1972; the MMOD handbook, NASA/TM-2009-214785 §4.2.1).
Two steps:

1. **Release.** Along the isentrope de = −p dV of the Mie–Grüneisen EOS (:mod:`._eos`), written in
   μ = ρ/ρ₀ − 1 as de/dμ = p(μ, e) / (ρ₀ (1 + μ)²), integrated (RK4, :func:`~._eos.isentrope_step`, steps
   of Δμ ≤ ``RELEASE_STEP``) from the state down to where p = 0 (the last step's length found by the
   secant method on p).  A state with p ≤ 0 is already released: its e is its energy at ambient
   pressure (a failed, expanded particle's density is the bulk density of its debris, not the
   material's; its material is at p ≈ 0).
2. **Phase.** The released energy e_r against the energies at ambient pressure (constant c_v, T from
   T_room as :func:`~impactdyn.constitutive.temperature` for μ ≤ 0)::

       e₁ = c_v (T_sol − T_room)                    melting begins (solidus)
       e₂ = c_v (T_liq − T_room) + L_f              melting complete (liquidus, latent heat of fusion)
       e₃ = e₂ + c_v (T_b − T_liq)                  boiling begins
       e₄ = e₃ + L_v                                boiling complete

   the liquid-and-vapour share (melted) χ_m = clip((e_r − e₁)/(e₂ − e₁), 0, 1), the vapour share
   χ_v = clip((e_r − e₃)/(e₄ − e₃), 0, 1), and the released temperature, held on the melting range
   and at T_b while the latent heats are absorbed.

Without the latent heat (the temperature estimate alone), every joule above e₁ would raise T: the
old flag T ≥ T_m counted a state as melted from e₁, where melting only begins.  The phase data are
:class:`impactdyn.materials.PhaseChange`; :func:`pack_phases` is their table.  The melting range is
that at ambient pressure, so the judgement holds on release, not in the shocked state (the melting
point rises steeply with pressure).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numba import njit, prange

from impactdyn.constitutive._eos import C0, CV, GAMMA0, RHO0, SLOPE, T_ROOM, isentrope_step, pressure
from impactdyn.materials import Material

#: Columns of the phase table (:func:`pack_phases`): solidus, liquidus, boiling point (K), latent heats of
#: fusion and vaporisation (cm²/µs²), and a flag (0: no phase data, never melted).
PH_SOLIDUS, PH_LIQUIDUS, PH_BOILING, PH_FUSION, PH_VAPOUR, PH_HAS = range(6)
N_PHASE = 6
#: Step in μ of the release integration (RK4; tests/shield/test_planar_thermodynamics.py compares it with scipy's
#: adaptive integration of the same isentrope).
RELEASE_STEP = 0.01


def pack_phases(materials: Sequence[Material]) -> np.ndarray:
    """The phase table (n, N_PHASE) of ``materials`` (index = material id); flag 0 where a material has no
    :attr:`~impactdyn.materials.Material.phase`."""
    table = np.zeros((len(materials), N_PHASE))
    for k, mat in enumerate(materials):
        ph = mat.phase
        if ph is not None:
            table[k] = (ph.solidus, ph.liquidus, ph.boiling, ph.latent_fusion, ph.latent_vaporisation, 1.0)
    return table


@njit(cache=True)
def released_energy(rho, e, params, k):
    """The specific energy at p = 0 on the isentrope through (ρ, e) of material k (module docstring).

    Steps of −``RELEASE_STEP`` in μ until p ≤ 0; the last step's length is then found by the secant
    method on p (4 iterations, each an RK4 step from the step's start), so the end lies on p = 0.
    """
    rho0, c0, s, gamma0 = params[k, RHO0], params[k, C0], params[k, SLOPE], params[k, GAMMA0]
    p = pressure(rho, e, rho0, c0, s, gamma0)
    if p <= 0.0:
        return e
    mu = rho / rho0 - 1.0
    while mu > -0.9:  # the isentrope reaches p = 0 near μ = −Γ₀e/c₀²: far above −0.9 for any debris
        e_next = isentrope_step(mu, e, -RELEASE_STEP, rho0, c0, s, gamma0)
        p_next = pressure(rho0 * (1.0 + mu - RELEASE_STEP), e_next, rho0, c0, s, gamma0)
        if p_next <= 0.0:
            h_lo, p_lo, h_hi, p_hi = 0.0, p, -RELEASE_STEP, p_next
            for _ in range(4):
                h = h_lo + (h_hi - h_lo) * p_lo / (p_lo - p_hi)
                e_h = isentrope_step(mu, e, h, rho0, c0, s, gamma0)
                p_h = pressure(rho0 * (1.0 + mu + h), e_h, rho0, c0, s, gamma0)
                if p_h > 0.0:
                    h_lo, p_lo = h, p_h
                else:
                    h_hi, p_hi = h, p_h
            return e_h
        mu, e, p = mu - RELEASE_STEP, e_next, p_next
    return e


@njit(cache=True)
def phase_of_released(e_r, params, phases, k):
    """(T_r, melted share χ_m, vapour share χ_v) of material k at the released energy e_r (module
    docstring); a material without phase data: (T_room + e_r/c_v, 0, 0)."""
    cv = params[k, CV]
    e_th = max(e_r, 0.0)
    if phases[k, PH_HAS] == 0.0:
        return T_ROOM + e_th / cv, 0.0, 0.0
    t_sol, t_liq, t_b = phases[k, PH_SOLIDUS], phases[k, PH_LIQUIDUS], phases[k, PH_BOILING]
    e1 = cv * (t_sol - T_ROOM)
    e2 = cv * (t_liq - T_ROOM) + phases[k, PH_FUSION]
    e3 = e2 + cv * (t_b - t_liq)
    e4 = e3 + phases[k, PH_VAPOUR]
    melted = min(max((e_th - e1) / (e2 - e1), 0.0), 1.0)
    vapour = min(max((e_th - e3) / (e4 - e3), 0.0), 1.0)
    if e_th <= e1:
        t = T_ROOM + e_th / cv
    elif e_th <= e2:
        t = t_sol + (t_liq - t_sol) * melted
    elif e_th <= e3:
        t = t_liq + (e_th - e2) / cv
    elif e_th <= e4:
        t = t_b
    else:
        t = t_b + (e_th - e4) / cv
    return t, melted, vapour


@njit(parallel=True, cache=True)
def release_states(rho, e, material, params, phases):
    """For every state i: (released energy, released temperature, melted share, vapour share) arrays."""
    n = rho.size
    e_r, t_r, melted, vapour = np.empty(n), np.empty(n), np.empty(n), np.empty(n)
    for i in prange(n):
        k = material[i]
        e_r[i] = released_energy(rho[i], e[i], params, k)
        t_r[i], melted[i], vapour[i] = phase_of_released(e_r[i], params, phases, k)
    return e_r, t_r, melted, vapour
