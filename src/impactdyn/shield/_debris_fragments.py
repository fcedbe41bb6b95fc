"""The debris's solid fragments at hand-off: how they are found, and which fly to the wall as compact bodies.

Two kinds of fragment leave the bumper (docs/theory/shield.md): the intact regions the cracks did not
reach (:func:`impactdyn.shield.fragments_of`), and, with ``failed_fragments = "grady"``, the failed solid
material partitioned into fragments of Grady's size (:func:`impactdyn.shield.grady_fragments`).  The
debris's fragments are those moving toward the wall; the compact ones, large enough for the wall to
crater, fly to it as bodies of their own (:func:`impactdyn.debris.compact_deposition`), the rest stays
in the binned cloud.  :class:`FragmentOptions` is the one home of these settings and their defaults;
the Whipple case's ``[shield]`` table exposes them under the same keys.
"""

from __future__ import annotations

from typing import Annotated, Literal

import numpy as np
from pydantic import Field, model_validator

from impactdyn._config import Positive, Section

FailedFragments = Literal["spray", "grady"]
FragmentRate = Literal["own_size", "at_failure"]

#: A fragment is debris when its centre of mass moves toward the wall faster than this share of the
#: projectile's speed: the bumper's remnant, the largest intact body, moves at a few m/s (7 m/s in a
#: 2-km/s shot), the debris at hundreds of m/s and more.
DEBRIS_FRAGMENT_SPEED_FRACTION = 0.05

#: The most draws of the partition one run may take: each draw is a wall run (20–60 s warm on 2 cores for
#: Table 2's 7a), so 64 draws are about an hour; more is a campaign, not a run.
MAX_FRAGMENT_DRAWS = 64

#: An intact debris fragment flies to the wall as a compact body when the SPH resolves it (at least
#: this many particles: two across).
COMPACT_MIN_PARTICLES = 8


class FragmentOptions(Section):
    """How the debris's solid fragments are found (module docstring).

    fragment_link_spacings : the friends-of-friends link length of the fragments at hand-off, in
        particle spacings (1.5 links a particle to its 18 nearest lattice neighbours; one broken layer
        separates two fragments).
    fragment_damage_threshold : a particle with damage below it (and less than half melted on release)
        is intact, part of a fragment (1: every particle that has not failed).
    failed_fragments : what the failed solid material of the debris becomes: ``"spray"``, the binned
        cloud; ``"grady"``, fragments of the size Grady's energy balance gives at the stretching rate
        ``fragment_rate`` (:func:`impactdyn.shield.grady_fragments`, seeded by ``fragment_seed``), those the wall
        resolves flying to it as compact bodies.  Needs the fragmentation failure model.
    fragment_seed : the seed of the random partition of the failed material into Grady's fragments.
    fragment_draws : how many partitions of the failed material a run draws, with the seeds
        ``fragment_seed``, ``fragment_seed + 1``, …: the SPH runs once, each draw's fragments fly to its own
        wall, and the run reports the perforations in k of N draws, P = k/N with its Wilson 95 % interval
        (1 to 64; more than 1 needs ``failed_fragments = "grady"``, the only random part).
    fragment_rate : the stretching rate that sizes Grady's fragments: ``"own_size"``, the velocity gradient
        of the failed material across each fragment's own size, against the particles' initial positions
        (:func:`impactdyn.shield.own_size_strain_rates`); ``"at_failure"``, the kernel-scale rate each
        particle recorded on failing, which grows as the spacing shrinks (kept to compare with).
    compact_bodies : the fragments large enough for the wall fly to it as compact bodies
        (:func:`compact_fragments`); true with the fragmentation failure model, whose intact regions are
        fragments (the threshold model's intact particles are what its compressive-strain criterion left).
        Set from the failure model, not a case key.
    """

    fragment_link_spacings: Positive = 1.5
    fragment_damage_threshold: Annotated[float, Field(gt=0, le=1)] = 1.0
    failed_fragments: FailedFragments = "spray"
    fragment_seed: Annotated[int, Field(ge=0)] = 1
    fragment_draws: Annotated[int, Field(ge=1, le=MAX_FRAGMENT_DRAWS)] = 1
    fragment_rate: FragmentRate = "own_size"
    compact_bodies: bool = False

    @model_validator(mode="after")
    def _draws_need_a_random_partition(self) -> "FragmentOptions":
        if self.fragment_draws > 1 and not self.grady:
            raise ValueError(f"fragment_draws = {self.fragment_draws} needs failed_fragments = \"grady\": without "
                             "Grady's partition the fragments are not drawn, and every draw would be the same")
        return self

    @property
    def seeds(self) -> tuple[int, ...]:
        """The partition seeds of the draws: ``fragment_seed`` and the next ``fragment_draws − 1``."""
        return tuple(range(self.fragment_seed, self.fragment_seed + self.fragment_draws))

    @property
    def grady(self) -> bool:
        """The failed solid material breaks into Grady's fragments (``failed_fragments = "grady"``)."""
        return self.failed_fragments == "grady"


#: The keys of :class:`FragmentOptions` a case table sets.
FRAGMENT_KEYS = ("fragment_link_spacings", "fragment_damage_threshold", "failed_fragments", "fragment_seed",
                 "fragment_draws", "fragment_rate")


def debris_fragments(particles, problem, options: FragmentOptions, impact_speed_cm_us: float):
    """The solid fragments of the debris in ``particles``, the shield stage's state of ``problem``
    (:func:`impactdyn.shield.fragments_of` with ``options``' link length, in the problem's particle
    spacings, and damage threshold, images of the half model included so that masses are the full
    model's; with Grady's fragments (``options.grady``) also those of the failed solid material,
    :func:`impactdyn.shield.grady_fragments`, sized at ``options.fragment_rate`` against the problem's state
    at t = 0): those moving toward the wall (v_y > :data:`DEBRIS_FRAGMENT_SPEED_FRACTION` of
    ``impact_speed_cm_us``), which leaves out the bumper's remnant; a fragment still crossing the
    bumper's plane counts."""
    from impactdyn.shield._fragments import fragments_of, join_fragments
    from impactdyn.shield._grady import grady_fragments

    link = options.fragment_link_spacings * problem.spacing_cm
    fragments = fragments_of(particles, link_length_cm=link, damage_threshold=options.fragment_damage_threshold)
    if options.grady:
        initial = problem.particles if options.fragment_rate == "own_size" else None
        fragments = join_fragments(fragments, grady_fragments(particles, link_length_cm=link,
                                                              damage_threshold=options.fragment_damage_threshold,
                                                              seed=options.fragment_seed, initial=initial))
    return fragments.select(fragments.velocity[:, 1] > DEBRIS_FRAGMENT_SPEED_FRACTION * impact_speed_cm_us)


def compact_fragments(fragments, options: FragmentOptions, *, min_diameter_cm: float):
    """The debris fragments carried to the wall as compact bodies, not binned (the second of the two
    populations to the wall): with ``options.compact_bodies`` only, at least ``min_diameter_cm`` across (the
    fragment the wall's mesh rule is built to crater, :data:`impactdyn.wall.FRAGMENT_DIAMETER_CM`), and,
    for an intact region, resolved by the SPH (:data:`COMPACT_MIN_PARTICLES`; a fragment of failed material
    has the size of the model that drew it, :func:`impactdyn.shield.grady_fragments`).  Smaller fragments
    stay in the binned cloud with their momentum."""
    carried = np.zeros(len(fragments), dtype=bool)
    if options.compact_bodies:
        carried = (((fragments.count >= COMPACT_MIN_PARTICLES) | fragments.from_failed)
                   & (fragments.diameter_cm >= min_diameter_cm))
    return fragments.select(carried)


def compact_particles(fragments, n_particles: int) -> np.ndarray:
    """``(n_particles,)`` bool: the particles of the half model in ``fragments`` (whose member indices
    count the images of :func:`impactdyn.shield.fragments_of` from ``n_particles`` on)."""
    taken = np.zeros(n_particles, dtype=bool)
    taken[fragments.members % n_particles] = True
    return taken
