"""Fragments of failed material, sized by the strain rate at which it failed (units cm, g, µs, Mbar).

The SPH resolves a fragment only when it is several particles across and the cracks around it left
a layer of failed particles (:func:`impactdyn.shield.fragments_of`).  At 4–8 km/s the particles of a
projectile fail nearly everywhere, while the fragments that hole a wall are a fifth of its diameter:
the cracks are finer than the particles and their spacing must come from a model.

**Size** (Grady 1982, J. Appl. Phys. 53, 322; the energy balance of a body breaking while it
stretches): material stretching at the rate ε̇ when it breaks forms fragments of size::

    s = (24 Γ / (ρ₀ ε̇²))^{1/3},     Γ = K_Ic² / E

the size at which the kinetic energy of the fragment's motion relative to its centre pays for the
new surfaces (Γ the fracture energy, K_Ic the fracture toughness, E Young's modulus: the form Zhou,
Molinari & Ramesh 2005 compare with resolved cohesive fragmentation).  ε̇ is the rate at which the
failed material was pulled apart, read across each fragment's own size against the initial positions
(``initial``: :func:`impactdyn.shield.own_size_strain_rates`), or, without ``initial``, the particle's
kernel-scale stretching rate on the first step it is failed and expanded beyond ρ₀
(``Particles.failure_strain_rate``), which grows as the particles shrink (median 0.85 → 1.27 ×10⁶ s⁻¹
from Δ = d/10 to d/20 at 6 km/s, about Δ^{-0.6}).

**Not converged yet (measured, docs/vv/convergence.md):** with the own-size rate the projectile's mass
in fragments of ≥ 0.06 cm agrees within 3 % between d/20 and d/40 at 4 km/s on a t/D 0.1 bumper, but
the largest projectile fragment does not (0.21 and 0.12 of the projectile), and at 6 km/s the pieces of
≥ 0.06 cm found at d/20 are gone at d/40: the set-4 gate fails (validation/set-4-decision.md), and the
fragments stay an option (``[shield] failed_fragments = "grady"``), not the default.

**Partition.**  The fragments' centres are a Poisson process of intensity 1/s³ in the failed solid
material, so the mean fragment volume is s³ (the cells of a Poisson–Voronoi tessellation; Grady &
Kipp's geometric statistics of fragmentation in three dimensions).  A failed particle of solid
volume V holds λ = V/s³ centres on average:

* λ ≥ 1: its fragments are no larger than the particle; they stay in the spray (the binned cloud);
* λ < 1: it holds a centre with probability λ (``seed``: the same seed, the same draw).

The particles with λ < 1 are linked into regions by friends-of-friends (link length b, as the intact
fragments are, :func:`impactdyn.shield.linked_groups`); each particle joins the nearest centre of its
region, and a region without a centre is one fragment.  Each fragment is a set of particles, so the
mass and momentum of the fragments and the rest are the particles' exactly.  Melted particles (at least
half melted on release, :func:`impactdyn.shield.released_phase`) form no solid fragment.  The partition is
drawn on the half model and mirrored, so a fragment across the symmetry plane x = 0 is found whole and is its
own image (as :func:`impactdyn.shield.fragments_of` finds the intact ones): a centre closer to the
plane than s/2 and its image are one centre on the plane (the mirrored pair's two cells, which the
plane would otherwise cut, joined).

Resolution: a fragment is a whole number of particles, so its mass is quantised by the particle's;
the fragments the wall resolves (≥ 0.06 cm) are 3–30 particles at the Whipple case's spacings.
"""

from __future__ import annotations

from functools import partial

import numpy as np
from scipy.spatial import cKDTree

from impactdyn._errors import InputError
from impactdyn.shield._fragment_rate import own_size_strain_rates
from impactdyn.shield._fragments import Fragments, fragments_of_groups, linked_groups
from impactdyn.shield._melt import solid_particles


def grady_fragment_size(toughness, density, young_modulus, strain_rate):
    """Grady's fragment size s = (24 K_Ic² / (E ρ₀ ε̇²))^{1/3}, cm (module docstring).

    toughness K_Ic Mbar·cm^½, density ρ₀ g/cm³, young_modulus E Mbar, strain_rate ε̇ µs⁻¹ (> 0);
    arrays broadcast.
    """
    toughness, strain_rate = np.asarray(toughness, float), np.asarray(strain_rate, float)
    return np.cbrt(24.0 * toughness ** 2 / (np.asarray(young_modulus, float) * np.asarray(density, float)
                                            * strain_rate ** 2))


def grady_fragments(particles, *, link_length_cm: float, damage_threshold: float = 1.0, seed: int = 1,
                    mirror_x0: bool = True, initial=None) -> Fragments:
    """The fragments of the failed solid particles of an SPH state (module docstring).

    Failed: damage ≥ ``damage_threshold`` with a recorded stretching rate at failure
    (``Particles.failure_strain_rate`` > 0), less than half melted on release.
    ``mirror_x0`` as :func:`impactdyn.shield.fragments_of`.  ``initial``: the run's state at t = 0
    (:class:`Particles`, the same particles in the same order); given, the rate that sizes a fragment is
    read across its own size (:func:`impactdyn.shield.own_size_strain_rates`, each body apart: the
    projectile, moving at t = 0, and the bumper); None, it is the kernel-scale rate recorded at failure.
    Returns fragments marked ``from_failed``.
    Raises :class:`InputError` naming a material of a failed particle without a fracture toughness
    (:data:`impactdyn.materials.FRACTURE_TOUGHNESS`).
    """
    from impactdyn.materials import FRACTURE_TOUGHNESS, get_material

    if not (0.0 < damage_threshold <= 1.0):
        raise InputError(f"damage_threshold = {damage_threshold}: must lie in (0, 1]")
    mats = [get_material(name) for name in particles.materials]
    kind = particles.material
    rho0 = np.array([m.rho0 for m in mats])[kind]
    rate = particles.failure_strain_rate
    failed = (particles.damage >= damage_threshold) & (rate > 0.0) & solid_particles(particles)
    missing = sorted({particles.materials[k] for k in np.unique(kind[failed])
                      if particles.materials[k] not in FRACTURE_TOUGHNESS})
    if missing:
        raise InputError(f"fragments of failed material: no fracture toughness for {', '.join(missing)} "
                         "(impactdyn.materials.FRACTURE_TOUGHNESS)")
    toughness = np.array([FRACTURE_TOUGHNESS.get(m.name, np.nan) for m in mats])[kind]
    young = np.array([m.young_modulus for m in mats])[kind]
    volume = particles.mass / rho0
    n = len(particles)
    size = np.full(n, np.inf)
    if initial is None:
        size[failed] = grady_fragment_size(toughness[failed], rho0[failed], young[failed], rate[failed])
    else:
        body = 2 * kind + np.any(initial.velocity != 0.0, axis=1)
        for b in np.unique(body[failed]):
            idx = np.flatnonzero(failed & (body == b))
            j = idx[0]  # one material a body
            size_of_rate = partial(grady_fragment_size, toughness[j], rho0[j], young[j])
            size[idx] = own_size_strain_rates(initial.position[idx], particles.velocity[idx], np.cbrt(volume[idx]),
                                              size_of_rate)[1]
    broken = failed & (volume < size ** 3)
    seeded = broken & (np.random.default_rng(seed).random(n) < volume / size ** 3)

    position, velocity, mass = particles.position, particles.velocity, particles.mass
    if mirror_x0:
        image = np.array([-1.0, 1.0, 1.0])
        position = np.concatenate([position, position * image])
        velocity = np.concatenate([velocity, velocity * image])
        mass, volume, broken, seeded = (np.concatenate([a, a]) for a in (mass, volume, broken, seeded))
    idx = np.flatnonzero(broken)
    group = _nearest_centre(position[idx], seeded[idx], linked_groups(position[idx], link_length_cm))
    group = np.where(group >= 0, idx[np.maximum(group, 0)], 2 * len(position) - group)  # centres by particle
    if mirror_x0:
        group = _mirrored(group, idx, n, seeded[:n] & (np.abs(particles.position[:, 0]) < 0.5 * size))
    return fragments_of_groups(position, velocity, mass, volume, idx, group, from_failed=True)


def _mirrored(group: np.ndarray, idx: np.ndarray, n: int, on_plane: np.ndarray) -> np.ndarray:
    """The groups (by centre particle, of the particles ``idx`` of a half model of n particles and its
    images n … 2n − 1) with each image in the image of its particle's group, so that the partition is
    mirror-symmetric even where a particle is as near to two centres (a lattice's ties); and the
    centres ``on_plane`` (n,) joined with their images: the half model cannot hold a centre just off
    its plane, whose cell the plane would cut."""
    local = np.full(2 * n, -1)
    local[idx] = np.arange(idx.size)
    images = idx[idx >= n]
    original = group[local[images - n]]
    by_centre = original < 2 * n
    group = group.copy()
    group[local[images[by_centre]]] = (original[by_centre] + n) % (2 * n)
    joined = np.arange(2 * n)
    joined[np.flatnonzero(on_plane) + n] = np.flatnonzero(on_plane)
    return np.where(group < 2 * n, joined[np.minimum(group, 2 * n - 1)], group)


def _nearest_centre(x: np.ndarray, centre: np.ndarray, region: np.ndarray) -> np.ndarray:
    """(k,) group of each point of x (k, 3): the index of the nearest centre (``centre`` a mask of x) in
    its own region, or, in a region without one, −1 − the region's number."""
    k = x.shape[0]
    group = -1 - region
    has_centre = np.zeros(region.max() + 1 if k else 0, dtype=bool)
    has_centre[region[centre]] = True
    inside = has_centre[region]
    if np.any(inside):
        # regions apart along a fourth axis, further than any two points of one region are
        far = 2.0 * float(np.ptp(x, axis=0).max()) + 1.0
        lifted = np.column_stack([x, far * region])
        which = np.flatnonzero(centre)
        _, nearest = cKDTree(lifted[which]).query(lifted[inside])
        group[inside] = which[nearest]
    return group
