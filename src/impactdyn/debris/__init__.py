"""DC3D debris-cloud propagation (Fahrenthold 1994): hand-off grid → particles → wall deposition.

Python API: ``run_debris(grid, wall, material, ...)`` → :class:`DebrisResult`, or from a
case file ``run_case(load_debris_case(path))``; :func:`write_debris_run` writes the
run folder.  File formats live in :mod:`impactdyn.io`.
"""

from impactdyn.debris._analytic import ShellCloud, shell_cloud_grid
from impactdyn.debris._case import (
    ComputeSection, DebrisCase, FilterSection, IntegratorSection, LegacySection, OutputSection, WallSection, build,
    check_bulk_modulus, check_seeding, load_debris_case, remap_grid)
from impactdyn.debris._deposit import (
    CRATERING_MOMENTUM, POINTS_PER_PARTICLE, MomentumTransfer, areal_density, arrival_points, cratering_factor,
    cratering_momentum, deposit, element_impulse, element_records, face_areas, face_element, momentum_enhancement,
    remap_impulse)
from impactdyn.hydrogrid import HydroGrid
from impactdyn.debris._legacy import run_legacy
from impactdyn.debris._integrators import (
    INTEGRATORS, Failure, IntegratorOptions, PropagationStats, propagate, register_integrator)
from impactdyn.debris._particle import (
    ParticleMaterial, check_wave_speed, pack_state, state_rates, total_energy, unpack_state)
from impactdyn.debris._compact import compact_arrival_us, compact_deposition, half_model_share
from impactdyn.debris._landing import compact_records, landing_mask, with_compact_fragments
from impactdyn.debris._debris_h5 import read_arrivals, read_deposition
from impactdyn.debris._decks import DeckOptions, write_decks
from impactdyn.debris._outputs import write_debris_files, write_debris_run
from impactdyn.debris._propagate import (
    ArrivalWindow, ComputeOptions, DebrisResult, DepositionOptions, propagate_chunked, run_debris, seed_and_select)
from impactdyn.debris._seed import ParticleCloud, SeedFilter, SeedOptions, arrival_times, seed_cells, seed_particles
from impactdyn.debris._tets import (
    affine_velocity_fit, cell_nodes, gather_tets, inertia_tensor, initial_state, signed_volume, tet_vertices)
from impactdyn.materials import AL_6061_T6_MAT13, Mat13Card
from impactdyn.wallgrid import WallDeposition, WallGrid


def run_case(case: DebrisCase, progress=None, source: str = "<case>") -> DebrisResult:
    """Run a validated debris case (see :func:`run_debris` for ``progress``)."""
    return run_debris(**build(case, source), progress=progress)


__all__ = [
    "CRATERING_MOMENTUM", "DeckOptions", "MomentumTransfer", "cratering_factor", "cratering_momentum",
    "AL_6061_T6_MAT13", "ArrivalWindow", "ComputeOptions", "ComputeSection", "DebrisCase", "DebrisResult",
    "DepositionOptions", "Failure", "FilterSection", "HydroGrid", "INTEGRATORS", "IntegratorOptions",
    "IntegratorSection", "LegacySection", "OutputSection", "ParticleMaterial", "POINTS_PER_PARTICLE", "ParticleCloud",
    "PropagationStats", "SeedFilter", "SeedOptions", "ShellCloud", "WallDeposition", "WallGrid", "WallSection",
    "Mat13Card", "affine_velocity_fit", "compact_arrival_us", "compact_deposition", "compact_records", "half_model_share", "landing_mask",
    "with_compact_fragments",
    "areal_density", "arrival_points", "arrival_times", "build",
    "cell_nodes", "check_bulk_modulus", "check_seeding", "check_wave_speed", "deposit",
    "element_impulse", "element_records", "face_areas", "face_element", "gather_tets", "inertia_tensor",
    "initial_state", "load_debris_case", "momentum_enhancement", "pack_state", "propagate", "propagate_chunked",
    "register_integrator", "remap_grid", "remap_impulse", "run_case", "run_debris", "run_legacy", "seed_and_select", "seed_cells",
    "seed_particles", "shell_cloud_grid", "signed_volume", "state_rates", "tet_vertices", "total_energy",
    "read_arrivals", "read_deposition", "unpack_state", "write_debris_files", "write_debris_run", "write_decks",
]
