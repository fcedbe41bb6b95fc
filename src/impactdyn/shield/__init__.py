"""Built-in shield-impact stage: 3-D SPH for a sphere striking a plate (docs/theory/shield.md).

Updated-Lagrangian SPH with a Mie–Grüneisen EOS, elastic–plastic deviatoric
stress (Jaumann rate, von Mises radial return, Johnson–Cook optional), Monaghan
artificial viscosity and artificial stress, failure (a spall / plastic-strain threshold, or damage
that leaves fragments: :mod:`._damage`, found by :func:`fragments_of`; the fragments of failed
material sized by Grady's energy balance at the rate read across their own size, :func:`grady_fragments`),
variable smoothing length and a cell-list neighbour search in compiled parallel
kernels (:mod:`._equations` states the equations). Units cm, g, µs, Mbar.

Typical use::

    from impactdyn import shield
    problem = shield.sphere_on_plate("al6061-t6", "al6061-t6", diameter_cm=0.575, velocity_km_s=7.0,
                                     obliquity_deg=25.0, plate_thickness_cm=0.127, spacing_cm=0.025)
    result = shield.run(problem, t_end_us=4.0)
    grid = shield.bin_to_hydrogrid(result.state, cell_size_cm=0.03175)
"""

from impactdyn.shield._binning import BinningMethod, bin_to_hydrogrid
from impactdyn.shield._debris_fragments import (COMPACT_MIN_PARTICLES, DEBRIS_FRAGMENT_SPEED_FRACTION, FRAGMENT_KEYS,
                                                MAX_FRAGMENT_DRAWS, FragmentOptions, compact_fragments, compact_particles,
                                                debris_fragments)
from impactdyn.shield._fragment_rate import own_size_strain_rates
from impactdyn.shield._fragments import (Fragments, cumulative_mass, cumulative_number, find_fragments, fragment_rows,
                                         fragment_mass_figure, fragments_of, join_fragments, origin_masses,
                                         plot_fragment_masses)
from impactdyn.shield._grady import SPRAY_SIZE_CM, grady_fragment_size, grady_fragments, grady_sizes
from impactdyn.shield._integrate import SPHError, run
from impactdyn.shield._io import read_fragments, read_particles, write_fragments, write_particles
from impactdyn.shield._melt import MELTED_SHARE, ReleasedPhase, released_phase, solid_particles
from impactdyn.shield._neighbours import Domain, neighbour_pairs
from impactdyn.shield._options import FAILURE_MODELS, FLOW_STRESS_MODELS, FailureModel, FlowStress, SPHOptions
from impactdyn.shield._problems import (DEFAULT_PLATE_RADIUS_D, Problem, planar_impact, spacing_too_coarse,
                                        sphere_on_plate)
from impactdyn.shield._state import TENSOR_COMPONENTS, History, Particles, RunResult

__all__ = [
    "BinningMethod", "COMPACT_MIN_PARTICLES", "DEBRIS_FRAGMENT_SPEED_FRACTION", "DEFAULT_PLATE_RADIUS_D",
    "FRAGMENT_KEYS", "FragmentOptions", "MAX_FRAGMENT_DRAWS", "compact_fragments", "compact_particles", "debris_fragments", "Domain", "FAILURE_MODELS", "FLOW_STRESS_MODELS", "FailureModel", "FlowStress", "Fragments",
    "History", "MELTED_SHARE", "Particles", "ReleasedPhase", "Problem", "RunResult", "SPHError", "SPHOptions", "TENSOR_COMPONENTS", "bin_to_hydrogrid",
    "cumulative_mass", "cumulative_number", "find_fragments", "fragment_rows", "fragments_of", "grady_fragment_size", "grady_fragments", "grady_sizes",
    "join_fragments", "neighbour_pairs", "origin_masses", "own_size_strain_rates", "planar_impact",
    "SPRAY_SIZE_CM", "fragment_mass_figure", "plot_fragment_masses", "read_fragments", "read_particles", "released_phase", "run", "solid_particles", "spacing_too_coarse", "sphere_on_plate", "write_fragments", "write_particles",
]
