"""The DC3D debris stage: seed particles, carry them to the wall, deposit their momentum.

Particles are independent, so the propagation runs in chunks of
``ComputeOptions.chunk_size`` particles: in this process (the numba kernels are
already parallel over particles) or on Dask.  Every particle's integration
depends on its own data only, so the result does not depend on the chunking or
on where a chunk runs: the Dask path returns bit-identical states.

Time origin: the HydroGrid's hand-off time.  Arrival times, deposition records
and the wall loads are measured from it (``DebrisResult.t_handoff`` gives the
absolute time).
"""

from __future__ import annotations

import time as _time
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Annotated, Literal

import numpy as np
from pydantic import Field

from impactdyn._config import NonNegative, Positive, Section, field_of, rule
from impactdyn._errors import InputError
from impactdyn._parallel import run_tasks
from impactdyn.debris._deposit import (POINTS_PER_PARTICLE, MomentumTransfer, areal_density, arrival_points,
                                       cratering_momentum, deposit, element_impulse, momentum_enhancement)
from impactdyn.hydrogrid import HydroGrid
from impactdyn.debris._integrators import IntegratorOptions, PropagationStats, propagate
from impactdyn.debris._particle import STATE_SIZE, ParticleMaterial
from impactdyn.debris._seed import ParticleCloud, SeedFilter, SeedOptions, arrival_times, seed_particles
from impactdyn.wallgrid import WallDeposition, WallGrid


def check_window(t_min: float, t_cut: float, names: tuple[str, str] = ("t_min", "t_cut")) -> None:
    """The arrival window is not empty: t_cut > t_min (a validator's ValueError naming ``names`` otherwise)."""
    if t_cut <= t_min:
        raise ValueError(f"{names[1]} = {t_cut} must exceed {names[0]} = {t_min}")


class ArrivalWindow(Section):
    """Keep particles arriving at the wall plane in [t_min, t_cut] µs after hand-off (dc3din record 8)."""

    t_min: NonNegative = 0.0
    t_cut: Positive = 25.0
    legacy_abs_arrival: bool = field_of(arrival_times, "legacy_abs_arrival")

    _window = rule(check_window, "t_min", "t_cut")


class ComputeOptions(Section):
    """Where the particle chunks run: ``local`` (this process) or ``dask`` (``address``; None starts a
    LocalCluster); a case's ``[compute]`` table.  The results do not depend on it (module docstring).

    scheduler : "local" (default): the chunks one after another in this process, whose compiled
        kernels already use every core; "dask": the chunks as tasks of a Dask cluster.
    address : the address of a running Dask scheduler (e.g. "tcp://host:8786"); none or "local": a
        LocalCluster started on this machine for the run.  Used with ``scheduler = "dask"`` only.
    chunk_size : particles per chunk (one task).
    workers : processes of the LocalCluster (none: one per CPU core); used only when the run
        starts that cluster.
    """

    scheduler: Literal["local", "dask"] = "local"
    address: str | None = None
    chunk_size: Annotated[int, Field(ge=1)] = 65536
    workers: Annotated[int, Field(ge=1)] | None = None


class DepositionOptions(Section):
    """What a particle deposits (:mod:`._deposit`).

    momentum_transfer : "arrival" (default): its own momentum; "cratering": its normal component times
        the β(V_n) of a droplet cratering a thick wall (:func:`cratering_momentum`, an upper bound).
    legacy_vertex_scaling : DYNOUT places a particle's deposition points at its vertices scaled by
        (ρ/ρ_ref)^⅓ about the centre; off: the deformed vertices c + F(x⁰ − c⁰).
    legacy_momentum_enhancement : DYNOUT's factor √((m_e + m)/m) on a particle's deposited momentum,
        m_e the mass of one wall element at the debris' reference density (the listing computes it,
        then sets it to 1); on, the deposited momentum exceeds the debris'.
    """

    momentum_transfer: MomentumTransfer = "arrival"
    legacy_vertex_scaling: bool = False
    legacy_momentum_enhancement: bool = False


@dataclass(frozen=True, eq=False)
class DebrisResult:
    """Everything the debris stage produced; N seeded particles, A = the propagated ones.

    cloud: the N seeded particles (:class:`ParticleCloud`).
    t_arrival ``(N,)`` µs after hand-off (inf: never reaches the wall plane).
    propagated ``(A,)`` int: indices into ``cloud`` of the particles in the arrival window.
    states ``(A, 33)``: their states at ``stats.t_reached``.
    stats: :class:`PropagationStats` of the propagated particles.
    points ``(A, 5, 3)``: deposition points at arrival (:func:`arrival_points`).
    on_wall ``(A, 5)`` bool: point lies on the wall's face grid (and the particle did not fail).
    point_momentum ``(A, 3)``: the momentum each propagated particle's points share (its own, times
    DYNOUT's legacy enhancement where that option is on).
    deposition: the time-resolved records; impulse ``(nx, nz, 3)`` per face element;
    areal ``(nx, nz)`` DCPOST's |Σ p|/(Δx Δz).
    """

    grid: HydroGrid
    wall: WallGrid
    cloud: ParticleCloud
    t_arrival: np.ndarray
    propagated: np.ndarray
    states: np.ndarray
    stats: PropagationStats
    points: np.ndarray
    on_wall: np.ndarray
    point_momentum: np.ndarray
    deposition: WallDeposition
    impulse: np.ndarray
    areal: np.ndarray
    integrator: IntegratorOptions
    timings: dict = field(default_factory=dict)

    @property
    def t_handoff(self) -> float:
        return self.grid.time

    @property
    def arrived(self) -> np.ndarray:
        """``(A,)`` bool: the propagated particle reached its arrival time (no integration failure)."""
        return self.stats.code == 0

    def deposition_on(self, face: WallGrid) -> WallDeposition:
        """The arrived particles' points deposited on another face grid ``face`` (e.g. the wall mesh's own
        face cells, where the case's grid would smooth the load), as on the case's grid."""
        ok = self.arrived
        return deposit(self.points[ok], self.point_momentum[ok], self.t_arrival[self.propagated][ok], face)[0]

    def summary(self) -> dict:
        """Headline numbers (``summary.json``); momenta in g cm/µs, times in µs.

        The cloud's momentum at hand-off is accounted for in full: ``momentum_in`` =
        ``momentum_arrived`` + ``momentum_failed`` (propagated, integration failed) +
        ``momentum_outside_window`` (reaches the wall plane before ``t_min`` or after ``t_cut``) +
        ``momentum_not_reaching`` (never reaches it), and ``momentum_arrived`` +
        ``momentum_added_at_wall`` = ``momentum_deposited`` + ``momentum_off_wall`` (its points off the
        face grid), to round-off.  ``momentum_added_at_wall`` is what the deposition gives the wall
        beyond the arriving momentum on the face grid: the crater ejecta's of ``momentum_transfer =
        "cratering"``, and DYNOUT's legacy enhancement where it is on; zero otherwise.
        """
        cloud, arrived = self.cloud, self.arrived
        p_prop = cloud.momentum[self.propagated]
        in_window = np.zeros(len(cloud), dtype=bool)
        in_window[self.propagated] = True
        reaches = np.isfinite(self.t_arrival)
        late = reaches & ~in_window
        share = p_prop[:, None, :] / POINTS_PER_PARTICLE
        off_wall = (share * (~self.on_wall & arrived[:, None])[..., None]).sum(axis=(0, 1))
        added = (self.point_momentum - p_prop)[:, None, :] / POINTS_PER_PARTICLE
        added_at_wall = (added * (self.on_wall & arrived[:, None])[..., None]).sum(axis=(0, 1))
        t_arr = self.t_arrival[self.propagated][arrived]
        return {
            "t_handoff_us": self.t_handoff,
            "n_cells": int(np.prod(self.grid.shape)),
            "n_cells_seeded": int(len(cloud) // 5),
            "n_particles": len(cloud),
            "n_propagated": int(len(self.propagated)),
            "n_arrived": int(arrived.sum()),
            "n_not_reaching_wall": int((~reaches).sum()),
            "n_outside_window": int(late.sum()),
            "n_points_off_wall": int((~self.on_wall & arrived[:, None]).sum()),
            "mass_seeded_g": float(cloud.mass.sum()),
            "mass_arrived_g": float(cloud.mass[self.propagated][arrived].sum()),
            "momentum_grid": self.grid.total_momentum().tolist(),
            "momentum_in": cloud.momentum.sum(axis=0).tolist(),
            "momentum_arrived": p_prop[arrived].sum(axis=0).tolist(),
            "momentum_deposited": self.deposition.impulse.sum(axis=0).tolist(),
            "momentum_off_wall": off_wall.tolist(),
            "momentum_added_at_wall": added_at_wall.tolist(),
            "momentum_failed": p_prop[~arrived].sum(axis=0).tolist(),
            "momentum_outside_window": cloud.momentum[late].sum(axis=0).tolist(),
            "momentum_not_reaching": cloud.momentum[~reaches].sum(axis=0).tolist(),
            "mass_outside_window_g": float(cloud.mass[late].sum()),
            "mass_not_reaching_g": float(cloud.mass[~reaches].sum()),
            "arrival_time_us": ({"first": float(t_arr.min()), "median": float(np.median(t_arr)),
                                 "last": float(t_arr.max())} if t_arr.size else None),
            "peak_areal_density_g_cm_us": float(self.areal.max()) if self.areal.size else 0.0,
            "integrator": {
                "method": self.integrator.method,
                "steps_total": int(self.stats.steps.sum()),
                "steps_per_particle_median": float(np.median(self.stats.steps)) if len(self.stats.steps) else 0.0,
                "rejected_total": int(self.stats.rejected.sum()),
                "n_failed": self.stats.n_failed,
                "failures": self.stats.failure_counts(),
            },
            "timings_s": dict(self.timings),
        }


def propagate_chunked(cloud: ParticleCloud, t_end: np.ndarray, material: ParticleMaterial,
                      integrator: IntegratorOptions = IntegratorOptions(),
                      compute: ComputeOptions = ComputeOptions(),
                      progress: Callable[[int], None] | None = None):
    """Integrate every particle of ``cloud`` to its ``t_end (N,)`` in chunks; (states ``(N, 33)``, stats).

    ``progress(n)`` is called with the number of particles of each finished chunk.
    """
    n = len(cloud)
    size = compute.chunk_size
    bounds = [(a, min(a + size, n)) for a in range(0, n, size)]
    tasks = [_Chunk(cloud.states[a:b], cloud.J[a:b], cloud.mass[a:b], cloud.void_fraction[a:b], t_end[a:b],
                    material, integrator) for a, b in bounds]
    states = np.empty((n, STATE_SIZE))
    counts = np.empty((n, 3), dtype=np.int64)
    t_reached = np.empty(n)
    scheduler = "dask" if compute.scheduler == "dask" else "serial"
    for i, (y, stats) in run_tasks(_run_chunk, tasks, scheduler=scheduler, workers=compute.workers,
                                   address=compute.address):
        a, b = bounds[i]
        states[a:b] = y
        counts[a:b] = np.stack([stats.steps, stats.rejected, stats.code], axis=-1)
        t_reached[a:b] = stats.t_reached
        if progress:
            progress(b - a)
    return states, PropagationStats(steps=counts[:, 0], rejected=counts[:, 1], code=counts[:, 2],
                                    t_reached=t_reached)


@dataclass(frozen=True, eq=False)
class _Chunk:
    states: np.ndarray
    J: np.ndarray
    mass: np.ndarray
    phi: np.ndarray
    t_end: np.ndarray
    material: ParticleMaterial
    integrator: IntegratorOptions


def _run_chunk(chunk: _Chunk):
    return propagate(chunk.states, chunk.J, chunk.mass, chunk.t_end, chunk.material, phi=chunk.phi,
                     **chunk.integrator.model_dump())


def seed_and_select(grid: HydroGrid, wall: WallGrid, material: ParticleMaterial, seed_filter: SeedFilter,
                    seed_options: SeedOptions, window: ArrivalWindow):
    """Particles of ``grid``, their arrival times at the wall plane and the indices in the window.

    Returns (cloud, t_arrival ``(N,)``, selected ``(A,)``).  A wall whose front face
    does not lie beyond the whole cloud in +y is an :class:`InputError`.
    """
    cloud = seed_particles(grid, material, seed_filter, seed_options)
    if len(cloud) and cloud.vertices[..., 1].max() > wall.y[0]:
        raise InputError(f"wall: the front face y = {wall.y[0]:g} cm lies behind or inside the debris, which "
                         f"reaches y = {cloud.vertices[..., 1].max():g} cm; the wall must lie beyond the cloud "
                         "in +y")
    t_arr = arrival_times(cloud, wall.y[0], legacy_abs_arrival=window.legacy_abs_arrival)
    return cloud, t_arr, np.nonzero((t_arr >= window.t_min) & (t_arr <= window.t_cut))[0]


def run_debris(grid: HydroGrid, wall: WallGrid, material: ParticleMaterial, *,
               seed_filter: SeedFilter = SeedFilter(), seed_options: SeedOptions = SeedOptions(),
               window: ArrivalWindow = ArrivalWindow(), integrator: IntegratorOptions = IntegratorOptions(),
               compute: ComputeOptions = ComputeOptions(), deposition: DepositionOptions = DepositionOptions(),
               progress: Callable[[str, int, int], None] | None = None) -> DebrisResult:
    """Seed, propagate to the wall plane y = wall.y[0], deposit (DC3D's main loop, docs/theory/debris.md).

    ``progress(stage, done, total)`` is called as work advances (stages
    ``seed``, ``propagate``, ``deposit``).
    """
    timings = {}
    tick = _time.perf_counter()
    cloud, t_arr, selected = seed_and_select(grid, wall, material, seed_filter, seed_options, window)
    timings["seed"] = _time.perf_counter() - tick
    if progress:
        progress("seed", len(cloud), len(cloud))

    tick = _time.perf_counter()
    moving = cloud.subset(selected)
    done = 0

    def advance(n: int) -> None:
        nonlocal done
        done += n
        if progress:
            progress("propagate", done, len(selected))

    t_moving = t_arr[selected]
    states, stats = propagate_chunked(moving, t_moving, material, integrator, compute, advance)
    timings["propagate"] = _time.perf_counter() - tick

    tick = _time.perf_counter()
    scale = np.cbrt(moving.density_ratio) if deposition.legacy_vertex_scaling else None
    points = arrival_points(states, moving.vertices, scale)
    p = moving.momentum
    if deposition.momentum_transfer == "cratering":
        p = cratering_momentum(p, moving.mass)
    if deposition.legacy_momentum_enhancement:
        p = p * momentum_enhancement(wall, moving.mass, material.rho_ref)[:, None]
    ok = stats.code == 0
    dep, on = deposit(points[ok], p[ok], t_moving[ok], wall)
    on_wall = np.zeros((len(selected), POINTS_PER_PARTICLE), dtype=bool)
    on_wall[ok] = on
    impulse = element_impulse(dep, wall)
    timings["deposit"] = _time.perf_counter() - tick
    if progress:
        progress("deposit", 1, 1)
    return DebrisResult(grid=grid, wall=wall, cloud=cloud, t_arrival=t_arr, propagated=selected, states=states,
                        stats=stats, points=points, on_wall=on_wall, point_momentum=p, deposition=dep,
                        impulse=impulse,
                        areal=areal_density(impulse, wall), integrator=integrator, timings=timings)
