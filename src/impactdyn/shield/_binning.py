"""Binning of SPH particles onto a cell-centred HydroGrid (the hand-off to the debris stage, docs/theory/binning.md).

Each particle p deposits its mass and the quantities it carries on the cells c
with weights w_pc, Σ_c w_pc = 1. Two assignments (``method``):

``"kernel"`` (default): the particle's own SPH kernel (:mod:`._kernel`, the M4
spline of support 2h_p), averaged over each cell and normalised per particle::

    w_pc = ∫_c W(x − x_p, h_p) dV / Σ_c' ∫_c' W(x − x_p, h_p) dV

The cell integrals are taken by the midpoint rule on s³ sub-cells of edge Δ/s,
s = ⌈2Δ/h_p⌉ (samples at most h_p/2 apart: s = 1, the kernel at the cell
centres, once h_p ≥ 2Δ; for h_p ≪ Δ the particle's whole kernel lies in its own
cell). The sum in the denominator runs over the unbounded lattice of cells, so
the discrete weights sum to 1 exactly whatever h_p/Δ (∫W dV = 1 holds for the
discrete sum only approximately).

Why: an SPH particle stands for the density field m_p W(x − x_p, h_p), not for a
point mass. Cloud-in-cell at the cell size puts it into the ≤ 8 cells around it,
so where the particles are farther apart than a cell — the expanding debris shell
— the grid is a set of clumps of one particle's mass each, which the debris stage
carries to the wall as a speckled map whose peak depends on the SPH resolution
(docs/vv/convergence.md, "The SPH spacing: the pipeline on Table 2's 7a"). Even a uniform block on a lattice
of 1/1.25 of the cell (the Whipple cases' 0.0254-cm particles in 0.03175-cm
cells) comes out in cloud-in-cell with density bands of −12 … +13 %; with the
kernel to 0.1 %. Binned with its kernel, the grid holds the SPH density field
averaged over each cell.

``"cic"``: cloud-in-cell (trilinear) over the eight cells whose centres surround x_p.

Both: the grid region selects the particles by position; a weight that falls
outside the grid is kept. Beyond the lower x face, when that face is the half
model's symmetry plane x = 0 (``mirror_x0``), the weight of ghost cell −1 − i goes
to cell i — the share of the image particle at (−x, y, z), since the cell centres
are symmetric about the face. Beyond any other face it is folded onto the
boundary cell. So every particle inside the region deposits all of its mass
(exactly, to round-off) and its momentum. (For cloud-in-cell, folding and
mirroring at a face coincide.) Per cell::

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
from functools import partial
from typing import Literal, get_args

import numpy as np
from numba import njit

from impactdyn._config import Positive, checked
from impactdyn._errors import InputError
from impactdyn.hydrogrid import DC3D_CELL_CM, HydroGrid
from impactdyn.shield._kernel import SUPPORT, w_shape
from impactdyn.shield._state import Particles

Region = tuple[tuple[float, float], tuple[float, float], tuple[float, float]]

BinningMethod = Literal["kernel", "cic"]
"""The particle-to-cell assignments of :func:`bin_to_hydrogrid`: each particle's own SPH kernel, or cloud-in-cell."""
METHODS: tuple[str, ...] = get_args(BinningMethod)

kernel = partial(njit, cache=True, error_model="numpy")


def _nodes(lo: float, hi: float, cell: float) -> np.ndarray:
    n = max(1, int(math.ceil((hi - lo) / cell - 1e-9)))
    return lo + cell * np.arange(n + 1)


@kernel
def _cic_weights(x):
    """Cloud-in-cell weights of a particle at x (3,), in cell units from the grid's lower corner.

    Returns the first cell's index (3,) and the weights (2, 2, 2) of the cells from it on.
    """
    lo = np.empty(3, dtype=np.int64)
    f = np.empty(3)
    for a in range(3):
        xi = x[a] - 0.5  # cell-centre coordinate
        lo[a] = math.floor(xi)
        f[a] = xi - lo[a]
    w = np.empty((2, 2, 2))
    for i in range(2):
        for j in range(2):
            for k in range(2):
                w[i, j, k] = ((f[0] if i else 1.0 - f[0]) * (f[1] if j else 1.0 - f[1])
                              * (f[2] if k else 1.0 - f[2]))
    return lo, w


@kernel
def _kernel_weights(x, h):
    """Unnormalised cell integrals of W(· − x, h) by the sub-cell midpoint rule (module docstring).

    x : (3,) and h in cell units. Returns the first cell's index (3,) and the
    weights (n_x, n_y, n_z) of the box of cells from it on that the support 2h touches.
    """
    s = max(1, math.ceil(2.0 / h))
    reach = SUPPORT * h
    n_max = int(2.0 * reach * s) + 2
    lo = np.empty(3, dtype=np.int64)
    nj = np.empty(3, dtype=np.int64)
    d2 = np.empty((3, n_max))  # squared distance from x of each sub-cell centre in reach, per axis
    box = np.empty((3, n_max), dtype=np.int64)  # its cell, counted from lo
    for a in range(3):
        # sub-cell j has its centre at (j + ½)/s
        j_lo = math.ceil((x[a] - reach) * s - 0.5)
        nj[a] = math.floor((x[a] + reach) * s - 0.5) - j_lo + 1
        lo[a] = j_lo // s
        for n in range(nj[a]):
            d2[a, n] = ((j_lo + n + 0.5) / s - x[a]) ** 2
            box[a, n] = (j_lo + n) // s - lo[a]
    w = np.zeros((box[0, nj[0] - 1] + 1, box[1, nj[1] - 1] + 1, box[2, nj[2] - 1] + 1))
    r2_max = reach * reach
    for a in range(nj[0]):
        for b in range(nj[1]):
            rab = d2[0, a] + d2[1, b]
            if rab >= r2_max:
                continue
            for c in range(nj[2]):
                r2 = rab + d2[2, c]
                if r2 < r2_max:
                    w[box[0, a], box[1, b], box[2, c]] += w_shape(math.sqrt(r2) / h)
    return lo, w


@kernel
def _scatter(x, h, carried, use_kernel, mirror_x0, sums):
    """sums[c] += Σ_p w_pc · carried[p] for all particles (module docstring).

    x : (n, 3) positions in cell units from the grid's lower corner (cell i spans [i, i + 1));
    h : (n,) smoothing lengths in cell units (read by the kernel assignment only);
    carried : (n, k); sums : (n_x, n_y, n_z, k), added to in place.
    """
    shape = sums.shape
    for p in range(x.shape[0]):
        if use_kernel:
            lo, w = _kernel_weights(x[p], h[p])
        else:
            lo, w = _cic_weights(x[p])
        w /= w.sum()
        for a in range(w.shape[0]):
            i = lo[0] + a
            if mirror_x0 and i < 0:
                i = -1 - i
            i = min(max(i, 0), shape[0] - 1)
            for b in range(w.shape[1]):
                j = min(max(lo[1] + b, 0), shape[1] - 1)
                for c in range(w.shape[2]):
                    wt = w[a, b, c]
                    if wt == 0.0:
                        continue
                    k = min(max(lo[2] + c, 0), shape[2] - 1)
                    for q in range(carried.shape[1]):
                        sums[i, j, k, q] += wt * carried[p, q]


@checked
def bin_to_hydrogrid(particles: Particles, cell_size_cm: Positive = DC3D_CELL_CM, region: Region | None = None, *,
                     method: BinningMethod = "kernel", mirror_x0: bool = True) -> HydroGrid:
    """Cell-centred :class:`HydroGrid` (``staggered=False``) of ``particles`` (module docstring).

    cell_size_cm : cubic cell edge, cm (default: the report's DC3D cells, 0.03175 cm).
    region : ((x0, x1), (y0, y1), (z0, z1)), cm; the grid starts at the lower
        corner and is extended to whole cells; particles outside are left out.
        Default: the particles' bounding box with its corners rounded outward to
        multiples of the cell size (so a half model's symmetry plane x = 0 is the
        face x[0] whenever its particles lie within a cell of it).
    method : "kernel" (each particle's SPH kernel of its own h) or "cic" (cloud-in-cell).
    mirror_x0 : the plane x = 0 is a symmetry plane (the shield stage's half
        models): where the grid's lower x face lies on it, weights beyond it go
        to the image cells; otherwise they are folded onto the face's cells.
    """
    cell = float(cell_size_cm)
    if method not in METHODS:
        raise InputError(f"method: {method!r}, expected one of {METHODS}")
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
    h = particles.smoothing_length[inside] / cell
    if method == "kernel" and np.any(h <= 0):
        raise InputError("bin_to_hydrogrid: kernel binning needs positive smoothing lengths")
    m = particles.mass[inside]
    carried = np.column_stack([
        m, m / particles.density[inside], m[:, None] * particles.velocity[inside],
        m * particles.pressure[inside], m * particles.specific_energy[inside],
        m * particles.sound_speed[inside], m * particles.temperature[inside]])
    sums = np.zeros(shape + (carried.shape[1],))
    _scatter((x[inside] - bounds[:, 0]) / cell, h, carried, method == "kernel",
             bool(mirror_x0 and bounds[0, 0] == 0.0), sums)

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
