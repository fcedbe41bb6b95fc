"""The run folder of the debris stage: which files it holds, ``summary.json`` and DCPOST's tables.

Files (``case.output`` switches the optional ones):

``summary.json``                  headline numbers (:meth:`DebrisResult.summary`) and the file list
``config.resolved.toml``          every parameter used (the run's case, defaults included)
``areal_density.csv``             DCPOST: impulse and areal density per wall face element
``areal_density_remap.csv``       the same on ``wall.remap``'s grid, if given
``handoff_grid.h5``               the HydroGrid the particles were seeded from (readable as a case's grid.file)
``debris.h5``                     all arrays: particles, arrival states, deposition, wall
``particles_handoff.vtu``         particles as tetrahedra at hand-off (ParaView)
``particles_arrival.vtu``         the propagated particles at their arrival
``wall_deposition.vtu``           the wall's front face with impulse and areal density per element
``wall.k``                        LS-DYNA keyword deck, time-resolved loads (:mod:`impactdyn.io._lsdyna`)
``wall_dyna3d.inp``               the legacy DYNA3D deck with DCPOST's cards (summed per element, t = 0)
``plots/areal_density.png``       DCMPLT's contour map
``plots/cloud.png``               side and top views of the cloud at hand-off and at arrival

A lean folder (``lean=True``, the Whipple pipeline's default) leaves out the heavy arrays: no
``handoff_grid.h5`` (``config.resolved.toml`` names the grid the case was run from), a
``debris.h5`` of the deposition and the wall only, and no particle VTU files (``wall_deposition.vtu``
stays); on the 7a shot 5.9 MB instead of 140 MB.

Times are µs after the hand-off; units cm, g, µs (momentum g·cm/µs = 10 N·s).
The writers of the other files: :mod:`._debris_h5` (``debris.h5``), :mod:`._vtk_output`,
:mod:`._decks`, :mod:`._plots`.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from impactdyn._config import dump_toml
from impactdyn._runfolder import FolderWriter, RunFolder
from impactdyn.debris._debris_h5 import write_hdf5
from impactdyn.debris._decks import DeckOptions, write_decks
from impactdyn.debris._deposit import areal_density, remap_impulse
from impactdyn.debris._plots import write_plots
from impactdyn.debris._propagate import DebrisResult
from impactdyn.debris._vtk_output import write_vtk
from impactdyn.wallgrid import WallGrid

AREAL_HEADER = ["i", "k", "element", "x_cm", "z_cm", "px_g_cm_us", "py_g_cm_us", "pz_g_cm_us",
                "areal_density_g_cm_us"]


def areal_rows(impulse: np.ndarray, wall: WallGrid) -> list[list]:
    """DCPOST's table: one row per face element, i fastest (element i + nx k)."""
    areal = areal_density(impulse, wall)
    xc = 0.5 * (wall.x[:-1] + wall.x[1:])
    zc = 0.5 * (wall.z[:-1] + wall.z[1:])
    nx, _, nz = wall.shape
    return [[i, k, i + nx * k, xc[i], zc[k], *impulse[i, k], areal[i, k]] for k in range(nz) for i in range(nx)]


def write_debris_run(result: DebrisResult, case, outdir: str | Path, *, force: bool = False,
                     remap: WallGrid | None = None, dcpost_factor: float = 1.0,
                     extra_summary: dict | None = None) -> dict:
    """Write the run folder atomically; returns the summary written."""
    with RunFolder(outdir, force=force) as rf:
        return write_debris_files(rf, result, case, remap=remap, dcpost_factor=dcpost_factor,
                                  extra_summary=extra_summary)


def write_debris_files(folder: FolderWriter, result: DebrisResult, case, *, remap: WallGrid | None = None,
                       dcpost_factor: float = 1.0, extra_summary: dict | None = None, decks: bool = True,
                       lean: bool = False) -> dict:
    """Every file of the module docstring into ``folder``; returns the summary (also ``summary.json``).

    ``decks=False`` leaves the wall decks out (the Whipple pipeline writes them in a stage of their own);
    ``lean`` leaves out the heavy arrays (module docstring).
    """
    o = case.output
    summary = result.summary() | (extra_summary or {})
    files = ["summary.json", "config.resolved.toml", "areal_density.csv"]
    folder.write_text("config.resolved.toml", dump_toml(case))
    folder.write_csv("areal_density.csv", AREAL_HEADER, areal_rows(result.impulse, result.wall))
    if remap is not None:
        moved = remap_impulse(result.impulse, result.wall, remap)
        folder.write_csv("areal_density_remap.csv", AREAL_HEADER, areal_rows(moved, remap))
        summary["remap"] = {"momentum_deposited": moved.reshape(-1, 3).sum(axis=0).tolist(),
                            "peak_areal_density_g_cm_us": float(areal_density(moved, remap).max())}
        files.append("areal_density_remap.csv")
    if o.hdf5:
        from impactdyn.io import write_grid

        if not lean:
            write_grid(folder.file("handoff_grid.h5"), result.grid)
            files.append("handoff_grid.h5")
        write_hdf5(result, folder.file("debris.h5"), lean=lean)
        files.append("debris.h5")
    if o.vtk:
        # lean: at most 0 particles, so the particle files are left out and wall_deposition.vtu stays
        files += write_vtk(result, folder.path, 0 if lean else o.max_vtk_particles)
    if decks:
        files += write_decks(folder, result.wall, result.deposition, result.impulse,
                             DeckOptions.of(case, dcpost_factor))
    if o.plots:
        write_plots(result, folder.path / "plots")
        files += ["plots/areal_density.png", "plots/cloud.png"]
    summary["files"] = sorted(files)
    folder.write_json("summary.json", summary)
    return summary
