"""Rear-wall impact stage: explicit Lagrangian FE of the wall under the deposited momentum (docs/theory/wall-solver.md).

The modern counterpart of the report's DYNA3D analysis: 8-node hexahedra with one-point
integration and hourglass control (Belytschko–Bindeman assumed strain by default, or the
Flanagan–Belytschko stiffness and viscous forms), lumped mass, central differences with
the element Courant step, bulk viscosity, Jaumann stress rate with radial return, in compiled
parallel kernels (:mod:`._step`: the step; :mod:`._hex`, :mod:`._kinematics`, :mod:`._hourglass`: the
element; :mod:`._settle`: bringing the wall to rest); material models in one registry
(:data:`MODELS`: the report's type-13 card ``"mat13"``, and ``"johnson_cook"`` with the
Mie–Grüneisen EOS, JC damage, spall and erosion), its failure laws in another (:data:`FAILURE_LAWS`, one
module each in :mod:`impactdyn.wall.failure_laws`); the solver mesh, the report's refined grid or one graded
to resolve the debris load (:mod:`._mesh`, :mod:`._grading`); the deposition records as nodal velocity
jumps (:mod:`._load`); a verdict and measures (:mod:`._verdict`); ParaView and PNG writers
(:mod:`._output`).  Units cm, g, µs, Mbar.

Typical use::

    from impactdyn import wall
    result = wall.run_wall(wall_grid, deposition, "al6061-t6", wall.WallOptions(material_model="mat13"))
    result.verdict, result.measures["crater_depth_ratio"]
    wall.write_wall_outputs(result, "runs/x/wall", plots="runs/x/plots")
"""

from impactdyn.wall._options import HOURGLASS_FORMS, LSDYNA_HOURGLASS_TYPE, WallOptions, WallSolverError
from impactdyn.wall._models import MODELS, WallModel, register_model, wall_model
from impactdyn.wall._failure_law import FAILURE_LAWS, J_LAW, FailureLaw
from impactdyn.wall._mat13 import Mat13Model
from impactdyn.wall._johnson_cook import JohnsonCookModel
from impactdyn.wall._mesh import MESH_KINDS, SUPPORTS, WallMesh, build_mesh
from impactdyn.wall._grading import FRAGMENT_DIAMETER_CM, check_mesh_sizes, core_element_size, graded_nodes, rebin_deposition, resolving_region, solver_grid, solver_mesh
from impactdyn.wall._load import SPREADS, NodalLoad, check_deposition_depth, default_depth, depth_weights, nodal_load
from impactdyn.wall._result import ENDINGS, HISTORY_KEYS, WallFrame, WallResult
from impactdyn.wall._state import FAILURE_CAUSES
from impactdyn.wall._solver import WallSolver, check_end_times, resolve_model, run_wall, wall_solver
from impactdyn.wall._verdict import (
    DETACHED_SPALL, NO_PERFORATION, PERFORATION, VERDICTS, classify, failed_mass_by_cause, measures)
from impactdyn.wall._output import write_wall_outputs

__all__ = [
    "DETACHED_SPALL", "ENDINGS", "FAILURE_CAUSES", "FAILURE_LAWS", "FailureLaw", "J_LAW", "HISTORY_KEYS", "HOURGLASS_FORMS", "JohnsonCookModel", "LSDYNA_HOURGLASS_TYPE", "MESH_KINDS", "MODELS", "Mat13Model",
    "NO_PERFORATION", "NodalLoad", "PERFORATION", "SPREADS", "SUPPORTS", "VERDICTS", "WallFrame", "WallMesh",
    "FRAGMENT_DIAMETER_CM", "WallModel", "WallOptions", "WallResult", "WallSolver", "WallSolverError", "build_mesh", "check_deposition_depth", "check_end_times", "check_mesh_sizes", "classify", "core_element_size",
    "default_depth", "depth_weights", "failed_mass_by_cause", "graded_nodes", "measures", "nodal_load",
    "rebin_deposition", "register_model", "resolve_model", "resolving_region", "run_wall", "solver_grid", "solver_mesh", "wall_solver",
    "wall_model", "write_wall_outputs",
]
