"""The grid-format registry: every registered writer round-trips through its reader."""

from __future__ import annotations

import base64
import dataclasses

import h5py
import numpy as np
import pytest

from impactdyn._errors import InputError
from impactdyn.io import _registry
from impactdyn.io._registry import formats, read_grid, register_format, write_grid

ROUND_TRIP = sorted(name for name, f in formats().items() if f.reader and f.writer)
#: The round-trip formats that do not keep every bit, and why; every other registered format is held to an
#: exact round trip (a new one too, until it says here why not).
LOSSY = {"avsout": "the legacy CTH text file: three significant digits (e11.3), always staggered"}
EXACT = [name for name in ROUND_TRIP if name not in LOSSY]


def file_name(fmt_name: str) -> str:
    ext = formats()[fmt_name].extensions[0]
    return f"grid{ext}" if ext.startswith(".") else ext


def test_built_in_formats_are_registered():
    assert {"hdf5", "vtk-rectilinear", "avsout"} <= set(ROUND_TRIP)


@pytest.mark.parametrize("name", ROUND_TRIP)
def test_round_trip_by_file_name(tmp_path, rng, name, representable_grid, assert_same_grid):
    g = representable_grid(rng)
    p = tmp_path / file_name(name)
    write_grid(p, g)
    assert_same_grid(read_grid(p), g)
    assert [q.name for q in tmp_path.iterdir()] == [p.name]  # no temporary left behind


@pytest.mark.parametrize("name", ROUND_TRIP)
def test_round_trip_by_format_name_is_stable(tmp_path, rng, name, representable_grid):
    """Whatever a format rounds, it rounds once: a second round trip changes nothing."""
    g0 = representable_grid(rng, shape=(2, 3, 2))
    g = dataclasses.replace(g0, density=rng.uniform(0.1, 9.0, g0.shape), velocity=rng.normal(size=g0.shape + (3,)))
    p = tmp_path / "no_extension"
    write_grid(p, g, format=name)
    once = read_grid(p, format=name)
    write_grid(p, once, format=name)
    twice = read_grid(p, format=name)
    for f in ("x", "y", "z", "density", "velocity", "pressure", "mass"):
        np.testing.assert_array_equal(getattr(twice, f), getattr(once, f), err_msg=f)


def test_lossy_formats_are_registered():
    assert set(LOSSY) <= set(ROUND_TRIP)


@pytest.mark.parametrize("name", EXACT)
def test_exact_formats_are_exact(tmp_path, rng, name, representable_grid):
    g0 = representable_grid(rng, shape=(4, 2, 3))
    x = np.cumsum(rng.uniform(0.1, 1.0, 5))
    g = dataclasses.replace(g0, x=x, pressure=rng.normal(size=g0.shape), velocity=rng.normal(size=g0.shape + (3,)),
                            staggered=False, time=np.pi)
    p = tmp_path / file_name(name)
    write_grid(p, g)
    back = read_grid(p)
    assert back.staggered is False and back.time == np.pi
    for f in ("x", "y", "z", "pressure", "velocity", "temperature"):
        np.testing.assert_array_equal(getattr(back, f), getattr(g, f), err_msg=f)


def test_extension_is_case_insensitive_and_name_overrides(tmp_path, rng, representable_grid):
    g = representable_grid(rng)
    write_grid(tmp_path / "A.H5", g)
    assert h5py.is_hdf5(tmp_path / "A.H5")
    write_grid(tmp_path / "b.h5", g, format="vtk-rectilinear")
    assert (tmp_path / "b.h5").read_bytes().startswith(b"<?xml")


def test_unknown_format_lists_the_known_ones(tmp_path, rng, representable_grid):
    with pytest.raises(InputError, match=r"unknown grid format .*known: avsout \(avsout \.avsout\), "
                                         r"hdf5 \(\.h5 \.hdf5\), vtk-rectilinear \(\.vtr\)"):
        write_grid(tmp_path / "grid.xyz", representable_grid(rng))
    with pytest.raises(InputError, match="no grid reader named 'netcdf'; known: "):
        read_grid(tmp_path / "grid.h5", format="netcdf")


def test_failed_write_leaves_the_old_file(tmp_path, rng, representable_grid):
    def broken(path, grid):
        path.write_text("half a file")
        raise RuntimeError("disk full")

    register_format("broken", (".broken",), writer=broken)
    try:
        p = tmp_path / "grid.broken"
        p.write_text("previous")
        with pytest.raises(RuntimeError, match="disk full"):
            write_grid(p, representable_grid(rng))
    finally:
        _registry.FORMATS.unregister("broken")
    assert p.read_text() == "previous"
    assert [q.name for q in tmp_path.iterdir()] == ["grid.broken"]


def test_hdf5_reader_checks_units_and_datasets(tmp_path, rng, representable_grid):
    p = tmp_path / "grid.h5"
    write_grid(p, representable_grid(rng))
    with h5py.File(p, "r+") as f:
        f["pressure"].attrs["units"] = "GPa"
    with pytest.raises(InputError, match=r"/pressure has units 'GPa', expected 'Mbar'"):
        read_grid(p)
    with h5py.File(p, "r+") as f:
        del f["pressure"]
    with pytest.raises(InputError, match="dataset /pressure missing"):
        read_grid(p)
    p.write_text("not hdf5")
    with pytest.raises(InputError, match="not an HDF5 file"):
        read_grid(p)


def test_vtr_reader_takes_other_encodings_and_reports_missing_arrays(tmp_path, rng, representable_grid):
    import xml.etree.ElementTree as ET

    g = representable_grid(rng)
    p = tmp_path / "grid.vtr"
    write_grid(p, g)
    tree = ET.parse(p)
    el = tree.find(".//CellData/DataArray[@Name='mass']")
    el.set("format", "ascii")
    el.text = " ".join(repr(float(v)) for v in g.mass.transpose(2, 1, 0).ravel())
    tree.write(p)
    np.testing.assert_array_equal(read_grid(p).mass, g.mass)
    # header and data base64-encoded as one stream, as meshio writes them
    el = tree.find(".//CellData/DataArray[@Name='density']")
    data = g.density.transpose(2, 1, 0).astype("<f8").tobytes()
    el.text = base64.b64encode(np.array([len(data)], "<u8").tobytes() + data).decode()
    tree.write(p)
    np.testing.assert_array_equal(read_grid(p).density, g.density)
    el = tree.find(".//CellData/DataArray[@Name='mass']")
    tree.find(".//CellData").remove(el)
    tree.write(p)
    with pytest.raises(InputError, match="data array 'mass' missing"):
        read_grid(p)
