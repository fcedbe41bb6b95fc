"""Momentum deposited on the rear wall (DC3D DYNOUT, DCPOST; docs/theory/debris.md, eq. (5)).

At its arrival time a particle's four vertices and its centroid,

    x_k = c + s F (x_k⁰ − c⁰)   (k = 1…4),     x_5 = c,

each carry p/5 onto the wall face element under them (the x–z grid of the wall's
front face).  s = 1 by default; ``legacy_vertex_scaling`` uses DYNOUT's
s = (ρ/ρ_ref)^{1/3}.  ``legacy_momentum_enhancement`` multiplies p by DYNOUT's
√((m_e + m)/m), m_e = ρ_ref Δx Δy Δz the mass of one wall element computed with the
debris reference density, as the listing does (it then overrides it with 1).
Points off the face grid deposit nothing; the caller counts them.

``momentum_transfer = "cratering"`` multiplies the normal component of a particle's momentum by the
momentum a droplet striking a thick wall gives it, β(V_n) of :data:`CRATERING_MOMENTUM`: the crater's
ejecta fly back toward the bumper and the wall keeps their momentum besides the droplet's.  An upper
bound for a cloud: every droplet is taken to strike a bare wall, where in a dense cloud later droplets
strike the melt and ejecta of earlier ones.

DCPOST: the impulse per face element and its areal density |Σ p| / (Δx Δz)
(g/(cm µs)), and a conservative remap onto another face grid.
"""

from __future__ import annotations

from typing import Literal

import numpy as np

from impactdyn.debris._particle import C_SLICE, F_SLICE, P_SLICE
from impactdyn.units import KM_S_PER_CM_US
from impactdyn.wallgrid import WallDeposition, WallGrid

POINTS_PER_PARTICLE = 5

MomentumTransfer = Literal["arrival", "cratering"]
"""What a particle gives the wall: its own momentum, or its normal component times β(V_n)
(:func:`cratering_momentum`)."""

#: β = p_wall / p_in of an Al 6061-T6 sphere striking a thick Al 6061-T6 plate normally, against the
#: normal speed (km/s): the SPH shield stage's own physics (package defaults), the ejecta's momentum
#: counted when they have left the plate's face, at 40 d/V (at most 12 µs), particle spacing d/6
#: (``verification/momentum_transfer.py``, which prints this table; docs/vv/test-shots.md).  The problem
#: carries no length, so β holds for droplets of any size.  Still rising when read (by 1–5 % over the
#: last 30 % of the run, most at the highest speeds), so a little low for one droplet.  No measured β for
#: aluminium on aluminium was available to check it against; it is a computed value, not a datum.
CRATERING_MOMENTUM = ((2.0, 3.0, 5.0, 7.0, 10.0, 13.0), (1.3791, 1.5684, 1.9587, 2.2385, 2.5436, 2.8171))


def arrival_points(states: np.ndarray, vertices0: np.ndarray, scale=None) -> np.ndarray:
    """The five deposition points ``(N, 5, 3)`` (four vertices, then the centroid).

    states ``(N, 33)`` at arrival; vertices0 ``(N, 4, 3)`` at hand-off;
    scale ``(N,)`` or None: the legacy vertex scaling s.
    """
    F = states[:, F_SLICE].reshape(-1, 3, 3)
    c = states[:, C_SLICE]
    d = vertices0 - vertices0.mean(axis=1, keepdims=True)
    arms = np.einsum("nij,nkj->nki", F, d)
    if scale is not None:
        arms = arms * np.asarray(scale, dtype=float)[:, None, None]
    return np.concatenate([c[:, None, :] + arms, c[:, None, :]], axis=1)


def face_element(wall: WallGrid, points: np.ndarray) -> np.ndarray:
    """Face element ``i + nx k`` under each point ``(..., 3)``, or −1 off the grid; returns ``(...)``."""
    nx, _, nz = wall.shape
    i = np.searchsorted(wall.x, points[..., 0], side="right") - 1
    k = np.searchsorted(wall.z, points[..., 2], side="right") - 1
    # the upper edge belongs to the last element
    i = np.where(points[..., 0] == wall.x[-1], nx - 1, i)
    k = np.where(points[..., 2] == wall.z[-1], nz - 1, k)
    on = (i >= 0) & (i < nx) & (k >= 0) & (k < nz)
    return np.where(on, i + nx * k, -1)


def cratering_factor(normal_speed_km_s: np.ndarray) -> np.ndarray:
    """β(V_n) of :data:`CRATERING_MOMENTUM`, linear between its speeds and held at its ends beyond them;
    1 for a particle not moving toward the wall (V_n ≤ 0)."""
    speeds, betas = CRATERING_MOMENTUM
    v = np.asarray(normal_speed_km_s, dtype=float)
    return np.where(v > 0.0, np.interp(v, speeds, betas), 1.0)


def cratering_momentum(momentum: np.ndarray, mass: np.ndarray) -> np.ndarray:
    """``(N, 3)`` momenta with the normal component (along +y, toward the wall) times β(V_n)."""
    out = np.array(momentum, dtype=float)
    out[:, 1] *= cratering_factor(KM_S_PER_CM_US * out[:, 1] / mass)
    return out


def momentum_enhancement(wall: WallGrid, mass: np.ndarray, rho_ref: float) -> np.ndarray:
    """DYNOUT's legacy factor √((m_e + m)/m), ``(N,)``; m_e from the first wall element's size."""
    m_e = rho_ref * np.diff(wall.x)[0] * np.diff(wall.y)[0] * np.diff(wall.z)[0]
    return np.sqrt((m_e + mass) / mass)


def deposit(points: np.ndarray, momentum: np.ndarray, time: np.ndarray, wall: WallGrid):
    """Deposition records of particles arriving at ``time``.

    points ``(N, 5, 3)`` from :func:`arrival_points`; momentum ``(N, 3)`` g cm/µs
    (each point carries a fifth); time ``(N,)`` µs.  Returns
    (:class:`WallDeposition` with one record per point on the grid, in particle
    then point order; on-grid mask ``(N, 5)``).
    """
    element = face_element(wall, points)
    on = element >= 0
    share = np.repeat(momentum[:, None, :] / POINTS_PER_PARTICLE, POINTS_PER_PARTICLE, axis=1)
    times = np.repeat(time[:, None], POINTS_PER_PARTICLE, axis=1)
    return WallDeposition(element=element[on], time=times[on], impulse=share[on]), on


def element_impulse(deposition: WallDeposition, wall: WallGrid) -> np.ndarray:
    """Σ impulse per face element, ``(nx, nz, 3)`` g cm/µs (DCPOST)."""
    nx, _, nz = wall.shape
    deposition.check_fits(wall)
    total = np.zeros((nx * nz, 3))
    np.add.at(total, deposition.element, deposition.impulse)
    return total.reshape(nz, nx, 3).transpose(1, 0, 2)


def face_areas(wall: WallGrid) -> np.ndarray:
    """Δx_i Δz_k of the face elements, ``(nx, nz)`` cm²."""
    return np.diff(wall.x)[:, None] * np.diff(wall.z)[None, :]


def areal_density(impulse: np.ndarray, wall: WallGrid) -> np.ndarray:
    """DCPOST's areal momentum density |Σ p| / (Δx Δz), ``(nx, nz)`` g/(cm µs), from ``(nx, nz, 3)`` impulses."""
    return np.linalg.norm(impulse, axis=-1) / face_areas(wall)


def remap_impulse(impulse: np.ndarray, source: WallGrid, target: WallGrid) -> np.ndarray:
    """Impulse per element ``(nx, nz, 3)`` of ``source``'s face grid moved onto ``target``'s.

    Conservative: each source element's impulse is spread uniformly over its
    area and shared by area overlap, so the target receives exactly the impulse
    of the overlapping area (all of it when ``target`` covers ``source``).
    DCPOST's remap (jtype 3) serves the same purpose.
    """
    wx = _overlap_fractions(source.x, target.x)
    wz = _overlap_fractions(source.z, target.z)
    return np.einsum("ia,kb,ikd->abd", wx, wz, impulse)


def _overlap_fractions(src: np.ndarray, dst: np.ndarray) -> np.ndarray:
    """Fraction of each source interval inside each target interval, ``(len(src)−1, len(dst)−1)``."""
    lo = np.maximum(src[:-1, None], dst[None, :-1])
    hi = np.minimum(src[1:, None], dst[None, 1:])
    return np.clip(hi - lo, 0.0, None) / np.diff(src)[:, None]


def element_records(impulse: np.ndarray, factor: float = 1.0, time: float = 0.0) -> WallDeposition:
    """DCPOST's deposition cards: one record per loaded face element, Σ p × ``factor`` at ``time``.

    impulse ``(nx, nz, 3)`` from :func:`element_impulse`.  DCPOST writes time 0
    (the wall problem starts with the whole impulse applied).
    """
    flat = impulse.transpose(1, 0, 2).reshape(-1, 3)  # element i + nx k
    loaded = np.nonzero(np.any(flat != 0.0, axis=1))[0]
    return WallDeposition(element=loaded, time=np.full(loaded.size, float(time)), impulse=flat[loaded] * factor)
