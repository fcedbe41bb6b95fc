"""The solver mesh: DYNGEN numbering, refinement, lumped masses, supports, node → element map."""

import numpy as np
import pytest

from impactdyn._errors import InputError
from impactdyn import wall
from impactdyn.wallgrid import WallGrid

GRID = WallGrid.uniform((0.0, 0.8), (0.0, 0.3175), (-0.4, 0.4), (6, 5, 6))


def test_refinement_one_keeps_dyngen_numbering():
    mesh = wall.build_mesh(GRID, 2.703)
    np.testing.assert_array_equal(mesh.connectivity + 1, GRID.element_nodes())
    np.testing.assert_array_equal(mesh.coordinates, GRID.node_coordinates())
    np.testing.assert_array_equal(mesh.fixed, GRID.constrained_dofs())
    assert mesh.shape == GRID.shape


@pytest.mark.parametrize("rt, rp", [(1, 1), (2, 1), (1, 3), (2, 2)])
def test_refined_mesh(rt, rp):
    rho = 2.703
    mesh = wall.build_mesh(GRID, rho, rt, rp)
    nx, ny, nz = GRID.shape
    assert mesh.shape == (nx * rp, ny * rt, nz * rp)
    total = 0.8 * 0.3175 * 0.8
    assert mesh.volume.sum() == pytest.approx(total, rel=1e-12)
    assert mesh.node_mass.sum() == pytest.approx(rho * total, rel=1e-12)
    np.testing.assert_allclose(mesh.volume, total / mesh.n_elements, rtol=1e-10)
    # the parent's nodes are nodes of the refined mesh, at the same places
    assert set(map(tuple, np.round(GRID.node_coordinates(), 12))) <= set(map(tuple, np.round(mesh.coordinates, 12)))
    # node → element map lists every corner once
    ptr, entry = mesh.node_element_ptr, mesh.node_element_entry
    for n in (0, mesh.n_nodes // 2, mesh.n_nodes - 1):
        corners = entry[ptr[n]:ptr[n + 1]]
        assert all(mesh.connectivity[c // 8, c % 8] == n for c in corners)
        assert len(corners) == np.count_nonzero(mesh.connectivity == n)


def test_supports():
    mesh = wall.build_mesh(GRID, 2.703, supports="clamped")
    x, z = mesh.coordinates[:, 0], mesh.coordinates[:, 2]
    np.testing.assert_array_equal(mesh.fixed[x == 0.0, 0], True)         # symmetry plane
    assert not mesh.fixed[(x == 0.0) & (z > -0.4) & (z < 0.4)][:, 1:].any()
    assert mesh.fixed[(x == 0.8) | (z == -0.4) | (z == 0.4)].all()         # clamped edges
    dyn = wall.build_mesh(GRID, 2.703, supports="dyngen")
    edge = dyn.fixed[x == 0.8]
    assert edge[:, 0].all() and edge[:, 1].all() and not edge[(z[x == 0.8] > -0.4) & (z[x == 0.8] < 0.4), 2].any()
    assert not wall.build_mesh(GRID, 2.703, supports="free").fixed.any()
    uni = wall.build_mesh(GRID, 2.703, supports="uniaxial").fixed
    assert uni[:, 0].all() and uni[:, 2].all() and not uni[:, 1].any()


@pytest.mark.parametrize("key, kwargs", [
    ("refinement_thickness", {"refinement_thickness": 0}),
    ("refinement_plane", {"refinement_plane": -2}),
    ("refinement_plane", {"refinement_plane": 1.5}),
    ("supports", {"supports": "glued"}),
])
def test_bad_mesh_input_names_the_key(key, kwargs):
    with pytest.raises(InputError, match=key):
        wall.build_mesh(GRID, 2.703, **kwargs)
