"""HydroGrid cells → deformable tetrahedral particles (DC3D DCELEM, ELDATA, NDDATA; docs/theory/debris.md, seeding).

Every cell that passes the material filters becomes five tetrahedra
(:mod:`._tets`). A tetrahedron's vertices carry the grid's nodal velocities
(:meth:`HydroGrid.nodal_velocities`), its mass is the material in it,

    m = (1 − φ) ρ V_tet,

and its initial state follows from the affine velocity fit
(:func:`._tets.initial_state`).

Cell filters (DCELEM), each a :class:`SeedFilter` field:

* ``min_density_ratio ≤ ρ/ρ_ref ≤ max_density_ratio`` (listing: 0.01, 1000);
* ``φ ≤ max_void_fraction`` (listing: 0.999);
* bulk density ratio ``(1 − φ) ρ/ρ_ref ≥ dencut`` (dc3din record 8);
* m > 0.

Which cells may become particles: all of a cell-centred grid; of a staggered
(legacy CTH) grid, the listing's range 2 … n−1 (1-based, per axis), because the
nodes on the grid's upper planes have no velocity component normal to them
(see :meth:`HydroGrid.nodal_velocities`) and the lower planes' nodes see half
stencils.

Legacy option ``legacy_nddata_swap``: NDDATA gives vertices n7 and n8 each
other's velocity (docs/theory/debris.md, the listing's errata).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Annotated

import numpy as np
from pydantic import Field

from impactdyn._config import NonNegative, Positive, Section, field_of
from impactdyn._limits import check_fits
from impactdyn.hydrogrid import HydroGrid
from impactdyn.debris._particle import P_SLICE, STATE_SIZE, ParticleMaterial
from impactdyn.debris._tets import NODE_OFFSETS, TET_NODES, initial_state

TETS_PER_CELL = len(TET_NODES)
"""Particles seeded per selected cell (the five tetrahedra of :data:`._tets.TET_NODES`)."""

PARTICLE_BYTES = 8 * (2 * 4 * 3 + STATE_SIZE + 9 + 3 + 3 + 1)
"""Bytes one seeded particle costs at least (:func:`seed_particles`, checked before any is
allocated): its vertices and their velocities (4 × 3 each), state (33), inertia tensor (9),
mass, void fraction and density ratio, source cell (3) and tetrahedron index, 8 bytes each."""


class SeedFilter(Section):
    """Which cells become particles (module docstring); dimensionless ratios."""

    dencut: NonNegative = 0.01
    min_density_ratio: NonNegative = 0.01
    max_density_ratio: Positive = 1000.0
    max_void_fraction: Annotated[float, Field(ge=0, le=1)] = 0.999


class SeedOptions(Section):
    """Listing deviations used while seeding (see :mod:`._tets` and the module docstring); the
    defaults of :func:`._tets.initial_state`'s keywords."""

    legacy_nddata_swap: bool = False
    legacy_fdot_scaling: bool = field_of(initial_state, "legacy_fdot_scaling")
    legacy_inertia_transform: bool = field_of(initial_state, "legacy_inertia_transform")


@dataclass(frozen=True, eq=False)
class ParticleCloud:
    """N particles seeded from a HydroGrid, in cell order (k slowest … i fastest, then tetrahedron).

    vertices ``(N, 4, 3)``: vertex positions at hand-off, cm.
    states ``(N, 33)``: initial packed states (:mod:`._particle`).
    J ``(N, 3, 3)``: inertia tensors, g cm².
    mass ``(N,)`` g; void_fraction ``(N,)``; density_ratio ``(N,)`` ρ/ρ_ref of the cell.
    cell ``(N, 3)`` int: (i, j, k) of the source cell; tet ``(N,)`` int: 0…4.
    """

    vertices: np.ndarray
    states: np.ndarray
    J: np.ndarray
    mass: np.ndarray
    void_fraction: np.ndarray
    density_ratio: np.ndarray
    cell: np.ndarray
    tet: np.ndarray

    def __len__(self) -> int:
        return len(self.mass)

    @property
    def momentum(self) -> np.ndarray:
        """p = m v_c of each particle, ``(N, 3)``, g cm/µs."""
        return self.states[:, P_SLICE]

    @property
    def centroid(self) -> np.ndarray:
        """Centroid c at hand-off, ``(N, 3)``, cm."""
        return self.vertices.mean(axis=1)

    def subset(self, index) -> "ParticleCloud":
        """The particles selected by a boolean mask or index array."""
        return ParticleCloud(**{name: getattr(self, name)[index] for name in self.__dataclass_fields__})


def seed_cells(grid: HydroGrid, rho_ref: float, filt: SeedFilter = SeedFilter()) -> np.ndarray:
    """Boolean mask ``(nx, ny, nz)`` of the cells that become particles (module docstring)."""
    ratio = grid.density / rho_ref
    keep = ((ratio >= filt.min_density_ratio) & (ratio <= filt.max_density_ratio)
            & (grid.void_fraction <= filt.max_void_fraction)
            & ((1.0 - grid.void_fraction) * ratio >= filt.dencut) & (grid.mass > 0.0))
    if grid.staggered:
        interior = np.zeros_like(keep)
        interior[1:-1, 1:-1, 1:-1] = True
        keep &= interior
    return keep


def check_particle_count(what: str, keep: np.ndarray) -> int:
    """The number of particles the selected cells ``keep`` (:func:`seed_cells`) make, if this machine's
    memory holds them; otherwise an :class:`InputError` that begins with ``what`` (the grid's name)."""
    cells = int(np.count_nonzero(keep))
    return check_fits(f"{what}: {cells} of its {'x'.join(map(str, keep.shape))} cells pass the seed filters, "
                      f"{TETS_PER_CELL} particles each", TETS_PER_CELL * cells, PARTICLE_BYTES, "debris particles")


def seed_particles(grid: HydroGrid, material: ParticleMaterial, filt: SeedFilter = SeedFilter(),
                   options: SeedOptions = SeedOptions()) -> ParticleCloud:
    """Five tetrahedral particles per selected cell of ``grid`` (DCELEM → NDDATA → JCALC → IVCALC)."""
    keep = seed_cells(grid, material.rho_ref, filt)
    check_particle_count("hand-off grid", keep)
    # cell order of the listing's loops: k slowest, then j, then i
    k, j, i = np.nonzero(keep.transpose(2, 1, 0))
    cells = np.stack([i, j, k], axis=-1)
    node_index = cells[:, None, :] + NODE_OFFSETS  # (ncell, 8, 3)
    nodes = np.stack([grid.x[node_index[..., 0]], grid.y[node_index[..., 1]], grid.z[node_index[..., 2]]], axis=-1)
    v_nodes = grid.nodal_velocities()[node_index[..., 0], node_index[..., 1], node_index[..., 2]]
    if options.legacy_nddata_swap:
        v_nodes = v_nodes[:, [0, 1, 2, 3, 4, 5, 7, 6]]
    x = nodes[:, TET_NODES].reshape(-1, 4, 3)
    v = v_nodes[:, TET_NODES].reshape(-1, 4, 3)
    cell_volume = grid.cell_volumes()[i, j, k]
    tet_fraction = np.full(5, 1.0 / 6.0)
    tet_fraction[2] = 1.0 / 3.0
    phi = np.repeat(grid.void_fraction[i, j, k], 5)
    rho = np.repeat(grid.density[i, j, k], 5)
    mass = (1.0 - phi) * rho * (cell_volume[:, None] * tet_fraction).ravel()
    states, J = initial_state(x, v, mass, legacy_fdot_scaling=options.legacy_fdot_scaling,
                              density_ratio=rho / material.rho_ref,
                              legacy_inertia_transform=options.legacy_inertia_transform)
    return ParticleCloud(vertices=x, states=states, J=J, mass=mass, void_fraction=phi,
                         density_ratio=rho / material.rho_ref, cell=np.repeat(cells, 5, axis=0),
                         tet=np.tile(np.arange(5), len(cells)))


def arrival_times(cloud: ParticleCloud, wall_y: float, *, legacy_abs_arrival: bool = False) -> np.ndarray:
    """Time for each centroid to reach the wall plane y = wall_y, ``(N,)`` µs (DCELEM's tarr).

    The centroid flies ballistically (ṗ = 0), so t = (y_wall − c_y)/v_y with
    v_y = p_y/m; particles that do not approach the plane (v_y ≤ 0 or already
    past it) get +inf.  ``legacy_abs_arrival``: the listing's |(y_wall − c_y)/v_y|,
    which also counts particles flying away from the wall (an erratum).
    """
    vy = cloud.momentum[:, 1] / cloud.mass
    gap = wall_y - cloud.centroid[:, 1]
    with np.errstate(divide="ignore", invalid="ignore"):
        t = gap / vy
    if legacy_abs_arrival:
        t = np.abs(t)
        return np.where(vy != 0.0, t, np.inf)
    return np.where((vy > 0.0) & (gap >= 0.0), t, np.inf)
