"""The debris state of an SPH state: each particle's melted and vapour share on release
(:mod:`impactdyn.constitutive._phase`), and which particles can belong to a solid fragment."""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from impactdyn.constitutive import pack_materials, pack_phases, release_states

#: A particle at least this much melted on release (liquid and vapour, by mass) is liquid: it forms no
#: solid fragment.  The majority rule: a particle is one lump of material, solid or not.
MELTED_SHARE = 0.5


class ReleasedPhase(NamedTuple):
    """Per particle, released along its isentrope to zero pressure (:mod:`impactdyn.constitutive._phase`)."""

    energy: np.ndarray       #: e_r, cm²/µs²
    temperature: np.ndarray  #: T_r, K (held on the melting range and at the boiling point)
    melted: np.ndarray       #: the liquid-and-vapour share χ_m in [0, 1]
    vapour: np.ndarray       #: the vapour share χ_v in [0, χ_m]


def released_phase(particles) -> ReleasedPhase:
    """The :class:`ReleasedPhase` of every particle of ``particles`` (:class:`impactdyn.shield.Particles`),
    with the library materials it names."""
    from impactdyn.materials import get_material

    mats = [get_material(name) for name in particles.materials]
    return ReleasedPhase(*release_states(particles.density, particles.specific_energy, particles.material,
                                         pack_materials(mats), pack_phases(mats)))


def solid_particles(particles) -> np.ndarray:
    """True where a particle is less than :data:`MELTED_SHARE` melted on release."""
    return released_phase(particles).melted < MELTED_SHARE
