"""The wall card: DYNA3D material type 13 / LS-DYNA ``*MAT_013``, the report's wall material, and the
card of any registered material (:func:`mat13_card`)."""

from __future__ import annotations

import math
from dataclasses import dataclass

from impactdyn._errors import InputError
from impactdyn.materials._records import Material, _require_numbers
from impactdyn.materials._registry import get_material

@dataclass(frozen=True)
class Mat13Card:
    """Isotropic elastic–plastic wall material with failure, cm-g-µs units.

    The parameters of DYNA3D material 13 (isotropic elastic–plastic with failure),
    the wall material of the report's deck (App. D).

    Attributes: density (g/cm³); shear_modulus, bulk_modulus, yield_stress and
    hardening_modulus (plastic hardening modulus E_h, Mbar); failure_strain
    (effective plastic strain at failure, 0 = none); failure_pressure (Mbar, ≤ 0).
    """

    density: float
    shear_modulus: float
    bulk_modulus: float
    yield_stress: float
    hardening_modulus: float
    failure_strain: float
    failure_pressure: float

    def __post_init__(self) -> None:
        _require_numbers(self, ("density", "shear_modulus", "bulk_modulus", "yield_stress"), positive=True)
        _require_numbers(self, ("hardening_modulus", "failure_strain"), positive=False)
        if not (math.isfinite(self.failure_pressure) and self.failure_pressure <= 0):
            raise InputError(f"Mat13Card.failure_pressure: must be <= 0, got {self.failure_pressure!r}")

    @property
    def youngs_modulus(self) -> float:
        """E = 9KG / (3K + G), Mbar."""
        k, g = self.bulk_modulus, self.shear_modulus
        return 9.0 * k * g / (3.0 * k + g)

    @property
    def poisson_ratio(self) -> float:
        """ν = (3K − 2G) / (2 (3K + G))."""
        k, g = self.bulk_modulus, self.shear_modulus
        return (3.0 * k - 2.0 * g) / (2.0 * (3.0 * k + g))

    @property
    def tangent_modulus(self) -> float:
        """Slope E_t of the bilinear stress–strain curve, E E_h / (E + E_h), Mbar."""
        e, eh = self.youngs_modulus, self.hardening_modulus
        return e * eh / (e + eh)


#: Al 6061-T6 as the report's DYNA3D deck gives it (Fahrenthold 1994, App. D,
#: material 1, type 13: G 0.276, σ_y 2.900e-03, E_h 3.88e-03, ε_f 1.5, p_cut
#: -12.e+33, K 0.720, in that order on the cards).  ρ, G and σ_y are Steinberg's
#: (1991) 6061-T6 values (2.703 g/cm³, 27.6 GPa, Y₀ 0.29 GPa); K = 72 GPa is close
#: to ρ₀c₀² = 74 GPa from his c₀ = 5.24 km/s.  p_cut = -1.2e34 Mbar means no
#: pressure cutoff.  E = 73.4 GPa and ν = 0.330 follow from G and K.
AL_6061_T6_MAT13 = Mat13Card(
    density=2.703,
    shear_modulus=0.276,
    bulk_modulus=0.720,
    yield_stress=2.900e-03,
    hardening_modulus=3.88e-03,
    failure_strain=1.5,
    failure_pressure=-12.0e33,
)


def mat13_card(material: "str | Material") -> Mat13Card:
    """The DYNA3D material-13 card of a registered material (:mod:`impactdyn.materials`).

    Al 6061-T6 gets the report's own card (:data:`AL_6061_T6_MAT13`).  Any other
    material: its ρ₀, G, K = ρ₀c₀² and Y₀, no hardening (the
    elastic–perfectly-plastic model of the shield stage), its plastic-strain
    failure limit (0 = none) and failure pressure −p_spall (no cutoff without one).
    """
    m = get_material(material)
    if m.name == "al6061-t6":
        return AL_6061_T6_MAT13
    return Mat13Card(density=m.rho0, shear_modulus=m.shear_modulus, bulk_modulus=m.rho0 * m.c0**2,
                        yield_stress=m.yield_stress, hardening_modulus=0.0, failure_strain=m.failure_strain or 0.0,
                        failure_pressure=-m.spall_strength if m.spall_strength else AL_6061_T6_MAT13.failure_pressure)

