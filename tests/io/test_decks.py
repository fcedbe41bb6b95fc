"""Wall decks: the legacy DYNA3D deck (DYNGEN, App. G; header App. D) and the LS-DYNA keyword deck."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from impactdyn._errors import InputError
from impactdyn.materials import AL_6061_T6_MAT13, get_material
from impactdyn.wallgrid import WallDeposition, WallGrid
from impactdyn.io._dyna3d import write_dyna3d_deck
from impactdyn.io._legacy_dc3din import read_dc3din
from impactdyn.io._lsdyna import _point, _points, read_lsdyna_deck, write_lsdyna_deck


def cut(line: str, widths) -> list[str]:
    edges = np.cumsum([0, *widths])
    return [line[a:b] for a, b in zip(edges[:-1], edges[1:])]


@pytest.fixture(scope="module")
def appendix_c_deck(tmp_path_factory):
    """The DYNA3D deck of App. C's wall grid, with a few deposition cards; (dc3din, deposition, lines)."""
    d = read_dc3din(Path(__file__).resolve().parents[2] / "examples" / "debris" / "legacy" / "dc3din")
    dep = WallDeposition(element=np.array([0, 4999, 1234]), time=np.array([5.25, 7.5, 12.0]),
                         impulse=np.array([[-1.23e-3, 4.56e-2, 7.89e-4], [0.0, 1.0e-5, -2.5e-6], [3.0, -4.0, 5.0]]))
    p = tmp_path_factory.mktemp("dyna3d") / "dc3d.dyn"
    write_dyna3d_deck(p, d.dyngen_wall, deposition=dep)
    return d, dep, p.read_text().splitlines()


def sections(lines, n_nodes, n_elements):
    """Split the deck at the counts DYNGEN writes: header, nodes, elements, 5 closing cards, deposition."""
    start = 2 + 16  # title, counts, two materials of 8 cards
    nodes = lines[start:start + n_nodes]
    elements = lines[start + n_nodes:start + n_nodes + n_elements]
    rest = lines[start + n_nodes + n_elements:]
    return lines[:start], nodes, elements, rest[:5], rest[5:]


def test_counts_of_appendix_d(appendix_c_deck):
    """App. D: 2 materials, 25763 nodes, 20001 elements for the 51 x 5 x 101 wall of App. C."""
    d, dep, lines = appendix_c_deck
    counts = [int(f) for f in cut(lines[1], [5, 8, 8] + [5] * 12)]
    assert counts[:3] == [2, 25763, 20001] and counts[3:] == [0] * 12
    assert 25763 == d.idmax * d.jdmax * d.kdmax + 8  # + the backing element's nodes
    assert 20001 == (d.idmax - 1) * (d.jdmax - 1) * (d.kdmax - 1) + 1  # + the backing element
    header, nodes, elements, closing, deposition = sections(lines, 25763, 20001)
    assert [int(line[:8]) for line in nodes] == list(range(1, 25764))
    assert [int(line[:8]) for line in elements] == list(range(1, 20002))
    assert len(deposition) == 3


def test_header_cards_of_appendix_d(appendix_c_deck):
    _, _, lines = appendix_c_deck
    assert lines[0].startswith("Debris Cloud Wall Impact Model") and lines[0][72:] == "88 large"
    m1 = cut(lines[2], [5, 5, 10])
    assert (int(m1[0]), int(m1[1]), float(m1[2])) == (1, 13, 2.703)
    assert lines[3] == "e-p w/failure"
    assert [float(v) for v in lines[4:10]] == [0.276, 2.900e-03, 3.88e-03, 1.5, -12.0e33, 0.720]
    m2 = cut(lines[10], [5, 5, 10])
    assert (int(m2[0]), int(m2[1]), float(m2[2])) == (2, 1, 1.0)
    assert lines[11] == "elastic" and [float(v) for v in lines[12:14]] == [1.0, 0.3]
    assert lines[14:18] == ["", "", "", ""]


def test_nodes_follow_dyngen(appendix_c_deck):
    """nnode = i + idmax (k-1) + idmax kdmax (j-1), at xdmin + (i-1) delx etc.; codes as DYNGEN sets them."""
    d, _, lines = appendix_c_deck
    _, nodes, _, _, _ = sections(lines, 25763, 20001)
    rows = [cut(line, [8, 5, 20, 20, 20]) for line in nodes]
    code = np.array([int(r[1]) for r in rows])
    xyz = np.array([[float(v) for v in r[2:]] for r in rows])
    delx = (d.xdmax - d.xdmin) / (d.idmax - 1)
    dely = (d.ydmax - d.ydmin) / (d.jdmax - 1)
    delz = (d.zdmax - d.zdmin) / (d.kdmax - 1)
    want_code, want_xyz = np.full(25755, -1), np.zeros((25755, 3))
    for j in range(1, d.jdmax + 1):
        for k in range(1, d.kdmax + 1):
            for i in range(1, d.idmax + 1):
                n = i + d.idmax * (k - 1) + d.idmax * d.kdmax * (j - 1)
                c = 0
                if i == 1:
                    c = 1
                if i == d.idmax:
                    c = 4
                if k == 1 or k == d.kdmax:
                    c = 5
                if i in (1, d.idmax) and k in (1, d.kdmax):
                    c = 7
                want_code[n - 1] = c
                want_xyz[n - 1] = (d.xdmin + (i - 1) * delx, d.ydmin + (j - 1) * dely, d.zdmin + (k - 1) * delz)
    np.testing.assert_array_equal(code[:25755], want_code)
    np.testing.assert_allclose(xyz[:25755], want_xyz, rtol=1e-8, atol=1e-8)  # e20.8: 8 significant digits
    corner = np.array([d.xdmin, d.ydmin, d.zdmin])
    backing = corner + [[0, -1, 0], [1, -1, 0], [1, -1, 1], [0, -1, 1], [0, -2, 0], [1, -2, 0], [1, -2, 1], [0, -2, 1]]
    np.testing.assert_allclose(xyz[25755:], backing, atol=1e-12)
    assert np.all(code[25755:] == 0)


def test_elements_follow_dyngen(appendix_c_deck):
    d, _, lines = appendix_c_deck
    _, _, elements, closing, _ = sections(lines, 25763, 20001)
    rows = np.array([[int(v) for v in cut(line, [8, 5] + [8] * 8)] for line in elements])
    im, km = d.idmax, d.kdmax
    for j in range(1, d.jdmax):
        for k in range(1, km):
            for i in range(1, im):
                nelem = i + (im - 1) * (k - 1) + (im - 1) * (km - 1) * (j - 1)
                n1 = i + im * (k - 1) + im * km * (j - 1)
                n2, n5 = n1 + 1, n1 + im * km
                n3, n6 = n2 + im, n5 + 1
                n4, n7 = n3 - 1, n6 + im
                n8 = n7 - 1
                assert list(rows[nelem - 1]) == [nelem, 1, n5, n6, n7, n8, n1, n2, n3, n4]
    assert list(rows[-1]) == [20001, 2, *range(25756, 25764)]
    assert closing == ["    1    1   11", "    1    0", "    1",
                       "    1    1    2      53      52", "    1    1   25759   25758   25757   25756"]


def test_deposition_cards_as_dcpost_writes_them(appendix_c_deck):
    _, dep, lines = appendix_c_deck
    _, _, _, _, cards = sections(lines, 25763, 20001)
    rows = [cut(line, [8, 10, 10, 10, 10]) for line in cards]
    assert [int(r[0]) for r in rows] == list(dep.element + 1)
    np.testing.assert_allclose([[float(v) for v in r[1:4]] for r in rows], dep.impulse, rtol=1e-12)
    np.testing.assert_allclose([float(r[4]) for r in rows], dep.time, rtol=1e-12)
    assert cards[0][8:18] == "-0.123E-02"  # Fortran e10.3: negative fields fill all ten columns


def test_every_hexahedron_has_positive_volume():
    wall = WallGrid.uniform((0.0, 2.0), (0.0, 0.3), (-1.0, 1.0), (5, 3, 4))
    xyz = wall.node_coordinates()[wall.element_nodes() - 1]  # (elements, 8, 3) in deck order
    jac = np.stack([xyz[:, 1] - xyz[:, 0], xyz[:, 3] - xyz[:, 0], xyz[:, 4] - xyz[:, 0]], axis=-1)
    assert np.all(np.linalg.det(jac) > 0)


def test_dyna3d_options(tmp_path):
    wall = WallGrid.uniform((1.0, 2.0), (0.5, 0.8), (-1.0, 1.0), (3, 2, 3))
    p = tmp_path / "deck"
    write_dyna3d_deck(p, wall, clamped_edges=True, legacy_origin=True, control_cards=["  my control card"])
    lines = p.read_text().splitlines()
    assert lines[2] == "  my control card"
    nodes = [cut(line, [8, 5, 20, 20, 20]) for line in lines[19:19 + wall.n_nodes]]
    assert [float(v) for v in nodes[0][2:]] == [0.0, 0.0, 0.0]  # DYNGEN's origin
    codes = np.array([int(r[1]) for r in nodes]).reshape(2, 3, 3)  # (j, k, i)
    assert np.all(codes[:, :, 2] == 7) and np.all(codes[:, 0, :] == 7) and np.all(codes[:, 1, 0] == 1)


def small_case(rng, n=150):
    wall = WallGrid.uniform((0.0, 2.0), (0.0, 0.3), (-1.0, 1.0), (6, 3, 5))
    elem = rng.integers(0, wall.n_face_elements, n)
    time = rng.uniform(2.0, 20.0, n)
    time[:5] = time[5]  # coincident arrivals
    elem[:5] = elem[5]
    time[10] = time[11] + 0.01  # overlapping pulses
    elem[10] = elem[11]
    impulse = rng.normal(size=(n, 3)) * 10.0 ** rng.integers(-6, -1, (n, 1))
    impulse[20, 1] = 0.0
    return wall, WallDeposition(elem, time, impulse)


def test_lsdyna_round_trip(tmp_path, rng):
    wall, dep = small_case(rng)
    p = tmp_path / "wall.k"
    write_lsdyna_deck(p, wall, deposition=dep)
    deck = read_lsdyna_deck(p)
    np.testing.assert_array_equal(deck.node_ids, np.arange(1, wall.n_nodes + 1))
    np.testing.assert_allclose(deck.coordinates, wall.node_coordinates(), rtol=1e-12, atol=1e-13)
    np.testing.assert_array_equal(deck.solid_ids, np.arange(1, wall.n_elements + 1))
    np.testing.assert_array_equal(deck.solid_parts, 1)
    np.testing.assert_array_equal(deck.solid_nodes, wall.element_nodes())
    fixed = wall.constrained_dofs(clamped=True)
    np.testing.assert_array_equal(deck.spc_nodes, np.flatnonzero(fixed.any(axis=1)) + 1)
    np.testing.assert_array_equal(deck.spc_dofs, fixed[fixed.any(axis=1)])


def test_curve_integrals_equal_the_deposited_impulse(tmp_path, rng):
    wall, dep = small_case(rng)
    p = tmp_path / "wall.k"
    width = 0.05
    write_lsdyna_deck(p, wall, deposition=dep, pulse_width=width)
    deck = read_lsdyna_deck(p)
    # expected per (node, dof), from DYNGEN's numbering of the front face (j = 1): a quarter of each record
    idmax = wall.x.size
    want, scale, first = {}, {}, {}
    for e, t, imp in zip(dep.element, dep.time, dep.impulse):
        i, k = e % (idmax - 1) + 1, e // (idmax - 1) + 1
        n1 = i + idmax * (k - 1)
        for n in (n1, n1 + 1, n1 + 1 + idmax, n1 + idmax):
            first[n] = min(first.get(n, np.inf), t)
            for d in range(3):
                want[n, d + 1] = want.get((n, d + 1), 0.0) + imp[d] / 4
                scale[n, d + 1] = scale.get((n, d + 1), 0.0) + abs(imp[d]) / 4
    got = {}
    for (nid, dof, lcid), sf in zip(deck.point_loads, deck.point_load_scale):
        t, f = deck.curves[lcid]
        assert sf == 0.25 and np.all(np.diff(t) > 0)  # a cell's curve, a quarter to each corner
        assert f[0] == f[1] == f[-2] == f[-1] == 0.0  # flat zero ends
        assert t[1] >= first[nid] - 1e-12  # nothing before the first arrival at the node
        got[nid, dof] = got.get((nid, dof), 0.0) + sf * np.trapezoid(f, t)
    assert sorted(deck.curves) == sorted({int(lcid) for _, _, lcid in deck.point_loads})
    assert len(deck.curves) <= 3 * np.unique(dep.element).size     # one per loaded cell and direction
    assert set(got) == {key for key, v in want.items() if scale[key] > 0}
    for key, v in got.items():
        assert abs(v - want[key]) <= 1e-12 * scale[key], key
    total = np.array([sum(v for (n, d), v in got.items() if d == dof) for dof in (1, 2, 3)])
    np.testing.assert_allclose(total, dep.impulse.sum(axis=0), rtol=0, atol=1e-12 * np.abs(dep.impulse).sum())


def test_material_card(tmp_path):
    wall = WallGrid.uniform((0.0, 1.0), (0.0, 0.3), (0.0, 1.0), (2, 2, 2))
    p = tmp_path / "wall.k"
    write_lsdyna_deck(p, wall)
    lines = p.read_text().splitlines()
    at = lines.index("*MAT_ISOTROPIC_ELASTIC_FAILURE")  # MAT_013: the report's App. D card, field for field
    card1 = [float(v) for v in cut(lines[at + 2], [10] * 6)]
    card2 = [float(v) for v in cut(lines[at + 4], [10] * 4)]
    np.testing.assert_allclose(card1, [1, 2.703, 0.276, 2.9e-3, 3.88e-3, 0.720], rtol=1e-9)
    assert card2[0] == 1.5 and card2[1] == -12.0e33  # EPF, and PRF written explicitly
    assert card2[2] != 0.0  # REM: failed elements kept (compressive pressure only), as DYNA3D type 13
    assert "*END" == lines[-1]


def test_johnson_cook_material_and_controls(tmp_path):
    """The JC alternative: MAT_015 + EOS_GRUNEISEN from the library material, its damage
    constants and spall cut-off; the wall stage's hourglass and bulk-viscosity settings as
    *CONTROL cards; all read back from the deck as written."""
    al = get_material("al6061-t6")
    jc, dmg = al.johnson_cook, al.johnson_cook_damage
    wall = WallGrid.uniform((0.0, 1.0), (0.0, 0.3), (0.0, 1.0), (2, 2, 2))
    p = tmp_path / "wall.k"
    write_lsdyna_deck(p, wall, al, hourglass=(6, 1.0), bulk_viscosity=(1.5, 0.06))
    cards = read_lsdyna_deck(p).cards
    assert "*MAT_ISOTROPIC_ELASTIC_FAILURE" not in cards
    assert cards["*CONTROL_HOURGLASS"][0][:2] == [6.0, 1.0]
    assert cards["*CONTROL_BULK_VISCOSITY"][0][:2] == [1.5, 0.06]
    mat = cards["*MAT_JOHNSON_COOK"]
    np.testing.assert_allclose(mat[0][:3], [1, al.rho0, al.shear_modulus], rtol=1e-8)
    np.testing.assert_allclose(mat[1], [jc.A, jc.B, jc.n, jc.C, jc.m, jc.t_melt, jc.t_room,
                                        jc.reference_strain_rate], rtol=1e-8)
    np.testing.assert_allclose(mat[2], [al.specific_heat, -al.spall_strength, 3, 0, dmg.D1, dmg.D2, dmg.D3, dmg.D4],
                               rtol=1e-8)
    assert mat[3][0] == pytest.approx(dmg.D5)
    assert mat[3][2] == 0.0 and mat[3][3] == 0.0  # EROD 0 (erode) and EFMIN blank (LS-DYNA's 1e-6) unless given
    kept = tmp_path / "kept.k"
    write_lsdyna_deck(kept, wall, al, failure_strain_floor=dmg.efmin, erode_failed=False)
    card4 = read_lsdyna_deck(kept).cards["*MAT_JOHNSON_COOK"][3]
    assert card4[2] == 1.0 and card4[3] == pytest.approx(dmg.efmin, rel=1e-6)  # the wall stage's defaults (a 10-column field: 7 digits)
    eos = cards["*EOS_GRUNEISEN"]
    np.testing.assert_allclose(eos[0][:6], [1, al.c0, al.s, 0, 0, al.gamma0], rtol=1e-8)
    assert eos[1][0] == 1.0
    plain = tmp_path / "plain.k"
    write_lsdyna_deck(plain, wall)
    assert not {"*CONTROL_HOURGLASS", "*CONTROL_BULK_VISCOSITY"} & set(read_lsdyna_deck(plain).cards)


@pytest.mark.parametrize("kwargs, message", [
    (dict(pulse_width=0.0), "pulse_width = 0.0"),
    (dict(end_time=-1.0), "end_time = -1.0"),
])
def test_lsdyna_bad_options(tmp_path, rng, kwargs, message):
    wall, dep = small_case(rng)
    with pytest.raises(InputError, match=message):
        write_lsdyna_deck(tmp_path / "wall.k", wall, deposition=dep, **kwargs)
    assert not (tmp_path / "wall.k").exists()


def test_deposition_outside_the_wall(tmp_path):
    wall = WallGrid.uniform((0.0, 1.0), (0.0, 0.3), (0.0, 1.0), (3, 2, 3))
    dep = WallDeposition(np.array([4]), np.array([1.0]), np.zeros((1, 3)))
    for write in (write_lsdyna_deck, write_dyna3d_deck):
        with pytest.raises(InputError, match="outside the wall's 2 x 2 face grid"):
            write(tmp_path / "deck", wall, deposition=dep)
    with pytest.raises(InputError, match="shapes"):
        WallDeposition(np.array([1, 2]), np.array([1.0]), np.zeros((2, 3)))


def test_curve_points_in_one_pass_are_the_point_cards():
    """The one-pass formatting of the load curves writes exactly what :func:`_point` writes, the
    fields that need a three-digit exponent (and NaN/inf) included."""
    rng = np.random.default_rng(7)
    awkward = np.array([0.0, -0.0, 1e-98, -1e-98, 9.99999999999995e-99, 1e-99, 1e-120, -3e-200, 1e99,
                        9.999999999999995e98, 1e100, -2.5e150, np.nan, np.inf, -np.inf, 5e-324, 1.0, -1.0])
    t = np.concatenate([awkward, rng.standard_normal(200) * 10.0 ** rng.integers(-12, 13, 200)])
    f = np.concatenate([awkward[::-1], rng.standard_normal(200) * 10.0 ** rng.integers(-12, 13, 200)])
    assert _points(t, f) == [_point(a, b) for a, b in zip(t.tolist(), f.tolist())]
    assert _points(np.zeros(0), np.zeros(0)) == []


def test_decks_carry_the_graded_mesh(tmp_path):
    """The decks of the mesh the wall stage ran: the graded grid's nodes and solids, loaded as the wall
    stage loads it (each case cell's curve shared among the mesh's front-face nodes under it), the
    curves integrating to the case's deposited impulse; the DYNA3D deck with the re-binned records."""
    from impactdyn.wall import nodal_load, rebin_deposition, solver_mesh
    from impactdyn.wallgrid import sphere_deposition

    case = WallGrid.uniform((0.0, 1.6), (0.0, 0.3175), (-1.6, 1.6), (11, 5, 21))
    dep = sphere_deposition(case, 0.3, 0.6, 2.7, t0_us=5.0)
    mesh = solver_mesh(case, dep, 2.703)
    on_mesh = rebin_deposition(dep, case, mesh.grid)
    assert mesh.grid.n_elements > case.n_elements and on_mesh.element.size > dep.element.size
    p = tmp_path / "wall.k"
    write_lsdyna_deck(p, mesh.grid, deposition=dep, deposition_grid=case)
    deck = read_lsdyna_deck(p)
    # the graded nodes are not round numbers: as many digits as a 16-column *NODE field holds
    np.testing.assert_allclose(deck.coordinates, mesh.coordinates, rtol=0, atol=1e-11)
    np.testing.assert_array_equal(deck.solid_nodes, mesh.connectivity + 1)
    total = np.zeros(3)
    for (nid, dof, lcid), sf in zip(deck.point_loads, deck.point_load_scale):
        t, f = deck.curves[lcid]
        total[dof - 1] += sf * np.trapezoid(f, t)
    np.testing.assert_allclose(total, dep.impulse.sum(axis=0), rtol=1e-10, atol=1e-14)
    # each front-face node takes the wall stage's share (on the front face: depth 0), to the SFs' 7 digits
    front = nodal_load(mesh, dep, "area", 0.0)
    stage = np.zeros((mesh.n_nodes, 3))
    record, node, weight = front.entries()
    np.add.at(stage, node, front.impulse[record] * weight[:, None])
    deck_nodal = np.zeros((mesh.n_nodes, 3))
    for (nid, dof, lcid), sf in zip(deck.point_loads, deck.point_load_scale):
        t, f = deck.curves[lcid]
        deck_nodal[nid - 1, dof - 1] += sf * np.trapezoid(f, t)
    np.testing.assert_allclose(deck_nodal, stage, rtol=0, atol=1e-6 * np.abs(dep.impulse).max())
    d3 = tmp_path / "wall_dyna3d.inp"
    write_dyna3d_deck(d3, mesh.grid, deposition=on_mesh)
    lines = d3.read_text().splitlines()
    assert lines[1][5:21] == f"{mesh.n_nodes + 8:8d}{mesh.n_elements + 1:8d}"
    assert len(lines) == 2 + 16 + mesh.n_nodes + 8 + mesh.n_elements + 1 + 5 + on_mesh.element.size
