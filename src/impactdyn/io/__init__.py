"""File formats of the debris-cloud pipeline (one registry of grid formats).

Grid formats register themselves at the bottom of their modules; ``read_grid`` and
``write_grid`` pick one by extension or name. Heavy dependencies (h5py) are imported
by the format modules only.
"""

from impactdyn.io._registry import (
    atomic_output, formats, load_builtin_formats, open_hdf5, read_grid, register_format, write_grid)
from impactdyn.io._legacy_avs import AvsLayout, read_avsout, write_avsout
from impactdyn.io._legacy_dc3din import Dc3dInput, RunType, read_dc3din
from impactdyn.io._dyna3d import write_dyna3d_deck
from impactdyn.io._lsdyna import read_lsdyna_deck, write_lsdyna_deck
from impactdyn.io._cth import read_cth_packages, write_cth_packages

__all__ = [
    "AvsLayout", "Dc3dInput", "RunType", "atomic_output", "formats", "load_builtin_formats", "open_hdf5",
    "read_avsout",
    "read_cth_packages", "read_dc3din", "read_grid", "read_lsdyna_deck", "register_format", "write_avsout",
    "write_cth_packages", "write_dyna3d_deck", "write_grid", "write_lsdyna_deck",
]
