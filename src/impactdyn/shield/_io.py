"""HDF5 files of an SPH state: the particles at one time and the run's history of totals; and the
fragments found in them (:func:`write_fragments`, :func:`read_fragments`).

Layout (units cm, g, µs, Mbar)::

    /particles/<field>      every array of :class:`Particles` (position (N, 3), …, material (N,))
    /particles attrs        time_us, materials (names, in material-id order)
    /history/<field>        time (S,), mass (S,), momentum (S, 3), kinetic (S,), internal (S,)   [optional]
    /  attrs                units, format = "impactdyn-sph-particles", version

This is the shield stage's artifact in a Whipple run folder, from which the
binning stage restarts.
"""

from __future__ import annotations

from dataclasses import fields
from pathlib import Path

import numpy as np

from impactdyn._errors import InputError
from impactdyn.shield._fragments import Fragments
from impactdyn.shield._state import History, Particles

FORMAT = "impactdyn-sph-particles"
VERSION = 1
_PARTICLE_FIELDS = tuple(f.name for f in fields(Particles) if f.name not in ("materials", "time"))
#: Fields a file may lack: written by a version that did not record them (the record fills them in).
_OPTIONAL_FIELDS = ("damage", "failure_strain_rate")
_HISTORY_FIELDS = tuple(f.name for f in fields(History))


def write_particles(path: str | Path, particles: Particles, history: History | None = None) -> None:
    """Write ``particles`` (and ``history``) to ``path``; written under a temporary name, then renamed."""
    import h5py

    from impactdyn._runfolder import atomic_output

    with atomic_output(path) as tmp, h5py.File(tmp, "w") as f:
        f.attrs["format"] = FORMAT
        f.attrs["version"] = VERSION
        f.attrs["units"] = "cm, g, us, Mbar; velocity cm/us; specific energy cm^2/us^2; temperature K"
        g = f.create_group("particles")
        g.attrs["time_us"] = particles.time
        g.attrs["materials"] = np.array(particles.materials, dtype=h5py.string_dtype())
        for name in _PARTICLE_FIELDS:
            g.create_dataset(name, data=getattr(particles, name), compression="gzip")
        if history is not None:
            h = f.create_group("history")
            for name in _HISTORY_FIELDS:
                h.create_dataset(name, data=getattr(history, name))


def read_particles(path: str | Path) -> tuple[Particles, History | None]:
    """The particles and history (None if the file has none) of a file written by :func:`write_particles`."""
    from impactdyn.io import open_hdf5

    path = Path(path)
    with open_hdf5(path) as f:
        if f.attrs.get("format") != FORMAT or f.attrs.get("version") != VERSION or "particles" not in f:
            raise InputError(f"{path}: not an impactdyn SPH particle file (format {FORMAT!r}, version {VERSION} expected)")
        g = f["particles"]
        missing = [name for name in _PARTICLE_FIELDS if name not in g and name not in _OPTIONAL_FIELDS]
        if missing:
            raise InputError(f"{path}: /particles lacks {', '.join(missing)}")
        particles = Particles(**{name: g[name][()] for name in _PARTICLE_FIELDS if name in g},
                              materials=tuple(str(s.decode() if isinstance(s, bytes) else s)
                                              for s in g.attrs["materials"]),
                              time=float(g.attrs["time_us"]))
        history = None
        if "history" in f:
            history = History(**{name: f["history"][name][()] for name in _HISTORY_FIELDS})
    return particles, history


FRAGMENTS_FORMAT = "impactdyn-fragments"
_FRAGMENT_FIELDS = tuple(f.name for f in fields(Fragments))


def write_fragments(path: str | Path, fragments: Fragments) -> None:
    """Write every array of ``fragments`` (:class:`Fragments`) to ``path`` (``/fragments/<field>``), atomically:
    the fragments are found once, by the stage that has the particles, and read back exactly by the others."""
    import h5py

    from impactdyn._runfolder import atomic_output

    with atomic_output(path) as tmp, h5py.File(tmp, "w") as f:
        f.attrs["format"] = FRAGMENTS_FORMAT
        f.attrs["version"] = VERSION
        f.attrs["units"] = "cm, g, us; spin rad/us"
        g = f.create_group("fragments")
        for name in _FRAGMENT_FIELDS:
            g.create_dataset(name, data=getattr(fragments, name))


def read_fragments(path: str | Path) -> Fragments:
    """The fragments of a file written by :func:`write_fragments`."""
    from impactdyn.io import open_hdf5

    path = Path(path)
    with open_hdf5(path) as f:
        if f.attrs.get("format") != FRAGMENTS_FORMAT or f.attrs.get("version") != VERSION or "fragments" not in f:
            raise InputError(f"{path}: not an impactdyn fragments file (format {FRAGMENTS_FORMAT!r}, "
                             f"version {VERSION} expected)")
        g = f["fragments"]
        missing = [name for name in _FRAGMENT_FIELDS if name not in g]
        if missing:
            raise InputError(f"{path}: /fragments lacks {', '.join(missing)}")
        return Fragments(**{name: g[name][()] for name in _FRAGMENT_FIELDS})
