"""Binning of SPH particles onto a cell-centred HydroGrid (the hand-off to the debris stage, DESIGN §5–6).

Cloud-in-cell (trilinear) assignment: particle p at x spreads weights w_pc
(Σ_c w_pc = 1) over the eight cells whose centres surround it; weights that
fall outside the grid are folded onto the nearest boundary cell, so every
particle inside the region deposits all of its mass (exactly, to round-off) and
its momentum. At a symmetry plane on a grid face this is the image's share. Per cell::

    M = Σ_p w m,   M v = Σ_p w m v,   V_s = Σ_p w m/ρ        (solid volume)
    ρ = M / V_s,   φ = 1 − V_s / V_cell
    q = Σ_p w m q / M   for q = p, e, c, T                   (mass-weighted means)

If V_s > V_cell (sampling noise in compressed material) the cell is full: φ = 0
and ρ = M/V_cell, so that the bulk density (1 − φ) ρ always equals M/V_cell and
the debris stage's particle mass (1 − φ) ρ V reproduces the cell mass. Empty
cells have φ = 1 and all other fields 0.
"""

from __future__ import annotations

import math

import numpy as np

from impactdyn._errors import InputError
from impactdyn.debris import HydroGrid
from impactdyn.shield._state import Particles

Region = tuple[tuple[float, float], tuple[float, float], tuple[float, float]]


def _nodes(lo: float, hi: float, cell: float) -> np.ndarray:
    n = max(1, int(math.ceil((hi - lo) / cell - 1e-9)))
    return lo + cell * np.arange(n + 1)


def bin_to_hydrogrid(particles: Particles, cell_size_cm: float, region: Region | None = None) -> HydroGrid:
    """Cell-centred :class:`HydroGrid` (``staggered=False``) of ``particles`` (module docstring).

    cell_size_cm : cubic cell edge, cm (the report's DC3D cells: 0.03175 cm).
    region : ((x0, x1), (y0, y1), (z0, z1)), cm; the grid starts at the lower
        corner and is extended to whole cells; particles outside are left out.
        Default: the particles' bounding box with its corners rounded outward to
        multiples of the cell size (so a half model's symmetry plane x = 0 is the
        face x[0] whenever its particles lie within a cell of it).
    """
    cell = float(cell_size_cm)
    if not (math.isfinite(cell) and cell > 0):
        raise InputError(f"cell_size_cm: must be a positive number, got {cell_size_cm!r}")
    x = particles.position
    if len(particles) == 0:
        raise InputError("bin_to_hydrogrid: no particles")
    if region is None:
        region = tuple((cell * math.floor(x[:, a].min() / cell), cell * math.ceil(x[:, a].max() / cell))
                       for a in range(3))
    try:
        bounds = np.array(region, dtype=np.float64).reshape(3, 2)
    except (TypeError, ValueError):
        raise InputError(f"region: expected ((x0, x1), (y0, y1), (z0, z1)), got {region!r}") from None
    if not np.all(np.isfinite(bounds)) or np.any(bounds[:, 1] <= bounds[:, 0]):
        raise InputError(f"region: needs finite bounds with lower < upper on each axis, got {region!r}")
    nodes = [_nodes(lo, hi, cell) for lo, hi in bounds]
    shape = tuple(a.size - 1 for a in nodes)
    upper = np.array([a[-1] for a in nodes])
    inside = np.all((x >= bounds[:, 0]) & (x <= upper), axis=1)
    xs = x[inside]
    m = particles.mass[inside]
    carried = np.column_stack([
        m, m / particles.density[inside], m[:, None] * particles.velocity[inside],
        m * particles.pressure[inside], m * particles.specific_energy[inside],
        m * particles.sound_speed[inside], m * particles.temperature[inside]])

    xi = (xs - bounds[:, 0]) / cell - 0.5  # cell-centre coordinates
    base = np.floor(xi).astype(np.int64)
    frac = xi - base
    corners = np.array(list(np.ndindex(2, 2, 2)))  # (8, 3)
    cells = np.clip(base[:, None, :] + corners, 0, np.array(shape) - 1)  # (n, 8, 3)
    flat = np.ravel_multi_index((cells[..., 0], cells[..., 1], cells[..., 2]), shape).ravel()
    weight = np.prod(np.where(corners == 1, frac[:, None, :], 1.0 - frac[:, None, :]), axis=2)  # (n, 8)
    n_cells = int(np.prod(shape))
    sums = np.stack([np.bincount(flat, weights=(weight * col[:, None]).ravel(), minlength=n_cells)
                     for col in carried.T], axis=-1).reshape(shape + (carried.shape[1],))

    mass, solid = sums[..., 0], sums[..., 1]
    v_cell = cell**3 * np.ones(shape)
    has = mass > 0
    per_mass = np.divide(sums[..., 2:], mass[..., None], out=np.zeros(shape + (sums.shape[-1] - 2,)),
                         where=has[..., None])
    full = solid >= v_cell
    void = np.where(has, np.clip(1.0 - solid / v_cell, 0.0, 1.0), 1.0)
    density = np.divide(mass, np.where(full, v_cell, solid), out=np.zeros(shape), where=has)
    return HydroGrid(x=nodes[0], y=nodes[1], z=nodes[2], density=density, void_fraction=void, mass=mass,
                     pressure=per_mass[..., 3], temperature=per_mass[..., 6], specific_energy=per_mass[..., 4],
                     sound_speed=per_mass[..., 5], velocity=per_mass[..., 0:3], staggered=False, time=particles.time)
