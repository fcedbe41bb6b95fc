"""The fragmentation model's flaws: the per-particle record the compiled damage update reads (:mod:`._equations`).

Tensile damage from Weibull-distributed flaws per unit volume, in Grady & Kipp's continuum form
(Int. J. Rock Mech. Min. Sci. 17 (1980) 147): n(ε) = k εᵐ flaws per unit volume activate as the
tensile strain passes their strain, each grows a crack at c_g = 0.4 c_L
(:attr:`impactdyn.materials.Material.crack_speed`) while the material is in tension, and the damage is
the cracks' volume per unit volume (:func:`impactdyn.constitutive.grady_kipp_damage`).  The strain is
ε = σ₁/E of the largest principal stress of the undamaged stress (Benz & Asphaug's local strain).

Each particle carries the record (ε_max, M₀ … M₃) of :data:`impactdyn.constitutive.N_FLAW` columns,
zero at the start.  Nothing in it depends on the particle's volume: halving the spacing neither
weakens nor strengthens the material.  (The earlier form, Benz & Asphaug's, gave each particle its own
weakest flaw and grew its damage over the particle's radius, so a finer particle failed sooner: the
onset of break-up moved with the spacing.)

Ductile damage is the Johnson–Cook sum Σ Δεₚ/ε_f with the alloy's fracture-strain floor, none below
the triaxiality −1/3 (:func:`impactdyn.constitutive.ductile_damage_increment`): compression, however
much it makes the metal flow, breaks nothing.
"""

from __future__ import annotations

import numpy as np

from impactdyn._errors import InputError
from impactdyn.constitutive import DM_HAS_WEIBULL, N_FLAW


def new_flaws(material: np.ndarray, names: tuple[str, ...], damage_table: np.ndarray) -> np.ndarray:
    """The flaw records (N, N_FLAW) of particles of the given material ids, all zero (no strain yet).

    A material without Weibull constants (:attr:`impactdyn.materials.Material.weibull_flaws`) is refused,
    naming it: the fragmentation model has no tensile failure for it.
    """
    missing = sorted({names[k] for k in np.unique(material) if damage_table[k, DM_HAS_WEIBULL] == 0.0})
    if missing:
        raise InputError(f"shield.failure_model = \"fragmentation\": no Weibull flaw constants for "
                         f"{', '.join(missing)} (no weibull_flaws in its material record); use failure_model = "
                         "\"threshold\" for it")
    return np.zeros((material.size, N_FLAW))
