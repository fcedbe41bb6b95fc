"""The compact fragments' landing: which of them reach the wall during its run, and the debris result with
their records beside the cloud's (the two populations to the wall in one deposition; :mod:`._compact`
lays each one down).  The fragments are :class:`impactdyn.shield.Fragments` of the shield stage's debris
(:func:`impactdyn.shield.compact_fragments`): only their masses, diameters, positions and velocities are read.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from impactdyn.debris._compact import compact_arrival_us, compact_deposition, half_model_share
from impactdyn.debris._deposit import areal_density, element_impulse
from impactdyn.wallgrid import WallDeposition, WallGrid


def landing_mask(fragments, wall_y_cm: float, t_min_us: float, end_us: float) -> np.ndarray:
    """``(F,)`` bool: the compact fragments that land during the wall run.

    A compact fragment lands whenever it arrives from ``t_min_us`` (``[filter] t_min_us``) and has passed
    into the wall (its rear at the face, d/v_y after its front: its records' last) by the wall run's end
    ``end_us``, not only inside the cloud's arrival window (``t_cut_us``, the 1994 code's budget for its
    many particles): a slow solid fragment still craters the wall it reaches.  One arriving after the run is
    stated by the debris summary (:func:`with_compact_fragments`), not silently dropped."""
    arrival = compact_arrival_us(wall_y_cm, fragments.diameter_cm, fragments.position, fragments.velocity)
    passed = arrival + fragments.diameter_cm / fragments.velocity[:, 1]
    return (arrival >= t_min_us) & (passed <= end_us)


def compact_records(face: WallGrid, wall_y_cm: float, fragments, inside: np.ndarray) -> WallDeposition:
    """The records of the compact fragments that land (``inside``, :func:`landing_mask`) on the face grid
    ``face`` (:func:`impactdyn.debris.compact_deposition`)."""
    landing = fragments.select(inside)
    return compact_deposition(face, wall_y_cm, landing.mass, landing.diameter_cm, landing.position,
                              landing.velocity)[0]


def with_compact_fragments(result, fragments, inside: np.ndarray, wall_y_cm: float):
    """The debris result (:class:`impactdyn.debris.DebrisResult`) with the records of the compact fragments
    that land during the wall run (``inside``, :func:`landing_mask`) added to the cloud's: the wall and the
    decks read one deposition, the two populations in it.  A fragment outside lays down nothing.  Returns
    the result and the fragments' record (how many, their mass and momentum in the half model, how many, how
    much mass and momentum arrive outside the wall run (``*_outside_window``: the compact fragments' window
    is the wall run), the momentum their records deposit; ``momentum_deposited`` of the summary holds both
    populations)."""
    records = compact_records(result.wall, wall_y_cm, fragments, inside)
    share = half_model_share(fragments.position, fragments.diameter_cm)
    mass = share * fragments.mass          # in the half model: images carry none of their own
    record = {"n_fragments": int(np.count_nonzero(share)), "mass_g": float(mass.sum()),
              "momentum": (mass @ fragments.velocity).tolist(),
              "n_outside_window": int(np.count_nonzero(share[~inside])),
              "mass_outside_window_g": float(mass[~inside].sum()),
              "momentum_outside_window": (mass[~inside] @ fragments.velocity[~inside]).tolist(),
              "momentum_deposited": records.impulse.sum(axis=0).tolist()}
    if not len(records.element):
        return result, record
    deposition = WallDeposition(element=np.concatenate([result.deposition.element, records.element]),
                                time=np.concatenate([result.deposition.time, records.time]),
                                impulse=np.concatenate([result.deposition.impulse, records.impulse]))
    impulse = result.impulse + element_impulse(records, result.wall)
    return replace(result, deposition=deposition, impulse=impulse, areal=areal_density(impulse, result.wall)), record
