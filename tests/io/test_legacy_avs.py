"""The legacy CTH dump avsout (RDAVS, Fahrenthold 1994 App. G)."""

from __future__ import annotations

import dataclasses
import re

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from impactdyn import units
from impactdyn._errors import InputError
from impactdyn.io._fortran import format_e, parse_real
from impactdyn.io._legacy_avs import AvsLayout, read_avsout, write_avsout
from impactdyn.io._legacy_dc3din import read_dc3din

LAYOUT = AvsLayout(i1=5, i2=7, j1=3, j2=4, k1=10, k2=13, xlow=0.0, dx=0.1, ylow=-1.0, dy=0.2, zlow=2.0, dz=0.05)


def code(i, j, k, f):
    """A value that tells which cell (0-based, of LAYOUT) and field it belongs to (field 8, the
    void fraction, stays in [0, 1])."""
    if f == 8:
        return 0.001 * (1 + i + 10 * j + 100 * k)
    return 1000 * (i + 1) + 100 * (j + 1) + 10 * (k + 1) + f


def legacy_dump(path, layout=LAYOUT, fmt=lambda v: f"{v:.6e}", sep="  "):
    """A dump written as CTH would: 27 opaque header lines, cells k outer, j, i inner."""
    nx, ny, nz = layout.shape
    lines = [f"# AVS-style header line {n}" for n in range(27)]
    for k in range(nz):
        for j in range(ny):
            for i in range(nx):
                vals = [code(i, j, k, f) for f in range(10)]
                lines.append(sep.join(fmt(v) for v in vals[:7]))
                lines.append(sep.join(fmt(v) for v in vals[7:]))
    path.write_text("\n".join(lines) + "\n")
    return lines


def test_cell_order_units_and_coordinates(tmp_path):
    p = tmp_path / "avsout"
    legacy_dump(p)
    g = read_avsout(p, LAYOUT, time=4.0)
    assert g.shape == (3, 2, 4) and g.staggered and g.time == 4.0
    i, j, k = np.meshgrid(*(np.arange(n) for n in g.shape), indexing="ij")
    f = lambda n: code(i, j, k, n)  # noqa: E731
    np.testing.assert_allclose(g.velocity, np.stack([f(0), f(1), f(2)], -1) / 1e6, rtol=1e-15)
    np.testing.assert_allclose(g.pressure, f(3) / 1e12, rtol=1e-15)
    np.testing.assert_allclose(g.temperature, f(4), rtol=1e-15)
    np.testing.assert_allclose(g.density, f(5), rtol=1e-15)
    np.testing.assert_allclose(g.specific_energy, f(6) / 1e12, rtol=1e-15)
    np.testing.assert_allclose(g.mass, f(7), rtol=1e-15)
    np.testing.assert_allclose(g.void_fraction, f(8), rtol=1e-15)
    np.testing.assert_allclose(g.sound_speed, f(9) / 1e6, rtol=1e-15)
    # x_i = xlow + (i - 2) dx for absolute cell i = i1 + l
    np.testing.assert_allclose(g.x, 0.0 + (5 + np.arange(4) - 2) * 0.1, rtol=1e-15)
    np.testing.assert_allclose(g.y, -1.0 + (3 + np.arange(3) - 2) * 0.2, rtol=1e-15)
    np.testing.assert_allclose(g.z, 2.0 + (10 + np.arange(5) - 2) * 0.05, rtol=1e-15)


@pytest.mark.parametrize("fmt, sep", [
    (lambda v: f"{v:11.3e}".replace("e", "D"), ""),  # D exponents, fixed 11 columns
    (lambda v: f"{v:.6e}", " \t "),  # whitespace of any kind
])
def test_tolerant_number_forms(tmp_path, fmt, sep):
    p = tmp_path / "avsout"
    legacy_dump(p, fmt=fmt, sep=sep)
    g = read_avsout(p, LAYOUT)
    np.testing.assert_allclose(g.mass[2, 1, 3], code(2, 1, 3, 7), rtol=1e-3)


def test_touching_fields_and_three_digit_exponents(tmp_path):
    p = tmp_path / "avsout"
    lines = legacy_dump(p)
    # Fortran e11.4 output of negatives fills all 11 columns; |exponent| > 99 loses its 'E'
    lines[27] = "-0.1001E+07-0.2002E+07-0.3003E+07 0.4004-104 0.5005E+03 0.6006E+01 0.7007E+10"
    p.write_text("\n".join(lines) + "\n")
    g = read_avsout(p, LAYOUT)
    np.testing.assert_allclose(g.velocity[0, 0, 0], [-1.001, -2.002, -3.003], rtol=1e-15)
    assert g.pressure[0, 0, 0] == pytest.approx(0.4004e-104 / 1e12, rel=1e-15)


def test_round_trip_of_representable_values(tmp_path, rng, representable_grid, assert_same_grid):
    g = representable_grid(rng)
    p = tmp_path / "dump.avsout"
    write_avsout(p, g)
    assert len(p.read_text().splitlines()) == 27 + 2 * np.prod(g.shape)
    assert_same_grid(read_avsout(p), g)


def test_three_significant_digits(tmp_path, rng, representable_grid):
    g0 = representable_grid(rng)
    g = dataclasses.replace(g0, pressure=rng.normal(size=g0.shape) * 10.0 ** rng.integers(-8, 3, g0.shape))
    p = tmp_path / "avsout"
    write_avsout(p, g)
    back = read_avsout(p).pressure
    assert np.all(np.abs(back - g.pressure) <= 5e-3 * np.abs(g.pressure))
    assert not np.array_equal(back, g.pressure)


def test_dc3din_layout_reads_a_dump_of_its_size(tmp_path, example_dc3din, representable_grid):
    layout = read_dc3din(example_dc3din).avs_layout
    assert layout.shape == (32, 49, 64)
    x, y, z = layout.nodes()
    small = representable_grid(np.random.default_rng(1), shape=(1, 1, 1))
    g = dataclasses.replace(small, x=x, y=y, z=z, **{
        f: np.broadcast_to(getattr(small, f).reshape(-1)[0], layout.shape) for f in
        ("density", "void_fraction", "mass", "pressure", "temperature", "specific_energy", "sound_speed")},
        velocity=np.broadcast_to(small.velocity[0, 0, 0], layout.shape + (3,)))
    p = tmp_path / "avsout"
    write_avsout(p, g, layout)
    back = read_avsout(p, layout)
    assert back.x[0] == pytest.approx(0.0) and back.y[0] == pytest.approx(-11.5 + 62 * 0.03175)
    assert back.z[-1] == pytest.approx(-1.0 + 79 * 0.03175)
    np.testing.assert_allclose(back.mass, g.mass, rtol=1e-12)


def test_truncated_header(tmp_path):
    p = tmp_path / "avsout"
    p.write_text("header\n" * 10)
    with pytest.raises(InputError, match=rf"{p}:10: truncated"):
        read_avsout(p, LAYOUT)


def test_truncated_data(tmp_path):
    p = tmp_path / "avsout"
    lines = legacy_dump(p)
    p.write_text("\n".join(lines[:-1]) + "\n")
    with pytest.raises(InputError, match=rf"{p}:{len(lines) - 1}: truncated: 47 data records, .* needs 48"):
        read_avsout(p, LAYOUT)


def test_wrong_record_count(tmp_path):
    p = tmp_path / "avsout"
    lines = legacy_dump(p)
    p.write_text("\n".join(lines + lines[-2:]) + "\n")
    with pytest.raises(InputError, match=rf"{p}:{len(lines) + 1}: wrong record count: 50 data records"):
        read_avsout(p, LAYOUT)


@pytest.mark.parametrize("line, bad, message", [
    (30, "1.0 2.0 3.0 4.0 5.0", "expected 7 fields, found 5"),
    (31, "1.0 abc 3.0", "not a number: 'abc'"),
    (31, "1.0 nan 3.0", "not a finite number: 'nan'"),
])
def test_bad_records_name_file_and_line(tmp_path, line, bad, message):
    p = tmp_path / "avsout"
    lines = legacy_dump(p)
    lines[line - 1] = bad
    p.write_text("\n".join(lines) + "\n")
    with pytest.raises(InputError, match=rf"{p}:{line}: .*{message}"):
        read_avsout(p, LAYOUT)


def test_cth_dump_needs_the_layout(tmp_path):
    p = tmp_path / "avsout"
    legacy_dump(p)
    with pytest.raises(InputError, match=rf"{p}:27: the header .* layout from dc3din"):
        read_avsout(p)


@pytest.mark.parametrize("key, value, message", [
    ("i2", "4.5", r":6: i2 = 4.5 must be an integer"),
    ("i2", "1", r":5-16: avsout layout: need 1 <= i1 <= i2"),
    ("dx", "1e-300", r":5-16: avsout layout: the x nodes reach"),
])
def test_bad_header_layout_names_its_lines(tmp_path, rng, representable_grid, key, value, message):
    p = tmp_path / "dump.avsout"
    write_avsout(p, representable_grid(rng))
    p.write_text(re.sub(rf"(?m)^{key} = .*$", f"{key} = {value}", p.read_text()))
    with pytest.raises(InputError, match=rf"^{p}{message}"):
        read_avsout(p)


def test_writer_refuses_what_avsout_cannot_hold(tmp_path, rng, representable_grid):
    g = representable_grid(rng)
    with pytest.raises(InputError, match="cell-centred"):
        write_avsout(tmp_path / "a", dataclasses.replace(g, staggered=False))
    x = g.x.copy()
    x[1] += 0.01
    with pytest.raises(InputError, match="uniform"):
        write_avsout(tmp_path / "a", dataclasses.replace(g, x=x))
    assert not (tmp_path / "a").exists()


def test_layout_checks_indices():
    with pytest.raises(InputError, match="i1 <= i2"):
        dataclasses.replace(LAYOUT, i2=4)


def test_unit_conversions_used_by_the_legacy_formats():
    assert units.cm_s_to_cm_us(7.0e5) == pytest.approx(units.km_s_to_cm_us(7.0)) == pytest.approx(0.7)
    assert units.dyn_cm2_to_mbar(1.0e12) == 1.0 and units.gpa_to_mbar(100.0) == pytest.approx(1.0)
    assert units.erg_g_to_cm2_us2(1.0e12) == 1.0
    assert units.ksi_to_mbar(1.0) == pytest.approx(6.894757e-5, rel=1e-7)
    assert units.inch_to_cm(0.125) == pytest.approx(0.3175)
    for there, back in [(units.cm_s_to_cm_us, units.cm_us_to_cm_s), (units.dyn_cm2_to_mbar, units.mbar_to_dyn_cm2),
                        (units.erg_g_to_cm2_us2, units.cm2_us2_to_erg_g), (units.km_s_to_cm_us, units.cm_us_to_km_s),
                        (units.gpa_to_mbar, units.mbar_to_gpa), (units.s_to_us, units.us_to_s)]:
        assert back(there(3.7)) == pytest.approx(3.7, rel=1e-15)


def test_invalid_cell_values_name_the_file_line_and_cell(tmp_path):
    p = tmp_path / "avsout"
    lines = legacy_dump(p)
    lines[27 + 2 * 4 + 1] = "-1.0 0.5 3.0"  # cell 5 in file order = (i, j, k) (1, 1, 0): negative mass
    p.write_text("\n".join(lines) + "\n")
    with pytest.raises(InputError, match=rf"{p}:37: HydroGrid.mass: negative value at index \(1, 1, 0\)"):
        read_avsout(p, LAYOUT)


@settings(max_examples=300, deadline=None)
@given(st.one_of(st.just(0.0), st.floats(min_value=1e-300, max_value=1e300), st.floats(min_value=-1e300,
                                                                                        max_value=-1e-300)),
       st.sampled_from([(11, 3), (10, 3), (20, 8), (8, 1)]))
def test_fortran_e_fields_round_trip(value, fmt):
    """Ew.d output (3-digit exponents without the E) reads back to d significant digits."""
    width, digits = fmt
    field = format_e([value], width, digits)
    assert len(field) == width
    assert abs(parse_real(field) - value) <= 0.5 * 10.0 ** (1 - digits) * abs(value) * (1 + 1e-12)
