"""Wall model ``"johnson_cook"``: Johnson–Cook strength, Mie–Grüneisen EOS, JC damage, spall, erosion.

The modern alternative to the report's type-13 card (docs/theory/wall-solver.md, Materials), built on the shared
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

Damage (Johnson & Cook, Eng. Fract. Mech. 21 (1985) 31), accumulated on plastic steps
(:func:`impactdyn.constitutive.fracture_strain`)::

    D ← D + Δεₚ/ε_f,   ε_f = max(D1 + D2 exp(D3 σ*), ε_f,min) [1 + D4 ln max(ε̇/ε̇₀, 1)] [1 + D5 T*]

σ* = −p/σ_eq (mean stress over von Mises stress).  ε_f,min is the fracture-strain floor
(``fracture_strain_floor``): ``"library"`` (the default) takes the material library's
:attr:`~impactdyn.materials.JohnsonCookDamage.efmin` (6061-T6: the fit held at its value at the
largest notched-bar triaxiality, 0.125; uncertain, see :mod:`impactdyn.materials`), or the
numerical 1e-6 where the library has none (a fit bounded below by D1 > 0 by itself);
``"unbounded"`` takes 1e-6 everywhere: the fit as published, extrapolated beyond its data,
where for the 6061-T6 constants (D1 < 0) ε_f vanishes for σ* > 1.35 and any plastic increment
in mean tension above ≈ 0.45 GPa fails the element (the behaviour before the floor; it decided the
``table2_7a`` verdict, 99 % of its failed mass, and made it mesh-dependent: docs/vv/convergence.md,
"The wall: Table 2 at the default mesh and at twice its resolution").  ``damage_at_floor=False`` skips the increments on steps where the fit
is at or below the floor instead (a study switch).  Constants:
the material's :attr:`~impactdyn.materials.Material.johnson_cook_damage` (6061-T6: Lesuer, Kay & LeBlanc
2001; 2024-T351 as widely quoted; OFHC copper: Johnson & Cook 1985); a material without them runs without
ductile damage and fails by spall alone (``failure_criteria`` in :meth:`describe` says which apply).

Spall (``spall_law``): a registered wall failure law (:data:`impactdyn.wall.FAILURE_LAWS`, one module
each in :mod:`impactdyn.wall.failure_laws`, bound into this model's update by :func:`jc_kernel`).
``"tuler_butcher"`` (the default; Tuler & Butcher, Int. J. Fract. Mech. 4
(1968) 431, :func:`impactdyn.constitutive.tuler_butcher_increment`)::

    ∫ max(0, σ_t − σ₀)^λ dt ≥ K,   σ_t = −p (the mean tension)

integrated by the trapezoidal rule over each step from the pressures at its start and end
(per-element column ``SPALL_DAMAGE`` of ``es``), constants
:attr:`~impactdyn.materials.Material.tuler_butcher` (the library's: a documented fallback scaled from the spall
strengths, not published Tuler–Butcher constants: uncertain).  The mean tension, not the largest
principal stress: the spall strengths the constants scale from are the pressure cut-offs of this
model and of type 13 (the cut-off law is the limit K → 0 of this one); void growth, the mechanism
of ductile spall, is driven by the mean stress (deviatoric, shear-driven failure is the
Johnson–Cook damage's part); in the uniaxial strain of spall tests the two differ by ⅔Y ≈ 0.2 GPa
only; and it needs no eigenvalues in the hot loop.  ``"cutoff"``: p < −p_spall (the library
material's spall strength; Kanel et al. 2004) fails the element at once, with no time scale
(the behaviour before the Tuler–Butcher law).

Each failed element records which criterion failed it (``flags[e, FAILED]``, codes of
:data:`impactdyn.wall._state.FAILURE_CAUSES`): ductile damage; ductile damage completed on a step
at the floor (the fit's D1 + D2 exp(D3 σ*) ≤ ε_f,min); the spall pressure (cut-off) or the spall
damage (Tuler–Butcher).  The split is reported as ``failed_mass_by_cause_g`` (:mod:`._verdict`).

Failure is for good.  A failed element carries no deviatoric stress and no tension but keeps its
compressive pressure (S = 0, p = max(p, 0)): failed material is rubble, which still pushes back
when squeezed.  By default (``erosion=False``) it stays in the force computation and is removed
only by the solver's geometric criteria (its step collapses below ``erosion_step_fraction`` of the
initial one, or its volume inverts, :mod:`impactdyn.wall._step`): eroding it at once
(``erosion=True``) deletes the mass and the support of the material around a crater, so that
debris behind the first failed layer meets no resistance, and the rubble's momentum leaves the
mesh (the energy balance books it as eroded).  LS-DYNA's *MAT_JOHNSON_COOK keeps failed solids
the same way with EROD = 1 (pressure only after failure).  Measured on a 1 × 0.2 × 1-cm clamped
wall of 20 × 4 × 20 bricks, a central 4 × 4 patch of face elements each loaded by four impulses
of 1e-5 to 5e-5 g·cm/µs over 0.75 µs, 8 µs (the default laws otherwise): the same verdict with
and without erosion at all four loads (no perforation at the lowest, perforation above); without
erosion 1.1–3.5× more failed mass (the rubble passes compression on to the material behind it,
which the eroded hole does not), deeper damage at the lowest load (0.15 against 0.05 cm), and
no mass leaves the mesh.

Sound speed: c² = c_b² + 4G/(3ρ), c_b the isentropic bulk sound speed of the EOS
(:func:`impactdyn.constitutive.sound_speed`).
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
from numba import njit

from impactdyn._errors import InputError
from impactdyn.constitutive import (
    C0, GAMMA0, JC_TMELT, JC_TROOM, JC_RATE0, RHO0, SHEAR, SLOPE, flow_stress, flow_stress_floor,
    fracture_strain, jaumann_rate, pack_materials, pressure, radial_return, sound_speed, temperature,
    temperature_bound, von_mises)
from impactdyn._jitcache import bind_globals
from impactdyn.materials import JohnsonCookDamage, Material, get_material
from impactdyn.wall import failure_laws  # noqa: F401  (the built-in failure laws register themselves)
from impactdyn.wall._failure_law import FAILURE_LAWS, J_LAW, FailureLaw
from impactdyn.wall._models import MODELS, WallModel
from impactdyn.wall._state import (
    DAMAGE, EPS_P, FAIL_DAMAGE, FAIL_DAMAGE_FLOOR, FAILED, FAILURE_CAUSES, IE, P, RATE, stress_power)

#: The model's own parameters (:meth:`JohnsonCookModel.kernel_params`); its failure law's constants follow,
#: from ``J_LAW`` (:mod:`impactdyn.wall._failure_law`).  ``J_SPALL``: 1 to apply the failure law, 0 not.
(J_DAMAGE, J_D1, J_D2, J_D3, J_D4, J_D5, J_EFMIN, J_SPALL, J_FLOOR) = range(J_LAW)

#: Numerical floor on the JC fracture strain, so that ε_f > 0 (module docstring); not a material constant.
FAILURE_STRAIN_FLOOR = 1.0e-6

#: The fracture-strain floors (``fracture_strain_floor``): the library's, or the fit unbounded.
FRACTURE_STRAIN_FLOORS = ("library", "unbounded")

#: The elastic shortcut of :func:`jc_update` takes trial stresses below this fraction of the flow stress's
#: lower bound, so that round-off in the bound can never skip a plastic step.
ELASTIC_MARGIN = 1.0 - 1.0e-12

#: Marker for "take the library's damage (or failure-law) constants" (None means none).
LIBRARY = "library"


@dataclass(frozen=True)
class JohnsonCookModel(WallModel):  # registered at the bottom of the module
    """Johnson–Cook / Mie–Grüneisen model of a library material (module docstring).

    material : Material with Johnson–Cook constants.
    damage : JohnsonCookDamage or None (no ductile damage).
    spall : apply the failure law (the spall criterion; a law the material has no constants for is off or
        refused, as the law says).
    erosion : erode failed elements at once (False, the default: they keep compressive pressure and
        are removed by the solver's geometric criteria only; module docstring).
    damage_at_floor : accumulate damage on steps where the fit's fracture strain is at the floor
        (True, the default); False: no ductile damage there, tension left to the spall criterion
        (the study in docs/vv/convergence.md, "Why the defaults are what they are"; not a case key).
    spall_law : a name of :data:`impactdyn.wall.FAILURE_LAWS`: "tuler_butcher" (default) or "cutoff".
    fracture_strain_floor : one of :data:`FRACTURE_STRAIN_FLOORS`: "library" (default) or "unbounded".
    spall_constants : the failure law's constants ("library", the default: the material's, as the law
        finds them, :attr:`impactdyn.wall.FailureLaw.library_constants`; None: none).
    """

    material: Material
    damage: JohnsonCookDamage | None = None
    spall: bool = True
    erosion: bool = False
    damage_at_floor: bool = True
    spall_law: str = "tuler_butcher"
    fracture_strain_floor: str = "library"
    spall_constants: Any = LIBRARY

    name = "johnson_cook"
    option_keys = ("spall_law", "fracture_strain_floor")

    def __post_init__(self) -> None:
        if self.material.johnson_cook is None:
            raise InputError(f"johnson_cook: material {self.material.name!r} has no Johnson-Cook constants")
        law = FAILURE_LAWS.get(self.spall_law)
        if isinstance(self.spall_constants, str) and self.spall_constants == LIBRARY:
            object.__setattr__(self, "spall_constants", law.library_constants(self.material))
        if self.fracture_strain_floor not in FRACTURE_STRAIN_FLOORS:
            raise InputError(f"fracture_strain_floor: {self.fracture_strain_floor!r} is not one of "
                             f"{', '.join(FRACTURE_STRAIN_FLOORS)}")
        if self.spall and law.required and self.spall_constants is None:
            raise InputError(f"spall_law: {law.name!r} needs {law.needs}, which material {self.material.name!r} "
                             f"lacks; choose another law ({', '.join(FAILURE_LAWS.names())}) or pass spall_constants=")

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
    def failure_law(self) -> FailureLaw:
        """The registered failure law ``spall_law``."""
        return FAILURE_LAWS.get(self.spall_law)

    @property
    def update_kernel(self) -> Callable:
        return jc_kernel(self.failure_law)

    def reference_moduli(self) -> tuple[float, float]:
        t = self.kernel_table()[0]
        return t[RHO0] * t[C0] ** 2, t[SHEAR]

    @property
    def deck_failure_strain_floor(self) -> float | None:
        return self.efmin if self.damage is not None else None

    @property
    def efmin(self) -> float:
        """The fracture-strain floor ε_f,min in effect (module docstring)."""
        d = self.damage
        if self.fracture_strain_floor == "library" and d is not None and d.efmin is not None:
            return d.efmin
        return FAILURE_STRAIN_FLOOR

    @property
    def spalls(self) -> bool:
        """Whether the failure law applies (``spall`` on and the law's constants known)."""
        return self.spall and self.spall_constants is not None

    def kernel_params(self) -> np.ndarray:
        d = self.damage
        constants = self.failure_law.kernel_constants(self.spall_constants) if self.spalls else ()
        prm = np.zeros(J_LAW + len(constants))
        if d is not None:
            prm[[J_DAMAGE, J_D1, J_D2, J_D3, J_D4, J_D5]] = (1.0, d.D1, d.D2, d.D3, d.D4, d.D5)
        prm[J_EFMIN] = self.efmin
        prm[J_SPALL] = 1.0 if self.spalls else 0.0
        prm[J_FLOOR] = 1.0 if self.damage_at_floor else 0.0
        prm[J_LAW:] = constants
        return prm

    def kernel_table(self) -> np.ndarray:
        return pack_materials([self.material])

    def failure_criteria(self) -> tuple[str, ...]:
        ductile = () if self.damage is None else ("ductile_damage", "ductile_damage_at_floor")
        return ductile + ((self.failure_law.cause,) if self.spalls else ())

    def describe(self) -> dict[str, Any]:
        m, jc, d, law = self.material, self.material.johnson_cook, self.damage, self.failure_law
        floor_source = (d.efmin_source if d is not None and self.efmin != FAILURE_STRAIN_FLOOR
                        else "numerical floor (the fit unbounded)")
        return {"model": self.name, "material": m.name, "source": m.source,
                "density_g_cm3": m.rho0, "c0_cm_us": m.c0, "s": m.s, "gamma0": m.gamma0,
                "shear_modulus_Mbar": m.shear_modulus,
                "johnson_cook": {"A_Mbar": jc.A, "B_Mbar": jc.B, "n": jc.n, "C": jc.C, "m": jc.m,
                                 "t_melt_K": jc.t_melt, "t_room_K": jc.t_room,
                                 "reference_strain_rate_per_us": jc.reference_strain_rate},
                "damage": None if d is None else {"D1": d.D1, "D2": d.D2, "D3": d.D3, "D4": d.D4, "D5": d.D5,
                                                  "source": d.source,
                                                  "fracture_strain_floor": self.fracture_strain_floor,
                                                  "failure_strain_floor": self.efmin,
                                                  "failure_strain_floor_source": floor_source},
                "spall_law": self.spall_law if self.spalls else None,
                # each registered law's constants under its own key (None but the law in use)
                **{other.describe_key: None for other in FAILURE_LAWS.values()},
                **({law.describe_key: law.describe(self.spall_constants)} if self.spalls else {}),
                "erosion": self.erosion, "damage_at_floor": self.damage_at_floor,
                "failure_criteria": list(self.failure_criteria())}

    @classmethod
    def from_material(cls, material: Any = "al6061-t6", damage: Any = LIBRARY, spall: bool = True,
                      erosion: bool = False, damage_at_floor: bool = True, spall_law: str = "tuler_butcher",
                      fracture_strain_floor: str = "library", spall_constants: Any = LIBRARY) -> "JohnsonCookModel":
        """The model of a library material; ``damage`` and ``spall_constants`` default to the library's
        constants (or none)."""
        if not isinstance(material, (str, Material)):
            raise InputError(f"johnson_cook: material must be a library name or Material, got {material!r}")
        m = get_material(material)
        if isinstance(damage, str) and damage == LIBRARY:
            damage = m.johnson_cook_damage
        return cls(m, damage=damage, spall=spall, erosion=erosion, damage_at_floor=damage_at_floor,
                   spall_law=spall_law, fracture_strain_floor=fracture_strain_floor, spall_constants=spall_constants)


@functools.cache
def jc_kernel(law: FailureLaw) -> Callable:
    """The model's element update with the failure law ``law`` bound in: :func:`jc_element_update` and
    :func:`jc_update` compiled with the law's kernels as their globals ``law_accumulate``, ``law_fails`` and
    its cause as ``LAW_CAUSE`` (:func:`impactdyn._jitcache.bind_globals`), once per process and law; cached on
    disk for the package's own laws."""
    cache = law.in_package
    update = njit(cache=cache, inline="always")(bind_globals(
        jc_update, law.name, law_accumulate=law.accumulate, law_fails=law.fails,
        LAW_CAUSE=1 + FAILURE_CAUSES.index(law.cause)))
    element = njit(cache=cache, inline="always")(bind_globals(jc_element_update, law.name, jc_update=update))
    element.cacheable = cache
    return element


def jc_element_update(e, L, dt, vbar, mass, rho, vratio, q, S, es, flags, table, prm):
    """:func:`jc_update` in the element pass's convention (:func:`impactdyn.wall._step.material_update`):
    the EOS takes the density, not the volume ratio.  A template: :func:`jc_kernel` compiles it per law."""
    return jc_update(e, L, dt, vbar, mass, rho, q, S, es, flags, table, prm)


def jc_update(e, L, dt, vbar, mass, rho, q, S, es, flags, table, prm):
    """Stress, pressure, energy and damage update of element e over Δt (module docstring).

    Arguments as :func:`impactdyn.wall._mat13.mat13_update`; ``table`` the packed material
    (row 0), ``prm`` the damage and spall constants and switches (:meth:`JohnsonCookModel.kernel_params`).
    Returns (c, ΔW_σ, ΔW_p).  A template: the failure law's kernels are bound in by :func:`jc_kernel`.
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
            tstar = min(max((temperature(rho, e_new, table, 0) - table[0, JC_TROOM])
                            / (table[0, JC_TMELT] - table[0, JC_TROOM]), 0.0), 1.0)
            eps_f, at_floor = fracture_strain(prm[J_D1], prm[J_D2], prm[J_D3], prm[J_D4], prm[J_D5],
                                              -p_new / von_mises(S, e), es[e, RATE] / table[0, JC_RATE0], tstar,
                                              prm[J_EFMIN])
            if prm[J_FLOOR] != 0.0 or not at_floor:
                es[e, DAMAGE] += dep / eps_f
        spall = prm[J_SPALL] != 0.0
        if spall:  # the failure law's state over the step (its module)
            law_accumulate(e, p_old, p_new, dt, es, table, prm)  # noqa: F821  (bound by jc_kernel)
        if es[e, DAMAGE] >= 1.0:
            flags[e, FAILED] = FAIL_DAMAGE_FLOOR if at_floor else FAIL_DAMAGE
            failed = True
        elif spall and law_fails(e, p_new, es, table, prm):  # noqa: F821
            flags[e, FAILED] = LAW_CAUSE  # noqa: F821
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


MODELS.register(JohnsonCookModel.name, JohnsonCookModel)
