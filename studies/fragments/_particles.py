"""Helpers the SPH diagnostics share: which particles are the projectile's, and clusters of touching particles."""

from __future__ import annotations

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components
from scipy.spatial import cKDTree

from impactdyn.shield import Problem


def projectile_count(problem: Problem) -> int:
    """The number of the projectile's particles, which come first in :func:`impactdyn.shield.sphere_on_plate`'s
    problem and are the only ones moving at t = 0."""
    return int(np.count_nonzero(np.any(problem.particles.velocity != 0.0, axis=1)))


def linked_clusters(points: np.ndarray, distance: float) -> tuple[int, np.ndarray]:
    """Clusters of ``points`` (n, 3) linked by pairs closer than ``distance``: (count, label of each point (n,))."""
    pairs = cKDTree(points).query_pairs(distance, output_type="ndarray")
    n = len(points)
    graph = coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(n, n))
    return connected_components(graph, directed=False)
