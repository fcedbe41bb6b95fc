"""DC3D debris-cloud propagation (seed 000): grid model, wall grid, particles (in progress)."""

from impactdyn.debris._grid import HydroGrid
from impactdyn.debris._wall import AL_6061_T6, WallDeposition, WallGrid, WallMaterial

__all__ = ["AL_6061_T6", "HydroGrid", "WallDeposition", "WallGrid", "WallMaterial"]
