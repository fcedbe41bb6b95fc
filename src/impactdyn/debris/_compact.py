"""Solid fragments carried to the rear wall as compact bodies (the debris's second population).

A fragment the SPH resolves and the wall's mesh can crater (:func:`impactdyn.whipple` picks them) is
not binned into the cloud: it flies ballistically from its hand-off state (centre of mass r_c,
velocity v_c; no force acts between bumper and wall) and strikes the wall's front face y = y_w as a
sphere of its solid volume (diameter d, density ρ = M/(πd³/6), the material's ρ₀)::

    t₀ = (y_w − y_c − d/2) / v_y                 (its front reaches the face; µs after hand-off)
    (x, z) = (x_c + v_x t₀, z_c + v_z t₀)        (where it strikes)

and loads it as :func:`impactdyn.wallgrid.sphere_deposition` lays a sphere down: each column of it
stopped at the wall at the rate ρ v_y², the tangential momentum in proportion (v_x/v_y, v_z/v_y).
Deformable, not rigid: at 2–7 km/s an aluminium fragment's impact pressure (tens of GPa) exceeds
its strength a hundredfold, so it flattens like a fluid column; that load gives the resolved wall the
Cour-Palais crater of one fragment within 20 % (studies/fragments/fragment_crater.py).

Half model (the wall's symmetry plane x = 0): a fragment on the plane (found whole with its image,
centre at x = 0) lays down its x ≥ 0 half; one beside it (x_c > 0) lays down all of itself, the part
of its footprint beyond the plane folded back, as its mirror image's part lands there; an image
(x_c < 0) lays down nothing of its own.  The records of a fragment whose footprint lies on the face
grid are scaled to carry exactly the fragment's (half-model) momentum, removing the sampling error of
the disc (0.2 % at four cells across); a footprint partly off the grid loses that part, as the cloud's
particles off the wall do.
"""

from __future__ import annotations

import numpy as np

from impactdyn._errors import InputError
from impactdyn.wallgrid import WallDeposition, WallGrid, sphere_deposition

#: |x_c| below this fraction of the diameter: the fragment lies on the symmetry plane (its centre is 0
#: to round-off, the particles and their images being exact mirrors).
ON_PLANE = 1e-9


def compact_deposition(wall: WallGrid, wall_y_cm: float, mass: np.ndarray, diameter_cm: np.ndarray,
                       position: np.ndarray, velocity: np.ndarray, *, half_model: bool = True
                       ) -> tuple[WallDeposition, np.ndarray]:
    """The deposition records of the fragments (module docstring) on ``wall``'s face grid at y = ``wall_y_cm``.

    mass (F,) g, diameter_cm (F,), position (F, 3) cm, velocity (F, 3) cm/µs: each fragment whole (a
    half model's images included, :func:`impactdyn.shield.fragments_of`).  Returns the records and
    each fragment's share of itself in the model (F,): ½ on the plane, 0 for an image, 1 otherwise (1
    for all without ``half_model``); the records carry share × mass × velocity when the footprint
    lies on the grid.
    """
    mass, diameter = np.asarray(mass, float), np.asarray(diameter_cm, float)
    position, velocity = np.asarray(position, float), np.asarray(velocity, float)
    if np.any(velocity[:, 1] <= 0.0):
        raise InputError("compact_deposition: every fragment must move toward the wall (v_y > 0)")
    share = half_model_share(position, diameter) if half_model else np.ones(mass.size)
    momentum = (share * mass)[:, None] * velocity
    arrival = compact_arrival_us(wall_y_cm, diameter, position, velocity)
    parts = []
    for f in np.flatnonzero(share > 0.0):
        v = velocity[f]
        t0 = arrival[f]
        x, z = position[f, 0] + v[0] * t0, position[f, 2] + v[2] * t0
        density = mass[f] / (np.pi * diameter[f] ** 3 / 6.0)
        centres = [x] if (not half_model or share[f] == 0.5) else [x, -x]   # the image's part beyond x = 0
        records = [sphere_deposition(wall, float(diameter[f]), float(v[1]), float(density), t0_us=float(t0),
                                     centre_xz=(cx, float(z))) for cx in centres]
        element = np.concatenate([r.element for r in records])
        time = np.concatenate([r.time for r in records])
        normal = np.concatenate([r.impulse[:, 1] for r in records])
        if _on_grid(wall, x, z, 0.5 * diameter[f], half_model):
            normal *= momentum[f, 1] / normal.sum()
        impulse = normal[:, None] * (v / v[1])[None, :]
        parts.append(WallDeposition(element=element, time=time, impulse=impulse))
    if not parts:
        return WallDeposition(element=np.zeros(0, np.int64), time=np.zeros(0), impulse=np.zeros((0, 3))), share
    return WallDeposition(element=np.concatenate([p.element for p in parts]),
                          time=np.concatenate([p.time for p in parts]),
                          impulse=np.concatenate([p.impulse for p in parts])), share


def half_model_share(position: np.ndarray, diameter_cm: np.ndarray) -> np.ndarray:
    """(F,) each whole fragment's share of itself in the half model (module docstring): ½ on the plane,
    0 for an image (x_c < 0), 1 beside the plane."""
    position, diameter = np.asarray(position, float), np.asarray(diameter_cm, float)
    on_plane = np.abs(position[:, 0]) <= ON_PLANE * diameter
    return np.where(on_plane, 0.5, np.where(position[:, 0] > 0.0, 1.0, 0.0))


def compact_arrival_us(wall_y_cm: float, diameter_cm: np.ndarray, position: np.ndarray,
                       velocity: np.ndarray) -> np.ndarray:
    """(F,) t₀ = (y_w − y_c − d/2) / v_y: when each fragment's front reaches the wall's face, µs after
    hand-off."""
    position, velocity = np.asarray(position, float), np.asarray(velocity, float)
    return (wall_y_cm - position[:, 1] - 0.5 * np.asarray(diameter_cm, float)) / velocity[:, 1]


def _on_grid(wall: WallGrid, x: float, z: float, radius: float, half_model: bool) -> bool:
    """The footprint (disc of ``radius`` about (x, z)) lies on the face grid (folded at x = 0 for a half model)."""
    x_low = wall.x[0] if not half_model else -np.inf
    return bool(x - radius >= x_low and abs(x) + radius <= wall.x[-1]
                and z - radius >= wall.z[0] and z + radius <= wall.z[-1])
