"""The ``debris.h5`` file of a debris run: its schema, written by :func:`write_hdf5` and read back by
:func:`read_deposition` (the Whipple pipeline's decks stage and report read it) and
:func:`read_arrivals` (the arriving particles' mass and momentum)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from impactdyn._errors import InputError
from impactdyn._runfolder import atomic_output
from impactdyn.debris._deposit import POINTS_PER_PARTICLE
from impactdyn.debris._particle import P_SLICE
from impactdyn.debris._propagate import DebrisResult
from impactdyn.wallgrid import WallDeposition, WallGrid


def write_hdf5(result: DebrisResult, path: Path, lean: bool = False) -> None:
    """The run's arrays in one HDF5 file (groups particles, arrival, deposition, wall; the grid is
    ``handoff_grid.h5``).  ``lean``: the groups deposition and wall only, what
    :func:`read_deposition` reads (the wall and decks stages): 4.9 MB of the 7a shot's 83 MB, whose
    particle states at hand-off and arrival are the rest (:func:`read_arrivals` needs them)."""
    import h5py

    r = result
    with atomic_output(path) as tmp, h5py.File(tmp, "w") as f:
        f.attrs["units"] = "cm, g, us; momentum g*cm/us; times after hand-off"
        f.attrs["t_handoff_us"] = r.t_handoff
        f.attrs["lean"] = lean
        if not lean:
            _write_particles(f, r)
        d = f.create_group("deposition")
        for name in ("element", "time", "impulse"):
            d.create_dataset(name, data=getattr(r.deposition, name), compression="gzip")
        w = f.create_group("wall")
        for name in ("x", "y", "z"):
            w.create_dataset(name, data=getattr(r.wall, name))
        w.create_dataset("impulse", data=r.impulse)
        w.create_dataset("areal_density", data=r.areal)


def _write_particles(f, result: DebrisResult) -> None:
    """The groups particles and arrival of :func:`write_hdf5`."""
    r, c = result, result.cloud
    p = f.create_group("particles")
    for name in ("vertices", "states", "J", "mass", "void_fraction", "density_ratio", "cell", "tet"):
        p.create_dataset(name, data=getattr(c, name), compression="gzip")
    p.create_dataset("t_arrival", data=r.t_arrival)
    a = f.create_group("arrival")
    a.create_dataset("index", data=r.propagated)
    a.create_dataset("states", data=r.states, compression="gzip")
    a.create_dataset("points", data=r.points, compression="gzip")
    a.create_dataset("on_wall", data=r.on_wall)
    for name in ("steps", "rejected", "code", "t_reached"):
        a.create_dataset(name, data=getattr(r.stats, name))


def read_deposition(path: str | Path) -> tuple[WallGrid, WallDeposition, np.ndarray]:
    """The wall, its time-resolved deposition and the impulse per element ``(nx, nz, 3)`` of a ``debris.h5``."""
    from impactdyn.io import open_hdf5

    path = Path(path)
    with open_hdf5(path) as f:
        try:
            w, d = f["wall"], f["deposition"]
            wall = WallGrid(x=w["x"][()], y=w["y"][()], z=w["z"][()])
            dep = WallDeposition(element=d["element"][()], time=d["time"][()], impulse=d["impulse"][()])
            impulse = w["impulse"][()]
        except KeyError as err:
            raise InputError(f"{path}: not a debris.h5 file ({err})") from None
    return wall, dep, impulse


def read_arrivals(path: str | Path) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The particles that reached the wall in a ``debris.h5``: mass ``(N,)`` g, momentum ``(N, 3)``
    g·cm/µs at arrival, and the share ``(N,)`` of it deposited on the wall grid (the fraction of the
    particle's deposition points that fell on the grid, :func:`impactdyn.debris.deposit`)."""
    from impactdyn.io import open_hdf5

    path = Path(path)
    with open_hdf5(path) as f:
        try:
            index, states, on = f["arrival/index"][()], f["arrival/states"][()], f["arrival/on_wall"][()]
            mass = f["particles/mass"][()][index]
        except KeyError as err:
            if f.attrs.get("lean", False):
                raise InputError(f"{path}: a lean debris.h5 holds no particle states; rerun its stage with "
                                 "--keep all") from None
            raise InputError(f"{path}: not a debris.h5 file ({err})") from None
    return mass, states[:, P_SLICE], on.sum(axis=1) / POINTS_PER_PARTICLE
