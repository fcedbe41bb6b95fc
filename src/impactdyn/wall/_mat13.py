"""Wall model ``"mat13"``: DYNA3D material type 13 / LS-DYNA ``*MAT_ISOTROPIC_ELASTIC_FAILURE``.

The report's wall card (Fahrenthold 1994, App. D; :data:`impactdyn.materials.AL_6061_T6_MAT13`):
isotropic elastic–plastic with linear hardening and failure.  Per element and step
(Δt, rate of deformation d, spin Ω from the mean velocity gradient, :mod:`._step`)::

    S* = Sⁿ + Δt [2G d' + ΩSⁿ − SⁿΩ]                         (Jaumann rate)
    Y = σ_y + E_h εₚ                                           (linear isotropic hardening)
    σ_eq* = √(3/2 S*:S*) > Y:  Δεₚ = (σ_eq* − Y)/(3G + E_h),
                               Sⁿ⁺¹ = S* (Y + E_h Δεₚ)/σ_eq*   (radial return, Wilkins 1964)
    pⁿ⁺¹ = K (1 − V/V₀)

The pressure is the linear bulk-modulus form with the engineering volume strain
1 − V/V₀ (the form of LS-DYNA's ``*MAT_013`` with its BULK modulus), not −K ln(V/V₀):
the two agree to first order in the volume strain (the report's wall compresses a few per
cent in the elements that have not failed).

Failure (DYNA3D type 13): εₚ ≥ ε_f (when ε_f > 0) or p < p_cut (``failure_pressure``;
−1.2e34 Mbar on the report's card, i.e. none).  A failed element stays failed; it keeps
only compressive pressure — S = 0, p = max(K(1 − V/V₀), 0) — and it is not eroded
(LS-DYNA ``REM = 1`` behaviour; the solver erodes a failed element only when it inverts
or its time step collapses, :mod:`._step`).

Internal energy per unit mass (for the energy balance), trapezoidal in time with
σ = S − pI and the bulk viscosity q::

    eⁿ⁺¹ = eⁿ + [½(σⁿ + σⁿ⁺¹):d − q tr d] V̄ Δt / m

Sound speed for the time step and the hourglass forces: c = √((K + 4G/3)/ρ).
Damage output: εₚ/ε_f (0 without ε_f).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
from numba import njit

from impactdyn._errors import InputError
from impactdyn.constitutive import jaumann_rate, radial_return, von_mises
from impactdyn.materials import Mat13Card, Material, get_material, mat13_card
from impactdyn.wall._models import MODELS, WallModel
from impactdyn.wall._state import DAMAGE, EPS_P, FAIL_STRAIN, FAIL_TENSION, FAILED, IE, P, RATE, stress_power

(M_RHO, M_G, M_K, M_SIGY, M_EH, M_EPSF, M_PCUT) = range(7)


@dataclass(frozen=True)
class Mat13Model(WallModel):
    """DYNA3D type 13 with the constants of ``card`` (module docstring); ``source`` names them."""

    card: Mat13Card
    source: str = ""

    name = "mat13"

    @property
    def density(self) -> float:
        return self.card.density

    @property
    def erodes(self) -> bool:
        return False

    @property
    def deck_material(self) -> Mat13Card:
        return self.card

    def wave_speed(self) -> float:
        c = self.card
        return math.sqrt((c.bulk_modulus + 4.0 * c.shear_modulus / 3.0) / c.density)

    @property
    def update_kernel(self) -> Callable:
        return mat13_element_update

    def reference_moduli(self) -> tuple[float, float]:
        return self.card.bulk_modulus, self.card.shear_modulus

    def kernel_params(self) -> np.ndarray:
        c = self.card
        return np.array([c.density, c.shear_modulus, c.bulk_modulus, c.yield_stress, c.hardening_modulus,
                         c.failure_strain, c.failure_pressure], dtype=np.float64)

    def failure_criteria(self) -> tuple[str, ...]:
        # a cutoff beyond −1e20 Mbar is the card's way of saying "none" (the report's −1.2e34)
        c = self.card
        return ((("plastic_strain",) if c.failure_strain > 0.0 else ())
                + (("tensile_pressure",) if c.failure_pressure > -1.0e20 else ()))

    def describe(self) -> dict[str, Any]:
        c = self.card
        return {"model": self.name, "source": self.source, "failure_criteria": list(self.failure_criteria()),
                "density_g_cm3": c.density, "shear_modulus_Mbar": c.shear_modulus,
                "bulk_modulus_Mbar": c.bulk_modulus, "yield_stress_Mbar": c.yield_stress,
                "hardening_modulus_Mbar": c.hardening_modulus, "failure_strain": c.failure_strain,
                "failure_pressure_Mbar": c.failure_pressure,
                "pressure": "p = K (1 - V/V0); failed: p = max(p, 0), S = 0"}

    @classmethod
    def from_material(cls, material: Any = "al6061-t6", **kwargs) -> "Mat13Model":
        """The type-13 card of a library material (:func:`impactdyn.materials.mat13_card`) or a card."""
        if kwargs:
            raise InputError(f"mat13: unknown options {sorted(kwargs)}")
        if isinstance(material, Mat13Card):
            return cls(material, source="card given")
        m = get_material(material) if isinstance(material, (str, Material)) else None
        if m is None:
            raise InputError(f"mat13: material must be a library name, Material or Mat13Card, got {material!r}")
        src = ("Fahrenthold 1994 App. D (the report's DYNA3D card)" if m.name == "al6061-t6"
               else f"impactdyn.materials.mat13_card({m.name!r}): {m.source}")
        return cls(mat13_card(m), source=src)


@njit(cache=True, inline="always")
def mat13_update(e, L, dt, vbar, mass, rho, vratio, q, S, es, flags, prm):
    """Stress update of element e over Δt (module docstring); returns (c, ΔW_σ, ΔW_p).

    L (ne, 3, 3) velocity gradient (midstep), V̄ = ``vbar`` the midstep volume, ρ = ``rho`` and
    V/V₀ = ``vratio`` at the step's end, q the bulk viscosity; S (ne, 6), es and flags the element
    state (:mod:`._state`), updated in place.  ΔW_σ = ½(σⁿ + σⁿ⁺¹):d V̄Δt and the plastic work
    ΔW_p = σ_eq Δεₚ V̄, g·cm²/µs².
    """
    wfac = vbar * dt
    G, K = prm[M_G], prm[M_K]
    s0, s1, s2, s3, s4, s5 = S[e, 0], S[e, 1], S[e, 2], S[e, 3], S[e, 4], S[e, 5]
    p_old = es[e, P]
    dep = 0.0
    yld = 0.0
    if flags[e, FAILED] == 0 and dt > 0.0:
        ds, rate = jaumann_rate(s0, s1, s2, s3, s4, s5, L, e, G)
        es[e, RATE] = rate
        S[e, 0], S[e, 1], S[e, 2] = s0 + dt * ds[0], s1 + dt * ds[1], s2 + dt * ds[2]
        S[e, 3], S[e, 4], S[e, 5] = s3 + dt * ds[3], s4 + dt * ds[4], s5 + dt * ds[5]
        yld = prm[M_SIGY] + prm[M_EH] * es[e, EPS_P]
        seq = von_mises(S, e)
        if seq > yld:
            dep = (seq - yld) / (3.0 * G + prm[M_EH])
            yld += prm[M_EH] * dep
            radial_return(S, e, yld, G)
            es[e, EPS_P] += dep
    if flags[e, FAILED] != 0:
        for k in range(6):
            S[e, k] = 0.0
    trd, sd_old, sd_new = stress_power(L, e, S, s0, s1, s2, s3, s4, s5)
    p_new = K * (1.0 - vratio)
    epsf = prm[M_EPSF]
    if flags[e, FAILED] == 0 and ((epsf > 0.0 and es[e, EPS_P] >= epsf) or p_new < prm[M_PCUT]):
        flags[e, FAILED] = FAIL_STRAIN if (epsf > 0.0 and es[e, EPS_P] >= epsf) else FAIL_TENSION
        for k in range(6):  # released at once; this step's work used the stress it carried
            S[e, k] = 0.0
    if flags[e, FAILED] != 0:
        p_new = max(p_new, 0.0)
    es[e, DAMAGE] = es[e, EPS_P] / epsf if epsf > 0.0 else 0.0
    dw = 0.5 * (sd_old + sd_new - (p_old + p_new) * trd) * wfac
    es[e, IE] += (dw - q * trd * wfac) / mass
    es[e, P] = p_new
    return math.sqrt((K + 4.0 * G / 3.0) / rho), dw, yld * dep * vbar


@njit(cache=True, inline="always")
def mat13_element_update(e, L, dt, vbar, mass, rho, vratio, q, S, es, flags, table, prm):
    """:func:`mat13_update` in the element pass's convention (:func:`impactdyn.wall._step.material_update`):
    the type-13 card has no EOS table."""
    return mat13_update(e, L, dt, vbar, mass, rho, vratio, q, S, es, flags, prm)


MODELS.register(Mat13Model.name, Mat13Model)
