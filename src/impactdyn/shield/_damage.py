"""The fragmentation model's per-particle flaws: what the compiled damage update reads (:mod:`._equations`).

Tensile damage from Weibull-distributed flaws (Grady & Kipp 1980; Benz & Asphaug 1994, 1995), in the
volume-based probabilistic form (as LLNL Spheral's ProbabilisticDamageModel, without an explicit
list of flaws): a volume V holds k V εᵐ flaws that activate at tensile strains ≤ ε
(:class:`impactdyn.materials.WeibullFlaws`).  Each particle, of solid volume V = m/ρ₀, gets

* its weakest-flaw strain ε_min, drawn from P(ε_min > ε) = exp(−k V εᵐ)::

      ε_min = (−ln u / (k V))^{1/m},   u uniform in (0, 1]      (seeded: ``flaw_seed``)

* k V, so that n_a = max(1, k V εᵐ) flaws are active at the strain ε ≥ ε_min;
* the growth rate c_g / R_s of its damage, R_s = (3V/4π)^{1/3} its radius and c_g = 0.4 c_L the
  crack speed (:attr:`impactdyn.materials.Material.crack_speed`)::

      d D^{1/3} / dt = n_a^{1/3} c_g / R_s      (Grady & Kipp: n_a cracks of radius c_g t damage
                                                  the fraction D = n_a (c_g t / R_s)³ of the sphere)

The strain is ε = σ₁/E of the largest principal stress of the undamaged stress (Benz & Asphaug's
local strain).  Because ε_min follows the particle's volume, a finer particle is stronger, as the
Weibull size effect of the material says; the fragment statistics' convergence with resolution is
checked, not assumed (studies/fragments/fragments_mechanism.py).

Ductile damage is the Johnson–Cook sum Σ Δεₚ/ε_f with the alloy's fracture-strain floor, none below
the triaxiality −1/3 (:func:`impactdyn.constitutive.ductile_damage_increment`): compression, however
much it makes the metal flow, breaks nothing.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from impactdyn._errors import InputError
from impactdyn.constitutive import DM_GROWTH, DM_HAS_WEIBULL, DM_K, DM_M, RHO0


class Flaws(NamedTuple):
    """Per-particle flaw data of the tensile damage (module docstring), in the particles' order."""

    strain: np.ndarray          #: ε_min, the weakest flaw's activation strain
    count: np.ndarray           #: k V: the active flaws at unit strain (n_a = max(1, k V εᵐ))
    growth_rate: np.ndarray     #: c_g / R_s, µs⁻¹


def seed_flaws(mass: np.ndarray, material: np.ndarray, names: tuple[str, ...], params: np.ndarray,
               damage_table: np.ndarray, seed: int) -> Flaws:
    """The flaws of every particle (module docstring); the same ``seed`` gives the same flaws.

    A material without Weibull constants (:data:`impactdyn.materials.WEIBULL_FLAWS`) is refused,
    naming it: the fragmentation model has no tensile failure for it.
    """
    missing = sorted({names[k] for k in np.unique(material) if damage_table[k, DM_HAS_WEIBULL] == 0.0})
    if missing:
        raise InputError(f"shield.failure_model = \"fragmentation\": no Weibull flaw constants for "
                         f"{', '.join(missing)} (impactdyn.materials.WEIBULL_FLAWS); use failure_model = "
                         "\"threshold\" for it")
    volume = mass / params[material, RHO0]
    k, m = damage_table[material, DM_K], damage_table[material, DM_M]
    u = 1.0 - np.random.default_rng(seed).random(mass.size)   # in (0, 1]
    radius = np.cbrt(3.0 * volume / (4.0 * np.pi))
    return Flaws(strain=(-np.log(u) / (k * volume)) ** (1.0 / m), count=k * volume,
                 growth_rate=damage_table[material, DM_GROWTH] / radius)
