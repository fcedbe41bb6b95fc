"""The DC3D input file dc3din (App. C; DC3D and DCPOST reads, App. G and F)."""

from __future__ import annotations

import numpy as np
import pytest

from impactdyn._errors import InputError
from impactdyn.io._legacy_dc3din import RunType, read_dc3din


def variant(tmp_path, example, edit):
    """A copy of the Appendix C file with ``edit(lines)`` applied (lines are 0-based)."""
    lines = example.read_text().splitlines()
    edit(lines)
    p = tmp_path / "dc3din"
    p.write_text("\n".join(lines) + "\n")
    return p


def test_appendix_c_parses(example_dc3din):
    d = read_dc3din(example_dc3din)
    assert (d.itype, d.jtype) == (2, 1) and d.run_type is RunType.PROPAGATE_TO_WALL
    assert (d.i1, d.i2, d.j1, d.j2, d.k1, d.k2) == (2, 33, 64, 112, 17, 80)
    # CTH mesh of App. A: x0 0, y0 -11.5, z0 -1.0, cells of 1.5875 cm / 50
    assert (d.xlow, d.ylow, d.zlow) == (0.0, -11.5, -1.0)
    assert d.dx == d.dy == d.dz == pytest.approx(1.5875 / 50, rel=1e-12)
    assert (d.tcut, d.tmin, d.dencut) == (25.0, 0.0, 0.01)
    assert (d.idmax, d.jdmax, d.kdmax) == (51, 5, 101)
    assert (d.xdmin, d.xdmax, d.ydmin, d.ydmax, d.zdmin, d.zdmax) == (0.0, 8.0, 0.0, 0.3175, -4.0, 12.0)
    assert (d.mu, d.lam, d.rho_ref) == (0.239, 0.503, 2.703)
    assert (d.eps, d.ymxref, d.factor) == (1.0e-6, 1.0e-6, 1.0)
    assert d.avs_layout.shape == (32, 49, 64)
    wall = d.dyngen_wall
    assert wall.shape == (50, 4, 100)
    np.testing.assert_allclose(np.diff(wall.x), 0.16, rtol=1e-12)
    np.testing.assert_allclose(np.diff(wall.y), 0.3175 / 4, rtol=1e-12)


def test_factor_without_its_comment_line(tmp_path, example_dc3din):
    """DCPOST's (////e15.3) reads the factor from the line after the zeta record."""
    p = variant(tmp_path, example_dc3din, lambda ls: ls.__setitem__(slice(-2, None), ["       0.75"]))
    assert read_dc3din(p).factor == 0.75


def test_fixed_columns_with_touching_fields(tmp_path, example_dc3din):
    def edit(ls):
        assert ls[13].split() == ["-11.5000", "0.031750"]
        ls[13] = "-11.50000000000.0317500000000"  # two e15 fields, no blank between
    d = read_dc3din(variant(tmp_path, example_dc3din, edit))
    assert (d.ylow, d.dy) == (-11.5, 0.03175)


def test_text_after_the_fields_is_ignored_as_fortran_does(tmp_path, example_dc3din):
    d = read_dc3din(variant(tmp_path, example_dc3din, lambda ls: ls.__setitem__(3, "         2         1   itype jtype")))
    assert (d.itype, d.jtype) == (2, 1)


def test_new_wall_grid_for_jtype_3(tmp_path, example_dc3din):
    def edit(ls):
        ls[3] = "         2         3"
    d = read_dc3din(variant(tmp_path, example_dc3din, edit))
    assert d.run_type is RunType.WALL_DECK_NEW_GRID and not d.run_type.propagates
    assert d.dyngen_wall.z[0] == d.zdminn == 2.0


def test_run_types():
    assert RunType((2, 1)).propagates and RunType((2, 1)).writes_wall_deck
    assert not RunType((2, 2)).propagates and RunType((2, 2)).writes_wall_deck
    assert RunType((2, 3)).uses_new_wall_grid
    assert RunType((1, 1)).propagates and not RunType((1, 1)).writes_wall_deck


@pytest.mark.parametrize("line, text, message", [
    (6, "        33         2", "inconsistent grid indices: need 1 <= i1 <= i2, got i1 = 33, i2 = 2"),
    (10, "        80        17", "inconsistent grid indices: need 1 <= k1 <= k2"),
    (12, "            0.0           -0.1", "dx = -0.1 must be > 0"),
    (4, "         1         3", "itype 1, jtype 3"),
    (22, "            8.0            0.0            0.0           8.00", "xdmax = 0.0 must exceed xdmin"),
    (20, "        51         1       101        51         5       101", "jdmax = 1"),
    (18, "           25.0           30.0           0.01", "tcut = 25.0 must exceed tmin = 30.0"),
    (28, "          0.239          0.503          2.703           abc", "not a number: 'abc'"),
    (8, "        64", "expected 2 fields, found 1"),
])
def test_bad_values_name_file_and_line(tmp_path, example_dc3din, line, text, message):
    p = variant(tmp_path, example_dc3din, lambda ls: ls.__setitem__(line - 1, text))
    with pytest.raises(InputError, match=rf"{p}:{line}: .*{message}"):
        read_dc3din(p)


def test_new_grid_checked_only_when_used(tmp_path, example_dc3din):
    def bad_new_grid(ls):
        ls[21] = "            0.0           8.00            0.0            0.0"
    assert read_dc3din(variant(tmp_path, example_dc3din, bad_new_grid)).xdmaxn == 0.0

    def jtype3(ls):
        bad_new_grid(ls)
        ls[3] = "         2         3"
    p = variant(tmp_path, example_dc3din, jtype3)
    with pytest.raises(InputError, match=rf"{p}:22: inconsistent wall bounds: xdmaxn"):
        read_dc3din(p)


def test_missing_record(tmp_path, example_dc3din):
    p = variant(tmp_path, example_dc3din, lambda ls: ls.__delitem__(slice(19, None)))
    with pytest.raises(InputError, match=rf"{p}:19: missing record 'idmax jdmax kdmax idmaxn jdmaxn kdmaxn'"):
        read_dc3din(p)


def test_missing_comment_line(tmp_path, example_dc3din):
    p = variant(tmp_path, example_dc3din, lambda ls: ls.__delitem__(6))  # the '* j1 j2' line
    with pytest.raises(InputError, match=rf"{p}:8: expected the record 'j1 j2', found a comment line"):
        read_dc3din(p)


def test_missing_file(tmp_path):
    with pytest.raises(InputError, match="no such file"):
        read_dc3din(tmp_path / "dc3din")
