"""DC3D debris-cloud propagation (seed 000): grid model, wall grid, particle kernels.

The propagation/deposition driver is not built yet (issue 3).
"""

from impactdyn.debris._grid import HydroGrid
from impactdyn.debris._integrators import INTEGRATORS, Failure, PropagationStats, propagate, register_integrator
from impactdyn.debris._particle import Material, pack_state, state_rates, total_energy, unpack_state
from impactdyn.debris._tets import (
    affine_velocity_fit, cell_nodes, gather_tets, inertia_tensor, initial_state, signed_volume, tet_vertices)
from impactdyn.debris._wall import AL_6061_T6, WallDeposition, WallGrid, WallMaterial

__all__ = [
    "AL_6061_T6", "Failure", "HydroGrid", "INTEGRATORS", "Material", "PropagationStats", "WallDeposition",
    "WallGrid", "WallMaterial", "affine_velocity_fit", "cell_nodes", "gather_tets", "inertia_tensor",
    "initial_state", "pack_state", "propagate", "register_integrator", "signed_volume", "state_rates",
    "tet_vertices", "total_energy", "unpack_state",
]
