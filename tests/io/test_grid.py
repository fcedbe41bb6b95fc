"""HydroGrid: validation, integrals and the nodal velocity rules (docs/theory/binning.md, RDAVS)."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from impactdyn._errors import InputError
from impactdyn.hydrogrid import CELL_FIELDS, UNITS, HydroGrid


def make_grid(shape=(3, 4, 5), *, velocity=None, mass=None, staggered=False, x=None, y=None, z=None,
              rng=None) -> HydroGrid:
    rng = rng or np.random.default_rng(7)
    nx, ny, nz = shape
    ones = np.ones(shape)
    return HydroGrid(
        x=np.linspace(0.0, 1.5, nx + 1) if x is None else x,
        y=np.linspace(-2.0, 0.0, ny + 1) if y is None else y,
        z=np.linspace(1.0, 3.5, nz + 1) if z is None else z,
        density=2.7 * ones, void_fraction=0.1 * ones,
        mass=rng.uniform(0.5, 2.0, shape) if mass is None else mass,
        pressure=rng.normal(size=shape), temperature=300.0 * ones,
        specific_energy=rng.normal(size=shape), sound_speed=0.5 * ones,
        velocity=rng.normal(size=shape + (3,)) if velocity is None else velocity,
        staggered=staggered, time=4.0)


def test_units_name_every_array():
    names = {f.name for f in dataclasses.fields(HydroGrid)} - {"staggered"}
    assert set(UNITS) == names
    assert set(CELL_FIELDS) | {"x", "y", "z", "time"} == names


@pytest.mark.parametrize("change, message", [
    (dict(mass=np.ones((3, 4, 4))), "HydroGrid.mass: shape"),
    (dict(velocity=np.ones((3, 4, 5))), "HydroGrid.velocity: shape"),
    (dict(x=np.array([0.0, 1.0, 1.0, 2.0])), "HydroGrid.x: nodes must increase"),
    (dict(mass=-np.ones((3, 4, 5))), "HydroGrid.mass: negative"),
    (dict(velocity=np.full((3, 4, 5, 3), np.nan)), "HydroGrid.velocity: not finite"),
])
def test_bad_input_names_the_field(change, message):
    with pytest.raises(InputError, match=message):
        make_grid(**change)


def test_void_fraction_outside_unit_interval():
    g = make_grid()
    with pytest.raises(InputError, match="void_fraction: outside"):
        dataclasses.replace(g, void_fraction=np.full(g.shape, 1.5))


def test_arrays_are_private_read_only_copies():
    mass = np.ones((3, 4, 5))
    g = make_grid(mass=mass)
    mass[0, 0, 0] = 99.0
    assert g.mass[0, 0, 0] == 1.0
    with pytest.raises(ValueError):
        g.mass[0, 0, 0] = 2.0


def test_cell_volumes_and_totals():
    x, y, z = np.array([0.0, 1.0, 3.0]), np.array([0.0, 0.5, 2.0, 2.5]), np.array([-1.0, 1.0])
    rng = np.random.default_rng(3)
    g = make_grid((2, 3, 1), x=x, y=y, z=z, rng=rng)
    vol = g.cell_volumes()
    assert vol[1, 2, 0] == pytest.approx(2.0 * 0.5 * 2.0)
    assert vol.sum() == pytest.approx(3.0 * 2.5 * 2.0)
    assert g.total_mass() == pytest.approx(sum(g.mass.ravel()))
    p = sum(g.mass[i, j, k] * g.velocity[i, j, k] for i in range(2) for j in range(3) for k in range(1))
    np.testing.assert_allclose(g.total_momentum(), p, rtol=1e-14)


@pytest.mark.parametrize("staggered", [False, True])
def test_uniform_velocity_at_every_node_with_mass(staggered):
    u = np.array([0.3, -0.7, 0.45])
    g = make_grid(velocity=np.broadcast_to(u, (3, 4, 5, 3)), staggered=staggered)
    v = g.nodal_velocities()
    assert v.shape == (4, 5, 6, 3)
    for d in range(3):
        comp = np.moveaxis(v[..., d], d, 0)
        if staggered:
            # the upper boundary plane of axis d has no cell whose lower d-face holds it
            np.testing.assert_allclose(comp[:-1], u[d], rtol=1e-14)
            np.testing.assert_array_equal(comp[-1], 0.0)
        else:
            np.testing.assert_allclose(comp, u[d], rtol=1e-14)


@pytest.mark.parametrize("staggered", [False, True])
def test_empty_stencil_gives_zero(staggered):
    mass = np.zeros((3, 4, 5))
    mass[0, 0, 0] = 1.0
    g = make_grid(mass=mass, velocity=np.ones((3, 4, 5, 3)), staggered=staggered)
    v = g.nodal_velocities()
    assert np.all(v[2:, 2:, 2:] == 0.0)
    np.testing.assert_allclose(v[0, 0, 0], 1.0)


def test_linear_field_reproduced_at_interior_nodes_cell_centred():
    a = np.array([[0.2, -0.1, 0.05], [0.3, 0.4, -0.2], [-0.15, 0.25, 0.1]])
    b = np.array([0.01, -0.02, 0.03])
    shape = (4, 5, 6)
    g0 = make_grid(shape, mass=np.full(shape, 0.7))
    centres = np.stack(np.meshgrid(*[0.5 * (c[1:] + c[:-1]) for c in (g0.x, g0.y, g0.z)], indexing="ij"), -1)
    g = dataclasses.replace(g0, velocity=centres @ a.T + b)
    nodes = np.stack(np.meshgrid(g.x, g.y, g.z, indexing="ij"), -1)
    v = g.nodal_velocities()
    np.testing.assert_allclose(v[1:-1, 1:-1, 1:-1], (nodes @ a.T + b)[1:-1, 1:-1, 1:-1], rtol=0, atol=1e-14)


def test_linear_field_reproduced_at_interior_nodes_staggered():
    """Component d sampled at the centre of each cell's lower d-face averages back to the node."""
    a = np.array([[0.2, -0.1, 0.05], [0.3, 0.4, -0.2], [-0.15, 0.25, 0.1]])
    shape = (4, 5, 6)
    g0 = make_grid(shape, mass=np.full(shape, 1.3), staggered=True)
    vel = np.empty(shape + (3,))
    for d in range(3):
        axes = [0.5 * (c[1:] + c[:-1]) for c in (g0.x, g0.y, g0.z)]
        axes[d] = (g0.x, g0.y, g0.z)[d][:-1]  # lower face
        face = np.stack(np.meshgrid(*axes, indexing="ij"), -1)
        vel[..., d] = face @ a[d]
    g = dataclasses.replace(g0, velocity=vel)
    nodes = np.stack(np.meshgrid(g.x, g.y, g.z, indexing="ij"), -1)
    v = g.nodal_velocities()
    np.testing.assert_allclose(v[1:-1, 1:-1, 1:-1], (nodes @ a.T)[1:-1, 1:-1, 1:-1], rtol=0, atol=1e-14)


def test_staggered_rule_matches_the_listing_loops():
    """RDAVS (App. G), transcribed loop by loop: 1-based node i is 0-based node i-1."""
    rng = np.random.default_rng(11)
    shape = (4, 3, 5)
    mass = rng.uniform(0.0, 1.0, shape)
    mass[1, 1, 2] = 0.0
    g = make_grid(shape, mass=mass, staggered=True, rng=rng)
    m, vel = g.mass, g.velocity
    v = g.nodal_velocities()
    ni, nj, nk = shape

    def mean(cells, d):
        w = [m[c] for c in cells]
        return sum(wt * vel[c][d] for wt, c in zip(w, cells)) / sum(w) if sum(w) > 0 else 0.0

    for k in range(2, nk + 1):
        for j in range(2, nj + 1):
            for i in range(2, ni + 1):
                a, b, c = i - 1, j - 1, k - 1  # 0-based node; listing cell (i, j, k) is 0-based (a, b, c)
                vfx = mean([(a, b, c - 1), (a, b - 1, c - 1), (a, b - 1, c), (a, b, c)], 0)
                vfy = mean([(a - 1, b, c - 1), (a, b, c - 1), (a, b, c), (a - 1, b, c)], 1)
                vfz = mean([(a, b, c), (a, b - 1, c), (a - 1, b - 1, c), (a - 1, b, c)], 2)
                np.testing.assert_allclose(v[a, b, c], [vfx, vfy, vfz], rtol=1e-13, atol=1e-15)


def test_boundary_stencils():
    rng = np.random.default_rng(5)
    shape = (2, 2, 2)
    g = make_grid(shape, staggered=True, rng=rng)
    m, u = g.mass, g.velocity
    v = g.nodal_velocities()
    # corner node (0,0,0): every stencil holds only cell (0,0,0)
    np.testing.assert_allclose(v[0, 0, 0], u[0, 0, 0], rtol=1e-14)
    # node (0,1,0), x: cells (0, 0..1, 0); y: cell (0, 1, 0); z: cells (0, 0..1, 0)
    want_x = (m[0, 0, 0] * u[0, 0, 0, 0] + m[0, 1, 0] * u[0, 1, 0, 0]) / (m[0, 0, 0] + m[0, 1, 0])
    assert v[0, 1, 0, 0] == pytest.approx(want_x, rel=1e-14)
    assert v[0, 1, 0, 1] == pytest.approx(u[0, 1, 0, 1], rel=1e-14)
    # upper x plane: x component empty, y component from cells (1, 0, 0..)
    assert v[2, 0, 0, 0] == 0.0
    assert v[2, 0, 0, 1] == pytest.approx(u[1, 0, 0, 1], rel=1e-14)
    cc = dataclasses.replace(g, staggered=False).nodal_velocities()
    np.testing.assert_allclose(cc[2, 2, 2], u[1, 1, 1], rtol=1e-14)
    np.testing.assert_allclose(cc[1, 1, 1], np.einsum("ijk,ijkd->d", m, u) / m.sum(), rtol=1e-14)
