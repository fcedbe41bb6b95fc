"""Figures of the debris cloud at hand-off, from the SPH particles (half model x ≥ 0).

The debris is every particle behind the bumper's back face (y > t_b) that moves
toward the wall (v_y > 0).  With mᵢ, vᵢ its masses and velocities (N_d,) and
(N_d, 3), and the full model's mirror image across x = 0:

* centre-of-mass velocity  v_cm = Σ mᵢ vᵢ / Σ mᵢ with its x component set to 0
  (the image cancels it); the cloud axis â = v_cm/|v_cm|, at the angle
  atan(v_cm,z / v_cm,y) from the wall normal;
* leading-edge velocity: the mean axial velocity vᵢ·â, mass-weighted, of the
  foremost debris holding 1 % of the debris mass (foremost by xᵢ·â; one
  particle alone is a noisy measure of the front);
* cone half-angle: the angle about â within which the flight directions of 95 %
  of the debris momentum Σ mᵢ|vᵢ| lie (the angle of vᵢ from â, image included);
* axial momentum: Σ mᵢ vᵢ,y, the momentum the wall can receive, and the debris mass.

Momenta are of the half model (g·cm/µs); the full model has twice the y and z
components and no x component.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from impactdyn._errors import InputError
from impactdyn.units import KM_S_PER_CM_US

#: Share of the debris mass whose mean axial velocity is the leading-edge velocity.
LEADING_MASS_FRACTION = 0.01
#: Share of the debris momentum inside the cone half-angle.
CONE_MOMENTUM_FRACTION = 0.95


def _weighted_quantile(values: np.ndarray, weights: np.ndarray, q: float) -> float:
    order = np.argsort(values)
    cum = np.cumsum(weights[order])
    return float(values[order][np.searchsorted(cum, q * cum[-1])])


def debris_mask(particles, bumper_back_y: float) -> np.ndarray:
    """``(N,)`` bool: particles behind the bumper's back face moving toward the wall."""
    return (particles.position[:, 1] > bumper_back_y) & (particles.velocity[:, 1] > 0)


def cloud_figures(particles, bumper_back_y: float) -> dict:
    """The module docstring's figures (velocities in km/s, angles in degrees, momenta g·cm/µs)."""
    debris = debris_mask(particles, bumper_back_y)
    if not np.any(debris):
        return {"n_debris_particles": 0, "debris_mass_g": 0.0}
    m = particles.mass[debris]
    v = particles.velocity[debris]
    x = particles.position[debris]
    v_cm = np.array([0.0, *(m @ v[:, 1:] / m.sum())])
    axis = v_cm / np.linalg.norm(v_cm)
    ahead = x @ axis
    front = ahead >= _weighted_quantile(ahead, m, 1.0 - LEADING_MASS_FRACTION)
    axial = v @ axis
    speed = np.linalg.norm(v, axis=1)
    angle = np.degrees(np.arccos(np.clip(axial / np.maximum(speed, 1e-300), -1.0, 1.0)))
    kms = KM_S_PER_CM_US
    return {
        "n_debris_particles": int(debris.sum()),
        "debris_mass_g": float(m.sum()),
        "centre_of_mass_velocity_km_s": (kms * v_cm).tolist(),
        "centre_of_mass_speed_km_s": float(kms * np.linalg.norm(v_cm)),
        "axis_angle_from_normal_deg": float(np.degrees(np.arctan2(v_cm[2], v_cm[1]))),
        "leading_edge_velocity_km_s": float(kms * (m[front] @ axial[front]) / m[front].sum()),
        "cone_half_angle_deg": _weighted_quantile(angle, m * speed, CONE_MOMENTUM_FRACTION),
        "axial_momentum_g_cm_us": float(m @ v[:, 1]),
        "momentum_g_cm_us": (m @ v).tolist(),
    }


def stage_fragments(folder: Path):
    """The debris fragments the shield stage of the run folder ``folder`` found (:func:`impactdyn.shield.debris_fragments`,
    ``shield/fragments.h5``): found once, read back exactly by the later stages.  A folder whose shield
    stage predates the file is refused, naming the stage to run from."""
    from impactdyn.shield import read_fragments

    path = Path(folder) / "shield" / "fragments.h5"
    if not path.is_file():
        raise InputError(f"{folder}: its shield stage kept no fragments file (shield/fragments.h5: a run folder "
                         "of an earlier version); run it again from the shield stage (--from shield)")
    return read_fragments(path)


def fragment_figures(fragments, from_projectile_g, projectile_mass_g: float) -> dict:
    """Numbers of the debris fragments (full model): how many, their mass and the part of it that was
    projectile material (``from_projectile_g``, each fragment's: :func:`impactdyn.shield.origin_masses`),
    the largest (mass, share of the projectile's mass, equivalent diameter, particles, speed)."""
    figures = {"n_fragments": len(fragments), "mass_g": fragments.total_mass(),
               "mass_from_projectile_g": float(np.sum(from_projectile_g))}
    if len(fragments):
        figures |= {"largest_g": float(fragments.mass[0]),
                    "largest_over_projectile": float(fragments.mass[0] / projectile_mass_g),
                    "largest_diameter_cm": float(fragments.diameter_cm[0]),
                    "largest_particles": int(fragments.count[0]),
                    "largest_speed_km_s": float(np.linalg.norm(fragments.velocity[0]) * KM_S_PER_CM_US)}
    return figures


def compact_fragments(fragments, case):
    """The debris fragments carried to the wall as compact bodies (:func:`impactdyn.shield.compact_fragments`
    with the case's fragment options), at least as large as the fragment the wall's mesh rule is built to
    crater (:data:`impactdyn.wall.FRAGMENT_DIAMETER_CM`, 0.06 cm: its crater spans ≥ 4 core elements)."""
    from impactdyn.shield import compact_fragments as compact
    from impactdyn.wall import FRAGMENT_DIAMETER_CM

    return compact(fragments, case.fragment_options, min_diameter_cm=FRAGMENT_DIAMETER_CM)


def projectile_particles(problem) -> np.ndarray:
    """``(N,)`` bool: the projectile's particles of the shield stage's problem (the sphere on plate): those
    moving at t = 0, the bumper being at rest.  The SPH state keeps the problem's particle order
    (:func:`impactdyn.shield.run`), so the mask holds for the state at hand-off too.  (Material id 0 is
    the projectile's only where the bumper is of another material.)"""
    return np.any(problem.particles.velocity != 0.0, axis=1)


def _phase_shares(mass: np.ndarray, melted: np.ndarray, vapour: np.ndarray) -> dict:
    """The mass and its solid, liquid and vapour shares by mass (None for no mass)."""
    total = float(mass.sum())
    if total <= 0.0:
        return {"mass_g": 0.0, "solid_mass_fraction": None, "liquid_mass_fraction": None,
                "vapour_mass_fraction": None}
    m_melted, m_vapour = float(mass @ melted) / total, float(mass @ vapour) / total
    return {"mass_g": total, "solid_mass_fraction": 1.0 - m_melted, "liquid_mass_fraction": m_melted - m_vapour,
            "vapour_mass_fraction": m_vapour}


def debris_state(particles, projectile: np.ndarray, fragments, bumper_back_y: float,
                 projectile_mass_g: float) -> dict:
    """The debris's state at hand-off: how much of it is solid, liquid and vapour, and the largest
    intact piece of the projectile.

    The debris is :func:`debris_mask`'s (half model).  Each particle released along its isentrope to zero
    pressure (:func:`impactdyn.shield.released_phase`) is 1 − χ_m solid, χ_m − χ_v liquid and χ_v vapour;
    the shares are mass-weighted over the debris, over its projectile particles (``projectile``, (N,) bool,
    :func:`projectile_particles`) and over its bumper particles; ``mass_g`` is each one's mass in the half
    model; the shares are None where there is no such debris.

    The largest projectile piece: the heaviest of ``fragments`` (:func:`impactdyn.shield.debris_fragments`, whose members
    count the images of the half model from N on and whose masses are the full model's) that is an intact
    region (not a fragment of failed material) and more than half projectile by mass; its mass (g, full
    model), its share of the projectile's mass ``projectile_mass_g`` (the full sphere), its equivalent
    diameter and particle count (images included); None for each where there is none."""
    from impactdyn.shield import released_phase

    debris = debris_mask(particles, bumper_back_y)
    phase = released_phase(particles)
    mass = particles.mass

    def shares(mask):
        return _phase_shares(mass[mask], phase.melted[mask], phase.vapour[mask])

    state = shares(debris) | {"projectile": shares(debris & projectile), "bumper": shares(debris & ~projectile)}
    both = np.concatenate([projectile, projectile])  # the fragments' member indices count the images
    m_both = np.concatenate([mass, mass])
    piece = None
    for f in range(len(fragments)):  # largest first
        members = fragments.indices(f)
        if not fragments.from_failed[f] and m_both[members[both[members]]].sum() > 0.5 * m_both[members].sum():
            piece = f
            break
    if piece is None:
        return state | {"largest_projectile_piece_g": None, "largest_projectile_piece_over_projectile": None,
                        "largest_projectile_piece_diameter_cm": None, "largest_projectile_piece_particles": None}
    return state | {
        "largest_projectile_piece_g": float(fragments.mass[piece]),
        "largest_projectile_piece_over_projectile": float(fragments.mass[piece] / projectile_mass_g),
        "largest_projectile_piece_diameter_cm": float(fragments.diameter_cm[piece]),
        "largest_projectile_piece_particles": int(fragments.count[piece])}
