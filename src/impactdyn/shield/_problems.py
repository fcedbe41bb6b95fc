"""Problem set-ups of the shield stage: sphere on plate (half model) and the planar-impact column.

Axes (consistent with the debris stage, docs/theory/debris.md): the debris flies toward the
rear wall along +y; the plate is normal to y with its front face at y = 0 and its
back face at y = thickness; x = 0 is the symmetry plane of the half model (the
impact plane is y–z), particles have x > 0. A projectile at obliquity θ moves
with v = V (0, cos θ, sin θ).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from impactdyn._errors import InputError
from impactdyn.materials import Material, get_material
from impactdyn.constitutive import T_ROOM
from impactdyn.shield._neighbours import Domain
from impactdyn.shield._state import Particles
from impactdyn.units import km_s_to_cm_us

#: h/Δ of the set-ups' initial smoothing lengths (the run recomputes h with its own option).
DEFAULT_H_FACTOR = 1.3
#: Particle lattices. Cubic only: the symmetry plane x = 0 must be a mirror plane of
#: the lattice, so that particles and their images continue it without a gap or an
#: overlap; the two stacking layers of an hcp lattice cannot both satisfy that.
LATTICES = ("cubic",)
#: The plate's radius when none is given, in projectile diameters.
DEFAULT_PLATE_RADIUS_D = 2.0


@dataclass(frozen=True, eq=False)
class Problem:
    """An initial particle state with its materials and boundary conditions.

    particles : the state at t = 0; ``particles.materials`` names ``materials`` in order.
    materials : the :class:`Material` of each material id.
    spacing_cm : the particle spacing Δ the particles were laid out with, cm: the resolution that
        lengths measured in particles (a fragment's link length) scale with.
    domain : mirror planes and periodic axes (:class:`Domain`).
    name : a label.
    """

    particles: Particles
    materials: tuple[Material, ...]
    spacing_cm: float
    domain: Domain = Domain()
    name: str = ""

    def __post_init__(self) -> None:
        object.__setattr__(self, "materials", tuple(self.materials))
        object.__setattr__(self, "spacing_cm", _positive("Problem.spacing_cm", self.spacing_cm))
        names = tuple(m.name for m in self.materials)
        if names != self.particles.materials:
            raise InputError(f"Problem: particles name materials {self.particles.materials}, given {names}")


def _particles(position: np.ndarray, velocity: np.ndarray, mass: np.ndarray, material: np.ndarray,
               materials: tuple[Material, ...]) -> Particles:
    """Particles at rest state ρ₀, e = 0, p = 0, S = 0, of the given material ids."""
    n = position.shape[0]
    rho0 = np.array([m.rho0 for m in materials])[material]
    c0 = np.array([m.c0 for m in materials])[material]
    return Particles(position=position, velocity=velocity, mass=mass, density=rho0, pressure=np.zeros(n),
                     specific_energy=np.zeros(n), deviatoric_stress=np.zeros((n, 6)), plastic_strain=np.zeros(n),
                     failed=np.zeros(n, dtype=bool), smoothing_length=DEFAULT_H_FACTOR * np.cbrt(mass / rho0),
                     sound_speed=c0, temperature=np.full(n, T_ROOM), material=material,
                     materials=tuple(m.name for m in materials))


def _positive(name: str, value: float) -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise InputError(f"{name}: must be a number, got {value!r}") from None
    if not (math.isfinite(v) and v > 0):
        raise InputError(f"{name}: must be a positive number, got {value!r}")
    return v


def spacing_too_coarse(spacing_cm: float, diameter_cm: float, plate_thickness_cm: float,
                       plate: str = "plate") -> str | None:
    """Why a particle spacing cannot model a sphere on a plate, as the end of "<spacing> is too coarse …"
    (``plate`` names the plate), or None: at least 4 particles across the sphere and one layer through the
    plate (a plate of 2/3 of a spacing and up keeps one layer, its thickness exact)."""
    if spacing_cm > diameter_cm / 4:
        return f"for the {diameter_cm} cm projectile: at least 4 particles across it"
    if spacing_cm > 1.5 * plate_thickness_cm:
        return f"for the {plate_thickness_cm} cm {plate}: at least one particle layer through it"
    return None


def _axis(lo: float, hi: float, step: float) -> np.ndarray:
    """lo + (k + ½)·step for k < round((hi − lo)/step) (at least one point)."""
    return lo + step * (np.arange(max(1, int(round((hi - lo) / step)))) + 0.5)


def sphere_on_plate(projectile: str | Material, plate: str | Material, diameter_cm: float, velocity_km_s: float,
                    obliquity_deg: float, plate_thickness_cm: float, spacing_cm: float,
                    plate_radius_cm: float | None = None, lattice: str = "cubic") -> Problem:
    """Half model of a sphere striking a plate (docs/theory/shield.md).

    Plate: the half disc x > 0, x² + z² ≤ R_p² (default R_p = 2 d, :data:`DEFAULT_PLATE_RADIUS_D`), y ∈ [0, t], on
    a cubic lattice of pitch Δ in x and z and t/round(t/Δ) through the thickness
    (so the areal density is exact). Projectile: the lattice points of pitch Δ
    (x = (i + ½)Δ, mirror-continuous across x = 0) inside the sphere of diameter
    d, its surface Δ/2 in front of the plate along y and placed so that the first
    contact is at the origin: centre (0, −d/2 − Δ/2, −(Δ/2) tan θ); velocity
    V (0, cos θ, sin θ). The projectile's particle masses are scaled so that its
    mass is exactly ρ π d³/12 (the half sphere); the lattice error of the count
    (a few per cent at 10 particles across) goes into the particle masses, not
    the impulse.
    """
    proj, targ = get_material(projectile), get_material(plate)
    d = _positive("diameter_cm", diameter_cm)
    speed = km_s_to_cm_us(_positive("velocity_km_s", velocity_km_s))
    t = _positive("plate_thickness_cm", plate_thickness_cm)
    dx = _positive("spacing_cm", spacing_cm)
    try:
        theta_deg = float(obliquity_deg)
    except (TypeError, ValueError):
        raise InputError(f"obliquity_deg: must be a number, got {obliquity_deg!r}") from None
    if not 0 <= theta_deg < 90:
        raise InputError(f"obliquity_deg: must lie in [0, 90), got {obliquity_deg!r}")
    radius_plate = (DEFAULT_PLATE_RADIUS_D * d if plate_radius_cm is None
                    else _positive("plate_radius_cm", plate_radius_cm))
    if radius_plate <= d / 2:
        raise InputError(f"plate_radius_cm: {radius_plate} must exceed the projectile radius {d / 2}")
    coarse = spacing_too_coarse(dx, d, t)
    if coarse:
        raise InputError(f"spacing_cm = {dx} is too coarse {coarse}")
    if lattice not in LATTICES:
        raise InputError(f"lattice: {lattice!r}, expected one of {LATTICES}")
    theta = math.radians(theta_deg)
    materials = (proj,) if proj == targ else (proj, targ)
    plate_id = 0 if len(materials) == 1 else 1

    # plate
    ny = max(1, int(round(t / dx)))
    dy = t / ny
    xs = _axis(0.0, radius_plate, dx)
    zs = dx * np.arange(-int(radius_plate / dx), int(radius_plate / dx) + 1)
    ys = dy * (np.arange(ny) + 0.5)
    gx, gy, gz = np.meshgrid(xs, ys, zs, indexing="ij")
    keep = gx**2 + gz**2 <= radius_plate**2
    plate_pos = np.stack([gx[keep], gy[keep], gz[keep]], axis=-1)

    # projectile
    r = d / 2
    gap = dx / 2
    centre = np.array([0.0, -r - gap, -gap * math.tan(theta)])
    k = int(math.ceil(r / dx)) + 1
    grid = dx * (np.arange(-k, k) + 0.5)
    px, py, pz = np.meshgrid(grid[grid > 0], grid, grid, indexing="ij")
    inside = px**2 + py**2 + pz**2 <= r**2
    proj_pos = np.stack([px[inside], py[inside], pz[inside]], axis=-1) + centre
    proj_mass = proj.rho0 * math.pi * d**3 / 12 / len(proj_pos)

    position = np.concatenate([proj_pos, plate_pos])
    n_p = len(proj_pos)
    velocity = np.zeros_like(position)
    velocity[:n_p] = speed * np.array([0.0, math.cos(theta), math.sin(theta)])
    mass = np.concatenate([np.full(n_p, proj_mass), np.full(len(plate_pos), targ.rho0 * dx * dx * dy)])
    material = np.concatenate([np.zeros(n_p, dtype=np.int64), np.full(len(plate_pos), plate_id, dtype=np.int64)])
    return Problem(particles=_particles(position, velocity, mass, material, materials), materials=materials,
                   spacing_cm=dx, domain=Domain(mirror=((0, 0.0),)),
                   name=f"sphere {d} cm {proj.name} on {t} cm {targ.name} at {velocity_km_s} km/s, {theta_deg} deg")


def planar_impact(flyer: str | Material, target: str | Material, velocity_km_s: float, flyer_length_cm: float,
                  target_length_cm: float, spacing_cm: float, width_particles: int = 4) -> Problem:
    """Quasi-1-D column: a flyer plate y ∈ [−L_f, 0] moving at +V ŷ onto a target y ∈ [0, L_t] at rest.

    Cubic lattice of pitch Δ, ``width_particles`` particles across in x and z,
    periodic in x and z (period width·Δ), so the flow is uniaxial strain along y.
    The period must exceed the kernel support 2h ≈ 2.6Δ: at least 3 particles across.
    """
    fly, targ = get_material(flyer), get_material(target)
    speed = km_s_to_cm_us(_positive("velocity_km_s", velocity_km_s))
    lf = _positive("flyer_length_cm", flyer_length_cm)
    lt = _positive("target_length_cm", target_length_cm)
    dx = _positive("spacing_cm", spacing_cm)
    if int(width_particles) != width_particles or width_particles < 3:
        raise InputError(f"width_particles: must be an integer ≥ 3, got {width_particles!r}")
    w = int(width_particles)
    materials = (fly,) if fly == targ else (fly, targ)
    lateral = dx * (np.arange(w) + 0.5)
    ys = np.concatenate([-_axis(0.0, lf, dx)[::-1], _axis(0.0, lt, dx)])
    gx, gy, gz = np.meshgrid(lateral, ys, lateral, indexing="ij")
    position = np.stack([gx.ravel(), gy.ravel(), gz.ravel()], axis=-1)
    is_flyer = position[:, 1] < 0
    velocity = np.zeros_like(position)
    velocity[is_flyer, 1] = speed
    rho0 = np.where(is_flyer, fly.rho0, targ.rho0)
    material = np.where(is_flyer, 0, len(materials) - 1).astype(np.int64)
    period = w * dx
    return Problem(particles=_particles(position, velocity, rho0 * dx**3, material, materials), materials=materials,
                   spacing_cm=dx, domain=Domain(periodic=((0, 0.0, period), (2, 0.0, period))),
                   name=f"planar {fly.name} on {targ.name} at {velocity_km_s} km/s")
