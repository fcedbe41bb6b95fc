"""The rate at which failed material was pulled apart, measured across each fragment's own size.

Grady's fragment size comes from the rate at which the breaking body is pulled apart, the imposed
expansion rate (Grady 1981, JGR 86:1047; 1982, J. Appl. Phys. 53:322).  The rate the SPH records when
a particle fails is the stretching rate inside the failure band, a kernel-scale rate that grows as the
band narrows with the spacing (about Δ^-0.6, docs/vv/convergence.md).  Here the rate is read instead
on a length of the material's own: the fragment's size s.

**The rate.**  Once failed material flies apart its pieces move freely, so the velocity each one
carries is the one it was given when the body was pulled apart.  Read against the particles'
*reference* (initial) positions X, the velocity field of the failed material is then, over a region
of the size of one fragment, v(X) ≈ a + G (X − Xⱼ), and G = ∂v/∂X is the rate of the deformation
gradient imposed on that region: for a body expanding uniformly at ε̇ (x = X (1 + ε̇ t)), G = ε̇ I at
any time, where the current-configuration gradient ∂v/∂x = ε̇/(1 + ε̇ t) decays as it flies.  G is
fitted by least squares over the failed particles of the same body within the radius::

    r = max(s/2, r_floor),   r_floor = 1.6 Δ

of each one (Δ = (m/ρ₀)^⅓ the particle's own spacing; within 1.6 Δ a cubic lattice holds a point's 18
nearest neighbours, enough for the 12 unknowns of a, G), and the rate is the largest principal value
of sym(G).  s is Grady's size at that rate, so r and s are iterated to a fixed point, starting at
r_floor; r is at most the body's half extent (no fragment outgrows its body; a region compressed or
at rest, whose s is infinite, is fitted over that).  A fragment smaller than the floor stays in the
spray (it is smaller than its particle, :func:`impactdyn.shield.grady_fragments`), so the floor decides
nothing there; the fragments the wall resolves are several particles across, and their rate is read
over their own size, not the kernel's.

**Cost.**  A fit over r = 20 Δ would take 33,000 points; a few hundred well spread ones average the
particles' own jitter as well.  A radius between 2^L and 2^(L+1) times 3.2 cells is fitted on the points
kept by a grid of 2^L Δ cells (one a cell, the first), so every fit takes 137–1,100 points whatever its
radius (fewer below 3.2 Δ), the same number at every spacing, and a pass costs O(N).
"""

from __future__ import annotations

from itertools import chain
from typing import Callable

import numpy as np
from numba import njit
from scipy.spatial import cKDTree

#: The fit's smallest radius, in the particle's own spacing (module docstring).
RADIUS_FLOOR_SPACINGS = 1.6
#: The fewest points a fit takes: a and G are 12 unknowns, 4 per velocity component.
MIN_POINTS = 5
#: The fixed point of radius and size is reached when no radius changes by more than this share.
RADIUS_TOLERANCE = 0.01
#: At most this many passes of the fixed point (module docstring).
MAX_PASSES = 12
#: A level's smallest radius, in its cells (module docstring, "Cost").
LEVEL_RADIUS_CELLS = 3.2
#: Points fitted per batch (bounds the neighbour lists' memory).
BATCH = 4096


@njit(cache=True)
def _fitted_rates(points, reference, velocity, start, neighbours, rates):
    """rates[k] = the largest principal value of sym(G) for the point ``points[k]``, G fitted by least
    squares to v ≈ a + G (X − X_k) over ``neighbours[start[k]:start[k + 1]]``; NaN with fewer than
    :data:`MIN_POINTS` of them."""
    for k in range(points.size):
        j = points[k]
        near = neighbours[start[k]:start[k + 1]]
        if near.size < MIN_POINTS:
            rates[k] = np.nan
            continue
        design = np.ones((near.size, 4))
        values = np.empty((near.size, 3))
        for q in range(near.size):
            for d in range(3):
                design[q, d + 1] = reference[near[q], d] - reference[j, d]
                values[q, d] = velocity[near[q], d]
        coefficients = np.linalg.lstsq(design, values)[0]      # rows 1..3: G transposed
        strain = np.empty((3, 3))
        for r in range(3):
            for c in range(3):
                strain[r, c] = 0.5 * (coefficients[c + 1, r] + coefficients[r + 1, c])
        rates[k] = np.linalg.eigvalsh(strain)[2]


def own_size_strain_rates(reference: np.ndarray, velocity: np.ndarray, spacing: np.ndarray,
                          size_of_rate: Callable[[np.ndarray], np.ndarray]) -> tuple[np.ndarray, np.ndarray, int]:
    """The stretching rate of failed material across each fragment's own size (module docstring).

    reference, velocity : (N, 3) the failed particles of one body: their initial positions (cm) and
        their velocities now (cm/µs).
    spacing : (N,) each particle's own spacing Δ, cm.
    size_of_rate : the fragment size (cm) at a rate (µs⁻¹), array in, array out (Grady's).

    Returns (rates µs⁻¹, sizes cm, passes): a rate of at most 0 (a region compressed or at rest) or
    one without enough points (NaN) gives an infinite size, no fragment boundary.
    """
    n = reference.shape[0]
    rates, sizes = np.full(n, np.nan), np.full(n, np.inf)
    if n == 0:
        return rates, sizes, 0
    floor = RADIUS_FLOOR_SPACINGS * np.asarray(spacing, float)
    pitch = float(np.median(spacing))
    ceiling = max(0.5 * float(np.ptp(reference, axis=0).max()), float(floor.max()))
    levels = _Levels(reference, pitch, ceiling)
    radius = floor.copy()
    for passes in range(1, MAX_PASSES + 1):
        level = levels.level_of(radius)
        for lv in np.unique(level):
            members = np.flatnonzero(level == lv)
            for chunk in np.array_split(members, max(1, members.size // BATCH)):
                rates[chunk] = levels.fit(int(lv), chunk, radius[chunk], velocity)
        stretching = np.isfinite(rates) & (rates > 0.0)
        sizes = np.full(n, np.inf)
        sizes[stretching] = size_of_rate(rates[stretching])
        new_radius = np.clip(0.5 * sizes, floor, ceiling)
        if np.all(np.abs(new_radius - radius) <= RADIUS_TOLERANCE * radius):
            break
        radius = new_radius
    return rates, sizes, passes


class _Levels:
    """The points kept at each level L of a grid of 2^L ``pitch`` cells (one a cell), each with its tree;
    level 0 keeps every point."""

    def __init__(self, reference: np.ndarray, pitch: float, ceiling: float):
        self.reference, self.pitch = reference, pitch
        self.top = max(0, int(np.ceil(np.log2(ceiling / (LEVEL_RADIUS_CELLS * pitch)))))
        self.kept, self.trees = [], []
        for lv in range(self.top + 1):
            if lv == 0:
                kept = np.arange(reference.shape[0])
            else:
                cells = np.floor((reference - reference.min(axis=0)) / (2 ** lv * pitch)).astype(np.int64)
                kept = np.sort(np.unique(cells, axis=0, return_index=True)[1])
            self.kept.append(kept)
            self.trees.append(cKDTree(reference[kept]))

    def level_of(self, radius: np.ndarray) -> np.ndarray:
        """The level whose cells fit a radius: 3.2 · 2^L ≤ r/Δ < 3.2 · 2^(L+1) (0 below, the top above)."""
        ratio = np.maximum(radius / (LEVEL_RADIUS_CELLS * self.pitch), 1.0)
        return np.minimum(np.floor(np.log2(ratio)).astype(np.int64), self.top)

    def fit(self, lv: int, points: np.ndarray, radius: np.ndarray, velocity: np.ndarray) -> np.ndarray:
        """The fitted rates of ``points`` over the level's points within ``radius`` of each."""
        lists = self.trees[lv].query_ball_point(self.reference[points], radius)
        start = np.zeros(points.size + 1, dtype=np.int64)
        start[1:] = np.cumsum([len(near) for near in lists])
        kept = self.kept[lv]
        flat = kept[np.fromiter(chain.from_iterable(lists), dtype=np.int64, count=int(start[-1]))]
        out = np.empty(points.size)
        _fitted_rates(points, self.reference, velocity, start, flat, out)
        return out
