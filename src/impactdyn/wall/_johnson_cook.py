"""Wall model ``"johnson_cook"``: Johnson–Cook strength, Mie–Grüneisen EOS, JC damage, spall, erosion.

The modern alternative to the report's type-13 card (DESIGN §9), built on the shared
constitutive kernels of :mod:`impactdyn.constitutive` (the SPH shield stage's EOS and
strength code) and the library material's constants.  Per element and step::

    S* = Sⁿ + Δt [2G d' + ΩSⁿ − SⁿΩ]                                  (Jaumann rate)
    Y = (A + B εₚⁿ)(1 + C ln max(ε̇/ε̇₀, 1))(1 − T*ᵐ)                    (Johnson & Cook 1983)
    σ_eq* > Y:  Sⁿ⁺¹ = S* Y/σ_eq*,  Δεₚ = (σ_eq* − Y)/(3G)              (radial return)
    p = p_MG(ρ, e) = A_MG(ρ) + Γ₀ρ₀ e                                  (Mie–Grüneisen)

ε̇ is the equivalent deviatoric strain rate √(⅔ d':d') (as the SPH stage uses it), T the
temperature estimate of :func:`impactdyn.constitutive.temperature` from (ρ, e) (all
work heats; Taylor–Quinney factor 1).  Y and T are evaluated only where σ_eq* exceeds
:func:`impactdyn.constitutive.flow_stress_floor`, a lower bound of Y without exp, log or pow:
below it the step is elastic whatever Y is, so the result is the same (bitwise, on the
benchmark wall's states) and the elastic bulk of the wall skips three transcendental calls.
The Mie–Grüneisen pressure is linear in e with slope Γ₀ρ₀ (:mod:`impactdyn.constitutive`), so
the trapezoidal energy equation

    eⁿ⁺¹ = eⁿ + [½(Sⁿ + Sⁿ⁺¹):d − ½(pⁿ + pⁿ⁺¹) tr d − q tr d] V̄Δt/m

is solved for eⁿ⁺¹ exactly with pⁿ⁺¹ = A_MG(ρⁿ⁺¹) + Γ₀ρ₀eⁿ⁺¹ (A_MG = p_MG(ρ, 0)).

Damage (Johnson & Cook, Eng. Fract. Mech. 21 (1985) 31), accumulated on plastic steps::

    D ← D + Δεₚ/ε_f,   ε_f = max(D1 + D2 exp(D3 σ*), ε_f,min) [1 + D4 ln max(ε̇/ε̇₀, 1)] [1 + D5 T*]

σ* = −p/σ_eq (mean stress over von Mises stress).  ε_f,min = 1e-6 is a numerical floor,
not a material constant: where the fit gives ε_f ≤ 0 (for the 6061-T6 constants, σ* > 1.35,
beyond the triaxialities of the tests it was fitted to) any plastic increment fails the
element (``damage_at_floor=False`` skips those increments instead).  Constants:
:data:`impactdyn.materials.JOHNSON_COOK_DAMAGE` (6061-T6: Lesuer, Kay & LeBlanc 2001; 2024-T351 as
widely quoted; OFHC copper: Johnson & Cook 1985); a material without an entry runs without
ductile damage and fails by spall alone (``failure_criteria`` in :meth:`describe` says which apply).

Spall: p < −p_spall (the library material's spall strength; Kanel et al. 2004) fails the
element.  Each failed element records which criterion failed it (``flags[e, FAILED]``, codes of
:data:`impactdyn.wall._state.FAILURE_CAUSES`): ductile damage; ductile damage completed on a step
at the floor (the fit's D1 + D2 exp(D3 σ*) ≤ ε_f,min: for 6061-T6 σ* > 1.35, a mean tension
above 1.35 times the flow stress, ≈ 0.45 GPa, less than half the spall strength, where any
plastic increment fails the element); or the spall pressure.  The split is reported as
``failed_mass_by_cause_g`` (:mod:`._verdict`): on the ``table2_7a`` wall 99 % of the failed mass
failed at the floor, at the default mesh and at 2×, and no element reached the 1.2-GPa spall
pressure (benchmarks/BENCHMARKS.md, "what fails the 7a wall").

Failure is for good; a failed element is eroded — removed from the force computation — at
once (``erosion=True``, the default).  Without erosion it keeps only compressive pressure
(S = 0, p = max(p, 0)), as the type-13 model.

Sound speed: c² = c_b² + 4G/(3ρ), c_b the isentropic bulk sound speed of the EOS
(:func:`impactdyn.constitutive.sound_speed`).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
from numba import njit

from impactdyn._errors import InputError
from impactdyn.constitutive import (
    C0, GAMMA0, JC_TMELT, JC_TROOM, JC_RATE0, P_SPALL, RHO0, SHEAR, SLOPE, flow_stress, flow_stress_floor, jaumann_rate,
    pack_materials, pressure, radial_return, sound_speed, temperature, temperature_bound, von_mises)
from impactdyn.materials import JOHNSON_COOK_DAMAGE, JohnsonCookDamage, Material, get_material
from impactdyn.wall._models import WallModel, register_model
from impactdyn.wall._state import (
    DAMAGE, EPS_P, FAIL_DAMAGE, FAIL_DAMAGE_FLOOR, FAIL_TENSION, FAILED, IE, P, RATE, stress_power)

(J_DAMAGE, J_D1, J_D2, J_D3, J_D4, J_D5, J_EFMIN, J_SPALL, J_FLOOR) = range(9)

#: Numerical floor on the JC fracture strain (module docstring).
FAILURE_STRAIN_FLOOR = 1.0e-6

#: The elastic shortcut of :func:`jc_update` takes trial stresses below this fraction of the flow stress's
#: lower bound, so that round-off in the bound can never skip a plastic step.
ELASTIC_MARGIN = 1.0 - 1.0e-12

#: Marker for "take the library's damage constants" (None means no ductile damage).
LIBRARY = "library"


@register_model
@dataclass(frozen=True)
class JohnsonCookModel(WallModel):
    """Johnson–Cook / Mie–Grüneisen model of a library material (module docstring).

    material : Material with Johnson–Cook constants.
    damage : JohnsonCookDamage or None (no ductile damage).
    spall : apply the spall criterion p < −p_spall (needs the material's spall strength).
    erosion : erode failed elements.
    damage_at_floor : accumulate damage on steps where the fit's fracture strain is at the floor
        (True, the default: the fit as published, any plastic increment there fails the element);
        False: no ductile damage beyond the fit's zero, tension there left to the spall criterion
        (an alternative for the study in benchmarks/BENCHMARKS.md, "what fails the 7a wall"; not
        a case key, and the LS-DYNA deck cannot carry it).
    """

    material: Material
    damage: JohnsonCookDamage | None = None
    spall: bool = True
    erosion: bool = True
    damage_at_floor: bool = True

    name = "johnson_cook"

    def __post_init__(self) -> None:
        if self.material.johnson_cook is None:
            raise InputError(f"johnson_cook: material {self.material.name!r} has no Johnson-Cook constants")

    @property
    def density(self) -> float:
        return self.material.rho0

    @property
    def erodes(self) -> bool:
        return self.erosion

    @property
    def deck_material(self) -> Material:
        return self.material

    def wave_speed(self) -> float:
        m = self.material
        return math.sqrt(m.c0 ** 2 + 4.0 * m.shear_modulus / (3.0 * m.rho0))

    @property
    def update_kernel(self) -> Callable:
        return jc_element_update

    def reference_moduli(self) -> tuple[float, float]:
        t = self.kernel_table()[0]
        return t[RHO0] * t[C0] ** 2, t[SHEAR]

    def kernel_params(self) -> np.ndarray:
        d = self.damage
        prm = np.zeros(9)
        if d is not None:
            prm[[J_DAMAGE, J_D1, J_D2, J_D3, J_D4, J_D5]] = (1.0, d.D1, d.D2, d.D3, d.D4, d.D5)
        prm[J_EFMIN] = FAILURE_STRAIN_FLOOR
        prm[J_SPALL] = 1.0 if self.spall and self.material.spall_strength is not None else 0.0
        prm[J_FLOOR] = 1.0 if self.damage_at_floor else 0.0
        return prm

    def kernel_table(self) -> np.ndarray:
        return pack_materials([self.material])

    def failure_criteria(self) -> tuple[str, ...]:
        ductile = () if self.damage is None else ("ductile_damage", "ductile_damage_at_floor")
        return ductile + (("tensile_pressure",) if self.kernel_params()[J_SPALL] != 0.0 else ())

    def describe(self) -> dict[str, Any]:
        m, jc, d = self.material, self.material.johnson_cook, self.damage
        return {"model": self.name, "material": m.name, "source": m.source,
                "density_g_cm3": m.rho0, "c0_cm_us": m.c0, "s": m.s, "gamma0": m.gamma0,
                "shear_modulus_Mbar": m.shear_modulus,
                "johnson_cook": {"A_Mbar": jc.A, "B_Mbar": jc.B, "n": jc.n, "C": jc.C, "m": jc.m,
                                 "t_melt_K": jc.t_melt, "t_room_K": jc.t_room,
                                 "reference_strain_rate_per_us": jc.reference_strain_rate},
                "damage": None if d is None else {"D1": d.D1, "D2": d.D2, "D3": d.D3, "D4": d.D4, "D5": d.D5,
                                                  "failure_strain_floor": FAILURE_STRAIN_FLOOR,
                                                  "source": d.source},
                "spall_strength_Mbar": m.spall_strength if self.spall else None,
                "erosion": self.erosion, "damage_at_floor": self.damage_at_floor,
                "failure_criteria": list(self.failure_criteria())}

    @classmethod
    def from_material(cls, material: Any = "al6061-t6", damage: Any = LIBRARY, spall: bool = True,
                      erosion: bool = True, damage_at_floor: bool = True) -> "JohnsonCookModel":
        """The model of a library material; ``damage`` defaults to the library's constants (or none)."""
        if not isinstance(material, (str, Material)):
            raise InputError(f"johnson_cook: material must be a library name or Material, got {material!r}")
        m = get_material(material)
        if isinstance(damage, str) and damage == LIBRARY:
            damage = JOHNSON_COOK_DAMAGE.get(m.name)
        return cls(m, damage=damage, spall=spall, erosion=erosion, damage_at_floor=damage_at_floor)


@njit(cache=True, inline="always")
def jc_element_update(e, L, dt, vbar, mass, rho, vratio, q, S, es, flags, table, prm):
    """:func:`jc_update` in the element pass's convention (:func:`impactdyn.wall._step.material_update`):
    the EOS takes the density, not the volume ratio."""
    return jc_update(e, L, dt, vbar, mass, rho, q, S, es, flags, table, prm)


@njit(cache=True, inline="always")
def jc_update(e, L, dt, vbar, mass, rho, q, S, es, flags, table, prm):
    """Stress, pressure, energy and damage update of element e over Δt (module docstring).

    Arguments as :func:`impactdyn.wall._mat13.mat13_update`; ``table`` the packed material
    (row 0), ``prm`` the damage/spall switches.  Returns (c, ΔW_σ, ΔW_p).
    """
    wfac = vbar * dt
    G = table[0, SHEAR]
    rho0, c0, slope, g0 = table[0, RHO0], table[0, C0], table[0, SLOPE], table[0, GAMMA0]
    s0, s1, s2, s3, s4, s5 = S[e, 0], S[e, 1], S[e, 2], S[e, 3], S[e, 4], S[e, 5]
    p_old = es[e, P]
    dep = 0.0
    yld = 0.0
    failed = flags[e, FAILED] != 0
    if not failed and dt > 0.0:
        ds, rate = jaumann_rate(s0, s1, s2, s3, s4, s5, L, e, G)
        es[e, RATE] = rate
        S[e, 0], S[e, 1], S[e, 2] = s0 + dt * ds[0], s1 + dt * ds[1], s2 + dt * ds[2]
        S[e, 3], S[e, 4], S[e, 5] = s3 + dt * ds[3], s4 + dt * ds[4], s5 + dt * ds[5]
        # a trial stress below a lower bound of the flow stress is elastic for certain: the temperature's
        # exp() and the flow stress's log() and pow() are skipped there (most of the wall, most steps)
        if von_mises(S, e) > ELASTIC_MARGIN * flow_stress_floor(table, 0, temperature_bound(rho, es[e, IE], table, 0)):
            temp = temperature(rho, es[e, IE], table, 0)
            yld = flow_stress(table, 0, True, es[e, EPS_P], rate, temp)
            dep = radial_return(S, e, yld, G)
            es[e, EPS_P] += dep
    if failed:
        for k in range(6):
            S[e, k] = 0.0
    trd, sd_old, sd_new = stress_power(L, e, S, s0, s1, s2, s3, s4, s5)
    # energy equation solved with the pressure at the step's end (linear in e)
    e_star = es[e, IE] + (0.5 * (sd_old + sd_new) - 0.5 * p_old * trd - q * trd) * wfac / mass
    h = 0.5 * trd * wfac / mass
    a_mg = pressure(rho, 0.0, rho0, c0, slope, g0)
    e_new = (e_star - h * a_mg) / (1.0 + h * g0 * rho0)
    p_new = a_mg + g0 * rho0 * e_new
    if not failed:
        at_floor = False
        if dep > 0.0 and prm[J_DAMAGE] != 0.0:
            seq = von_mises(S, e)
            tstar = min(max((temperature(rho, e_new, table, 0) - table[0, JC_TROOM])
                            / (table[0, JC_TMELT] - table[0, JC_TROOM]), 0.0), 1.0)
            fit = prm[J_D1] + prm[J_D2] * math.exp(prm[J_D3] * (-p_new / seq))
            at_floor = fit <= prm[J_EFMIN]
            eps_f = (max(fit, prm[J_EFMIN])
                     * (1.0 + prm[J_D4] * math.log(max(es[e, RATE] / table[0, JC_RATE0], 1.0)))
                     * (1.0 + prm[J_D5] * tstar))
            if prm[J_FLOOR] != 0.0 or not at_floor:
                es[e, DAMAGE] += dep / max(eps_f, prm[J_EFMIN])
        if es[e, DAMAGE] >= 1.0:
            flags[e, FAILED] = FAIL_DAMAGE_FLOOR if at_floor else FAIL_DAMAGE
            failed = True
        elif prm[J_SPALL] != 0.0 and p_new < -table[0, P_SPALL]:
            flags[e, FAILED] = FAIL_TENSION
            failed = True
    if failed and p_new < 0.0:  # a failed element carries no tension
        p_new = 0.0
        e_new = e_star
    if failed:  # released at once; this step's work used the stress it carried
        for k in range(6):
            S[e, k] = 0.0
    dw = 0.5 * (sd_old + sd_new - (p_old + p_new) * trd) * wfac
    es[e, IE] = e_new
    es[e, P] = p_new
    cb = sound_speed(rho, p_new, rho0, c0, slope, g0)
    return math.sqrt(cb * cb + 4.0 * G / (3.0 * rho)), dw, yld * dep * vbar
