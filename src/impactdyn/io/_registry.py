"""Registry of HydroGrid file formats, and atomic output.

Each format module registers itself by a call at its bottom (as meshio does; :data:`FORMATS` is a
:class:`impactdyn._registry.Registry`, the package's one plug-in idiom)::

    register_format("hdf5", (".h5", ".hdf5"), reader=read_hdf5, writer=write_hdf5)

:func:`read_grid` and :func:`write_grid` pick the format by explicit name or by
the file name: an extension starting with ``.`` matches the end of the name, one
without (``avsout``) matches the whole name.  Writers write to a temporary file
in the target's folder that replaces the target only when complete
(:func:`impactdyn._runfolder.atomic_output`), so an interrupted write never leaves a file that looks
complete.
"""

from __future__ import annotations

import importlib
import os
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path

from impactdyn._errors import InputError
from impactdyn._registry import Registry
from impactdyn._runfolder import atomic_output
from impactdyn.hydrogrid import HydroGrid

Reader = Callable[[Path], HydroGrid]
Writer = Callable[[Path, HydroGrid], None]

_BUILTIN = ("_hdf5", "_vtk", "_legacy_avs")


@dataclass(frozen=True)
class GridFormat:
    name: str
    extensions: tuple[str, ...]
    reader: Reader | None
    writer: Writer | None


def load_builtin_formats() -> None:
    """Import the built-in format modules, which register themselves."""
    for mod in _BUILTIN:
        importlib.import_module(f"impactdyn.io.{mod}")


#: Registered grid formats by name (the case key ``format``); the built-ins are imported at the first lookup.
FORMATS: Registry[GridFormat] = Registry("grid format", "format", load=load_builtin_formats)


def register_format(name: str, extensions: tuple[str, ...] | list[str],
                    reader: Reader | None = None, writer: Writer | None = None) -> GridFormat:
    """``FORMATS.register(name, GridFormat(...))``, replacing a format of that name."""
    return FORMATS.register(name, GridFormat(name, tuple(e.lower() for e in extensions), reader, writer),
                            replace=True)


def formats() -> dict[str, GridFormat]:
    """The registered formats by name (built-ins loaded)."""
    return dict(FORMATS.items())


def read_grid(path: str | os.PathLike, format: str | None = None) -> HydroGrid:
    """Read a HydroGrid, format by name or by the file name."""
    fmt = _choose(Path(path), format, "reader")
    return fmt.reader(Path(path))


def write_grid(path: str | os.PathLike, grid: HydroGrid, format: str | None = None) -> None:
    """Write a HydroGrid atomically, format by name or by the file name."""
    fmt = _choose(Path(path), format, "writer")
    with atomic_output(path) as tmp:
        fmt.writer(tmp, grid)


def open_hdf5(path: str | os.PathLike):
    """``h5py.File(path, "r")``, with a missing or non-HDF5 file an :class:`InputError` naming it."""
    import h5py

    path = Path(path)
    if not path.is_file():
        raise InputError(f"{path}: no such file")
    try:
        return h5py.File(path, "r")
    except OSError as err:
        raise InputError(f"{path}: not an HDF5 file ({err})") from None


@contextmanager
def in_file(path: str | os.PathLike) -> Iterator[None]:
    """Prefix the file name to an InputError raised inside (e.g. by HydroGrid's checks)."""
    try:
        yield
    except InputError as err:
        if str(err).startswith(str(path)):
            raise
        raise InputError(f"{path}: {err}") from None


def _choose(path: Path, name: str | None, role: str) -> GridFormat:
    table = formats()
    known = ", ".join(f"{f.name} ({' '.join(f.extensions)})" for _, f in sorted(table.items())
                      if getattr(f, role) is not None)
    if name is not None:
        fmt = table.get(name)
        if fmt is None or getattr(fmt, role) is None:
            raise InputError(f"{path}: no grid {role} named {name!r}; known: {known}")
        return fmt
    lname = path.name.lower()
    for fmt in table.values():
        if getattr(fmt, role) is not None and any(
                lname.endswith(e) if e.startswith(".") else lname == e for e in fmt.extensions):
            return fmt
    raise InputError(f"{path}: unknown grid format (by file name); known: {known}")
