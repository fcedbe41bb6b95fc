"""Boundary images and the cell-list neighbour search.

Boundaries (:class:`Domain`) are represented by *images*: affine maps
``T(x) = s ⊙ x + o`` (s ∈ {±1}³, o ∈ ℝ³) that carry a real particle to a ghost.
A mirror plane x_a = c reflects (s_a = −1, o_a = 2c); a periodic axis
[lo, hi) shifts by ±L (o_a = ±L). The image set is the product over the
constrained axes, identity first. A ghost carries the transformed state: velocity
s ⊙ v, stress σ'_{αβ} = s_α s_β σ_{αβ}, everything else unchanged — so no ghost
particles are stored, only (j, image) pairs.

Neighbours: i and the image T(xⱼ) interact when |xᵢ − T(xⱼ)| < 2hᵢⱼ with
hᵢⱼ = (hᵢ + hⱼ)/2 (the symmetric smoothing length of the pair, which keeps the
pair forces antisymmetric). Search: particles are counting-sorted into cubic
cells of edge max h + ℓ/2 (ℓ the skin, below; cell key (ix·n_y + iy)·n_z + iz, a
start index per cell); for each particle and image the query point
T⁻¹(xᵢ) = s ⊙ (xᵢ − o) is looked up in the cells within reach
hᵢ + max h + ℓ, each z-run of cells being one contiguous
slice of the sorted particles. Pairs (i, T(j)) with T(j) found from T⁻¹(xᵢ) are
exactly those of the definition, since |xᵢ − T(xⱼ)| = |T⁻¹(xᵢ) − xⱼ| for these
isometries.

The list is stored per particle with a fixed capacity (``neighbours`` (N, cap)
int32, ``image`` (N, cap) int8, ``count`` (N,)); :class:`NeighbourList` grows
the capacity when a particle overflows it and keeps the arrays between steps.
A half list holds a pair of real particles (image 0) in one of its two rows only,
for a force loop that applies each such pair to both particles; image pairs are
in both rows.

Reuse (a Verlet list with a skin ℓ ≥ 0): the list is built with the pairs
|xᵢ − T(xⱼ)| < hᵢ + hⱼ + ℓ, at positions x⁰ and smoothing lengths h⁰, and kept
while every particle satisfies

    2 δ_max ≤ ℓ,   δᵢ = |xᵢ − xᵢ⁰| + max(hᵢ − hᵢ⁰, 0).

It then still holds every interacting pair: |xᵢ − T(xⱼ)| ≥ |xᵢ⁰ − T(xⱼ⁰)| −
|xᵢ − xᵢ⁰| − |xⱼ − xⱼ⁰| (T is an isometry), so a pair left out at the build
(distance ≥ hᵢ⁰ + hⱼ⁰ + ℓ) is now at least

    hᵢ⁰ + hⱼ⁰ + ℓ − (δᵢ + δⱼ) + max(hᵢ − hᵢ⁰, 0) + max(hⱼ − hⱼ⁰, 0) ≥ hᵢ + hⱼ + ℓ − 2δ_max ≥ hᵢ + hⱼ

apart. The list may hold pairs beyond the support; the force loop skips them
by the same test as the search (|xᵢ − T(xⱼ)| < hᵢ + hⱼ), so the pairs that
interact, and the results, are those of a search at every step up to the order
of summation. ℓ = 0 searches again whenever anything moved. A particle crossing a periodic boundary changes the
image of its pairs, so the wrap (:meth:`Domain.wrap`) reports crossings and the
caller discards the list (:meth:`NeighbourList.invalidate`).
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

import numpy as np
from numba import njit, prange

from impactdyn._errors import InputError


@dataclass(frozen=True)
class Domain:
    """Boundary conditions by images.

    mirror : tuple of (axis, position)
        Symmetry planes x_axis = position (at most one per axis).
    periodic : tuple of (axis, lo, hi)
        Periodic axes with period hi − lo (at most one condition per axis).
    """

    mirror: tuple[tuple[int, float], ...] = ()
    periodic: tuple[tuple[int, float, float], ...] = ()

    def __post_init__(self) -> None:
        axes = [a for a, _ in self.mirror] + [a for a, _, _ in self.periodic]
        if any(a not in (0, 1, 2) for a in axes) or len(set(axes)) != len(axes):
            raise InputError(f"Domain: one boundary condition per axis 0, 1, 2; got axes {axes}")
        if any(not hi > lo for _, lo, hi in self.periodic):
            raise InputError(f"Domain: a periodic axis needs hi > lo, got {self.periodic}")

    def transforms(self) -> tuple[np.ndarray, np.ndarray]:
        """Image maps as (signs (K, 3), offsets (K, 3)); row 0 is the identity."""
        options = [[(1.0, 0.0)] for _ in range(3)]
        for axis, c in self.mirror:
            options[axis].append((-1.0, 2.0 * c))
        for axis, lo, hi in self.periodic:
            options[axis] += [(1.0, hi - lo), (1.0, lo - hi)]
        combos = list(itertools.product(*options))
        signs = np.array([[o[0] for o in combo] for combo in combos])
        offsets = np.array([[o[1] for o in combo] for combo in combos])
        return signs, offsets

    def wrap(self, x: np.ndarray) -> bool:
        """Map positions (N, 3) back into the periodic box, in place; whether any particle crossed a boundary.

        Only the particles outside [lo, hi) move, so that the others keep their positions bit for bit.
        """
        crossed = False
        for axis, lo, hi in self.periodic:
            out = np.flatnonzero((x[:, axis] < lo) | (x[:, axis] >= hi))
            if out.size:
                x[out, axis] = lo + np.mod(x[out, axis] - lo, hi - lo)
                crossed = True
        return crossed

    def min_period(self) -> float:
        return min((hi - lo for _, lo, hi in self.periodic), default=math.inf)


@njit(cache=True)
def _cell_grid(x, cell):
    """Counting sort of particles x (N, 3) into cubic cells of edge ≥ ``cell``.

    Returns (lo (3,), edge, dims (3,), start (n_cells + 1,), order (N,)): the
    particles of cell key k = (ix·n_y + iy)·n_z + iz are order[start[k]:start[k+1]].
    If the bounding box would need more than max(64 N, 2²⁰) cells (a few far
    outliers), the edge is enlarged until it does not — slower, never wrong.
    """
    n = x.shape[0]
    lo = np.empty(3)
    span = np.empty(3)
    for a in range(3):
        lo[a] = x[0, a]
        hi = x[0, a]
        for i in range(n):
            lo[a] = min(lo[a], x[i, a])
            hi = max(hi, x[i, a])
        span[a] = hi - lo[a]
    most = max(64 * n, 1 << 20)
    edge = cell
    while (span[0] / edge + 1.0) * (span[1] / edge + 1.0) * (span[2] / edge + 1.0) > most:
        edge *= 1.25
    dims = np.empty(3, dtype=np.int64)
    for a in range(3):
        dims[a] = int(span[a] / edge) + 1
    start = np.zeros(dims[0] * dims[1] * dims[2] + 1, dtype=np.int64)
    keys = np.empty(n, dtype=np.int64)
    for i in range(n):
        ix = min(int((x[i, 0] - lo[0]) / edge), dims[0] - 1)
        iy = min(int((x[i, 1] - lo[1]) / edge), dims[1] - 1)
        iz = min(int((x[i, 2] - lo[2]) / edge), dims[2] - 1)
        keys[i] = (ix * dims[1] + iy) * dims[2] + iz
        start[keys[i] + 1] += 1
    for k in range(1, start.size):
        start[k] += start[k - 1]
    fill = start[:-1].copy()
    order = np.empty(n, dtype=np.int64)
    for i in range(n):
        order[fill[keys[i]]] = i
        fill[keys[i]] += 1
    return lo, edge, dims, start, order


@njit(cache=True)
def _cell_range(q, reach, lo, cell, dim):
    """Cells [c0, c1] of one axis within reach of coordinate q (empty when c0 > c1)."""
    a = math.floor((q - reach - lo) / cell)
    b = math.floor((q + reach - lo) / cell)
    c0 = int(min(max(a, 0.0), dim))
    c1 = int(max(min(b, dim - 1.0), -1.0))
    return c0, c1


@njit(parallel=True, cache=True)
def find_neighbours(x, h, skin, half, signs, offsets, neighbours, image, count):
    """Fill the neighbour list of positions x (N, 3) with smoothing lengths h (N,) and skin ℓ ≥ 0.

    Lists the pairs |xᵢ − T(xⱼ)| < hᵢ + hⱼ + ℓ; with ``half``, a pair of real
    particles (image 0) in the row of the lower index only (image pairs stay in
    both rows). Writes up to ``neighbours.shape[1]`` pairs per particle into
    ``neighbours`` (j) and ``image`` (image index); ``count[i]`` is the true
    number of neighbours of i (it may exceed the capacity). Returns max(count).
    """
    n = x.shape[0]
    cap = neighbours.shape[1]
    hmax = h.max()
    lo, cell, dims, start, order = _cell_grid(x, hmax + 0.5 * skin)
    for i in prange(n):
        c = 0
        reach = h[i] + hmax + skin
        for t in range(signs.shape[0]):
            q0 = signs[t, 0] * (x[i, 0] - offsets[t, 0])
            q1 = signs[t, 1] * (x[i, 1] - offsets[t, 1])
            q2 = signs[t, 2] * (x[i, 2] - offsets[t, 2])
            x0, x1 = _cell_range(q0, reach, lo[0], cell, dims[0])
            y0, y1 = _cell_range(q1, reach, lo[1], cell, dims[1])
            z0, z1 = _cell_range(q2, reach, lo[2], cell, dims[2])
            if z0 > z1:
                continue
            for cx in range(x0, x1 + 1):
                for cy in range(y0, y1 + 1):
                    row = (cx * dims[1] + cy) * dims[2]
                    for s in range(start[row + z0], start[row + z1 + 1]):
                        j = order[s]
                        if t == 0 and (j == i or (half and j < i)):
                            continue
                        d0 = q0 - x[j, 0]
                        d1 = q1 - x[j, 1]
                        d2 = q2 - x[j, 2]
                        support = h[i] + h[j] + skin
                        if d0 * d0 + d1 * d1 + d2 * d2 < support * support:
                            if c < cap:
                                neighbours[i, c] = j
                                image[i, c] = t
                            c += 1
        count[i] = c
    return count.max()


@njit(parallel=True, cache=True)
def list_drift(x, h, x_built, h_built):
    """δ_max = maxᵢ |xᵢ − xᵢ⁰| + max(hᵢ − hᵢ⁰, 0) of positions x (N, 3) and h (N,) since the list's build."""
    drift = 0.0
    for i in prange(x.shape[0]):
        d0 = x[i, 0] - x_built[i, 0]
        d1 = x[i, 1] - x_built[i, 1]
        d2 = x[i, 2] - x_built[i, 2]
        drift = max(drift, math.sqrt(d0 * d0 + d1 * d1 + d2 * d2) + max(h[i] - h_built[i], 0.0))
    return drift


@njit(parallel=True, cache=True)
def _permute_rows(order, neighbours, image, count, x_built, h_built):
    """The list of the particles renumbered so that new i is old order[i] (rows moved, j renamed)."""
    n = order.size
    new_index = np.empty(n, dtype=np.int32)
    for i in range(n):
        new_index[order[i]] = i
    nb, im, ct = np.empty_like(neighbours), np.empty_like(image), np.empty_like(count)
    xb, hb = np.empty_like(x_built), np.empty_like(h_built)
    cap = neighbours.shape[1]
    for i in prange(n):
        o = order[i]
        ct[i] = count[o]
        for k in range(min(count[o], cap)):
            nb[i, k] = new_index[neighbours[o, k]]
            im[i, k] = image[o, k]
        for a in range(3):
            xb[i, a] = x_built[o, a]
        hb[i] = h_built[o]
    return nb, im, ct, xb, hb


@njit(cache=True)
def spatial_order(x, h):
    """Permutation of particles x (N, 3) that sorts them by the key of their search cell (edge 2 max h)."""
    return _cell_grid(x, 2.0 * h.max())[4]


class NeighbourList:
    """Per-particle neighbour list kept between steps (module docstring): grows when a particle overflows it,
    and is searched again only when the particles have moved or h has grown by more than the skin allows.

    skin : ℓ as a fraction of the largest smoothing length at the build (0: search whenever anything moved).
    half : list each pair of real particles once (in one of the two rows; image pairs in both), for a
        force loop that applies each such pair to both particles.
    """

    def __init__(self, n: int, domain: Domain, capacity: int = 96, skin: float = 0.0, half: bool = False):
        self.signs, self.offsets = domain.transforms()
        self.skin_factor, self.half = skin, half
        self.skin = 0.0
        self.neighbours = np.empty((n, capacity), dtype=np.int32)
        self.image = np.empty((n, capacity), dtype=np.int8)
        self.count = np.zeros(n, dtype=np.int64)
        self.x_built = np.empty((n, 3))
        self.h_built = np.empty(n)
        self.valid = False
        self.builds = 0

    def update(self, x: np.ndarray, h: np.ndarray) -> bool:
        """Make the list hold every interacting pair of (x, h); returns whether it was searched again."""
        if self.valid and 2.0 * list_drift(x, h, self.x_built, self.h_built) <= self.skin:
            return False
        self.skin = self.skin_factor * float(h.max())
        most = self._search(x, h)
        if most > self.neighbours.shape[1]:
            capacity = int(1.25 * most) + 8
            self.neighbours = np.empty((x.shape[0], capacity), dtype=np.int32)
            self.image = np.empty((x.shape[0], capacity), dtype=np.int8)
            self._search(x, h)
        self.x_built[:] = x
        self.h_built[:] = h
        self.valid = True
        self.builds += 1
        return True

    def invalidate(self) -> None:
        """Search again at the next update (a particle changed its periodic image)."""
        self.valid = False

    def permute(self, order: np.ndarray) -> None:
        """Follow a renumbering of the particles: new particle i is old particle order[i]."""
        if self.valid:
            (self.neighbours, self.image, self.count, self.x_built,
             self.h_built) = _permute_rows(order, self.neighbours, self.image, self.count, self.x_built, self.h_built)

    def _search(self, x: np.ndarray, h: np.ndarray) -> int:
        return find_neighbours(x, h, self.skin, self.half, self.signs, self.offsets, self.neighbours, self.image,
                               self.count)


def neighbour_pairs(x: np.ndarray, h: np.ndarray, domain: Domain = Domain()) -> np.ndarray:
    """All interacting (i, j, image) triples of positions x (N, 3) and h (N,), shape (P, 3), sorted."""
    x = np.ascontiguousarray(x, dtype=np.float64)
    h = np.ascontiguousarray(h, dtype=np.float64)
    nl = NeighbourList(x.shape[0], domain, capacity=8)
    nl.update(x, h)
    rows = [(i, int(nl.neighbours[i, k]), int(nl.image[i, k])) for i in range(x.shape[0])
            for k in range(nl.count[i])]
    return np.array(sorted(rows), dtype=np.int64).reshape(-1, 3)
