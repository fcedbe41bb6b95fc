"""File formats of the impact pipeline (one registry of grid formats), on the data model only.

Grid formats register themselves at the bottom of their modules; ``read_grid`` and
``write_grid`` pick one by extension or name. Every writer goes through
:func:`atomic_output`.  This package imports the data model (:mod:`impactdyn.hydrogrid`,
:mod:`impactdyn.wallgrid`, :mod:`impactdyn.materials`) and no solver package. Heavy
dependencies (h5py, meshio) are imported by the format modules only when used.
"""

from impactdyn._runfolder import atomic_output
from impactdyn.io._registry import FORMATS, formats, load_builtin_formats, open_hdf5, read_grid, register_format, write_grid
from impactdyn.io._cell_block import CellBlock
from impactdyn.io._legacy_avs import AvsLayout, read_avsout, write_avsout
from impactdyn.io._legacy_dc3din import Dc3dInput, RunType, read_dc3din
from impactdyn.io._dyna3d import write_dyna3d_deck
from impactdyn.io._lsdyna import read_lsdyna_deck, write_lsdyna_deck
from impactdyn.io._cth import read_cth_packages, write_cth_packages
from impactdyn.io._vtk import write_mesh

__all__ = [
    "AvsLayout", "CellBlock", "FORMATS", "Dc3dInput", "RunType", "atomic_output", "formats", "load_builtin_formats", "open_hdf5",
    "read_avsout", "read_cth_packages", "read_dc3din", "read_grid", "read_lsdyna_deck", "register_format",
    "write_avsout", "write_cth_packages", "write_dyna3d_deck", "write_grid", "write_lsdyna_deck", "write_mesh",
]
